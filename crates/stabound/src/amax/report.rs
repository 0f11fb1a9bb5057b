//! `alpha_max` of any loop on its own polynomial, and what a recommendation needs beside it:
//! the stable stiffnesses at its damping, the best wall over `beta >= 0`, and the best wall
//! whose whole range from a margin wall up to it is stable.
//!
//! Behind a velocity filter the stable stiffnesses at one damping need not be one range from
//! `0` to `alpha_max`: the rightmost point of the region can be the tip of a thin wedge, and a
//! fraction of it at the same damping unstable. [`margin_alpha_max`] finds the best wall
//! `(alpha, beta)` for which the whole segment from `margin alpha` to `alpha` at `beta` is
//! stable.

use super::direct::{Candidate, rightmost, strictly_stable};
use super::{Amax, AmaxOptions, curve::PaperCurve, detail};
use crate::curve::{Decomposition, Free, LoopCurve};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::{Wall, in_range};
use crate::poly::PaperPoly;
use crate::search::{Interval, MAX_FIXED, curve_stable_set};
use crate::stability::{certify, schur_cohn};

/// `alpha_max` together with the stable stiffness range at its damping and the best wall
/// with a nonnegative virtual damping.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[non_exhaustive]
pub struct AmaxReport {
    /// The rightmost point of the stable region (within the beta limits asked for).
    pub amax: Amax,
    /// The stable stiffnesses at `amax.beta_at_max`, sorted open intervals; ordinarily
    /// `alpha_max` is the upper end of the last one. More than one interval, or a last one
    /// starting well above `0`, says that softer walls at this damping are not all stable;
    /// none reaching `alpha_max` says the optimum is the tip of a wedge tilted off this
    /// line, approached only by walls at other dampings ([`margin_alpha_max`] then gives a
    /// wall to recommend).
    pub stable_alphas: Vec<Interval>,
    /// The rightmost point over `beta >= 0` (and the other limits asked for), when
    /// `amax.beta_at_max` is negative; `None` when the optimum already has `beta >= 0`.
    pub nonnegative: Option<Amax>,
    /// Why no wall with `beta >= 0` is given beside an optimum that needs negative
    /// damping (`nonnegative` is `None` then): none within the beta limits was confirmed,
    /// or the best one found does not hold (no wall a relative `1e-6` below it is strictly
    /// stable by the closed loop's state-matrix eigenvalues, nor any on its damping down to
    /// a quarter of it). `None` when `nonnegative` is given or the optimum has `beta >= 0`
    /// or the beta limits exclude `beta >= 0`.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub no_nonnegative: Option<String>,
    /// The spectral radius of the wall a relative `1e-6` below `alpha_max` at its damping
    /// (the stiffest wall to render) when the checker with its default marginal band
    /// (`1e-9`, [`crate::stability::Options`]) calls that wall marginal rather than stable:
    /// a closed-loop root within the band of the unit circle (a slow mode: behind a filter
    /// pole near `z = 1`, or with a physical damping of `1e-3` and less; on the paper's loop
    /// with much physical damping and no delay: at `delta = 100`, `d = 0` the root on the
    /// circle at the optimum moves only `2e-10` inside a relative `1e-6` below it), whose
    /// mode decays by a factor `e` only every
    /// `1 / (1 - radius)` samples. `None` when the checker calls it stable, or unstable (a
    /// tip tilted off its damping, whose stable walls below lie at other dampings: see
    /// `stable_alphas`).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub marginal_below: Option<f64>,
    /// The same for `nonnegative`: the radius of the wall a relative `1e-6` below it at its
    /// damping when the checker calls that wall marginal.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub nonnegative_marginal_below: Option<f64>,
    /// `None` when the direct search found `amax`; else where it comes from instead (the
    /// rightmost point of the traced boundary) and how accurate it is.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub fallback: Option<String>,
}

impl AmaxReport {
    /// Whether the stable stiffnesses at the optimum's damping are one range from `0` up to
    /// `alpha_max`, as in the paper's loop: ends within a relative `1e-7` (the 1-D search's
    /// ends are good to about `1e-12`). `false` says that some softer wall at that damping is
    /// unstable, or that the optimum is the tip of a wedge tilted off that damping.
    pub fn one_range(&self) -> bool {
        let a = self.amax.alpha_max;
        match self.stable_alphas.as_slice() {
            [i] => i.lo <= 1e-7 * a && (i.hi - a).abs() <= 1e-7 * a,
            _ => false,
        }
    }
}

/// A loop's D-decomposition: the paper's closed form for the paper's loop, its own
/// polynomial otherwise.
// built once per call, never stored in bulk: the paper's curve stays inline
#[allow(clippy::large_enum_variant)]
enum Engine {
    Paper(PaperCurve),
    General(Box<LoopCurve>),
}

impl Engine {
    fn new(lp: &Loop) -> Result<Self> {
        Ok(if lp.is_paper() {
            Engine::Paper(PaperCurve::new(lp.plant(), super::curve::ROTOR_RESEED))
        } else {
            Engine::General(Box::new(LoopCurve::new(lp)?))
        })
    }

    fn rightmost(&self, opts: &AmaxOptions) -> Option<Candidate> {
        match self {
            Engine::Paper(c) => rightmost(c, opts),
            Engine::General(c) => rightmost(c.as_ref(), opts),
        }
    }

    /// The stable set on a line, each piece decided by Schur-Cohn at radius exactly 1 (the
    /// boundary's own test: the ends are where a root crosses the circle).
    fn stable_set(&self, free: Free, fixed: f64) -> Result<Vec<Interval>> {
        fn on<D: Decomposition>(dec: &D, free: Free, fixed: f64) -> Result<Vec<Interval>> {
            let test = |w: &Wall| {
                Ok(crate::stability::schur_cohn::with_scratch(
                    dec.degree() + 1,
                    |buf| strictly_stable(dec, w, buf),
                ))
            };
            curve_stable_set(dec, free, fixed, &test)
        }
        match self {
            Engine::Paper(c) => on(c, free, fixed),
            Engine::General(c) => on(c.as_ref(), free, fixed),
        }
    }
}

/// `alpha_max` of `lp` on its own polynomial by the direct search (see the
/// [module documentation](super)), whatever its elements: for the paper's loop too, where
/// [`super::alpha_max`]'s closed forms give the same point faster.
///
/// # Errors
///
/// As [`crate::poly::CharPoly::new`]; [`Error::InvalidRequest`] when the beta limits
/// leave no stable wall; the boundary engines' errors where the direct search confirms no
/// candidate and the traced boundary's rightmost point is taken instead
/// ([`super::traced_rightmost`]).
pub(crate) fn loop_alpha_max(lp: &Loop, opts: &AmaxOptions) -> Result<Amax> {
    loop_held(lp, opts).map(|(a, _)| a)
}

