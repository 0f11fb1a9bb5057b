//! The generated C header's lookup keeps the table's promise: compiled with the system C
//! compiler into a program that calls `stabound_lookup` (or `stabound_lookup_physical`)
//! over a dense grid of queries, every wall it prints is stable by the library's point test
//! (`stabound::Checker`), for double and float, one and several delays, fractional delays
//! and physical units; with loop elements every wall is stable by that loop's own point test
//! (`stabound::elements::LoopChecker`), the loop built for each query's device. The grid (37 steps per delta interval, 7 per d interval, points
//! `1e-7` from every node) differs from the points the construction checked (16 and 8
//! steps, `2^-20`), so these are fresh queries. Queries outside the range must be refused.
//! The header compiles with `-Wfloat-equal`: a table of whole delays is looked up by an `int`
//! number of samples.

use stabound::elements::{Loop, PhysicalElements};
use stabound::{Checker, Delay, Device, Plant, Verdict, Wall};

use crate::common::stdout;

fn cc() -> Option<&'static str> {
    ["cc", "gcc", "clang"].into_iter().find(|c| {
        std::process::Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// A C program printing `x d k b` for every query of the dense grid (`%.17g` of the value
/// converted to double: exact for float and double), then `refused N` for the out-of-range
/// queries that were refused and `queries N`.
fn program(ty: &str, func: &str, xs: &str) -> String {
    format!(
        r#"#include <stdio.h>
#include <math.h>
#include "amax_table.h"
/* a table of whole delays takes an int number of samples */
#if STABOUND_INTERPOLATE_D
typedef {ty} delay_t;
#else
typedef int delay_t;
#endif
static int query({ty} x, delay_t d)
{{
    {ty} k = 0, b = 0;
    if ({func}(x, d, &k, &b) != 0)
        return 0;
    printf("%.17g %.17g %.17g %.17g\n", (double)x, (double)d, (double)k, (double)b);
    return 1;
}}
int main(void)
{{
    int i, j, a, c, n = 0, refused = 0;
    const {ty} ts[] = {{0, 1e-7, 1 - 1e-7}};
    for (i = 0; i < STABOUND_N_D; i++) {{
        int nd = (STABOUND_INTERPOLATE_D && i + 1 < STABOUND_N_D) ? 7 : 1;
        for (c = 0; c < nd + (nd > 1 ? 2 : 0); c++) {{
            {ty} u = c < nd ? ({ty})c / ({ty})nd : ts[c - nd + 1];
            delay_t d = nd > 1 ? (delay_t)(stabound_d[i] + u * (stabound_d[i + 1] - stabound_d[i])) : stabound_d[i];
            for (j = 0; j < STABOUND_N_DELTA; j++) {{
                if (j + 1 == STABOUND_N_DELTA) {{
                    n += query({xs}[j], d);
                    continue;
                }}
                for (a = 0; a < 37 + 2; a++) {{
                    {ty} t = a < 37 ? ({ty})a / ({ty})37 : ts[a - 37 + 1];
                    n += query({xs}[j] + t * ({xs}[j + 1] - {xs}[j]), d);
                }}
            }}
        }}
    }}
    {{
        {ty} k = 0, b = 0;
        {ty} hi = {xs}[STABOUND_N_DELTA - 1], lo = {xs}[0];
        delay_t dhi = stabound_d[STABOUND_N_D - 1];
        refused += {func}(hi + (hi > 0 ? hi : 1) * ({ty})1e-3, stabound_d[0], &k, &b) != 0;
        refused += {func}(lo - ({ty})1e-3, stabound_d[0], &k, &b) != 0;
        refused += {func}(({ty})NAN, stabound_d[0], &k, &b) != 0;
#if STABOUND_INTERPOLATE_D
        refused += {func}(lo, dhi + ({ty})0.25, &k, &b) != 0;
        refused += {func}(lo, ({ty})NAN, &k, &b) != 0;
        refused += 1;
#else
        refused += {func}(lo, dhi + 1, &k, &b) != 0;
        refused += {func}(lo, -1, &k, &b) != 0;
        {{
            /* a whole delay between the rows, when there is one */
            int g = stabound_d[0] + 1, m, row = 0;
            for (m = 0; m < STABOUND_N_D; m++)
                row |= g == stabound_d[m];
            refused += (row || g > dhi) ? 1 : {func}(lo, g, &k, &b) != 0;
        }}
#endif
    }}
    printf("refused %d\nqueries %d\n", refused, n);
    return 0;
}}
"#
    )
}

/// Generates the header for `args`, compiles the program, runs it, and checks every wall.
/// `scale` is `(mass, period)` for a physical table. Returns the number of walls checked, or
/// `None` when no C compiler is found (a message says the check was skipped).
fn check_header(args: &[&str], precision: &str, scale: Option<(f64, f64)>) -> Option<usize> {
    check_loop_header(args, precision, scale, None)
}

/// [`check_header`] for a table with loop elements (`named`, the same as the element flags
/// in `args`, on the device `scale`): each wall is checked with the loop of the query's own
/// device, built from physical units (damping `b`, delay `d` samples) here.
fn check_loop_header(
    args: &[&str],
    precision: &str,
    scale: Option<(f64, f64)>,
    named: Option<&PhysicalElements>,
) -> Option<usize> {
    let Some(cc) = cc() else {
        eprintln!("SKIPPED C lookup check: no C compiler (cc, gcc, clang) found on PATH");
        return None;
    };
    let header = String::from_utf8(stdout(
        &[
            &["table"][..],
            args,
            &["--conservative", "--format", "c", "--precision", precision],
        ]
        .concat(),
    ))
    .unwrap();
    let ty = if precision == "float" {
        "float"
    } else {
        "double"
    };
    let (func, xs) = match scale {
        Some(_) => ("stabound_lookup_physical", "stabound_damping"),
        None => ("stabound_lookup", "stabound_delta"),
    };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("amax_table.h"), &header).unwrap();
    std::fs::write(dir.path().join("main.c"), program(ty, func, xs)).unwrap();
    let exe = dir.path().join("main");
    let out = std::process::Command::new(cc)
        .args([
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Wfloat-equal",
            "-Werror",
            "-O2",
            "-o",
        ])
        .arg(&exe)
        .arg(dir.path().join("main.c"))
        .arg("-lm")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = std::process::Command::new(&exe).output().unwrap();
    assert!(run.status.success());
    let text = String::from_utf8(run.stdout).unwrap();
    let mut walls = 0;
    let mut queries = None;
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f[0] {
            "refused" => assert_eq!(f[1], "6", "every out-of-range query is refused"),
            "queries" => queries = Some(f[1].parse::<usize>().unwrap()),
            _ => {
                let v: Vec<f64> = f.iter().map(|s| s.parse().unwrap()).collect();
                let (x, d, k, b) = (v[0], v[1], v[2], v[3]);
                // Back to normalized units: one rounding each, far below what the
                // construction's guard allowed for.
                let (delta, alpha, beta) = match scale {
                    Some((m, t)) => (x * t / m, k * t * t / m, b * t / m),
                    None => (x, k, b),
                };
                let wall = Wall::new(alpha, beta).unwrap();
                let verdict = match (named, scale) {
                    (Some(named), Some((m, t))) => {
                        let device = Device::new(m, t, x, Delay::Samples(d)).unwrap();
                        let lp = Loop::new(device.plant().unwrap())
                            .with_physical(&device, named)
                            .unwrap();
                        let checker = Checker::new(lp, Default::default()).unwrap();
                        checker.verdict(&wall).unwrap()
                    }
                    _ => Checker::new(Plant::new(delta, d).unwrap(), Default::default())
                        .unwrap()
                        .verdict(&wall)
                        .unwrap(),
                };
                assert_eq!(
                    verdict,
                    Verdict::Stable,
                    "{args:?} {precision}: the lookup at x = {x}, d = {d} gave the wall ({k}, {b})"
                );
                walls += 1;
            }
        }
    }
    assert_eq!(queries, Some(walls));
    Some(walls)
}

