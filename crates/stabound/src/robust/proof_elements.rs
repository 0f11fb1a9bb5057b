//! The box recursion of [`super::prove_wall`] for the sets of loops with elements that the
//! paper loop's recursion (`proof.rs`) leaves out: a delay interval on a loop with elements,
//! an interval of a first- or second-order velocity filter's cutoff, of the actuator lag's
//! time constant, of a transmission's handle mass, coupling stiffness, coupling damping or
//! the share of the damping its loop names, and mass or damping intervals on a loop with a
//! transmission (`docs/MODEL.md` sections 8, 11 and 12).
//!
//! # Method
//!
//! A cell is an interval of each spread parameter in physical units. Its normalized
//! parameters are enclosed in outward-rounded interval arithmetic: `alpha m_ref / m`,
//! `beta m_ref / m`, `delta = b T / m`, the hand's `m_h / m`, `b_h T / m`, `k_h T^2 / m`, the
//! transmission's `r = m_2 / m`, `kappa_c = k_c T^2 / m`, `delta_c = b_c T / m` and its two
//! shares of the damping `b_1 T / m`, `b_2 T / m` (the share named given, the other `b`
//! less it), the lag's `tau = tau_a / T`, the low-pass pole `a = exp(-2 pi f_c T)`
//! (decreasing in the cutoff: enclosed by its ends) and the second-order filter's
//! `K = tan(pi f_c T)` (increasing below Nyquist: enclosed by its ends, each by the Taylor
//! series of `sin` and `cos` with a rigorous remainder). The device's sampled polynomial is then
//! enclosed over them by the certificate's route for loops with elements (the device
//! exponential by scaling, Taylor with a rigorous remainder and squaring; Faddeev-LeVerrier;
//! Van Loan 1978, Moler and Van Loan 2003), each step interval arithmetic, so the range
//! over the cell lies in the enclosures.
//!
//! A delay interval is cut at whole samples into pieces `[n, n + 1]`, each one family in
//! the fractional form, as for the paper's loop: the held force's sampling instant `eps`
//! enters through `Gamma(1 - eps)` and `e^{A (1 - eps)} Gamma(eps)`; at `eps = 0` the form is
//! `z` times the integer delay's polynomial (`Gamma(0) = 0`), at `eps = 1` the delay
//! `n + 1`'s. Over a sub-interval of the fraction the coefficients are taken in centred form
//! (the mean-value theorem, [`fraction_family`]): enclosed at the middle fraction, plus the
//! offset times their derivative in the fraction enclosed over the cell.
//!
//! A cell that spreads other parameters is taken in the mean-value form in them
//! ([`parameter_family`], up to [`MAX_CENTRED`] of them in the order of [`CENTRED`]): the
//! enclosure with those parameters at the cell's middle, plus each offset times the
//! coefficients' partial derivative in it enclosed over the cell, carried through every step
//! by forward differentiation in interval arithmetic (the exponential's derivatives by Van
//! Loan's block exponential in its block-triangular form). Its overestimation is second order
//! in the cell's width where the plain extension's, which lets each occurrence of a parameter
//! vary on its own, is first order: about 30 cells close an actuator lag's interval at a tenth
//! of a percent below the optimum where the plain extension needed 783, and a box of a
//! filter's cutoff and a lag's time constant, which a form in one of them (the other as an
//! interval) could not close within the budget, closes in both. A cell of one to four
//! spread parameters is taken to second order instead ([`second_order_family`]: the gradient
//! at the middle, the second derivatives over the cell); a box of a hand's mass and damping
//! and a filter's cutoff closes in 33 cells that way, where the first-order form in the three
//! needed about 8,500. Both forms take each side in a variable in which the continuous model
//! is linear (`variable`: Taylor's theorem holds in any variable that maps the side's
//! interval one to one onto an interval): the mass in `m_0 / m` (without a transmission), an
//! actuator lag in its rate `T / tau_a`, a first-order filter's cutoff in its pole and a
//! hand's mass in its share `m_0 / (m_0 + m_h)`. In the sides themselves their second derivatives carry those of
//! `1 / m`, `e^{-T / tau_a}` or `1 / (1 + m_h / m)`, sums of terms that cancel, which
//! interval arithmetic encloses many times wider than their range (the box of a hand's mass
//! and damping and a cutoff closes in 13 cells with the variables).
//!
//! The cells are decided, halved and queued by the paper loop's recursion (`proof.rs`:
//! Rouche's theorem around the midpoint polynomial with second-order arc bounds, then the
//! interval Schur-Cohn recursion, Schur 1917, Cohn 1922; an undecided cell is halved across
//! the side whose halving narrows the enclosures most, breadth-first, until the budget of
//! cells runs out); only the enclosure of a cell is this module's. The midpoint polynomial
//! of Rouche's test, and its slope in the centred forms, recover the correlation the final
//! interval recursion would lose.

use std::cell::RefCell;

use super::proof::{self, CellDelay, Family, Proof, ProofCell};
use super::{DeviceSet, Quantity};
use crate::certificate::tangent::{Dual, Dual2};
use crate::certificate::{
    DeviceSpread, ElementSpread, Scalar, fraction_family, parameter_family, parts_spread,
    second_derivatives, second_order_family,
};
use crate::elements::Loop;
use crate::enclosure::interval::{self, Interval};
use crate::error::Result;
use crate::params::Wall;

/// The sides of a cell, `[lo, hi]` in physical units: mass, damping, the hand's mass,
/// damping and stiffness, the filter's cutoff, the lag's time constant, the handle mass, the
/// coupling stiffness, the coupling damping and the named share of the damping (zero for an
/// element not named).
type Sides = [(f64, f64); SIDES];

const SIDES: usize = 11;
const MASS: usize = 0;
const DAMPING: usize = 1;
const HAND: usize = 2;
const CUTOFF: usize = 5;
const LAG: usize = 6;
const HANDLE_MASS: usize = 7;
const COUPLING_STIFFNESS: usize = 8;
const COUPLING_DAMPING: usize = 9;
const SHARE: usize = 10;

/// The sides a cell's centred form is taken in, in this order of preference when a cell
/// spreads several (the others enter as intervals): the elements' parameters, whose plain
/// extensions are widest, then the device's.
const CENTRED: [usize; 11] = [
    CUTOFF,
    LAG,
    HANDLE_MASS,
    COUPLING_STIFFNESS,
    COUPLING_DAMPING,
    SHARE,
    MASS,
    DAMPING,
    HAND,
    HAND + 1,
    HAND + 2,
];

/// One cell of the recursion.
type Cell = proof::Cell<SIDES>;

/// Which share of the device's damping a transmission's loop names (the other side takes
/// the rest of `b`; the named share is the side [`SHARE`]): the motor side's `b_1`, or the
/// handle side's `b_2` (zero when neither is named).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Share {
    Motor,
    Handle,
}

/// One box of a set: the loop at its low corner, its sides, the sampling period, the
/// damping's split, whether it spreads the filter's cutoff, and the delay factors
/// `[lo, hi]` (equal ends: one delay).
struct ElementBox {
    lp: Loop,
    sides: Sides,
    period: f64,
    share: Share,
    cutoff: bool,
    delay: (f64, f64),
}

