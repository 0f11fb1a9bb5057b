//! The largest buzz-free stiffness: a scan of the stiffness, then bisection on its top edge,
//! with the buzz protocol as the oracle (the model document, docs/MODEL.md, section 10.3).
//!
//! At a damping `beta` the linear loop is stable for stiffnesses up to its limit
//! `alpha_lin(beta)` ([`crate::search::alpha_limit`]). Below it a quantizer can still hold a
//! buzz; a wall is *buzz-free* when every start of the protocol ([`super::buzz`]) comes to
//! rest. The buzz-free stiffness is the largest `alpha` such that every wall from the
//! softest up to `alpha` is buzz-free: a stiffness a user can turn the wall up to without
//! passing a buzzing one. The quiet stiffnesses need not form one interval (a stiffer wall
//! can be quiet again above a buzzing band), so the search does not assume it: it scans
//! [`BuzzFreeOptions::scan_points`] stiffnesses on a log grid from `tol alpha_lin` to `(1 - tol) alpha_lin`,
//! takes the run of quiet points that starts at the lowest, and bisects on `log alpha`
//! between that run's last point and the buzzing point after it until their ratio is below
//! `1 + tol`; the answer is the quiet end (`(1 - tol) alpha_lin` when the whole scan is
//! quiet, none when the lowest point buzzes). A quiet point of the scan above a buzzing one
//! is reported ([`BuzzFree::quiet_beyond`]): there the quiet set is not one interval. A band
//! narrower than the grid's ratio can fall between its points, as with any scan.
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
    /// Stiffnesses scanned before the bisection (a log grid over the linear range; at least
    /// 2, at most [`MAX_SCAN_POINTS`]): the finer, the narrower the buzzing band it sees.
    pub scan_points: usize,
}

impl Default for BuzzFreeOptions {
    /// The default protocol; `tol = 1e-3` (a thousandth of the stiffness: below the spread
    /// of any device's parameters); [`SCAN_POINTS`] stiffnesses scanned (with the bisection,
    /// about 25 protocol runs per damping).
    fn default() -> Self {
        Self {
            protocol: BuzzOptions::default(),
            tol: 1e-3,
            scan_points: SCAN_POINTS,
        }
    }
}

/// A buzz-free stiffness at one damping, normalized.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct BuzzFree {
    /// The damping `beta`.
    pub beta: f64,
    /// The largest buzz-free stiffness found: every stiffness of the scan below it is quiet
    /// too (`None`: even `tol` times the linear limit buzzes).
    pub alpha: Option<f64>,
    /// A quiet stiffness the scan found above a buzzing one, the largest (`None`: the quiet
    /// stiffnesses scanned form one interval from the lowest). When set, the quiet set is not
    /// one interval and a stiffer wall than `alpha` is quiet again, yet not the walls
    /// between.
    pub quiet_beyond: Option<f64>,
    /// The linear loop's stiffness limit at this damping.
    pub linear_alpha: f64,
}

