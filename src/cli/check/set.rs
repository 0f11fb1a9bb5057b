//! `stabound check` on a set of devices: the wall is judged for every member (the model
//! document, docs/MODEL.md, section 12), and the report names the set, the verdict for the
//! whole set, how it was shown, and a member the wall fails on.

use stabound::robust::{DeviceSet, RobustCheck, robust_check};
use stabound::stability::Verdict;

use super::Format;

/// The report of one wall `(k, b)` in N/m and N s/m on `set`, and the verdict for the set
/// (the failing member's, or marginal when the sampling left it undecided).
pub(super) fn report(
    set: &DeviceSet,
    k: f64,
    b: f64,
    format: Format,
) -> anyhow::Result<(String, Verdict)> {
    let wall = set.reference().device().wall(k, b)?;
    let found = robust_check(set, &wall)?;
    let described = set.describe().join("; ");
    let (verdict, shown) = (found.verdict(), found.describe());
    let member = found.failing().map(|m| set.describe_member(m));
    let whole = match (&found, verdict) {
        (RobustCheck::Stable(_), _) => "stable for every member of the set".to_string(),
        (RobustCheck::Fails(..), v) => format!("{} for a member of the set", v.name()),
        _ => "undecided for the set".to_string(),
    };
    let text = match format {
        Format::Text => {
            let mut t = format!(
                "wall: K = {k} N/m, B = {b} N s/m\nset of devices: {described}\nverdict: {whole}\nshown by: {shown}\n"
            );
            if let Some(m) = &member {
                t.push_str(&format!("failing member: {m} ({})\n", verdict.name()));
            }
            t
        }
        Format::Json => {
            let mut v = serde_json::json!({
                "stiffness_N_per_m": k,
                "wall_damping_Ns_per_m": b,
                "set": set.describe(),
                "verdict": verdict.name(),
                "for_every_member": matches!(found, RobustCheck::Stable(_)),
                "verification": shown,
            });
            if let Some(m) = member {
                v["failing_member"] = serde_json::Value::String(m);
            }
            format!("{v:#}\n")
        }
    };
    Ok((text, verdict))
}
