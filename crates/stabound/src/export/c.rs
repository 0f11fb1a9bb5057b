//! The `alpha_max` lookup table as a self-contained C99 header (`stabound table --format c`),
//! with a `static inline` lookup function that implements the table's documented procedure
//! (see [`crate::amax::AmaxTable::lookup`]). Also the pieces the Rust and JSON exports share
//! with it: the values in the table's precision and units, and the procedure in words.

use std::fmt::Write;

use crate::amax::{AmaxTable, Interpolation, Precision};
use crate::elements::{Loop, list};
use crate::export::lookup::{DeviceScale, TableUnits};

/// Round-trip decimal form of `v`, a valid C and Rust floating literal.
pub(crate) fn lit(v: f64) -> String {
    // `{:?}` prints the shortest string that parses back to the same f64 (e.g. `0.1`,
    // `1e-5`, `3.0`), so header values equal the CSV's bit for bit.
    format!("{v:?}")
}

/// The shortest literal of `v` in precision `p` (`f32` values with the C suffix `f` when
/// `suffix`), reading back to the same value of that type.
pub(crate) fn lit_in(v: f64, p: Precision, suffix: &str) -> String {
    match p {
        Precision::Double => lit(v),
        // the values of a float table are f32 values already: `as` is exact here
        Precision::Float => format!("{:?}{suffix}", v as f32),
    }
}

/// `v` to 6 significant digits, for the header's prose.
pub(crate) fn sig(v: f64) -> String {
    format!("{:.5e}", v)
        .parse::<f64>()
        .map(|x| format!("{x}"))
        .unwrap_or_else(|_| format!("{v}"))
}

/// The arrays a lookup reads: the `delta` (or physical damping) axis, `alpha` (or `K`) and
/// `beta` (or `B`), in the table's precision.
pub(crate) struct LookupData {
    /// The first axis.
    pub x: Vec<f64>,
    /// Stiffness values `[d][x]`.
    pub k: Vec<Vec<f64>>,
    /// Damping values `[d][x]`.
    pub b: Vec<Vec<f64>>,
}

/// The physical arrays of `t` for device `u`, rounded to the table's precision: the
/// damping axis and `B` to nearest, `K` down for a conservative table (toward safety: a
/// smaller stiffness at the same damping stays in the stable interval the table was checked
/// on) and to nearest otherwise.
pub(crate) fn physical(t: &AmaxTable, u: &DeviceScale) -> LookupData {
    let p = t.precision;
    let k = |a: f64| {
        if t.conservative {
            p.round_down(u.k(a))
        } else {
            p.round(u.k(a))
        }
    };
    LookupData {
        x: t.delta.iter().map(|&x| p.round(u.damping(x))).collect(),
        k: t.alpha_max
            .iter()
            .map(|r| r.iter().map(|&a| k(a)).collect())
            .collect(),
        b: t.beta_at_max
            .iter()
            .map(|r| r.iter().map(|&b| p.round(u.b(b))).collect())
            .collect(),
    }
}

/// The loop elements `t` models, one line each (no comment markers): each element's
/// normalized values exactly (round-trip literals) and, with `units`, in physical units to 6
/// digits; empty for the paper's loop.
pub(crate) fn element_lines(t: &AmaxTable, units: &TableUnits) -> Vec<String> {
    let mut l = match &t.elements {
        Some(lp) => element_lines_of(lp, units),
        None => Vec::new(),
    };
    if let Some(set) = &t.set {
        l.push(
            "Set of devices: every node is the largest stiffness for which one damping is".into(),
        );
        l.push("  stable for every member (the model document, section 12):".into());
        l.extend(set.describe().into_iter().map(|d| format!("    {d};")));
        l.push(
            "  verified exactly for a finite set, proved over a box of the device's and its".into(),
        );
        l.push(
            "  elements' parameters when the cells close, by a sampling argument otherwise; the"
                .into(),
        );
        l.push("  conservative check tests each query on a sample of the members (all of a finite set).".into());
    }
    // exact: 1 is the default, no margin asked for
    if t.margin != 1.0 {
        l.push(format!(
            "Nodes at {} of alpha_max (damping left where the maximum is reached); every check",
            t.margin
        ));
        l.push("  below was made on these walls.".into());
    }
    l
}

