//! Line figures: every plot the crate draws (boundaries, alpha_max curves, step responses,
//! the paper's figures) is a [`Figure`] of [`Series`], written as SVG by [`Figure::to_svg`]
//! and converted to PNG or PDF by [`render`] (features `raster` and `pdf`).
//!
//! The SVG is the crate's own small writer (no plotting library): coordinates to 1/100 of a
//! pixel, lines clipped to the plot area exactly (Liang-Barsky), dashes as
//! `stroke-dasharray` along whole paths, a marker shape per colour so that greyscale prints
//! read, a legend placed in a free corner of the plot area (or outside it when no corner is
//! free, so that it never covers data), ticks at 1, 2, 5 times a power of ten printed with
//! the decimals of the tick step, and text as SVG `<text>` in DejaVu Sans (embedded in PNG
//! and PDF output; a viewer of the SVG uses its own copy or a sans-serif font).
//!
//! ```
//! use stabound::plot::{Figure, FigureStyle, LineStyle};
//!
//! let mut fig = Figure::new("A line", "stiffness α", "damping β");
//! fig.push("β = α / 3", vec![(0.0, 0.0), (1.0, 1.0 / 3.0)], LineStyle::Solid, 1);
//! fig.style = FigureStyle::new(360.0, 270.0, 12.0)?;
//! let svg = fig.to_svg()?;
//! assert!(svg.starts_with("<svg") && svg.contains("α"));
//! # Ok::<(), stabound::Error>(())
//! ```

mod format;
mod layout;
mod svg;
mod ticks;

pub use format::{Format, render};

use crate::error::{Error, Result};

/// How a series' line is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum LineStyle {
    /// A solid line.
    #[default]
    Solid,
    /// A dashed line (paper: path of maximum stiffness).
    Dashed,
    /// A dash-dotted line (paper: passivity condition).
    DashDot,
    /// A dotted line without markers (reference lines).
    Dotted,
    /// A wide, light line without markers, drawn beneath every other line: a reference
    /// line that data lie on (the floor `beta = -delta`) stays visible under them.
    Band,
    /// Markers only, no line.
    Points,
}

impl LineStyle {
    /// Whether markers label the line: reference lines carry none.
    fn marked(self) -> bool {
        !matches!(self, LineStyle::Dotted | LineStyle::Band)
    }

    /// The SVG `stroke-dasharray` of the style in units of the line width, or `None` for a
    /// solid line.
    fn dashes(self) -> Option<&'static [f64]> {
        match self {
            LineStyle::Solid | LineStyle::Points | LineStyle::Band => None,
            LineStyle::Dashed => Some(&[5.0, 3.0]),
            LineStyle::DashDot => Some(&[6.0, 2.5, 1.2, 2.5]),
            LineStyle::Dotted => Some(&[1.2, 2.0]),
        }
    }
}

/// Where the legend goes. Every choice keeps the legend off the data: a corner is only a
/// preference, tried first in a search of the free corners and edge middles of the plot
/// area; when none is free the legend goes outside the plot area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Legend {
    /// The first free place in the order upper right, upper left, lower right, lower left,
    /// then the edge middles (the default).
    #[default]
    UpperRight,
    /// Upper left first.
    UpperLeft,
    /// Lower right first.
    LowerRight,
    /// Lower left first.
    LowerLeft,
    /// Always outside the plot area, right of it (below it when it is too wide).
    Outside,
}

/// One labelled polyline. Points with a non-finite coordinate split the line into pieces.
/// A series without points draws nothing but its legend entry: a key to a kind of line
/// (for example "passive region" for several dash-dotted curves of different colours).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub label: String,
    /// The points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Line style.
    pub style: LineStyle,
    /// Index into the figure's palette of ten colours and seven marker shapes (colour
    /// `i % 10`, marker `i % 7`: 70 distinct pairs); series with one index share both.
    pub color: usize,
}

/// Size and text of a figure: canvas width and height in pixels (CSS pixels, 1/96 inch:
/// the SVG's user units, PNG pixels, and 3/4 point in PDF) and the font size of the axis
/// labels and legend (tick labels are 7/8 of it).
///
/// The default, 480 x 360 with 16 px text, prints text at about 8 pt when the figure is
/// scaled to a single journal column (3.5 in, 252 pt: 16 x 252 / 480 = 8.4 pt).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "StyleFields", into = "StyleFields")
)]
pub struct FigureStyle {
    width: f64,
    height: f64,
    font_size: f64,
    markers: bool,
}

/// The fields of [`FigureStyle`] as read and written by serde (checked on the way in).
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct StyleFields {
    width: f64,
    height: f64,
    font_size: f64,
    markers: bool,
}

#[cfg(feature = "serde")]
impl TryFrom<StyleFields> for FigureStyle {
    type Error = Error;
    fn try_from(f: StyleFields) -> Result<Self> {
        Ok(FigureStyle::new(f.width, f.height, f.font_size)?.with_markers(f.markers))
    }
}

#[cfg(feature = "serde")]
impl From<FigureStyle> for StyleFields {
    fn from(s: FigureStyle) -> Self {
        StyleFields {
            width: s.width,
            height: s.height,
            font_size: s.font_size,
            markers: s.markers,
        }
    }
}

impl Default for FigureStyle {
    fn default() -> Self {
        FigureStyle {
            width: 480.0,
            height: 360.0,
            font_size: 16.0,
            markers: true,
        }
    }
}

/// Smallest and largest canvas side in pixels.
pub const FIGURE_SIDE: (f64, f64) = (120.0, 10_000.0);

