//! Rigorous enclosures: interval arithmetic in `f64` with outward rounding (with the paper
//! loop's discretization enclosed, `docs/MODEL.md` section 2) and the Schur-Cohn recursion
//! over interval coefficients (`docs/MODEL.md` section 11).
//!
//! The certificates' proofs, the robust box proofs and `alpha_max`'s question whether a wall
//! is clearly inside the unit circle share them; they build on the stability tests' own
//! scaling helpers and on nothing above them.

pub(crate) mod interval;
pub(crate) mod schur;

/// `m.max(v)` for a running maximum `m` that is never NaN: the same value (a NaN `v` leaves
/// `m`, as `f64::max` does; `m` starts as a number and only ever takes a `v` greater than
/// it), by one comparison instead of `max`'s NaN handling, a few instructions fewer in the
/// short loops of the proofs' hot paths.
#[inline(always)]
pub(crate) fn larger(m: f64, v: f64) -> f64 {
    if v > m { v } else { m }
}