/// [`loop_alpha_max`] and the state matrix's spectral radius at the wall a relative
/// [`HOLD_STEP`] below it ([`held`]'s).
fn loop_held(lp: &Loop, opts: &AmaxOptions) -> Result<(Amax, f64)> {
    let curve = LoopCurve::new(lp)?;
    let amax = match rightmost(&curve, opts) {
        Some(c) => detail(c).amax,
        None => super::traced_rightmost(lp, opts).map(|(a, _)| a)?,
    };
    held(&curve, amax, opts)
}

/// Relative step below `alpha_max` of the stiffest wall to render: `alpha_max (1 - HOLD_STEP)`
/// at the optimum's damping. A strictly stable wall must exist that far below every answer
/// of [`super::alpha_max`] (at the answer's damping or a damping beside it), and
/// [`marginal_below`] and [`AmaxReport::marginal_below`] speak of the wall that far below.
///
/// `1e-6`: far above the rounding of a search's answer (about `1e-12` relative), and a
/// millionth of the stiffness given up.
///
/// ```
/// use stabound::amax::{AmaxOptions, HOLD_STEP, alpha_max};
/// use stabound::params::{Plant, Wall};
/// use stabound::stability::{Checker, Options};
///
/// let plant = Plant::new(0.1, 1.0)?;
/// let a = alpha_max(plant, &AmaxOptions::default())?;
/// let render = Wall::new(a.alpha_max * (1.0 - HOLD_STEP), a.beta_at_max)?;
/// assert!(Checker::new(plant, Options::default())?.is_stable(&render)?);
/// # Ok::<(), stabound::Error>(())
/// ```
pub const HOLD_STEP: f64 = 1e-6;

/// Dampings sampled by [`held`] across its window, and golden-section steps around the best
/// sample (each keeps 0.618 of the bracket: 40 shrink it by `4e-9`, far inside a sliver
/// whose width is a thousandth of the window).
const HOLD_SCAN: usize = 32;
const HOLD_REFINE: usize = 40;

/// Half-width of [`held`]'s damping window in [`HOLD_STEP`]s of the answer's larger
/// coordinate: four, as the direct search's sliver test ([`super::direct`]), which holds the
/// measured shifts of a tilted tip's stable walls one step below it (about one step of
/// `|beta|` behind a low-pass pole `1e-7` from `z = 1`, 1.6 steps behind a slow
/// second-order filter at nine samples of delay).
const HOLD_REACH: f64 = 4.0;

/// Factors of [`HOLD_STEP`] by which [`held`] lowers an answer that does not hold, along its
/// damping, before bisecting: `4^k` up to `4^9` (about a quarter of the answer).
const LOWER_STEPS: u32 = 9;

/// Bisection steps between the stable and the unstable stiffness of [`held`]'s lowering:
/// the bracket is at most three quarters of the answer; 50 halvings leave under `1e-15` of
/// it.
const LOWER_BISECT: usize = 50;

/// The closed loop's spectral radius at `(alpha, beta)`: the eigenvalues of its state matrix
/// (built from the sampled device and the wall law, not from the polynomial; balanced, capped
/// QR), infinite where QR gives up. Near a cluster of roots at `z = 1` (a filter pole and the
/// device's free integrator within `1e-5` of it) the expanded polynomial's coefficients
/// carry rounding of about `1e-16` of their size against values of `1e-11` there, so the
/// polynomial's tests decide walls only to about `1e-5` of the stiffness; the state matrix
/// keeps the loop's parameters as they are, and its eigenvalues agree with 50-digit ones to
/// about `1e-12` there (`tools/amax_oracle.py`).
fn state_radius(curve: &LoopCurve, alpha: f64, beta: f64) -> f64 {
    let m = curve
        .poly()
        .discretization()
        .state_matrix(&Wall { alpha, beta });
    crate::roots::eigen::eigenvalues_capped(m).map_or(f64::INFINITY, |roots| {
        roots.iter().map(|z| z.norm()).fold(0.0, f64::max)
    })
}

/// The smallest spectral radius at stiffness `alpha` over the dampings of `[lo, hi]`:
/// [`HOLD_SCAN`] samples from the middle outwards (the stable walls below a tilted tip lie
/// an eighth to a fifth of the window off its damping), golden-section search around the
/// best ([`golden_min`]). Returns at once when a sample is strictly stable.
fn best_radius_across(curve: &LoopCurve, alpha: f64, lo: f64, hi: f64) -> f64 {
    let step = (hi - lo) / HOLD_SCAN as f64;
    let (mut best, mut at) = (f64::INFINITY, 0);
    let middle = HOLD_SCAN / 2;
    let outwards = (0..=HOLD_SCAN).map(|i| {
        // middle, middle + 1, middle - 1, middle + 2, ...
        let off = i.div_ceil(2);
        if i % 2 == 1 {
            middle + off
        } else {
            middle - off
        }
    });
    for k in outwards {
        let r = state_radius(curve, alpha, lo + step * k as f64);
        if r < 1.0 {
            return r;
        }
        if r < best {
            (best, at) = (r, k);
        }
    }
    let Ok(refined) = golden_min(
        lo + step * at.saturating_sub(1) as f64,
        lo + step * (at + 1).min(HOLD_SCAN) as f64,
        HOLD_REFINE,
        |beta| Ok::<f64, std::convert::Infallible>(state_radius(curve, alpha, beta)),
        |r| r < 1.0,
    );
    best.min(refined)
}

/// Golden-section search for the least `f` on `[x0, x1]` (J. Kiefer, "Sequential minimax
/// search for a maximum", *Proc. AMS* 4, 1953): `steps` steps, each keeping 0.618 of the
/// bracket, or fewer once a value seen satisfies `enough`. Returns the least value seen.
fn golden_min<E>(
    mut x0: f64,
    mut x1: f64,
    steps: usize,
    mut f: impl FnMut(f64) -> std::result::Result<f64, E>,
    enough: impl Fn(f64) -> bool,
) -> std::result::Result<f64, E> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut u = x1 - g * (x1 - x0);
    let mut v = x0 + g * (x1 - x0);
    let (mut fu, mut fv) = (f(u)?, f(v)?);
    let mut best = f64::INFINITY;
    for _ in 0..steps {
        best = best.min(fu).min(fv);
        if enough(best) {
            break;
        }
        if fu <= fv {
            x1 = v;
            (v, fv) = (u, fu);
            u = x1 - g * (x1 - x0);
            fu = f(u)?;
        } else {
            x0 = u;
            (u, fu) = (v, fv);
            v = x0 + g * (x1 - x0);
            fv = f(v)?;
        }
    }
    Ok(best.min(fu).min(fv))
}

