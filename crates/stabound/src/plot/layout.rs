//! Geometry of a figure: text widths, the plot rectangle, exact clipping of lines to it, and
//! the legend's place (a free corner or edge middle, else outside the plot area).

/// A rectangle in pixels, `x0 < x1`, `y0 < y1` (y grows downwards, as in SVG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    pub fn grown(self, by: f64) -> Rect {
        Rect {
            x0: self.x0 - by,
            y0: self.y0 - by,
            x1: self.x1 + by,
            y1: self.y1 + by,
        }
    }

    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }

    pub fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }

    /// Whether the segment `a`-`b` meets the rectangle (Liang-Barsky).
    pub fn meets(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        clip_segment(*self, a, b).is_some()
    }
}

/// The part of the segment `a`-`b` inside `r`, by Liang and Barsky's parametric clipping
/// ("A new concept and method for line clipping", ACM TOG 3(1), 1984).
pub(crate) fn clip_segment(
    r: Rect,
    a: (f64, f64),
    b: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    // a non-finite end (data beyond the f64 range after scaling) draws nothing
    if !(dx.is_finite() && dy.is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        // exact zero: the segment is parallel to this edge
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
        // all finite here: the ends are finite (checked above)
        if t0 > t1 {
            return None;
        }
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    // the ends themselves when not cut, so that polylines stay joined exactly
    let p = if t0 > 0.0 { at(t0) } else { a };
    let q = if t1 < 1.0 { at(t1) } else { b };
    Some((p, q))
}

/// Cuts a polyline in pixels into the runs inside `r`, then drops vertices closer than
/// `min_step` pixels to the previous kept one (the first and last vertex of a run are kept).
pub(crate) fn clip_polyline(r: Rect, pts: &[(f64, f64)], min_step: f64) -> Vec<Vec<(f64, f64)>> {
    if pts.len() == 1 {
        return if r.contains(pts[0]) {
            vec![vec![pts[0]]]
        } else {
            Vec::new()
        };
    }
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    for w in pts.windows(2) {
        match clip_segment(r, w[0], w[1]) {
            None => runs.push(std::mem::take(&mut current)),
            Some((p, q)) => {
                if current.last() != Some(&p) {
                    runs.push(std::mem::take(&mut current));
                    current.push(p);
                }
                current.push(q);
                if q != w[1] {
                    // the segment leaves the rectangle
                    runs.push(std::mem::take(&mut current));
                }
            }
        }
    }
    runs.push(current);
    runs.retain(|run| run.len() > 1);
    for run in &mut runs {
        *run = thin(run, min_step);
    }
    runs
}

/// Keeps the first and last vertex and every vertex at least `min_step` from the previous
/// kept one.
fn thin(run: &[(f64, f64)], min_step: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(run.len());
    for (i, &p) in run.iter().enumerate() {
        let far = out
            .last()
            .is_none_or(|l| (l.0 - p.0).hypot(l.1 - p.1) >= min_step);
        if far {
            out.push(p);
        } else if i + 1 == run.len() {
            // the last vertex replaces a near one, unless that one is the run's start
            if out.len() > 1 {
                out.pop();
            }
            out.push(p);
        }
    }
    out
}

/// Estimated advance width of `text` at `size` pixels in DejaVu Sans: per-character widths
/// rounded up from the font's advances (digits 0.636 em, lower case 0.5 to 0.65 em, narrow
/// punctuation about 0.32 em), so that boxes sized with it hold the text in any sans-serif
/// font of similar width.
pub(crate) fn text_width(text: &str, size: f64) -> f64 {
    super::svg::runs(text)
        .map(|(run, sub)| em_width(run) * if sub { SUB_SCALE } else { 1.0 })
        .sum::<f64>()
        * size
}

/// Size of a subscript relative to its line: the 70 % typesetting programs use.
pub(crate) const SUB_SCALE: f64 = 0.7;

/// Width of a run of text in em, from the per-character table above.
fn em_width(text: &str) -> f64 {
    text.chars()
        .map(|c| match c {
            ' ' | '.' | ',' | ':' | ';' | '\'' | '!' | '|' | 'i' | 'j' | 'l' | 'I' => 0.34,
            '(' | ')' | '[' | ']' | 'f' | 't' | 'r' => 0.42,
            'm' | 'w' | 'M' | 'W' | '%' => 0.98,
            'A'..='Z' => 0.74,
            '0'..='9' | '=' | '+' | '\u{2212}' | '-' | '_' | '<' | '>' => 0.64,
            _ => 0.62,
        })
        .sum()
}

/// Sizes of one legend: entry rows and columns, and the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LegendBox {
    pub columns: usize,
    pub rows: usize,
    pub column_width: f64,
    pub row_height: f64,
    pub pad: f64,
}

