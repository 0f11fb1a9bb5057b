//! Passivity of a sampled spring wall read by an encoder, with a quantized force output and
//! Coulomb friction in the device (the model document, docs/MODEL.md, section 9.1).
//!
//! Normalized units as in [`crate::buzz::Quantization`]: lengths in counts, time in samples,
//! forces as `F T^2 / (m Delta_x)`; `alpha` the stiffness, `delta` the viscous damping, `phi`
//! the Coulomb friction, `s` the force step. The wall is the undelayed spring
//! `u_k = -Q_u(alpha Q_x(x_k))`, held over the period (`Q_x` the mid-tread encoder, `Q_u` the
//! force output's rounding).
//!
//! Method (an energy argument; the derivation is in the model document): the operator's
//! net energy over any motion is at least the initial stored energy's negative plus the sum,
//! over the periods, of the dissipation `delta D_k^2 + phi |D_k|` (for a displacement `D_k`
//! in period `k`; equality when the velocity is constant within the period) minus the
//! sampled staircase's excess work `G_k = integral from x_k to x_{k+1} of (f(x_k) - f(x)) dx`
//! over the ideal staircase `f`. The wall is passive exactly when those sums are bounded
//! above; the cycles that make them grow, and a storage function that bounds them, give:
//!
//! - encoder, no force step: `alpha <= 2 delta` and `alpha <= 2 phi`;
//! - force step, no encoder: `alpha <= 2 delta` and `s <= 2 phi`;
//! - neither (friction alone): `alpha <= 2 delta`.
//!
//! In physical units: `K <= 2 b / T` and `K Delta_x <= 2 f_c` (Abbott and Okamura,
//! "Effects of position quantization and sampling rate on virtual-wall passivity", IEEE T-RO
//! 21(5), 2005), or `Delta_u <= 2 f_c` for the force output: each step of the staircase the
//! wall renders must be at most twice the Coulomb friction.

use crate::buzz::Quantization;
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::params::{MAX_DELAY, MAX_DELTA, Wall, in_range};

/// What limits a quantized wall's passivity.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct QuantizedPassivity {
    /// The largest passive stiffness, `min(2 delta, 2 phi)` with an encoder, `2 delta`
    /// otherwise (0 when the force step alone is above `2 phi`: no spring is passive).
    pub alpha_max: f64,
    /// Colgate's bound for large motions, `2 delta` (`K <= 2 b / T`).
    pub viscous_bound: f64,
    /// The bound from the staircase's steps: `2 phi` on the stiffness with an encoder;
    /// `None` without one.
    pub friction_bound: Option<f64>,
    /// With a force step and no encoder: whether the step is at most `2 phi`.
    pub force_step_ok: bool,
    /// Whether the wall is passive: stiffness at least 0 and at most [`Self::alpha_max`].
    pub passive: bool,
}

