//! The D-decomposition of an affine characteristic polynomial `q = Q0 + alpha QA + beta QB`
//! (`docs/MODEL.md` sections 4 and 8): the curve of walls with a root `e^{i theta}`,
//! `0 < theta < pi`, with its exact derivative along `theta`; the lines of the real roots
//! `z = +1` and `z = -1`; and where a line of constant `alpha` or `beta` crosses them. The
//! direct searches (`alpha_max`, the stable set on a line), the checker's cache and the exact
//! boundary engine all read a loop's curve from here ([`LoopCurve`]); the paper's loop adds
//! its closed-form curve as another [`Decomposition`].
//!
//! Method for [`LoopCurve`]: on `z = e^{i theta}` the complex equation
//! `alpha QA(z) + beta QB(z) = -Q0(z)` is two real linear equations, solved by Cramer's rule
//! (D-decomposition, Neimark 1948). Along the curve `q(e^{i theta}) = 0`, so
//! `alpha' QA + beta' QB = -i z q'(z)` (the derivative of `q(e^{i theta})` at the fixed wall),
//! the same two-by-two system with another right-hand side: the exact derivative, no finite
//! difference.
//!
//! # Crossings of a line
//!
//! Along the line `beta = b` (or `alpha = a`) stability can change only where the line meets
//! the D-decomposition: the curve (where `beta(theta) - b` changes sign: a bracket from the
//! scan, then Brent's method in `theta`, R. P. Brent, *Algorithms for Minimization without
//! Derivatives*, 1973, ch. 4) and the lines of the roots `z = +-1` (one linear equation
//! each). [`line_crossings`] returns them; a crossing found in error (at a pole of the curve)
//! only adds one more piece for the caller to test.

use std::borrow::Cow;
use std::f64::consts::PI;
use std::sync::OnceLock;

use crate::elements::{GeneralPoly, Loop};
use crate::params::{Plant, Wall};
use crate::roots::Complex;
use crate::roots::brent;
use crate::roots::eigen::poly_roots;

/// Which wall parameter a line varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Free {
    /// The stiffness `alpha` varies, the damping is fixed.
    Alpha,
    /// The damping `beta` varies, the stiffness is fixed.
    Beta,
}

impl Free {
    /// The name of the fixed parameter.
    pub(crate) fn fixed_name(self) -> &'static str {
        match self {
            Free::Alpha => "beta",
            Free::Beta => "alpha",
        }
    }
}

/// A point of the D-decomposition curve with the derivatives along `theta`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CurvePoint {
    pub(crate) alpha: f64,
    pub(crate) beta: f64,
    pub(crate) dalpha: f64,
    pub(crate) dbeta: f64,
}

impl CurvePoint {
    /// The finite point, or `None`.
    pub(crate) fn finite(self) -> Option<Self> {
        (self.alpha.is_finite()
            && self.beta.is_finite()
            && self.dalpha.is_finite()
            && self.dbeta.is_finite())
        .then_some(self)
    }
}

/// The D-decomposition of `q = Q0 + alpha QA + beta QB` (see the module documentation).
pub(crate) trait Decomposition {
    /// Calls `f(theta, point)` for the scan's angles in increasing order, all inside
    /// `(0, pi)` (`None` where the curve has no finite point).
    fn scan(&self, f: &mut dyn FnMut(f64, Option<CurvePoint>));

    /// Appends the points of [`Decomposition::scan`] to `out`, in its order.
    fn scan_into(&self, out: &mut Vec<ScanPoint>) {
        self.scan(&mut |t, p| out.push((t, p)));
    }

    /// The curve at `theta` in `(0, pi)`.
    fn eval(&self, theta: f64) -> Option<CurvePoint>;

    /// The Cramer determinant of the two real equations at `theta` in `(0, pi)`, as
    /// [`Decomposition::eval`] computes it there (its sign says on which side of a pole of
    /// the curve `theta` lies), without the right-hand sides and the derivatives; `None`
    /// where it is singular (see [`SINGULAR`]) or the decomposition does not give it.
    fn determinant(&self, _theta: f64) -> Option<f64> {
        None
    }

    /// The curve's end at `theta = pi`: the wall with a double root at `z = -1`, where
    /// `d alpha / d theta = 0` by the curve's symmetry about `pi`.
    fn eval_end(&self) -> Option<CurvePoint>;

    /// The curve's start at `theta = 0`: the wall with a double root at `z = 1`
    /// (`q(1) = q'(1) = 0`), where both derivatives along `theta` vanish by symmetry.
    fn eval_start(&self) -> Option<CurvePoint>;

    /// [`Decomposition::eval`] inside `(0, pi)`, [`Decomposition::eval_start`] and
    /// [`Decomposition::eval_end`] at and beyond the ends (a root finder may probe them).
    fn eval_or_end(&self, theta: f64) -> Option<CurvePoint> {
        if theta >= PI {
            self.eval_end()
        } else if theta <= 0.0 {
            self.eval_start()
        } else {
            self.eval(theta)
        }
    }

    /// The line of walls with the root `z = -1` as `(a, b, r)`, `a alpha + b beta = r`;
    /// `None` if `z = -1` is a root for no wall.
    fn line_minus_one(&self) -> Option<(f64, f64, f64)>;

    /// The line of walls with the root `z = +1`: `QB(1) = 0` for every loop, so it is the
    /// vertical line `alpha = -Q0(1) / QA(1)`, exactly `0` with a free integrator.
    fn alpha_plus_one(&self) -> Option<f64>;

    /// Whether `Q0(1) = 0` exactly (no hand stiffness): the line `alpha = 0` bounds every
    /// stable region on the left.
    fn free_integrator(&self) -> bool;

    /// Degree of `q`.
    fn degree(&self) -> usize;

    /// Whether two branches of the curve can meet at the region's boundary (a wedge's tip),
    /// so that the search must look for the curve's self-intersections. The paper's region
    /// has none (its boundary is the curve's one arc between the two lines).
    fn self_intersections(&self) -> bool {
        true
    }

