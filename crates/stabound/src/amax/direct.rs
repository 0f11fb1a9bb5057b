//! The direct search for the rightmost point of the stable region (`alpha_max`, see the
//! [`super`] module documentation for the method) on a [`Decomposition`], written once for
//! every loop; the stable set on a line of constant `beta` or `alpha` reads the same curve
//! through [`crate::curve::line_crossings`].

use std::f64::consts::PI;

use super::{AmaxKind, AmaxOptions};
use crate::curve::{CROSSING_THETA_TOL, CurvePoint, Decomposition, Free};
use crate::params::Wall;
use crate::roots::{brent, brent_from};
use crate::stability::schur_cohn;

/// A candidate for the rightmost point of the stable region.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub(super) alpha: f64,
    pub(super) beta: f64,
    pub(super) kind: AmaxKind,
    pub(super) theta: f64,
}

/// The rightmost point of the stable region of `dec` within the beta limits of `opts`, or
/// `None` if no candidate has stable walls next to it (see the [`super`] module
/// documentation: scan, Brent's method on the exact derivative and on the distances to the
/// lines, candidates confirmed by their stable neighbours, largest first).
///
/// On a loop's curve the self-crossings are looked for last, and only above the largest
/// other candidate the nearest neighbours confirm: the candidates are tried largest first
/// and the first confirmed is the answer, so a crossing below it is never tried. Only the
/// segments of the scanned polyline that reach that far right inside the necessary
/// conditions of stability are swept ([`reaching`]): ordinarily a few around the region's
/// rightmost point, where the curve's far stretches (which run off to large stiffnesses
/// near `theta = pi`) lie outside those conditions. The answer is the one the search over
/// every crossing gives.
pub(super) fn rightmost(dec: &impl Decomposition, opts: &AmaxOptions) -> Option<Candidate> {
    // the linear necessary conditions of stability on a loop's curve, for its brackets, the
    // sweep of its self-crossings and the candidates above the answer (computed once)
    let necessary = if dec.self_intersections() {
        necessary_conditions(dec)
    } else {
        None
    };
    // (the paper's curve, or a loop's without the conditions: no filter, compiled away)
    let scan = match necessary.map(Necessary::new) {
        Some(n) => candidates(dec, opts, &n),
        None => candidates(dec, opts, &()),
    };
    let bmin = opts.beta_min().unwrap_or(f64::NEG_INFINITY);
    let bmax = opts.beta_max().unwrap_or(f64::INFINITY);
    // The nearest neighbours first; the farther ones only when no candidate has a stable
    // neighbour that near (see `has_stable_left_neighbour` for why that can happen). The
    // coefficient buffer is sized from the degree: zeroing all of `MAX_COEFFS` per call was
    // a twentieth of a short delay's `alpha_max`.
    let near = |c: &Candidate, step: f64, buf: &mut [f64]| {
        has_stable_left_neighbour(dec, c, step, bmin, bmax, buf)
    };
    // A region far longer in one coordinate than in the other (a thin sliver along a line
    // through the origin, as behind a filter with a pole near z = 1, where `QB` is tiny and
    // the walls' dampings a million times their stiffnesses), or a wedge narrower than the
    // neighbours' diagonals: the neighbours above, a step relative to the candidate's whole
    // size away, leave it. Each coordinate's own relative step then, on the line just left
    // of the candidate.
    let fan = |c: &Candidate, step: f64, buf: &mut [f64]| {
        has_stable_scaled_neighbour(dec, c, step, bmin, bmax, buf)
    };
    let wedge = |c: &Candidate, step: f64| has_stable_wall_left(dec, c, step, bmin, bmax);
    // A loop's answer must have a clearly stable wall beside it (not only walls whose roots
    // are within rounding of the circle, as at a tip near a double root at `z = 1`).
    let clear = |c: &Candidate| clearly_stable_near(dec, c.alpha, c.beta, bmin, bmax);
    crate::stability::schur_cohn::with_scratch(dec.degree() + 1, |buf| {
        if !dec.self_intersections() {
            // the paper's curve: the neighbours alone, as they always confirmed its results
            let cands = scan.into_sorted(Vec::new());
            return NEIGHBOUR_STEPS
                .into_iter()
                .find_map(|step| cands.iter().find(|c| near(c, step, buf)).copied())
                .or_else(|| {
                    // the last resort, one line search per candidate: every damping within
                    // reach
                    NEIGHBOUR_STEPS
                        .into_iter()
                        .find_map(|step| cands.iter().find(|c| wedge(c, step)).copied())
                });
        }
        // A loop's curve: each candidate by both neighbour tests before the next, lower one
        // (a wedge's tip is confirmed before a crossing inside the wedge).
        let step = NEIGHBOUR_STEPS[0];
        let others = scan.sorted(scan.found.clone());
        let mut confirm = |c: &Candidate, step: f64| near(c, step, buf) || fan(c, step, buf);
        // A candidate that violates the necessary conditions beyond their slack has no
        // stable neighbour at the nearest step: passed over without its 24 tests (a spike
        // of the curve towards a zero of `QB` on the circle, behind a second-order filter).
        let within = |c: &&Candidate| may_be_stable_near(necessary.as_ref(), c);
        // The answer at the nearest step and the candidates above it that failed it.
        let (answer, mut above) =
            if let Some(best) = others.iter().filter(within).find(|c| confirm(c, step)) {
                // Only the crossings listed before `best` can change the answer: those above it
                // and, at an equal `alpha` (exact: the order of equal keys), those above a
                // corner of the lines, which the search lists after the crossings.
                let lines = scan.found[scan.split..].iter().any(|c| c.same(best));
                let crossings: Vec<Candidate> = scan
                    .crossings(dec, best.alpha, necessary)
                    .into_iter()
                    .filter(|c| c.alpha > best.alpha || (c.alpha == best.alpha && lines))
                    .collect();
                let found = crossings
                    .iter()
                    .filter(within)
                    .find(|c| confirm(c, step))
                    .copied()
                    .unwrap_or(*best);
                (found, [others, crossings].concat())
            } else {
                // No other candidate confirmed at the nearest step: every crossing, and the
                // search over all of them as above (the others already failed the nearest step).
                let crossings = scan.crossings(dec, f64::NEG_INFINITY, necessary);
                if let Some(c) = crossings.iter().filter(within).find(|c| confirm(c, step)) {
                    (*c, [others, crossings].concat())
                } else {
                    let cands = scan.into_sorted(crossings);
                    let found = NEIGHBOUR_STEPS[1..]
                        .iter()
                        .find_map(|&step| cands.iter().find(|c| confirm(c, step)).copied())
                        .or_else(|| {
                            // the last resort, one line search per candidate: every damping
                            // within reach
                            NEIGHBOUR_STEPS
                                .into_iter()
                                .find_map(|step| cands.iter().find(|c| wedge(c, step)).copied())
                        });
                    return found.filter(|c| !stable_right_of(dec, c, buf) && clear(c));
                }
            };
        // A candidate above the answer whose neighbours at the farther step are stable and
        // lie right of the answer proves the answer is not the rightmost point: the tip of
        // a wedge whose edges leave it at slopes the nearest step's fans miss (behind a slow
        // second-order filter, edges about 110 and 225 times the tip's `|beta| / |alpha|`,
        // where the fan's directions 1 and 2 lie on the edges), with a lower crossing
        // confirmed at the nearest step. Every neighbour at the step `h` is within
        // `h (|alpha| + |beta|)` left of its candidate; the line search just left of a
        // crossing (a wedge's tip) too. Candidates that violate the necessary conditions of
        // stability there (far out on the curve) have no stable neighbour and are passed
        // over without a test.
        let coarse = NEIGHBOUR_STEPS[1];
        above.sort_by(|x, y| y.alpha.total_cmp(&x.alpha));
        let upgrade = above
            .iter()
            .filter(|c| {
                c.alpha - coarse * (c.alpha.abs() + c.beta.abs()) > answer.alpha
                    && may_be_stable_near(necessary.as_ref(), c)
            })
            .find(|c| confirm(c, coarse) || (c.kind == AmaxKind::CurveCorner && wedge(c, coarse)));
        let found = upgrade.copied().unwrap_or(answer);
        // Every wall right of the rightmost point is unstable: a stable wall a relative
        // step right of the answer at its damping disproves it (a point on the region's
        // lower edge whose neighbours confirmed it, as beside a sliver along a filter pole
        // 1e-7 from z = 1), and the traced boundary answers instead; so does an answer
        // whose stable neighbours are all marginal (roots within the marginal band).
        (!stable_right_of(dec, &found, buf) && clear(&found)).then_some(found)
    })
}

/// Relative distances (of `|alpha| + |beta|`) right of a candidate at which
/// [`stable_right_of`] looks for a stable wall. Every wall right of the region's rightmost
/// point is unstable, so any distance would do: `1e-6`, the neighbours' farther step, and
/// `1e-3`, where Schur-Cohn at radius 1 resolves walls whose roots crowd within `1e-7` of
/// `z = 1` (behind a filter pole that close it calls walls with eigenvalue radius
/// `1 - 1e-7` not stable `1e-6` away and stable `1e-3` away).
const RIGHT_STEPS: [f64; 2] = [1e-6, 1e-3];

/// Whether a wall right of the candidate at its damping ([`RIGHT_STEPS`]) is strictly
/// stable: then the candidate is not the rightmost point of the region.
fn stable_right_of(dec: &impl Decomposition, c: &Candidate, buf: &mut [f64]) -> bool {
    RIGHT_STEPS.into_iter().any(|step| {
        let right = Wall {
            alpha: c.alpha + step * (c.alpha.abs() + c.beta.abs()),
            beta: c.beta,
        };
        // Schur-Cohn first (ordinarily unstable, and cheap); a stable verdict must be
        // seconded by the roots themselves (companion eigenvalues) inside the library's
        // marginal band, as the recursion can call walls stable within rounding where the
        // roots crowd near the circle (no physical damping, a root near a double root at
        // z = 1): only a clearly stable wall disproves the answer
        let coeffs = dec.coefficients_into(&right, buf);
        schur_cohn(coeffs, 1.0).stable && roots_inside_band(coeffs)
    })
}