/// The largest buzz-free stiffness of `lp` (built on a device, [`Loop::physical`]) with the
/// quantizers and friction `nonlinear` at damping `beta`; `None` when no stiffness is
/// linearly stable there. `tick` is called after each wall judged (for progress).
///
/// Method: the module doc (a log scan of the stiffness, then bisection on `log alpha` at
/// the top of the first quiet run, the protocol as the oracle).
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
    let found = search(&lp, nonlinear, beta, linear, options, tick)?;
    Ok(Some(BuzzFree {
        beta,
        alpha: found.top,
        quiet_beyond: found.beyond,
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
    if !(2..=MAX_SCAN_POINTS).contains(&options.scan_points) {
        return Err(Error::InvalidRequest(format!(
            "the buzz-free scan takes 2 to {MAX_SCAN_POINTS} stiffnesses (got {})",
            options.scan_points
        )));
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

/// The default number of stiffnesses scanned before the bisection: a log grid from
/// `tol alpha_lin` to `(1 - tol) alpha_lin`, both ends included.
///
/// 16 points put neighbours a ratio of at most `1000^(1/15) = 1.58` apart at the default
/// `tol`: a buzzing band wider than that is always seen, a narrower one may fall between
/// two points (quiet and buzzing bands of a few percent of the stiffness occur; a finer
/// scan, [`BuzzFreeOptions::scan_points`], resolves them at a proportional cost).
pub const SCAN_POINTS: usize = 16;

/// The most stiffnesses one scan may take.
pub const MAX_SCAN_POINTS: usize = 10_000;

/// The scan and bisection of one damping (module doc) with `quiet` as the oracle.
fn search(
    lp: &Loop,
    nonlinear: &Nonlinear,
    beta: f64,
    linear: f64,
    options: &BuzzFreeOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<Quiet> {
    let Some(device) = lp.device() else {
        return Ok(Quiet::default());
    };
    let quiet = |alpha: f64| -> Result<bool> {
        let wall = Wall::new(alpha, beta)?;
        let q = nonlinear.normalize(device, device.stiffness(alpha))?;
        let r = buzz(*lp, &wall, &q, &options.protocol)?;
        tick();
        Ok(!r.sustained())
    };
    scan_and_bisect(quiet, linear, options.tol, options.scan_points)
}

/// What the scan and bisection found at one damping.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Quiet {
    /// The top of the quiet run that starts at the lowest stiffness (`None`: the lowest
    /// buzzes).
    top: Option<f64>,
    /// The largest quiet stiffness of the scan above a buzzing one (`None`: the quiet
    /// stiffnesses scanned form one run from the lowest).
    beyond: Option<f64>,
}

/// The top edge of the quiet run that starts at `tol linear` (module doc): the scan of
/// `points` stiffnesses on a log grid up to `(1 - tol) linear`, then bisection on
/// `log alpha` between the last quiet point of the first run and the buzzing point after it
/// until their ratio is below `1 + tol`. The oracle is called in increasing order of the
/// scan, then in the bisection's order.
fn scan_and_bisect(
    quiet: impl Fn(f64) -> Result<bool>,
    linear: f64,
    tol: f64,
    points: usize,
) -> Result<Quiet> {
    let (lo, hi) = (linear * tol, linear * (1.0 - tol));
    let last = points - 1;
    let grid: Vec<f64> = (0..points)
        .map(|i| match i {
            0 => lo,
            i if i == last => hi,
            i => lo * (hi / lo).powf(i as f64 / last as f64),
        })
        .collect();
    let verdicts = grid.iter().map(|&a| quiet(a)).collect::<Result<Vec<_>>>()?;
    let run = verdicts.iter().take_while(|&&q| q).count();
    let beyond = grid
        .iter()
        .zip(&verdicts)
        .skip(run)
        .rev()
        .find(|(_, q)| **q)
        .map(|(a, _)| *a);
    let top = match run {
        0 => None,
        r if r == points => Some(hi),
        r => {
            let (mut lo, mut hi) = (grid[r - 1], grid[r]);
            while hi / lo > 1.0 + tol {
                let mid = (lo * hi).sqrt();
                if quiet(mid)? {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            Some(lo)
        }
    };
    Ok(Quiet { top, beyond })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic oracle whose quiet set is two intervals: the search returns the top of
    /// the first, to `tol`, and reports the second; one interval is reported as one.
    #[test]
    fn quiet_set_of_two_intervals() {
        let tol = 1e-3;
        let two = |a: f64| Ok((0.0..=0.3).contains(&a) || (0.5..=0.8).contains(&a));
        let r = scan_and_bisect(two, 1.0, tol, SCAN_POINTS).unwrap();
        let top = r.top.unwrap();
        assert!(top <= 0.3 && top * (1.0 + tol) > 0.3, "{top}");
        let beyond = r.beyond.unwrap();
        assert!((0.5..=0.8).contains(&beyond), "{beyond}");
        let one = |a: f64| Ok(a <= 0.3);
        let r = scan_and_bisect(one, 1.0, tol, SCAN_POINTS).unwrap();
        assert!(r.top.unwrap() <= 0.3 && r.beyond.is_none());
        // all quiet: the top of the range at once; the lowest buzzing: none
        let r = scan_and_bisect(|_| Ok(true), 1.0, tol, SCAN_POINTS).unwrap();
        assert_eq!(
            r,
            Quiet {
                top: Some(1.0 - tol),
                beyond: None
            }
        );
        let r = scan_and_bisect(|a| Ok(a > 0.5), 1.0, tol, SCAN_POINTS).unwrap();
        assert_eq!(r.top, None);
        assert!(r.beyond.unwrap() > 0.5);
    }
}