fn element_lines_of(lp: &Loop, units: &TableUnits) -> Vec<String> {
    let mut l = vec![
        "Loop elements modelled (the paper's loop plus these; the model document, section 8):"
            .to_string(),
    ];
    for el in list::Element::ALL {
        let readings = el.readings(lp);
        if readings.is_empty() {
            continue;
        }
        l.push(format!("  {}:", el.title(lp)));
        let last = readings.len() - 1;
        for (i, (p, r)) in readings.into_iter().enumerate() {
            let value = match r.value {
                list::Value::Number(x) => lit(x),
                list::Value::Count(n) => n.to_string(),
                list::Value::Choice(c) => c.to_string(),
            };
            let physical = units
                .as_ref()
                .and_then(|u| r.physical(u.mass, u.period))
                .map_or(String::new(), |x| format!(" ({} {})", sig(x), p.unit));
            let end = if i == last { "." } else { "," };
            l.push(format!("    {} = {value}{physical}{end}", r.form));
        }
    }
    l.push(
        "  Every node and every checked query is this loop on the device at that damping and"
            .into(),
    );
    l.push("  delay; the nodes come from the direct search on its own curve.".into());
    l
}

/// The procedure, the range and the promise of `t` in words, one line each (no comment
/// markers): the same text in the C header, the Rust module and the JSON object.
pub(crate) fn rule_lines(t: &AmaxTable, units: &TableUnits) -> Vec<String> {
    let (x, xs, unit, k, b) = match units {
        Some(u) => ("b", physical(t, u).x, " N s/m", "K", "B"),
        None => ("delta", t.delta.clone(), "", "alpha", "beta"),
    };
    let first = xs.first().copied().unwrap_or(0.0);
    let last = xs.last().copied().unwrap_or(0.0);
    let mut l = Vec::new();
    l.push(format!(
        "Lookup (the lookup function implements it; every operation in {}):",
        t.precision.name()
    ));
    let dl: Vec<String> = t.d.iter().map(|&d| sig(d)).collect();
    let d_rule = match t.interpolation {
        Interpolation::Rows => format!("one of {}", dl.join(", ")),
        Interpolation::Bilinear => format!("in [{}, {}]", sig(t.d[0]), sig(t.d[t.d.len() - 1])),
    };
    l.push(format!(
        "  range: {x} in [{}, {}]{unit}; d (delay in samples) {d_rule}.",
        sig(first),
        sig(last)
    ));
    l.push(
        "  Any other query (NaN included) is refused: the lookup returns no wall and writes".into(),
    );
    l.push("  nothing; it never clamps or extrapolates.".into());
    l.push(format!(
        "  X is the {x} axis, D the d axis, V[i][j] the {k} or {b} values ([d][{x}]):"
    ));
    if xs.len() > 1 {
        l.push(format!(
            "  j is the first interval with X[j] <= {x} <= X[j+1], s = ({x} - X[j]) / (X[j+1] - X[j]);"
        ));
        l.push(format!(
            "  in row i, v_i = V[i][j] + s * (V[i][j+1] - V[i][j]) for {k} and {b} alike"
        ));
        l.push("  (the same nodes and the same s for both).".into());
    } else {
        l.push(format!(
            "  one node per row: v_i = V[i][0] for {k} and {b} alike."
        ));
    }
    match t.interpolation {
        Interpolation::Rows => l.push(
            "  d is not interpolated: i is the row whose delay equals d, and v = v_i.".into(),
        ),
        Interpolation::Bilinear => {
            if t.d.len() > 1 {
                l.push(
                    "  d is interpolated: i is the first interval with D[i] <= d <= D[i+1],".into(),
                );
                l.push("  u = (d - D[i]) / (D[i+1] - D[i]), v = v_i + u * (v_{i+1} - v_i) for both alike.".into());
            } else {
                l.push("  one row: v = v_0.".into());
            }
        }
    }
    if t.conservative {
        let along = match t.interpolation {
            Interpolation::Rows => {
                "  interval; each row alone, so nothing is lowered along d) by stabound's point test,"
            }
            Interpolation::Bilinear => {
                "  interval, with k/8 of every d interval, in every combination) by stabound's point test,"
            }
        };
        l.push(format!(
            "CONSERVATIVE: every wall ({k}, {b}) this lookup yields for a query in range is stable."
        ));
        l.push(format!(
            "  Checked at {} queries (the nodes, 2^-20 inside each end and k/16 of every {x}",
            t.checked_queries()
        ));
        l.push(along.into());
        l.push(format!(
            "  with {k} raised and {b} moved either way by {} units of roundoff of the largest",
            crate::amax::GUARD_ULPS
        ));
        l.push(format!(
            "  node read. {k} nodes were lowered ({b} never) only as far as that needed."
        ));
        l.push(format!("  Largest lowering of {k} per row:"));
        for r in t.lowering() {
            let (abs, at, exact) = match units {
                Some(u) => (
                    format!("{} N/m", sig(u.k(r.largest))),
                    format!("b = {} N s/m", sig(u.damping(r.at_delta))),
                    sig(u.k(r.exact)),
                ),
                None => (
                    sig(r.largest),
                    format!("delta = {}", sig(r.at_delta)),
                    sig(r.exact),
                ),
            };
            l.push(format!(
                "    d = {}: {abs} at {at} ({} % of the exact {exact}); largest relative {} %",
                sig(r.d),
                sig(100.0 * r.largest / r.exact.max(f64::MIN_POSITIVE)),
                sig(100.0 * r.largest_relative)
            ));
        }
        if t.certified {
            l.push(format!(
                "CERTIFIED: for every {x} of every interval (not samples), every wall with {k} and {b}"
            ));
            l.push(
                "  each within that guard of the interpolated values, and delta too, is proved stable by"
                    .into(),
            );
            l.push("  interval Schur-Cohn boxes (the model document, section 11); the certificate file".into());
            l.push("  replays with the standalone checker tools/verify_certificate.py.".into());
        }
    } else {
        l.push(format!(
            "NOT conservative: the nodes are the exact values{}; a wall read between nodes can be",
            if t.precision == Precision::Float {
                " rounded to nearest float"
            } else {
                ""
            }
        ));
        l.push(
            "  unstable, and at a node it is on the stability boundary. Generate a conservative"
                .into(),
        );
        l.push("  table for firmware.".into());
    }
    l
}