/// Whether the roots of `coeffs` (companion eigenvalues) are all inside the library's
/// marginal band, `|z| < 1 - DEFAULT_MARGIN`.
fn roots_inside_band(coeffs: &[f64]) -> bool {
    crate::roots::eigen::poly_roots(coeffs).is_ok_and(|roots| {
        roots
            .iter()
            .all(|z| z.norm() < 1.0 - crate::stability::DEFAULT_MARGIN)
    })
}

/// Whether `wall` is clearly stable: strictly stable by Schur-Cohn at radius 1, seconded by
/// the roots themselves (companion eigenvalues) all inside the library's marginal band (the
/// recursion can call a wall stable within rounding where the roots crowd near the circle,
/// and the library's own verdict calls such a wall marginal).
fn clearly_stable(dec: &impl Decomposition, wall: &Wall, buf: &mut [f64]) -> bool {
    let coeffs = dec.coefficients_into(wall, buf);
    schur_cohn(coeffs, 1.0).stable && roots_inside_band(coeffs)
}

/// Relative steps left of an answer at which [`clearly_stable_near`] looks for a clearly
/// stable wall on the line of constant stiffness: a wall a relative `1e-6` inside the
/// boundary can have its roots within the marginal band of the circle where the loop's
/// slow modes are lightly damped (a physical damping of `1e-3` behind a slow filter), so
/// farther lines, `1e-3` and halfway down, are tried too. A region that is only marginal
/// (walls that rounding calls stable near a double root at `z = 1`) has no clearly stable
/// wall on any of them.
const CLEAR_STEPS: [f64; 4] = [1e-6, 1e-3, 1e-2, 1e-1];

/// Whether a clearly stable wall ([`clearly_stable`]) with damping inside `[bmin, bmax]`
/// lies left of the wall `(alpha, beta)`: first the neighbours of the confirmations (a
/// relative step of [`NEIGHBOUR_STEPS`], farther first, in the plane's scale and in each
/// coordinate's own), then the middles of the stable pieces on the lines of constant
/// stiffness [`CLEAR_STEPS`] left of it. `false` says the stable walls near the answer are
/// at best marginal (every root within rounding of the circle): none can be recommended.
pub(super) fn clearly_stable_near(
    dec: &impl Decomposition,
    alpha: f64,
    beta: f64,
    bmin: f64,
    bmax: f64,
) -> bool {
    let near = wall_beside(
        dec,
        (alpha, beta),
        (bmin, bmax),
        NEIGHBOUR_STEPS.into_iter().rev(),
        clearly_stable,
    );
    near || CLEAR_STEPS.into_iter().any(|step| {
        // the dampings within the reach of the sliver test at this step
        let reach = SLIVER_REACH * step * alpha.abs().max(beta.abs());
        let (lo, hi) = ((beta - reach).max(bmin), (beta + reach).min(bmax));
        clearly_stable_on_line(dec, alpha - step * alpha.abs(), lo, hi).is_some()
    })
}

/// A clearly stable wall ([`clearly_stable`]) of stiffness `alpha` with its damping inside
/// `[bmin, bmax]`: the damping of the first stable piece on that line (by Schur-Cohn, each
/// piece decided at its middle) whose middle within the limits is clearly stable.
pub(super) fn clearly_stable_on_line(
    dec: &impl Decomposition,
    alpha: f64,
    bmin: f64,
    bmax: f64,
) -> Option<f64> {
    let set = stable_pieces_on(dec, alpha).ok()?;
    crate::stability::schur_cohn::with_scratch(dec.degree() + 1, |buf| {
        set.iter().find_map(|i| {
            let (a, b) = (i.lo.max(bmin), i.hi.min(bmax));
            // a piece running to infinity within the limits: a point a unit (or its own
            // size) inside its finite end
            let mid = match (a.is_finite(), b.is_finite()) {
                (true, true) => 0.5 * (a + b),
                (true, false) => a + 1.0 + a.abs(),
                (false, true) => b - 1.0 - b.abs(),
                (false, false) => 0.0,
            };
            let wall = Wall { alpha, beta: mid };
            (a < b && clearly_stable(dec, &wall, buf)).then_some(mid)
        })
    })
}

/// Whether the candidate satisfies the linear necessary conditions of stability
/// ([`necessary_conditions`]) within [`NECESSARY_SLACK`] of their size there, so that a wall
/// beside it can be stable (`true` without conditions).
fn may_be_stable_near(necessary: Option<&[(f64, f64, f64); 4]>, c: &Candidate) -> bool {
    let size = c.alpha.abs() + c.beta.abs();
    necessary.is_none_or(|conds| {
        conds.iter().all(|&(c0, u, v)| {
            let value = c0 + u * c.alpha + v * c.beta;
            let slack = NECESSARY_SLACK * (c0.abs() + (u.abs() + v.abs()) * size);
            value >= -slack || value.is_nan()
        })
    })
}

impl Candidate {
    /// The same candidate, bit for bit.
    fn same(&self, o: &Candidate) -> bool {
        self.alpha.to_bits() == o.alpha.to_bits()
            && self.beta.to_bits() == o.beta.to_bits()
            && self.theta.to_bits() == o.theta.to_bits()
            && self.kind == o.kind
    }
}

/// The candidates of one scan of the curve in the order they were found, with the place of
/// the curve's self-crossings among them (looked for on demand, [`Scan::crossings`]) and
/// the scanned polyline they are looked for on.
struct Scan {
    /// The smooth maxima, the corners with the lines and the beta limits, in the order
    /// found.
    found: Vec<Candidate>,
    /// Where the self-crossings go in that order: after the scan's candidates and the
    /// curve's end, before the lines' corners.
    split: usize,
    /// The scanned polyline, `None` points between branches (empty where the curve has no
    /// self-crossings).
    polyline: Vec<(f64, Option<CurvePoint>)>,
    /// A candidate must have `alpha` above this (`0` with a free integrator: the `z = 1`
    /// line bounds the region there).
    floor: f64,
    bmin: f64,
    bmax: f64,
}

impl Scan {
    /// `cands` without the candidates outside the region's reach (not finite, at or left of
    /// the floor, outside the beta limits), largest `alpha` first (a stable sort: equal
    /// values in the order found).
    fn sorted(&self, mut cands: Vec<Candidate>) -> Vec<Candidate> {
        let (floor, bmin, bmax) = (self.floor, self.bmin, self.bmax);
        cands.retain(|c| {
            c.alpha.is_finite()
                && c.alpha > floor
                && c.beta.is_finite()
                && c.beta >= bmin
                && c.beta <= bmax
        });
        cands.sort_by(|x, y| y.alpha.total_cmp(&x.alpha));
        cands
    }

    /// Every candidate, `crossings` in their place, as [`Scan::sorted`].
    fn into_sorted(mut self, crossings: Vec<Candidate>) -> Vec<Candidate> {
        let mut all = std::mem::take(&mut self.found);
        if !crossings.is_empty() {
            all.splice(self.split..self.split, crossings);
        }
        self.sorted(all)
    }

    /// The self-crossings of the curve with `alpha` at least `above`, as candidates (all of
    /// them for `-inf`), as [`Scan::sorted`], `necessary` the polynomial's
    /// [`necessary_conditions`].
    fn crossings(
        &self,
        dec: &impl Decomposition,
        above: f64,
        necessary: Option<[(f64, f64, f64); 4]>,
    ) -> Vec<Candidate> {
        let found = self_crossings(dec, &self.polyline, above, necessary)
            .into_iter()
            .map(|(theta, w)| Candidate {
                alpha: w.alpha,
                beta: w.beta,
                kind: AmaxKind::CurveCorner,
                theta,
            })
            .filter(|c| c.alpha >= above)
            .collect();
        self.sorted(found)
    }
}

