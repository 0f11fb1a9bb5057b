//! Rigorous enclosures: interval arithmetic in `f64` with outward rounding (with the paper
//! loop's discretization enclosed, `docs/MODEL.md` section 2) and the Schur-Cohn recursion
//! over interval coefficients (`docs/MODEL.md` section 11).
//!
//! The certificates' proofs, the robust box proofs and `alpha_max`'s question whether a wall
//! is clearly inside the unit circle share them; they build on the stability tests' own
//! scaling helpers and on nothing above them.

pub(crate) mod interval;
pub(crate) mod schur;
