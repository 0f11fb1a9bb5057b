//! Certified `alpha_max` (`certify_alpha_max`): `stabound amax --certify` for one row or a
//! grid, the enclosure of each loop's `alpha_max` or of a finite set of devices' robust
//! `alpha_max`.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use stabound::alpha_max as amax_of;
use stabound::certificate::{
    AMAX_LEAVES, AmaxCertificate, SetAmaxCertificate, certify_alpha_max as certify_amax,
    certify_set_alpha_max,
};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::params::{Device, Plant, outward};
use stabound::request::{self, Given};
use stabound::robust::robust_alpha_max;

use crate::amax::{intervals_and_limits, options, plants};
use crate::args::{Floats, delay_name, delay_of, floats};
use crate::certify::write;
use crate::point::{DeviceArgs, columns};
use crate::work::{interruptible, par_map};
use crate::{class, to_py, to_py_at};

/// ``alpha_max`` with a certified enclosure, proven in interval arithmetic (``stabound amax
/// ... --certify FILE``): ``alpha_lo <= alpha_max < alpha_hi``, where the wall
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
/// A grid, as the command line takes one: ``delta=`` and ``d=`` 1-D arrays, or a device's
/// ``damping=`` and ``delay=`` / ``delay_samples=`` 1-D arrays (``mass=`` and ``period=``
/// one number each), every pair of values a row, proved in parallel in one certificate (the
/// command line's for the same grid). The numeric fields are then arrays of shape
/// ``(len(d), len(delta))`` (``(len(delay), len(damping))``), an input given as one number
/// adding no axis:
///
/// >>> g = certify_alpha_max([0.0, 0.5], [1.0, 2.0], beta_min=0.0, beta_max=1.0)
/// >>> g.alpha_lo.shape, bool((g.alpha_lo <= g.alpha_max).all())
/// ((2, 2), True)
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
    // the rows of the grid, d outer and delta inner (a device's delays outer and dampings
    // inner), as the command line orders them
    let (rows, shape, scale) = if let Given::Normalized {
        delta: x, d: dd, ..
    } = given
    {
        let (x, dd) = (floats(x, "delta")?, floats(dd, "d")?);
        let shape = grid_shape(&dd, &x)?;
        let mut rows = Vec::with_capacity(x.values.len() * dd.values.len());
        for &dv in &dd.values {
            for &xv in &x.values {
                let plant = Plant::new(xv, dv).map_err(to_py)?;
                rows.push((
                    Row::One(Loop::new(plant)),
                    format!("delta = {xv}, d = {dv}"),
                ));
            }
        }
        (rows, shape, None)
    } else {
        let (inputs, samples) = device.inputs()?;
        let [mass, period, damping, delays] = &inputs[..] else {
            return Err(PyValueError::new_err(
                "certify_alpha_max in physical units needs mass=, period=, damping= and delay= (or delay_samples=)",
            ));
        };
        if !mass.is_scalar() || !period.is_scalar() {
            return Err(PyValueError::new_err(
                "certify_alpha_max proves a grid of one device's dampings and delays: mass= and period= are one number each",
            ));
        }
        let (m, t) = (mass.values[0], period.values[0]);
        let shape = grid_shape(delays, damping)?;
        let mut rows = Vec::with_capacity(damping.values.len() * delays.values.len());
        for &dl in &delays.values {
            for &b in &damping.values {
                let dev = Device::new(m, t, b, delay_of(dl, samples)).map_err(to_py)?;
                let set = request::device_set(&dev, &named, &spreads, always_gripped, true)
                    .map_err(to_py)?;
                let row = match set {
                    Some(set) if set.has_intervals() => {
                        return Err(PyValueError::new_err(
                            "certify_alpha_max over a set of devices proves the robust alpha_max of a finite set (a hand that can let go, OneOf values of loop elements): give an interval's values as OneOf",
                        ));
                    }
                    Some(set) if !set.is_single() => Row::Set(Box::new(set)),
                    _ => Row::One(Loop::physical(&dev, &named).map_err(to_py)?),
                };
                let at = format!("damping = {b}, {} = {dl}", delay_name(samples));
                rows.push((row, at));
            }
        }
        (rows, shape, Some(DeviceScale { mass: m, period: t }))
    };
    let n = rows.len();
    let (rows, places): (Vec<Row>, Vec<String>) = rows.into_iter().unzip();
    // each row proved on its own: the results do not depend on the number of threads
    let prove = move |row: &Row| -> stabound::Result<_> {
        Ok(match row {
            Row::One(lp) => {
                let amax = amax_of(*lp, &opts)?;
                let cert = certify_amax(*lp, &amax, strip, AMAX_LEAVES)?;
                let optimum = (amax.alpha_max, amax.beta_at_max);
                (optimum, cert.bounds(), 1, None, Proof::One(Box::new(cert)))
            }
            Row::Set(set) => {
                let r = robust_alpha_max(set, &opts)?;
                let optimum = (r.alpha_max, r.beta_at_max);
                let cert = certify_set_alpha_max(set, optimum, strip, AMAX_LEAVES)?;
                let members = cert.members();
                (
                    optimum,
                    cert.bounds(),
                    members,
                    Some(set.describe()),
                    Proof::Set(cert),
                )
            }
        })
    };
    let proved =
        interruptible(py, move |cancel| par_map(&rows, cancel, prove))?.map_err(|(i, e)| {
            if n == 1 {
                to_py(e)
            } else {
                to_py_at(e, &places[i])
            }
        })?;
    let (mut ones, mut sets) = (Vec::new(), Vec::new());
    let mut cols: [Vec<f64>; 4] = Default::default();
    let (members, set) = (proved[0].2, proved[0].3.clone());
    for ((amax, bmax), (alo, ahi), _, _, proof) in proved {
        for (c, v) in cols.iter_mut().zip([amax, bmax, alo, ahi]) {
            c.push(v);
        }
        match proof {
            Proof::One(c) => ones.push(*c),
            Proof::Set(c) => sets.push(c),
        }
    }
    // one row's own certificate, or one holding every row's, as the command line writes it
    let text = if sets.is_empty() {
        AmaxCertificate::rows_json(&ones)
    } else {
        SetAmaxCertificate::rows_json(&sets)
    };
    let [amax, bmax, alo, ahi] = cols;
    let mut names = vec!["alpha_max", "beta_at_max", "alpha_lo", "alpha_hi"];
    let mut values = vec![amax.clone(), bmax.clone(), alo.clone(), ahi.clone()];
    if let Some(u) = scale {
        let k = |a: &[f64]| -> PyResult<Vec<f64>> {
            a.iter().map(|&a| u.try_k(a).map_err(to_py)).collect()
        };
        let b: Vec<f64> = bmax
            .iter()
            .map(|&b| u.try_b(b).map_err(to_py))
            .collect::<PyResult<_>>()?;
        names.extend(["stiffness", "wall_damping", "stiffness_lo", "stiffness_hi"]);
        values.extend([k(&amax)?, b, k(&alo)?, k(&ahi)?]);
    }
    let out = PyDict::new(py);
    for (name, value) in names.into_iter().zip(columns(py, &shape, values)?) {
        out.set_item(name, value)?;
    }
    out.set_item("members", members)?;
    if let Some(described) = set {
        out.set_item("set", PyTuple::new(py, described)?)?;
    }
    write(path, &text)?;
    out.set_item("certificate", text)?;
    class(py, "CertifiedAmax")?.call((), Some(&out))
}

/// The shape of a grid of `outer` by `inner` values (each one number or a 1-D array): the
/// outer's axis then the inner's, without the axis of one given as one number.
fn grid_shape(outer: &Floats, inner: &Floats) -> PyResult<Vec<usize>> {
    for f in [outer, inner] {
        if f.shape.len() > 1 {
            return Err(PyValueError::new_err(format!(
                "certify_alpha_max proves a grid: {}= is one number or a 1-D array (the grid is every pair of values)",
                f.name
            )));
        }
    }
    Ok([outer.shape.as_slice(), inner.shape.as_slice()].concat())
}

/// A row's proof: the enclosure of one loop's alpha_max, or of a set's robust alpha_max.
enum Proof {
    One(Box<AmaxCertificate>),
    Set(SetAmaxCertificate),
}

/// The device of a row: one loop, or a finite set of devices.
enum Row {
    One(Loop),
    Set(Box<stabound::robust::DeviceSet>),
}
