//! The `alpha_max` lookup table as CSV and JSON (`stabound table --format csv|json`).

use serde_json::json;

use crate::amax::AmaxTable;

/// A device in physical units for tables with physical columns: `None` for normalized only.
pub type TableUnits = Option<DeviceScale>;

/// Mass and period, enough to turn normalized `alpha`, `beta`, `delta` into N/m and N s/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceScale {
    /// Moving mass in kg.
    pub mass: f64,
    /// Sampling period in s.
    pub period: f64,
}

impl DeviceScale {
    /// `K = alpha m / T^2` (N/m) for every value.
    pub fn stiffness(&self, alpha: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let k = self.mass / (self.period * self.period);
        alpha
            .iter()
            .map(|r| r.iter().map(|a| a * k).collect())
            .collect()
    }

    /// `B = beta m / T` (N s/m) for every value.
    pub fn wall_damping(&self, beta: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let k = self.mass / self.period;
        beta.iter()
            .map(|r| r.iter().map(|b| b * k).collect())
            .collect()
    }
}

/// Long-format CSV, one row per grid node, `d` outer and `delta` inner: columns
/// `d,delta,alpha_max,beta_at_max` (and `damping,K_max,B` with units). Values are printed
/// in shortest round-trip form, equal to the C and Rust exports bit for bit.
pub fn to_csv(t: &AmaxTable, units: &TableUnits) -> String {
    let lit = super::c::lit;
    let mut o = String::from("d,delta,alpha_max,beta_at_max");
    if units.is_some() {
        o.push_str(",damping,K_max,B");
    }
    o.push('\n');
    for (i, &d) in t.d.iter().enumerate() {
        for (j, &x) in t.delta.iter().enumerate() {
            let (a, b) = (t.alpha_max[i][j], t.beta_at_max[i][j]);
            o.push_str(&format!("{},{},{},{}", lit(d), lit(x), lit(a), lit(b)));
            if let Some(u) = units {
                o.push_str(&format!(
                    ",{},{},{}",
                    lit(x * u.mass / u.period),
                    lit(a * (u.mass / (u.period * u.period))),
                    lit(b * (u.mass / u.period))
                ));
            }
            o.push('\n');
        }
    }
    o
}

/// JSON object: axes, `alpha_max[d][delta]`, `beta_at_max[d][delta]`, the tolerance, beta
/// limits, whether conservative, and the physical arrays with units.
pub fn to_json(t: &AmaxTable, units: &TableUnits) -> String {
    let mut v = json!({
        "model": "Hulin et al. 2006, exact ZOH discretization; alpha = K T^2/m, beta = B T/m, delta = b T/m, d = delay/T",
        "tol": t.tol,
        "beta_min": t.options.beta_min,
        "beta_max": t.options.beta_max,
        "conservative": t.conservative,
        "delta": t.delta,
        "d": t.d,
        "alpha_max": t.alpha_max,
        "beta_at_max": t.beta_at_max,
    });
    if let Some(u) = units {
        v["mass_kg"] = json!(u.mass);
        v["period_s"] = json!(u.period);
        v["damping_Ns_per_m"] = json!(
            t.delta
                .iter()
                .map(|x| x * u.mass / u.period)
                .collect::<Vec<_>>()
        );
        v["K_max_N_per_m"] = json!(u.stiffness(&t.alpha_max));
        v["B_Ns_per_m"] = json!(u.wall_damping(&t.beta_at_max));
    }
    format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
}