/// The answer `amax` if a wall a relative [`HOLD_STEP`] below it is strictly stable by the
/// state matrix's eigenvalues ([`state_radius`]): at its damping, at a damping of the
/// direct search's neighbour directions a step away that Schur-Cohn calls stable, or at the
/// best damping within [`HOLD_REACH`] steps of it inside the beta limits (the stable walls
/// below a tip tilted off its damping). Otherwise the polynomial's tests placed the answer beyond the
/// region (roots crowding near `z = 1`, see [`state_radius`]): the stiffest wall on the
/// answer's damping that the eigenvalues call stable, lowered by steps of `4^k`
/// [`HOLD_STEP`] and bisected, answers instead when the wall a relative [`HOLD_STEP`] below
/// it holds too.
///
/// # Errors
///
/// [`Error::InvalidRequest`] with beta limits, [`Error::Numerical`] without, when no wall
/// on the answer's damping down to a quarter of it is strictly stable by the eigenvalues:
/// the stable walls the polynomial's tests found there are rounding.
fn held(curve: &LoopCurve, amax: Amax, opts: &AmaxOptions) -> Result<(Amax, f64)> {
    hold(curve, amax, opts).map_err(|why| {
        let (bmin, bmax) = (
            opts.beta_min().unwrap_or(f64::NEG_INFINITY),
            opts.beta_max().unwrap_or(f64::INFINITY),
        );
        if opts.beta_min().is_some() || opts.beta_max().is_some() {
            Error::InvalidRequest(format!(
                "no stable wall of this loop was found with a virtual damping between {bmin} and {bmax} ({why}); widen the beta limits"
            ))
        } else {
            Error::Numerical(format!(
                "no rightmost point of this loop's stable region holds ({why}); give beta limits that keep the search away from that tip"
            ))
        }
    })
}

/// [`held`]'s test and lowering: the answer that holds with the state matrix's spectral
/// radius a relative [`HOLD_STEP`] below it at its damping (infinite where that wall is not
/// the one that holds it), or why none does.
fn hold(
    curve: &LoopCurve,
    amax: Amax,
    opts: &AmaxOptions,
) -> std::result::Result<(Amax, f64), String> {
    let (a, b) = (amax.alpha_max, amax.beta_at_max);
    let below = a * (1.0 - HOLD_STEP);
    let first = state_radius(curve, below, b);
    if first < 1.0 {
        return Ok((amax, first));
    }
    let (bmin, bmax) = (
        opts.beta_min().unwrap_or(f64::NEG_INFINITY),
        opts.beta_max().unwrap_or(f64::INFINITY),
    );
    let reach = HOLD_REACH * HOLD_STEP * a.abs().max(b.abs());
    let (lo, hi) = ((b - reach).max(bmin), (b + reach).min(bmax));
    // First the dampings of the direct search's neighbour directions a step away (in
    // `beta`'s own scale and in the plane's), screened by Schur-Cohn (cheap) and held only
    // by the eigenvalues: a wedge's walls below its tip lie along its edges.
    let own = super::direct::FAN.iter().map(|k| k * HOLD_STEP * b.abs());
    let plane = super::direct::LEFT_SLOPES
        .iter()
        .map(|k| k * HOLD_STEP * (a.abs() + b.abs()));
    let beside = crate::stability::schur_cohn::with_scratch(curve.degree() + 1, |buf| {
        own.chain(plane).any(|off| {
            let wall = Wall {
                alpha: below,
                beta: b + off,
            };
            (bmin..=bmax).contains(&wall.beta)
                && strictly_stable(curve, &wall, buf)
                && state_radius(curve, below, wall.beta) < 1.0
        })
    });
    if beside || (lo < hi && best_radius_across(curve, below, lo, hi) < 1.0) {
        return Ok((amax, f64::INFINITY));
    }
    let mut above = below;
    let stable = (1..=LOWER_STEPS).find_map(|k| {
        let alpha = a * (1.0 - HOLD_STEP * 4f64.powi(k as i32));
        if state_radius(curve, alpha, b) < 1.0 {
            Some(alpha)
        } else {
            above = alpha;
            None
        }
    });
    if let Some(mut low) = stable {
        for _ in 0..LOWER_BISECT {
            let mid = 0.5 * (low + above);
            if state_radius(curve, mid, b) < 1.0 {
                low = mid;
            } else {
                above = mid;
            }
        }
        let last = state_radius(curve, low * (1.0 - HOLD_STEP), b);
        if last < 1.0 {
            return Ok((
                Amax {
                    alpha_max: low,
                    beta_at_max: b,
                },
                last,
            ));
        }
    }
    Err(format!(
        "the direct search's rightmost point alpha = {a}, beta = {b} does not hold: no wall a relative {HOLD_STEP:e} below it (at that damping or within {reach:e} of it), nor any on that damping down to a quarter of it, is strictly stable by the closed loop's state-matrix eigenvalues; the polynomial's tests called walls there stable within their rounding near z = 1"
    ))
}

/// The error when no candidate was confirmed: the cancellation when the run was cancelled
/// meanwhile (a cancelled search answers its point tests the cheapest way and confirms
/// nothing), else what the beta limits or the loop leave.
pub(super) fn no_candidate(opts: &AmaxOptions) -> Error {
    if let Err(cancelled) = crate::cancel::poll() {
        cancelled
    } else if opts.beta_min().is_some() || opts.beta_max().is_some() {
        Error::InvalidRequest(format!(
            "no stable wall of this loop has a virtual damping between {} and {}; widen the beta limits",
            opts.beta_min().unwrap_or(f64::NEG_INFINITY),
            opts.beta_max().unwrap_or(f64::INFINITY)
        ))
    } else {
        Error::Numerical(
            "no rightmost point of this loop's stable region could be confirmed".into(),
        )
    }
}

/// The largest stable stiffness of `lp` over the dampings `opts` admits, with the stable
/// stiffnesses at that damping and, when it needs negative damping, the best wall with
/// `beta >= 0` beside it.
///
/// Method: the direct search of [`super::alpha_max`] on the loop's D-decomposition (the
/// closed form for the paper's loop, whose `alpha_max` is then the same bits), twice when
/// the optimum has `beta < 0`; the stable set on the line `beta = beta_at_max` by direct
/// search on the same curve and lines.
///
/// ```
/// use stabound::amax::{AmaxOptions, amax_report};
/// use stabound::elements::Loop;
/// use stabound::filter::VelocityFilter;
/// use stabound::params::Plant;
///
/// let lp = Loop::new(Plant::new(1.0, 1.0)?).with_filter(VelocityFilter::low_pass(0.5)?)?;
/// let r = amax_report(&lp, &AmaxOptions::default())?;
/// // here the stable stiffnesses at the optimum's damping are one range from 0 up to it
/// let top = r.stable_alphas.last().expect("stable walls at the optimum's damping");
/// assert!(top.lo == 0.0 && (top.hi - r.amax.alpha_max).abs() <= 1e-9 * r.amax.alpha_max);
/// if let Some(b) = r.nonnegative {
///     assert!(b.beta_at_max >= 0.0 && b.alpha_max <= r.amax.alpha_max);
/// }
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`crate::elements::loop_alpha_max`]; [`Error::InvalidRequest`] when the optimum's
/// damping is beyond the searches along a line ([`MAX_FIXED`]; beta limits within it give a
/// report).
pub fn amax_report(lp: &Loop, opts: &AmaxOptions) -> Result<AmaxReport> {
    let engine = Engine::new(lp)?;
    let (amax, fallback, radius) = best(&engine, lp, opts)?;
    beyond_line_searches(&amax)?;
    let stable_alphas = engine.stable_set(Free::Alpha, amax.beta_at_max)?;
    let (nonnegative, no_nonnegative) = match nonnegative_beside(&engine, &amax, opts)? {
        None => (None, None),
        Some(Ok(n)) => (Some(n), None),
        Some(Err(why)) => (None, Some(why)),
    };
    let nonnegative_radius = nonnegative.map(|(_, r)| r);
    let nonnegative = nonnegative.map(|(n, _)| n);
    let paper = match &engine {
        Engine::Paper(c) => Some(&c.poly),
        Engine::General(_) => None,
    };
    let marginal_below = marginal_radius_below(lp, paper, &amax, radius)?;
    let nonnegative_marginal_below = match (&nonnegative, nonnegative_radius) {
        (Some(n), Some(r)) => marginal_radius_below(lp, paper, n, r)?,
        _ => None,
    };
    Ok(AmaxReport {
        amax,
        stable_alphas,
        nonnegative,
        no_nonnegative,
        marginal_below,
        nonnegative_marginal_below,
        fallback,
    })
}