#[test]
fn one_delay_normalized_double_and_float() {
    for p in ["double", "float"] {
        if let Some(n) = check_header(&["--delta", "0:4:21", "--d", "1"], p, None) {
            // 20 intervals of 39 queries and the last node
            assert_eq!(n, 20 * 39 + 1);
        }
    }
}

#[test]
fn several_delays_physical_double_and_float() {
    let dev = [
        "--mass",
        "0.25",
        "--period",
        "0.0005",
        "--damping",
        "0:20:11",
        "--delay-samples",
        "1,2,4",
    ];
    for p in ["double", "float"] {
        if let Some(n) = check_header(&dev, p, Some((0.25, 0.0005))) {
            assert_eq!(n, 3 * (10 * 39 + 1));
        }
    }
}

#[test]
fn fractional_delays_bilinear_double_and_float() {
    for p in ["double", "float"] {
        if let Some(n) = check_header(&["--delta", "0:2:5", "--d", "0.5,1,1.5"], p, None) {
            // two d intervals of 7 + 2 rows each, and the last row
            assert_eq!(n, (2 * 9 + 1) * (4 * 39 + 1));
        }
    }
    let dev = [
        "--mass",
        "0.25",
        "--period",
        "0.0005",
        "--damping",
        "0:10:5",
        "--delay",
        "0.0005,0.00075",
    ];
    if let Some(n) = check_header(&dev, "float", Some((0.25, 0.0005))) {
        assert_eq!(n, 10 * (4 * 39 + 1));
    }
}

/// A conservative table of a loop with elements keeps its promise for that loop: a hand
/// (whole delays, double and float) and a low-pass filter (fractional delays, bilinear).
#[test]
fn loop_elements_checked_with_the_loops_own_test() {
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.1);
    hand.hand_damping = Some(2.0);
    let dev = [
        "--mass",
        "0.25",
        "--period",
        "0.0005",
        "--damping",
        "0:10:6",
        "--delay-samples",
        "1,2",
        "--hand-mass",
        "0.1",
        "--hand-damping",
        "2",
        // the held device alone (the free device would join the set)
        "--always-gripped",
    ];
    for p in ["double", "float"] {
        if let Some(n) = check_loop_header(&dev, p, Some((0.25, 0.0005)), Some(&hand)) {
            assert_eq!(n, 2 * (5 * 39 + 1));
        }
    }
    let mut filter = PhysicalElements::default();
    filter.velocity_filter_cutoff = Some(100.0);
    let dev = [
        "--mass",
        "0.25",
        "--period",
        "0.0005",
        "--damping",
        "0:10:4",
        "--delay",
        "0.0005,0.00075",
        "--velocity-filter-cutoff",
        "100",
    ];
    if let Some(n) = check_loop_header(&dev, "double", Some((0.25, 0.0005)), Some(&filter)) {
        assert_eq!(n, 10 * (3 * 39 + 1));
    }
}
