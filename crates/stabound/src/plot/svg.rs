//! The SVG writer: frame, ticks, labels, clipped paths with dashes and markers, legend.

use std::fmt::Write as _;

use super::layout::{LegendBox, Rect, candidates, clip_polyline, sample_length, text_width};
use super::ticks::{Tick, ticks};
use super::{Figure, Legend, LineStyle, palette};

/// Font family of every text element: the font embedded in PNG and PDF output first.
pub(crate) const FONT: &str = "DejaVu Sans, Verdana, Arial, sans-serif";

/// A coordinate or length in pixels with at most two decimals (1/100 pixel, far below
/// what a viewer resolves; whole numbers print without a point), never `-0`.
pub(crate) fn num(v: f64) -> String {
    let mut s = format!("{v:.2}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" { "0".into() } else { s }
}

/// Text escaped for XML character data and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // control characters are not allowed in XML 1.0
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// The seven marker shapes, by series colour index modulo 7.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
    OpenCircle,
    OpenSquare,
}

fn marker_of(color: usize) -> Marker {
    [
        Marker::Circle,
        Marker::Square,
        Marker::TriangleUp,
        Marker::Diamond,
        Marker::TriangleDown,
        Marker::OpenCircle,
        Marker::OpenSquare,
    ][color % 7]
}

fn write_marker(out: &mut String, m: Marker, color: &str, (x, y): (f64, f64), r: f64, lw: f64) {
    let (cx, cy) = (num(x), num(y));
    let poly = |pts: &[(f64, f64)]| {
        let mut d = String::new();
        for (i, (dx, dy)) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{} {}",
                if i == 0 { "M" } else { "L" },
                num(x + dx * r),
                num(y + dy * r)
            );
        }
        d.push('Z');
        d
    };
    let filled = format!("fill=\"{color}\" stroke=\"none\"");
    let open = format!(
        "fill=\"white\" stroke=\"{color}\" stroke-width=\"{}\"",
        num(0.8 * lw)
    );
    let _ = match m {
        Marker::Circle => writeln!(
            out,
            "<circle cx=\"{cx}\" cy=\"{cy}\" r=\"{}\" {filled}/>",
            num(r)
        ),
        Marker::OpenCircle => writeln!(
            out,
            "<circle cx=\"{cx}\" cy=\"{cy}\" r=\"{}\" {open}/>",
            num(0.9 * r)
        ),
        Marker::Square | Marker::OpenSquare => {
            let s = 0.85 * r;
            writeln!(
                out,
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {}/>",
                num(x - s),
                num(y - s),
                num(2.0 * s),
                num(2.0 * s),
                if m == Marker::Square { &filled } else { &open }
            )
        }
        Marker::TriangleUp => writeln!(
            out,
            "<path d=\"{}\" {filled}/>",
            poly(&[(0.0, -1.2), (1.1, 0.75), (-1.1, 0.75)])
        ),
        Marker::TriangleDown => writeln!(
            out,
            "<path d=\"{}\" {filled}/>",
            poly(&[(0.0, 1.2), (1.1, -0.75), (-1.1, -0.75)])
        ),
        Marker::Diamond => writeln!(
            out,
            "<path d=\"{}\" {filled}/>",
            poly(&[(0.0, -1.25), (1.0, 0.0), (0.0, 1.25), (-1.0, 0.0)])
        ),
    };
}

/// Stroke attributes of a line style at line width `lw`.
fn stroke(style: LineStyle, color: &str, lw: f64) -> String {
    // a band: five line widths at 35 % opacity, wide enough to show beside a line drawn on
    // it and light enough not to hide it
    let (w, extra) = if style == LineStyle::Band {
        (
            5.0 * lw,
            " stroke-opacity=\"0.35\" stroke-linecap=\"round\"",
        )
    } else {
        (lw, "")
    };
    let mut s = format!(
        "fill=\"none\" stroke=\"{color}\" stroke-width=\"{}\" stroke-linejoin=\"round\"{extra}",
        num(w)
    );
    if let Some(d) = style.dashes() {
        let pattern: Vec<String> = d.iter().map(|v| num(v * lw)).collect();
        let _ = write!(s, " stroke-dasharray=\"{}\"", pattern.join(" "));
    }
    s
}