/// The best wall with `beta >= 0` (within the beta limits) beside an optimum that needs
/// negative damping: `None` when the optimum has `beta >= 0` or the limits exclude
/// `beta >= 0`; else the wall, held as the optimum is (the stiffest wall that holds on its
/// damping, [`held`]) for a loop with elements, or why there is none.
fn nonnegative_beside(
    engine: &Engine,
    amax: &Amax,
    opts: &AmaxOptions,
) -> Result<Option<std::result::Result<(Amax, f64), String>>> {
    if amax.beta_at_max >= 0.0 {
        return Ok(None);
    }
    let lo = opts.beta_min().map_or(0.0, |b| b.max(0.0));
    let hi = opts.beta_max();
    if hi.is_some_and(|h| h < lo) {
        return Ok(None);
    }
    let o = opts.with_beta_limits(Some(lo), hi)?;
    let Some(found) = engine.rightmost(&o).map(|c| detail(c).amax) else {
        // a cancelled search confirms nothing: the cancellation is the answer then
        crate::cancel::poll()?;
        return Ok(Some(Err(format!(
            "the direct search confirmed no wall with a virtual damping between {lo} and {} as the rightmost stable one; ask for alpha_max with a lower beta limit of {lo} for the traced boundary's rightmost point there, or its refusal",
            hi.unwrap_or(f64::INFINITY)
        ))));
    };
    Ok(Some(match engine {
        Engine::Paper(_) => Ok((found, f64::NAN)),
        Engine::General(curve) => hold(curve, found, &o),
    }))
}

/// Distance inside the unit circle beyond which a state-matrix radius is not within the
/// checker's marginal band (`1e-9`): with `|beta| <= 1e6` the matrix's entries are at most
/// about `1e6`, its eigenvalues' rounding about `1e6 eps = 2e-10` (`1e-12` near a root
/// cluster at `z = 1`, by the 50-digit oracle), so `1e-8` leaves `9e-9` beyond the band,
/// some 45 times that rounding. (A wall a relative `1e-6` below the boundary commonly has a
/// radius only some `1e-7` inside the circle, so a wider distance would ask the checker on
/// most answers.)
const CLEARLY_INSIDE: f64 = 1e-8;

/// The spectral radius of the wall a relative [`HOLD_STEP`] below the optimum at its
/// damping when the checker (default options, the band `check` uses) calls it marginal;
/// `None` when it calls it stable or unstable (a tip tilted off its damping, whose stable
/// walls below lie at other dampings: the stable stiffnesses say so), or where it reaches no
/// verdict (its eigenvalues do not converge on a long moving average's state matrix: the
/// report stands on the held answer then, as `check` would answer with its error). One
/// decision of the checker (Schur-Cohn, no roots where it decides); the radius, from the
/// roots, only for a marginal wall, else by Schur-Cohn bisection on the radius where the
/// roots fail.
///
/// The checker is asked only where a root can lie within the band: not where `radius`, the
/// state matrix's at that wall when known (NaN or infinite otherwise), is farther than
/// [`CLEARLY_INSIDE`] inside the circle, nor, for the paper's loop, where
/// [`paper_clearly_inside`] proves every root that far inside.
fn marginal_radius_below(
    lp: &Loop,
    paper: Option<&PaperPoly>,
    amax: &Amax,
    radius: f64,
) -> Result<Option<f64>> {
    if radius < 1.0 - CLEARLY_INSIDE && amax.beta_at_max.abs() <= 1e6 {
        return Ok(None);
    }
    let wall = Wall::new(amax.alpha_max * (1.0 - HOLD_STEP), amax.beta_at_max)?;
    if paper.is_some_and(|poly| paper_clearly_inside(poly, &wall)) {
        return Ok(None);
    }
    let checker = crate::stability::Checker::new(*lp, crate::stability::Options::default())?;
    Ok(match checker.decide_with_marginal_radius(&wall) {
        Ok((_, Some(radius))) => {
            Some(radius.unwrap_or_else(|_| checker.spectral_radius_schur_cohn(&wall)))
        }
        _ => None,
    })
}

/// Whether every root of the paper's loop at `wall` lies more than [`CLEARLY_INSIDE`]
/// inside the unit circle, proved for the model's exact polynomial.
///
/// Method: the coefficients as balls, the computed ones with the bound of their rounding
/// ([`certify::Enclosure`], the bounds the checker's own proofs use), scaled to the circle of
/// radius `r = 1 - CLEARLY_INSIDE` (`q(r z)`), and the Schur-Cohn recursion on them (Schur
/// 1917, Cohn 1922; Marden, "Geometry of Polynomials", AMS 1966, section 42;
/// [`crate::enclosure::schur`]): first in plain `f64` with a running bound on the
/// coefficients' rounding (midpoint-radius arithmetic, Rump 1999, with Higham's bounds on a
/// rounded product and sum, from the largest coefficient error bound
/// [`certify::Enclosure::max_error`]: [`crate::enclosure::schur::balls_inside`], a fraction
/// of the cost), and where that cannot decide, in interval arithmetic with outward rounding
/// on each coefficient's own bound. When every
/// step is decided with `|a_0| < |a_k|` for every polynomial within the intervals, each has
/// all its roots strictly inside `r`: the exact spectral radius is below `1 - 1e-8`, ten
/// times the checker's band inside the circle, so no method of the checker (each decides
/// only what holds for every polynomial within the enclosure) proves the wall marginal. The
/// recursion's steps neither divide by `1 - k^2` nor bound errors to first order, so a wall
/// a relative `1e-6` below the boundary (a root about `1e-7` inside the circle) is decided
/// where the checker's rounding guard is not, at the cost of one recursion of the
/// polynomial's degree (`n + 3` or `n + 4`) against the checker's root count (a fifth of
/// the whole report on the paper's loop). `false` says only that the recursion could not
/// prove it: the checker decides then.
fn paper_clearly_inside(poly: &PaperPoly, wall: &Wall) -> bool {
    use crate::enclosure::{interval::Interval, schur};
    let enclosure = certify::Enclosure::new(poly);
    let len = poly.degree() + 1;
    schur_cohn::with_two_rows(len, |q, e| {
        poly.coefficients_into(wall, q);
        let rad = enclosure.max_error(wall);
        if schur::balls_inside(q, e, rad, 1.0 - CLEARLY_INSIDE) {
            return true;
        }
        let q = poly.coefficients_into(wall, q);
        let e = enclosure.errors_into(wall, e);
        let boxed: Vec<Interval> = q
            .iter()
            .zip(e)
            .map(|(&c, &r)| Interval::from_ball(c, r))
            .collect();
        schur::all_inside(schur::scaled(&boxed, Interval::point(1.0 - CLEARLY_INSIDE)))
    })
}