/// Every candidate for the rightmost point of the stable region of `dec` within the beta
/// limits of `opts` but the curve's self-crossings: the smooth maxima of the curve, its
/// corners with the lines and the beta limits.
///
/// A bracket whose stretch of the curve violates one of the `necessary` conditions beyond
/// their slack throughout ([`Stretch::may_hold`]) is not searched: a candidate
/// there has no stable neighbour at any of the neighbours' steps (see [`NECESSARY_SLACK`]),
/// so none of the searches could confirm it. Such brackets are where the curve runs off to
/// infinity towards a zero of `QB` on the circle (a moving average's, a second-order
/// filter's): `d alpha / d theta` changes sign through the pole, and Brent's method
/// followed it outwards over a dozen evaluations or more.
fn candidates(dec: &impl Decomposition, opts: &AmaxOptions, necessary: &impl Stretch) -> Scan {
    let line = dec.line_minus_one();
    let tol = opts.theta_tol();
    let bmin = opts.beta_min().unwrap_or(f64::NEG_INFINITY);
    let bmax = opts.beta_max().unwrap_or(f64::INFINITY);

    let mut cands: Vec<Candidate> = Vec::with_capacity(16);
    let line_dist = |p: &CurvePoint| line.map(|(a, b, r)| a * p.alpha + b * p.beta - r);

    // Where `g` changes sign between two angles, Brent's method finds the angle and the
    // curve point there (the one root finder every candidate kind goes through).
    let search = |g: &dyn Fn(f64) -> f64, t0: f64, t1: f64| {
        let t = brent(g, t0, t1, tol);
        dec.eval(t).map(|q| (t, q))
    };
    // `search` between two scanned samples, unless their stretch violates a necessary
    // condition throughout (see above)
    let root =
        |g: &dyn Fn(f64) -> f64, (t0, p0): (f64, CurvePoint), (t1, p1): (f64, CurvePoint)| {
            if necessary.may_hold((t1 - t0).abs(), &p0, &p1) {
                search(g, t0, t1)
            } else {
                None
            }
        };
    let mut push = |kind: AmaxKind, found: Option<(f64, CurvePoint)>, beta: Option<f64>| {
        if let Some((theta, q)) = found {
            cands.push(Candidate {
                alpha: q.alpha,
                beta: beta.unwrap_or(q.beta),
                kind,
                theta,
            });
        }
    };
    let limits = [opts.beta_min(), opts.beta_max()];
    // Without a free integrator the z = +1 line is a vertical line off alpha = 0 (see its
    // corners below); with one it is alpha = 0, never the rightmost point of a region of
    // positive stiffnesses: no candidate at or left of it is kept ([`Scan::sorted`]).
    let floor = if dec.free_integrator() {
        0.0
    } else {
        f64::NEG_INFINITY
    };

    let mut prev: Option<(f64, CurvePoint)> = None;
    let mut last_theta: Option<f64> = None;
    // The scanned points only decide which grid intervals bracket a sign change; Brent's
    // method then evaluates the curve afresh, so how the scan got its points reaches a
    // candidate only through a sign taken within rounding of zero at a grid point.
    let mut visit = |th: f64, p: Option<CurvePoint>| {
        last_theta = Some(th);
        let Some(p) = p else {
            prev = None;
            return;
        };
        if let Some((th0, p0)) = prev {
            // Smooth maximum: d alpha / d theta goes from + to -.
            if p0.dalpha > 0.0 && p.dalpha <= 0.0 {
                let g = |t| dec.eval(t).map_or(f64::NAN, |q| q.dalpha);
                push(AmaxKind::Smooth, root(&g, (th0, p0), (th, p)), None);
            }
            // Corner with the z = -1 line.
            if let (Some(g0), Some(g1)) = (line_dist(&p0), line_dist(&p))
                && (g0 > 0.0) != (g1 > 0.0)
            {
                let g = |t| dec.eval(t).and_then(|q| line_dist(&q)).unwrap_or(f64::NAN);
                push(AmaxKind::MinusOneCorner, root(&g, (th0, p0), (th, p)), None);
            }
            // Crossings of the beta limits.
            for lim in limits.into_iter().flatten() {
                if (p0.beta > lim) != (p.beta > lim) {
                    let g = |t| dec.eval(t).map_or(f64::NAN, |q| q.beta - lim);
                    push(AmaxKind::BetaLimit, root(&g, (th0, p0), (th, p)), Some(lim));
                }
            }
        }
        prev = Some((th, p));
    };
    // the scanned polyline, `None` points between branches, kept when self-intersections
    // are looked for (the paper's curve keeps none)
    let polyline = if dec.self_intersections() {
        // a loop's curve: its scan with the turns between samples resolved
        let mut scanned: Vec<(f64, Option<CurvePoint>)> =
            Vec::with_capacity(64 * (dec.degree() + 1));
        dec.scan_into(&mut scanned);
        // a point at or left of the floor (its coordinates are finite) or outside the
        // necessary conditions is no candidate
        let unreachable = |p: &CurvePoint| p.alpha <= floor || !necessary.may_hold_at(p);
        let polyline = resolve_turns(dec, scanned, &unreachable);
        for &(th, p) in &polyline {
            visit(th, p);
        }
        polyline
    } else {
        dec.scan(&mut visit);
        Vec::new()
    };
    // The end of the curve on the z = -1 line (a double root at -1): for d = 0 and large
    // delta alpha grows all the way to theta = pi and the maximum sits there.
    if line.is_some()
        && let Some(q) = dec.eval_end()
    {
        push(AmaxKind::MinusOneCorner, Some((PI, q)), None);
        for lim in limits.into_iter().flatten() {
            // The curve's last stretch may cross a beta limit before pi: caught by the scan
            // only if a sample lies beyond; close the gap between the last sample and pi.
            let Some(t0) = last_theta else { break };
            if let Some(p0) = dec.eval(t0)
                && (p0.beta > lim) != (q.beta > lim)
            {
                let g = |t| dec.eval_or_end(t).map_or(f64::NAN, |q| q.beta - lim);
                push(AmaxKind::BetaLimit, search(&g, t0, PI), Some(lim));
            }
        }
    }
    // Where two branches of the curve meet: looked for later, listed here.
    let split = cands.len();
    // The z = -1 line meets the beta limits.
    if let Some((a, b, r)) = line {
        for lim in limits.into_iter().flatten() {
            cands.push(Candidate {
                alpha: (r - b * lim) / a,
                beta: lim,
                kind: AmaxKind::BetaLimit,
                theta: PI,
            });
        }
    }
    // Without a free integrator the z = +1 line is a vertical line off alpha = 0: its
    // corners with the z = -1 line and the beta limits.
    if !dec.free_integrator()
        && let Some(a1) = dec.alpha_plus_one()
    {
        let mut betas: Vec<f64> = limits.into_iter().flatten().collect();
        if let Some((a, b, r)) = line {
            betas.push((r - a * a1) / b);
        }
        for beta in betas {
            cands.push(Candidate {
                alpha: a1,
                beta,
                kind: AmaxKind::BetaLimit,
                theta: 0.0,
            });
        }
    }

    Scan {
        found: cands,
        split,
        polyline,
        floor,
        bmin,
        bmax,
    }
}

/// Halvings of a scan interval at most, in [`resolve_turns`]: `2^-30` of a grid step, far
/// below any feature the curve's double-precision evaluation resolves in `theta`.
const TURN_DEPTH: u32 = 30;

/// Chords shorter than this, relative to their ends' size, are not split by
/// [`resolve_turns`]: `1e-10`, a million roundings, above the noise of the curve's
/// evaluation where its points crowd together (near `z = 1`).
const TURN_CHORD: f64 = 1e-10;

/// Samples [`resolve_turns`] adds at most, per scanned sample: it bounds the cost where
/// many intervals turn (each halving evaluates the curve once).
const TURN_BUDGET: usize = 1;

/// How far out, relative to the larger of its scanned ends, a turning interval's two ends
/// must both lie, where neither can be a candidate, for [`resolve_turns`] to follow its
/// remaining halvings by the determinant's sign ([`across_pole`]) instead of curve points:
/// `1e3`.
///
/// Such an interval holds a pole of the curve (a zero of the Cramer determinant on the
/// circle, behind a moving average or a second-order filter): the chord across it points
/// against both tangents at every depth, and each halving adds a point about twice as far
/// out along the pole's asymptote, one curve evaluation each, all the way to [`TURN_DEPTH`]
/// (thirty points out to `1e11` times the scan's size, with the brackets and segments they
/// make). The points within this factor, where the curve's wedges next to the pole have
/// their tips, are placed as before. Past it only the last interval's two ends are: the
/// chord between them stands in for the asymptote, and a branch that crosses the asymptote
/// meets it there (a point of that branch near the pole's stretches, which
/// [`crossing_of`] keeps where it finds no crossing of the curve itself; it moves with the
/// chord's ends, so they stay the ones the halvings reach). The points left out
/// lie between those ends and the first far ones, each nearer the pole than the end on its
/// side, so farther out along the asymptote: left of the floor or outside the necessary
/// conditions of stability like the ends (a linear condition violated along a ray stays
/// violated farther out, by a margin growing as its slack does), so no candidate on their
/// segments or brackets can be confirmed.
const POLE_FAR: f64 = 1e3;

