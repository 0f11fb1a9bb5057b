//! The drawings, read back from the SVG text: sub-pixel coordinates, Greek labels, clean
//! tick labels, legends off the data, no box edges drawn as boundaries, and PNG / PDF
//! files that decode to the requested size.

use stabound::boundary::{Axis, BisectOptions, Plane, bisect};
use stabound::figures::{self, boundary_lines};
use stabound::plot::{Figure, Format, Legend, LineStyle};
#[cfg(any(feature = "raster", feature = "pdf"))]
use stabound::plot::{FigureStyle, render};
use stabound::{Normalized, Wall};

/// The numbers of every `d="..."` path attribute inside the plot's clip group (the data).
fn data_paths(svg: &str) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for group in svg.split("<g clip-path=").skip(1) {
        let group = &group[..group.find("</g>").unwrap()];
        for path in group.split("<path d=\"").skip(1) {
            let d = &path[..path.find('"').unwrap()];
            let mut poly: Vec<(f64, f64)> = Vec::new();
            for cmd in d.split(['M', 'L']) {
                let nums: Vec<f64> = cmd
                    .trim_end_matches('Z')
                    .split_whitespace()
                    .filter_map(|t| t.parse().ok())
                    .collect();
                if nums.len() == 2 {
                    poly.push((nums[0], nums[1]));
                }
            }
            out.push(poly);
        }
    }
    out
}

/// The legend boxes: the first `<rect>` of every `<g class="legend">`, as (x0, y0, x1, y1).
fn legend_boxes(svg: &str) -> Vec<(f64, f64, f64, f64)> {
    let attr = |s: &str, name: &str| -> f64 {
        let key = format!(" {name}=\"");
        let i = s.find(&key).unwrap() + key.len();
        s[i..i + s[i..].find('"').unwrap()].parse().unwrap()
    };
    svg.split("<g class=\"legend\"><rect")
        .skip(1)
        .map(|r| {
            let r = &r[..r.find("/>").unwrap()];
            let (x, y) = (attr(r, "x"), attr(r, "y"));
            (x, y, x + attr(r, "width"), y + attr(r, "height"))
        })
        .collect()
}

/// Whether segment a-b comes within the box, by sampling it every 0.05 px (an independent
/// route to the drawing's own clipping arithmetic).
fn touches(b: (f64, f64, f64, f64), a: (f64, f64), c: (f64, f64)) -> bool {
    let len = (c.0 - a.0).hypot(c.1 - a.1);
    let n = (len / 0.05).ceil().max(1.0) as usize;
    (0..=n).any(|i| {
        let t = i as f64 / n as f64;
        let (x, y) = (a.0 + t * (c.0 - a.0), a.1 + t * (c.1 - a.1));
        x >= b.0 && x <= b.2 && y >= b.1 && y <= b.3
    })
}

fn assert_legends_clear(name: &str, svg: &str) {
    let boxes = legend_boxes(svg);
    let paths = data_paths(svg);
    assert!(!paths.is_empty(), "{name}: no data paths");
    for b in &boxes {
        for p in &paths {
            for w in p.windows(2) {
                assert!(
                    !touches(*b, w[0], w[1]),
                    "{name}: legend {b:?} covers {w:?}"
                );
            }
        }
    }
}

