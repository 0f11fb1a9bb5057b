//! Line figures as SVG: every plot the crate draws (boundaries, alpha_max curves, step
//! responses) is a [`Figure`] of [`Series`], rendered by [`Figure::to_svg`].
//!
//! Rendering uses plotters' SVG backend without system fonts: text is emitted as SVG `<text>`
//! and laid out by the viewer.

use plotters::prelude::*;

use crate::error::{Error, Result};

/// How a series' line is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LineStyle {
    /// A solid line.
    #[default]
    Solid,
    /// A dashed line (paper: path of maximum stiffness).
    Dashed,
    /// A dash-dotted line (paper: passivity condition).
    DashDot,
    /// Markers only, no line.
    Points,
}

/// Where the legend box goes inside the plot area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Legend {
    /// Top right corner (the default).
    #[default]
    UpperRight,
    /// Top left corner.
    UpperLeft,
    /// Bottom right corner.
    LowerRight,
    /// Bottom left corner.
    LowerLeft,
}

/// One labelled polyline. Points with a non-finite coordinate split the line into pieces.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub label: String,
    /// The points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Line style.
    pub style: LineStyle,
    /// Index into the figure's palette; series with one colour share it.
    pub color: usize,
}

/// A figure: title, axis labels, and the series to draw.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Figure {
    /// Title above the plot.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
    /// Axis ranges; `None` fits the data with a 5 % margin.
    pub x_range: Option<(f64, f64)>,
    /// See `x_range`.
    pub y_range: Option<(f64, f64)>,
    /// Size in pixels.
    pub size: (u32, u32),
    /// Corner of the legend box.
    #[cfg_attr(feature = "serde", serde(default))]
    pub legend: Legend,
}

/// The largest axis end a figure draws: the tick computation needs widths well inside the
/// `f64` range (a range of +-1e308 has an infinite width).
const MAX_AXIS: f64 = 1e300;

impl Figure {
    /// An empty figure with labels and the default size (800 x 600).
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            size: (800, 600),
            legend: Legend::default(),
        }
    }

    /// Adds a series.
    pub fn push(
        &mut self,
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        style: LineStyle,
        color: usize,
    ) {
        self.series.push(Series {
            label: label.into(),
            points,
            style,
            color,
        });
    }

    fn fitted(&self, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
        let (lo, hi) = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .map(&pick)
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
        if !lo.is_finite() {
            return (0.0, 1.0);
        }
        // halves, so that data near +-f64::MAX (an unstable response) cannot overflow the
        // span; the range is then cut to +-MAX_AXIS, beyond which the drawing clips
        let span = 2.0 * (hi / 2.0 - lo / 2.0).max(1e-12 * lo.abs().max(1.0));
        (
            (lo - 0.05 * span).max(-MAX_AXIS),
            (hi + 0.05 * span).min(MAX_AXIS),
        )
    }

    /// The range of one axis, checked: finite ends, `lo < hi`, a width that is finite and
    /// resolvable in `f64`.
    fn checked(name: &str, (lo, hi): (f64, f64)) -> Result<(f64, f64)> {
        let width = hi - lo;
        if !(lo.is_finite() && hi.is_finite() && lo < hi && width.is_finite())
            || lo.abs().max(hi.abs()) > MAX_AXIS
            || width <= 1e-12 * lo.abs().max(hi.abs())
        {
            return Err(Error::InvalidRequest(format!(
                "the {name} range [{lo}, {hi}] of the figure cannot be drawn: give finite ends with lo < hi, |ends| <= {MAX_AXIS:e} and a width above 1e-12 of their size"
            )));
        }
        Ok((lo, hi))
    }

    /// Renders the figure as an SVG document.
    ///
    /// A given range must have finite ends with `lo < hi`, ends of at most `1e300` in size
    /// and a width above `1e-12` of their size (else [`Error::InvalidRequest`]); a fitted
    /// range covers the finite data, cut to +-1e300.
    pub fn to_svg(&self) -> Result<String> {
        let x = Self::checked("x", self.x_range.unwrap_or_else(|| self.fitted(|p| p.0)))?;
        let y = Self::checked("y", self.y_range.unwrap_or_else(|| self.fitted(|p| p.1)))?;
        let mut out = String::new();
        self.draw(&mut out, x, y)
            .map_err(|e| Error::Numerical(format!("drawing the figure failed: {e}")))?;
        Ok(out)
    }

    fn draw(
        &self,
        out: &mut String,
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
    ) -> std::result::Result<(), Box<dyn std::error::Error + '_>> {
        let root = SVGBackend::with_string(out, self.size).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        for s in &self.series {
            let color = palette(s.color);
            let style = ShapeStyle::from(color).stroke_width(2);
            for piece in s.points.split(|p| !(p.0.is_finite() && p.1.is_finite())) {
                if piece.is_empty() {
                    continue;
                }
                let pts = piece.iter().copied();
                let anno = match s.style {
                    LineStyle::Solid => chart.draw_series(LineSeries::new(pts, style))?,
                    LineStyle::Dashed => {
                        chart.draw_series(DashedLineSeries::new(pts, 8, 5, style))?
                    }
                    LineStyle::DashDot => {
                        // plotters has no dash-dot: cut the line into dashes and dots by
                        // its length in pixels (the data-to-pixel map is affine, so cutting
                        // by linear interpolation in data coordinates is exact).
                        let coord = chart.as_coord_spec();
                        let px: Vec<(i32, i32)> =
                            piece.iter().map(|p| coord.translate(p)).collect();
                        let pieces = dash_dot(piece, &px);
                        let mut last = None;
                        for d in pieces {
                            last = Some(chart.draw_series(LineSeries::new(d, style))?);
                        }
                        match last {
                            Some(a) => a,
                            None => chart.draw_series(LineSeries::new(pts, style))?,
                        }
                    }
                    LineStyle::Points => chart
                        .draw_series(piece.iter().map(|&p| Circle::new(p, 2, style.filled())))?,
                };
                if !s.label.is_empty() && std::ptr::eq(piece.as_ptr(), first_piece(&s.points)) {
                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
            }
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(match self.legend {
                    Legend::UpperRight => SeriesLabelPosition::UpperRight,
                    Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
                    Legend::LowerRight => SeriesLabelPosition::LowerRight,
                    Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
                })
                .draw()?;
        }
        root.present()?;
        Ok(())
    }
}