/// The scan with samples added where the curve turns back between two samples: where the
/// chord between neighbouring samples points against the curve's exact tangent at either
/// end (a negative dot product), the curve went out and came back between them (a
/// resonance narrower than the grid, an excursion near a near-zero of the Cramer
/// determinant), and the interval is halved until it does not, at most [`TURN_DEPTH`]
/// times (towards a pole of the curve, past [`POLE_FAR`], by the determinant's sign).
/// Ordinary smooth stretches and extrema (whose tangents both follow the chord) are left
/// alone, so the scan's cost grows only where its samples missed a piece of the curve.
/// `unreachable` says of a point that no candidate there can be confirmed.
fn resolve_turns(
    dec: &impl Decomposition,
    scanned: Vec<(f64, Option<CurvePoint>)>,
    unreachable: &dyn Fn(&CurvePoint) -> bool,
) -> Vec<(f64, Option<CurvePoint>)> {
    fn turns(p: &CurvePoint, q: &CurvePoint) -> bool {
        let (da, db) = (q.alpha - p.alpha, q.beta - p.beta);
        // The chord against a tangent first: ordinarily neither is, and the chord's size is
        // not needed (both tests are pure, so their order does not change the verdict).
        if !(da * p.dalpha + db * p.dbeta < 0.0 || da * q.dalpha + db * q.dbeta < 0.0) {
            return false;
        }
        // a chord within rounding of the points' size is noise, not a turn (near z = 1,
        // where the curve's points are the same to the last few digits)
        let size = p.alpha.abs() + p.beta.abs() + q.alpha.abs() + q.beta.abs();
        da.abs() + db.abs() > TURN_CHORD * size
    }
    fn size(p: &CurvePoint) -> f64 {
        p.alpha.abs() + p.beta.abs()
    }
    // Halves the turning interval `a`, `b`; `far` the size past which two ends that can
    // hold no candidate are followed to the pole by the determinant (see [`POLE_FAR`]).
    #[allow(clippy::too_many_arguments)]
    fn split(
        dec: &impl Decomposition,
        a: (f64, CurvePoint),
        b: (f64, CurvePoint),
        depth: u32,
        far: f64,
        unreachable: &dyn Fn(&CurvePoint) -> bool,
        out: &mut Vec<(f64, Option<CurvePoint>)>,
        budget: &mut usize,
    ) {
        if depth == 0 || *budget == 0 || !turns(&a.1, &b.1) {
            return;
        }
        if size(&a.1) > far
            && size(&b.1) > far
            && unreachable(&a.1)
            && unreachable(&b.1)
            && let Some((lo, hi)) = across_pole(dec, a.0, b.0, depth, budget)
        {
            // the last interval's ends the halvings added, evaluated as they would have been
            for t in [lo, hi] {
                // exact: an end no halving moved is the caller's angle, bit for bit
                if t != a.0 && t != b.0 {
                    let Some(m) = dec.eval(t) else { return };
                    out.push((t, Some(m)));
                }
            }
            return;
        }
        *budget -= 1;
        let t = 0.5 * (a.0 + b.0);
        let Some(m) = dec.eval(t) else { return };
        split(dec, a, (t, m), depth - 1, far, unreachable, out, budget);
        out.push((t, Some(m)));
        split(dec, (t, m), b, depth - 1, far, unreachable, out, budget);
    }
    // The intervals that turn, resolved in the order of their chords' size relative to
    // their ends' (largest first), so that where rounding makes many tiny intervals look
    // like turns (near `z = 1`, where the curve's points agree to nine digits and their
    // tangents are noise) they cannot spend the budget before a turn of the curve itself.
    // Where the budget suffices the order does not matter: each interval's samples depend on
    // it alone.
    let chord = |p: &CurvePoint, q: &CurvePoint| {
        let size = p.alpha.abs() + p.beta.abs() + q.alpha.abs() + q.beta.abs();
        ((q.alpha - p.alpha).abs() + (q.beta - p.beta).abs()) / size
    };
    let mut turning: Vec<(usize, f64)> = Vec::new();
    for i in 1..scanned.len() {
        if let ((_, Some(p0)), (_, Some(p1))) = (scanned[i - 1], scanned[i])
            && turns(&p0, &p1)
        {
            turning.push((i, chord(&p0, &p1)));
        }
    }
    // most scans have none, and are returned as they are
    if turning.is_empty() {
        return scanned;
    }
    let mut order: Vec<usize> = (0..turning.len()).collect();
    // a NaN size (an overflow) sorts first: resolved before the noise
    order.sort_by(|&a, &b| turning[b].1.total_cmp(&turning[a].1));
    let mut budget = TURN_BUDGET * scanned.len();
    let mut added: Vec<Vec<(f64, Option<CurvePoint>)>> = vec![Vec::new(); turning.len()];
    for k in order {
        let i = turning[k].0;
        if let ((t0, Some(p0)), (th, Some(p1))) = (scanned[i - 1], scanned[i]) {
            let far = POLE_FAR * size(&p0).max(size(&p1));
            split(
                dec,
                (t0, p0),
                (th, p1),
                TURN_DEPTH,
                far,
                unreachable,
                &mut added[k],
                &mut budget,
            );
        }
    }
    let mut out = Vec::with_capacity(scanned.len() + added.iter().map(Vec::len).sum::<usize>());
    let mut next = turning.iter().map(|t| t.0).zip(added).peekable();
    for (i, sample) in scanned.into_iter().enumerate() {
        if let Some((_, between)) = next.next_if(|(at, _)| *at == i) {
            out.extend(between);
        }
        out.push(sample);
    }
    out
}

/// The interval around a pole of the curve between `a` and `b` that `depth` halvings toward
/// it end on (each halving spending one of `budget`, as [`resolve_turns`] spends it), with
/// the sides taken from the sign of the Cramer determinant alone
/// ([`Decomposition::determinant`], a few Horner steps against a curve point's
/// derivatives and three solves); `None` where the determinant does not change sign
/// between `a` and `b` (no pole between them), and the halvings stop early where it is
/// singular, as [`Decomposition::eval`] there stops them.
///
/// Between two ends on either side of a pole the chord crosses it against both tangents,
/// and the half holding the pole turns again while the other half, both its ends on one
/// side of the asymptote, does not: the halvings follow the determinant's sign change.
fn across_pole(
    dec: &impl Decomposition,
    a: f64,
    b: f64,
    mut depth: u32,
    budget: &mut usize,
) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (a, b);
    let lo_side = dec.determinant(lo)? > 0.0;
    if (dec.determinant(hi)? > 0.0) == lo_side {
        return None;
    }
    while depth > 0 && *budget > 0 {
        *budget -= 1;
        depth -= 1;
        let t = 0.5 * (lo + hi);
        let Some(det) = dec.determinant(t) else { break };
        if (det > 0.0) == lo_side {
            lo = t;
        } else {
            hi = t;
        }
    }
    Some((lo, hi))
}

/// A segment of the scanned polyline: its end angles and points.
type Segment = ((f64, CurvePoint), (f64, CurvePoint));

/// The points where the curve crosses itself: crossings of the scanned polyline's
/// non-adjacent segments (a sweep over the segments sorted by their smallest `alpha`),
/// each refined by Newton's method on `P(t1) - P(t2) = 0` with the exact derivatives
/// (quadratic convergence from the polyline's crossing, which is within the chords' error).
/// Returns the angle of one branch and the wall. With `above` finite, only the segments
/// whose stretch of the curve can reach `alpha >= above` within the `necessary` conditions
/// of stability are swept ([`reaching`]): a
/// crossing lies on both of its branches.
fn self_crossings(
    dec: &impl Decomposition,
    polyline: &[(f64, Option<CurvePoint>)],
    above: f64,
    necessary: Option<[(f64, f64, f64); 4]>,
) -> Vec<(f64, Wall)> {
    let segs: Vec<Segment> = if above > f64::NEG_INFINITY || necessary.is_some() {
        reaching(polyline, above, necessary)
    } else {
        let mut segs = Vec::with_capacity(polyline.len());
        segs.extend(
            polyline
                .windows(2)
                .filter_map(|w| Some(((w[0].0, w[0].1?), (w[1].0, w[1].1?)))),
        );
        segs
    };
    // each segment's range of alpha (the sweep's keys) and of beta (to pass over pairs that
    // cannot meet before the crossing formula's divisions), side by side
    let ranges: Vec<SegmentRanges> = segs
        .iter()
        .map(|s| SegmentRanges {
            lo: s.0.1.alpha.min(s.1.1.alpha),
            hi: s.0.1.alpha.max(s.1.1.alpha),
            blo: s.0.1.beta.min(s.1.1.beta),
            bhi: s.0.1.beta.max(s.1.1.beta),
        })
        .collect();
    let order = run_merge_order(ranges.len(), |i| ranges[i].lo);
    let mut out = Vec::new();
    let mut active: Vec<usize> = Vec::with_capacity(segs.len());
    for i in order {
        let (s, here) = (&segs[i], &ranges[i]);
        let (start, blo, bhi) = (here.lo, here.blo, here.bhi);
        active.retain(|&j| ranges[j].hi >= start);
        for &j in &active {
            let (o, there) = (&segs[j], &ranges[j]);
            // adjacent segments share an end (the same angle, bit for bit)
            if s.0.0 == o.1.0 || s.1.0 == o.0.0 {
                continue;
            }
            // Disjoint ranges of beta: the segments do not meet. (The crossing formula then
            // gives a parameter outside [0, 1] for one of them unless its rounding errs by
            // the gap: the segments would touch within rounding, a crossing at a scanned
            // point that the segments sharing that point report.)
            if there.bhi < blo || there.blo > bhi {
                continue;
            }
            crossing_of(dec, s, o, &mut out);
        }
        active.push(i);
    }
    out
}

/// A segment's ranges of `alpha` and `beta` over its two ends.
struct SegmentRanges {
    lo: f64,
    hi: f64,
    blo: f64,
    bhi: f64,
}

/// The necessary conditions of Schur stability of `q = Q0 + alpha QA + beta QB` that are
/// linear in the wall, as `(c, u, v)` with `c + u alpha + v beta > 0` at every stable wall:
/// `q(1) > 0`, `(-1)^n q(-1) > 0` and `|q_0| < q_n` (Jury's necessary conditions for a
/// real polynomial of degree `n` with `q_n > 0`: `q(+-1)` and `q_0 / q_n` are `q_n` times
/// the products of `1 -+ r` and of the roots `r`; E. I. Jury, *Theory and Application of
/// the z-Transform Method*, 1964, section 3.4). Linear where the walls do not reach the
/// leading coefficient (`QA` and `QB` of lower degree than the monic `Q0`, exact zeros by
/// construction); `None` otherwise.
fn necessary_conditions(dec: &impl Decomposition) -> Option<[(f64, f64, f64); 4]> {
    let [q0, qa, qb] = dec.affine();
    let n = dec.degree();
    // exact: the leading coefficients of QA and QB are structural zeros
    if !(qa[n] == 0.0 && qb[n] == 0.0 && q0[n] > 0.0) {
        return None;
    }
    let at = |z: f64| {
        let value = |p: &[f64]| p.iter().rev().fold(0.0, |v, &c| v * z + c);
        let sign = if z < 0.0 && n % 2 == 1 { -1.0 } else { 1.0 };
        (sign * value(&q0), sign * value(&qa), sign * value(&qb))
    };
    Some([
        at(1.0),
        at(-1.0),
        (q0[n] - q0[0], -qa[0], -qb[0]),
        (q0[n] + q0[0], qa[0], qb[0]),
    ])
}

/// How far the necessary conditions may be violated at a crossing that a neighbour
/// confirms, relative to the conditions' size there: the neighbours of [`rightmost`] are at
/// most `16` relative steps of at most `1e-6` away in each coordinate (the fan's steepest
/// slope at the farther step), `1.6e-5`; `1e-4` leaves six times that for the crossing's
/// size beyond its segments' bound.
const NECESSARY_SLACK: f64 = 1e-4;

/// A linear function's bound over a stretch of the curve of width `w` in `theta` from its
/// ends' values and slopes (see [`reaching`] for why it holds on a smooth stretch).
fn bound(w: f64, fp: f64, fq: f64, dp: f64, dq: f64) -> f64 {
    fp.max(fq) + w * (dp.abs() + dq.abs())
}

/// The linear necessary conditions of stability ([`necessary_conditions`]) with each one's
/// `|c|` and `|u| + |v|`, the terms of its slack (computed once, not at every stretch), and
/// the condition violated last, tried first at the next stretch (see
/// [`Necessary::holds_on`]).
struct Necessary {
    conds: [(f64, f64, f64); 4],
    sizes: [(f64, f64); 4],
    first: std::cell::Cell<usize>,
}