impl LegendBox {
    /// A legend of `n` entries whose longest label is `label_width` wide, at font `f`, in
    /// `columns` columns.
    pub fn new(n: usize, label_width: f64, f: f64, columns: usize) -> LegendBox {
        let columns = columns.clamp(1, n.max(1));
        LegendBox {
            columns,
            rows: n.div_ceil(columns),
            column_width: sample_length(f) + 0.5 * f + label_width + 0.6 * f,
            row_height: 1.3 * f,
            pad: 0.4 * f,
        }
    }

    pub fn width(&self) -> f64 {
        self.columns as f64 * self.column_width + 2.0 * self.pad - 0.6 * self.row_height / 1.3
    }

    pub fn height(&self) -> f64 {
        self.rows as f64 * self.row_height + 2.0 * self.pad
    }

    pub fn at(&self, x: f64, y: f64) -> Rect {
        Rect {
            x0: x,
            y0: y,
            x1: x + self.width(),
            y1: y + self.height(),
        }
    }
}

/// Length of a legend's line sample at font size `f`: long enough to show one period of
/// the dash-dot pattern at the default line width.
pub(crate) fn sample_length(f: f64) -> f64 {
    2.4 * f
}

/// The candidate places of a legend box `b` in the plot rectangle `plot`, inset by `inset`,
/// in the order of preference starting at corner `first` (0 upper right, 1 upper left,
/// 2 lower right, 3 lower left), then the edge middles.
pub(crate) fn candidates(plot: Rect, b: &LegendBox, inset: f64, first: usize) -> Vec<Rect> {
    let (w, h) = (b.width(), b.height());
    let left = plot.x0 + inset;
    let right = plot.x1 - inset - w;
    let top = plot.y0 + inset;
    let bottom = plot.y1 - inset - h;
    let mid_x = plot.x0 + 0.5 * (plot.width() - w);
    let mid_y = plot.y0 + 0.5 * (plot.height() - h);
    let corners = [(right, top), (left, top), (right, bottom), (left, bottom)];
    let mut out: Vec<Rect> = (0..4)
        .map(|k| corners[(first + k) % 4])
        .chain([(mid_x, top), (mid_x, bottom), (right, mid_y), (left, mid_y)])
        .map(|(x, y)| b.at(x, y))
        .collect();
    out.retain(|r| r.x0 >= plot.x0 && r.x1 <= plot.x1 && r.y0 >= plot.y0 && r.y1 <= plot.y1);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: Rect = Rect {
        x0: 0.0,
        y0: 0.0,
        x1: 10.0,
        y1: 10.0,
    };

    /// Hand-worked clips: a segment crossing the square is cut at its edges; one outside
    /// is dropped; one inside is returned as given.
    #[test]
    fn liang_barsky_by_hand() {
        assert_eq!(
            clip_segment(R, (-5.0, 5.0), (15.0, 5.0)),
            Some(((0.0, 5.0), (10.0, 5.0)))
        );
        assert_eq!(clip_segment(R, (-5.0, -1.0), (15.0, -1.0)), None);
        assert_eq!(
            clip_segment(R, (1.0, 2.0), (3.0, 4.0)),
            Some(((1.0, 2.0), (3.0, 4.0)))
        );
        // the diagonal from (-10, 0) to (10, 20) enters at (0, 10), a corner
        let (p, q) = clip_segment(R, (-10.0, 0.0), (10.0, 20.0)).unwrap();
        assert!((p.0 - 0.0).abs() < 1e-12 && (p.1 - 10.0).abs() < 1e-12 && p == q);
        assert_eq!(clip_segment(R, (f64::NAN, 0.0), (1.0, 1.0)), None);
    }

    /// A polyline leaving and re-entering the square gives two runs.
    #[test]
    fn polyline_runs() {
        let runs = clip_polyline(R, &[(1.0, 1.0), (1.0, 20.0), (2.0, 20.0), (2.0, 1.0)], 0.0);
        assert_eq!(runs.len(), 2, "{runs:?}");
        assert_eq!(runs[0], vec![(1.0, 1.0), (1.0, 10.0)]);
        assert_eq!(runs[1], vec![(2.0, 10.0), (2.0, 1.0)]);
    }
}
