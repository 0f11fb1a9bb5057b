//! Step responses (`stabound step`).

use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList};
use stabound::amax::margin_wall;
use stabound::elements::Loop;
use stabound::params::Device;
use stabound::sim::{StepOptions, step_response};
use stabound::stability::{Checker, Options, Verdict};

use crate::args::{self, delay_arg, floats, number};
use crate::work::{interruptible, par_map};
use crate::{class, to_py};

/// A count: an `int` (a float is refused, not cut); a negative one is passed on as 0, which
/// the library refuses with its own message.
fn count(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    if obj.is_instance_of::<PyBool>() || obj.is_instance_of::<PyFloat>() {
        return Err(args::not_whole(name, obj));
    }
    let v: i64 = obj.extract().map_err(|_| args::not_whole(name, obj))?;
    Ok(usize::try_from(v).unwrap_or(0))
}

/// Step responses from operator force to position, exact between samples (paper Fig. 11).
///
/// One device per value of ``damping`` (N s/m; a scalar gives one :class:`StepResponse`,
/// a sequence a list). The wall is ``stiffness=`` (N/m) with ``wall_damping=`` (N s/m,
/// default 0), or ``margin=F``: ``F * alpha_max`` with the damping at ``alpha_max``
/// (paper Section VIII uses 0.75). ``force`` is the step in N, ``duration`` the simulated
/// time in s.
///
/// >>> r = step(mass=1.0, period=1e-3, damping=[0.0, 10.0], delay_samples=1, margin=0.75)
/// >>> [x.verdict for x in r], float(r[0].time[-1])
/// (['stable', 'stable'], 0.05)
///
/// Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
/// ``velocity_filter_cutoff=``, as ``stabound step`` takes them) are modelled on each
/// device; the operator's force acts on the handle, the position is the one the encoder
/// reads, and ``margin=`` takes that loop's ``alpha_max``. A hand's spring to ground shares
/// the static deflection with the wall:
///
/// >>> r = step(mass=0.1, period=1e-3, damping=1.0, delay_samples=1, stiffness=2000.0,
/// ...          duration=0.5, hand_mass=0.05, hand_stiffness=500.0)
/// >>> r.elements, round(r.final_value * 2500.0, 12)
/// (('hand',), 1.0)
///
/// A wall that is not stable gives a :class:`RuntimeWarning` (as ``stabound step`` warns): its response does not settle and may overflow to ``inf`` or NaN.
#[pyfunction]
#[pyo3(signature = (*, mass, period, damping, delay=None, delay_samples=None, stiffness=None, wall_damping=None, margin=None, force=None, duration=None, points_per_period=None, settling_band=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn step<'py>(
    py: Python<'py>,
    mass: &Bound<'py, PyAny>,
    period: &Bound<'py, PyAny>,
    damping: &Bound<'py, PyAny>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
    force: Option<&Bound<'py, PyAny>>,
    duration: Option<&Bound<'py, PyAny>>,
    points_per_period: Option<&Bound<'py, PyAny>>,
    settling_band: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let named = args::elements(elements)?;
    let (dl, samples) = delay_arg(delay, delay_samples, [mass, period, damping])?;
    let delay = args::delay_of(number(dl, args::delay_name(samples))?, samples);
    let (mass, period) = (number(mass, "mass")?, number(period, "period")?);
    let opt = |o: Option<&Bound<'py, PyAny>>, name, default: f64| -> PyResult<f64> {
        o.map_or(Ok(default), |v| number(v, name))
    };
    let wall = match (stiffness, margin, wall_damping) {
        (Some(k), None, bw) => Ok((number(k, "stiffness")?, opt(bw, "wall_damping", 0.0)?)),
        (None, Some(f), None) => Err(number(f, "margin")?),
        (None, Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "wall_damping= goes with stiffness=; with margin= the damping is the one at alpha_max",
            ));
        }
        _ => {
            return Err(PyValueError::new_err(
                "give stiffness= K or margin= F (one of them)",
            ));
        }
    };
    let band = opt(settling_band, "settling_band", 0.02)?;
    if !(band.is_finite() && band > 0.0) {
        return Err(PyValueError::new_err(
            "settling_band must be a positive number",
        ));
    }
    let options = StepOptions {
        force: opt(force, "force", 1.0)?,
        duration: opt(duration, "duration", 0.05)?,
        points_per_period: points_per_period.map_or(Ok(10), |n| count(n, "points_per_period"))?,
    };
    let dampings = floats(damping, "damping")?;
    if dampings.values.is_empty() {
        return Err(PyValueError::new_err(
            "damping= is empty; give at least one value",
        ));
    }
    let scalar = dampings.is_scalar();
    let names: Vec<&str> = named.names();
    let bs = dampings.values;
    let runs = interruptible(py, move |cancel| {
        par_map(&bs, cancel, |&b| {
            let device = Device::new(mass, period, b, delay)?;
            let plant = device.plant()?;
            let lp = Loop::physical(&device, &named)?;
            let (k, bw) = match wall {
                Ok(kb) => kb,
                Err(f) => margin_wall(&lp, f)?,
            };
            let wall = device.wall(k, bw)?;
            let r = step_response(&lp, k, bw, &options)?;
            let verdict = Checker::new(lp, Options::default())?.verdict(&wall)?;
            Ok((device, plant, wall, k, bw, verdict, r))
        })
    })?
    .map_err(|(i, e)| match scalar {
        true => to_py(e),
        false => crate::to_py_at(e, &format!("damping[{i}]")),
    })?;
    let cls = class(py, "StepResponse")?;
    let out = PyList::empty(py);
    for (device, plant, wall, k, bw, verdict, r) in runs {
        if verdict != Verdict::Stable {
            // as the command line warns: the response does not settle (it may overflow)
            let msg = format!(
                "b = {} N s/m, K = {k} N/m, B = {bw} N s/m is {} (alpha = {}, beta = {}, delta = {}, d = {}); its response does not settle",
                device.damping(),
                verdict.name(),
                wall.alpha(),
                wall.beta(),
                plant.delta(),
                plant.d()
            );
            PyErr::warn(
                py,
                &py.get_type::<PyRuntimeWarning>(),
                &std::ffi::CString::new(msg)?,
                1,
            )?;
        }
        let o = PyDict::new(py);
        o.set_item("damping", device.damping())?;
        o.set_item("stiffness", k)?;
        o.set_item("wall_damping", bw)?;
        o.set_item("alpha", wall.alpha())?;
        o.set_item("beta", wall.beta())?;
        o.set_item("delta", plant.delta())?;
        o.set_item("d", plant.d())?;
        o.set_item("verdict", verdict.name())?;
        o.set_item("final_value", r.final_value)?;
        o.set_item("peak", r.peak())?;
        o.set_item("settling_time", r.settling_time(band))?;
        o.set_item("time", PyArray1::from_slice(py, &r.time))?;
        o.set_item("position", PyArray1::from_slice(py, &r.position))?;
        o.set_item("samples", PyArray1::from_slice(py, &r.samples))?;
        o.set_item("elements", pyo3::types::PyTuple::new(py, &names)?)?;
        out.append(cls.call((), Some(&o))?)?;
    }
    if scalar {
        return Ok(out.get_item(0)?.unbind());
    }
    Ok(out.into_any().unbind())
}