/// Whether a stretch of the curve between two samples can satisfy the necessary conditions
/// of stability: [`Necessary`]'s test, or none (`()`, always: the paper's curve, whose
/// search has no use for them).
trait Stretch {
    /// Whether the stretch between the samples `p` and `q`, `w` apart in `theta`, can
    /// satisfy every condition within [`NECESSARY_SLACK`] of its size there.
    fn may_hold(&self, w: f64, p: &CurvePoint, q: &CurvePoint) -> bool;

    /// Whether the point `p` satisfies every condition within [`NECESSARY_SLACK`] of its
    /// size there (the test of [`may_be_stable_near`]).
    fn may_hold_at(&self, p: &CurvePoint) -> bool;
}

impl Stretch for () {
    fn may_hold(&self, _w: f64, _p: &CurvePoint, _q: &CurvePoint) -> bool {
        true
    }

    fn may_hold_at(&self, _p: &CurvePoint) -> bool {
        true
    }
}

impl Stretch for Necessary {
    fn may_hold(&self, w: f64, p: &CurvePoint, q: &CurvePoint) -> bool {
        let mut first = self.first.get();
        let holds = self.holds_on(w, p, q, &mut first);
        self.first.set(first);
        holds
    }

    fn may_hold_at(&self, p: &CurvePoint) -> bool {
        let c = Candidate {
            alpha: p.alpha,
            beta: p.beta,
            kind: AmaxKind::CurveCorner,
            theta: 0.0,
        };
        may_be_stable_near(Some(&self.conds), &c)
    }
}

impl Necessary {
    fn new(conds: [(f64, f64, f64); 4]) -> Self {
        let sizes = conds.map(|(c0, u, v)| (c0.abs(), u.abs() + v.abs()));
        Self {
            conds,
            sizes,
            first: std::cell::Cell::new(0),
        }
    }

    /// Whether the stretch of the curve between the samples `p` and `q`, `w` apart in
    /// `theta`, can satisfy every condition within [`NECESSARY_SLACK`] of its size there
    /// (by [`bound`]; a NaN bound, from an overflow, can). The first condition violated
    /// decides, tried from `first`, the one violated last (set to the one violated here):
    /// whether all hold does not depend on the order, and along the polyline the same one
    /// ordinarily fails over long stretches (`|q_0| < q_n` on the far ones).
    fn holds_on(&self, w: f64, p: &CurvePoint, q: &CurvePoint, first: &mut usize) -> bool {
        let size = bound(
            w,
            p.alpha.abs() + p.beta.abs(),
            q.alpha.abs() + q.beta.abs(),
            p.dalpha.abs() + p.dbeta.abs(),
            q.dalpha.abs() + q.dbeta.abs(),
        );
        for k in (*first..self.conds.len()).chain(0..*first) {
            let (c0, u, v) = self.conds[k];
            let (c_size, uv_size) = self.sizes[k];
            let slack = NECESSARY_SLACK * (c_size + uv_size * size);
            let most = bound(
                w,
                c0 + u * p.alpha + v * p.beta,
                c0 + u * q.alpha + v * q.beta,
                u * p.dalpha + v * p.dbeta,
                u * q.dalpha + v * q.dbeta,
            );
            if !(most >= -slack || most.is_nan()) {
                *first = k;
                return false;
            }
        }
        true
    }
}

/// The segments of `segs` (in the scan's order) within Newton's reach in [`refine`] (the
/// segment's angles widened by its width each way) of a segment whose stretch of the curve
/// can have `alpha >= above` while satisfying the necessary conditions of stability (within
/// [`NECESSARY_SLACK`]; a crossing outside them has no stable neighbour, so no neighbour
/// confirms it). A segment's bound on a linear function of the curve is its ends' larger
/// value plus the width times the sum of the ends' derivatives' sizes: a cubic through the
/// ends' values and slopes exceeds the larger end by at most `4/27` of that width times the
/// slopes' sum (the Hermite basis functions of the slopes are at most `4/27` in size), so
/// the margin is about seven times a smooth stretch's bulge between samples; a sharper turn
/// between samples is split by [`resolve_turns`] first. A crossing lies on both of its
/// branches, so both of its segments are kept; the segments kept are in their order in
/// `segs`, so the sweep finds their crossings in the same order as among all segments.
fn reaching(
    polyline: &[(f64, Option<CurvePoint>)],
    above: f64,
    necessary: Option<[(f64, f64, f64); 4]>,
) -> Vec<Segment> {
    let conds = Necessary::new(necessary.unwrap_or([(1.0, 0.0, 0.0); 4]));
    // Each segment (its start in `polyline`, its angles) and whether its stretch of the
    // curve can hold a confirmed crossing above `above` (a NaN bound, from an overflow,
    // keeps it).
    let mut live: Vec<(usize, f64, f64, bool)> = Vec::with_capacity(polyline.len());
    let mut first = 0;
    for (i, pair) in polyline.windows(2).enumerate() {
        let [(tp, Some(p)), (tq, Some(q))] = pair else {
            continue;
        };
        let w = (tq - tp).abs();
        let right = bound(w, p.alpha, q.alpha, p.dalpha, q.dalpha);
        let ok = (right >= above || right.is_nan()) && conds.holds_on(w, p, q, &mut first);
        live.push((i, *tp, *tq, ok));
    }
    let mut kept = Vec::with_capacity(live.len());
    // The nearest live segments before and after the one looked at (indices into `live`).
    // The segments follow each other in angle (their ends never decrease along `live`), so
    // a live segment overlaps `[a - w, b + w]` on one side exactly when the nearest one on
    // that side does.
    // (`live.len()` after: none; each search starts past the last one found)
    let mut before: Option<usize> = None;
    let mut after = 0;
    for (k, &(i, a, b, here)) in live.iter().enumerate() {
        if after <= k {
            after = live[k + 1..]
                .iter()
                .position(|l| l.3)
                .map_or(live.len(), |x| x + k + 1);
        }
        let w = b - a;
        let near = here
            || before.is_some_and(|x| live[x].2 >= a - w)
            || live.get(after).is_some_and(|l| l.1 <= b + w);
        if here {
            before = Some(k);
        }
        if near && let ((tp, Some(p)), (tq, Some(q))) = (polyline[i], polyline[i + 1]) {
            kept.push(((tp, p), (tq, q)));
        }
    }
    kept
}

/// The indices `0..n` in the order of a stable sort of their keys `key(i)` by
/// [`f64::total_cmp`] (ties in index order), by merging the natural runs of the sequence:
/// along a scanned polyline the segments' smallest `alpha` rises and falls in monotone
/// stretches, so a few runs hold all of them. Method: natural merge sort (D. E. Knuth,
/// *The Art of Computer Programming*, vol. 3, 2nd ed., 1998, section 5.2.4), strictly
/// descending runs reversed (which keeps it stable), adjacent runs merged pairwise, the left
/// one first on ties.
fn run_merge_order(n: usize, key: impl Fn(usize) -> f64) -> Vec<usize> {
    let less = |a: usize, b: usize| key(a).total_cmp(&key(b)).is_lt();
    let mut idx: Vec<usize> = Vec::with_capacity(n);
    // the runs' ends, and the merged runs' ends of the next pass (one buffer each, reused)
    let mut bounds = Vec::with_capacity(16);
    bounds.push(0);
    let mut i = 0;
    while i < n {
        let mut j = i + 1;
        if j < n && less(j, i) {
            while j < n && less(j, j - 1) {
                j += 1;
            }
            idx.extend((i..j).rev());
        } else {
            while j < n && !less(j, j - 1) {
                j += 1;
            }
            idx.extend(i..j);
        }
        bounds.push(j);
        i = j;
    }
    if bounds.len() <= 2 {
        return idx;
    }
    let mut buf = vec![0; n];
    let mut next = Vec::with_capacity(bounds.len());
    while bounds.len() > 2 {
        next.clear();
        next.push(0);
        for w in bounds.windows(3).step_by(2) {
            let (a, m, b) = (w[0], w[1], w[2]);
            let (mut l, mut r) = (a, m);
            for slot in &mut buf[a..b] {
                // the right run's element only when strictly smaller: stable
                if r < b && (l == m || less(idx[r], idx[l])) {
                    *slot = idx[r];
                    r += 1;
                } else {
                    *slot = idx[l];
                    l += 1;
                }
            }
            next.push(b);
        }
        // an odd run out stays as it is
        if bounds.len() % 2 == 0 {
            let (a, b) = (bounds[bounds.len() - 2], bounds[bounds.len() - 1]);
            buf[a..b].copy_from_slice(&idx[a..b]);
            next.push(b);
        }
        std::mem::swap(&mut idx, &mut buf);
        std::mem::swap(&mut bounds, &mut next);
    }
    idx
}

/// Where two segments cross: the angles interpolated at the crossing.
fn segment_crossing(s: &Segment, o: &Segment) -> Option<(f64, f64)> {
    let (p, q) = ((s.0.1.alpha, s.0.1.beta), (o.0.1.alpha, o.0.1.beta));
    let r = (s.1.1.alpha - p.0, s.1.1.beta - p.1);
    let v = (o.1.1.alpha - q.0, o.1.1.beta - q.1);
    let den = r.0 * v.1 - r.1 * v.0;
    // parallel segments (exactly: the formula below divides by it) do not cross at a point
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let w = (q.0 - p.0, q.1 - p.1);
    let t = (w.0 * v.1 - w.1 * v.0) / den;
    let u = (w.0 * r.1 - w.1 * r.0) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u))
        .then_some((s.0.0 + t * (s.1.0 - s.0.0), o.0.0 + u * (o.1.0 - o.0.0)))
}

