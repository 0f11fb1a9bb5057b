//! Checking a scene's walls: point tests and exact one-dimensional searches.

use rayon::prelude::*;

use super::{
    DeviceReport, MaxStiffness, Range, Scene, SceneReport, SceneWall, Suggestion, WallReport,
};
use crate::error::Result;
use crate::filter::VelocityFilter;
use crate::params::{Device, Plant, Wall};
use crate::passivity::delay::Criterion;
use crate::search::{Interval, stable_alphas, stable_betas};
use crate::stability::{Checker, Options};

impl Scene {
    /// Checks every wall (module doc): walls in parallel, results in file order whatever the
    /// number of threads.
    ///
    /// `limit` gives each device's maximum stable stiffness and the damping where it is
    /// reached, `(alpha_max, beta_at_max)` in normalized form, or `None` to leave the
    /// suggested damping out. The scene does not compute it itself: pass the crate's
    /// `alpha_max` ([`Scene::check`] does) or any other source.
    pub fn check_with<F>(&self, options: &Options, limit: F) -> Result<SceneReport>
    where
        F: Fn(&Plant) -> Result<Option<(f64, f64)>> + Sync,
    {
        options.validate()?;
        let mut checkers = Vec::with_capacity(self.devices.len());
        for d in &self.devices {
            let plant = d.device.plant()?;
            let checker = Checker::new(&plant, *options)?;
            let lim = limit(&plant)?;
            checkers.push((plant, checker, lim));
        }
        let jobs: Vec<(usize, &SceneWall)> = self
            .devices
            .iter()
            .enumerate()
            .flat_map(|(i, d)| d.walls.iter().map(move |w| (i, w)))
            .collect();
        let walls: Vec<WallReport> = jobs
            .par_iter()
            .map(|&(i, w)| {
                let (_, checker, lim) = &checkers[i];
                check_wall(&self.devices[i].device, checker, *lim, w)
            })
            .collect::<Result<_>>()?;
        let mut walls = walls.into_iter();
        let devices = self
            .devices
            .iter()
            .zip(&checkers)
            .map(|(d, (plant, _, lim))| DeviceReport {
                name: d.name.clone(),
                mass: d.device.mass,
                period: d.device.period,
                damping: d.device.damping,
                delay: plant.d() * d.device.period,
                delta: plant.delta(),
                d: plant.d(),
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

fn check_wall(
    device: &Device,
    checker: &Checker,
    limit: Option<(f64, f64)>,
    w: &SceneWall,
) -> Result<WallReport> {
    let wall: Wall = device.wall(w.stiffness, w.damping)?;
    let verdict = checker.verdict(&wall)?;
    let spectral_radius = checker.spectral_radius_schur_cohn(&wall);
    let plant = checker.poly().plant();
    // Colgate-Schenkel with the device's delay (docs/MODEL.md section 9); a fractional delay
    // is outside the criterion, so there is no answer rather than a guess
    let passive = match Criterion::new(plant.d(), VelocityFilter::none()) {
        Ok(crit) => Some(crit.is_passive(plant.delta(), &wall)?),
        Err(_) => None,
    };
    let alphas = stable_alphas(checker, wall.beta)?;
    let alpha_limit = alphas.last().map(|i| i.hi);
    let betas = stable_betas(checker, wall.alpha)?;
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
    /// from [`crate::amax::alpha_max`] (one direct search per device).
    pub fn check(&self, options: &Options) -> Result<SceneReport> {
        self.check_with(options, |plant| {
            let a = crate::amax::alpha_max(plant, &crate::amax::AmaxOptions::default())?;
            Ok(Some((a.alpha_max, a.beta_at_max)))
        })
    }
}