    /// `[Q0, QA, QB]`, lowest power first, each `degree + 1` long (borrowed where the
    /// decomposition holds them).
    fn affine(&self) -> [Cow<'_, [f64]>; 3];

    /// Writes `q` for `wall` into `buf` (at least `degree + 1` long) and returns it.
    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64];
}

/// A polynomial `z^shift s(z)`: `Q0 = z^(n+2) D Fd` has a long delay's power of `z` as a
/// factor, so evaluating `s` and `z^shift` costs the device's order, not the delay's.
#[derive(Debug, Clone)]
struct Shifted {
    shift: usize,
    /// `s`, from the lowest nonzero coefficient to the end.
    s: Vec<f64>,
    /// The length of `s` without its trailing zeros.
    len: usize,
}

impl Shifted {
    fn new(p: &[f64]) -> Self {
        let shift = p.iter().position(|c| *c != 0.0).unwrap_or(0);
        let end = p.iter().rposition(|c| *c != 0.0).map_or(shift, |e| e + 1);
        Self {
            shift,
            s: p[shift..].to_vec(),
            len: end - shift,
        }
    }

    /// `s(z)` by Horner's rule (without the power of `z`).
    fn horner(&self, z: Complex) -> Complex {
        self.s[..self.len]
            .iter()
            .rev()
            .fold(Complex::new(0.0, 0.0), |v, &c| v * z + c)
    }

    /// The value at `z` by one product per power of `z` (for the short shifts of `QA` and
    /// `QB`).
    fn by_powers(&self, z: Complex) -> Complex {
        (0..self.shift).fold(self.horner(z), |v, _| v * z)
    }

    /// The value and the derivative at `z = e^{i theta}`, with `zk = z^shift` (from the
    /// angle: one rounding of `shift theta`, as the paper's curve).
    #[inline]
    fn on_circle(&self, z: Complex, zk: Complex) -> (Complex, Complex) {
        let zero = Complex::new(0.0, 0.0);
        let (mut v, mut dv) = (zero, zero);
        // from the highest nonzero coefficient: the zeros above it add nothing
        for &c in self.s[..self.len].iter().rev() {
            dv = dv * z + v;
            v = v * z + c;
        }
        if self.shift == 0 {
            return (v, dv);
        }
        // (z^k s)' = z^k (k s / z + s'); 1 / z = conj(z) on the circle
        let k = self.shift as f64;
        (zk * v, zk * (v * z.conj() * k + dv))
    }
}

/// Uniform scan samples per degree of `q`: the curve turns about `degree` times as fast as
/// `theta` (`z^(n+2)` for the delay, a moving average's denominator, the device's modes), and
/// 32 samples per turn are what the paper's scan uses (`32 (n + 2)`).
const SAMPLES_PER_DEGREE: usize = 32;

/// Samples added around a root of `Q0` or `QA` close to the circle, each side of its angle.
///
/// Near such a root (a lightly damped mode, a filter pole near 1) the curve runs through a
/// loop of width about the root's distance `rho` to the circle in `theta`, however fine the
/// uniform grid; 16 samples over `4 rho` each side resolve it as the uniform grid resolves
/// one turn.
const SAMPLES_PER_RESONANCE: usize = 16;

/// How near `z = 1` a computed root of `Q0` is taken for the free integrator's (a simple
/// root exactly at 1 when the device integrates freely, computed to a few roundings;
/// `1e-9`, the scale [`scan_grid`] gives a root on the circle), which gets no samples of
/// its own.
///
/// There `Q0` and `QB` both vanish (`QB(1) = 0` for every loop) and `QA(1)` does not, so
/// the curve is not a resonance's loop but ends regularly at `theta = 0`, at the wall with
/// a double root at `z = 1` ([`Decomposition::eval_start`]): dividing the equation by
/// `z - 1` leaves `alpha QA / (z - 1) + beta QB / (z - 1) = -Q0 / (z - 1)` with the last two
/// analytic at `z = 1`, and the curve is smooth in `theta` at the scale of the other roots,
/// which have their own samples. The 16 samples that lay within `4e-9` of `theta = 0` read
/// the curve's start through the cancellation of `Q0(e^{i theta})`, about `theta` in size:
/// rounding noise of relative size `1e-16 / theta`. Only the nearest root is passed over: a filter pole as near `z = 1` keeps its samples.
const FREE_ROOT: f64 = 1e-9;

/// A Cramer determinant below this fraction of the product of its columns' sizes is a
/// direction in which the curve runs off to infinity (the two equations dependent to
/// rounding): about a thousand roundings, above what Horner's evaluation on the circle
/// leaves of a degree-70 polynomial's terms.
const SINGULAR: f64 = 1e-13;

/// Solves `a1 alpha + b1 beta = c1`, `a2 alpha + b2 beta = c2` by Cramer's rule; `None`
/// where the determinant is at rounding level of its rows (see [`SINGULAR`]) or the wall
/// is not finite.
pub(crate) fn cramer((a1, b1, c1): (f64, f64, f64), (a2, b2, c2): (f64, f64, f64)) -> Option<Wall> {
    let det = a1 * b2 - b1 * a2;
    if det.is_nan() || det.abs() <= SINGULAR * a1.hypot(b1) * a2.hypot(b2) {
        return None;
    }
    let alpha = (c1 * b2 - b1 * c2) / det;
    let beta = (a1 * c2 - c1 * a2) / det;
    (alpha.is_finite() && beta.is_finite()).then_some(Wall { alpha, beta })
}

/// A scan's sample: its angle and the curve's point there (`None` where it has none).
pub(crate) type ScanPoint = (f64, Option<CurvePoint>);