/// How far a crossing found by [`refine`] may miss, relative to its two points' size
/// (`|alpha| + |beta|` of each): `1e-8`, the neighbours' nearest step
/// ([`NEIGHBOUR_STEPS`]), far above the rounding Newton's method leaves at a crossing it
/// converged to (its last steps are quadratic), and far below the features of a region its
/// neighbours resolve.
const CROSSING_RESIDUAL: f64 = 1e-8;

/// The crossing of the curve's stretches of the segments `s` and `o` near their chords'
/// crossing, pushed to `out` (nothing where the chords do not cross): [`refine`] from the
/// chords' crossing; where Newton's method does not converge there (a stretch bent far
/// from its chord, as beside a pole of the curve, where `theta` interpolated along the
/// chord is far from the angle of the curve's point there and the iterates leave the
/// bracket), the crossing by one coordinate of the plane ([`crossing_along`]). A pair with
/// no converged crossing either way gives Newton's iterate, as before: a point of one
/// branch near the other (beside a pole, where the chord across the pole stands in for its
/// asymptote, see [`POLE_FAR`]), which the neighbour tests take as any candidate.
fn crossing_of(dec: &impl Decomposition, s: &Segment, o: &Segment, out: &mut Vec<(f64, Wall)>) {
    let Some((found, converged)) =
        segment_crossing(s, o).and_then(|(t1, t2)| refine(dec, t1, t2, s, o))
    else {
        return;
    };
    // A stretch across a pole of the curve (the Cramer determinant of either sign at its
    // ends) is no function of a coordinate: its chord stands in for the pole's asymptote
    // and keeps Newton's iterate (two determinants, where Brent's method along a coordinate
    // would follow the pole outwards over dozens of points).
    let across = |seg: &Segment| {
        matches!(
            (dec.determinant(seg.0.0), dec.determinant(seg.1.0)),
            (Some(a), Some(b)) if (a > 0.0) != (b > 0.0)
        )
    };
    let along = |x: Coordinate| crossing_along(dec, s, o, x);
    out.push(if converged || across(s) || across(o) {
        found
    } else {
        along(Coordinate::Alpha)
            .or_else(|| along(Coordinate::Beta))
            .unwrap_or(found)
    });
}

/// A coordinate of the `(alpha, beta)` plane: its value and its derivative along the curve
/// at a point.
#[derive(Clone, Copy)]
enum Coordinate {
    Alpha,
    Beta,
}

impl Coordinate {
    /// The value and the derivative along `theta` of this coordinate at `p`, and the other
    /// coordinate's value.
    fn of(self, p: &CurvePoint) -> (f64, f64, f64) {
        match self {
            Coordinate::Alpha => (p.alpha, p.dalpha, p.beta),
            Coordinate::Beta => (p.beta, p.dbeta, p.alpha),
        }
    }
}

/// The crossing of the curve's stretches of the segments `s` and `o` found by one
/// coordinate `x` of the plane where each stretch is monotone in it (its derivative of one
/// sign at both ends): the other coordinate of each stretch is a function of `x` (the
/// stretch's angle where it has that `x`, by Brent's method in `theta`), and their
/// difference changes sign over the range of `x` both stretches cover exactly where they
/// cross (Brent's method along the stretch bent more, in its angle); the crossing then
/// polished by [`refine`]. `None` where
/// a stretch is not monotone in `x` at its ends, the difference does not change sign, or
/// the point found is not a crossing within [`CROSSING_RESIDUAL`] (a stretch across a pole
/// of the curve, whose coordinate jumps from one infinity to the other).
///
/// Brent's method is bracketed, so it finds the crossing however far the stretch bends
/// from its chord in `theta`: beside a pole the curve runs off as `1 / (theta - theta_p)`
/// and Newton's method in `theta` from the chords' crossing leaves its bracket, while the
/// stretch is monotone in both coordinates there.
fn crossing_along(
    dec: &impl Decomposition,
    s: &Segment,
    o: &Segment,
    x: Coordinate,
) -> Option<(f64, Wall)> {
    // the stretch's ends in `x`, with their angles, `None` unless monotone at its ends (exact
    // comparisons: a zero derivative has no sign, and equal ends no range of `x`)
    let ends = |seg: &Segment| -> Option<Ends> {
        let ((ta, pa), (tb, pb)) = (seg.0, seg.1);
        let ((xa, da, _), (xb, db, _)) = (x.of(&pa), x.of(&pb));
        ((da > 0.0) == (db > 0.0) && da != 0.0 && db != 0.0 && xa != xb).then_some(if xa < xb {
            ((xa, ta), (xb, tb))
        } else {
            ((xb, tb), (xa, ta))
        })
    };
    let (es, eo) = (ends(s)?, ends(o)?);
    let (lo, hi) = (es.0.0.max(eo.0.0), es.1.0.min(eo.1.0));
    if lo >= hi || lo.is_nan() || hi.is_nan() {
        return None;
    }
    // The angle of the stretch `e` where it has the coordinate `v` and the point there,
    // from the angle `start` (see [`angle_at`]).
    let angle = |e: Ends, v: f64, start: Option<f64>| angle_at(dec, x, e, v, start);
    // The stretch bent more (the larger ratio of its ends' derivatives in `x`, the one
    // beside a pole) is walked in `theta`, the other solved for its `x` at each step: Brent's
    // method in `theta` on a nearly straight stretch converges in a few steps, on the bent
    // one in dozens.
    let bent = |seg: &Segment| {
        let (a, b) = (x.of(&seg.0.1).1.abs(), x.of(&seg.1.1).1.abs());
        a.max(b) / a.min(b)
    };
    let swapped = bent(s) > bent(o);
    let (walked, solved) = if swapped { (es, eo) } else { (eo, es) };
    // the other coordinate's difference between the solved and the walked stretch at the
    // walked one's angle `t`
    // (each solve starts from the angle the last one found: the outer search's steps move
    // the walked point less and less, so Newton's method needs a step or two; every pair of
    // points found is kept, so the one at the angle the search returns is not solved again)
    let mut last: Option<f64> = None;
    let mut pairs: Vec<(f64, CurvePoint, (f64, CurvePoint))> = Vec::with_capacity(16);
    let mut gap = |t: f64| {
        let Some(p) = dec.eval(t) else {
            return f64::NAN;
        };
        let (v, _, other) = x.of(&p);
        match angle(solved, v, last) {
            Some((tq, q)) => {
                last = Some(tq);
                pairs.push((t, p, (tq, q)));
                x.of(&q).2 - other
            }
            None => f64::NAN,
        }
    };
    let (ta, tb) = (angle(walked, lo, None)?.0, angle(walked, hi, None)?.0);
    let (g_a, g_b) = (gap(ta), gap(tb));
    if !(g_a.is_finite() && g_b.is_finite() && (g_a > 0.0) != (g_b > 0.0)) {
        return None;
    }
    let t = brent_from(&mut gap, (ta, g_a), (tb, g_b), CROSSING_THETA_TOL);
    // exact: the search returns one of the angles it evaluated, bit for bit
    let (p, (tq, q)) = match pairs.iter().rev().find(|e| e.0 == t) {
        Some(&(_, p, found)) => (p, found),
        None => {
            let p = dec.eval(t)?;
            (p, angle(solved, x.of(&p).0, last)?)
        }
    };
    let ((t1, p1), (t2, p2)) = if swapped {
        ((t, p), (tq, q))
    } else {
        ((tq, q), (t, p))
    };
    // polished by Newton's method from there (quadratic from so near), else the point as
    // found where it is a crossing to the residual
    match refine(dec, t1, t2, s, o)? {
        (found, true) => Some(found),
        _ => meet(&p1, &p2).then_some((
            t1,
            Wall {
                alpha: p1.alpha,
                beta: p1.beta,
            },
        )),
    }
}

/// A stretch's ends ordered by a coordinate `x`: `((x_lo, theta_lo), (x_hi, theta_hi))`.
type Ends = ((f64, f64), (f64, f64));

/// Width of a bracket, in Brent's tolerances, within which [`angle_at`] takes its iterate
/// for the root when Newton's steps stop contracting: `16`, about `1e-14` in `theta`, where
/// the curve's coordinate is evaluated to a few roundings of its size and its steps wander
/// by that over the derivative (`3e-15` on the stretches beside a Butterworth filter's
/// pole); a start left of the root by more than that has a bracket as wide as its step.
const ANGLE_ROUNDING: f64 = 16.0;

/// Newton steps [`angle_at`] takes at most before Brent's method: from the last solve's
/// angle on a nearly straight stretch two or three reach rounding (quadratic convergence);
/// more means the start was far, and the bracketed solve is as quick.
const ANGLE_NEWTON_STEPS: usize = 6;