/// The runs of a label: plain text, and subscripts written `_{...}` (`α_{max}`), each with
/// whether it is a subscript. An unclosed `_{` is plain text.
pub(crate) fn runs(label: &str) -> impl Iterator<Item = (&str, bool)> {
    let mut rest = label;
    let mut pending: Option<&str> = None;
    std::iter::from_fn(move || {
        if let Some(sub) = pending.take() {
            return Some((sub, true));
        }
        if rest.is_empty() {
            return None;
        }
        match rest
            .find("_{")
            .and_then(|i| rest[i + 2..].find('}').map(|j| (i, i + 2 + j)))
        {
            Some((open, close)) => {
                let (plain, sub) = (&rest[..open], &rest[open + 2..close]);
                rest = &rest[close + 1..];
                if plain.is_empty() {
                    Some((sub, true))
                } else {
                    pending = Some(sub);
                    Some((plain, false))
                }
            }
            None => Some((std::mem::take(&mut rest), false)),
        }
    })
}

/// A label as SVG character data: escaped, subscripts as lowered, smaller `tspan`s.
fn markup(label: &str) -> String {
    runs(label)
        .map(|(run, sub)| {
            if sub {
                format!(
                    "<tspan baseline-shift=\"sub\" font-size=\"{}%\">{}</tspan>",
                    num(100.0 * super::layout::SUB_SCALE),
                    escape(run)
                )
            } else {
                escape(run)
            }
        })
        .collect()
}

fn text(out: &mut String, (x, y): (f64, f64), size: f64, anchor: &str, body: &str, extra: &str) {
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\"{extra}>{}</text>",
        num(x),
        num(y),
        num(size),
        markup(body)
    );
}

/// Where the legend goes once placed.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    Inside,
    Right,
    Below,
}

/// The frame of one layout: plot rectangle and ticks.
struct Frame {
    plot: Rect,
    xt: Vec<Tick>,
    yt: Vec<Tick>,
    title_size: f64,
}

/// Sizes derived from the style.
struct Metrics {
    w: f64,
    h: f64,
    f: f64,
    /// tick labels and legend text
    small: f64,
    lw: f64,
    tick: f64,
}

fn frame(
    fig: &Figure,
    m: &Metrics,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    legend: Option<(Place, &LegendBox)>,
) -> Frame {
    let f = m.f;
    let title_size = if fig.title.is_empty() {
        0.0
    } else {
        let tw = text_width(&fig.title, f);
        // a long title shrinks to the width, down to half the font size (a title wider than
        // that at a large font is cut at the canvas edges)
        (f * ((m.w - f) / tw).min(1.0)).max(0.5 * f)
    };
    let top = if fig.title.is_empty() {
        0.7 * f
    } else {
        1.9 * title_size
    };
    let mut bottom = m.tick + 0.3 * f + m.small + 0.4 * f;
    if !fig.x_label.is_empty() {
        bottom += 1.2 * f;
    }
    let mut right = 0.8 * f;
    match legend {
        Some((Place::Right, b)) => right += b.width() + 0.2 * f,
        Some((Place::Below, b)) => bottom += b.height() + 0.5 * f,
        _ => {}
    }
    let plot_h = (m.h - top - bottom).max(2.0 * f);
    let yt = ticks(y0, y1, (plot_h / (2.0 * f)) as usize);
    let yw = yt
        .iter()
        .map(|t| text_width(&t.label, m.small))
        .fold(0.0, f64::max);
    let mut left = 0.5 * f + yw + 0.3 * f + m.tick;
    if !fig.y_label.is_empty() {
        left += 1.3 * f;
    }
    let mut plot_w = (m.w - left - right).max(2.0 * f);
    let mut xt = ticks(x0, x1, (plot_w / (4.0 * f)) as usize);
    // fewer ticks when their labels would touch
    for _ in 0..4 {
        let widest = xt
            .iter()
            .map(|t| text_width(&t.label, m.small))
            .fold(0.0, f64::max);
        if xt.len() < 3 || widest + 0.8 * f <= plot_w / (xt.len() - 1) as f64 {
            break;
        }
        xt = ticks(x0, x1, xt.len().saturating_sub(2).max(2));
    }
    // room for half of the last tick label right of the plot
    if let Some(last) = xt.last() {
        let half = 0.5 * text_width(&last.label, m.small) + 0.2 * f;
        let at_end = (last.value - x1).abs() <= 1e-9 * (x1 - x0);
        if at_end && half > right && legend.is_none_or(|(p, _)| p != Place::Right) {
            plot_w -= half - right;
        }
    }
    Frame {
        plot: Rect {
            x0: left,
            y0: top,
            x1: left + plot_w.max(2.0 * f),
            y1: top + plot_h,
        },
        xt,
        yt,
        title_size,
    }
}