/// The passivity of the spring wall `wall` (no wall damping) on the device of viscous
/// damping `delta` and delay `d` with velocity filter `filter`, read and driven through the
/// encoder, force output and friction of `q` (see the module documentation for the
/// condition and its method). Derived for `d = 0` without a filter.
///
/// ```
/// use stabound::VelocityFilter;
/// use stabound::buzz::Quantization;
/// use stabound::params::Wall;
/// use stabound::passivity::quantized;
///
/// // An encoder and Coulomb friction phi = 0.3 (normalized): passive up to alpha = 0.6,
/// // although the viscous damping alone would allow alpha = 2.
/// let q = Quantization::new(true, 0.0, 0.3, 0.0)?;
/// let none = VelocityFilter::none();
/// let p = quantized(1.0, 0.0, none, &Wall::new(0.5, 0.0)?, &q)?;
/// assert!(p.passive);
/// assert!((p.alpha_max - 0.6).abs() < 1e-15);
/// assert!(!quantized(1.0, 0.0, none, &Wall::new(0.7, 0.0)?, &q)?.passive);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// `delta` or `d` out of range; [`Error::InvalidRequest`] for a delay, a velocity filter, a
/// wall with damping (`beta != 0`) or both an encoder and a force step: the condition is derived for the undelayed
/// spring wall with one staircase of equal steps only.
pub fn quantized(
    delta: f64,
    d: f64,
    filter: VelocityFilter,
    wall: &Wall,
    q: &Quantization,
) -> Result<QuantizedPassivity> {
    in_range("delta", delta, 0.0, MAX_DELTA)?;
    in_range("d", d, 0.0, MAX_DELAY)?;
    // exact zero on purpose: only the undelayed loop is covered
    if d > 0.0 || !filter.is_identity() {
        return Err(Error::InvalidRequest(
            "passivity with quantizers and friction is derived for the undelayed wall without a velocity filter only: give a delay of 0 and no filter".into(),
        ));
    }
    // exact zero on purpose: only the pure spring is covered
    if wall.beta().abs() > 0.0 {
        return Err(Error::InvalidRequest(
            "passivity with quantizers and friction is derived for the spring wall only: give a wall damping of 0".into(),
        ));
    }
    if q.encoder() && q.force_step() > 0.0 {
        return Err(Error::InvalidRequest(
            "passivity with both an encoder and a force step is not derived (their staircase has unequal steps): name one of the two".into(),
        ));
    }
    let viscous_bound = 2.0 * delta;
    let phi = q.coulomb();
    let friction_bound = q.encoder().then_some(2.0 * phi);
    let force_step_ok = q.force_step() <= 2.0 * phi;
    let alpha_max = if force_step_ok {
        friction_bound.map_or(viscous_bound, |f| f.min(viscous_bound))
    } else {
        0.0
    };
    let a = wall.alpha();
    Ok(QuantizedPassivity {
        alpha_max,
        viscous_bound,
        friction_bound,
        force_step_ok,
        passive: force_step_ok && a >= 0.0 && a <= alpha_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_and_refusals() {
        let enc = Quantization::new(true, 0.0, 2.0, 0.0).unwrap();
        // the viscous bound binds when friction is large
        let p = quantized(
            0.5,
            0.0,
            VelocityFilter::none(),
            &Wall::new(1.0, 0.0).unwrap(),
            &enc,
        )
        .unwrap();
        assert_eq!(p.alpha_max, 1.0);
        assert!(p.passive);
        // no friction: no spring read by an encoder is passive except alpha = 0
        let bare = Quantization::new(true, 0.0, 0.0, 0.0).unwrap();
        let p = quantized(
            1.0,
            0.0,
            VelocityFilter::none(),
            &Wall::new(1e-9, 0.0).unwrap(),
            &bare,
        )
        .unwrap();
        assert!(!p.passive);
        // force step alone: the step against twice the friction
        let dac = Quantization::new(false, 0.5, 0.2, 0.0).unwrap();
        let p = quantized(
            1.0,
            0.0,
            VelocityFilter::none(),
            &Wall::new(0.1, 0.0).unwrap(),
            &dac,
        )
        .unwrap();
        assert!(!p.force_step_ok && !p.passive);
        let dac = Quantization::new(false, 0.4, 0.2, 0.0).unwrap();
        assert!(
            quantized(
                1.0,
                0.0,
                VelocityFilter::none(),
                &Wall::new(0.1, 0.0).unwrap(),
                &dac
            )
            .unwrap()
            .passive
        );
        assert!(
            quantized(
                1.0,
                0.0,
                VelocityFilter::none(),
                &Wall::new(0.1, 0.1).unwrap(),
                &enc
            )
            .is_err()
        );
        let both = Quantization::new(true, 0.1, 0.2, 0.0).unwrap();
        assert!(
            quantized(
                1.0,
                0.0,
                VelocityFilter::none(),
                &Wall::new(0.1, 0.0).unwrap(),
                &both
            )
            .is_err()
        );
        assert!(
            quantized(
                -1.0,
                0.0,
                VelocityFilter::none(),
                &Wall::new(0.1, 0.0).unwrap(),
                &enc
            )
            .is_err()
        );
        let w = Wall::new(0.1, 0.0).unwrap();
        assert!(quantized(1.0, 1.0, VelocityFilter::none(), &w, &enc).is_err());
        let lp = VelocityFilter::low_pass(0.5).unwrap();
        assert!(quantized(1.0, 0.0, lp, &w, &enc).is_err());
    }
}