/// The angle of the stretch with the ends `e` (monotone in `x` at its ends) where it has the
/// coordinate `v`, and the curve's point there; `None` where the point found misses `v` by
/// more than [`CROSSING_RESIDUAL`] of its size (a pole of the curve between the ends, where
/// the coordinate changes sign through infinity) or the curve has no point there.
///
/// Newton's method in `theta` from `start` (else the chord's angle at `v`), safeguarded as
/// in `rtsafe` (W. H. Press et al., *Numerical Recipes*, 3rd ed., 2007, section 9.4): the
/// sign of `x - v` at each iterate narrows the bracket of the ends, and a step that leaves
/// it, or is not at most half the one before (no contraction), hands the narrowed bracket to
/// Brent's method, as does `v` outside the ends' range. Converged at a step within Brent's
/// own tolerance ([`CROSSING_THETA_TOL`] and two roundings of `theta`).
fn angle_at(
    dec: &impl Decomposition,
    x: Coordinate,
    e: Ends,
    v: f64,
    start: Option<f64>,
) -> Option<(f64, CurvePoint)> {
    let ((x_lo, t_lo), (x_hi, t_hi)) = e;
    let found = |t: f64, p: CurvePoint| {
        let miss = (x.of(&p).0 - v).abs();
        (miss <= CROSSING_RESIDUAL * (p.alpha.abs() + p.beta.abs())).then_some((t, p))
    };
    // the angles where `x - v` is below and above zero (by the ends' samples)
    let (mut below, mut above) = (t_lo, t_hi);
    let inside = |t: f64, a: f64, b: f64| t > a.min(b) && t < a.max(b);
    if v.is_nan() {
        return None;
    }
    {
        // (`v` outside the ends' range by rounding, as at the other stretch's end: the
        // nearer end, where the first step is within rounding too)
        let along = ((v - x_lo) / (x_hi - x_lo)).clamp(0.0, 1.0);
        let chord = t_lo + along * (t_hi - t_lo);
        let mut t = start.filter(|&t| inside(t, t_lo, t_hi)).unwrap_or(chord);
        let mut last = (t_hi - t_lo).abs();
        for _ in 0..ANGLE_NEWTON_STEPS {
            let Some(p) = dec.eval(t) else { break };
            let (xv, dx, _) = x.of(&p);
            let g = xv - v;
            // exact: a root to the last bit ends the search, as in Brent's method
            if g == 0.0 {
                return found(t, p);
            }
            if g < 0.0 {
                below = t;
            } else {
                above = t;
            }
            let step = -g / dx;
            // Brent's own tolerance
            let tol = 2.0 * f64::EPSILON * t.abs() + 0.5 * CROSSING_THETA_TOL;
            if step.abs() <= tol {
                return found(t, p);
            }
            let next = t + step;
            // (a NaN step, from a zero or overflowed derivative, fails both)
            if !(inside(next, below, above) && step.abs() <= 0.5 * last) {
                // A sign change within a few of Brent's tolerances: the steps are at the
                // rounding of the curve's evaluation (its coordinate's error over its
                // derivative), where Brent's method on that bracket would return a point
                // inside it: the iterate, an end of it, is the root as closely.
                if (above - below).abs() <= ANGLE_ROUNDING * tol {
                    return found(t, p);
                }
                break;
            }
            last = step.abs();
            t = next;
        }
    }
    let g = |t: f64| dec.eval(t).map_or(f64::NAN, |p| x.of(&p).0 - v);
    let t = brent(g, below, above, CROSSING_THETA_TOL);
    found(t, dec.eval(t)?)
}

/// Whether two points of the curve are one wall to [`CROSSING_RESIDUAL`] of their size.
fn meet(p: &CurvePoint, q: &CurvePoint) -> bool {
    let size = p.alpha.abs() + p.beta.abs() + q.alpha.abs() + q.beta.abs();
    (p.alpha - q.alpha).abs() + (p.beta - q.beta).abs() <= CROSSING_RESIDUAL * size
}

/// Newton's method on `P(t1) = P(t2)` from the segments' crossing, each angle kept inside
/// its segment's bracket; the wall at the last iterate, and whether the iterates converged
/// (the last step at rounding of `theta`, or the two points within [`CROSSING_RESIDUAL`] of
/// their size).
fn refine(
    dec: &impl Decomposition,
    mut t1: f64,
    mut t2: f64,
    s: &Segment,
    o: &Segment,
) -> Option<((f64, Wall), bool)> {
    let inside = |t: f64, seg: &Segment| {
        let (a, b) = (seg.0.0.min(seg.1.0), seg.0.0.max(seg.1.0));
        // a bracket one segment wider each way: the chord's crossing is near the curve's
        let w = b - a;
        t >= a - w && t <= b + w
    };
    let mut converged = false;
    for _ in 0..12 {
        let (p, q) = (dec.eval(t1)?, dec.eval(t2)?);
        let f = (p.alpha - q.alpha, p.beta - q.beta);
        let det = -p.dalpha * q.dbeta + q.dalpha * p.dbeta;
        if det == 0.0 || !det.is_finite() {
            break; // tangent branches: keep the iterate
        }
        // J = [[p.da, -q.da], [p.db, -q.db]], J d = -f
        let d1 = (-f.0 * -q.dbeta - -q.dalpha * -f.1) / det;
        let d2 = (p.dalpha * -f.1 - p.dbeta * -f.0) / det;
        let (n1, n2) = (t1 + d1, t2 + d2);
        if !(inside(n1, s) && inside(n2, o)) {
            break;
        }
        (t1, t2) = (n1, n2);
        if d1.abs().max(d2.abs()) <= 4.0 * f64::EPSILON {
            converged = true;
            break;
        }
    }
    let p = dec.eval(t1)?;
    if !converged {
        // the iterates stopped early (outside the bracket, tangent branches, the iteration
        // limit): a crossing only where the two points agree
        converged = dec.eval(t2).is_some_and(|q| meet(&p, &q));
    }
    let wall = Wall {
        alpha: p.alpha,
        beta: p.beta,
    };
    Some(((t1, wall), converged))
}

/// Relative distances of the neighbours that confirm a candidate, nearest first.
///
/// `1e-8`: far above the Schur-Cohn recursion's resolution near the circle for simple roots
/// (about `1e-13` for these degrees), so a confirmed neighbour is really stable; and small
/// enough that a candidate just outside a corner of the region (not on its boundary) can be
/// off by at most that much.
///
/// `1e-6`: where the corner is a double root at `z = -1` (the `z = -1` line meeting the
/// D-decomposition curve, e.g. `d = 0`, `delta = 11.25`), rounding moves the double root by
/// about the square root of the coefficients' error, so the stable wedge's neighbours `1e-8`
/// away may test unstable; `1e-6` is well inside, above the double root's resolution. Used
/// only when no candidate is confirmed at `1e-8`, so an ordinary corner is still confirmed to
/// `1e-8`.
const NEIGHBOUR_STEPS: [f64; 2] = [1e-8, 1e-6];

/// Whether strictly stable walls lie beside the wall `(alpha, beta)` on its left, inside
/// `[bmin, bmax]` in damping: the neighbour tests of [`rightmost`] on a loop's curve (a
/// relative step of [`NEIGHBOUR_STEPS`], in the plane's and in each coordinate's own
/// scale), without the line search.
pub(super) fn has_stable_wall_near(
    dec: &impl Decomposition,
    alpha: f64,
    beta: f64,
    bmin: f64,
    bmax: f64,
) -> bool {
    wall_beside(
        dec,
        (alpha, beta),
        (bmin, bmax),
        NEIGHBOUR_STEPS,
        strictly_stable,
    )
}

/// Whether a wall beside `(alpha, beta)` on its left with its damping inside `[bmin, bmax]`
/// passes `test`: the walls of [`has_stable_left_neighbour`] and then of
/// [`has_stable_scaled_neighbour`] at each relative step of `steps` in turn.
fn wall_beside<D: Decomposition>(
    dec: &D,
    (alpha, beta): (f64, f64),
    limits: (f64, f64),
    steps: impl IntoIterator<Item = f64>,
    test: impl Fn(&D, &Wall, &mut [f64]) -> bool,
) -> bool {
    let c = Candidate {
        alpha,
        beta,
        kind: AmaxKind::Smooth,
        theta: 0.0,
    };
    crate::stability::schur_cohn::with_scratch(dec.degree() + 1, |buf| {
        steps.into_iter().any(|step| {
            let plane = step * (alpha.abs() + beta.abs());
            let own = (step * alpha.abs(), step * beta.abs());
            wall_toward(dec, &c, (plane, plane), &LEFT_SLOPES, limits, buf, &test)
                || wall_toward(dec, &c, own, &FAN, limits, buf, &test)
        })
    })
}

/// Whether some wall a relative `step` to the left of the candidate (straight left or up to
/// 4:1 diagonally, inside the beta limits) is strictly stable.
fn has_stable_left_neighbour(
    dec: &impl Decomposition,
    c: &Candidate,
    step: f64,
    bmin: f64,
    bmax: f64,
    buf: &mut [f64],
) -> bool {
    let h = step * (c.alpha.abs() + c.beta.abs());
    wall_toward(
        dec,
        c,
        (h, h),
        &LEFT_SLOPES,
        (bmin, bmax),
        buf,
        &strictly_stable,
    )
}

/// Slopes of [`has_stable_left_neighbour`]'s directions: straight left, and diagonally up
/// to 4:1 either way.
pub(super) const LEFT_SLOPES: [f64; 7] = [0.0, 1.0, -1.0, 0.25, -0.25, 4.0, -4.0];

/// Whether some wall a relative `step` to the left of the candidate, each coordinate
/// relative to its own size (`alpha (1 - step)`, `beta + k step |beta|` for the slopes `k`
/// of [`FAN`]), inside the beta limits, is strictly stable: [`has_stable_left_neighbour`]
/// in coordinates scaled by the candidate's, with a denser fan of directions for a thin
/// wedge.
fn has_stable_scaled_neighbour(
    dec: &impl Decomposition,
    c: &Candidate,
    step: f64,
    bmin: f64,
    bmax: f64,
    buf: &mut [f64],
) -> bool {
    let steps = (step * c.alpha.abs(), step * c.beta.abs());
    wall_toward(dec, c, steps, &FAN, (bmin, bmax), buf, &strictly_stable)
}

/// Whether some wall `ha` left of the candidate and `k hb` up, for a slope `k` of `slopes`
/// (in order) with its damping inside `[bmin, bmax]`, passes `test` ([`strictly_stable`]
/// for the confirmations, [`clearly_stable`] for an answer's clear neighbour).
fn wall_toward<D: Decomposition>(
    dec: &D,
    c: &Candidate,
    (ha, hb): (f64, f64),
    slopes: &[f64],
    (bmin, bmax): (f64, f64),
    buf: &mut [f64],
    test: &impl Fn(&D, &Wall, &mut [f64]) -> bool,
) -> bool {
    slopes.iter().any(|&k| {
        let wall = Wall {
            alpha: c.alpha - ha,
            beta: c.beta + k * hb,
        };
        (bmin..=bmax).contains(&wall.beta) && test(dec, &wall, buf)
    })
}