/// The drawn geometry of every series in pixels: clipped runs and marker positions.
struct Drawn {
    runs: Vec<Vec<Vec<(f64, f64)>>>,
    markers: Vec<Vec<(f64, f64)>>,
}

fn geometry(
    fig: &Figure,
    m: &Metrics,
    fr: &Frame,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Drawn {
    let p = fr.plot;
    let sx = p.width() / (x1 - x0);
    let sy = p.height() / (y1 - y0);
    let clip = p.grown(0.5 * m.lw);
    let spacing = 0.25 * (p.width() + p.height());
    let mut runs = Vec::with_capacity(fig.series.len());
    let mut markers = Vec::with_capacity(fig.series.len());
    for s in &fig.series {
        let mut rs = Vec::new();
        for piece in s.points.split(|q| !(q.0.is_finite() && q.1.is_finite())) {
            if piece.is_empty() {
                continue;
            }
            let px: Vec<(f64, f64)> = piece
                .iter()
                .map(|&(x, y)| (p.x0 + (x - x0) * sx, p.y1 - (y - y0) * sy))
                .collect();
            // 0.1 px: below what any viewer shows, and it keeps files of 30,000-vertex
            // boundaries small
            let min_step = if s.style == LineStyle::Points {
                0.0
            } else {
                0.1
            };
            rs.extend(clip_polyline(clip, &px, min_step));
        }
        let mut ms = Vec::new();
        if s.style == LineStyle::Points {
            ms.extend(rs.iter().flatten().copied().filter(|q| p.contains(*q)));
        } else if fig.style.markers() && s.style.marked() {
            // markers every `spacing` pixels of arc length, offset by the golden ratio per
            // colour so that markers of different series do not coincide
            let phase = (0.5 + 0.381_966 * s.color as f64).fract();
            for run in &rs {
                let mut next = phase * spacing;
                let mut along = 0.0;
                for w in run.windows(2) {
                    let len = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1);
                    while along + len >= next && len > 0.0 {
                        let t = (next - along) / len;
                        let q = (
                            w[0].0 + t * (w[1].0 - w[0].0),
                            w[0].1 + t * (w[1].1 - w[0].1),
                        );
                        if p.contains(q) {
                            ms.push(q);
                        }
                        next += spacing;
                    }
                    along += len;
                }
            }
        }
        runs.push(rs);
        markers.push(ms);
    }
    Drawn { runs, markers }
}

/// Whether the rectangle `r` is clear of every drawn line and marker.
fn is_free(r: Rect, d: &Drawn, marker_r: f64) -> bool {
    let lines_clear = d.runs.iter().flatten().all(|run| {
        run.windows(2).all(|w| !r.meets(w[0], w[1])) && !run.iter().any(|q| r.contains(*q))
    });
    let grown = r.grown(marker_r);
    lines_clear && d.markers.iter().flatten().all(|q| !grown.contains(*q))
}

