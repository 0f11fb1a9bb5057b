//! The scene report as text: physical units first, normalized values in parentheses.

use super::SceneReport;

/// `x` with 6 significant digits, trailing zeros dropped; `e` notation outside `[1e-4, 1e9)`.
pub(crate) fn sig6(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    let a = x.abs();
    // Values below 5e-13 in magnitude are zeros left by rounding in sums of order 1.
    if a < 5e-13 {
        return "0".into();
    }
    if !(1e-4..1e9).contains(&a) {
        let s = format!("{x:.5e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = trim_zeros(m);
        return format!("{m}e{e}");
    }
    let digits = a.log10().floor() as i32;
    if digits > 5 {
        // Integers of 7 to 9 digits: round away the digits past the sixth.
        let unit = 10f64.powi(digits - 5);
        return format!("{:.0}", (x / unit).round() * unit);
    }
    let decimals = (5 - digits) as usize;
    trim_zeros(&format!("{x:.decimals$}")).to_string()
}

/// A physical value with its unit; one too large for `f64` (a device whose mass and period
/// scale a finite normalized value past `1.8e308`) says so instead of printing `inf`.
fn physical(x: f64, unit: &str) -> String {
    if x.is_finite() {
        format!("{} {unit}", sig6(x))
    } else {
        format!("beyond the range of f64 in {unit}")
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

impl SceneReport {
    /// A plain-text report: one block per device, one per wall, physical units first and
    /// normalized values in parentheses, 6 significant digits.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let walls: usize = self
            .devices
            .iter()
            .map(|d| d.walls.len() + d.set.as_ref().map_or(0, |s| s.walls.len()))
            .sum();
        let _ = writeln!(
            s,
            "scene: {} device(s), {} wall(s); verdicts by the auto method (Schur-Cohn, another method where its rounding guard cannot vouch) with marginal band +-{:e}",
            self.devices.len(),
            walls,
            self.margin
        );
        for d in &self.devices {
            let _ = writeln!(
                s,
                "\ndevice {}: m = {} kg, T = {} s, b = {} N s/m, delay {} samples = {} s",
                crate::export::text::quoted(&d.name),
                sig6(d.mass),
                sig6(d.period),
                sig6(d.damping),
                sig6(d.d),
                sig6(d.delay)
            );
            let _ = writeln!(
                s,
                "  normalized: delta = {}, d = {}",
                sig6(d.delta),
                sig6(d.d)
            );
            if !d.elements.is_empty() {
                let _ = writeln!(s, "  elements modelled: {}", d.elements.join(", "));
            }
            if let Some(hand) = d.hand {
                let _ = writeln!(s, "  hand: {hand}");
            }
            if let Some(set) = &d.set {
                set_text(&mut s, set);
            }
            if let Some(m) = &d.max_stiffness {
                let _ = writeln!(
                    s,
                    "  K_max = {} at B* = {} (alpha_max = {}, beta* = {})",
                    physical(m.stiffness, "N/m"),
                    physical(m.damping, "N s/m"),
                    sig6(m.alpha),
                    sig6(m.beta)
                );
                if d.nonnegative_wall_damping {
                    let _ = writeln!(
                        s,
                        "  nonnegative wall damping required: K_max and B* are over B >= 0"
                    );
                }
                if let Some(n) = &m.nonnegative {
                    let _ = writeln!(
                        s,
                        "  K_max needs negative virtual damping; with B >= 0 the largest is {} at B = {} (alpha = {}, beta = {})",
                        physical(n.stiffness, "N/m"),
                        physical(n.damping, "N s/m"),
                        sig6(n.alpha),
                        sig6(n.beta)
                    );
                }
            }
            for w in &d.walls {
                let _ = writeln!(
                    s,
                    "\n  wall {}: {}",
                    crate::export::text::quoted(&w.name),
                    w.verdict.name()
                );
                let _ = writeln!(
                    s,
                    "    K = {} N/m, B = {} N s/m (alpha = {}, beta = {})",
                    sig6(w.stiffness),
                    sig6(w.damping),
                    sig6(w.alpha),
                    sig6(w.beta)
                );
                let _ = writeln!(s, "    spectral radius {:.9}", w.spectral_radius);
                let _ = writeln!(
                    s,
                    "    passive: {}",
                    match w.passive {
                        Some(true) => "yes",
                        Some(false) => "no",
                        None => "not defined for a fractional delay",
                    }
                );
                match (w.stiffness_limit, w.alpha_limit, w.stiffness_margin) {
                    (Some(k), Some(a), Some(m)) => {
                        let pieces = if w.stable_stiffness_pieces > 1 {
                            format!(
                                " [stable stiffnesses at this B form {} intervals]",
                                w.stable_stiffness_pieces
                            )
                        } else {
                            String::new()
                        };
                        let _ = writeln!(
                            s,
                            "    K_lim(B) = {} N/m (alpha {}); stiffness margin K/K_lim = {}{}",
                            sig6(k),
                            sig6(a),
                            sig6(m),
                            pieces
                        );
                    }
                    _ => {
                        let _ = writeln!(s, "    K_lim(B): no stiffness is stable at this B");
                    }
                }
                if w.damping_intervals.is_empty() {
                    let _ = writeln!(s, "    stable B for this K: none");
                } else {
                    let phys: Vec<String> = w
                        .damping_intervals
                        .iter()
                        .map(|r| format!("{} < B < {}", sig6(r.lo), sig6(r.hi)))
                        .collect();
                    let norm: Vec<String> = w
                        .damping_intervals
                        .iter()
                        .map(|r| {
                            format!(
                                "{} < beta < {}",
                                sig6(r.lo_normalized),
                                sig6(r.hi_normalized)
                            )
                        })
                        .collect();
                    let _ = writeln!(
                        s,
                        "    stable B for this K: {} N s/m ({})",
                        phys.join(" or "),
                        norm.join(" or ")
                    );
                }
                if let Some(b) = &w.buzz {
                    let _ = writeln!(
                        s,
                        "    buzz: {}",
                        crate::export::report::buzz_verdict(&crate::buzz::BuzzReport {
                            runs: b.runs.clone()
                        })
                    );
                }
                if let Some(g) = &w.suggested {
                    let _ = writeln!(
                        s,
                        "    suggested B* = {} (beta* = {}): K/K_max = {}{}",
                        physical(g.damping, "N s/m"),
                        sig6(g.beta),
                        sig6(g.stiffness_margin),
                        if g.stiffness_margin >= 1.0 {
                            " (no damping makes this K stable: lower K)"
                        } else {
                            ""
                        }
                    );
                }
            }
        }
        s
    }
}

/// A set of devices' answers: the set, the robust optimum, each wall for every member.
fn set_text(s: &mut String, set: &super::SetReport) {
    use std::fmt::Write;
    let _ = writeln!(
        s,
        "  set of devices: {} (the values above are its reference member: every interval at its low end, every list at its smallest value)",
        set.spread.join("; ")
    );
    let o = &set.optimum;
    let _ = writeln!(
        s,
        "  robust K_max = {} at B* = {} (alpha_max = {}, beta* = {}); shown for every member: K = {} (alpha = {})",
        physical(o.stiffness, "N/m"),
        physical(o.damping, "N s/m"),
        sig6(o.alpha_max),
        sig6(o.beta_at_max),
        physical(o.stiffness_verified, "N/m"),
        sig6(o.alpha_verified)
    );
    let _ = writeln!(s, "  shown by: {}", o.verification);
    let _ = writeln!(s, "  binding: {}", o.binding.join(" | "));
    for w in &set.walls {
        let whole = if w.for_every_member {
            "stable for every member of the set".to_string()
        } else if w.failing_member.is_some() {
            format!("{} for a member of the set", w.verdict.name())
        } else {
            "undecided for the set".to_string()
        };
        let _ = writeln!(
            s,
            "\n  wall {}: {whole}",
            crate::export::text::quoted(&w.name)
        );
        let _ = writeln!(
            s,
            "    K = {} N/m, B = {} N s/m (alpha = {}, beta = {})",
            sig6(w.stiffness),
            sig6(w.damping),
            sig6(w.alpha),
            sig6(w.beta)
        );
        let _ = writeln!(s, "    shown by: {}", w.verification);
        if let Some(m) = &w.failing_member {
            let _ = writeln!(s, "    failing member: {m} ({})", w.verdict.name());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_digits() {
        assert_eq!(sig6(14450.0), "14450");
        assert_eq!(sig6(0.1445), "0.1445");
        assert_eq!(sig6(1.0 / 3.0), "0.333333");
        assert_eq!(sig6(-42.5), "-42.5");
        assert_eq!(sig6(0.0), "0");
        assert_eq!(sig6(1e-17), "0");
        assert_eq!(sig6(2.5e-6), "2.5e-6");
        assert_eq!(sig6(123456789.0), "123457000");
        assert_eq!(sig6(f64::INFINITY), "inf");
    }
}