/// The D-decomposition of a loop's own polynomial ([`GeneralPoly`]): the one curve of a loop
/// with elements that the direct searches, the checker's cache and the exact boundary
/// engine read.
#[derive(Debug, Clone)]
pub(crate) struct LoopCurve {
    poly: GeneralPoly,
    plant: Plant,
    free_integrator: bool,
    /// The scan's samples, built on the first scan (the boundary engine samples on its own
    /// grid).
    grid: OnceLock<Grid>,
    /// Set by the first scan: a curve scanned once (one `alpha_max`) keeps no points.
    scanned_once: OnceLock<()>,
    /// The scan's points, kept from the second scan on and replayed by every later one: the
    /// curve does not depend on the line it is crossed with, so the searches along many
    /// lines of one loop (the stable sets at many dampings) read the same points, computed
    /// once ([`Decomposition::scan`]).
    scanned: OnceLock<Box<[ScanPoint]>>,
    /// `Q0`, `QA`, `QB` as `z^k s(z)`.
    shifted: [Shifted; 3],
    /// The scan's table of the three `s`: row `j` holds `s_j` and `j s_j` of each (see
    /// [`LoopCurve::scan_point`]), zeros past each one's end.
    powers_table: Box<[[f64; 6]]>,
    /// `Q0(1)` (exactly 0 with a free integrator) and `QA(1)`.
    at_one: (f64, f64),
}

impl LoopCurve {
    /// The decomposition of `lp`'s polynomial.
    pub(crate) fn new(lp: &Loop) -> crate::error::Result<Self> {
        GeneralPoly::new(lp).map(Self::from_poly)
    }

    /// The decomposition of a loop's polynomial already built (as [`LoopCurve::new`] of its
    /// loop, without building it again).
    pub(crate) fn from_poly(poly: GeneralPoly) -> Self {
        let lp = *poly.discretization().loop_model();
        let shifted = [poly.q0(), poly.qa(), poly.qb()].map(Shifted::new);
        let rows = shifted.iter().map(|s| s.len).max().unwrap_or(0);
        let powers_table = (0..rows)
            .map(|j| {
                let mut row = [0.0; 6];
                for (k, s) in shifted.iter().enumerate() {
                    if j < s.len {
                        row[2 * k] = s.s[j];
                        row[2 * k + 1] = j as f64 * s.s[j];
                    }
                }
                row
            })
            .collect();
        let (v, _) = real_values(&poly, 1.0);
        let free_integrator = lp.free_integrator();
        Self {
            at_one: (if free_integrator { 0.0 } else { v[0] }, v[1]),
            free_integrator,
            plant: *lp.plant(),
            poly,
            grid: OnceLock::new(),
            scanned_once: OnceLock::new(),
            scanned: OnceLock::new(),
            shifted,
            powers_table,
        }
    }

    /// The loop's polynomial.
    pub(crate) fn poly(&self) -> &GeneralPoly {
        &self.poly
    }

    /// The loop's plant.
    pub(crate) fn plant(&self) -> &Plant {
        &self.plant
    }

    /// `(Q0(1), QA(1))`, the first exactly 0 with a free integrator.
    pub(crate) fn at_one(&self) -> (f64, f64) {
        self.at_one
    }

    /// The power `k` of `z` factored out of `Q0` (the delay's), whose value
    /// [`LoopCurve::wall_at`] takes precomputed.
    pub(crate) fn circle_power(&self) -> usize {
        self.shifted[0].shift
    }

    /// The wall with the root pair `e^{+-i theta}` from `z = e^{i theta}` and `zk = z^k`
    /// ([`LoopCurve::circle_power`]), without the derivative: the boundary engine's sample.
    pub(crate) fn wall_at(&self, z: Complex, zk: Complex) -> Option<Wall> {
        let q0 = self.shifted[0].horner(z) * zk;
        let (qa, qb) = (self.shifted[1].by_powers(z), self.shifted[2].by_powers(z));
        cramer((qa.re, qb.re, -q0.re), (qa.im, qb.im, -q0.im))
    }

    /// The wall with a double root at `z0 = +-1` (`q(z0) = q'(z0) = 0`); at `z0 = 1` the
    /// first equation is the `z = 1` line `QA(1) alpha = r_one` (`QB(1) = 0`).
    pub(crate) fn double_root(&self, z0: f64, r_one: f64) -> Option<Wall> {
        let (v, dv) = real_values(&self.poly, z0);
        let first = if z0 > 0.0 {
            (v[1], 0.0, r_one)
        } else {
            (v[1], v[2], -v[0])
        };
        cramer(first, (dv[1], dv[2], -dv[0]))
    }

    /// The scan's samples, built once.
    fn grid(&self) -> &Grid {
        self.grid.get_or_init(|| scan_grid(&self.poly))
    }

    fn at(&self, theta: f64) -> Option<CurvePoint> {
        if !(theta > 0.0 && theta < PI) {
            return None;
        }
        let z = Complex::from_polar(1.0, theta);
        self.on_circle(z, self.circle_powers(theta, z))
    }

    /// [`LoopCurve::at`] by [`LoopCurve::scan_point`]: a scan's sample off its uniform grid.
    fn scan_at(&self, theta: f64) -> Option<CurvePoint> {
        if !(theta > 0.0 && theta < PI) {
            return None;
        }
        let z = Complex::from_polar(1.0, theta);
        self.scan_point(z, self.circle_powers(theta, z))
    }

    /// The powers `z^k` of each polynomial's shift at `z = e^{i theta}`: one sine and cosine
    /// per distinct shift above 1 (`QA` and `QB` share theirs; `1 theta` is `theta` exactly,
    /// so `z^1` is `z`).
    fn circle_powers(&self, theta: f64, z: Complex) -> [Complex; 3] {
        let mut powers: [(usize, Complex); 3] = [(1, z); 3];
        for k in 0..3 {
            let shift = self.shifted[k].shift;
            let known = powers[..k]
                .iter()
                .copied()
                .chain([(1, z)])
                .find(|p| p.0 == shift);
            powers[k] = match known {
                Some(p) => p,
                // unused: a shift of 0 takes no power
                None if shift == 0 => (0, Complex::new(1.0, 0.0)),
                None => (shift, Complex::from_polar(1.0, shift as f64 * theta)),
            };
        }
        powers.map(|p| p.1)
    }

