//! `alpha_max` and its lookup tables.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyTuple};
use stabound::amax::{
    AmaxOptions, HOLD_STEP, TableOptions, alpha_max_with_marginal, amax_report, amax_table,
    recommend,
};
use stabound::certificate::{CELL_BOXES_CAP, DEFAULT_CELL_BOXES, certify_table};
use stabound::elements::{Loop, PhysicalElements};
use stabound::export::{
    DeviceScale, c::to_c_header, csv::to_csv_bytes, json::lookup_json, lookup_rows, rust::to_rust,
};
use stabound::params::{Device, Plant};
use stabound::request::{self, DampingLimits, DeviceInputs, Given, Takes};
use stabound::robust::{DeviceSet, robust_alpha_max};

use crate::args::{self, Floats, broadcast, floats, located, opt_number};
use crate::certify::write;
use crate::point::{DeviceArgs, Lows, aliases, columns, physical_rows};
use crate::work::{first_error, interruptible, par_map};
use crate::{class, renamed, to_py};

/// Up to this many `alpha_max` run on the calling thread (module `work` for more).
const SMALL: usize = 4;

/// The normalized damping limits `(beta_min, beta_max)`, each given normalized or as a wall
/// damping in N s/m (`wall_damping_<end>=`), resolved by the library's request layer as
/// `stabound amax` resolves its flags; a wall damping needs one device (a scalar `mass=` and
/// `period=`).
fn damping_limits(
    beta: [Option<&Bound<'_, PyAny>>; 2],
    wall_damping: [Option<&Bound<'_, PyAny>>; 2],
    device: &DeviceArgs<'_, '_>,
) -> PyResult<Limits> {
    let limits = DampingLimits {
        beta_min: opt_number(beta[0], "beta_min")?,
        beta_max: opt_number(beta[1], "beta_max")?,
        wall_damping_min: opt_number(wall_damping[0], "wall_damping_min")?,
        wall_damping_max: opt_number(wall_damping[1], "wall_damping_max")?,
    };
    let scale = match (device.mass, device.period) {
        (Some(m), Some(t)) if wall_damping.iter().any(Option::is_some) => {
            let (m, t) = (floats(m, "mass")?, floats(t, "period")?);
            if !m.is_scalar() || !t.is_scalar() {
                return Err(PyValueError::new_err(
                    "with wall_damping_min= or wall_damping_max= mass= and period= are one number each (one device)",
                ));
            }
            Some((m.values[0], t.values[0]))
        }
        _ => None,
    };
    limits.resolve(scale).map_err(to_py)
}

/// Normalized damping limits `(beta_min, beta_max)`, `None` where not given.
type Limits = (Option<f64>, Option<f64>);

/// The device's intervals (their low ends, read with [`DeviceArgs::with_lows`], and the
/// intervals, [`DeviceArgs::intervals`]) and the normalized damping limits resolved on the
/// device of the low ends ([`damping_limits`]).
pub(crate) fn intervals_and_limits<'py>(
    given: &DeviceArgs<'_, 'py>,
    beta: [Option<&Bound<'py, PyAny>>; 2],
    wall_damping: [Option<&Bound<'py, PyAny>>; 2],
) -> PyResult<(Lows<'py>, Vec<args::Spread>, Limits)> {
    let (lows, spreads) = given.intervals()?;
    let limits = damping_limits(beta, wall_damping, &given.with_lows(&lows))?;
    Ok((lows, spreads, limits))
}

/// `margin=F`, a fraction in (0, 1] as `stabound amax --margin` takes it (the library's
/// request layer checks it).
fn margin_fraction(margin: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    opt_number(margin, "margin")?
        .map(|f| stabound::request::margin(f).map_err(to_py))
        .transpose()
}

/// `alpha_max` options of `theta_tol=` (`tol=` its old name) and the beta limits.
pub(crate) fn options(
    py: Python<'_>,
    theta_tol: Option<&Bound<'_, PyAny>>,
    tol: Option<&Bound<'_, PyAny>>,
    beta_min: Option<f64>,
    beta_max: Option<f64>,
) -> PyResult<AmaxOptions> {
    let tol = match renamed(py, theta_tol, tol, "tol", "theta_tol")? {
        Some(t) => args::number(&t, "theta_tol")?,
        None => stabound::amax::DEFAULT_THETA_TOL,
    };
    AmaxOptions::new(tol)
        .and_then(|o| o.with_beta_limits(beta_min, beta_max))
        .map_err(to_py)
}

/// The plants of `alpha_max` and `certify_alpha_max`: the form the library's request layer
/// decides from `delta`, `d` and the device (refusing mixed or missing inputs), the loop
/// elements (their sets added to `spreads`), and whether the request must be physical (loop
/// elements or sets of devices, refused otherwise).
pub(crate) fn plants<'a, 'py>(
    delta: Option<&'a Bound<'py, PyAny>>,
    d: Option<&'a Bound<'py, PyAny>>,
    device: &DeviceArgs<'a, 'py>,
    elements: Option<&Bound<'py, PyDict>>,
    spreads: &mut Vec<args::Spread>,
) -> PyResult<(Given<&'a Bound<'py, PyAny>>, PhysicalElements, bool)> {
    let (named, element_spreads) = args::elements_and_intervals(elements)?;
    spreads.extend(element_spreads);
    let given = DeviceInputs {
        delta,
        d,
        ..device.request()
    }
    .resolve(Takes::Plants)
    .map_err(to_py)?;
    let physical_only = named.any() || !spreads.is_empty();
    given
        .physical_for(
            "loop elements and sets of devices",
            physical_only,
            Takes::Plants,
        )
        .map_err(to_py)?;
    Ok((given, named, physical_only))
}

/// The physical `K` and `B` of one `alpha_max`, refused when not finite (as the command line).
fn physical(mass: f64, period: f64, alpha: f64, beta: f64) -> stabound::Result<[f64; 2]> {
    let u = DeviceScale { mass, period };
    u.check_scale()?;
    Ok([u.try_k(alpha)?, u.try_b(beta)?])
}

/// Maximum stable stiffness ``alpha_max`` and the ``beta`` where it is reached.
///
/// ``delta`` and ``d`` broadcast; scalar in, scalar out. ``beta_min`` / ``beta_max``
/// restrict the admissible virtual damping (e.g. ``beta_min=0`` when negative damping
/// cannot be rendered); ``theta_tol`` is the refinement tolerance in theta (rad), in
/// ``[1e-15, 1e-2]`` (``tol=`` is its old name). ``margin=F`` (a fraction in ``(0, 1]``, as
/// ``stabound amax --margin``) adds ``alpha_margin = F * alpha_max`` and ``beta_margin``
/// (and, in physical units, ``stiffness_margin`` in N/m): :class:`AmaxMargin` /
/// :class:`AmaxPhysicalMargin`. Or give devices as ``mass=``, ``period=``, ``damping=`` and
/// ``delay=`` / ``delay_samples=`` (broadcasting): the result then also has ``stiffness``
/// (``K_max``, N/m) and ``wall_damping`` (N s/m), and the damping limits may be given
/// as wall dampings in N s/m, ``wall_damping_min=`` / ``wall_damping_max=`` (the physical
/// ``beta_min`` / ``beta_max``, ``beta = B T / m``; they need one device mass and period,
/// as ``stabound amax --wall-damping-min``).
///
/// Computed in parallel with the GIL released; the same numbers, bit for bit, as
/// ``stabound amax``.
///
/// >>> round(alpha_max(0.0, 0.0).alpha_max, 12)     # 12 - 8 sqrt 2 (paper, Remark 4)
/// 0.686291501015
/// >>> a, b = alpha_max([0.0, 0.1, 1.0], 1.0)
/// >>> (0.75 * a).round(3).tolist()                  # paper Section VIII
/// [0.108, 0.149, 0.656]
/// >>> round(alpha_max(mass=1.0, period=1e-3, damping=0.0, delay_samples=1).stiffness)
/// 144469
/// >>> round(alpha_max(0.0, 1.0, margin=0.75).alpha_margin, 6)    # paper Section VIII
/// 0.108352
///
/// Without negative wall damping (``B >= 0``) a device keeps its ``alpha_max`` (its
/// optimal ``beta`` is positive), and with ``B <= 0`` the optimum is at ``B = 0``:
///
/// >>> dev = dict(mass=1.0, period=1e-3, damping=100.0, delay_samples=1)
/// >>> bool(alpha_max(**dev, wall_damping_min=0.0) == alpha_max(**dev))
/// True
/// >>> alpha_max(**dev, wall_damping_max=0.0).wall_damping
/// 0.0
///
/// Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
/// ``velocity_filter_cutoff=``) on one device in physical units give ``alpha_max`` of that
/// loop by direct search on its own polynomial. With ``margin=`` the margin wall is checked
/// stable; where the stable stiffnesses at the optimum's damping do not reach from the margin
/// wall up to ``alpha_max`` it is the fraction of the stiffest wall whose do, at that wall's
/// damping (``beta_margin``), and a ``UserWarning`` says so; another says where the optimum
/// needs negative damping and gives the stiffest wall with ``B >= 0``:
///
/// >>> bare = alpha_max(mass=0.1, period=1e-3, damping=0.0, delay_samples=1).stiffness
/// >>> lp = alpha_max(mass=0.1, period=1e-3, damping=0.0, delay_samples=1,
/// ...                velocity_filter_cutoff=30.0).stiffness
/// >>> bool(lp < bare)
/// True
///
/// In physical units a ``K_max`` or ``B`` that is not a finite number (a mass and period far apart in scale) raises ValueError, as ``stabound amax`` refuses it.
#[pyfunction]
#[pyo3(signature = (delta=None, d=None, *, beta_min=None, beta_max=None, theta_tol=None, margin=None, mass=None, period=None, damping=None, delay=None, delay_samples=None, tol=None, wall_damping_min=None, wall_damping_max=None, always_gripped=false, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn alpha_max<'py>(
    py: Python<'py>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    beta_min: Option<&Bound<'py, PyAny>>,
    beta_max: Option<&Bound<'py, PyAny>>,
    theta_tol: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    tol: Option<&Bound<'py, PyAny>>,
    wall_damping_min: Option<&Bound<'py, PyAny>>,
    wall_damping_max: Option<&Bound<'py, PyAny>>,
    always_gripped: bool,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
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
    let opts = options(py, theta_tol, tol, lo, hi)?;
    let fraction = margin_fraction(margin)?;
    let (given, named, physical_only) = plants(delta, d, &device, elements, &mut spreads)?;
    if physical_only {
        let dev = device.one("a set of devices or loop elements")?;
        if let Some(set) =
            request::device_set(&dev, &named, &spreads, always_gripped, true).map_err(to_py)?
            && !set.is_single()
        {
            return robust_amax(py, set, opts, fraction);
        }
    }
    if named.any() {
        let dev = device.one("loop elements")?;
        let lp = Loop::physical(&dev, &named).map_err(to_py)?;
        // the margin wall checked stable before it is given, and the notes of the report
        let (report, wall) = interruptible(py, move |_| match fraction {
            None => amax_report(&lp, &opts).map(|r| (r, None)),
            Some(f) => recommend(&lp, &opts, f).map(|m| {
                let wall = (
                    m.wall.alpha(),
                    m.wall.beta(),
                    (!m.at_optimum()).then_some(m.top),
                );
                (m.report, Some(wall))
            }),
        })?
        .map_err(to_py)?;
        let a = report.amax;
        let scale = |alpha: f64, beta: f64| {
            format!(
                "K = {} N/m at B = {} N s/m",
                dev.stiffness(alpha),
                dev.wall_damping(beta)
            )
        };
        let mut notes = Vec::new();
        if let Some(n) = report.nonnegative {
            notes.push(format!(
                "the stiffest wall ({}) needs negative virtual damping; the stiffest with nonnegative damping is {} (wall_damping_min=0.0 requires it)",
                scale(a.alpha_max, a.beta_at_max),
                scale(n.alpha_max, n.beta_at_max)
            ));
        }
        if let Some(why) = &report.no_nonnegative {
            notes.push(format!(
                "the stiffest wall ({}) needs negative virtual damping, and no wall with nonnegative damping is given: {why}",
                scale(a.alpha_max, a.beta_at_max)
            ));
        }
        if let Some(radius) = report.marginal_below {
            notes.push(format!(
                "the stiffest wall to render ({}, {HOLD_STEP:e} below K_max) has spectral radius {radius}, within the marginal band of 1 ({:e}): check calls it marginal, not stable; {} (more physical damping, or a filter pole farther from z = 1, moves it out of the band)",
                scale(a.alpha_max * (1.0 - HOLD_STEP), a.beta_at_max),
                stabound::stability::DEFAULT_MARGIN,
                slow_mode(radius)
            ));
        }
        if let (Some(n), Some(radius)) = (report.nonnegative, report.nonnegative_marginal_below) {
            notes.push(format!(
                "the stiffest wall with nonnegative damping to render ({}, {HOLD_STEP:e} below it) has spectral radius {radius}, within the marginal band of 1 ({:e}): check calls it marginal, not stable",
                scale(n.alpha_max * (1.0 - HOLD_STEP), n.beta_at_max),
                stabound::stability::DEFAULT_MARGIN,
            ));
        }
        if let Some((_, _, Some(top))) = wall {
            notes.push(format!(
                "the stable stiffnesses at the damping of K_max do not reach from the margin wall up to it; the margin wall is a fraction of {}, the stiffest wall whose every stiffness from the margin wall up is stable at its damping",
                scale(top.alpha_max, top.beta_at_max)
            ));
        } else if !report.one_range() {
            notes.push(
                "the stable stiffnesses at the damping of K_max are not one range from 0 up to it: a softer wall at that damping can be unstable".to_string(),
            );
        }
        warn_all(py, &notes)?;
        let cols = amax_columns(
            &[(dev.mass(), dev.period())],
            &[(a.alpha_max, a.beta_at_max)],
            fraction.map(|f| (f, wall.map(|(am, bm, _)| vec![(am, bm)]))),
        )
        .map_err(|(_, e)| to_py(e))?;
        return amax_result(py, &[], cols, true, fraction.is_some());
    }
    // the plants, normalized or physical, broadcast
    let (shape, rows, inputs, samples) = if let Given::Normalized {
        delta: x, d: dd, ..
    } = given
    {
        let inputs = vec![floats(x, "delta")?, floats(dd, "d")?];
        let shape = broadcast(&[&inputs[0], &inputs[1]])?;
        let (xs, ds) = (inputs[0].spread(&shape), inputs[1].spread(&shape));
        let rows = xs
            .into_iter()
            .zip(ds)
            .map(|(x, d)| [f64::NAN, f64::NAN, x, d])
            .collect();
        (shape, rows, inputs, false)
    } else {
        let w = physical_rows(&device, None)?;
        (w.shape, w.rows, w.inputs, w.samples)
    };
    let refs: Vec<&Floats> = inputs.iter().collect();
    let at = |(i, e)| located(e, i, &shape, &refs, &aliases(samples));
    // the paper's loop has no report: the wall below each optimum is checked here, as a
    // loop with elements' report checks its own
    let one = move |r: &[f64; 4]| {
        let plant = Plant::new(r[2], r[3])?;
        let (a, marginal) = alpha_max_with_marginal(plant, &opts)?;
        Ok((a.alpha_max, a.beta_at_max, marginal))
    };
    let found: Vec<(f64, f64, Option<f64>)> = if rows.len() <= SMALL {
        py.detach(|| first_error(rows.iter().map(one).collect()))
    } else {
        let rows = rows.clone();
        interruptible(py, move |cancel| par_map(&rows, cancel, one))?
    }
    .map_err(at)?;
    let marginal: Vec<String> = found
        .iter()
        .zip(&rows)
        .filter_map(|(&(a, b, radius), r)| {
            radius.map(|radius| {
                format!(
                    "delta = {}, d = {}: the stiffest wall to render (alpha = {}, beta = {b}, {HOLD_STEP:e} below alpha_max) has spectral radius {radius}, within the marginal band of 1 ({:e}): check calls it marginal, not stable; {} (walls farther below alpha_max at its damping are farther inside the circle: margin= gives one)",
                    r[2],
                    r[3],
                    a * (1.0 - HOLD_STEP),
                    stabound::stability::DEFAULT_MARGIN,
                    slow_mode(radius)
                )
            })
        })
        .collect();
    warn_all(py, &marginal)?;
    let found: Vec<(f64, f64)> = found.iter().map(|&(a, b, _)| (a, b)).collect();
    let physical = device.any();
    let scales: Vec<(f64, f64)> = if physical {
        let (m, t) = (inputs[0].spread(&shape), inputs[1].spread(&shape));
        m.into_iter().zip(t).collect()
    } else {
        Vec::new()
    };
    let cols = amax_columns(&scales, &found, fraction.map(|f| (f, None))).map_err(at)?;
    amax_result(py, &shape, cols, physical, fraction.is_some())
}

/// What a closed-loop root of modulus `radius` within the marginal band means for the wall.
fn slow_mode(radius: f64) -> String {
    if radius < 1.0 {
        format!(
            "its slowest mode decays by a factor e only every {:.3e} samples",
            1.0 / (1.0 - radius)
        )
    } else {
        // a radius within the band but not below 1: no decay to count
        "its slowest mode is not shown to decay at all".to_string()
    }
}

/// The rows' notes as `UserWarning`s: the first [`SHOWN_NOTES`] in full, then how many more
/// (as the command line's notes, so that a large array does not bury its answer).
fn warn_all(py: Python<'_>, notes: &[String]) -> PyResult<()> {
    let shown = notes.iter().take(SHOWN_NOTES).cloned();
    let more = notes.len().saturating_sub(SHOWN_NOTES);
    let rest = (more > 0).then(|| format!("{more} more rows like these"));
    for msg in shown.chain(rest) {
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(msg)?,
            1,
        )?;
    }
    Ok(())
}

/// Notes shown in full before the rest are counted.
const SHOWN_NOTES: usize = 20;

/// The robust `alpha_max` of a set of devices, as `stabound amax` gives it for a set (one
/// row): a `UserWarning` when it is not verified over the whole set.
fn robust_amax(
    py: Python<'_>,
    set: DeviceSet,
    opts: AmaxOptions,
    fraction: Option<f64>,
) -> PyResult<Py<PyAny>> {
    let (r, set) = interruptible(py, move |_| robust_alpha_max(&set, &opts).map(|r| (r, set)))?
        .map_err(to_py)?;
    let dev = *set.reference().device();
    let (m, t) = (dev.mass(), dev.period());
    let [k, b] = physical(m, t, r.alpha_max, r.beta_at_max).map_err(to_py)?;
    let [k_verified, _] = physical(m, t, r.alpha_verified, 0.0).map_err(to_py)?;
    // as the command line: F * alpha_verified at the optimum's damping
    let margin = match fraction {
        Some(f) => {
            let a = f * r.alpha_verified;
            let [km, _] = physical(m, t, a, 0.0).map_err(to_py)?;
            (Some(a), Some(r.beta_at_max), Some(km))
        }
        None => (None, None, None),
    };
    if !r.verification.holds() {
        let msg = format!(
            "the optimum is not verified over the whole set of devices: {}",
            r.verification.describe()
        );
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(msg)?,
            1,
        )?;
    }
    let binding: Vec<String> = r.binding.iter().map(|x| set.describe_member(x)).collect();
    let out = PyDict::new(py);
    out.set_item("alpha_max", r.alpha_max)?;
    out.set_item("beta_at_max", r.beta_at_max)?;
    out.set_item("alpha_verified", r.alpha_verified)?;
    out.set_item("stiffness", k)?;
    out.set_item("wall_damping", b)?;
    out.set_item("stiffness_verified", k_verified)?;
    out.set_item("alpha_margin", margin.0)?;
    out.set_item("beta_margin", margin.1)?;
    out.set_item("stiffness_margin", margin.2)?;
    out.set_item("members_examined", r.examined)?;
    out.set_item("verification", r.verification.describe())?;
    out.set_item("verified", r.verification.holds())?;
    out.set_item("binding", PyTuple::new(py, binding)?)?;
    out.set_item("set", PyTuple::new(py, set.describe())?)?;
    out.set_item(
        "proof_stopped",
        r.verification.proof_stop().map(|p| p.describe()),
    )?;
    Ok(class(py, "RobustAmax")?.call((), Some(&out))?.unbind())
}