/// Slopes of [`has_stable_scaled_neighbour`]'s directions, in units of the candidate's own
/// `|beta| / |alpha|`: a factor of 2 or less apart up to 16 either way, so a wedge whose
/// edges' slopes differ by more than a factor of 2 holds one of them.
pub(super) const FAN: [f64; 17] = [
    0.0, 0.125, -0.125, 0.25, -0.25, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, 4.0, -4.0, 8.0, -8.0, 16.0,
    -16.0,
];

/// Reach of [`has_stable_wall_left`] in `beta`, in steps: four, the farthest diagonal of
/// [`has_stable_left_neighbour`].
const SLIVER_REACH: f64 = 4.0;

/// Whether the line `alpha = alpha_c (1 - step)` has strictly stable walls with `beta` within
/// [`SLIVER_REACH`] relative steps of the candidate's (each coordinate relative to its own
/// size, inside the beta limits): [`has_stable_left_neighbour`] in coordinates scaled by
/// the candidate's, with every `beta` of that reach tried at once by the stable set on the
/// line (its ends are where the line meets the curve, each piece decided by Schur-Cohn).
fn has_stable_wall_left(
    dec: &impl Decomposition,
    c: &Candidate,
    step: f64,
    bmin: f64,
    bmax: f64,
) -> bool {
    let alpha = c.alpha - step * c.alpha.abs();
    let reach = SLIVER_REACH * step * c.alpha.abs().max(c.beta.abs());
    let (lo, hi) = ((c.beta - reach).max(bmin), (c.beta + reach).min(bmax));
    stable_pieces_on(dec, alpha).is_ok_and(|set| set.iter().any(|i| i.lo < hi && i.hi > lo))
}

/// The stable dampings on the line `alpha` (each piece decided by Schur-Cohn at radius 1).
fn stable_pieces_on(
    dec: &impl Decomposition,
    alpha: f64,
) -> crate::error::Result<Vec<crate::search::Interval>> {
    let test = |w: &Wall| {
        Ok(crate::stability::schur_cohn::with_scratch(
            dec.degree() + 1,
            |buf| strictly_stable(dec, w, buf),
        ))
    };
    crate::search::curve_stable_set(dec, Free::Beta, alpha, &test)
}

/// Schur-Cohn at radius exactly 1 on `q` of `dec` for `wall` (`buf` at least `degree + 1`
/// long): every root strictly inside the circle, the boundary's own test.
pub(super) fn strictly_stable(dec: &impl Decomposition, wall: &Wall, buf: &mut [f64]) -> bool {
    schur_cohn(dec.coefficients_into(wall, buf), 1.0).stable
}

#[cfg(test)]
mod tests {
    use super::{Coordinate, Ends, angle_at, resolve_turns, run_merge_order};
    use crate::curve::{CurvePoint, Decomposition, LoopCurve};
    use crate::elements::Loop;
    use crate::filter::VelocityFilter;
    use crate::params::Plant;

    /// Towards a pole of the curve (a moving average's at `theta = pi / 2`, a slow
    /// Butterworth filter's near `0.177`) the halvings followed by the determinant's sign
    /// keep a subset of the points the halvings by curve points place, bit for bit, with
    /// the two points next to the pole among them, and leave out the far ones.
    #[test]
    fn pole_halvings_keep_the_points_next_to_the_pole() {
        let filters = [
            VelocityFilter::moving_average(4).unwrap(),
            VelocityFilter::butterworth(0.03).unwrap(),
        ];
        for filter in filters {
            let lp = Loop::new(Plant::new(0.1, 1.0).unwrap())
                .with_filter(filter)
                .unwrap();
            let dec = LoopCurve::new(&lp).unwrap();
            let mut scanned = Vec::new();
            dec.scan_into(&mut scanned);
            // every point reachable: the halvings by curve points all the way
            let full = resolve_turns(&dec, scanned.clone(), &|_: &CurvePoint| false);
            // no point reachable: the far halvings by the determinant's sign
            let fast = resolve_turns(&dec, scanned, &|_: &CurvePoint| true);
            assert!(
                fast.len() + 10 < full.len(),
                "{filter:?}: {} of {}",
                fast.len(),
                full.len()
            );
            let bits = |(t, p): &(f64, Option<CurvePoint>)| {
                let p = p.unwrap();
                [
                    t.to_bits(),
                    p.alpha.to_bits(),
                    p.beta.to_bits(),
                    p.dalpha.to_bits(),
                ]
            };
            let all: Vec<_> = full.iter().filter(|x| x.1.is_some()).map(bits).collect();
            for x in fast.iter().filter(|x| x.1.is_some()) {
                assert!(
                    all.contains(&bits(x)),
                    "{filter:?}: {x:?} not placed by the halvings"
                );
            }
            // the pole: the closest pair of neighbours in angle with a determinant of either
            // sign, in both
            let closest = |pts: &[(f64, Option<CurvePoint>)]| {
                pts.windows(2)
                    .filter(|w| {
                        let (d0, d1) = (dec.determinant(w[0].0), dec.determinant(w[1].0));
                        matches!((d0, d1), (Some(a), Some(b)) if (a > 0.0) != (b > 0.0))
                    })
                    .map(|w| (w[0].0.to_bits(), w[1].0.to_bits(), w[1].0 - w[0].0))
                    .min_by(|x, y| x.2.total_cmp(&y.2))
                    .unwrap()
            };
            assert_eq!(closest(&fast), closest(&full), "{filter:?}");
        }
    }

    /// The angle where a stretch of the curve has a given coordinate, by Newton's method from
    /// the chord, from the stretch's end and from its middle, is the one bisection in
    /// `theta` finds (the stretches between the scanned samples of a loop with a slow
    /// Butterworth filter, bent beside its pole and nearly straight elsewhere, each
    /// monotone in the coordinate at its samples and at 15 points between).
    #[test]
    fn angle_at_finds_the_bisections_angle() {
        let lp = Loop::new(Plant::new(0.1, 1.0).unwrap())
            .with_filter(VelocityFilter::butterworth(0.03).unwrap())
            .unwrap();
        let dec = LoopCurve::new(&lp).unwrap();
        let mut scanned = Vec::new();
        dec.scan_into(&mut scanned);
        let mut tried = 0;
        for w in scanned.windows(2) {
            let ((ta, Some(pa)), (tb, Some(pb))) = (w[0], w[1]) else {
                continue;
            };
            // (the far stretches towards `theta = pi`, out to 1e8, whose evaluation is
            // noisier in proportion, are left out)
            if pa.alpha.abs() + pa.beta.abs() > 1e4 || pb.alpha.abs() + pb.beta.abs() > 1e4 {
                continue;
            }
            for x in [Coordinate::Alpha, Coordinate::Beta] {
                let at = |t: f64| dec.eval(t).map(|p| x.of(&p).0);
                // monotone along the stretch (strictly, at 17 points)
                let xs: Vec<Option<f64>> = (0..=16)
                    .map(|i| at(ta + (tb - ta) * f64::from(i) / 16.0))
                    .collect();
                let Some(xs) = xs.into_iter().collect::<Option<Vec<f64>>>() else {
                    continue;
                };
                let up = xs.windows(2).all(|p| p[1] > p[0]);
                let down = xs.windows(2).all(|p| p[1] < p[0]);
                if !(up || down) {
                    continue;
                }
                let ((xa, _, _), (xb, _, _)) = (x.of(&pa), x.of(&pb));
                let e: Ends = if xa < xb {
                    ((xa, ta), (xb, tb))
                } else {
                    ((xb, tb), (xa, ta))
                };
                for frac in [0.1, 0.5, 0.9] {
                    let v = e.0.0 + frac * (e.1.0 - e.0.0);
                    // bisection on the sign of x - v, to adjacent angles
                    let (mut lo, mut hi) = (e.0.1, e.1.1);
                    for _ in 0..200 {
                        let mid = 0.5 * (lo + hi);
                        if mid == lo || mid == hi {
                            break;
                        }
                        if at(mid).unwrap() < v {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    for start in [None, Some(e.0.1), Some(0.5 * (ta + tb))] {
                        let (t, p) = angle_at(&dec, x, e, v, start).unwrap();
                        // The coordinate is evaluated to about 1e-13 of the point's size
                        // near `z = 1` and 1e-12 beside the pole (bisection's own angle
                        // misses `v` by 6e-13 of it there), so every angle within that over
                        // the derivative is a root: 1e-11 of the size, ten times that noise,
                        // for the residual (plus the derivative times 16 roundings of
                        // `theta`, the search's tolerance, where the stretch is steep) and
                        // over the derivative for the angle.
                        let size = p.alpha.abs() + p.beta.abs();
                        let slope = x.of(&p).1.abs();
                        let miss = (x.of(&p).0 - v).abs();
                        assert!(
                            miss <= 1e-11 * size + 16.0 * f64::EPSILON * slope,
                            "{ta} {tb}: {miss} from {v}"
                        );
                        let tol = 1e-11 * size / slope;
                        assert!(
                            (t - lo).abs() <= tol,
                            "{ta} {tb} {start:?}: {t} against {lo}"
                        );
                        tried += 1;
                    }
                }
            }
        }
        assert!(tried > 300, "{tried}");
    }

    /// The natural merge gives the order of the library's stable sort by `total_cmp`, on
    /// sequences of runs up and down, with ties, signed zeros and single elements.
    #[test]
    fn run_merge_order_is_the_stable_sort() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for case in 0..400 {
            let n = (next() % 60) as usize;
            let mut keys: Vec<f64> = Vec::with_capacity(n);
            let mut v = 0.0;
            let mut up = true;
            for _ in 0..n {
                if next() % 7 == 0 {
                    up = !up;
                }
                let step = (next() % 4) as f64 - if case % 3 == 0 { 1.0 } else { 0.0 };
                v += if up { step } else { -step };
                keys.push(if next() % 11 == 0 { -0.0 } else { v });
            }
            let mut want: Vec<usize> = (0..n).collect();
            want.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
            assert_eq!(run_merge_order(keys.len(), |i| keys[i]), want, "{keys:?}");
        }
    }
}
