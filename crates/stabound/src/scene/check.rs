//! Checking a scene's walls: point tests and exact one-dimensional searches.

use rayon::prelude::*;

use super::{
    DeviceReport, MaxStiffness, Optimum, Range, RobustOptimum, Scene, SceneDevice, SceneReport,
    SceneWall, SetReport, SetWallReport, Suggestion, WallReport,
};
use crate::amax::AmaxOptions;
use crate::elements::{Loop, PhysicalElements};
use crate::error::Result;
use crate::params::Wall;
use crate::passivity::Criterion;
use crate::robust::{DeviceSet, RobustCheck, hand_let_go, robust_alpha_max, robust_check};
use crate::search::{Interval, stable_alphas, stable_betas};
use crate::stability::{Checker, Options};

impl Scene {
    /// Checks every wall (module doc): walls in parallel, results in file order whatever the
    /// number of threads.
    ///
    /// `limit` gives each device's maximum stable stiffness within the beta limits of its
    /// options and the damping where it is reached, `(alpha_max, beta_at_max)` in normalized
    /// form, or `None` to leave the suggested damping out. The scene does not compute it
    /// itself: pass the crate's `alpha_max` ([`Scene::check`] does) or any other source. It
    /// is asked over `beta >= 0` for a device that requires nonnegative wall damping, and
    /// again over `beta >= 0` where the unrestricted optimum has `beta < 0` (the report gives
    /// both). Each device's loop has the elements it names, and only those.
    pub fn check_with<F>(&self, options: &Options, limit: F) -> Result<SceneReport>
    where
        F: Fn(&Loop, &AmaxOptions) -> Result<Option<(f64, f64)>> + Sync,
    {
        options.validate()?;
        let nonnegative = AmaxOptions::default().with_beta_limits(Some(0.0), None)?;
        // each device as the file gives it and, when it names a hand that may let go, the
        // same device with the hand let go (docs/MODEL.md section 12)
        let mut views: Vec<(String, &SceneDevice, PhysicalElements, Option<&'static str>)> =
            Vec::new();
        for d in self.devices.iter().filter(|d| d.set.is_none()) {
            match (hand_let_go(&d.elements), d.always_gripped) {
                (None, _) => views.push((d.name.clone(), d, d.elements, None)),
                (Some(_), true) => views.push((d.name.clone(), d, d.elements, Some(GRIPPED))),
                (Some(free), false) => {
                    views.push((d.name.clone(), d, d.elements, Some(HELD)));
                    views.push((format!("{} (hand let go)", d.name), d, free, Some(LET_GO)));
                }
            }
        }
        let mut checkers = Vec::with_capacity(views.len());
        for (_, d, elements, _) in &views {
            let lp = Loop::physical(&d.device, elements)?;
            let model = Checker::new(lp, *options)?;
            let lim = if d.nonnegative_wall_damping {
                limit(&lp, &nonnegative)?
            } else {
                limit(&lp, &AmaxOptions::default())?
            };
            let beside = match lim {
                Some((_, b)) if b < 0.0 => limit(&lp, &nonnegative)?,
                _ => None,
            };
            checkers.push((lp, model, lim, beside));
        }
        let jobs: Vec<(usize, &SceneWall)> = views
            .iter()
            .enumerate()
            .flat_map(|(i, v)| v.1.walls.iter().map(move |w| (i, w)))
            .collect();
        let walls: Vec<WallReport> = jobs
            .par_iter()
            .map(|&(i, w)| {
                let (lp, model, lim, _) = &checkers[i];
                check_wall(views[i].1, lp, model, *lim, w)
            })
            .collect::<Result<_>>()?;
        let mut walls = walls.into_iter();
        let mut singles = views
            .iter()
            .zip(&checkers)
            .map(|((name, d, elements, hand), (lp, _, lim, beside))| {
                (
                    *d,
                    DeviceReport {
                        name: name.clone(),
                        elements: elements.names(),
                        hand: *hand,
                        mass: d.device.mass,
                        period: d.device.period,
                        damping: d.device.damping,
                        delay: lp.plant().d() * d.device.period,
                        delta: lp.plant().delta(),
                        d: lp.plant().d(),
                        max_stiffness: lim.map(|(a, b)| MaxStiffness {
                            stiffness: d.device.stiffness(a),
                            damping: d.device.wall_damping(b),
                            alpha: a,
                            beta: b,
                            nonnegative: beside.map(|(a, b)| Optimum {
                                stiffness: d.device.stiffness(a),
                                damping: d.device.wall_damping(b),
                                alpha: a,
                                beta: b,
                            }),
                        }),
                        nonnegative_wall_damping: d.nonnegative_wall_damping,
                        walls: walls.by_ref().take(d.walls.len()).collect(),
                        set: None,
                    },
                )
            })
            .peekable();
        // file order: a set's report where its device is, a device's views (held, let go)
        // together
        let mut devices = Vec::with_capacity(views.len());
        for d in &self.devices {
            match &d.set {
                Some(set) => devices.push(check_set(d, set)?),
                None => {
                    while let Some((_, r)) = singles.next_if(|(of, _)| std::ptr::eq(*of, d)) {
                        devices.push(r);
                    }
                }
            }
        }
        Ok(SceneReport {
            margin: options.margin,
            devices,
        })
    }
}

/// What a device with a hand that may let go assumes, for the held device.
const HELD: &str = "on the handle; the same device with the hand let go is checked too";
/// The same, for the device with the hand let go.
const LET_GO: &str = "let go (the device of the same name without its hand)";
/// What a device with `always_gripped = true` assumes.
const GRIPPED: &str =
    "always on the handle (always_gripped = true: the free device is not checked)";

fn check_wall(
    scene_device: &SceneDevice,
    lp: &Loop,
    model: &Checker,
    limit: Option<(f64, f64)>,
    w: &SceneWall,
) -> Result<WallReport> {
    let device = &scene_device.device;
    let wall: Wall = device.wall(w.stiffness, w.damping)?;
    let verdict = model.verdict(&wall)?;
    let nonlinear = crate::buzz::Nonlinear::from(&scene_device.elements);
    let buzz = if nonlinear.any() {
        let q = nonlinear.normalize(device, w.stiffness)?;
        Some(crate::buzz::buzz(*lp, &wall, &q, &crate::buzz::BuzzOptions::default())?.into())
    } else {
        None
    };
    let spectral_radius = model.spectral_radius(&wall)?;
    let plant = lp.plant();
    // Colgate-Schenkel with the device's delay and the loop's velocity filter (docs/MODEL.md
    // section 9); a fractional delay is outside the criterion, so there is no answer rather
    // than a guess
    let passive = match Criterion::new(plant.d(), *lp.filter()) {
        Ok(crit) => Some(crit.is_passive(plant.delta(), &wall)?),
        Err(_) => None,
    };
    let alphas = stable_alphas(model, wall.beta)?;
    let alpha_limit = alphas.last().map(|i| i.hi);
    let betas = stable_betas(model, wall.alpha)?;
    let to_b = |i: &Interval| Range {
        lo: device.wall_damping(i.lo),
        hi: device.wall_damping(i.hi),
        lo_normalized: i.lo,
        hi_normalized: i.hi,
    };
    let suggested = limit.map(|(alpha_max, beta_at_max)| Suggestion {
        damping: device.wall_damping(beta_at_max),
        beta: beta_at_max,
        stiffness_margin: wall.alpha / alpha_max,
    });
    Ok(WallReport {
        name: w.name.clone(),
        stiffness: w.stiffness,
        damping: w.damping,
        alpha: wall.alpha,
        beta: wall.beta,
        verdict,
        spectral_radius,
        stiffness_limit: alpha_limit.map(|a| device.stiffness(a)),
        alpha_limit,
        stiffness_margin: alpha_limit.map(|a| wall.alpha / a),
        stable_stiffness_pieces: alphas.len(),
        damping_intervals: betas.iter().map(to_b).collect(),
        suggested,
        passive,
        buzz,
    })
}

impl Scene {
    /// Checks every wall, with each device's maximum stiffness and the suggested damping
    /// from [`crate::amax::alpha_max`] of each device's loop.
    pub fn check(&self, options: &Options) -> Result<SceneReport> {
        self.check_with(options, |lp, opts| {
            let a = crate::amax::alpha_max(lp, opts)?;
            Ok(Some((a.alpha_max, a.beta_at_max)))
        })
    }
}

/// The answers for a device the file spreads over intervals (docs/MODEL.md section 12):
/// each wall by [`robust_check`], the optimum by [`robust_alpha_max`] (over `beta >= 0` when
/// the device requires nonnegative wall damping), walls in parallel, results in file order.
/// Verdicts use the default marginal band, as the set's engines do.
fn check_set(d: &SceneDevice, set: &DeviceSet) -> Result<DeviceReport> {
    let reference = set.reference();
    let device = reference.device();
    let opts = if d.nonnegative_wall_damping {
        AmaxOptions::default().with_beta_limits(Some(0.0), None)?
    } else {
        AmaxOptions::default()
    };
    let r = robust_alpha_max(set, &opts)?;
    let optimum = RobustOptimum {
        stiffness: device.stiffness(r.alpha_max),
        damping: device.wall_damping(r.beta_at_max),
        alpha_max: r.alpha_max,
        beta_at_max: r.beta_at_max,
        stiffness_verified: device.stiffness(r.alpha_verified),
        alpha_verified: r.alpha_verified,
        verification: r.verification.describe(),
        verified: r.verification.holds(),
        binding: r.binding.iter().map(|m| set.describe_member(m)).collect(),
        members_examined: r.examined,
    };
    let walls = d
        .walls
        .par_iter()
        .map(|w| {
            let wall = device.wall(w.stiffness, w.damping)?;
            let found = robust_check(set, &wall)?;
            Ok(SetWallReport {
                name: w.name.clone(),
                stiffness: w.stiffness,
                damping: w.damping,
                alpha: wall.alpha,
                beta: wall.beta,
                verdict: found.verdict(),
                for_every_member: matches!(found, RobustCheck::Stable(_)),
                verification: found.describe(),
                failing_member: found.failing().map(|m| set.describe_member(m)),
            })
        })
        .collect::<Result<_>>()?;
    let lp = reference.to_loop()?;
    Ok(DeviceReport {
        name: d.name.clone(),
        elements: reference.elements().names(),
        hand: None,
        mass: device.mass,
        period: device.period,
        damping: device.damping,
        delay: lp.plant().d() * device.period,
        delta: lp.plant().delta(),
        d: lp.plant().d(),
        max_stiffness: None,
        nonnegative_wall_damping: d.nonnegative_wall_damping,
        walls: Vec::new(),
        set: Some(SetReport {
            spread: set.describe(),
            optimum,
            walls,
        }),
    })
}