/// Margin walls `(alpha, beta)`, one per row.
type Walls = Vec<(f64, f64)>;

/// The columns of an `Amax*` result: alpha_max, beta_at_max, then with `scales` (mass,
/// period per row) K and B, then with `margin` the margin's alpha, beta (and K): the walls
/// given, or the fraction of alpha_max at its damping (the paper's loop).
fn amax_columns(
    scales: &[(f64, f64)],
    found: &[(f64, f64)],
    margin: Option<(f64, Option<Walls>)>,
) -> Result<Vec<Vec<f64>>, (usize, stabound::Error)> {
    let mut cols = vec![
        found.iter().map(|p| p.0).collect::<Vec<f64>>(),
        found.iter().map(|p| p.1).collect(),
    ];
    if !scales.is_empty() {
        let kb: Vec<[f64; 2]> = first_error(
            scales
                .iter()
                .zip(found)
                .map(|(&(m, t), &(a, b))| physical(m, t, a, b))
                .collect(),
        )?;
        cols.push(kb.iter().map(|p| p[0]).collect());
        cols.push(kb.iter().map(|p| p[1]).collect());
    }
    if let Some((f, walls)) = margin {
        let (am, bm): (Vec<f64>, Vec<f64>) = match walls {
            Some(w) => w.into_iter().unzip(),
            // as the command line: F * alpha_max, one IEEE product
            None => (cols[0].iter().map(|a| f * a).collect(), cols[1].clone()),
        };
        cols.push(am.clone());
        cols.push(bm);
        if !scales.is_empty() {
            let km = first_error(
                scales
                    .iter()
                    .zip(&am)
                    .map(|(&(m, t), &a)| physical(m, t, a, 0.0).map(|p| p[0]))
                    .collect(),
            )?;
            cols.push(km);
        }
    }
    Ok(cols)
}

