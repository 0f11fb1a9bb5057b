//! Passivity (`stabound passivity`): the passive region and its comparison with the stable
//! region.

use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use stabound::VelocityFilter;
use stabound::export::DeviceScale;
use stabound::figures::passivity::stable_delta_beta;
use stabound::passivity::{
    Criterion, PassiveRegion, Summary, Witness, compare_alpha_beta, compare_delta_beta,
};
use stabound::request::DeviceInputs;

use crate::args::{number, opt_number, whole};
use crate::work::interruptible;
use crate::{class, to_py};

/// The passive region for a whole-sample delay and a velocity filter, and how it compares
/// with the stable region (``stabound passivity``, the same numbers bit for bit).
///
/// ``plane='alpha-beta'`` (the default) at physical damping ``delta``: the passive polygon,
/// the largest passive stiffness (over beta, and at ``beta=``), and the comparison with the
/// stable region (the exact boundary of the loop with its filter; exact stable sets on
/// ``2 columns + 1`` lines of constant beta where that boundary does not trace the piece of
/// the stable region holding the passive region). ``plane='delta-beta'`` at stiffness ``alpha=``, for
/// delta up to ``delta`` (default 4): the passive edge and, for ``alpha > 0``, the comparison
/// on lines of constant delta. ``d`` is the delay in whole samples (a fractional delay raises
/// ValueError, saying why). The filter: ``filter_pole=a`` (first-order low-pass, ``0 <= a <
/// 1``), or the velocity-filter keywords of :func:`check` (``velocity_filter_cutoff=`` Hz
/// with ``period=`` s and ``velocity_filter_order=``, or ``velocity_filter_samples=N``, a
/// moving average). ``tol`` is the largest distance of the traced edge from the true one.
/// With ``mass=`` (kg) and ``period=`` the largest passive wall is also given in N/m and
/// N s/m, and the parameters may be given in physical units instead, as ``stabound
/// passivity --damping ...``: ``damping=`` (N s/m) for ``delta``, ``stiffness=`` (N/m) for
/// ``alpha=``, ``wall_damping=`` (N s/m) for ``beta=`` (converted through the device:
/// ``delta = b T / m``, ``alpha = K T^2 / m``, ``beta = B T / m``), and ``delay=`` (s, a
/// whole number of periods; needs only ``period=``) or ``delay_samples=`` for ``d``. A
/// normalized parameter and its physical counterpart together raise ValueError, as does a
/// physical one without the device.
///
/// >>> p = passivity(1.0, 1)
/// >>> round(p.alpha_max_passive, 6), p.inside           # (2 sqrt 2 - 2) delta at d = 1
/// (0.828427, True)
/// >>> round(passivity(2.0, 1, beta=0.0).alpha_max_at_beta, 6)   # Diolaiti: 2 delta / (1 + 2 d)
/// 1.333333
/// >>> q = passivity(1.0, 1, velocity_filter_samples=2)
/// >>> q.stable_method, q.inside, q.passive_unstable is None
/// ('exact', True, True)
/// >>> r = passivity(3.0, 1, plane="delta-beta", alpha=0.5)
/// >>> r.inside, 0 < r.passive_share_of_stable < 1
/// (True, True)
///
/// The same device in physical units: b = 200 N s/m, m = 0.1 kg, T = 1 ms (delta = 2), one
/// sample of delay; the largest passive stiffness is 2 (2 sqrt 2 - 2) = 1.656854 (K in N/m
/// is alpha m / T^2), and at B = 0 N s/m it is 4/3:
///
/// >>> s = passivity(damping=200.0, mass=0.1, period=1e-3, delay=1e-3, wall_damping=0.0)
/// >>> round(s.alpha_max_passive, 6), round(s.stiffness_max), round(s.alpha_max_at_beta, 6)
/// (1.656854, 165685, 1.333333)
#[pyfunction]
#[pyo3(signature = (delta=None, d=None, *, plane="alpha-beta", alpha=None, beta=None, filter_pole=None, mass=None, period=None, damping=None, delay=None, delay_samples=None, stiffness=None, wall_damping=None, tol=None, columns=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn passivity<'py>(
    py: Python<'py>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    plane: &str,
    alpha: Option<&Bound<'py, PyAny>>,
    beta: Option<&Bound<'py, PyAny>>,
    filter_pole: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    tol: Option<&Bound<'py, PyAny>>,
    columns: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let period = opt_number(period, "period")?;
    let parts = DeviceInputs {
        alpha: opt_number(alpha, "alpha")?,
        beta: opt_number(beta, "beta")?,
        delta: opt_number(delta, "delta")?,
        d: opt_number(d, "d")?,
        mass: opt_number(mass, "mass")?,
        period,
        damping: opt_number(damping, "damping")?,
        delay: opt_number(delay, "delay")?,
        delay_samples: opt_number(delay_samples, "delay_samples")?,
        stiffness: opt_number(stiffness, "stiffness")?,
        wall_damping: opt_number(wall_damping, "wall_damping")?,
    }
    .resolve_parts()
    .map_err(to_py)?;
    let (delta, alpha, beta, d) = (parts.delta, parts.alpha, parts.beta, parts.d);
    let (fixed, delta_max) = match plane {
        "alpha-beta" => {
            if alpha.is_some() {
                return Err(PyValueError::new_err(
                    "alpha= belongs to plane='delta-beta', as stiffness= does; in the alpha-beta plane give delta (or damping=)",
                ));
            }
            let Some(x) = delta else {
                return Err(PyValueError::new_err(
                    "missing delta (physical damping; or damping= in N s/m with mass= and period=)",
                ));
            };
            (x, 0.0)
        }
        "delta-beta" => {
            let Some(a) = alpha else {
                return Err(PyValueError::new_err(
                    "missing alpha= for plane='delta-beta' (or stiffness= in N/m with mass= and period=)",
                ));
            };
            if beta.is_some() {
                return Err(PyValueError::new_err(
                    "beta= belongs to the alpha-beta plane, as wall_damping= does (the largest passive stiffness at one delta)",
                ));
            }
            (a, delta.unwrap_or(4.0))
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "invalid plane = '{plane}': expected 'alpha-beta' or 'delta-beta'"
            )));
        }
    };
    let columns = columns.map_or(Ok(stabound::passivity::DEFAULT_COLUMNS), |c| {
        whole(c, "columns")
    })?;
    let scale = parts
        .device
        .map(|(mass, period)| DeviceScale { mass, period });
    // the filter keywords of the element list (`velocity_filter_cutoff=` Hz, ...), or a pole
    let filter = stabound::request::velocity_filter(
        &crate::args::elements(elements)?,
        opt_number(filter_pole, "filter_pole")?,
        period,
    )
    .map_err(to_py)?;
    let tol = tol.map_or(Ok(1e-7), |t| number(t, "tol"))?;
    let r = core(py, plane, fixed, d, filter, tol, columns, delta_max, beta)?;
    let best =
        |key: &str| -> PyResult<Option<f64>> { r.get_item(key)?.map(|v| v.extract()).transpose() };
    let (mut k, mut b) = (None, None);
    if let (Some(u), Some(a), Some(bb)) = (scale, best("alpha_max_passive")?, best("beta_at_max")?)
    {
        k = Some(u.try_k(a).map_err(to_py)?);
        b = Some(u.try_b(bb).map_err(to_py)?);
    }
    for key in [
        "stable_x",
        "stable_y",
        "stable_points",
        "alpha_max_passive",
        "beta_at_max",
        "alpha_max_at_beta",
        "inside",
        "passive_area",
        "stable_area",
        "passive_share_of_stable",
        "stable_share_of_passive",
        "passive_share_error",
        "passive_share_bound",
        "stable_method",
        "passive_unstable",
        "stable_not_passive",
    ] {
        if !r.contains(key)? {
            r.set_item(key, py.None())?;
        }
    }
    r.set_item("plane", plane)?;
    r.set_item("at", fixed)?;
    r.set_item("d", d)?;
    r.set_item("stiffness_max", k)?;
    r.set_item("wall_damping_at_max", b)?;
    let edge = class(py, "np")?
        .getattr("array")?
        .call1((r.get_item("edge")?,))?;
    r.set_item("edge", edge)?;
    Ok(class(py, "Passivity")?.call((), Some(&r))?.unbind())
}