    /// The curve at `z = e^{i theta}` with `zk[i]` the power `z^k` of `shifted[i]`.
    fn on_circle(&self, z: Complex, zk: [Complex; 3]) -> Option<CurvePoint> {
        // three calls, not an array map: the map's closure was not inlined
        let (q0, d0) = self.shifted[0].on_circle(z, zk[0]);
        let (qa, da) = self.shifted[1].on_circle(z, zk[1]);
        let (qb, db) = self.shifted[2].on_circle(z, zk[2]);
        // d/dtheta of q(e^{i theta}) at the wall: i z q'(z)
        point(q0, qa, qb, |alpha, beta| {
            Complex::new(0.0, 1.0) * z * (d0 + da * alpha + db * beta)
        })
    }

    /// The curve at a scan sample `z = e^{i theta}` (`zk` as [`LoopCurve::on_circle`]):
    /// the same point as there to rounding, by one shared sequence of the powers `z^j`
    /// instead of three Horner recurrences with derivatives.
    ///
    /// Method: on the circle `s(z) = sum s_j z^j` and `z s'(z) = sum j s_j z^j`, so one
    /// complex product per power of `z` and four real products per coefficient give each
    /// polynomial's value and derivative (`z^k s` contributes `z^k (k s + z s')` to
    /// `z q'(z)`). The powers by repeated multiplication err by about `j` roundings at
    /// `z^j`, as Horner's rule does over `j` coefficients. The scan's points only decide
    /// which intervals bracket a sign change (the candidates and crossings are evaluated
    /// afresh by [`Decomposition::eval`]), so this rounding reaches a result only where a
    /// sign is taken within rounding of zero at a sample.
    #[inline]
    fn scan_point(&self, z: Complex, zk: [Complex; 3]) -> Option<CurvePoint> {
        // per polynomial: Re s, Im s, Re z s', Im z s'
        let mut acc = [[0.0f64; 4]; 3];
        let mut p = Complex::new(1.0, 0.0);
        for row in self.powers_table.iter() {
            for (k, a) in acc.iter_mut().enumerate() {
                let (c, cj) = (row[2 * k], row[2 * k + 1]);
                a[0] += c * p.re;
                a[1] += c * p.im;
                a[2] += cj * p.re;
                a[3] += cj * p.im;
            }
            p *= z;
        }
        let parts = |k: usize| {
            let [vr, vi, wr, wi] = acc[k];
            let (v, w) = (Complex::new(vr, vi), Complex::new(wr, wi));
            let shift = self.shifted[k].shift;
            if shift == 0 {
                (v, w)
            } else {
                (zk[k] * v, zk[k] * (v * shift as f64 + w))
            }
        };
        let ((q0, d0), (qa, da), (qb, db)) = (parts(0), parts(1), parts(2));
        point(q0, qa, qb, |alpha, beta| {
            Complex::new(0.0, 1.0) * (d0 + da * alpha + db * beta)
        })
    }
}

/// The curve point from `Q0`, `QA`, `QB` at `z = e^{i theta}` by Cramer's rule, with the
/// derivative of `q(e^{i theta})` along `theta` at the wall `dq(alpha, beta)` as the second
/// right-hand side; `None` where the determinant is singular (see [`SINGULAR`]) or the
/// point is not finite.
#[inline]
fn point(
    q0: Complex,
    qa: Complex,
    qb: Complex,
    dq: impl Fn(f64, f64) -> Complex,
) -> Option<CurvePoint> {
    let det = determinant(qa, qb)?;
    let solve = |c: Complex| {
        (
            (c.re * qb.im - qb.re * c.im) / det,
            (qa.re * c.im - c.re * qa.im) / det,
        )
    };
    let (alpha, beta) = solve(-q0);
    let (dalpha, dbeta) = solve(-dq(alpha, beta));
    CurvePoint {
        alpha,
        beta,
        dalpha,
        dbeta,
    }
    .finite()
}

/// The Cramer determinant of the columns `QA`, `QB` at a point of the circle; `None` where
/// it is singular (see [`SINGULAR`]).
#[inline]
fn determinant(qa: Complex, qb: Complex) -> Option<f64> {
    let det = qa.re * qb.im - qb.re * qa.im;
    // The columns' sizes by their 1-norms first (at least the Euclidean ones): a
    // determinant above the threshold with those is above it with the Euclidean sizes,
    // whose square roots are then not needed.
    let taxicab = (qa.re.abs() + qa.im.abs()) * (qb.re.abs() + qb.im.abs());
    if det.is_nan()
        || (det.abs() <= SINGULAR * taxicab && det.abs() <= SINGULAR * qa.norm() * qb.norm())
    {
        return None;
    }
    Some(det)
}

/// `(Q0(z), QA(z), QB(z))` and their derivatives, by Horner's rule, for a real `z`.
fn real_values(p: &GeneralPoly, z: f64) -> ([f64; 3], [f64; 3]) {
    let (mut v, mut dv) = ([0.0; 3], [0.0; 3]);
    for i in (0..=p.degree()).rev() {
        for (k, c) in [p.q0()[i], p.qa()[i], p.qb()[i]].into_iter().enumerate() {
            dv[k] = dv[k] * z + v[k];
            v[k] = v[k] * z + c;
        }
    }
    (v, dv)
}

/// The scan's samples in increasing angle: the midpoints of a uniform grid of `steps`
/// intervals over `[0, pi]`, every one in index order, merged during the scan with the extra
/// angles (sorted, without repeats).
#[derive(Debug, Clone)]
struct Grid {
    steps: usize,
    extra: Vec<f64>,
}