fn amax_result(
    py: Python<'_>,
    shape: &[usize],
    cols: Vec<Vec<f64>>,
    physical: bool,
    margin: bool,
) -> PyResult<Py<PyAny>> {
    let name = match (physical, margin) {
        (false, false) => "Amax",
        (true, false) => "AmaxPhysical",
        (false, true) => "AmaxMargin",
        (true, true) => "AmaxPhysicalMargin",
    };
    let items: Bound<'_, PyTuple> = columns(py, shape, cols)?;
    Ok(class(py, name)?.call1(items)?.unbind())
}

/// A lookup table of ``alpha_max`` for firmware: arrays and the C / Rust / CSV / JSON text.
///
/// ``delta`` and ``d`` are the strictly increasing axes (1-D). Or, in physical units:
/// ``mass=`` and ``period=`` (scalars), ``damping=`` (N s/m, the axis) and ``delay=`` (s)
/// or ``delay_samples=`` (the other axis); the table then has ``stiffness`` and
/// ``wall_damping`` too. With ``conservative=True`` every node is lowered just enough that
/// linear interpolation never exceeds the true ``alpha_max`` at the test points.
/// ``theta_tol`` is the refinement tolerance in theta, as for :func:`alpha_max` (``tol=``
/// is its old name).
///
/// >>> t = table([0.0, 0.5, 1.0], [0.0, 1.0])
/// >>> t.alpha_max.shape, t.c_header.count("{") > 0
/// ((2, 3), True)
///
/// Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
/// ``velocity_filter_cutoff=``) need the table in physical units; every node is then that
/// loop's ``alpha_max`` (``stabound table`` with the element flags), the conservative check
/// tests every query with the loop's own point test, and the C header lists the elements:
///
/// >>> f = table(mass=0.1, period=1e-3, damping=[0.0, 2.0], delay_samples=[1],
/// ...           velocity_filter_cutoff=30.0)
/// >>> bool((f.stiffness < table(mass=0.1, period=1e-3, damping=[0.0, 2.0],
/// ...                           delay_samples=[1]).stiffness).all())
/// True
/// >>> "low-pass velocity filter" in f.c_header
/// True
///
/// In physical units a table whose ``K`` or ``B`` would not be finite raises ValueError (as ``stabound table``: a C header with ``inf`` does not compile).
///
/// With ``certify=True`` (or a path, to which the certificate is also written) a
/// conservative table is proved: every wall its lookup yields, for every ``delta`` of each
/// interval and within the rounding guard, stable by interval Schur-Cohn boxes, the nodes of
/// a cell that is not proved lowered until it is (``stabound table --conservative --certify
/// FILE``; the certificate is the command line's, byte for byte). ``certify_boxes`` (default
/// 256) is the most boxes a cell is halved into before it is lowered; a cell that no
/// lowering proves within them has its budget doubled, up to 16384, before its nodes are
/// lowered (:attr:`LookupTable.grown` says so). The standalone checker (``python -m
/// stabound.verify_certificate FILE``) replays it, at about 10 boxes a second on wide cells
/// of a loop with elements. One loop, or a finite set of devices of one mass; whole delays
/// (or one delay). A cell no lowering proves raises StaboundError:
///
/// >>> t = table([0.5, 0.75, 1.0], [1.0], conservative=True, certify=True)
/// >>> t.certificate.startswith('{'), t.boxes > 0, t.grown
/// (True, True, None)
/// >>> bool((t.alpha_max <= table([0.5, 0.75, 1.0], [1.0], conservative=True).alpha_max).all())
/// True
#[pyfunction]
#[pyo3(signature = (delta=None, d=None, *, conservative=false, beta_min=None, beta_max=None, theta_tol=None, mass=None, period=None, damping=None, delay=None, delay_samples=None, tol=None, always_gripped=false, certify=None, certify_boxes=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn table<'py>(
    py: Python<'py>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    conservative: bool,
    beta_min: Option<&Bound<'py, PyAny>>,
    beta_max: Option<&Bound<'py, PyAny>>,
    theta_tol: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    tol: Option<&Bound<'py, PyAny>>,
    always_gripped: bool,
    certify: Option<&Bound<'py, PyAny>>,
    certify_boxes: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let proof = certify_request(certify, certify_boxes, conservative)?;
    let (named, mut spreads) = args::elements_and_intervals(elements)?;
    let lo = opt_number(beta_min, "beta_min")?;
    let hi = opt_number(beta_max, "beta_max")?;
    let opts = options(py, theta_tol, tol, lo, hi)?;
    let given = DeviceArgs {
        mass,
        period,
        damping,
        delay,
        delay_samples,
    };
    let (lows, device_spreads) = given.intervals()?;
    spreads.extend(device_spreads);
    let device = given.with_lows(&lows);
    let given = DeviceInputs {
        delta,
        d,
        ..device.request()
    }
    .resolve(Takes::Plants)
    .map_err(to_py)?;
    given
        .physical_for(
            "loop elements and sets of devices",
            named.any() || !spreads.is_empty(),
            Takes::Plants,
        )
        .map_err(to_py)?;
    let (deltas, ds, scale, lp) = if given.is_physical() {
        let (inputs, samples) = device.inputs()?;
        if !inputs[0].is_scalar() || !inputs[1].is_scalar() {
            return Err(PyValueError::new_err(
                "a table in physical units is for one device: mass= and period= are scalars",
            ));
        }
        let (m, t) = (inputs[0].values[0], inputs[1].values[0]);
        let (bs, dls) = (inputs[2].axis(), inputs[3].axis());
        // as the command line: delta from each damping, d from each delay
        let plant = |b: f64, dl: f64| Device::new(m, t, b, args::delay_of(dl, samples))?.plant();
        let at = |name: &'static str, len: usize| {
            move |(i, e): (usize, stabound::Error)| match len {
                1 => to_py(e),
                _ => crate::to_py_at(e, &format!("{name}[{i}]")),
            }
        };
        let first = |v: &[f64]| v.first().copied().unwrap_or(0.0);
        let deltas: Vec<f64> = first_error(
            bs.iter()
                .map(|&b| plant(b, first(dls)).map(|p| p.delta()))
                .collect(),
        )
        .map_err(at("damping", bs.len()))?;
        let ds: Vec<f64> = first_error(
            dls.iter()
                .map(|&dl| plant(first(bs), dl).map(|p| p.d()))
                .collect(),
        )
        .map_err(at(args::delay_name(samples), dls.len()))?;
        // the loop of the first node carries the elements (or the set) to every node
        let lp = if (named.any() || !spreads.is_empty()) && !deltas.is_empty() && !ds.is_empty() {
            let dev = Device::new(m, t, bs[0], args::delay_of(dls[0], samples)).map_err(to_py)?;
            let set =
                request::device_set(&dev, &named, &spreads, always_gripped, true).map_err(to_py)?;
            Some((Loop::physical(&dev, &named).map_err(to_py)?, set))
        } else {
            None
        };
        (deltas, ds, Some(DeviceScale { mass: m, period: t }), lp)
    } else {
        let (Some(x), Some(dd)) = (delta, d) else {
            return Err(PyValueError::new_err("missing delta and d"));
        };
        (
            floats(x, "delta")?.values,
            floats(dd, "d")?.values,
            None,
            None,
        )
    };
    if let Some(u) = &scale {
        u.check_scale().map_err(to_py)?;
    }
    let t = interruptible(py, move |_| {
        let base = TableOptions::new(opts).with_conservative(conservative);
        match lp {
            None => amax_table(&deltas, &ds, &base),
            Some((_, Some(set))) => amax_table(&deltas, &ds, &base.with_device_set(set)),
            Some((lp, None)) => amax_table(&deltas, &ds, &base.with_elements(lp)),
        }
    })?
    .map_err(to_py)?;
    let (t, certified) = match proof {
        None => (t, None),
        Some((path, budget)) => {
            let cert = interruptible(py, move |_| certify_table(&t, budget))?.map_err(|e| match e {
                // not proved: the arguments that help
                stabound::Error::Numerical(_) => crate::StaboundError::new_err(format!(
                    "{e}: try certify_boxes={MAX_CELL_BOXES} (the budget grew to {} boxes a cell), or a finer axis (a node halfway in each interval of damping= or delta=)",
                    budget.max(CELL_BOXES_CAP)
                )),
                e => to_py(e),
            })?;
            let text = cert.to_json();
            write(path, &text)?;
            let (_, boxes) = cert.counts();
            let grown = cert.grown();
            (cert.into_table(), Some((text, boxes, grown)))
        }
    };
    if let Some(u) = &scale {
        // no table in physical units holds inf or NaN (a C header with them does not compile)
        u.check_table(&t).map_err(to_py)?;
    }
    let out = PyDict::new(py);
    let grid = |v: &[Vec<f64>]| {
        PyArray2::from_vec2(py, v).map_err(|e| PyValueError::new_err(e.to_string()))
    };
    out.set_item("delta", PyArray1::from_slice(py, &t.delta))?;
    out.set_item("d", PyArray1::from_slice(py, &t.d))?;
    out.set_item("alpha_max", grid(&t.alpha_max)?)?;
    out.set_item("beta_at_max", grid(&t.beta_at_max)?)?;
    match &scale {
        Some(u) => {
            out.set_item("stiffness", grid(&u.stiffness(&t.alpha_max))?)?;
            out.set_item("wall_damping", grid(&u.wall_damping(&t.beta_at_max))?)?;
        }
        None => {
            out.set_item("stiffness", py.None())?;
            out.set_item("wall_damping", py.None())?;
        }
    }
    let all = 0..t.delta.len() * t.d.len();
    let csv = String::from_utf8_lossy(&to_csv_bytes(&lookup_rows(&t, &scale, all))).into_owned();
    out.set_item("csv", csv)?;
    out.set_item("json", lookup_json(&t, &scale))?;
    out.set_item("c_header", to_c_header(&t, &scale))?;
    out.set_item("rust", to_rust(&t, &scale))?;
    if let Some((text, boxes, grown)) = certified {
        out.set_item("certificate", text)?;
        out.set_item("boxes", boxes)?;
        out.set_item("grown", grown)?;
    }
    Ok(class(py, "LookupTable")?.call((), Some(&out))?.unbind())
}