impl FigureStyle {
    /// A style of `width` x `height` pixels with text of `font_size` pixels.
    ///
    /// The sides must lie in [`FIGURE_SIDE`] and the font size in `[4, side / 6]` for the
    /// shorter side (larger text leaves no room for the plot); else
    /// [`Error::InvalidParameter`].
    pub fn new(width: f64, height: f64, font_size: f64) -> Result<Self> {
        for (name, v) in [("figure width", width), ("figure height", height)] {
            if !(v >= FIGURE_SIDE.0 && v <= FIGURE_SIDE.1) {
                return Err(Error::InvalidParameter {
                    name,
                    value: v,
                    expected: format!("a size in pixels in [{}, {}]", FIGURE_SIDE.0, FIGURE_SIDE.1),
                });
            }
        }
        let most = width.min(height) / 6.0;
        if !(font_size >= 4.0 && font_size <= most) {
            return Err(Error::InvalidParameter {
                name: "font size",
                value: font_size,
                expected: format!(
                    "a size in pixels in [4, {most}] (a sixth of the shorter side of the figure)"
                ),
            });
        }
        Ok(FigureStyle {
            width,
            height,
            font_size,
            markers: true,
        })
    }

    /// A canvas of 720 x 540 pixels with 16 px text, for figures of many curves (a
    /// two-column figure in print).
    pub fn large() -> Self {
        FigureStyle {
            width: 720.0,
            height: 540.0,
            ..FigureStyle::default()
        }
    }

    /// The same style with markers along the lines (`true`, the default) or without.
    pub fn with_markers(mut self, markers: bool) -> Self {
        self.markers = markers;
        self
    }

    /// Canvas width in pixels.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Canvas height in pixels.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Font size of labels and legend in pixels.
    pub fn font_size(&self) -> f64 {
        self.font_size
    }

    /// Whether lines carry markers.
    pub fn markers(&self) -> bool {
        self.markers
    }
}

/// A figure: title, axis labels, the series to draw, and its style.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Figure {
    /// Title above the plot; empty for none (a paper's caption replaces it).
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
    /// Canvas size and font size.
    #[cfg_attr(feature = "serde", serde(default))]
    pub style: FigureStyle,
    /// Where the legend goes.
    #[cfg_attr(feature = "serde", serde(default))]
    pub legend: Legend,
}

/// The largest axis end a figure draws: the tick computation needs widths well inside the
/// `f64` range (a range of +-1e308 has an infinite width).
const MAX_AXIS: f64 = 1e300;

impl Figure {
    /// An empty figure with labels and the default style ([`FigureStyle::default`]).
    ///
    /// In the title, the axis labels and series labels, `_{...}` is drawn as a subscript
    /// (`"α_{max}"`); any other underscore is drawn as itself.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            style: FigureStyle::default(),
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

    /// The checked axis ranges (given, or fitted to the data).
    fn ranges(&self) -> Result<((f64, f64), (f64, f64))> {
        let x = Self::checked("x", self.x_range.unwrap_or_else(|| self.fitted(|p| p.0)))?;
        let y = Self::checked("y", self.y_range.unwrap_or_else(|| self.fitted(|p| p.1)))?;
        Ok((x, y))
    }

    /// Renders the figure as an SVG document of [`FigureStyle::width`] x
    /// [`FigureStyle::height`] pixels.
    ///
    /// A given range must have finite ends with `lo < hi`, ends of at most `1e300` in size
    /// and a width above `1e-12` of their size (else [`Error::InvalidRequest`]); a fitted
    /// range covers the finite data, cut to +-1e300.
    pub fn to_svg(&self) -> Result<String> {
        let (w, h) = (self.style.width, self.style.height);
        let mut out = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n"
        );
        out.push_str(&self.svg_body("f")?);
        out.push_str("</svg>\n");
        Ok(out)
    }

    /// The figure's SVG elements without the root element, with `id` as the prefix of its
    /// element ids (unique per panel when several figures share one document).
    pub(crate) fn svg_body(&self, id: &str) -> Result<String> {
        let (x, y) = self.ranges()?;
        Ok(svg::draw(self, x, y, id))
    }
}

/// A colour-blind-friendly palette of ten: Okabe and Ito's eight (black, blue, vermillion,
/// bluish green, reddish purple, orange, sky blue; grey in place of their yellow, which is
/// too light on white) and Tol's wine and olive.
pub(crate) fn palette(i: usize) -> &'static str {
    const C: [&str; 10] = [
        "#000000", "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#777777",
        "#882255", "#999933",
    ];
    C[i % C.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_labels_and_lines() {
        let mut f = Figure::new("Test", "α", "β");
        f.push(
            "d = 0",
            vec![(0.0, 0.0), (1.0, 1.0), (f64::NAN, 0.0), (2.0, 0.5)],
            LineStyle::Solid,
            1,
        );
        f.push("path", vec![(0.0, 1.0), (1.0, 0.0)], LineStyle::Dashed, 2);
        let svg = f.to_svg().unwrap();
        assert!(svg.starts_with("<svg"));
        for text in ["Test", "α", "β", "d = 0", "path", "stroke-dasharray"] {
            assert!(svg.contains(text), "missing {text}");
        }
        assert!(svg.contains("<path"));
    }

    #[test]
    fn style_limits() {
        assert!(FigureStyle::new(480.0, 360.0, 16.0).is_ok());
        assert!(FigureStyle::new(100.0, 360.0, 16.0).is_err());
        assert!(FigureStyle::new(480.0, f64::NAN, 16.0).is_err());
        assert!(FigureStyle::new(480.0, 360.0, 61.0).is_err());
        assert!(FigureStyle::new(480.0, 360.0, 3.0).is_err());
    }
}