/// The spectral radius of the wall a relative `1e-6` below `amax` (a rightmost point of
/// `lp`'s stable region, as [`super::alpha_max`] or [`amax_report`] gives it) at its damping
/// when the checker with its default band ([`crate::stability::DEFAULT_MARGIN`]) calls that
/// wall marginal: a closed-loop root within `1e-9` of the unit circle, whose mode decays by
/// a factor `e` only every `1 / (1 - radius)` samples. `None` when the checker calls it
/// stable or unstable, or reaches no verdict. This is [`AmaxReport::marginal_below`] for a
/// caller that has `alpha_max` without the report; [`alpha_max_with_marginal`] computes
/// both, the paper's loop's discretization once.
///
/// Method: for the paper's loop the Schur-Cohn recursion on the circle of radius `1 - 1e-8`
/// first, over the coefficients' rounding enclosure (cheap: a pass proves every root farther
/// inside than the band), in `f64` with a running rounding bound and, where that cannot
/// decide, in interval arithmetic; otherwise, and for a loop with elements, the checker's decision
/// ([`crate::stability::Checker::decide`]) and, for a marginal wall, its spectral radius.
///
/// ```
/// use stabound::amax::{AmaxOptions, alpha_max, marginal_below};
/// use stabound::elements::Loop;
/// use stabound::params::Plant;
///
/// let lp = Loop::new(Plant::new(0.1, 1.0)?);
/// let a = alpha_max(lp, &AmaxOptions::default())?;
/// // an ordinary loop: the wall below alpha_max is clearly stable
/// assert_eq!(marginal_below(&lp, &a)?, None);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A stiffness or damping that is not finite ([`Error::InvalidParameter`]); as
/// [`crate::stability::Checker::new`].
pub fn marginal_below(lp: &Loop, amax: &Amax) -> Result<Option<f64>> {
    let paper = lp.is_paper().then(|| PaperPoly::new(lp.plant()));
    marginal_radius_below(lp, paper.as_ref(), amax, f64::NAN)
}

/// `alpha_max` of `lp`, the same bits as [`super::alpha_max`], and the spectral radius of
/// the wall a relative [`HOLD_STEP`] below it at its damping when the checker calls that wall
/// marginal, as [`marginal_below`] says it of that answer: for the paper's loop at the cost
/// of `alpha_max` and the wall's proof alone (the search's discretization serves both), for
/// a loop with elements as [`amax_report`] (the state matrix's radius at that wall, which
/// the answer's hold computes, asks the checker only where it is within [`CLEARLY_INSIDE`] of
/// the circle).
///
/// Method: [`super::alpha_max`]'s, then [`marginal_below`]'s on the same polynomial.
///
/// ```
/// use stabound::amax::{AmaxOptions, alpha_max, alpha_max_with_marginal};
/// use stabound::params::Plant;
///
/// let plant = Plant::new(0.1, 1.0)?;
/// let (a, below) = alpha_max_with_marginal(plant, &AmaxOptions::default())?;
/// assert_eq!(a, alpha_max(plant, &AmaxOptions::default())?);
/// // an ordinary loop: the wall below alpha_max is clearly stable
/// assert_eq!(below, None);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`super::alpha_max`] and [`marginal_below`].
pub fn alpha_max_with_marginal(
    lp: impl Into<Loop>,
    opts: &AmaxOptions,
) -> Result<(Amax, Option<f64>)> {
    let lp = lp.into();
    if lp.is_paper() {
        let curve = PaperCurve::new(lp.plant(), super::curve::ROTOR_RESEED);
        let amax = super::search_on(&curve, lp.plant(), opts)?.amax;
        let below = marginal_radius_below(&lp, Some(&curve.poly), &amax, f64::NAN)?;
        Ok((amax, below))
    } else {
        let (amax, radius) = loop_held(&lp, opts)?;
        Ok((amax, marginal_radius_below(&lp, None, &amax, radius)?))
    }
}

/// Refuses an optimum whose damping is beyond the line searches' reach ([`MAX_FIXED`]):
/// its stable stiffnesses cannot be listed there. A filter pole within about `1e-7` of
/// `z = 1` with some physical damping stretches the stable region into a sliver whose tip
/// has dampings of `1e13` and more (normalized); the refusal says where it is and that beta
/// limits give a report within them.
fn beyond_line_searches(amax: &Amax) -> Result<()> {
    if amax.beta_at_max.abs() <= MAX_FIXED {
        return Ok(());
    }
    Err(Error::InvalidRequest(format!(
        "alpha_max of this loop is {} at beta = {}, a damping beyond the reach of the searches along a line (|beta| <= {MAX_FIXED:e}, normalized), so the stable stiffnesses there cannot be listed; give beta limits within that reach (a lower limit of -{MAX_FIXED:e} or above) for a report within them",
        amax.alpha_max, amax.beta_at_max
    )))
}

/// `alpha_max` of `lp`: the paper's closed form for the paper's loop (the same bits as
/// [`super::alpha_max`]), the direct search on its own polynomial otherwise, and where that
/// confirms no candidate the traced boundary's rightmost point with a sentence saying so
/// ([`super::traced_rightmost`]).
fn best(engine: &Engine, lp: &Loop, opts: &AmaxOptions) -> Result<(Amax, Option<String>, f64)> {
    match engine {
        Engine::Paper(c) => super::search_on(c, lp.plant(), opts).map(|d| (d.amax, None, f64::NAN)),
        Engine::General(curve) => {
            let (amax, why) = match engine.rightmost(opts) {
                Some(c) => (detail(c).amax, None),
                None => super::traced_rightmost(lp, opts).map(|(a, why)| (a, Some(why)))?,
            };
            let (amax, radius) = held(curve, amax, opts)?;
            Ok((amax, why, radius))
        }
    }
}