/// Every figure of the paper: legends (one per panel) cover no drawn line, coordinates
/// carry decimals (not whole pixels), labels are Greek, tick labels are clean.
#[test]
fn paper_figures_draw_cleanly() {
    for n in figures::FIGURES {
        let fd = figures::figure(n).unwrap();
        let svg = fd.to_svg().unwrap();
        let name = &fd.name;
        assert_eq!(
            legend_boxes(&svg).len(),
            fd.panels.len(),
            "{name}: one legend a panel"
        );
        assert_legends_clear(name, &svg);
        let coords: Vec<f64> = data_paths(&svg)
            .into_iter()
            .flatten()
            .flat_map(|(x, y)| [x, y])
            .collect();
        let fractional = coords.iter().filter(|v| v.fract() != 0.0).count();
        // exact: a whole-pixel writer gives fract() == 0 for every coordinate
        assert!(
            fractional * 2 > coords.len(),
            "{name}: {fractional} of {} coordinates off the pixel grid",
            coords.len()
        );
        // no negative zero, no ASCII Greek names
        for bad in [">-0<", ">\u{2212}0<", "alpha", "delta ="] {
            assert!(!svg.contains(bad), "{name}: contains {bad}");
        }
        if n != 11 {
            assert!(svg.contains('δ'), "{name}: no δ");
        }
    }
    // whole steps print without decimals: Fig. 10 (b) has delta ticks 0, 2, ..., 10
    let svg = figures::fig10().unwrap().to_svg().unwrap();
    assert!(svg.contains(">10</text>") && !svg.contains(">10.0</text>"));
    let svg = figures::fig05().unwrap().to_svg().unwrap();
    assert!(svg.contains("virtual stiffness α") && svg.contains("δ = 0.25"));
}

/// Every kind of line has a legend entry: the dashed path (Fig. 5), the passive region
/// (Figs. 8, 9), the floor (Fig. 6); the dashed sample is dashed.
#[test]
fn legends_name_every_kind_of_line() {
    let legend = |svg: &str| -> String {
        let i = svg.find("<g class=\"legend\">").unwrap();
        svg[i..].to_string()
    };
    let f5 = figures::fig05().unwrap().to_svg().unwrap();
    let l5 = legend(&f5);
    let path = &l5[l5.find("max. stiffness path").unwrap() - 400..];
    assert!(path.contains("stroke-dasharray"));
    for (fd, key) in [
        (figures::fig08().unwrap(), "passive region"),
        (figures::fig09().unwrap(), "passive region"),
        (figures::fig06().unwrap(), "floor β = −δ"),
    ] {
        assert!(legend(&fd.to_svg().unwrap()).contains(key), "{}", fd.name);
    }
}

/// A plot filled with lines everywhere has no free corner: the legend goes outside the plot
/// area and still covers nothing.
#[test]
fn crowded_plot_puts_the_legend_outside() {
    let mut f = Figure::new("crowded", "x", "y");
    for k in 0..12 {
        let y = k as f64 / 11.0;
        f.push(
            format!("line {k}"),
            vec![(0.0, y), (1.0, y)],
            LineStyle::Solid,
            k,
        );
    }
    f.push(
        "diagonal",
        vec![(0.0, 0.0), (1.0, 1.0)],
        LineStyle::DashDot,
        12,
    );
    for legend in [Legend::UpperRight, Legend::LowerLeft, Legend::Outside] {
        f.legend = legend;
        let svg = f.to_svg().unwrap();
        assert_legends_clear("crowded", &svg);
        // outside: the box lies right of or below every data vertex
        let b = legend_boxes(&svg)[0];
        let pts: Vec<(f64, f64)> = data_paths(&svg).into_iter().flatten().collect();
        let max_x = pts.iter().map(|p| p.0).fold(f64::MIN, f64::max);
        let max_y = pts.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert!(b.0 > max_x || b.1 > max_y, "{legend:?}: {b:?}");
    }
}