#[cfg(test)]
thread_local! {
    /// How many times [`boxes`] ran on this thread: the search's tests count its passes.
    pub(super) static BUILT: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The boxes of `set` when this recursion applies to it, otherwise the first quantity whose
/// interval it does not enclose: a filter's cutoff other than a low-pass's, or the share of
/// the damping the loop does not name.
fn boxes(set: &DeviceSet) -> Result<std::result::Result<Vec<ElementBox>, Quantity>> {
    #[cfg(test)]
    BUILT.with(|n| n.set(n.get() + 1));
    let mut out = Vec::new();
    for v in set.variants() {
        let dev = v.base.device;
        let lp = v.base.to_loop()?;
        let e = &v.base.elements;
        let at = |x: Option<f64>| {
            let x = x.unwrap_or(0.0);
            (x, x)
        };
        let d = dev.plant()?.d();
        let (share, named) = match (e.motor_damping, e.handle_damping) {
            (Some(b1), _) => (Share::Motor, b1),
            (None, b2) => (Share::Handle, b2.unwrap_or(0.0)),
        };
        let low_pass = lp.low_pass_pole().is_some() || lp.filter().is_prewarped();
        let mut b = ElementBox {
            lp,
            sides: [
                (dev.mass, dev.mass),
                (dev.damping, dev.damping),
                at(e.hand_mass),
                at(e.hand_damping),
                at(e.hand_stiffness),
                at(e.velocity_filter_cutoff),
                at(e.actuator_time_constant),
                at(e.handle_mass),
                at(e.transmission_stiffness),
                at(e.transmission_damping),
                (named, named),
            ],
            period: dev.period,
            share,
            cutoff: false,
            delay: (d, d),
        };
        for &(q, lo, hi) in &v.dims {
            let side = match q {
                Quantity::Mass => MASS,
                Quantity::Damping => DAMPING,
                Quantity::Delay => {
                    b.delay = proof::delay_factors(&dev, lo, hi);
                    continue;
                }
                Quantity::Element(p) => match p.keyword {
                    "hand_mass" => HAND,
                    "hand_damping" => HAND + 1,
                    "hand_stiffness" => HAND + 2,
                    "velocity_filter_cutoff" if low_pass => {
                        b.cutoff = true;
                        CUTOFF
                    }
                    "actuator_time_constant" => LAG,
                    "handle_mass" => HANDLE_MASS,
                    "transmission_stiffness" => COUPLING_STIFFNESS,
                    "transmission_damping" => COUPLING_DAMPING,
                    "motor_damping" if share == Share::Motor => SHARE,
                    "handle_damping" if share == Share::Handle && lp.transmission().is_some() => {
                        SHARE
                    }
                    _ => return Ok(Err(q)),
                },
            };
            b.sides[side] = (lo, hi);
        }
        out.push(b);
    }
    Ok(Ok(out))
}

/// `2 pi` enclosed: `std::f64::consts::PI` is `pi` rounded to nearest, below it, and the next
/// number up is above it; doubling is exact.
fn two_pi() -> Interval {
    let pi = std::f64::consts::PI;
    Interval::new(2.0 * pi, 2.0 * pi.next_up())
}

/// The low-pass pole `a = exp(-2 pi f_c T)` over the cutoffs `fc` (Hz) at the period `t`,
/// widened by a relative `2e-15` so that it holds the poles the loops of the members compute
/// in `f64` too: their argument rounds twice (at most `2^-52` of it, below `7e-16` for the
/// arguments up to `pi` of cutoffs up to Nyquist) and `exp` by about a unit, `1.1e-16`.
fn pole<T: Scalar>(fc: T, t: Interval) -> T {
    let a = (T::constant(two_pi() * t) * fc).nonneg().exp_neg();
    let rel = Interval::new(1.0 - 2e-15, 1.0 + 2e-15);
    a * T::constant(rel)
}

/// The second-order filter's `K = tan(pi f_c T)` over the cutoffs `fc` (Hz) at the period
/// `t` (a prewarped filter), its derivative `pi T (1 + K^2)` and second derivative
/// `2 (pi T)^2 K (1 + K^2)`. The argument `pi f_c T` is
/// enclosed in interval arithmetic and `tan` over it by its Taylor series with a rigorous
/// remainder ([`interval::tan`]: `sin` and `cos` summed in outward-rounded arithmetic, the
/// range of the increasing `tan` from the ends); an argument that reaches `pi / 2` is the
/// whole line. That encloses the exact `K` of every cutoff of the cell; each member's own
/// `f64` route rounds its `K` by a few units more, which the coefficients' comparisons
/// allow for.
fn prewarp<T: Scalar>(fc: T, t: Interval) -> T {
    let pi = std::f64::consts::PI;
    let arg = T::constant(Interval::new(pi, pi.next_up()) * t) * fc;
    let one = Interval::point(1.0);
    arg.chain2(
        interval::tan,
        |x| {
            let k = interval::tan(x);
            one + k * k
        },
        // (tan)'' = 2 tan (1 + tan^2)
        |x| {
            let k = interval::tan(x);
            Interval::point(2.0) * k * (one + k * k)
        },
    )
}

/// The wall's polynomials over every member of one cell: for a cell of fractions of a
/// delay their centred form in the fraction ([`fraction_family`]); for a cell that spreads
/// one to four parameters, their second-order form in them ([`second_order`]); for more,
/// their mean-value form ([`parameter_family`]: in each spread side, up to [`MAX_CENTRED`] of
/// them in the order of [`CENTRED`], the others as intervals); otherwise the enclosures of
/// their coefficients (module documentation).
#[cfg(test)]
fn family(wall: &Wall, m_ref: f64, b: &ElementBox, cell: Cell) -> Family {
    family_kept(wall, m_ref, b, cell, &Kept::default())
}

/// Second derivatives already enclosed over cells of one box: `(cell's sides, N,
/// H_kl of each coefficient flattened, N x N per coefficient)`. A cell inside a kept one
/// takes its second derivatives from it (they hold over the smaller cell too: each side's
/// variable is one map of the side for the whole box, [`variable`]) when the kept cell's
/// volume in the spread sides is at most [`REUSE`] times its own; they enter the form times
/// the offsets squared, so the wider enclosure costs little, and the exponential with
/// second derivatives, most of a cell's cost, is computed once for a few levels of
/// halving. With a hand's mass taken in its share `m_0 / (m_0 + m_h)` this holds for a
/// hand's sides with the lag too (a box of a hand's mass, a cutoff and a lag: 186 cells and
/// 1,069 M instructions with the reuse, 174 cells and 1,504 M taking them afresh in every
/// cell; in the hand's mass itself its second derivatives widened with the cell faster than
/// its width, and the reuse cost more cells than it saved).
type Kept = RefCell<Vec<(Sides, usize, Vec<Interval>)>>;

/// How much larger (in volume over the spread sides) a kept cell may be than the cell that
/// takes its second derivatives: two halvings.
const REUSE: f64 = 4.0;

/// [`family`] with the second derivatives kept over earlier cells of the same box.
fn family_kept(wall: &Wall, m_ref: f64, b: &ElementBox, cell: Cell, kept: &Kept) -> Family {
    let (sides, _) = cell;
    let (el, device, a, beta) = spread_of(wall, m_ref, b, cell, |_, x| x);
    if let Some(f) = fraction_family(&b.lp, &device, &el, a, beta) {
        return Family::Centred(f.into());
    }
    let spread: Vec<usize> = CENTRED
        .into_iter()
        .filter(|&i| sides[i].1 > sides[i].0)
        .collect();
    match spread.len() {
        0 => Family::Plain(parts_spread(&b.lp, &device, &el).at(a, beta)),
        1 => second_order::<1>(wall, m_ref, b, cell, &spread, kept),
        2 => second_order::<2>(wall, m_ref, b, cell, &spread, kept),
        3 => second_order::<3>(wall, m_ref, b, cell, &spread, kept),
        4 => second_order::<4>(wall, m_ref, b, cell, &spread, kept),
        _ => centred::<MAX_CENTRED>(wall, m_ref, b, cell, &spread),
    }
}

/// The most sides a cell's mean-value form is taken in: each costs two products of the
/// exponential's size per product ([`Dual`]), and a box rarely spreads more.
const MAX_CENTRED: usize = 3;

/// The cell `sides` with the sides `chosen` at their middles, and each chosen side with the
/// offsets of its variable from the middle's, rounded outward ([`variable`]: the side itself,
/// `[lo - mid, hi - mid]`; for a side taken in another variable, the middle is the member
/// whose variable is the midpoint of the variable's enclosure over the side ([`member`]),
/// and the offsets are that enclosure less the variable's enclosure at the middle, so that
/// they hold every member's offset from the middle's variable, which the centre encloses).
fn middle_of<const N: usize>(
    sides: Sides,
    chosen: [usize; N],
    b: &ElementBox,
) -> (Sides, [(usize, Interval); N]) {
    let mut middle = sides;
    let offsets = chosen.map(|i| {
        let (lo, hi) = sides[i];
        let v = variable(b, i, Interval::new(lo, hi));
        // a member within [lo, hi] (the variable's midpoint lies within its enclosure,
        // which rounds by a few units at most beyond the ends' images); clamped so that
        // the middle stays a member of the cell
        let mid = match member(b, i, 0.5 * v.lo() + 0.5 * v.hi()) {
            Some(x) if x.is_finite() => x.clamp(lo, hi),
            _ => 0.5 * lo + 0.5 * hi,
        };
        middle[i] = (mid, mid);
        let at = |x: Interval| variable(b, i, x);
        (i, at(Interval::new(lo, hi)) - at(Interval::point(mid)))
    });
    (middle, offsets)
}

/// The variable a cell's forms take side `i` of box `b` in, over the values `x` of the side
/// (rounded outward): the side itself, but
///
/// - for the mass (on a loop without a transmission) `w = m_0 / m`, `m_0` the box's lowest
///   mass: the wall's `alpha m_ref / m` and `beta m_ref / m` and every parameter per mass
///   (`delta = b T / m`, the hand's) are linear in it, where in `m` they carry the second
///   derivatives of `1 / m`;
/// - for the lag its rate `T / tau_a`, in which the continuous model's entries are linear
///   (`-1 / tau` and `1 / tau`, `tau = tau_a / T`): in `tau_a` the lag's second derivatives
///   are `e^{-1 / tau}` times `1 / tau^4 - 2 / tau^3` (in units of `T`), two terms that
///   cancel to a fifth near `tau = 0.6`, which interval arithmetic cannot see (the lag's
///   second derivative of `e^{-1 / tau}` over a cell of 0.58 to 0.59 ms behind a hand was
///   enclosed 14 times wider than its range);
/// - for a first-order low-pass filter's cutoff its pole `a = exp(-2 pi f_c T)` ([`pole`]),
///   in which the filter's coefficients `1 - a` and `-a` are linear: the polynomial, a sum
///   of products with one filter coefficient each, is then affine in it (no second
///   derivative of its own, the cross ones products of first derivatives);
/// - for a hand's mass (on a loop without a transmission) the share `s = m_0 / (m_0 + m_h)`
///   of the box's lowest mass `m_0`, in which the continuous model's entries `k_h s`,
///   `(delta + delta_h) s` and the force's gain `s` are linear where the mass is one value
///   (`1 / (1 + m_h / m) = s` when `m = m_0`): in `m_h` they carry the second derivatives of
///   `1 / (1 + m_h / m)`, which the exponential and the assembly of the polynomial widen.
///
/// Taylor's theorem holds in any variable that maps the side's interval one to one onto an
/// interval (each of these is monotone in its side), and each is a function of its side
/// alone, so a cell's sides map onto a box of variables.
fn variable(b: &ElementBox, i: usize, x: Interval) -> Interval {
    match i {
        MASS if mass_side(b) => Interval::point(b.sides[MASS].0) / x,
        LAG => Interval::point(b.period) / x,
        CUTOFF if pole_side(b) => pole(x, Interval::point(b.period)),
        HAND if share_side(b) => {
            let m0 = Interval::point(b.sides[MASS].0);
            m0 / (m0 + x)
        }
        _ => x,
    }
}

/// The member of side `i` of box `b` whose [`variable`] is `v`, in `f64` (any member of the
/// side will do: the offsets are taken from the enclosures); `None` for a side taken in
/// itself.
fn member(b: &ElementBox, i: usize, v: f64) -> Option<f64> {
    match i {
        MASS if mass_side(b) => Some(b.sides[MASS].0 / v),
        LAG => Some(b.period / v),
        CUTOFF if pole_side(b) => Some(-v.ln() / (2.0 * std::f64::consts::PI * b.period)),
        HAND if share_side(b) => Some(b.sides[MASS].0 * (1.0 / v - 1.0)),
        _ => None,
    }
}

/// Whether box `b`'s mass is taken in `m_0 / m` ([`variable`]): on a loop without a
/// transmission (with one, the entries `k_c / (1 - r)` are no more linear in it than in
/// the mass, and a box of the mass and a hand's mass took 1,723 cells in it against 956).
fn mass_side(b: &ElementBox) -> bool {
    b.lp.transmission().is_none()
}

/// Whether box `b`'s cutoff is taken in the first-order low-pass pole ([`variable`]).
fn pole_side(b: &ElementBox) -> bool {
    b.cutoff && !b.lp.filter().is_prewarped()
}

/// Whether box `b`'s hand mass is taken in the share `m_0 / (m_0 + m_h)` ([`variable`]).
fn share_side(b: &ElementBox) -> bool {
    b.lp.hand().is_some() && b.lp.transmission().is_none()
}

/// The mean-value form of the wall's polynomials over `cell` in its first `N` spread sides
/// `spread` (the rest of them as intervals): the enclosure with those sides at their
/// middles, and the partial derivatives in them over the cell ([`parameter_family`]).
fn centred<const N: usize>(
    wall: &Wall,
    m_ref: f64,
    b: &ElementBox,
    (sides, delay): Cell,
    spread: &[usize],
) -> Family {
    let chosen: [usize; N] = std::array::from_fn(|k| spread[k]);
    let (middle, offsets) = middle_of(sides, chosen, b);
    let (el_c, device_c, a_c, beta_c) = spread_of(wall, m_ref, b, (middle, delay), |_, x| x);
    let seed = |i: usize, x: Interval| match chosen.iter().position(|&c| c == i) {
        Some(k) => Dual::<N>::variable(x, k),
        None => Dual::constant(x),
    };
    let (el_d, device_d, a_d, beta_d) = spread_of(wall, m_ref, b, (sides, delay), seed);
    Family::Centred(parameter_family(
        &b.lp,
        (&device_c, &el_c, a_c, beta_c),
        (&device_d, &el_d, a_d, beta_d),
        offsets,
        spread.len() == N,
    ))
}

/// The second-order form of the wall's polynomials over `cell` in its `N` spread sides
/// `spread` ([`second_order_family`]): the enclosure with those sides at their middles, the
/// partial derivatives there, and the second partial derivatives over the cell.
fn second_order<const N: usize>(
    wall: &Wall,
    m_ref: f64,
    b: &ElementBox,
    (sides, delay): Cell,
    spread: &[usize],
    kept: &Kept,
) -> Family {
    let chosen: [usize; N] = std::array::from_fn(|k| spread[k]);
    let (middle, offsets) = middle_of(sides, chosen, b);
    let position = |i: usize| chosen.iter().position(|&c| c == i);
    let at_middle = |i: usize, x: Interval| match position(i) {
        Some(k) => Dual::<N>::variable(x, k),
        None => Dual::constant(x),
    };
    let (el_m, device_m, a_m, beta_m) = spread_of(wall, m_ref, b, (middle, delay), at_middle);
    let over = |i: usize, x: Interval| match position(i) {
        Some(k) => Dual2::<N>::variable(x, k),
        None => Dual2::constant(x),
    };
    let volume = |s: &Sides| chosen.iter().map(|&i| s[i].1 - s[i].0).product::<f64>();
    let inside = |s: &Sides| (0..SIDES).all(|i| s[i].0 <= sides[i].0 && sides[i].1 <= s[i].1);
    let found = kept.borrow().iter().rev().find_map(|(s, n, h)| {
        (*n == N && inside(s) && volume(s) <= REUSE * volume(&sides)).then(|| {
            h.chunks(N * N)
                .map(|c| std::array::from_fn(|k| std::array::from_fn(|l| c[k * N + l])))
                .collect::<Vec<[[Interval; N]; N]>>()
        })
    });
    let hessians = found.unwrap_or_else(|| {
        let (el_d, device_d, a_d, beta_d) = spread_of(wall, m_ref, b, (sides, delay), over);
        let h = second_derivatives(&b.lp, (&device_d, &el_d, a_d, beta_d));
        let flat = h.iter().flatten().flatten().copied().collect();
        kept.borrow_mut().push((sides, N, flat));
        h
    });
    Family::Centred(second_order_family(
        &b.lp,
        (&device_m, &el_m, a_m, beta_m),
        &hessians,
        offsets,
        spread.len() == N,
    ))
}

/// The enclosures of the wall's coefficients (lowest power first) over every member of one
/// cell (module documentation).
#[cfg(test)]
fn enclose(wall: &Wall, m_ref: f64, b: &ElementBox, cell: Cell) -> Vec<Interval> {
    let (el, device, a, beta) = spread_of(wall, m_ref, b, cell, |_, x| x);
    parts_spread(&b.lp, &device, &el).at(a, beta)
}

/// The normalized parameters of one cell (module documentation): the elements', the
/// device's, and the wall's `alpha m_ref / m` and `beta m_ref / m`, in the arithmetic `T`
/// into which `lift` takes side `i`'s variable over the cell ([`variable`]).
fn spread_of<T: Scalar>(
    wall: &Wall,
    m_ref: f64,
    b: &ElementBox,
    (sides, delay): Cell,
    lift: impl Fn(usize, Interval) -> T,
) -> (ElementSpread<T>, DeviceSpread<T>, T, T) {
    let side = |i: usize| lift(i, Interval::new(sides[i].0, sides[i].1));
    // side `i` in its variable ([`variable`])
    let var = |i: usize| lift(i, variable(b, i, Interval::new(sides[i].0, sides[i].1)));
    let k = |x: f64| T::constant(Interval::point(x));
    // the mass in its variable `w = m_0 / m` ([`variable`]): `1 / m = w / m_0`
    let m0 = k(b.sides[MASS].0);
    let (w, inv_m) = if mass_side(b) {
        let w = var(MASS);
        (w, w * (k(1.0) / m0))
    } else {
        let inv_m = k(1.0) / side(MASS);
        (m0 * inv_m, inv_m)
    };
    let scale = k(m_ref) * inv_m;
    let a = k(wall.alpha()) * scale;
    let beta = k(wall.beta()) * scale;
    let t = k(b.period);
    let per_mass = |x: T| (x * inv_m).nonneg();
    // the hand's mass from its share `s = m_0 / (m_0 + m_h)`: `m_h / m = w (1 / s - 1)`,
    // and the force's gain `1 / (1 + m_h / m) = s / (w + s (1 - w))`, which is `s` itself
    // where the mass is one value, `m_0` (exact: then no arithmetic is needed)
    let hand_share = share_side(b).then(|| var(HAND));
    let hand_mass = match hand_share {
        Some(s) => (w * (k(1.0) / s - k(1.0))).nonneg(),
        None => per_mass(side(HAND)),
    };
    let hand_gain = hand_share.map(|s| {
        // exact: a box whose mass is one value
        if b.sides[MASS].0 == b.sides[MASS].1 {
            s
        } else {
            s / (w + s * (k(1.0) - w))
        }
    });
    let device = DeviceSpread {
        delta: per_mass(side(DAMPING) * t),
        hand: [
            hand_mass,
            per_mass(side(HAND + 1) * t),
            per_mass(side(HAND + 2) * t * t),
        ],
    };
    let transmission = b.lp.transmission().map(|_| {
        let (named, rest) = (side(SHARE), (side(DAMPING) - side(SHARE)).nonneg());
        let (b1, b2) = match b.share {
            Share::Motor => (named, rest),
            Share::Handle => (rest, named),
        };
        [
            per_mass(side(HANDLE_MASS)),
            per_mass(side(COUPLING_STIFFNESS) * t * t),
            per_mass(side(COUPLING_DAMPING) * t),
            per_mass(b1 * t),
            per_mass(b2 * t),
        ]
    });
    let period = Interval::point(b.period);
    let second = b.lp.filter().is_prewarped();
    let el = ElementSpread {
        transmission,
        rate: b.lp.actuator().map(|_| var(LAG)),
        pole: pole_side(b).then(|| var(CUTOFF)),
        hand_gain,
        prewarp: (b.cutoff && second).then(|| prewarp(side(CUTOFF), period)),
        delay: match delay {
            CellDelay::Point(_) => None,
            CellDelay::Piece { n, frac } => Some((n, Interval::new(frac.0, frac.1))),
        },
    };
    (el, device, a, beta)
}

/// The most cells a box of three or more spread parameters (one delay) is given, a share of
/// its own (the set's other boxes, such as the device let go, keep theirs): the ones the
/// second-order form closes take tens to a few hundred in `alpha_max`'s verification, each
/// side in its [`variable`] (a hand's mass and damping and a cutoff, 13 in all; the mass,
/// damping and a lag, 16; the mass, a cutoff and a lag, 95; a hand's mass, a cutoff and a
/// lag, 186; with the hand's damping too, four sides, 360; a few million instructions a
/// cell); a box that needs more keeps the sampling argument's answer rather than wait for
/// it.
const THREE_SIDE_BUDGET: usize = 1024;

/// Proves `wall` stable for every member of `set` by the box recursion over the loops with
/// elements (module documentation), examining at most `budget` cells (a box that spreads
/// three parameters or more at most [`THREE_SIDE_BUDGET`] of them); the first parameter
/// the set spreads that this recursion does not enclose, when there is one.
///
/// # Errors
///
/// As [`crate::elements::Loop::physical`] for a member; [`crate::Error::Cancelled`] when
/// cancelled.
pub(super) fn prove_wall(
    set: &DeviceSet,
    wall: &Wall,
    budget: usize,
) -> Result<std::result::Result<Proof, Quantity>> {
    let boxes = match boxes(set)? {
        Ok(b) => b,
        Err(q) => return Ok(Err(q)),
    };
    // a box of three spread parameters or more (one delay) is given its own share
    let share = |b: &ElementBox| {
        let spread = CENTRED.iter().filter(|&&i| b.sides[i].1 > b.sides[i].0);
        // exact: equal ends are one delay (no delay piece to centre)
        if b.delay.0 == b.delay.1 && spread.count() >= 3 {
            budget.min(THREE_SIDE_BUDGET)
        } else {
            budget
        }
    };
    let m_ref = set.device.mass;
    let leaf = |(sides, delay): Cell, stable| ProofCell {
        mass: sides[MASS],
        damping: sides[DAMPING],
        delay: delay.span(),
        hand: [sides[HAND], sides[HAND + 1], sides[HAND + 2]],
        elements: [
            sides[CUTOFF],
            sides[LAG],
            sides[HANDLE_MASS],
            sides[COUPLING_STIFFNESS],
            sides[COUPLING_DAMPING],
        ],
        stable,
    };
    let cells = boxes
        .iter()
        .map(|b| (b, proof::start(b.sides, b.delay), share(b)));
    // second derivatives kept per box (the boxes are decided one after the other)
    let kept: Vec<Kept> = boxes.iter().map(|_| Kept::default()).collect();
    let index = |b: &ElementBox| boxes.iter().position(|x| std::ptr::eq(x, b)).unwrap_or(0);
    let enclosed = |b: &ElementBox, c| family_kept(wall, m_ref, b, c, &kept[index(b)]);
    proof::recurse(cells, enclosed, leaf, budget).map(Ok)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certificate::tangent::MeanValueForm;
    use crate::elements::PhysicalElements;
    use crate::params::{Delay, Device};
    use crate::stability::{Checker, Options};

    /// Whether each enclosure holds the matching value, to a relative `1e-12` of the
    /// largest coefficient: the `f64` route (`elements::discrete`, a floating-point matrix
    /// exponential) rounds each coefficient by a few hundred units of that at most.
    fn encloses(enclosures: &[Interval], values: &[f64]) -> bool {
        let scale = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        enclosures.len() == values.len()
            && enclosures
                .iter()
                .zip(values)
                .all(|(e, &v)| e.contains(v, 1e-12 * scale))
    }

    /// An enclosure over a cell that spreads the mass, the damping, the filter's cutoff, the
    /// lag's time constant, the handle mass, the coupling's stiffness and damping and a
    /// piece of delay holds the `f64` coefficients of the loops at the cell's 256 corners
    /// and its centre (a hand on the handle; the handle side's damping named, so the motor
    /// side's share moves with the damping).
    #[test]
    fn element_enclosures_hold_every_member() {
        let named = PhysicalElements {
            hand_mass: Some(0.2),
            hand_stiffness: Some(200.0),
            handle_mass: Some(0.03),
            transmission_stiffness: Some(5e4),
            transmission_damping: Some(2.0),
            handle_damping: Some(0.1),
            actuator_time_constant: Some(3e-4),
            velocity_filter_cutoff: Some(40.0),
            ..Default::default()
        };
        let device = Device::new(0.1, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
        let lp = Loop::physical(&device, &named).unwrap();
        let mut sides: Sides = [(0.0, 0.0); SIDES];
        sides[MASS] = (0.1, 0.11);
        sides[DAMPING] = (0.5, 0.6);
        sides[HAND] = (0.2, 0.2);
        sides[HAND + 2] = (200.0, 200.0);
        sides[CUTOFF] = (40.0, 44.0);
        sides[LAG] = (3e-4, 3.3e-4);
        sides[HANDLE_MASS] = (0.03, 0.032);
        sides[COUPLING_STIFFNESS] = (5e4, 5.5e4);
        sides[COUPLING_DAMPING] = (2.0, 2.2);
        sides[SHARE] = (0.1, 0.1);
        let b = ElementBox {
            lp,
            sides,
            period: 1e-3,
            share: Share::Handle,
            cutoff: true,
            delay: (1.0, 2.0),
        };
        let frac = (0.0, 0.25);
        let cell = enclose(
            &Wall::new(0.3, 0.2).unwrap(),
            0.1,
            &b,
            (sides, CellDelay::Piece { n: 1, frac }),
        );
        let spread = [MASS, DAMPING, CUTOFF, LAG, HANDLE_MASS, COUPLING_STIFFNESS];
        for corner in 0..=256u32 {
            // 256: the centre; below it, the corners (the seventh bit the fraction, the
            // eighth the coupling damping)
            let pick = |bit: u32, (lo, hi): (f64, f64)| {
                if corner == 256 {
                    0.5 * (lo + hi)
                } else if corner >> bit & 1 == 1 {
                    hi
                } else {
                    lo
                }
            };
            let at = |i: usize| {
                let bit = spread.iter().position(|&s| s == i).map_or(7, |k| k as u32);
                pick(bit, sides[i])
            };
            let eps = pick(6, frac);
            let dev = Device::new(at(MASS), 1e-3, at(DAMPING), Delay::Samples(1.0 + eps)).unwrap();
            let mut e = named;
            e.velocity_filter_cutoff = Some(at(CUTOFF));
            e.actuator_time_constant = Some(at(LAG));
            e.handle_mass = Some(at(HANDLE_MASS));
            e.transmission_stiffness = Some(at(COUPLING_STIFFNESS));
            e.transmission_damping = Some(at(COUPLING_DAMPING));
            let s = 0.1 / at(MASS);
            let mut q = Checker::new(Loop::physical(&dev, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&Wall::new(0.3 * s, 0.2 * s).unwrap());
            // exact: the fraction 0 is the integer delay, one degree less
            if eps == 0.0 {
                q.insert(0, 0.0);
            }
            assert!(encloses(&cell, &q), "{corner}: {cell:?} {q:?}");
        }
    }

    /// The centred form over a cell of fractions of a delay behind a 50 Hz filter, with a
    /// hand, the mass and the cutoff spread too, holds the `f64` coefficients of the loops
    /// at 41 fractions of the cell, each at its own offset from the centre fraction, at the
    /// four corners of mass and cutoff.
    #[test]
    fn centred_fraction_form_holds_every_fraction() {
        let named = PhysicalElements {
            hand_mass: Some(0.2),
            hand_stiffness: Some(300.0),
            velocity_filter_cutoff: Some(50.0),
            ..Default::default()
        };
        let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(2.0)).unwrap();
        let lp = Loop::physical(&device, &named).unwrap();
        let mut sides: Sides = [(0.0, 0.0); SIDES];
        sides[MASS] = (0.1, 0.101);
        sides[DAMPING] = (1.0, 1.0);
        sides[HAND] = (0.2, 0.2);
        sides[HAND + 2] = (300.0, 300.0);
        sides[CUTOFF] = (50.0, 50.5);
        let b = ElementBox {
            lp,
            sides,
            period: 1e-3,
            share: Share::Handle,
            cutoff: true,
            delay: (2.0, 3.0),
        };
        let wall = Wall::new(0.3, 0.2).unwrap();
        let frac = (0.25, 0.5);
        let Family::Centred(f) = family(&wall, 0.1, &b, (sides, CellDelay::Piece { n: 2, frac }))
        else {
            panic!("a cell of fractions has the centred form");
        };
        let e_c = 0.375;
        for k in 0..=40 {
            let eps = 0.25 + 0.25 * f64::from(k) / 40.0;
            let offset = Interval::point(eps) - Interval::point(e_c);
            let at_eps: Vec<Interval> = f
                .centre
                .iter()
                .zip(&f.slopes[0].slope)
                .map(|(&c, &s)| c + s * offset)
                .collect();
            for (m, fc) in [(0.1, 50.0), (0.1, 50.5), (0.101, 50.0), (0.101, 50.5)] {
                let dev = Device::new(m, 1e-3, 1.0, Delay::Samples(2.0 + eps)).unwrap();
                let mut e = named;
                e.velocity_filter_cutoff = Some(fc);
                let s = 0.1 / m;
                let q = Checker::new(Loop::physical(&dev, &e).unwrap(), Options::default())
                    .unwrap()
                    .coefficients(&Wall::new(0.3 * s, 0.2 * s).unwrap());
                assert!(encloses(&at_eps, &q), "{eps} {m} {fc}: {at_eps:?} {q:?}");
            }
        }
    }

    /// The centred form of one cell of the parameter `keyword` (side `k`), the set's other
    /// parameters as `named` on `device`, holds the `f64` coefficients of the loops at 41
    /// values of the parameter across the cell, each at its own offset from the middle
    /// (`centre + slope (p - p_c)`); and the sum of its widths is below the plain interval
    /// extension's over the cell divided by `gain`. Returns the ratio of the two sums.
    fn centred_holds(
        device: &Device,
        named: &PhysicalElements,
        (keyword, k): (&str, usize),
        (lo, hi): (f64, f64),
        gain: f64,
    ) -> f64 {
        use crate::robust::Quantity;
        let put = |e: &mut PhysicalElements, d: &mut Device, x: f64| match keyword {
            "mass" => *d = Device::new(x, d.period, d.damping, d.delay).unwrap(),
            "velocity_filter_cutoff" => e.velocity_filter_cutoff = Some(x),
            "actuator_time_constant" => e.actuator_time_constant = Some(x),
            "handle_mass" => e.handle_mass = Some(x),
            "transmission_stiffness" => e.transmission_stiffness = Some(x),
            "transmission_damping" => e.transmission_damping = Some(x),
            _ => e.motor_damping = Some(x),
        };
        let quantity = match keyword {
            "mass" => Quantity::Mass,
            _ => Quantity::element(keyword).unwrap(),
        };
        let set = DeviceSet::new(device, named)
            .unwrap()
            .with_interval(quantity, lo, hi)
            .unwrap();
        let b = boxes(&set).unwrap().unwrap().remove(0);
        let m_ref = device.mass;
        let wall = Wall::new(0.05, 0.2).unwrap();
        let cell = (b.sides, CellDelay::Point(1.0));
        let spread = [k];
        let Family::Centred(f) = centred::<1>(&wall, m_ref, &b, cell, &spread) else {
            panic!("{keyword}: a cell of a parameter has the centred form");
        };
        let Family::Centred(second) = family(&wall, m_ref, &b, cell) else {
            panic!("{keyword}: a cell of a parameter has the second-order form");
        };
        assert_eq!(second.slopes.len(), 2);
        // the form's variable (the lag's rate) at the member less at the middle
        let (middle, _) = middle_of(b.sides, [k], &b);
        let at = |x: f64| variable(&b, k, Interval::point(x));
        for j in 0..=40 {
            let x = lo + (hi - lo) * f64::from(j) / 40.0;
            let offset = at(x) - at(middle[k].0);
            let at_x = form_at(&f, &[offset]);
            // the gradient at the middle times the offset, the second derivative over the
            // cell times half its square
            let at_x_second = form_at(&second, &[offset, offset * offset]);
            let (mut e, mut d) = (*named, *device);
            put(&mut e, &mut d, x);
            let s = m_ref / d.mass;
            let q = Checker::new(Loop::physical(&d, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&Wall::new(0.05 * s, 0.2 * s).unwrap());
            assert!(encloses(&at_x, &q), "{keyword} {x}: {at_x:?} {q:?}");
            assert!(
                encloses(&at_x_second, &q),
                "{keyword} {x}: {at_x_second:?} {q:?}"
            );
        }
        let width = |c: &[Interval]| c.iter().map(|c| c.hi() - c.lo()).sum::<f64>();
        let ratio = width(&enclose(&wall, m_ref, &b, cell)) / width(&f.coefficients());
        assert!(ratio > gain, "{keyword}: {ratio}");
        assert_eq!(
            k,
            CENTRED
                .into_iter()
                .find(|&i| b.sides[i].1 > b.sides[i].0)
                .unwrap()
        );
        ratio
    }

    /// `centre + sum_s slope_s t_s` of the form `f` at the offsets `t` (one per slope).
    fn form_at(f: &MeanValueForm, t: &[Interval]) -> Vec<Interval> {
        assert_eq!(f.slopes.len(), t.len());
        let mut out = f.centre.clone();
        for (s, &t) in f.slopes.iter().zip(t) {
            for (c, &d) in out.iter_mut().zip(&s.slope) {
                *c = *c + d * t;
            }
        }
        out
    }

    /// The second-order form over a cell of a filter's cutoff and a lag's time constant
    /// (`g_1 t_1 + g_2 t_2 + H_11 / 2 t_1^2 + H_12 t_1 t_2 + H_22 / 2 t_2^2` around the
    /// middle, `t_2` the lag's rate less the middle's), first- and second-order filter, holds the `f64` coefficients of the loops
    /// at the 9 x 9 grid of the cell; and Rouché's need along it (the centre's radii and
    /// each term's radii times its reach) is below a tenth of the first-order form's.
    #[test]
    fn second_order_form_holds_every_member_of_a_two_parameter_cell() {
        use crate::robust::Quantity;
        let device = Device::new(0.1, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
        for order in [1, 2] {
            let named = PhysicalElements {
                velocity_filter_cutoff: Some(40.0),
                velocity_filter_order: Some(order),
                actuator_time_constant: Some(3e-4),
                ..Default::default()
            };
            let ((f0, f1), (t0, t1)) = ((40.0, 42.0), (3e-4, 3.2e-4));
            let set = DeviceSet::new(&device, &named)
                .unwrap()
                .with_interval(Quantity::element("velocity_filter_cutoff").unwrap(), f0, f1)
                .unwrap()
                .with_interval(Quantity::element("actuator_time_constant").unwrap(), t0, t1)
                .unwrap();
            let b = boxes(&set).unwrap().unwrap().remove(0);
            let wall = Wall::new(0.01, 0.2).unwrap();
            let cell = (b.sides, CellDelay::Point(1.0));
            let Family::Centred(f) = family(&wall, 0.1, &b, cell) else {
                panic!("a cell of two parameters has the second-order form");
            };
            assert_eq!(f.slopes.len(), 5);
            // the cutoff's variable's offset from the middle (the pole's for the first order),
            // and the lag's rate's
            grid_holds(&b, &f, [(CUTOFF, f0, f1), (LAG, t0, t1)], |fc, tau| {
                let mut e = named;
                e.velocity_filter_cutoff = Some(fc);
                e.actuator_time_constant = Some(tau);
                Checker::new(Loop::physical(&device, &e).unwrap(), Options::default())
                    .unwrap()
                    .coefficients(&wall)
            });
            let need = |f: &MeanValueForm| {
                let radii = |c: &[Interval]| c.iter().map(|c| 0.5 * (c.hi() - c.lo())).sum::<f64>();
                radii(&f.centre)
                    + f.slopes
                        .iter()
                        .map(|s| s.offset.mag() * radii(&s.slope))
                        .sum::<f64>()
            };
            let Family::Centred(first) = centred::<2>(&wall, 0.1, &b, cell, &[CUTOFF, LAG]) else {
                panic!("a cell of two parameters has the mean-value form");
            };
            assert!(
                need(&f) < 0.1 * need(&first),
                "{order}: {} {}",
                need(&f),
                need(&first)
            );
        }
    }

    /// The centred form in each parameter the recursion spreads holds the members'
    /// coefficients at 41 values of a cell (`centred_holds`): the first- and second-order
    /// filters' cutoff, the lag's time constant, the transmission's handle mass, coupling
    /// stiffness and damping, the motor side's share of the damping and the device's mass
    /// under a transmission. Over these cells the plain extension is wider by at least the
    /// factors asserted (measured: 1.06 for the first-order cutoff, which enters only
    /// through the filter's pole, so there the two are close; 1.10 for the second order,
    /// 1.6 for the lag, 9 to 14 for the transmission's parameters and the mass under it).
    /// Rouche's test along the slope gains more than the widths show: the coefficients move
    /// together with the parameter.
    #[test]
    fn centred_parameter_form_holds_every_member() {
        let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
        let filtered = PhysicalElements {
            velocity_filter_cutoff: Some(40.0),
            actuator_time_constant: Some(3e-4),
            ..Default::default()
        };
        centred_holds(
            &device,
            &filtered,
            ("velocity_filter_cutoff", CUTOFF),
            (40.0, 43.0),
            1.0,
        );
        centred_holds(
            &device,
            &filtered,
            ("actuator_time_constant", LAG),
            (3e-4, 3.3e-4),
            1.3,
        );
        let mut second = filtered;
        second.velocity_filter_order = Some(2);
        centred_holds(
            &device,
            &second,
            ("velocity_filter_cutoff", CUTOFF),
            (40.0, 43.0),
            1.05,
        );
        let coupled = PhysicalElements {
            handle_mass: Some(0.03),
            transmission_stiffness: Some(5e4),
            transmission_damping: Some(2.0),
            motor_damping: Some(0.2),
            hand_mass: Some(0.2),
            hand_stiffness: Some(300.0),
            ..Default::default()
        };
        for (keyword, k, cell) in [
            ("handle_mass", HANDLE_MASS, (0.03, 0.0315)),
            ("transmission_stiffness", COUPLING_STIFFNESS, (5e4, 5.2e4)),
            ("transmission_damping", COUPLING_DAMPING, (2.0, 2.1)),
            ("motor_damping", SHARE, (0.2, 0.25)),
            ("mass", MASS, (0.1, 0.102)),
        ] {
            centred_holds(&device, &coupled, (keyword, k), cell, 5.0);
        }
    }

    /// The pole's enclosure holds `exp(-2 pi f_c T)` as `f64` computes it at the ends and
    /// inside, and is narrow over one cutoff.
    #[test]
    fn pole_enclosure_holds_the_computed_poles() {
        let t = Interval::point(1e-3);
        let cell = pole(Interval::new(30.0, 60.0), t);
        for i in 0..=30 {
            let fc = 30.0 + f64::from(i);
            let a = (-2.0 * std::f64::consts::PI * fc * 1e-3).exp();
            assert!(cell.contains(a, 0.0), "{fc}: {cell:?} {a}");
            let one = pole(Interval::point(fc), t);
            assert!(
                one.contains(a, 0.0) && one.hi() - one.lo() < 1e-14,
                "{one:?}"
            );
        }
    }

    /// Over a cell of a hand's mass, a first-order filter's cutoff and a lag's time constant,
    /// taken in the hand's share `m_0 / (m_0 + m_h)`, the pole and the rate ([`variable`]):
    /// the second-order form holds the `f64` coefficients of the loops at the 5 x 5 x 5 grid
    /// of the cell; the gradient at the middle holds their central differences in the three
    /// variables there, and the second derivatives over the cell hold their second central
    /// differences at the 3 x 3 x 3 grid. The members are built from the variables' values
    /// mapped back to physical units ([`member`]), and their coefficients computed by the
    /// loop's own floating-point route, independent of the interval one. A variable that is
    /// not one to one on the side or a form in the wrong variable fails: the pole's own
    /// second derivative is zero (the polynomial is affine in it) where the cutoff's is not.
    #[test]
    fn hand_pole_and_rate_variables_hold_the_members_and_their_derivatives() {
        use crate::robust::Quantity;
        let device = Device::new(0.1, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
        let named = PhysicalElements {
            hand_mass: Some(0.3),
            hand_stiffness: Some(300.0),
            velocity_filter_cutoff: Some(40.0),
            actuator_time_constant: Some(3e-4),
            ..Default::default()
        };
        // in the order of the form's sides ([`CENTRED`])
        let ranges = [(CUTOFF, 40.0, 44.0), (LAG, 3e-4, 3.3e-4), (HAND, 0.3, 0.34)];
        let mut set = DeviceSet::new(&device, &named).unwrap();
        for (i, lo, hi) in ranges {
            let keyword = match i {
                HAND => "hand_mass",
                CUTOFF => "velocity_filter_cutoff",
                _ => "actuator_time_constant",
            };
            set = set
                .with_interval(Quantity::element(keyword).unwrap(), lo, hi)
                .unwrap();
        }
        let b = boxes(&set).unwrap().unwrap().remove(0);
        assert!(share_side(&b) && pole_side(&b));
        let wall = Wall::new(0.01, 0.2).unwrap();
        let cell = (b.sides, CellDelay::Point(1.0));
        let Family::Centred(f) = family(&wall, 0.1, &b, cell) else {
            panic!("a cell of three parameters has the second-order form");
        };
        let sides = ranges.map(|(i, _, _)| i);
        let (middle, _) = middle_of(b.sides, sides, &b);
        let var = |i: usize, x: f64| variable(&b, i, Interval::point(x));
        // the coefficients of the member whose variables are `v`, by the `f64` route
        let coefficients = |v: [f64; 3]| {
            let mut e = named;
            e.velocity_filter_cutoff = member(&b, CUTOFF, v[0]);
            e.actuator_time_constant = member(&b, LAG, v[1]);
            e.hand_mass = member(&b, HAND, v[2]);
            Checker::new(Loop::physical(&device, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&wall)
        };
        let grid = |(_, lo, hi): (usize, f64, f64), j: u32, n: u32| {
            lo + (hi - lo) * f64::from(j) / f64::from(n)
        };
        for j in 0..125u32 {
            let x = [0, 1, 2].map(|k| grid(ranges[k], j / 5u32.pow(k as u32) % 5, 4));
            let t = [0, 1, 2].map(|k| var(sides[k], x[k]) - var(sides[k], middle[sides[k]].0));
            let [u, v, w] = t;
            let form = form_at(&f, &[u, v, w, u * u, u * v, u * w, v * v, v * w, w * w]);
            let mut e = named;
            e.velocity_filter_cutoff = Some(x[0]);
            e.actuator_time_constant = Some(x[1]);
            e.hand_mass = Some(x[2]);
            let q = Checker::new(Loop::physical(&device, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&wall);
            assert!(encloses(&form, &q), "{x:?}: {form:?} {q:?}");
        }
        // the second derivatives over the cell, as the recursion takes them
        let over = |i: usize, x: Interval| match sides.iter().position(|&c| c == i) {
            Some(k) => Dual2::<3>::variable(x, k),
            None => Dual2::constant(x),
        };
        let (el, dev, a, beta) = spread_of(&wall, 0.1, &b, cell, over);
        let hessians = second_derivatives(&b.lp, (&dev, &el, a, beta));
        // central differences with steps of a thousandth of each variable's width over the
        // cell: their error is the `f64` route's rounding (a few hundred units, below `1e-13`,
        // of the largest coefficient) over the step, or over the steps' product for a second
        // difference, plus the truncation, the third or fourth derivatives times the steps
        // squared, far below that at these steps (measured: at most `1.9e-13` of the
        // largest coefficient over the step for the gradient, `3.5e-16` over the steps'
        // product for the second derivatives); the tolerances are 50 and 300 times that
        let widths = sides.map(|i| {
            let v = variable(&b, i, Interval::new(b.sides[i].0, b.sides[i].1));
            v.hi() - v.lo()
        });
        let h = widths.map(|w| 1e-3 * w);
        let at_var = |v: [f64; 3], k: usize, step: f64| {
            let mut v = v;
            v[k] += step;
            coefficients(v)
        };
        let scale = coefficients(sides.map(|i| var(i, middle[i].0).lo()))
            .iter()
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let centre = sides.map(|i| {
            let v = var(i, middle[i].0);
            0.5 * v.lo() + 0.5 * v.hi()
        });
        for (k, &hk) in h.iter().enumerate() {
            let (up, down) = (at_var(centre, k, hk), at_var(centre, k, -hk));
            let tol = 1e-11 * scale / hk;
            for (c, (&u, &d)) in up.iter().zip(&down).enumerate() {
                let diff = (u - d) / (2.0 * hk);
                let g = f.slopes[k].slope[c];
                assert!(g.contains(diff, tol), "{k} {c}: {g:?} {diff}");
            }
        }
        for j in 0..27u32 {
            let v = [0, 1, 2].map(|k| {
                let w = variable(
                    &b,
                    sides[k],
                    Interval::new(b.sides[sides[k]].0, b.sides[sides[k]].1),
                );
                // inside the cell by two steps, so that the differences stay in it
                let (lo, hi) = (w.lo() + 2.0 * h[k], w.hi() - 2.0 * h[k]);
                lo + (hi - lo) * f64::from(j / 3u32.pow(k as u32) % 3) / 2.0
            });
            for k in 0..3 {
                for l in k..3 {
                    let second: Vec<f64> = if k == l {
                        let (up, mid, down) =
                            (at_var(v, k, h[k]), coefficients(v), at_var(v, k, -h[k]));
                        (0..up.len())
                            .map(|c| (up[c] - 2.0 * mid[c] + down[c]) / (h[k] * h[k]))
                            .collect()
                    } else {
                        let shifted = |a: f64, bb: f64| {
                            let mut w = v;
                            w[k] += a;
                            w[l] += bb;
                            coefficients(w)
                        };
                        let (pp, pm, mp, mm) = (
                            shifted(h[k], h[l]),
                            shifted(h[k], -h[l]),
                            shifted(-h[k], h[l]),
                            shifted(-h[k], -h[l]),
                        );
                        (0..pp.len())
                            .map(|c| (pp[c] - pm[c] - mp[c] + mm[c]) / (4.0 * h[k] * h[l]))
                            .collect()
                    };
                    let tol = 1e-13 * scale / (h[k] * h[l]);
                    for (c, &d) in second.iter().enumerate() {
                        let hh = hessians[c][k][l];
                        assert!(hh.contains(d, tol), "{v:?} {k}{l} {c}: {hh:?} {d}");
                    }
                }
            }
        }
        // exact: in the pole the filter's coefficients are affine, so the polynomial's own
        // second derivative in it is the enclosure of zero
        assert!(hessians.iter().all(|h| h[0][0].contains(0.0, 0.0)));
    }

    /// Over a cell of the mass and a hand's mass (a 30 Hz filter, no transmission), taken in
    /// `m_0 / m` and the hand's share `m_0 / (m_0 + m_h)` ([`variable`]), where the force's
    /// gain is `s / (w + s (1 - w))`: the second-order form holds the `f64` coefficients of
    /// the loops at the 9 x 9 grid of the cell, each member's wall in its own normalization
    /// (`m_ref / m` times the set's).
    #[test]
    fn mass_and_hand_share_variables_hold_the_members() {
        use crate::robust::Quantity;
        let device = Device::new(0.1, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
        let named = PhysicalElements {
            hand_mass: Some(0.2),
            hand_stiffness: Some(300.0),
            velocity_filter_cutoff: Some(30.0),
            ..Default::default()
        };
        let ((m0, m1), (h0, h1)) = ((0.1, 0.11), (0.2, 0.25));
        let set = DeviceSet::new(&device, &named)
            .unwrap()
            .with_interval(Quantity::Mass, m0, m1)
            .unwrap()
            .with_interval(Quantity::element("hand_mass").unwrap(), h0, h1)
            .unwrap();
        let b = boxes(&set).unwrap().unwrap().remove(0);
        assert!(mass_side(&b) && share_side(&b));
        let wall = Wall::new(0.01, 0.2).unwrap();
        let cell = (b.sides, CellDelay::Point(1.0));
        let Family::Centred(f) = family(&wall, m0, &b, cell) else {
            panic!("a cell of two parameters has the second-order form");
        };
        // in the order of the form's sides ([`CENTRED`])
        grid_holds(&b, &f, [(MASS, m0, m1), (HAND, h0, h1)], |m, mh| {
            let dev = Device::new(m, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
            let mut e = named;
            e.hand_mass = Some(mh);
            let s = m0 / m;
            Checker::new(Loop::physical(&dev, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&Wall::new(0.01 * s, 0.2 * s).unwrap())
        });
    }

    /// Whether the second-order form `f` of box `b`'s cell in two sides (`(side, lo, hi)`, in
    /// the form's order) holds the coefficients `q(x, y)` of the members at the 9 x 9 grid of
    /// the cell, each at the offsets of its sides' variables from the middle's
    /// (`g_1 t_1 + g_2 t_2 + H_11 / 2 t_1^2 + H_12 t_1 t_2 + H_22 / 2 t_2^2`).
    fn grid_holds(
        b: &ElementBox,
        f: &MeanValueForm,
        sides: [(usize, f64, f64); 2],
        q: impl Fn(f64, f64) -> Vec<f64>,
    ) {
        let (middle, _) = middle_of(b.sides, sides.map(|(i, _, _)| i), b);
        let offset = |(i, lo, hi): (usize, f64, f64), k: u32| {
            let x = lo + (hi - lo) * f64::from(k) / 8.0;
            let at = |x: f64| variable(b, i, Interval::point(x));
            (x, at(x) - at(middle[i].0))
        };
        for i in 0..=8 {
            for j in 0..=8 {
                let ((x, u), (y, v)) = (offset(sides[0], i), offset(sides[1], j));
                let form = form_at(f, &[u, v, u * u, u * v, v * v]);
                let q = q(x, y);
                assert!(encloses(&form, &q), "{x} {y}: {form:?} {q:?}");
            }
        }
    }
}