/// The scan's samples for `poly`: the midpoints of a uniform grid of `32 (degree + 1)`
/// intervals over `[0, pi]`, refined around the angle of every root of `Q0` and `QA` within a grid step of
/// the circle (see [`SAMPLES_PER_RESONANCE`]), but the free integrator's root `z = 1` of
/// `Q0` (see [`FREE_ROOT`]).
fn scan_grid(poly: &GeneralPoly) -> Grid {
    let steps = SAMPLES_PER_DEGREE * (poly.degree() + 1);
    let h = PI / steps as f64;
    // two sides of 16 samples around each root of `Q0` and `QA`
    let mut extra: Vec<f64> = Vec::with_capacity(4 * SAMPLES_PER_RESONANCE * (poly.degree() + 1));
    let free = poly.discretization().loop_model().free_integrator();
    for (which, p) in [poly.q0(), poly.qa()].into_iter().enumerate() {
        let Some(last) = p.iter().rposition(|c| *c != 0.0) else {
            continue;
        };
        let Some(first) = p.iter().position(|c| *c != 0.0) else {
            continue;
        };
        // a failure of the root finder leaves the uniform grid, which is still a scan
        let Ok(mut roots) = poly_roots(&p[first..=last]) else {
            continue;
        };
        if free && which == 0 {
            // the root of `Q0` nearest `z = 1`, if it is the free integrator's
            let nearest = (0..roots.len())
                .min_by(|&a, &b| (roots[a] - 1.0).norm().total_cmp(&(roots[b] - 1.0).norm()));
            if let Some(k) = nearest
                && (roots[k] - 1.0).norm() < FREE_ROOT
            {
                roots.swap_remove(k);
            }
        }
        for r in roots {
            let rho = (r.norm() - 1.0).abs();
            if rho >= 4.0 * h || r.im < 0.0 {
                continue;
            }
            // a root on the circle (an undamped mode): its neighbourhood at the scale of
            // rounding
            let rho = rho.max(1e-9);
            let centre = r.arg();
            let k = SAMPLES_PER_RESONANCE as f64;
            let off = |i: usize| 4.0 * rho * i as f64 / k;
            // in increasing angle, so that the sort below finds one run per root
            extra.extend((1..=SAMPLES_PER_RESONANCE).rev().map(|i| centre - off(i)));
            extra.extend((1..=SAMPLES_PER_RESONANCE).map(|i| centre + off(i)));
        }
    }
    extra.retain(|t| *t > 0.0 && *t < PI);
    extra.sort_by(f64::total_cmp);
    // a repeated angle (equal bits) is the same sample
    extra.dedup();
    Grid { steps, extra }
}

impl LoopCurve {
    /// The scan's points computed afresh ([`Decomposition::scan`]), handed to `f` (a
    /// closure known here, so that [`Decomposition::scan_into`] pushes each point without an
    /// indirect call).
    fn scan_fresh(&self, f: &mut impl FnMut(f64, Option<CurvePoint>)) {
        let grid = self.grid();
        let powers = self.shifted.each_ref().map(|s| s.shift as f64);
        let mut rotor = Rotor::<3, true>::new(grid.steps, ROTOR_RESEED, powers);
        // The midpoints of the uniform grid (the rotor's angles `pi (j + 1/2) / steps`): the
        // rational angles `pi j / steps` include the zeros a moving average's numerator puts
        // on the circle (`2 pi k / N`, where `QB` vanishes and the curve runs off to
        // infinity), which would cut the scan exactly there. The extra angles go in before
        // the first midpoint above them; one equal to a midpoint is that sample (exact
        // comparison: the same angle).
        let mut rest = grid.extra.iter().copied().peekable();
        for j in 0..grid.steps {
            let (t, z, zk) = rotor.at(j);
            while let Some(e) = rest.next_if(|e| e.total_cmp(&t).is_lt()) {
                f(e, self.scan_at(e));
            }
            rest.next_if(|e| *e == t);
            f(t, self.scan_point(z, zk));
        }
        for e in rest {
            f(e, self.scan_at(e));
        }
    }
}

impl LoopCurve {
    /// The scan's kept points ([`Decomposition::scan`]: the first scan computes its points,
    /// hands them to `first` and keeps none, `None`; the second keeps them and every later
    /// one replays them).
    fn scan_kept(&self, first: &mut impl FnMut(f64, Option<CurvePoint>)) -> Option<&[ScanPoint]> {
        match self.scanned.get() {
            Some(p) => Some(p),
            None if self.scanned_once.set(()).is_ok() => {
                self.scan_fresh(first);
                None
            }
            None => Some(self.scanned.get_or_init(|| {
                let grid = self.grid();
                let mut v = Vec::with_capacity(grid.steps + grid.extra.len());
                self.scan_fresh(&mut |t, p| v.push((t, p)));
                v.into_boxed_slice()
            })),
        }
    }
}

impl Decomposition for LoopCurve {
    /// The first scan computes its points and keeps none; the second keeps them and every
    /// later one replays them: the same angles and points, bit for bit, in the same order.
    fn scan(&self, f: &mut dyn FnMut(f64, Option<CurvePoint>)) {
        let Some(points) = self.scan_kept(&mut |t, p| f(t, p)) else {
            return;
        };
        for &(t, p) in points.iter() {
            f(t, p);
        }
    }

    fn scan_into(&self, out: &mut Vec<ScanPoint>) {
        if let Some(points) = self.scan_kept(&mut |t, p| out.push((t, p))) {
            out.extend_from_slice(points);
        }
    }

    fn eval(&self, theta: f64) -> Option<CurvePoint> {
        self.at(theta)
    }

    fn determinant(&self, theta: f64) -> Option<f64> {
        if !(theta > 0.0 && theta < PI) {
            return None;
        }
        let z = Complex::from_polar(1.0, theta);
        let zk = self.circle_powers(theta, z);
        // `QA` and `QB` as [`Shifted::on_circle`] computes them (the same roundings)
        let value = |k: usize| {
            let v = self.shifted[k].horner(z);
            if self.shifted[k].shift == 0 {
                v
            } else {
                zk[k] * v
            }
        };
        determinant(value(1), value(2))
    }