/// The (delta, beta) plane's box edges are not boundary: at alpha = 0.1, d = 1 on
/// delta in [0, 2], no drawn piece runs along delta = 0 or delta = 2, and every drawn vertex
/// off those edges is a wall at the stability boundary (stable and unstable walls within
/// 1e-4 of it on either side in beta).
#[test]
fn box_edges_are_not_drawn() {
    let plane = Plane {
        x: Axis::Delta,
        y: Axis::Beta,
        at: Normalized::new(0.1, 0.0, 0.0, 1.0).unwrap(),
    };
    let c = bisect(
        plane.at.plant(),
        &plane,
        &BisectOptions {
            tol: 1e-6,
            x_range: Some((0.0, 2.0)),
            ..BisectOptions::default()
        },
    )
    .unwrap();
    assert!(
        c.loops.iter().flatten().any(|p| p.clipped()),
        "the box clips the region"
    );
    let pieces: Vec<Vec<(f64, f64)>> = c.loops.iter().flat_map(|l| boundary_lines(l)).collect();
    assert!(!pieces.is_empty());
    for piece in &pieces {
        for w in piece.windows(2) {
            // exact: box-edge vertices carry the range's end itself
            let along_edge = w[0].0 == w[1].0 && (w[0].0 == 0.0 || w[0].0 == 2.0);
            assert!(!along_edge, "edge segment {w:?}");
        }
        for &(delta, beta) in piece {
            // neighbours 1e-4 away (100 times the tolerance) in delta and in beta: on the
            // boundary, some are stable and some are not
            if !(1e-3..=2.0 - 1e-3).contains(&delta) {
                continue;
            }
            let v = |dl: f64, b: f64| {
                let plant = stabound::Plant::new(dl, 1.0).unwrap();
                let checker = stabound::Checker::new(plant, Default::default()).unwrap();
                checker.verdict(&Wall::new(0.1, b).unwrap()).unwrap()
            };
            let h = 1e-4;
            let near = [
                v(delta, beta - h),
                v(delta, beta + h),
                v(delta - h, beta),
                v(delta + h, beta),
            ];
            assert!(
                near.iter().any(|x| *x != near[0]),
                "({delta}, {beta}) is not on the boundary: {near:?}"
            );
        }
    }
}

/// Format by extension, in any case; no extension is SVG; others are refused with the
/// accepted ones named.
#[test]
fn format_follows_the_extension() {
    use std::path::Path;
    assert_eq!(Format::from_path(Path::new("a.svg")).unwrap(), Format::Svg);
    assert_eq!(Format::from_path(Path::new("a.Png")).unwrap(), Format::Png);
    assert_eq!(
        Format::from_path(Path::new("dir.v2/a.pdf")).unwrap(),
        Format::Pdf
    );
    assert_eq!(
        Format::from_path(Path::new("/dev/stdout")).unwrap(),
        Format::Svg
    );
    for bad in ["a.jpg", "a.svgz", "a.csv"] {
        let e = Format::from_path(Path::new(bad)).unwrap_err().to_string();
        assert!(e.contains(".svg, .png or .pdf"), "{bad}: {e}");
    }
}

#[cfg(any(feature = "raster", feature = "pdf"))]
fn small_figure() -> Figure {
    let mut f = Figure::new("α and β", "α", "β");
    f.push(
        "δ = 1",
        vec![(0.0, 0.0), (0.5, 0.7), (1.0, 0.2)],
        LineStyle::Solid,
        1,
    );
    f.style = FigureStyle::new(321.0, 203.0, 11.0).unwrap();
    f
}

/// The PNG has the PNG signature and decodes (with the `png` crate) to the figure's size,
/// with dark text and line pixels on the white background.
#[cfg(feature = "raster")]
#[test]
fn png_decodes_to_the_requested_size() {
    let bytes = render(&small_figure().to_svg().unwrap(), Format::Png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (321, 203));
    let px = &buf[..info.buffer_size()];
    let step = info.line_size / info.width as usize;
    let dark = px.chunks(step).filter(|p| p[0] < 100 && p[1] < 100).count();
    let white = px
        .chunks(step)
        .filter(|p| p[..3] == [255, 255, 255])
        .count();
    assert!(dark > 200, "{dark} dark pixels: text and frame are drawn");
    assert!(white * 2 > px.len() / step, "mostly white background");
}

/// The PDF starts with `%PDF`, names svg2pdf as its producer, embeds DejaVu Sans and has a
/// page of the figure's size at 96 px per inch (321 px = 240.75 pt).
#[cfg(feature = "pdf")]
#[test]
fn pdf_is_svg2pdf_output_with_the_font() {
    let bytes = render(&small_figure().to_svg().unwrap(), Format::Pdf).unwrap();
    assert!(bytes.starts_with(b"%PDF-"));
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("/Producer (svg2pdf)"));
    assert!(text.contains("DejaVuSans"));
    assert!(text.contains("240.75"), "page width in points");
}