/// Cuts a polyline into the pieces of a dash-dot pattern (dash 10 px, gap 4, dot 2, gap 4),
/// measuring length on the pixel coordinates `px` of the same points.
fn dash_dot(pts: &[(f64, f64)], px: &[(i32, i32)]) -> Vec<Vec<(f64, f64)>> {
    const PATTERN: [(f64, bool); 4] = [(10.0, true), (4.0, false), (2.0, true), (4.0, false)];
    let mut out = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let (mut k, mut left) = (0usize, PATTERN[0].0);
    if let Some(&p) = pts.first() {
        current.push(p);
    }
    for i in 1..pts.len() {
        let (a, b) = (pts[i - 1], pts[i]);
        let dx = f64::from(px[i].0 - px[i - 1].0);
        let dy = f64::from(px[i].1 - px[i - 1].1);
        let len = dx.hypot(dy);
        let mut pos = 0.0;
        while len - pos > left {
            pos += left;
            let t = pos / len;
            let q = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            if PATTERN[k].1 {
                current.push(q);
                out.push(std::mem::take(&mut current));
            } else {
                current = vec![q];
            }
            k = (k + 1) % PATTERN.len();
            left = PATTERN[k].0;
        }
        left -= len - pos;
        if PATTERN[k].1 {
            current.push(b);
        }
    }
    if PATTERN[k].1 && current.len() > 1 {
        out.push(current);
    }
    out
}

/// Pointer to the first drawn piece of a series (for a single legend entry per series).
fn first_piece(points: &[(f64, f64)]) -> *const (f64, f64) {
    points
        .split(|p| !(p.0.is_finite() && p.1.is_finite()))
        .find(|p| !p.is_empty())
        .map_or(std::ptr::null(), |p| p.as_ptr())
}

/// A colour-blind-friendly palette (Okabe-Ito), cycling.
pub(crate) fn palette(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(0, 0, 0),
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(120, 120, 120),
    ];
    C[i % C.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_labels_and_lines() {
        let mut f = Figure::new("Test", "alpha", "beta");
        f.push(
            "d = 0",
            vec![(0.0, 0.0), (1.0, 1.0), (f64::NAN, 0.0), (2.0, 0.5)],
            LineStyle::Solid,
            1,
        );
        f.push("path", vec![(0.0, 1.0), (1.0, 0.0)], LineStyle::Dashed, 2);
        let svg = f.to_svg().unwrap();
        assert!(svg.starts_with("<svg"));
        for text in ["Test", "alpha", "beta", "d = 0", "path"] {
            assert!(svg.contains(text), "missing {text}");
        }
        assert!(svg.contains("polyline") || svg.contains("<path"));
    }

    /// The dash-dot cutter: on a 40 px straight line (1 data unit = 1 px) the pattern
    /// 10 on, 4 off, 2 on, 4 off gives dashes [0, 10], [14, 16], [20, 30], [34, 36].
    #[test]
    fn dash_dot_pattern() {
        let pts = [(0.0, 0.0), (25.0, 0.0), (40.0, 0.0)];
        let px = [(0, 0), (25, 0), (40, 0)];
        let pieces = dash_dot(&pts, &px);
        let spans: Vec<(f64, f64)> = pieces.iter().map(|p| (p[0].0, p[p.len() - 1].0)).collect();
        let want = [(0.0, 10.0), (14.0, 16.0), (20.0, 30.0), (34.0, 36.0)];
        assert_eq!(spans.len(), want.len());
        for (s, w) in spans.iter().zip(want) {
            // interpolation t = pos / len rounds to an ulp or so
            assert!(
                (s.0 - w.0).abs() < 1e-9 && (s.1 - w.1).abs() < 1e-9,
                "{spans:?}"
            );
        }
    }
}