    fn eval_start(&self) -> Option<CurvePoint> {
        // q(1) = 0 and q'(1) = 0; QB(1) = 0 for every loop, and Q0(1) = 0 exactly with a free
        // integrator
        let r = if self.free_integrator {
            0.0
        } else {
            -self.at_one.0
        };
        let w = self.double_root(1.0, r)?;
        Some(CurvePoint {
            alpha: w.alpha,
            beta: w.beta,
            dalpha: 0.0,
            dbeta: 0.0,
        })
    }

    fn eval_end(&self) -> Option<CurvePoint> {
        // q(-1) = 0 and q'(-1) = 0: two real linear equations.
        let w = self.double_root(-1.0, 0.0)?;
        Some(CurvePoint {
            alpha: w.alpha,
            beta: w.beta,
            dalpha: 0.0,
            dbeta: 0.0,
        })
    }

    fn line_minus_one(&self) -> Option<(f64, f64, f64)> {
        let (v, _) = real_values(&self.poly, -1.0);
        let (a, b, r) = (v[1], v[2], -v[0]);
        (self.poly.wall_moves_root(a, b) && r.is_finite()).then_some((a, b, r))
    }

    fn alpha_plus_one(&self) -> Option<f64> {
        if self.free_integrator {
            return Some(0.0);
        }
        let a = -self.at_one.0 / self.at_one.1;
        a.is_finite().then_some(a)
    }

    fn free_integrator(&self) -> bool {
        self.free_integrator
    }

    fn degree(&self) -> usize {
        self.poly.degree()
    }

    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64] {
        self.poly.coefficients_into(wall, buf)
    }

    fn affine(&self) -> [Cow<'_, [f64]>; 3] {
        [self.poly.q0(), self.poly.qa(), self.poly.qb()].map(Cow::Borrowed)
    }
}

/// Samples between exact re-seeds of [`Rotor`].
///
/// Each rotation step adds at most about `4 u` (`u = 1.1e-16`) to the error of `z` and of
/// `z^k`: the rounding of the step `e^{i h}` itself and of one complex product. After
/// `ROTOR_RESEED - 1 = 15` steps that is below `7e-15` rad of angle (and of modulus), about
/// the error the library's sine and cosine already have in `z^k` from the rounding of
/// `k theta` once `k >= 32`, and 150 times below the default `theta` tolerance
/// [`crate::amax::DEFAULT_THETA_TOL`] (and below the smallest accepted one, `1e-15`, times
/// the paper's curve's `n + 2`). 16 samples is one oscillation of `e^{i (n+2) theta}` on the
/// paper's scan grid, and the exact `sin_cos` per re-seed then cost an eighth of a call per
/// sample.
pub(crate) const ROTOR_RESEED: usize = 16;

/// `z = e^{i theta_j}` and the powers `z^k` on the uniform grid `theta_j = pi j / steps`
/// (with `MID`, its midpoints `pi (j + 1/2) / steps`) by complex rotation: each step
/// multiplies `z` by `e^{i pi / steps}` and each power by `e^{i k pi / steps}`, and every
/// [`ROTOR_RESEED`] steps all are taken afresh from the sine and cosine of `theta_j` and
/// `k theta_j`, which bounds the drift (see there). Method: the recurrence for `cos` and `sin` of equally spaced
/// angles by repeated multiplication by a unit complex number (e.g. W. H. Press et al.,
/// *Numerical Recipes*, 3rd ed., 2007, section 5.4).
pub(crate) struct Rotor<const P: usize, const MID: bool> {
    steps: usize,
    reseed: usize,
    powers: [f64; P],
    step: Complex,
    step_k: [Complex; P],
    z: Complex,
    zk: [Complex; P],
}

impl<const P: usize, const MID: bool> Rotor<P, MID> {
    /// The rotor on a grid of `steps` intervals over `[0, pi]` (their midpoints with `MID`),
    /// for the powers `powers` of `z`, re-seeded every `reseed` steps ([`ROTOR_RESEED`];
    /// `1`: every sample from `sin_cos`).
    pub(crate) fn new(steps: usize, reseed: usize, powers: [f64; P]) -> Self {
        let h = PI / steps as f64;
        Self {
            steps,
            reseed: reseed.max(1),
            powers,
            step: Complex::from_polar(1.0, h),
            step_k: powers.map(|k| Complex::from_polar(1.0, k * h)),
            z: Complex::new(1.0, 0.0),
            zk: [Complex::new(1.0, 0.0); P],
        }
    }

    /// The grid angle `theta_j`, `z` and the powers there. Called for `j = 0, 1, 2, ...` in
    /// turn (or from any `j` that is a multiple of the re-seeding interval).
    ///
    /// Inlined into each scan's loop: the step is a few products, which a call would double.
    #[inline(always)]
    pub(crate) fn at(&mut self, j: usize) -> (f64, Complex, [Complex; P]) {
        // `j + 1/2` is exact for any grid; `MID` is a constant, so the ends' rotor (the
        // paper's scan) does no addition
        let x = if MID { j as f64 + 0.5 } else { j as f64 };
        let theta = PI * x / self.steps as f64;
        if j.is_multiple_of(self.reseed) {
            let (s, c) = theta.sin_cos();
            self.z = Complex::new(c, s);
            if P == 1 {
                // the paper's scan: one power, `n + 2 >= 2`
                self.zk = self.powers.map(|k| Complex::from_polar(1.0, k * theta));
                return (theta, self.z, self.zk);
            }
            // A power taken before (the same `k`, as `QA` and `QB` often share theirs), `1`
            // (`z^0`, what the sine and cosine of `0 theta = 0` give exactly) and `z` itself
            // (`1 theta = theta` exactly, the same sine and cosine) are not taken again: the
            // same bits, without their sine and cosine (exact comparisons: equal powers).
            for i in 0..P {
                let k = self.powers[i];
                let known = (0..i).find(|&e| self.powers[e] == k);
                self.zk[i] = if let Some(e) = known {
                    self.zk[e]
                } else if k == 0.0 {
                    Complex::new(1.0, 0.0)
                } else if k == 1.0 {
                    self.z
                } else {
                    Complex::from_polar(1.0, k * theta)
                };
            }
        } else {
            self.z *= self.step;
            for (zk, step) in self.zk.iter_mut().zip(&self.step_k) {
                *zk *= step;
            }
        }
        (theta, self.z, self.zk)
    }
}