/// How far inside the stable set the margin wall must be, relative: where the best wall is
/// limited by the margin wall reaching the lower end of a stable interval, the margin wall
/// would otherwise sit on the boundary, with a spectral radius a hair below 1 and every
/// softer wall at its damping unstable. `1e-2` keeps it a percent of its stiffness inside
/// (a spectral radius visibly below 1, robust to the device's parameters being known to a
/// few digits) and costs at most a percent of the stiffness, only where the stable set at
/// the optimum's damping does not reach from the margin wall up to `alpha_max`.
const MARGIN_ROOM: f64 = 1e-2;

/// Beta samples of the scan for the best margin wall over the dampings the region spans
/// (see [`margin_alpha_max`]).
const MARGIN_SCAN: usize = 192;

/// Golden-section steps that refine the best sample: each keeps 0.618 of the bracket, 60 of
/// them shrink it by `3e-13`, below the `1e-12` relative resolution the scan's neighbour
/// spacing needs.
const MARGIN_REFINE: usize = 60;

/// Ratio of successive tops in the scan down from `alpha_max` (see [`margin_alpha_max`]):
/// `2^(-1/4)`, four tops an octave, so that the first feasible top is within 19 % of the
/// best one before the bisection refines it.
const TOP_RATIO: f64 = 0.840_896_415_253_714_6;

/// Lowest top of that scan, relative to `alpha_max`: a sliver region (a filter pole `1e-6`
/// from `z = 1`) is wide enough for a margin range only about `1e-4` of the way up to its
/// tip; `1e-9` leaves five decades below that, at 120 tops at most.
const TOP_FLOOR: f64 = 1e-9;

/// Bisection steps between the first feasible top and the infeasible one above it: the
/// bracket is 19 % of the top, 40 halvings bring it below `2e-13` of it.
const TOP_BISECT: usize = 40;

/// The search for the best margin wall: the stable stiffnesses at a damping, and the best
/// wall seen so far (every wall offered is checked by its own stable set, so keeping the best
/// is safe whatever the search proposes).
struct MarginSearch<'a> {
    engine: &'a Engine,
    margin: f64,
    /// The beta limits asked for.
    limits: (f64, f64),
    /// The best `(alpha, beta)` seen: `alpha` the top of the stable interval at `beta` that
    /// holds `[margin alpha, alpha)` with room.
    found: (f64, f64),
}

impl MarginSearch<'_> {
    /// The top of the stable set at `beta` whose interval covers `[margin a, a)` with room,
    /// `-inf` where none does; kept when it is the best so far.
    fn offer(&mut self, beta: f64) -> Result<f64> {
        // beyond the line searches' reach (a common piece of two lines' stable dampings
        // may end far out) no wall is offered: the search goes on instead of failing
        if !(self.limits.0 <= beta && beta <= self.limits.1 && beta.abs() <= MAX_FIXED) {
            return Ok(f64::NEG_INFINITY);
        }
        let m = self.margin * (1.0 - MARGIN_ROOM);
        let a = self
            .engine
            .stable_set(Free::Alpha, beta)?
            .iter()
            .filter(|i| i.lo < m * i.hi)
            .map(|i| i.hi)
            .fold(f64::NEG_INFINITY, f64::max);
        if a > self.found.0 {
            self.found = (a, beta);
        }
        Ok(a)
    }

    /// Golden-section search ([`golden_min`]) for the largest [`Self::offer`] on
    /// `[x0, x1]`; the best wall is kept by `offer` itself.
    fn golden(&mut self, x0: f64, x1: f64) -> Result<()> {
        // negation is exact, so the steps compare as they would on `offer` itself
        golden_min(
            x0,
            x1,
            MARGIN_REFINE,
            |beta| self.offer(beta).map(|a| -a),
            |_| false,
        )
        .map(|_| ())
    }

    /// Scan of [`MARGIN_SCAN`] dampings over `[lo, hi]`, refined around the best sample.
    fn scan(&mut self, lo: f64, hi: f64) -> Result<()> {
        let step = (hi - lo) / MARGIN_SCAN as f64;
        let (mut best_k, mut best_a) = (0, f64::NEG_INFINITY);
        for k in 0..=MARGIN_SCAN {
            let a = self.offer(lo + step * k as f64)?;
            if a > best_a {
                (best_a, best_k) = (a, k);
            }
        }
        if best_a.is_finite() {
            self.golden(
                lo + step * best_k.saturating_sub(1) as f64,
                lo + step * (best_k + 1).min(MARGIN_SCAN) as f64,
            )?;
        }
        Ok(())
    }

    /// Whether some damping holds the whole range `[margin top, top]`: the dampings stable
    /// both at the margin stiffness (with room) and at `top` (the region's own position and
    /// width there), each common piece offered at its middle and quarters. Returns the
    /// common piece of the best damping offered, if that damping reaches `top`.
    fn feasible(&mut self, top: f64) -> Result<Option<(f64, f64)>> {
        let low = self
            .engine
            .stable_set(Free::Beta, self.margin * (1.0 - MARGIN_ROOM) * top)?;
        if low.is_empty() {
            return Ok(None);
        }
        let high = self.engine.stable_set(Free::Beta, top)?;
        let mut best: Option<(f64, f64, f64)> = None;
        for i in &low {
            for j in &high {
                let lo = i.lo.max(j.lo).max(self.limits.0);
                let hi = i.hi.min(j.hi).min(self.limits.1);
                if !(lo < hi && lo.is_finite() && hi.is_finite()) {
                    continue;
                }
                for f in [0.5, 0.25, 0.75] {
                    let a = self.offer(lo + f * (hi - lo))?;
                    if a >= top && best.is_none_or(|b| a > b.0) {
                        best = Some((a, lo, hi));
                    }
                }
            }
        }
        Ok(best.map(|(_, lo, hi)| (lo, hi)))
    }

    /// The largest top whose margin range some damping holds, from `alpha_max` down: tops
    /// in ratio [`TOP_RATIO`] down to [`TOP_FLOOR`] of it (or to the best wall found so
    /// far) until one is feasible, bisection
    /// between it and the one above, then the golden-section search on the common dampings
    /// of the best feasible top.
    fn descend(&mut self, alpha_max: f64) -> Result<()> {
        let mut above = alpha_max;
        let mut top = alpha_max * TOP_RATIO;
        let mut piece = None;
        // a top below the best wall already found cannot improve on it
        while top >= alpha_max * TOP_FLOOR && top > self.found.0 {
            piece = self.feasible(top)?;
            if piece.is_some() {
                break;
            }
            above = top;
            top *= TOP_RATIO;
        }
        let Some(mut piece) = piece else {
            return Ok(());
        };
        for _ in 0..TOP_BISECT {
            let mid = 0.5 * (top + above);
            match self.feasible(mid)? {
                Some(p) => (top, piece) = (mid, p),
                None => above = mid,
            }
        }
        self.golden(piece.0, piece.1)
    }
}

