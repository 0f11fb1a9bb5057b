//! Checking a scene's walls: point tests and exact one-dimensional searches.

use rayon::prelude::*;

use super::SceneDevice;
use super::{
    DeviceReport, MaxStiffness, Range, Scene, SceneReport, SceneWall, Suggestion, WallReport,
};
use crate::elements::{Loop, PhysicalElements};
use crate::error::Result;
use crate::params::{Device, Wall};
use crate::passivity::Criterion;
use crate::robust::hand_let_go;
use crate::search::{Interval, stable_alphas, stable_betas};
use crate::stability::{Checker, Options};

impl Scene {
    /// Checks every wall (module doc): walls in parallel, results in file order whatever the
    /// number of threads.
    ///
    /// `limit` gives each device's maximum stable stiffness and the damping where it is
    /// reached, `(alpha_max, beta_at_max)` in normalized form, or `None` to leave the
    /// suggested damping out. The scene does not compute it itself: pass the crate's
    /// `alpha_max` ([`Scene::check`] does) or any other source. Each device's loop has the
    /// elements it names, and only those.
    pub fn check_with<F>(&self, options: &Options, limit: F) -> Result<SceneReport>
    where
        F: Fn(&Loop) -> Result<Option<(f64, f64)>> + Sync,
    {
        options.validate()?;
        // each device as the file gives it and, when it names a hand that may let go, the
        // same device with the hand let go (docs/MODEL.md section 12)
        let mut views: Vec<(String, &SceneDevice, PhysicalElements, Option<&'static str>)> =
            Vec::new();
        for d in &self.devices {
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
            let lim = limit(&lp)?;
            checkers.push((lp, model, lim));
        }
        let jobs: Vec<(usize, &SceneWall)> = views
            .iter()
            .enumerate()
            .flat_map(|(i, v)| v.1.walls.iter().map(move |w| (i, w)))
            .collect();
        let walls: Vec<WallReport> = jobs
            .par_iter()
            .map(|&(i, w)| {
                let (lp, model, lim) = &checkers[i];
                check_wall(&views[i].1.device, lp, model, *lim, w)
            })
            .collect::<Result<_>>()?;
        let mut walls = walls.into_iter();
        let devices = views
            .iter()
            .zip(&checkers)
            .map(|((name, d, elements, hand), (lp, _, lim))| DeviceReport {
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
                }),
                walls: walls.by_ref().take(d.walls.len()).collect(),
            })
            .collect();
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
    device: &Device,
    lp: &Loop,
    model: &Checker,
    limit: Option<(f64, f64)>,
    w: &SceneWall,
) -> Result<WallReport> {
    let wall: Wall = device.wall(w.stiffness, w.damping)?;
    let verdict = model.verdict(&wall)?;
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
    })
}

impl Scene {
    /// Checks every wall, with each device's maximum stiffness and the suggested damping
    /// from [`crate::amax::alpha_max`] of each device's loop.
    pub fn check(&self, options: &Options) -> Result<SceneReport> {
        self.check_with(options, |lp| {
            let opts = crate::amax::AmaxOptions::default();
            let a = crate::amax::alpha_max(lp, &opts)?;
            Ok(Some((a.alpha_max, a.beta_at_max)))
        })
    }
}
