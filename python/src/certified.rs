//! Certified `alpha_max` (`certify_alpha_max`): `stabound amax --certify` for one row, the
//! enclosure of one loop's `alpha_max` or of a finite set of devices' robust `alpha_max`.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use stabound::alpha_max as amax_of;
use stabound::certificate::{
    AMAX_LEAVES, certify_alpha_max as certify_amax, certify_set_alpha_max,
};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::params::{Plant, outward};
use stabound::request::{self, Given};
use stabound::robust::robust_alpha_max;

use crate::amax::{intervals_and_limits, options, plants};
use crate::args::floats;
use crate::certify::write;
use crate::point::DeviceArgs;
use crate::work::interruptible;
use crate::{class, to_py};

/// ``alpha_max`` with a certified enclosure, proven in interval arithmetic (``stabound amax
/// ... --certify FILE`` for one row): ``alpha_lo <= alpha_max < alpha_hi``, where the wall
/// ``(alpha_lo, beta_at_max)`` is certified stable and no wall at ``alpha_hi`` or stiffer,
/// with a damping of ``[beta_min, beta_max]``, is stable (where the budget of leaves does
/// not prove every stiffer wall, only the walls at ``alpha_hi``: the checker says which).
/// Both damping limits are needed: ``beta_min=`` and ``beta_max=``, or in N s/m
/// ``wall_damping_min=`` and ``wall_damping_max=`` (widened by a few units in the last place,
/// as the command line widens them, so that the proof holds the whole physical range).
///
/// One row: ``delta=`` and ``d=`` (the paper's loop), or one device in physical units
/// (``mass=``, ``period=``, ``damping=``, ``delay=`` or ``delay_samples=``, each one number)
/// with loop elements by keyword as :func:`alpha_max` takes them; with a loop element's
/// values as :class:`OneOf` (or a hand that can let go), the robust ``alpha_max`` of that
/// finite set, proved for every member. The result is a :class:`CertifiedAmax` whose
/// ``certificate`` is the command line's, byte for byte; with ``path=`` it is also written to
/// that file. The standalone checker (``python -m stabound.verify_certificate FILE``)
/// replays it.
///
/// >>> c = certify_alpha_max(0.5, 1.0, beta_min=0.0, beta_max=1.0)
/// >>> bool(c.alpha_lo <= c.alpha_max < c.alpha_hi), c.stiffness is None
/// (True, True)
/// >>> c = certify_alpha_max(mass=0.1, period=1e-3, damping=0.0, delay_samples=1,
/// ...                       wall_damping_min=0.0, wall_damping_max=100.0, hand_mass=0.3,
/// ...                       hand_damping=2.0, hand_stiffness=300.0,
/// ...                       velocity_filter_cutoff=50.0)   # the hand on, or let go
/// >>> bool(c.stiffness_lo <= c.stiffness < c.stiffness_hi), c.members
/// (True, 2)
#[pyfunction]
#[pyo3(signature = (delta=None, d=None, *, beta_min=None, beta_max=None, wall_damping_min=None, wall_damping_max=None, theta_tol=None, mass=None, period=None, damping=None, delay=None, delay_samples=None, always_gripped=false, path=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn certify_alpha_max<'py>(
    py: Python<'py>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    beta_min: Option<&Bound<'py, PyAny>>,
    beta_max: Option<&Bound<'py, PyAny>>,
    wall_damping_min: Option<&Bound<'py, PyAny>>,
    wall_damping_max: Option<&Bound<'py, PyAny>>,
    theta_tol: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    always_gripped: bool,
    path: Option<PathBuf>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let given = DeviceArgs {
        mass,
        period,
        damping,
        delay,
        delay_samples,
    };
    let (lows, mut spreads, (lo, hi)) = intervals_and_limits(
        &given,
        [beta_min, beta_max],
        [wall_damping_min, wall_damping_max],
    )?;
    let device = given.with_lows(&lows);
    let (Some(lo), Some(hi)) = (lo, hi) else {
        return Err(PyValueError::new_err(
            "certify_alpha_max proves an enclosure over a bounded damping range: give beta_min= and beta_max= (or wall_damping_min= and wall_damping_max= in N s/m)",
        ));
    };
    // the search takes the limits as given; the proof's strip is widened where a limit was
    // given in N s/m, so that it holds every damping of the physical range
    let opts = options(py, theta_tol, None, Some(lo), Some(hi))?;
    let wide = outward(lo, hi);
    let strip = (
        if wall_damping_min.is_some() {
            wide.0
        } else {
            lo
        },
        if wall_damping_max.is_some() {
            wide.1
        } else {
            hi
        },
    );
    let (given, named, _) = plants(delta, d, &device, elements, &mut spreads)?;
    let (row, scale) = if let Given::Normalized {
        delta: x, d: dd, ..
    } = given
    {
        let (x, dd) = (floats(x, "delta")?, floats(dd, "d")?);
        if !x.is_scalar() || !dd.is_scalar() {
            return Err(PyValueError::new_err(
                "certify_alpha_max proves one row: delta= and d= are one number each (call it once a row, or use stabound amax ... --certify FILE for a grid)",
            ));
        }
        let plant = Plant::new(x.values[0], dd.values[0]).map_err(to_py)?;
        (Row::One(Loop::new(plant)), None)
    } else {
        let dev = device.one("certify_alpha_max")?;
        let scale = DeviceScale {
            mass: dev.mass(),
            period: dev.period(),
        };
        let set =
            request::device_set(&dev, &named, &spreads, always_gripped, true).map_err(to_py)?;
        let row = match set {
            Some(set) if set.has_intervals() => {
                return Err(PyValueError::new_err(
                    "certify_alpha_max over a set of devices proves the robust alpha_max of a finite set (a hand that can let go, OneOf values of loop elements): give an interval's values as OneOf",
                ));
            }
            Some(set) if !set.is_single() => Row::Set(Box::new(set)),
            _ => Row::One(Loop::physical(&dev, &named).map_err(to_py)?),
        };
        (row, Some(scale))
    };
    let proved = interruptible(py, move |_| -> stabound::Result<_> {
        Ok(match &row {
            Row::One(lp) => {
                let amax = amax_of(*lp, &opts)?;
                let cert = certify_amax(*lp, &amax, strip, AMAX_LEAVES)?;
                let optimum = (amax.alpha_max, amax.beta_at_max);
                (optimum, cert.bounds(), cert.to_json(), 1, None)
            }
            Row::Set(set) => {
                let r = robust_alpha_max(set, &opts)?;
                let optimum = (r.alpha_max, r.beta_at_max);
                let cert = certify_set_alpha_max(set, optimum, strip, AMAX_LEAVES)?;
                let described = set.describe();
                (
                    optimum,
                    cert.bounds(),
                    cert.to_json(),
                    cert.members(),
                    Some(described),
                )
            }
        })
    })?
    .map_err(to_py)?;
    let ((amax, bmax), (alo, ahi), text, members, set) = proved;
    let out = PyDict::new(py);
    out.set_item("alpha_max", amax)?;
    out.set_item("beta_at_max", bmax)?;
    out.set_item("alpha_lo", alo)?;
    out.set_item("alpha_hi", ahi)?;
    if let Some(u) = scale {
        let k = |a: f64| u.try_k(a).map_err(to_py);
        out.set_item("stiffness", k(amax)?)?;
        out.set_item("wall_damping", u.try_b(bmax).map_err(to_py)?)?;
        out.set_item("stiffness_lo", k(alo)?)?;
        out.set_item("stiffness_hi", k(ahi)?)?;
    }
    out.set_item("members", members)?;
    if let Some(described) = set {
        out.set_item("set", PyTuple::new(py, described)?)?;
    }
    write(path, &text)?;
    out.set_item("certificate", text)?;
    class(py, "CertifiedAmax")?.call((), Some(&out))
}

/// The device of a row: one loop, or a finite set of devices.
enum Row {
    One(Loop),
    Set(Box<stabound::robust::DeviceSet>),
}