/// The largest `certify_boxes=` (as the command line's `--certify-boxes`).
const MAX_CELL_BOXES: usize = 65536;

/// `certify=` (`True`, or a path to write the certificate to) and `certify_boxes=` of
/// [`table`]: the path and the budget of boxes a cell, or `None` without `certify=`.
fn certify_request(
    certify: Option<&Bound<'_, PyAny>>,
    boxes: Option<&Bound<'_, PyAny>>,
    conservative: bool,
) -> PyResult<Option<(Option<PathBuf>, usize)>> {
    let path = match certify {
        None => None,
        Some(c) if c.is_instance_of::<PyBool>() => c.extract::<bool>()?.then_some(None),
        Some(c) => Some(Some(c.extract::<PathBuf>().map_err(|_| {
            PyValueError::new_err(
                "certify= is True or a path (str or os.PathLike) to write the certificate to",
            )
        })?)),
    };
    let Some(path) = path else {
        return match boxes {
            Some(_) => Err(PyValueError::new_err(
                "certify_boxes= is the budget of a certified table: give certify=True (or a path) too",
            )),
            None => Ok(None),
        };
    };
    if !conservative {
        return Err(PyValueError::new_err(
            "a certified table starts from a conservative one: give conservative=True with certify=",
        ));
    }
    let budget = boxes.map_or(Ok(DEFAULT_CELL_BOXES), |b| args::whole(b, "certify_boxes"))?;
    if !(1..=MAX_CELL_BOXES).contains(&budget) {
        return Err(PyValueError::new_err(format!(
            "invalid certify_boxes = {budget}: give a whole number from 1 to {MAX_CELL_BOXES}"
        )));
    }
    Ok(Some((path, budget)))
}
