//! The largest buzz-free stiffness: bisection on the stiffness with the buzz protocol as the
//! oracle (the model document, docs/MODEL.md, section 10.3).
//!
//! At a damping `beta` the linear loop is stable for stiffnesses up to its limit
//! `alpha_lin(beta)` ([`crate::search::alpha_limit`]). Below it a quantizer can still hold a
//! buzz; a wall is *buzz-free* when every start of the protocol ([`super::buzz`]) comes to
//! rest. The search brackets the switch between `alpha_lin (1 - tol)` (accepted at once
//! when buzz-free) and `tol alpha_lin` and bisects on `log alpha` until the bracket's ratio
//! is below `1 + tol`; the answer is the bracket's buzz-free end. Bisection assumes one
//! switch from buzz-free to buzzing as the stiffness grows; where the buzz-free set is not
//! an interval it returns one switch, not necessarily the largest.
//!
//! Over the damping, the search runs on a grid of dampings around the linear `alpha_max`'s
//! `beta*` ([`DAMPING_GRID`] times `beta*`) and keeps the largest; each damping's search is
//! independent, so they run in parallel and the answer does not depend on the threads.

use rayon::prelude::*;

use super::{BuzzOptions, Nonlinear, buzz};
use crate::amax::{AmaxOptions, alpha_max};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::search::alpha_limit;
use crate::stability::{Checker, Options};

/// The dampings of the search over damping, as multiples of the linear `beta*`.
pub const DAMPING_GRID: [f64; 8] = [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0];

/// Settings of the buzz-free search.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct BuzzFreeOptions {
    /// The protocol that judges each wall.
    pub protocol: BuzzOptions,
    /// Relative accuracy of the stiffness (the bracket's ratio at the end is below `1 + tol`).
    pub tol: f64,
}

impl Default for BuzzFreeOptions {
    /// The default protocol; `tol = 1e-3` (a thousandth of the stiffness: below the spread
    /// of any device's parameters, about 13 protocol runs per damping).
    fn default() -> Self {
        Self {
            protocol: BuzzOptions::default(),
            tol: 1e-3,
        }
    }
}

/// A buzz-free stiffness at one damping, normalized.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct BuzzFree {
    /// The damping `beta`.
    pub beta: f64,
    /// The largest buzz-free stiffness found (`None`: even `tol` times the linear limit
    /// buzzes).
    pub alpha: Option<f64>,
    /// The linear loop's stiffness limit at this damping.
    pub linear_alpha: f64,
}

