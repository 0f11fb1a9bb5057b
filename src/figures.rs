//! The paper's figures as data: each function returns the [`Figure`] to draw and the CSV
//! rows behind it (Hulin, Preusche, Hirzinger, "Stability Boundary for Haptic Rendering:
//! Influence of Physical Damping", IROS 2006, Figs. 5 to 11).
//!
//! Every figure is one SVG; figures with several panels in the paper (Fig. 5: one panel per
//! delay; Fig. 10: two scalings) are composed side by side with [`compose_svg`].

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::params::Device;
use crate::plot::{Figure, LineStyle};
use crate::sim::StepResponse;

/// One figure's data: the panels to draw and the table behind them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FigureData {
    /// Short name, used for file names: `fig05`, ..., `fig11`.
    pub name: String,
    /// The panels, drawn left to right, top to bottom in [`FigureData::columns_of_panels`].
    pub panels: Vec<Figure>,
    /// Panels per row in the composed SVG.
    pub columns_of_panels: usize,
    /// CSV column names; the first column is the series label (text), the rest numbers.
    pub columns: Vec<String>,
    /// CSV rows: series label and the numeric columns.
    pub rows: Vec<(String, Vec<f64>)>,
}

impl FigureData {
    /// The table as CSV text: a header line and one line per row; numbers in Rust's shortest
    /// round-trip form, so the file reads back to the same `f64` values.
    pub fn to_csv(&self) -> String {
        let mut s = self.columns.join(",");
        s.push('\n');
        for (label, values) in &self.rows {
            s.push_str(&csv_text(label));
            for v in values {
                s.push(',');
                s.push_str(&number(*v));
            }
            s.push('\n');
        }
        s
    }

    /// The figure as one SVG document (panels composed with [`compose_svg`]).
    pub fn to_svg(&self) -> Result<String> {
        compose_svg(&self.panels, self.columns_of_panels)
    }
}

/// A number for CSV in the shortest form that reads back to the same `f64`: plain decimal for
/// magnitudes in `[1e-4, 1e15)` and zero, scientific notation (`5e-8`) otherwise, so that tiny
/// positions do not turn into long runs of zeros.
pub fn number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Quotes a CSV text field when it contains a comma, quote or line break (RFC 4180).
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Places several figures in one SVG document, `columns` per row, each at its own size, by
/// nesting each panel's `<svg>` element at its offset (SVG 1.1, section 5.1.2: nested `svg`
/// elements establish a new viewport).
pub fn compose_svg(panels: &[Figure], columns: usize) -> Result<String> {
    if panels.len() == 1 {
        return panels[0].to_svg();
    }
    let columns = columns.max(1);
    let (w, h) = panels
        .iter()
        .fold((0, 0), |(w, h), p| (w.max(p.size.0), h.max(p.size.1)));
    let rows = panels.len().div_ceil(columns);
    let (tw, th) = (w * columns.min(panels.len()) as u32, h * rows as u32);
    let mut out = format!(
        "<svg width=\"{tw}\" height=\"{th}\" viewBox=\"0 0 {tw} {th}\" xmlns=\"http://www.w3.org/2000/svg\">\n"
    );
    for (i, p) in panels.iter().enumerate() {
        let svg = p.to_svg()?;
        let x = (i % columns) as u32 * w;
        let y = (i / columns) as u32 * h;
        // Insert the offset into the panel's own root element.
        let body = svg.trim_start();
        let body = body
            .strip_prefix("<svg")
            .map(|rest| format!("<svg x=\"{x}\" y=\"{y}\"{rest}"))
            .unwrap_or_else(|| body.to_string());
        out.push_str(&body);
        out.push('\n');
    }
    out.push_str("</svg>\n");
    Ok(out)
}

/// A figure of step responses (paper Fig. 11): position in mm against time in ms, one solid
/// line per response, labelled; the rows are `(label, time_s, position_m)`.
///
/// `responses` pairs a legend label with each response.
pub fn step_figure(name: &str, title: &str, responses: &[(String, StepResponse)]) -> FigureData {
    let mut fig = Figure::new(title, "time t [ms]", "position x [mm]");
    let mut rows = Vec::new();
    for (i, (label, r)) in responses.iter().enumerate() {
        let pts = r
            .time
            .iter()
            .zip(&r.position)
            .map(|(&t, &x)| (t * 1e3, x * 1e3))
            .collect();
        fig.push(label.clone(), pts, LineStyle::Solid, i + 1);
        rows.extend(
            r.time
                .iter()
                .zip(&r.position)
                .map(|(&t, &x)| (label.clone(), vec![t, x])),
        );
    }
    FigureData {
        name: name.into(),
        panels: vec![fig],
        columns_of_panels: 1,
        columns: vec!["series".into(), "time_s".into(), "position_m".into()],
        rows,
    }
}

/// The legend label of one step response: physical damping, stiffness and wall damping.
pub fn step_label(device: &Device, stiffness: f64, wall_damping: f64) -> String {
    format!(
        "b = {} N s/m, K = {:.0} N/m, B = {:.1} N s/m",
        device.damping, stiffness, wall_damping
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_and_round_trips() {
        let fd = FigureData {
            name: "t".into(),
            panels: vec![Figure::new("a", "x", "y")],
            columns_of_panels: 1,
            columns: vec!["series".into(), "x".into()],
            rows: vec![("a, b".into(), vec![0.1]), ("c".into(), vec![1.0 / 3.0])],
        };
        let csv = fd.to_csv();
        assert_eq!(
            csv.lines().nth(1).unwrap(),
            "\"a, b\",0.1",
            "comma in a label must be quoted"
        );
        let third: f64 = csv.lines().nth(2).unwrap()[2..].parse().unwrap();
        assert_eq!(
            third,
            1.0 / 3.0,
            "shortest round-trip form reads back exactly"
        );
    }

    #[test]
    fn composes_panels_side_by_side() {
        let mut a = Figure::new("left", "x", "y");
        a.push("one", vec![(0.0, 0.0), (1.0, 1.0)], LineStyle::Solid, 1);
        let mut b = Figure::new("right", "x", "y");
        b.push("two", vec![(0.0, 1.0), (1.0, 0.0)], LineStyle::Dashed, 2);
        let svg = compose_svg(&[a, b], 2).unwrap();
        assert!(svg.starts_with("<svg width=\"1600\" height=\"600\""));
        assert!(svg.contains("<svg x=\"800\" y=\"0\""));
        assert!(svg.contains("left") && svg.contains("right"));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
}
