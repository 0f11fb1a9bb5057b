//! `stabound check --certify` over a finite set of devices (one-of lists of loop-element
//! values): the certified verdict of the wall, or of every wall of a box, for every member
//! (the model document, docs/MODEL.md, section 11), the report and the certificate.

use stabound::certificate::{SetClaim, WallBox, certify_set, certify_set_box};
use stabound::params::Wall;
use stabound::robust::DeviceSet;
use stabound::stability::Verdict;

use super::{Args, Format, verdict_status};

/// The report, the certificate and the exit status `--exit-status` asks for (0 stable, 3
/// unstable, 4 marginal or not proved) of the wall `(k, b)` in N/m and N s/m on `set`, or of
/// every wall of the box with the corners `corners` in `(alpha, beta)`.
pub(super) fn run(
    a: &Args,
    set: &DeviceSet,
    (k, b): (f64, f64),
    corners: Option<((f64, f64), (f64, f64))>,
) -> anyhow::Result<(String, String, anyhow::Result<()>)> {
    let (cert, walls) = match corners {
        Some(((alo, blo), (ahi, bhi))) => {
            let walls = WallBox::new(Wall::new(alo, blo)?, Wall::new(ahi, bhi)?)?;
            (certify_set_box(set, &walls, a.certify_leaves)?, Some(walls))
        }
        None => {
            let wall = set.reference().device().wall(k, b)?;
            (certify_set(set, &wall, a.margin)?, None)
        }
    };
    let every = if walls.is_some() {
        " at every wall of the box"
    } else {
        ""
    };
    let (verdict, whole, member) = match cert.claim() {
        SetClaim::Stable => (Verdict::Stable, "stable for every member of the set", None),
        SetClaim::Unstable { member } => (
            Verdict::Unstable,
            "unstable for a member of the set",
            Some(member),
        ),
        SetClaim::Marginal { member } => (
            Verdict::Marginal,
            "marginal for a member of the set",
            Some(member),
        ),
        SetClaim::NotProved { member } => (
            Verdict::Marginal,
            "not proved for a member of the set",
            Some(member),
        ),
        _ => (Verdict::Marginal, "not proved for the set", None),
    };
    let failing = member.and_then(|m| cert.member(m));
    let described = set.describe().join("; ");
    let n = cert.members();
    let report = match a.format {
        Format::Text => {
            let head = match walls {
                Some(w) => {
                    let ((alo, ahi), (blo, bhi)) = (w.alpha(), w.beta());
                    format!("box: alpha in [{alo}, {ahi}], beta in [{blo}, {bhi}]")
                }
                None => format!("wall: K = {k} N/m, B = {b} N s/m"),
            };
            let mut t = format!(
                "{head}\nset of devices: {described}\nverdict: {whole}{every}\ncertified by: one certificate per member ({n} members)\n"
            );
            if let Some(m) = failing {
                t.push_str(&format!("deciding member: {m}\n"));
            }
            t
        }
        Format::Json => {
            let mut v = serde_json::json!({
                "set": set.describe(),
                "verdict": format!("{whole}{every}"),
                "members": n,
            });
            match walls {
                Some(w) => {
                    v["alpha"] = serde_json::json!([w.alpha().0, w.alpha().1]);
                    v["beta"] = serde_json::json!([w.beta().0, w.beta().1]);
                }
                None => {
                    v["stiffness_N_per_m"] = k.into();
                    v["wall_damping_Ns_per_m"] = b.into();
                }
            }
            if let Some(m) = failing {
                v["deciding_member"] = m.into();
            }
            format!("{v:#}\n")
        }
    };
    let status = if a.exit_status {
        verdict_status([verdict])
    } else {
        Ok(())
    };
    Ok((report, cert.to_json(), status))
}