fn array_1d(out: &mut String, ty: &str, p: Precision, name: &str, n: &str, v: &[f64]) {
    let _ = writeln!(out, "static const {ty} {name}[{n}] = {{");
    for chunk in v.chunks(4) {
        let row: Vec<String> = chunk.iter().map(|x| lit_in(*x, p, "f")).collect();
        let _ = writeln!(out, "    {},", row.join(", "));
    }
    out.push_str("};\n\n");
}

fn array_2d(out: &mut String, ty: &str, p: Precision, name: &str, v: &[Vec<f64>]) {
    let _ = writeln!(
        out,
        "static const {ty} {name}[STABOUND_N_D][STABOUND_N_DELTA] = {{"
    );
    for row in v {
        out.push_str("    {\n");
        for chunk in row.chunks(4) {
            let r: Vec<String> = chunk.iter().map(|x| lit_in(*x, p, "f")).collect();
            let _ = writeln!(out, "        {},", r.join(", "));
        }
        out.push_str("    },\n");
    }
    out.push_str("};\n\n");
}

/// The C function `name(x, d, *k, *b)` implementing the procedure on the arrays `xs`, `ks`,
/// `bs` (returns 0, or -1 for a refused query).
fn c_lookup(o: &mut String, t: &AmaxTable, ty: &str, names: [&str; 4], args: [&str; 2]) {
    let [name, xs, ks, bs] = names;
    let [kn, bn] = args;
    let nx = t.delta.len();
    let nd = t.d.len();
    // a table of whole delays is looked up by an integer number of samples: no comparison
    // of floating-point values for equality in the firmware
    let dty = match t.interpolation {
        Interpolation::Rows => "int",
        Interpolation::Bilinear => ty,
    };
    let _ = writeln!(
        o,
        "static inline int {name}({ty} x, {dty} d, {ty} *{kn}, {ty} *{bn})\n{{"
    );
    let _ = writeln!(o, "    int i = 0, j = 0;");
    let _ = writeln!(
        o,
        "    if (!(x >= {xs}[0] && x <= {xs}[STABOUND_N_DELTA - 1]))\n        return -1;"
    );
    let row = |o: &mut String, var: &str, i: &str| {
        if nx > 1 {
            let _ = writeln!(
                o,
                "    {var}_k = {ks}[{i}][j] + s * ({ks}[{i}][j + 1] - {ks}[{i}][j]);\n    {var}_b = {bs}[{i}][j] + s * ({bs}[{i}][j + 1] - {bs}[{i}][j]);"
            );
        } else {
            let _ = writeln!(
                o,
                "    {var}_k = {ks}[{i}][0];\n    {var}_b = {bs}[{i}][0];"
            );
        }
    };
    match t.interpolation {
        Interpolation::Rows => {
            let _ = writeln!(
                o,
                "    while (i < STABOUND_N_D && d != stabound_d[i])\n        i++;\n    if (i == STABOUND_N_D)\n        return -1;"
            );
        }
        Interpolation::Bilinear => {
            let _ = writeln!(
                o,
                "    if (!(d >= stabound_d[0] && d <= stabound_d[STABOUND_N_D - 1]))\n        return -1;"
            );
            if nd > 1 {
                let _ = writeln!(
                    o,
                    "    while (i + 2 < STABOUND_N_D && d > stabound_d[i + 1])\n        i++;"
                );
            }
        }
    }
    if nx > 1 {
        let _ = writeln!(
            o,
            "    while (j + 2 < STABOUND_N_DELTA && x > {xs}[j + 1])\n        j++;\n    {{\n    const {ty} s = (x - {xs}[j]) / ({xs}[j + 1] - {xs}[j]);"
        );
    } else {
        let _ = writeln!(o, "    (void)j;\n    {{");
    }
    let _ = writeln!(o, "    {ty} r0_k, r0_b;");
    row(o, "r0", "i");
    if t.interpolation == Interpolation::Bilinear && nd > 1 {
        let _ = writeln!(
            o,
            "    {{\n    const {ty} u = (d - stabound_d[i]) / (stabound_d[i + 1] - stabound_d[i]);\n    {ty} r1_k, r1_b;"
        );
        row(o, "r1", "i + 1");
        let _ = writeln!(
            o,
            "    *{kn} = r0_k + u * (r1_k - r0_k);\n    *{bn} = r0_b + u * (r1_b - r0_b);\n    }}"
        );
    } else {
        let _ = writeln!(o, "    *{kn} = r0_k;\n    *{bn} = r0_b;");
    }
    o.push_str("    }\n    return 0;\n}\n\n");
}