/// Draws the figure with the given checked ranges; element ids start with `id`.
pub(crate) fn draw(fig: &Figure, x: (f64, f64), y: (f64, f64), id: &str) -> String {
    let f = fig.style.font_size();
    let m = Metrics {
        w: fig.style.width(),
        h: fig.style.height(),
        f,
        small: 0.875 * f,
        lw: (f / 9.0).max(1.0),
        tick: 0.35 * f,
    };
    let marker_r = 0.3 * f;
    let entries: Vec<usize> = (0..fig.series.len())
        .filter(|&i| !fig.series[i].label.is_empty())
        .collect();
    let label_w = entries
        .iter()
        .map(|&i| text_width(&fig.series[i].label, m.small))
        .fold(0.0, f64::max);
    // a free place inside the plot area, in the preferred order
    let mut fr = frame(fig, &m, x, y, None);
    let mut drawn = geometry(fig, &m, &fr, x, y);
    let mut legend: Option<(Place, LegendBox, Rect)> = None;
    if !entries.is_empty() {
        let one = LegendBox::new(entries.len(), label_w, m.small, 1);
        let first = match fig.legend {
            Legend::UpperRight | Legend::Outside => 0,
            Legend::UpperLeft => 1,
            Legend::LowerRight => 2,
            Legend::LowerLeft => 3,
        };
        if fig.legend != Legend::Outside {
            let gap = 0.3 * f;
            legend = candidates(fr.plot, &one, 0.4 * f, first)
                .into_iter()
                .find(|r| is_free(r.grown(gap), &drawn, marker_r))
                .map(|r| (Place::Inside, one, r));
        }
        if legend.is_none() {
            // outside: right of the plot in as many columns as the height needs, or below
            // it in as many columns as the width holds, whichever leaves the larger plot
            let avail = m.h - fr.plot.y0 - 0.6 * f;
            let per_column = (((avail - 2.0 * one.pad) / one.row_height).floor() as usize).max(1);
            let right = LegendBox::new(
                entries.len(),
                label_w,
                m.small,
                entries.len().div_ceil(per_column),
            );
            let fit = (((m.w - 1.2 * f) / one.column_width).floor() as usize).max(1);
            let below = LegendBox::new(entries.len(), label_w, m.small, fit);
            // the plot's area, counting no more width than 1.6 heights and no more height
            // than one width: flat or tall slivers of plot read badly
            let area = |place: Place, b: &LegendBox| {
                let p = frame(fig, &m, x, y, Some((place, b))).plot;
                p.width().min(1.6 * p.height()) * p.height().min(p.width())
            };
            let (place, b) = if area(Place::Right, &right) >= area(Place::Below, &below) {
                (Place::Right, right)
            } else {
                (Place::Below, below)
            };
            fr = frame(fig, &m, x, y, Some((place, &b)));
            drawn = geometry(fig, &m, &fr, x, y);
            let r = match place {
                Place::Right => b.at(fr.plot.x1 + 0.5 * f, fr.plot.y0),
                _ => b.at(
                    (0.5 * (m.w - b.width())).max(0.0),
                    m.h - b.height() - 0.4 * f,
                ),
            };
            legend = Some((place, b, r));
        }
    }
    let p = fr.plot;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<g font-family=\"{FONT}\" fill=\"black\">\n<rect width=\"{}\" height=\"{}\" fill=\"white\"/>",
        num(m.w),
        num(m.h)
    );
    let clip_id = format!("{id}-plot");
    let c = p.grown(0.5 * m.lw);
    let _ = writeln!(
        out,
        "<defs><clipPath id=\"{clip_id}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath></defs>",
        num(c.x0),
        num(c.y0),
        num(c.width()),
        num(c.height())
    );
    if !fig.title.is_empty() {
        text(
            &mut out,
            (0.5 * m.w, 1.25 * fr.title_size),
            fr.title_size,
            "middle",
            &fig.title,
            "",
        );
    }
    // ticks (outward) and their labels
    let (sx, sy) = (p.width() / (x.1 - x.0), p.height() / (y.1 - y.0));
    let mut tick_path = String::new();
    for t in &fr.xt {
        let px = p.x0 + (t.value - x.0) * sx;
        let _ = write!(
            tick_path,
            "M{} {}V{}",
            num(px),
            num(p.y1),
            num(p.y1 + m.tick)
        );
        text(
            &mut out,
            (px, p.y1 + m.tick + 0.2 * f + 0.8 * m.small),
            m.small,
            "middle",
            &t.label,
            "",
        );
    }
    for t in &fr.yt {
        let py = p.y1 - (t.value - y.0) * sy;
        let _ = write!(
            tick_path,
            "M{} {}H{}",
            num(p.x0),
            num(py),
            num(p.x0 - m.tick)
        );
        text(
            &mut out,
            (p.x0 - m.tick - 0.25 * f, py + 0.35 * m.small),
            m.small,
            "end",
            &t.label,
            "",
        );
    }
    let frame_w = (f / 16.0).max(0.8);
    let _ = writeln!(
        out,
        "<path d=\"{tick_path}\" fill=\"none\" stroke=\"black\" stroke-width=\"{}\"/>",
        num(frame_w)
    );
    if !fig.x_label.is_empty() {
        let base = p.y1 + m.tick + 0.3 * f + m.small + 0.2 * f + 0.85 * f;
        text(
            &mut out,
            (0.5 * (p.x0 + p.x1), base),
            f,
            "middle",
            &fig.x_label,
            "",
        );
    }
    if !fig.y_label.is_empty() {
        let (lx, ly) = (0.5 * f + 0.8 * f, 0.5 * (p.y0 + p.y1));
        let rot = format!(" transform=\"rotate(-90 {} {})\"", num(lx), num(ly));
        text(&mut out, (lx, ly), f, "middle", &fig.y_label, &rot);
    }
    // the data, clipped to the plot area
    let _ = writeln!(out, "<g clip-path=\"url(#{clip_id})\">");
    // bands first, beneath every other line
    let bands_first = fig
        .series
        .iter()
        .zip(&drawn.runs)
        .filter(|(s, _)| s.style == LineStyle::Band)
        .chain(
            fig.series
                .iter()
                .zip(&drawn.runs)
                .filter(|(s, _)| s.style != LineStyle::Band),
        );
    for (s, runs) in bands_first {
        if s.style == LineStyle::Points || runs.is_empty() {
            continue;
        }
        let mut d = String::new();
        for run in runs {
            for (i, q) in run.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{} {}",
                    if i == 0 { "M" } else { "L" },
                    num(q.0),
                    num(q.1)
                );
            }
        }
        let _ = writeln!(
            out,
            "<path d=\"{d}\" {}/>",
            stroke(s.style, palette(s.color), m.lw)
        );
    }
    for (s, ms) in fig.series.iter().zip(&drawn.markers) {
        let r = if s.style == LineStyle::Points {
            0.8 * marker_r
        } else {
            marker_r
        };
        for &q in ms {
            write_marker(&mut out, marker_of(s.color), palette(s.color), q, r, m.lw);
        }
    }
    out.push_str("</g>\n");
    let _ = writeln!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"{}\"/>",
        num(p.x0),
        num(p.y0),
        num(p.width()),
        num(p.height()),
        num(frame_w)
    );
    if let Some((place, b, r)) = legend {
        let _ = writeln!(
            out,
            "<g class=\"legend\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"white\" stroke=\"{}\" stroke-width=\"{}\"/>",
            num(r.x0),
            num(r.y0),
            num(r.width()),
            num(r.height()),
            if place == Place::Inside {
                "#999999"
            } else {
                "none"
            },
            num(0.8 * frame_w)
        );
        for (k, &i) in entries.iter().enumerate() {
            let s = &fig.series[i];
            let (col, row) = (k / b.rows, k % b.rows);
            let x0 = r.x0 + b.pad + col as f64 * b.column_width;
            let yc = r.y0 + b.pad + (row as f64 + 0.5) * b.row_height;
            let len = sample_length(m.small);
            let color = palette(s.color);
            if s.style != LineStyle::Points {
                let _ = writeln!(
                    out,
                    "<path d=\"M{} {}H{}\" {}/>",
                    num(x0),
                    num(yc),
                    num(x0 + len),
                    stroke(s.style, color, m.lw)
                );
            }
            let keyed = !s.points.is_empty()
                && match s.style {
                    LineStyle::Points => true,
                    style => style.marked() && fig.style.markers(),
                };
            if keyed {
                write_marker(
                    &mut out,
                    marker_of(s.color),
                    color,
                    (x0 + 0.5 * len, yc),
                    0.8 * marker_r,
                    m.lw,
                );
            }
            text(
                &mut out,
                (x0 + len + 0.5 * m.small, yc + 0.35 * m.small),
                m.small,
                "start",
                &s.label,
                "",
            );
        }
        out.push_str("</g>\n");
    }
    out.push_str("</g>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_two_decimals_at_most() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(1.234567), "1.23");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(12.5), "12.5");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn subscripts_are_lowered_and_other_underscores_kept() {
        let sub = "<tspan baseline-shift=\"sub\" font-size=\"70%\">";
        assert_eq!(markup("α_{max} [N]"), format!("α{sub}max</tspan> [N]"));
        assert_eq!(markup("F_{H}"), format!("F{sub}H</tspan>"));
        assert_eq!(markup("_{a}_{b}"), format!("{sub}a</tspan>{sub}b</tspan>"));
        // no braces: a plain underscore, as in a file name
        assert_eq!(markup("phantom_filtered"), "phantom_filtered");
        assert_eq!(markup("x_{<"), "x_{&lt;");
        assert_eq!(markup("a_{<b}"), format!("a{sub}&lt;b</tspan>"));
    }

    #[test]
    fn a_subscript_is_narrower_than_the_same_text_inline() {
        let (inline, sub) = (text_width("αmax", 10.0), text_width("α_{max}", 10.0));
        assert!(
            sub < inline && sub > text_width("α", 10.0),
            "{sub} vs {inline}"
        );
    }
}