/// Samples on the last stretch of a curve that runs off to infinity at `theta = pi`, each
/// halving the distance to `pi`: 48 reach `2^-48` of a grid step, where the curve is
/// `2^48` times farther out than at the last grid sample.
const END_HALVINGS: i32 = 48;

/// Brent's tolerance in `theta` for a crossing of a line with the curve: a few roundings of
/// `theta` itself (`pi` is the largest), so the crossing's value is as accurate as the curve
/// can be evaluated there.
pub(crate) const CROSSING_THETA_TOL: f64 = 4.0 * f64::EPSILON;

/// The values of the free parameter where the line `free` at `fixed` meets the
/// D-decomposition of `dec` (curve and the lines of `z = +-1`), sorted, unfiltered (see the
/// module documentation). With a free integrator the crossing at `z = 1` in `alpha` is `0`
/// exactly.
pub(crate) fn line_crossings(dec: &impl Decomposition, free: Free, fixed: f64) -> Vec<f64> {
    // (the fixed coordinate, the free one) of a curve point
    let split = |p: &CurvePoint| match free {
        Free::Alpha => (p.beta, p.alpha),
        Free::Beta => (p.alpha, p.beta),
    };
    // (fixed coordinate - fixed, its derivative) along the curve
    let g = |p: &CurvePoint| match free {
        Free::Alpha => (p.beta - fixed, p.dbeta),
        Free::Beta => (p.alpha - fixed, p.dalpha),
    };
    let value = |t: f64| dec.eval_or_end(t).map_or(f64::NAN, |q| g(&q).0);
    let slope = |t: f64| dec.eval_or_end(t).map_or(f64::NAN, |q| g(&q).1);
    let mut out: Vec<f64> = Vec::new();
    let mut crossing = |t0: f64, t1: f64| {
        let t = brent(value, t0, t1, CROSSING_THETA_TOL);
        if let Some(q) = dec.eval_or_end(t) {
            out.push(split(&q).1);
        }
    };
    let mut prev: Option<(f64, (f64, f64))> = None;
    // the scan with the curve's two ends, which it leaves out
    let mut visit = |th: f64, p: Option<CurvePoint>| {
        let Some(p) = p else {
            prev = None;
            return;
        };
        let (g1, d1) = g(&p);
        if let Some((th0, (g0, d0))) = prev {
            if (g0 > 0.0) != (g1 > 0.0) {
                crossing(th0, th);
            } else if (d0 > 0.0) != (d1 > 0.0) && (g0 > 0.0) != (d0 > 0.0) {
                // The coordinate turns back towards the line between the samples: a pair of
                // crossings can hide in one interval. Where it turns, on the line's other
                // side, the pair is bracketed on both sides of the turn.
                let te = brent(slope, th0, th, CROSSING_THETA_TOL);
                let ge = value(te);
                if ge.is_finite() && (ge > 0.0) != (g0 > 0.0) {
                    crossing(th0, te);
                    crossing(te, th);
                }
            }
        }
        prev = Some((th, (g1, d1)));
    };
    visit(0.0, dec.eval_start());
    let mut last = 0.0;
    dec.scan(&mut |th, p| {
        last = th;
        visit(th, p);
    });
    match dec.eval_end() {
        Some(end) => visit(PI, Some(end)),
        None => {
            // No double root at z = -1 (QB(-1) = 0, as behind a two-sample average): the
            // curve runs off to infinity as theta -> pi, along the z = -1 line. Samples
            // halving the distance to pi find a crossing on that last stretch.
            for k in 1..=END_HALVINGS {
                let t = PI - (PI - last) * 0.5f64.powi(k);
                visit(t, dec.eval(t));
            }
        }
    }
    // the curve's end at pi lies on the z = -1 line, whose crossing follows
    if let Some((a, b, r)) = dec.line_minus_one() {
        out.push(match free {
            Free::Alpha => (r - b * fixed) / a,
            Free::Beta => (r - a * fixed) / b,
        });
    }
    if free == Free::Alpha
        && let Some(a1) = dec.alpha_plus_one()
    {
        out.push(a1);
    }
    out.retain(|v| v.is_finite());
    out.sort_by(f64::total_cmp);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::Hand;
    use crate::filter::VelocityFilter;
    use crate::params::Plant;

    /// With a free integrator the curve ends regularly at `theta = 0` (see [`FREE_ROOT`]):
    /// its points within `4e-9` of it (evaluated on the circle) are its start, the wall
    /// with a double root at `z = 1` (`q(1) = q'(1) = 0`, real equations at `z = 1`), to
    /// the rounding of `Q0(e^{i theta})`, and the scan takes no samples there; a filter
    /// pole `1e-12` from `z = 1` keeps its samples.
    #[test]
    fn free_integrator_root_gets_no_samples() {
        let plant = Plant::new(0.1, 1.0).unwrap();
        for filter in [
            VelocityFilter::low_pass(0.8),
            VelocityFilter::moving_average(4),
        ] {
            let lp = Loop::new(plant).with_filter(filter.unwrap()).unwrap();
            let c = LoopCurve::new(&lp).unwrap();
            let start = c.eval_start().unwrap();
            let size = start.alpha.abs() + start.beta.abs();
            for t in [2.5e-10, 1e-9, 4e-9] {
                let p = c.eval(t).unwrap();
                // rounding of a value of size theta, relative 1e-16 / theta, a thousand times
                let noise = 1e3 * f64::EPSILON / t * size;
                assert!(
                    (p.alpha - start.alpha).abs() <= noise,
                    "{t}: {p:?} {start:?}"
                );
                assert!((p.beta - start.beta).abs() <= noise, "{t}: {p:?} {start:?}");
            }
            assert!(
                c.grid().extra.iter().all(|t| *t > 1e-3),
                "{:?}",
                c.grid().extra
            );
        }
        let slow = Loop::new(plant)
            .with_filter(VelocityFilter::low_pass(1.0 - 1e-12).unwrap())
            .unwrap();
        let c = LoopCurve::new(&slow).unwrap();
        assert!(c.grid().extra.iter().filter(|t| **t < 1e-6).count() >= 16);
    }

    /// A curve scanned many times replays its points: the first scan (computed, nothing
    /// kept), the second (computed and kept) and every later one (replayed) give the same
    /// angles and points bit for bit as a curve built afresh for each scan, and so do the
    /// crossings of lines with it.
    #[test]
    fn later_scans_replay_the_first_bit_for_bit() {
        let plant = Plant::new(0.005, 1.0).unwrap();
        let lp = Loop::new(plant)
            .with_filter(VelocityFilter::low_pass(0.8).unwrap())
            .unwrap()
            .with_hand(Hand::new(0.5, 0.2, 0.01).unwrap())
            .unwrap();
        let bits = |p: Option<CurvePoint>| {
            p.map(|p| [p.alpha, p.beta, p.dalpha, p.dbeta].map(f64::to_bits))
        };
        let points = |c: &LoopCurve| {
            let mut v = Vec::new();
            c.scan(&mut |t, p| v.push((t.to_bits(), bits(p))));
            v
        };
        let fresh = points(&LoopCurve::new(&lp).unwrap());
        assert!(fresh.len() > 100 && fresh.iter().filter(|p| p.1.is_some()).count() > 100);
        let reused = LoopCurve::new(&lp).unwrap();
        for scan in 0..4 {
            assert_eq!(points(&reused), fresh, "scan {scan}");
        }
        assert!(reused.scanned.get().is_some(), "the points are kept");
        let mut crossings = 0;
        for fixed in [-0.02, 0.0, 0.01, 0.03, 0.2] {
            for free in [Free::Alpha, Free::Beta] {
                let once = line_crossings(&LoopCurve::new(&lp).unwrap(), free, fixed);
                crossings += once.len();
                let again = line_crossings(&reused, free, fixed);
                let to_bits = |v: Vec<f64>| v.into_iter().map(f64::to_bits).collect::<Vec<_>>();
                assert_eq!(to_bits(again), to_bits(once), "{free:?} at {fixed}");
            }
        }
        assert!(crossings >= 10, "{crossings} crossings");
    }

    /// The curve's walls have the root `e^{i theta}`, and its derivative matches a central
    /// difference, for loops with a hand and a filter; the scan's evaluation gives the same
    /// points.
    #[test]
    fn curve_has_the_root_and_its_derivative() {
        let plant = Plant::new(0.7, 1.3).unwrap();
        let loops = [
            Loop::new(plant)
                .with_hand(Hand::new(0.5, 0.2, 0.01).unwrap())
                .unwrap(),
            Loop::new(plant)
                .with_filter(VelocityFilter::low_pass(0.8).unwrap())
                .unwrap(),
            // a long delay's power of z factored out of Q0, and a longer filter
            Loop::new(Plant::new(0.7, 9.5).unwrap())
                .with_filter(VelocityFilter::moving_average(5).unwrap())
                .unwrap(),
        ];
        for lp in loops {
            let c = LoopCurve::new(&lp).unwrap();
            for t in [0.2, 0.9, 1.7, 2.8] {
                let p = c.eval(t).unwrap();
                let q = c.poly.coefficients(&Wall {
                    alpha: p.alpha,
                    beta: p.beta,
                });
                let z = Complex::from_polar(1.0, t);
                let v = q
                    .iter()
                    .rev()
                    .fold(Complex::new(0.0, 0.0), |acc, &k| acc * z + k);
                let scale: f64 = q.iter().map(|k| k.abs()).sum();
                assert!(v.norm() < 1e-12 * scale, "{t}: {v}");
                // the boundary engine's sample (no derivative) is the same wall
                let zk = Complex::from_polar(1.0, c.circle_power() as f64 * t);
                let w = c.wall_at(z, zk).unwrap();
                assert!((w.alpha - p.alpha).abs() <= 1e-12 * (1.0 + p.alpha.abs()));
                assert!((w.beta - p.beta).abs() <= 1e-12 * (1.0 + p.beta.abs()));
                // the scan's sample (shared powers of z, no Horner recurrence) is the same
                // point and derivative to rounding: a few hundred roundings of the sizes
                let s = c.scan_point(z, c.circle_powers(t, z)).unwrap();
                for (x, y) in [
                    (s.alpha, p.alpha),
                    (s.beta, p.beta),
                    (s.dalpha, p.dalpha),
                    (s.dbeta, p.dbeta),
                ] {
                    assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{t}: {s:?} {p:?}");
                }
                let h = 1e-6;
                let (a, b) = (c.eval(t + h).unwrap(), c.eval(t - h).unwrap());
                // central difference: error O(h^2) times the third derivative
                let fd = |x: f64, y: f64| (x - y) / (2.0 * h);
                assert!((p.dalpha - fd(a.alpha, b.alpha)).abs() <= 1e-6 * (1.0 + p.dalpha.abs()));
                assert!((p.dbeta - fd(a.beta, b.beta)).abs() <= 1e-6 * (1.0 + p.dbeta.abs()));
            }
        }
    }
}