/// A witness wall as a dict, or None.
fn witness<'py>(py: Python<'py>, w: Option<Witness>) -> PyResult<Option<Bound<'py, PyAny>>> {
    let Some(w) = w else { return Ok(None) };
    let o = PyDict::new(py);
    o.set_item("alpha", w.alpha)?;
    o.set_item("beta", w.beta)?;
    o.set_item("delta", w.delta)?;
    o.set_item("margin", w.margin)?;
    o.set_item("verdict", w.verdict.name())?;
    Ok(Some(class(py, "Witness")?.call((), Some(&o))?))
}

/// What `stabound passivity` computes, as a dict: the passive edge (`x`, `y`, `theta`,
/// `edge`), the stable region's points and how they were found, the largest passive
/// stiffness (alpha-beta plane) and the comparison with the stable region.
#[allow(clippy::too_many_arguments)]
fn core<'py>(
    py: Python<'py>,
    plane: &str,
    fixed: f64,
    d: f64,
    filter: VelocityFilter,
    tol: f64,
    columns: usize,
    delta_max: f64,
    beta: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let crit = Criterion::new(d, filter).map_err(to_py)?;
    let out = PyDict::new(py);
    out.set_item("filter", filter.name())?;
    type Cmp = (
        PassiveRegion,
        Option<(Vec<(f64, f64)>, &'static str)>,
        Option<Summary>,
    );
    let (region, stable, verdicts): Cmp = match plane {
        "alpha-beta" => {
            let delta = fixed;
            let (cmp, best, at) = interruptible(py, move |_| -> stabound::Result<_> {
                let c = compare_alpha_beta(delta, d, filter, columns, tol)?;
                let cmp: Cmp = (
                    c.region,
                    Some((c.stable, c.summary.method)),
                    Some(c.summary),
                );
                let best = crit.max_stiffness(delta, tol)?;
                let at = match beta {
                    Some(b) => Some(crit.max_stiffness_at(delta, b, tol)?),
                    None => None,
                };
                Ok((cmp, best, at))
            })?
            .map_err(to_py)?;
            out.set_item("alpha_max_passive", best.map(|b| b.0))?;
            out.set_item("beta_at_max", best.map(|b| b.1))?;
            out.set_item("alpha_max_at_beta", at.flatten())?;
            cmp
        }
        "delta-beta" => {
            let alpha = fixed;
            interruptible(py, move |_| -> stabound::Result<Cmp> {
                let cmp = if alpha > 0.0 {
                    Some(compare_delta_beta(
                        alpha, d, filter, delta_max, columns, tol,
                    )?)
                } else {
                    None
                };
                let region = match &cmp {
                    Some(c) => c.region.clone(),
                    None => crit.region_delta_beta(alpha, delta_max, tol)?,
                };
                // as the command line: without a filter the bisection engine draws it
                let stable = if filter.is_identity() {
                    Some((stable_delta_beta(alpha, d, delta_max)?, "bisection"))
                } else {
                    cmp.as_ref().map(|c| (c.stable_outline.clone(), "columns"))
                };
                Ok((region, stable, cmp.as_ref().map(Summary::from)))
            })?
            .map_err(to_py)?
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "invalid plane = '{plane}': expected 'alpha-beta' or 'delta-beta'"
            )));
        }
    };
    let pts = &region.points;
    out.set_item(
        "x",
        PyArray1::from_vec(py, pts.iter().map(|p| p.x).collect()),
    )?;
    out.set_item(
        "y",
        PyArray1::from_vec(py, pts.iter().map(|p| p.y).collect()),
    )?;
    out.set_item(
        "theta",
        PyArray1::from_vec(py, pts.iter().map(|p| p.piece.theta).collect()),
    )?;
    out.set_item(
        "edge",
        pts.iter().map(|p| p.piece.edge.name()).collect::<Vec<_>>(),
    )?;
    out.set_item("tol", region.tol)?;
    if let Some((s, how)) = &stable {
        out.set_item(
            "stable_x",
            PyArray1::from_vec(py, s.iter().map(|p| p.0).collect()),
        )?;
        out.set_item(
            "stable_y",
            PyArray1::from_vec(py, s.iter().map(|p| p.1).collect()),
        )?;
        out.set_item("stable_points", *how)?;
    }
    if let Some(v) = verdicts {
        out.set_item("inside", v.inside)?;
        out.set_item("passive_area", v.passive_area)?;
        out.set_item("stable_area", v.stable_area)?;
        out.set_item("passive_share_of_stable", v.passive_share)?;
        out.set_item("stable_share_of_passive", v.stable_share)?;
        out.set_item("passive_share_error", v.share_error)?;
        out.set_item("passive_share_bound", v.share_bound)?;
        out.set_item("stable_method", v.method)?;
        out.set_item("passive_unstable", witness(py, v.passive_unstable)?)?;
        out.set_item("stable_not_passive", witness(py, v.stable_not_passive)?)?;
    }
    Ok(out)
}