/// The best wall whose whole range of stiffnesses from `margin alpha` to `alpha` at its
/// damping is stable: `alpha` is as large as possible among walls `(alpha, beta)` within the
/// beta limits of `opts` whose stable set at `beta` holds the segment
/// `[margin alpha, alpha)` (`alpha` itself is on the boundary, as `alpha_max` is). Where
/// the stable set at `beta_at_max` holds that segment, the answer is `alpha_max` itself (the
/// same bits as [`amax_report`]); otherwise a lower wall at another damping.
///
/// Method: the stable stiffnesses on lines of constant `beta` and the stable dampings on
/// lines of constant `alpha` by direct search (as [`amax_report`]). Two searches, the best
/// wall of both kept:
/// - over the damping range the region spans (the stable dampings at 15 stiffnesses between
///   `0` and `alpha_max`), a scan of `192` dampings refined by golden-section search around
///   the best (J. Kiefer, "Sequential minimax search for a maximum", *Proc. AMS* 4, 1953);
/// - for a region too thin for that grid (a sliver along a tilted line, as behind a filter
///   pole near `z = 1`), tops falling from `alpha_max` in ratio `2^(-1/4)`, each tried at the
///   dampings stable both at it and at the margin stiffness below it (the sliver's own
///   position and width there); bisection between the first feasible top and the one above,
///   then golden-section search on its common dampings.
///
/// ```
/// use stabound::amax::{AmaxOptions, margin_alpha_max};
/// use stabound::elements::Loop;
/// use stabound::params::Plant;
///
/// // The paper's loop: the stable set at every damping is one range from 0, so the best
/// // margin wall is alpha_max itself.
/// let lp = Loop::new(Plant::new(1.0, 1.0)?);
/// let m = margin_alpha_max(&lp, &AmaxOptions::default(), 0.75)?;
/// let a = stabound::alpha_max(lp.plant(), &AmaxOptions::default())?;
/// assert_eq!(m, a);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// `margin` outside `(0, 1]`; as [`amax_report`].
pub fn margin_alpha_max(lp: &Loop, opts: &AmaxOptions, margin: f64) -> Result<Amax> {
    in_range("margin", margin, f64::MIN_POSITIVE, 1.0)?;
    let engine = Engine::new(lp)?;
    let (amax, _, _) = best(&engine, lp, opts)?;
    let at_max = engine.stable_set(Free::Alpha, amax.beta_at_max)?;
    // the interval whose top is alpha_max (to the 1-D search's accuracy, far inside 1e-7)
    if at_max.iter().any(|i| {
        (i.hi - amax.alpha_max).abs() <= 1e-7 * amax.alpha_max.abs()
            && i.lo < margin * amax.alpha_max * (1.0 - MARGIN_ROOM)
    }) {
        return Ok(amax);
    }
    let limits = (
        opts.beta_min().unwrap_or(f64::NEG_INFINITY),
        opts.beta_max().unwrap_or(f64::INFINITY),
    );
    // The dampings the region spans: the hull of the stable dampings at stiffnesses from
    // near 0 to near alpha_max, within the beta limits.
    let (mut lo, mut hi) = (amax.beta_at_max, amax.beta_at_max);
    for k in 1..16 {
        for i in engine.stable_set(Free::Beta, amax.alpha_max * f64::from(k) / 16.0)? {
            lo = lo.min(i.lo);
            hi = hi.max(i.hi);
        }
    }
    let mut search = MarginSearch {
        engine: &engine,
        margin,
        limits,
        found: (f64::NEG_INFINITY, amax.beta_at_max),
    };
    search.scan(lo.max(limits.0), hi.min(limits.1))?;
    search.descend(amax.alpha_max)?;
    let (alpha, beta) = search.found;
    if !(alpha.is_finite() && alpha > 0.0) {
        return Err(Error::Numerical(format!(
            "no wall of this loop has every stiffness from {margin} of it up to it stable at one damping"
        )));
    }
    Ok(Amax {
        alpha_max: alpha,
        beta_at_max: beta,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Plant;

    /// The closed loop's spectral radius at `(alpha, beta)` by nalgebra's eigenvalues of
    /// its state matrix balanced first (Parlett-Reinsch; not the library's capped QR that
    /// [`state_radius`] uses, nor the polynomial the direct search reads). Near a root
    /// cluster at `z = 1` these agree with 50-digit eigenvalues to about `1e-12`
    /// (`tools/amax_oracle.py`).
    fn balanced_radius(curve: &LoopCurve, alpha: f64, beta: f64) -> f64 {
        let mut m = curve
            .poly()
            .discretization()
            .state_matrix(&Wall { alpha, beta });
        nalgebra::linalg::balancing::balance_parlett_reinsch(&mut m);
        m.complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max)
    }

    /// Behind a low-pass pole `1e-5` from `z = 1` with neither delay nor physical damping,
    /// the direct search on the polynomial places the tip too far (the polynomial's rounding
    /// near the root cluster at `z = 1`), and the answer falls back to the search along its
    /// damping: lowered by steps, then bisected on the state matrix's radius. Checked by
    /// independent eigenvalues: the direct search's wall a relative `1e-6` below its answer
    /// is unstable; the lowered answer is the boundary on that damping to a relative `1e-5`
    /// (stable that far below, unstable that far above). The radius moves by about
    /// `2.5e-12` per relative `1e-6` of stiffness there, so `1e-5` is `2.5e-11` from the
    /// circle, 25 times the eigenvalues' accuracy; the direct answer lies about `7e-6`
    /// above the boundary, its wall below some `1.5e-11` outside.
    #[test]
    fn answer_that_does_not_hold_is_lowered_by_bisection() {
        let lp = Loop::new(Plant::new(0.0, 0.0).unwrap())
            .with_filter(crate::filter::VelocityFilter::low_pass(1.0 - 1e-5).unwrap())
            .unwrap();
        let opts = AmaxOptions::default();
        let curve = LoopCurve::new(&lp).unwrap();
        let direct = detail(rightmost(&curve, &opts).expect("a candidate")).amax;
        let (a, b) = (direct.alpha_max, direct.beta_at_max);
        assert!(
            balanced_radius(&curve, a * (1.0 - HOLD_STEP), b) > 1.0,
            "{direct:?}"
        );
        let (held_at, radius) = held(&curve, direct, &opts).unwrap();
        let h = held_at.alpha_max;
        // the fallback's answer: lower, on the same damping (exact: it keeps the damping)
        assert!(
            h < a && held_at.beta_at_max == b,
            "{held_at:?} vs {direct:?}"
        );
        assert!(radius < 1.0, "{radius}");
        assert!(
            balanced_radius(&curve, h * (1.0 - 1e-5), b) < 1.0,
            "{held_at:?}"
        );
        assert!(
            balanced_radius(&curve, h * (1.0 + 1e-5), b) > 1.0,
            "{held_at:?}"
        );
    }

    /// The interval recursion's proof against the state matrix's eigenvalues (nalgebra's
    /// real Schur form): where it proves every root `1e-8` inside, the eigenvalues agree;
    /// on walls whose eigenvalue radius is within `1e-8` of the circle (delta 100 at no
    /// delay, `2e-10` inside; stiffer walls up to the boundary) it proves nothing.
    #[test]
    fn clearly_inside_is_proved_only_clearly_inside() {
        let radius = |plant: &Plant, wall: &Wall| {
            crate::stability::Checker::new(*plant, crate::stability::Options::default())
                .unwrap()
                .state_matrix(wall)
                .complex_eigenvalues()
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max)
        };
        let (mut proved, mut refused) = (0, 0);
        for delta in [0.0, 0.1, 1.0, 10.0, 100.0] {
            for d in [0.0, 1.0, 2.7, 10.0] {
                let plant = Plant::new(delta, d).unwrap();
                let poly = PaperPoly::new(&plant);
                let a = super::super::alpha_max(plant, &AmaxOptions::default()).unwrap();
                for step in [1e-3, 1e-6, 1e-9, 0.0] {
                    let wall = Wall::new(a.alpha_max * (1.0 - step), a.beta_at_max).unwrap();
                    let rho = radius(&plant, &wall);
                    if paper_clearly_inside(&poly, &wall) {
                        proved += 1;
                        assert!(rho < 1.0 - CLEARLY_INSIDE, "{delta} {d} {step}: {rho}");
                    } else {
                        refused += 1;
                    }
                }
            }
        }
        // both outcomes occur: the walls 1e-3 below are proved, those on the boundary not
        assert!(proved >= 20 && refused >= 20, "{proved} {refused}");
    }

    /// The `f64` proof with its running rounding bound ([`schur::balls_inside`]) against
    /// independent verdicts on a few thousand walls of the paper's loop (delta 0 to 100, d 0
    /// to 20, both ends included): walls a relative `1e-12` to `1e-1` below the optimum (roots
    /// from `1e-13` to `1e-2` inside the circle), walls with a root placed by construction
    /// between `0.9e-8` inside the circle and `1e-9` outside it (solving `alpha QA(z) + beta
    /// QB(z) = -Q0(z)` at `z = rho e^{i theta}`), random walls, and walls of extreme
    /// stiffness. Where it proves every root `1e-8` inside, the interval recursion finds no
    /// root outside that circle, the checker calls the wall stable (not marginal), and no
    /// root was placed within `0.9e-8` of the circle; and it proves most walls that the
    /// interval recursion proves (else it would only add cost).
    #[test]
    fn balls_prove_only_what_holds() {
        use crate::enclosure::{interval::Interval, schur};
        use crate::poly::Complex;
        use crate::stability::{Checker, Options, Verdict};
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let r = 1.0 - CLEARLY_INSIDE;
        let (mut cheap, mut interval, mut both, mut placed) = (0, 0, 0, 0);
        for case in 0..3000 {
            let delta = match case % 5 {
                0 => 0.0,
                1 => 100.0,
                _ => 10f64.powf(uniform() * 5.0 - 3.0),
            };
            let d = match case % 7 {
                0 => 0.0,
                1 => 20.0,
                2 => (uniform() * 20.0).floor(),
                _ => uniform() * 20.0,
            };
            let plant = Plant::new(delta, d).unwrap();
            let poly = PaperPoly::new(&plant);
            let enclosure = certify::Enclosure::new(&poly);
            let a = super::super::alpha_max(plant, &AmaxOptions::default()).unwrap();
            let kind = (case / 35) % 4;
            let (alpha, beta) = match kind {
                0 => (
                    a.alpha_max * (1.0 - 10f64.powf(-1.0 - 11.0 * uniform())),
                    a.beta_at_max,
                ),
                1 => {
                    // a root at rho e^{i theta}, rho from 1 - 0.9e-8 to 1 + 1e-9
                    let rho = 1.0 - 0.9e-8 + 1e-8 * uniform();
                    let z = Complex::from_polar(rho, 0.01 + 3.13 * uniform());
                    let at = |c: &dyn Fn(usize) -> f64| {
                        (0..=poly.degree())
                            .rev()
                            .fold(Complex::new(0.0, 0.0), |v, i| v * z + c(i))
                    };
                    let (qa, qb, q0) = (
                        at(&|i| poly.qa(i)),
                        at(&|i| poly.qb(i)),
                        at(&|i| poly.q0(i)),
                    );
                    let det = qa.re * qb.im - qa.im * qb.re;
                    (
                        (-q0.re * qb.im + q0.im * qb.re) / det,
                        (-qa.re * q0.im + qa.im * q0.re) / det,
                    )
                }
                2 => (
                    a.alpha_max * (2.0 * uniform() - 0.5),
                    a.beta_at_max * (3.0 * uniform() - 1.0) + uniform() - 0.5,
                ),
                _ => {
                    let big = |u: f64, s: f64| s * 10f64.powf(600.0 * u - 300.0);
                    let (u, v, s, t) = (uniform(), uniform(), uniform(), uniform());
                    (
                        big(u, if s < 0.5 { -1.0 } else { 1.0 }),
                        big(v, if t < 0.5 { -1.0 } else { 1.0 }),
                    )
                }
            };
            let Ok(wall) = Wall::new(alpha, beta) else {
                continue;
            };
            let proved = schur_cohn::with_two_rows(poly.degree() + 1, |q, e| {
                poly.coefficients_into(&wall, q);
                schur::balls_inside(q, e, enclosure.max_error(&wall), r)
            });
            let mut q = vec![0.0; poly.degree() + 1];
            let mut e = q.clone();
            poly.coefficients_into(&wall, &mut q);
            enclosure.errors_into(&wall, &mut e);
            let boxed: Vec<Interval> = q
                .iter()
                .zip(&e)
                .map(|(&c, &r)| Interval::from_ball(c, r))
                .collect();
            let scaled = schur::scaled(&boxed, Interval::point(r));
            let by_intervals = schur::all_inside(scaled.clone());
            interval += usize::from(by_intervals && kind != 3);
            if kind == 1 {
                placed += 1;
                assert!(!proved, "{delta} {d} {wall:?}: a root placed within 0.9e-8");
            }
            if !proved {
                continue;
            }
            cheap += usize::from(kind != 3);
            both += usize::from(by_intervals && kind != 3);
            let count = schur::recursion(&scaled);
            assert!(
                count.outside.unwrap_or(0) == 0 && count.first_greater.is_none(),
                "{delta} {d} {wall:?}: {count:?}"
            );
            let checker = Checker::new(plant, Options::default()).unwrap();
            if let Ok((decision, radius)) = checker.decide_with_marginal_radius(&wall) {
                assert!(
                    decision.verdict == Verdict::Stable && radius.is_none(),
                    "{delta} {d} {wall:?}: {decision:?}"
                );
            }
        }
        // the placed roots were tried, the proofs are many, and most of the interval
        // recursion's proofs are also found by the f64 one (its one radius for a whole row
        // is wider on rows whose coefficients differ much in size: on walls near the
        // boundary at the larger delays the interval recursion still decides)
        assert!(placed >= 500 && cheap >= 300, "{placed} {cheap} {interval}");
        assert!(both as f64 >= 0.6 * interval as f64, "{both} of {interval}");
    }
}