/// The table as a C99 header: `static const double` (or `float`) arrays for the axes and the
/// values, the model, tolerance and units in a comment, the lookup procedure, its range, the
/// promise and the largest lowering per row, and `static inline` lookup functions
/// (`stabound_lookup`, and with units `stabound_lookup_physical`) implementing the
/// procedure. Compiles with `cc -std=c99 -Wall -Werror` and needs no other header.
pub fn to_c_header(t: &AmaxTable, units: &TableUnits) -> String {
    let p = t.precision;
    let ty = match p {
        Precision::Double => "double",
        Precision::Float => "float",
    };
    let mut o = String::new();
    o.push_str("/* Maximum stable virtual-wall stiffness, generated by stabound ");
    o.push_str(env!("CARGO_PKG_VERSION"));
    o.push_str(
        ".\n *\n * Model: damped mass m with physical damping b, sampled every T, virtual wall\n * F_k = -(K x_k + B (x_k - x_{k-1}) / T) delayed by d*T through a zero-order hold\n * (Hulin, Preusche, Hirzinger, IROS 2006; exact ZOH discretization, any real d).\n * Normalized: alpha = K T^2/m, beta = B T/m, delta = b T/m, d = delay/T.\n *\n",
    );
    let _ = writeln!(
        o,
        " * alpha_max[i][j]: largest stable alpha for d = stabound_d[i], delta = stabound_delta[j],\n *   over {}; beta_at_max: the beta where it is reached.",
        beta_range(t)
    );
    if t.elements.is_none() {
        let _ = writeln!(
            o,
            " * Computed by direct search of the stable region's rightmost point, theta tolerance\n *   {:e} rad (relative accuracy about 1e-10 at the default 1e-12).",
            t.tol
        );
    }
    if let Some(u) = units {
        let _ = writeln!(
            o,
            " * Device: m = {} kg, T = {} s; stabound_damping is b in N s/m (delta = b T / m),\n *   stabound_k_max is K_max = alpha_max m / T^2 in N/m, stabound_b_at_max is B in N s/m.",
            lit(u.mass),
            lit(u.period)
        );
    }
    let elements = element_lines(t, units);
    if !elements.is_empty() {
        o.push_str(" *\n");
    }
    for line in elements {
        let _ = writeln!(o, " * {line}");
    }
    if p == Precision::Float {
        o.push_str(" * Precision: float (values and arithmetic); stiffness values rounded down (toward\n *   safety), the rest to nearest; the check below was made on the rounded values.\n");
    }
    o.push_str(" *\n");
    for line in rule_lines(t, units) {
        let _ = writeln!(o, " * {line}");
    }
    o.push_str(" * Use a stiffness below the wall read: a margin against model error is yours to choose.\n */\n");
    o.push_str("#ifndef STABOUND_AMAX_TABLE_H\n#define STABOUND_AMAX_TABLE_H\n\n");
    let _ = writeln!(o, "#define STABOUND_N_DELTA {}", t.delta.len());
    let _ = writeln!(o, "#define STABOUND_N_D {}", t.d.len());
    let _ = writeln!(
        o,
        "#define STABOUND_CONSERVATIVE {}",
        u8::from(t.conservative)
    );
    let _ = writeln!(
        o,
        "#define STABOUND_INTERPOLATE_D {}\n",
        u8::from(t.interpolation == Interpolation::Bilinear)
    );
    o.push_str("/* normalized physical damping delta = b T / m (dimensionless) */\n");
    array_1d(
        &mut o,
        ty,
        p,
        "stabound_delta",
        "STABOUND_N_DELTA",
        &t.delta,
    );
    o.push_str("/* delay factor d = delay / T (samples) */\n");
    match t.interpolation {
        Interpolation::Rows => {
            // whole numbers of samples, far below the range of int (MAX_DELAY)
            let whole: Vec<String> = t.d.iter().map(|d| format!("{}", *d as i64)).collect();
            let _ = writeln!(
                o,
                "static const int stabound_d[STABOUND_N_D] = {{\n    {},\n}};\n",
                whole.join(", ")
            );
        }
        Interpolation::Bilinear => array_1d(&mut o, ty, p, "stabound_d", "STABOUND_N_D", &t.d),
    }
    o.push_str("/* alpha_max = K_max T^2 / m (dimensionless), [d][delta] */\n");
    array_2d(&mut o, ty, p, "stabound_alpha_max", &t.alpha_max);
    o.push_str("/* beta at alpha_max = B T / m (dimensionless), [d][delta] */\n");
    array_2d(&mut o, ty, p, "stabound_beta_at_max", &t.beta_at_max);
    if let Some(u) = units {
        let ph = physical(t, u);
        o.push_str("/* physical damping b in N s/m */\n");
        array_1d(&mut o, ty, p, "stabound_damping", "STABOUND_N_DELTA", &ph.x);
        o.push_str("/* K_max in N/m, [d][delta] */\n");
        array_2d(&mut o, ty, p, "stabound_k_max", &ph.k);
        o.push_str("/* wall damping B at K_max in N s/m, [d][delta] */\n");
        array_2d(&mut o, ty, p, "stabound_b_at_max", &ph.b);
    }
    o.push_str("/* The lookup above in normalized units: the wall (alpha, beta) at (delta, d).\n   Returns 0, or -1 for a query outside the table (outputs untouched). */\n");
    c_lookup(
        &mut o,
        t,
        ty,
        [
            "stabound_lookup",
            "stabound_delta",
            "stabound_alpha_max",
            "stabound_beta_at_max",
        ],
        ["alpha", "beta"],
    );
    if units.is_some() {
        o.push_str("/* The lookup above in physical units: the wall (K in N/m, B in N s/m) at physical\n   damping b (N s/m) and delay d (samples). Returns 0, or -1 for a query outside\n   the table (outputs untouched). */\n");
        c_lookup(
            &mut o,
            t,
            ty,
            [
                "stabound_lookup_physical",
                "stabound_damping",
                "stabound_k_max",
                "stabound_b_at_max",
            ],
            ["k", "b"],
        );
    }
    o.push_str("#endif /* STABOUND_AMAX_TABLE_H */\n");
    o
}

/// The beta range the table was computed over, in words.
pub(crate) fn beta_range(t: &AmaxTable) -> String {
    match (t.options.beta_min(), t.options.beta_max()) {
        (None, None) => "all beta".into(),
        (Some(a), None) => format!("beta >= {}", lit(a)),
        (None, Some(b)) => format!("beta <= {}", lit(b)),
        (Some(a), Some(b)) => format!("{} <= beta <= {}", lit(a), lit(b)),
    }
}