/// The largest buzz-free stiffness of `lp` (built on a device, [`Loop::physical`]) with the
/// quantizers and friction `nonlinear` at damping `beta`; `None` when no stiffness is
/// linearly stable there. `tick` is called after each wall judged (for progress).
///
/// Method: the module doc (bisection on `log alpha`, the protocol as the oracle).
///
/// ```
/// use stabound::buzz::{BuzzFreeOptions, Nonlinear, buzz_free_alpha};
/// use stabound::elements::{Loop, PhysicalElements};
/// use stabound::params::{Delay, Device};
///
/// let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0))?;
/// let lp = Loop::physical(&device, &PhysicalElements::default())?;
/// let mut n = Nonlinear::default();
/// n.encoder_resolution = Some(1e-5);
/// let mut opts = BuzzFreeOptions::default();
/// opts.tol = 1e-2;
/// let r = buzz_free_alpha(lp, &n, 0.3, &opts, &|| ())?.unwrap();
/// assert!(r.alpha.unwrap() <= r.linear_alpha);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a loop without a device or nothing named; a `tol` outside
/// `(0, 0.5)`; as [`buzz`].
pub fn buzz_free_alpha(
    lp: impl Into<Loop>,
    nonlinear: &Nonlinear,
    beta: f64,
    options: &BuzzFreeOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<Option<BuzzFree>> {
    let lp = lp.into();
    check(&lp, nonlinear, options)?;
    let checker = Checker::new(lp, Options::default())?;
    let Some(linear) = alpha_limit(&checker, beta)? else {
        return Ok(None);
    };
    let alpha = search(&lp, nonlinear, beta, linear, options, tick)?;
    Ok(Some(BuzzFree {
        beta,
        alpha,
        linear_alpha: linear,
    }))
}

/// The largest buzz-free stiffness over the damping, and at the linear `alpha_max`'s
/// damping `beta*`: `(best over the grid, at beta*)`, with the linear `alpha_max` and
/// `beta*`. `tick` is called after each wall judged.
///
/// Method: the module doc ([`DAMPING_GRID`] times `beta*`, the largest kept; ties go to the
/// smaller damping).
///
/// # Errors
///
/// As [`buzz_free_alpha`] and [`alpha_max`].
pub fn buzz_free_alpha_max(
    lp: impl Into<Loop>,
    nonlinear: &Nonlinear,
    options: &BuzzFreeOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<BuzzFreeMax> {
    let lp = lp.into();
    check(&lp, nonlinear, options)?;
    let linear = alpha_max(lp, &AmaxOptions::default())?;
    let betas: Vec<f64> = DAMPING_GRID
        .iter()
        .map(|f| f * linear.beta_at_max)
        .collect();
    let found = betas
        .par_iter()
        .map(|&b| buzz_free_alpha(lp, nonlinear, b, options, tick))
        .collect::<Result<Vec<_>>>()?;
    let at_beta_star = found[DAMPING_GRID.iter().position(|f| *f == 1.0).unwrap_or(0)];
    let best =
        found
            .iter()
            .flatten()
            .filter(|r| r.alpha.is_some())
            .fold(None::<BuzzFree>, |best, r| match best {
                Some(b) if b.alpha >= r.alpha => Some(b),
                _ => Some(*r),
            });
    Ok(BuzzFreeMax {
        alpha_max: linear.alpha_max,
        beta_at_max: linear.beta_at_max,
        best,
        at_beta_star,
    })
}

/// The buzz-free stiffness over the damping beside the linear `alpha_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct BuzzFreeMax {
    /// The linear loop's `alpha_max`.
    pub alpha_max: f64,
    /// Its damping `beta*`.
    pub beta_at_max: f64,
    /// The largest buzz-free stiffness over the damping grid (`None`: none found).
    pub best: Option<BuzzFree>,
    /// The buzz-free stiffness at `beta*`.
    pub at_beta_star: Option<BuzzFree>,
}

fn check(lp: &Loop, nonlinear: &Nonlinear, options: &BuzzFreeOptions) -> Result<()> {
    nonlinear.validate()?;
    options.protocol.validate()?;
    if lp.device().is_none() {
        return Err(Error::InvalidRequest(
            "the buzz-free stiffness needs the loop's device in physical units (build the loop with Loop::physical)".into(),
        ));
    }
    if !nonlinear.any() {
        return Err(Error::InvalidRequest(
            "name an encoder resolution, a force resolution or a friction to search for the buzz-free stiffness".into(),
        ));
    }
    if !(options.tol > 0.0 && options.tol < 0.5) {
        return Err(Error::InvalidParameter {
            name: "buzz-free tolerance",
            value: options.tol,
            expected: "a relative accuracy in (0, 0.5), e.g. 1e-3".into(),
        });
    }
    Ok(())
}

/// Bisection on `log alpha` between `tol linear` and `(1 - tol) linear` (module doc).
fn search(
    lp: &Loop,
    nonlinear: &Nonlinear,
    beta: f64,
    linear: f64,
    options: &BuzzFreeOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<Option<f64>> {
    let Some(device) = lp.device() else {
        return Ok(None);
    };
    let quiet = |alpha: f64| -> Result<bool> {
        let wall = Wall::new(alpha, beta)?;
        let q = nonlinear.normalize(device, device.stiffness(alpha))?;
        let r = buzz(*lp, &wall, &q, &options.protocol)?;
        tick();
        Ok(!r.sustained())
    };
    let tol = options.tol;
    let hi = linear * (1.0 - tol);
    if quiet(hi)? {
        return Ok(Some(hi));
    }
    let mut lo = linear * tol;
    if !quiet(lo)? {
        return Ok(None);
    }
    let mut hi = hi;
    while hi / lo > 1.0 + tol {
        let mid = (lo * hi).sqrt();
        if quiet(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some(lo))
}
