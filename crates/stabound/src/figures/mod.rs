//! The paper's figures as data: each function returns the [`Figure`] panels to draw and the
//! CSV rows behind them (Hulin, Preusche, Hirzinger, "Stability Boundary for Haptic
//! Rendering: Influence of Physical Damping", IROS 2006, Figs. 5 to 11).
//!
//! The recipes of the paper's figures are in `paper` (Figs. 5 to 10) and `step` (Fig. 11
//! and the step-response figures of the command line), the companions of Figs. 8 and 9 for
//! delayed loops in [`passivity`], the CSV text in `csv`; drawing is
//! [`crate::plot`]'s. Every figure is one document; figures with several panels in the paper
//! (Fig. 5: one panel per delay; Fig. 10: two scalings) are composed side by side with
//! [`compose_svg`]. [`FigureData::render`] writes SVG, PNG or PDF ([`Format`]).

mod csv;
mod paper;
pub mod passivity;
mod step;

pub use paper::{
    DELTA_BETA_RANGE, FIG5_DELAYS, FIG5_DELTAS, FIG6_DELAYS, FIG7_DELTAS, FIG9_ALPHAS,
    FIG10_DELAYS, FIGURE_TOL, boundary_lines, fig05, fig06, fig07, fig08, fig09, fig10,
};
pub use step::{fig11, limit_cycle_panel, section8_device, step_figure, step_label};

use crate::error::{Error, Result};
use crate::plot::{Figure, FigureStyle, Format};

/// One figure's data: the panels to draw and the table behind them.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FigureData {
    /// Short name, used for file names: `fig05`, ..., `fig11`.
    pub name: String,
    /// The panels, drawn left to right, top to bottom in [`FigureData::columns_of_panels`].
    pub panels: Vec<Figure>,
    /// Panels per row in the composed document.
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
        csv::to_csv(&self.columns, &self.rows)
    }

    /// The figure as one SVG document (panels composed with [`compose_svg`]).
    pub fn to_svg(&self) -> Result<String> {
        compose_svg(&self.panels, self.columns_of_panels)
    }

    /// The figure as a file of `format` ([`crate::plot::render`] of [`FigureData::to_svg`]).
    pub fn render(&self, format: Format) -> Result<Vec<u8>> {
        crate::plot::render(&self.to_svg()?, format)
    }

    /// The same figure with every panel in `style` (canvas and font size).
    pub fn with_style(mut self, style: FigureStyle) -> Self {
        for p in &mut self.panels {
            p.style = style;
        }
        self
    }
}

/// Places several figures in one SVG document, `columns` per row, each panel in a cell of
/// the largest panel's size (a group translated to the cell; element ids get the panel's
/// number, so that clip paths stay distinct).
pub fn compose_svg(panels: &[Figure], columns: usize) -> Result<String> {
    if panels.len() == 1 {
        return panels[0].to_svg();
    }
    let columns = columns.max(1);
    let (w, h) = panels.iter().fold((0.0f64, 0.0f64), |(w, h), p| {
        (w.max(p.style.width()), h.max(p.style.height()))
    });
    let rows = panels.len().div_ceil(columns);
    let (tw, th) = (w * columns.min(panels.len()) as f64, h * rows as f64);
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{tw}\" height=\"{th}\" viewBox=\"0 0 {tw} {th}\">\n<rect width=\"{tw}\" height=\"{th}\" fill=\"white\"/>\n"
    );
    for (i, p) in panels.iter().enumerate() {
        let x = (i % columns) as f64 * w;
        let y = (i / columns) as f64 * h;
        out.push_str(&format!("<g transform=\"translate({x} {y})\">\n"));
        out.push_str(&p.svg_body(&format!("p{i}"))?);
        out.push_str("</g>\n");
    }
    out.push_str("</svg>\n");
    Ok(out)
}

/// The paper's figures this module reproduces.
pub const FIGURES: [u32; 7] = [5, 6, 7, 8, 9, 10, 11];

/// The data of the paper's figure `number` (one of [`FIGURES`]).
pub fn figure(number: u32) -> Result<FigureData> {
    match number {
        10 => fig10(),
        11 => fig11(),
        5 => fig05(),
        6 => fig06(),
        7 => fig07(),
        8 => fig08(),
        9 => fig09(),
        _ => Err(Error::InvalidRequest(format!(
            "the paper has no figure {number} with data; give one of 5, 6, 7, 8, 9, 10, 11 or all"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::LineStyle;

    #[test]
    fn composes_panels_side_by_side() {
        let mut a = Figure::new("left", "x", "y");
        a.push("one", vec![(0.0, 0.0), (1.0, 1.0)], LineStyle::Solid, 1);
        let mut b = Figure::new("right", "x", "y");
        b.push("two", vec![(0.0, 1.0), (1.0, 0.0)], LineStyle::Dashed, 2);
        let svg = compose_svg(&[a, b], 2).unwrap();
        assert!(
            svg.starts_with(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"960\" height=\"360\""
            )
        );
        assert!(svg.contains("<g transform=\"translate(480 0)\">"));
        assert!(svg.contains("id=\"p0-plot\"") && svg.contains("id=\"p1-plot\""));
        assert!(svg.contains("left") && svg.contains("right"));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
}
