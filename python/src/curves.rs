//! Stability boundaries in the (alpha, beta) and (delta, beta) planes.

use numpy::PyArray1;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use stabound::boundary::{self, Boundary, SweepOptions};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Delay, Device, Normalized, Plant};
use stabound::request;
use stabound::robust::{DeviceSet, robust_region};

use crate::args::{self, Floats, floats, number};
use crate::point::DeviceArgs;
use crate::work::interruptible;
use crate::{class, to_py};

/// Piece codes are indices into this list (the package's `PIECES`).
pub const PIECES: [boundary::Piece; 6] = [
    boundary::Piece::Curve,
    boundary::Piece::AlphaZero,
    boundary::Piece::MinusOne,
    boundary::Piece::Bisection,
    boundary::Piece::Clipped,
    boundary::Piece::PlusOne,
];

fn piece_code(p: boundary::Piece) -> i8 {
    PIECES
        .iter()
        .position(|&q| q == p)
        .and_then(|i| i8::try_from(i).ok())
        .unwrap_or(-1)
}

/// The boundary engine of a method name.
fn engine(method_name: &str) -> PyResult<boundary::Engine> {
    match method_name {
        "exact" => Ok(boundary::Engine::Exact),
        "bisect" => Ok(boundary::Engine::Bisect),
        _ => Err(PyValueError::new_err(format!(
            "invalid method = '{method_name}': expected 'exact' or 'bisect'"
        ))),
    }
}

/// Piece names of piece codes, as a numpy array of strings.
fn piece_names<'py>(
    py: Python<'py>,
    codes: Vec<i8>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let codes = PyArray1::from_vec(py, codes).into_any();
    Ok((class(py, "_PIECE_NAMES")?.get_item(&codes)?, codes))
}

/// A `Boundary` of the package.
fn boundary_of<'py>(py: Python<'py>, b: &Boundary) -> PyResult<Bound<'py, PyAny>> {
    let (names, codes) = piece_names(py, b.points.iter().map(|p| piece_code(p.piece)).collect())?;
    class(py, "Boundary")?.call1((
        b.delta,
        b.d,
        PyArray1::from_vec(py, b.points.iter().map(|p| p.x).collect()),
        PyArray1::from_vec(py, b.points.iter().map(|p| p.y).collect()),
        names,
        codes,
    ))
}

/// One curve for scalar inputs, else the list.
fn one_or_list<'py>(
    py: Python<'py>,
    scalar: bool,
    curves: Vec<Bound<'py, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let list = PyList::new(py, curves)?;
    if scalar && list.len() == 1 {
        return Ok(list.get_item(0)?.unbind());
    }
    Ok(list.into_any().unbind())
}

/// Stability boundaries in the (alpha, beta) plane, or in the (delta, beta) plane.
///
/// ``plane='alpha-beta'`` (paper Figs. 5, 7, 8): one :class:`Boundary` for scalar ``delta``
/// and ``d``; otherwise a list with one per ``(delta, d)``, ``delta`` outer and ``d`` inner
/// (the order of ``stabound boundary``), at most 1000 curves. ``method`` is ``'exact'``
/// (the default: D-decomposition, exact curve pieces) or ``'bisect'`` (grid of point tests
/// and bisection).
///
/// ``plane='delta-beta'`` (paper Figs. 6, 9): one :class:`DeltaBetaBoundary` per
/// ``(alpha, d)`` (``alpha`` outer), by bisection, over delta from ``min(delta)`` to
/// ``max(delta)`` (default 0 to 1); a single one for scalar ``alpha`` and ``d``.
///
/// ``tol`` is the accuracy of every point and the largest deviation of the polyline from
/// the true curve, in ``[1e-12, 1e-2]``. Computed in parallel with the GIL released.
///
/// >>> b = boundary(0.0, 0.0, tol=1e-6)
/// >>> float(b.alpha[0]), float(b.beta[0]), round(float(b.alpha.max()), 4)
/// (0.0, -0.0, 0.6863)
/// >>> [(c.delta, c.d) for c in boundary([0.0, 1.0], [0.0, 1.0], tol=1e-4)]
/// [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]
/// >>> c = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4)
/// >>> float(c.delta.min()) >= 0.0, set(c.piece.tolist()) <= {"bisection", "clipped"}
/// (True, True)
///
/// Loop elements (the keywords of :func:`check`) on one device in physical units (``mass=``,
/// ``period=``, ``damping=``, ``delay=`` or ``delay_samples=``) give that loop's boundary in
/// the (alpha, beta) plane; a hand stiffness makes negative ``alpha`` stable:
///
/// >>> h = boundary(mass=0.1, period=1e-3, damping=0.0, delay_samples=1,
/// ...              hand_mass=0.05, hand_stiffness=200.0, tol=1e-6)
/// >>> bool(h.alpha.min() < 0.0)
/// True
///
/// In the delta-beta plane the elements need only the device's ``mass=`` and ``period=``
/// (delta and d stay normalized): a first-order velocity filter at 30 Hz shrinks the stable
/// region of ``alpha = 0.5`` at one sample of delay:
///
/// >>> bare = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4)
/// >>> lp = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4,
/// ...               mass=0.1, period=1e-3, velocity_filter_cutoff=30.0)
/// >>> bool(lp.delta.min() > bare.delta.min())
/// True
///
/// A physical parameter given as :class:`Interval` or :class:`OneOf` (a set of devices,
/// ``LO..HI`` or ``one-of:LIST`` on the command line) gives the robust region: the walls stable for every member, one
/// :class:`Boundary` in the set's reference normalization (that of the low ends), the rows
/// of ``stabound boundary`` for the same set. With a hand the device with the hand let go is
/// a member unless ``always_gripped=True``. ``members=True`` returns ``(region, curves)``,
/// ``curves`` each member's own :class:`MemberBoundary` (the ``--members`` curves). With
/// intervals the members are a sample (ends and middle of each interval), said by a
/// ``UserWarning``:
///
/// >>> import warnings
/// >>> with warnings.catch_warnings():
/// ...     warnings.simplefilter("ignore")
/// ...     r, curves = boundary(mass=1.0, period=1.0, damping=0.5,
/// ...                          delay_samples=Interval(1, 3), tol=1e-4, members=True)
/// >>> [c.label for c in curves]
/// ['delay = 1 samples', 'delay = 2 samples', 'delay = 3 samples']
/// >>> bool(r.alpha.max() <= min(c.boundary.alpha.max() for c in curves))
/// True
#[pyfunction]
#[pyo3(name = "boundary", signature = (delta=None, d=None, *, tol=None, method=None, plane="alpha-beta", alpha=None, mass=None, period=None, damping=None, delay=None, delay_samples=None, members=false, always_gripped=false, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn boundary_py<'py>(
    py: Python<'py>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    tol: Option<&Bound<'py, PyAny>>,
    method: Option<&str>,
    plane: &str,
    alpha: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    members: bool,
    always_gripped: bool,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let tol = match tol {
        Some(t) => number(t, "tol")?,
        None => boundary::DEFAULT_TOL,
    };
    if plane != "alpha-beta" && plane != "delta-beta" {
        return Err(PyValueError::new_err(format!(
            "invalid plane = '{plane}': expected 'alpha-beta' or 'delta-beta'"
        )));
    }
    let given = DeviceArgs {
        mass,
        period,
        damping,
        delay,
        delay_samples,
    };
    let (lows, mut spreads) = given.intervals()?;
    let device = given.with_lows(&lows);
    let (named, element_spreads) = args::elements_and_intervals(elements)?;
    spreads.extend(element_spreads);
    if !spreads.is_empty() {
        if plane != "alpha-beta"
            || delta.is_some()
            || d.is_some()
            || alpha.is_some()
            || method.is_some()
        {
            return Err(PyValueError::new_err(
                "a set of devices (an Interval or a OneOf) is drawn in the alpha-beta plane by exact searches along lines of constant damping: give the device in physical units, not delta, d, alpha or method",
            ));
        }
        let dev = device.one("a set of devices")?;
        // a set is what an interval or a list gives; a hand alone keeps its one curve (held)
        if let Some(set) =
            request::device_set(&dev, &named, &spreads, always_gripped, true).map_err(to_py)?
            && set.is_spread()
        {
            return robust(py, set, tol, members);
        }
    }
    if members {
        return Err(PyValueError::new_err(
            "members=True draws the members of a set of devices: give an Interval or a OneOf, e.g. delay_samples=Interval(1, 3)",
        ));
    }
    if plane == "delta-beta" {
        if !matches!(method, None | Some("bisect")) {
            return Err(PyValueError::new_err(
                "method='exact' is for the alpha-beta plane; the delta-beta plane uses method='bisect'",
            ));
        }
        let read = |x: Option<&Bound<'py, PyAny>>, name| x.map(|v| floats(v, name)).transpose();
        let (alpha, d, delta) = (read(alpha, "alpha")?, read(d, "d")?, read(delta, "delta")?);
        let (mass, period) = (read(mass, "mass")?, read(period, "period")?);
        let (damping, delay) = (read(damping, "damping")?, read(delay, "delay")?);
        let delay_samples = read(delay_samples, "delay_samples")?;
        fn values(f: &Option<Floats>) -> Option<&[f64]> {
            f.as_ref().map(|f| &f.values[..])
        }
        let plane = request::DeviceInputs {
            alpha: values(&alpha),
            d: values(&d),
            delta: values(&delta),
            mass: values(&mass),
            period: values(&period),
            damping: values(&damping),
            delay: values(&delay),
            delay_samples: values(&delay_samples),
            ..Default::default()
        }
        .delta_beta_plane(named.any())
        .map_err(to_py)?;
        let scalar = [&alpha, &d]
            .iter()
            .all(|f| f.as_ref().is_some_and(Floats::is_scalar));
        let on_device = plane.device.map(|dev| (named, dev));
        let curves = delta_beta(py, &plane, tol, on_device)?;
        return one_or_list(py, scalar, curves);
    }
    if named.any() {
        if delta.is_some() || d.is_some() || alpha.is_some() {
            return Err(PyValueError::new_err(
                "loop elements: give the device (mass=, period=, damping=, delay=|delay_samples=) in the alpha-beta plane, not delta, d or alpha",
            ));
        }
        let dev = device.one("loop elements")?;
        let lp = Loop::physical(&dev, &named).map_err(to_py)?;
        let options = SweepOptions {
            engine: engine(method.unwrap_or("exact"))?,
            tol,
        };
        let b = interruptible(py, move |_| boundary::trace(lp, &options))?.map_err(to_py)?;
        return Ok(boundary_of(py, &b)?.unbind());
    } else if device.any() {
        return Err(PyValueError::new_err(
            "boundary takes a device in physical units only with loop elements; otherwise give delta and d",
        ));
    }
    let Some(d) = d else {
        return Err(PyValueError::new_err("missing d (delay factors)"));
    };
    let d = floats(d, "d")?;
    if alpha.is_some() {
        return Err(PyValueError::new_err(
            "alpha= belongs to plane='delta-beta'; in the alpha-beta plane give delta and d",
        ));
    }
    let Some(delta) = delta else {
        return Err(PyValueError::new_err("missing delta (physical damping)"));
    };
    let delta: Floats = floats(delta, "delta")?;
    let options = SweepOptions {
        engine: engine(method.unwrap_or("exact"))?,
        tol,
    };
    let scalar = delta.is_scalar() && d.is_scalar();
    let (deltas, ds) = (delta.values, d.values);
    let curves = interruptible(py, move |_| boundary::sweep(&deltas, &ds, &options, None))?
        .map_err(to_py)?;
    let curves = curves
        .iter()
        .map(|b| boundary_of(py, b))
        .collect::<PyResult<Vec<_>>>()?;
    one_or_list(py, scalar, curves)
}

/// The robust region of a set of devices (the walls stable for every member,
/// [`robust_region`]) as `stabound boundary` draws it for an interval: one `Boundary` in the
/// set's reference normalization, with `members` also each member's own (label, `Boundary`).
/// A `UserWarning` saying how the region of a set with intervals was found (the search
/// over the set, the walls proved) or that the common walls form several pieces at one
/// damping, as the command line's notes.
fn robust(py: Python<'_>, set: DeviceSet, tol: f64, members: bool) -> PyResult<Py<PyAny>> {
    let (r, set) =
        interruptible(py, move |_| robust_region(&set, tol).map(|r| (r, set)))?.map_err(to_py)?;
    let described = set.describe().join("; ");
    let mut notes = Vec::new();
    if let Some(search) = &r.search {
        notes.push(format!(
            "the robust region of {described} is {}",
            search.describe(r.boundary.tol)
        ));
    }
    if r.pieces > 1 {
        notes.push(format!(
            "the walls stable for every member form {} pieces at some damping; the one reaching the largest stiffness is given",
            r.pieces
        ));
    }
    for msg in notes {
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(msg)?,
            1,
        )?;
    }
    let region = boundary_of(py, &r.boundary)?;
    if !members {
        return Ok(region.unbind());
    }
    let cls = class(py, "MemberBoundary")?;
    let curves = r
        .members
        .iter()
        .zip(&r.member_boundaries)
        .map(|(m, b)| cls.call1((set.describe_member(m), boundary_of(py, b)?)))
        .collect::<PyResult<Vec<_>>>()?;
    Ok((region, PyList::new(py, curves)?)
        .into_pyobject(py)?
        .into_any()
        .unbind())
}

/// Boundaries in the (delta, beta) plane (bisection engine) for every `alpha` (outer) and
/// `d` (inner), over `delta` in `[lo, hi]`, as the command line's `--plane delta-beta`.
/// With elements on a device `(mass, period)`, each curve is that of the loop with those
/// elements, one curve after the other as the command line.
fn delta_beta<'py>(
    py: Python<'py>,
    plane: &request::DeltaBetaPlane<'_>,
    tol: f64,
    elements: Option<(PhysicalElements, (f64, f64))>,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let (alphas, ds, (lo, hi)) = (plane.alphas, plane.ds, plane.range);
    let curves = alphas.len().saturating_mul(ds.len());
    if curves > boundary::MAX_CURVES {
        return Err(PyValueError::new_err(format!(
            "{curves} curves ({} alpha x {} d) exceed the {} one call holds in memory; split the request",
            alphas.len(),
            ds.len(),
            boundary::MAX_CURVES
        )));
    }
    let requests: Vec<(f64, f64)> = alphas
        .iter()
        .flat_map(|&a| ds.iter().map(move |&d| (a, d)))
        .collect();
    let options = boundary::BisectOptions {
        tol,
        x_range: Some((lo, hi)),
        ..boundary::BisectOptions::default()
    };
    let plane_of = |alpha: f64, d: f64| -> stabound::Result<boundary::Plane> {
        Ok(boundary::Plane {
            x: boundary::Axis::Delta,
            y: boundary::Axis::Beta,
            at: Normalized::new(alpha, 0.0, 0.0, d)?,
        })
    };
    let todo = requests.clone();
    let contours = interruptible(py, move |_| match &elements {
        None => todo
            .par_iter()
            .map(|&(alpha, d)| {
                let plane = plane_of(alpha, d)?;
                boundary::bisect(plane.at.plant(), &plane, &options)
            })
            .collect::<stabound::Result<Vec<_>>>(),
        // one loop per curve, in order (each contour uses every core itself)
        Some((named, (m, t))) => todo
            .iter()
            .map(|&(alpha, d)| {
                let device = Device::new(*m, *t, 0.0, Delay::Samples(d))?;
                let lp = Loop::new(Plant::new(lo, d)?).with_physical(&device, named)?;
                boundary::bisect(lp, &plane_of(alpha, d)?, &options)
            })
            .collect(),
    })?
    .map_err(to_py)?;
    let cls = class(py, "DeltaBetaBoundary")?;
    let mut out = Vec::with_capacity(contours.len());
    for (c, &(alpha, d)) in contours.iter().zip(&requests) {
        let pts = || {
            c.loops
                .iter()
                .enumerate()
                .flat_map(|(i, l)| l.iter().map(move |p| (i, p)))
        };
        let codes = pts()
            .map(|(_, p)| {
                piece_code(if p.clipped() {
                    boundary::Piece::Clipped
                } else {
                    boundary::Piece::Bisection
                })
            })
            .collect();
        out.push(cls.call1((
            alpha,
            d,
            PyArray1::from_vec(py, pts().map(|(_, p)| p.x).collect()),
            PyArray1::from_vec(py, pts().map(|(_, p)| p.y).collect()),
            PyArray1::from_vec(
                py,
                pts().map(|(i, _)| i64::try_from(i).unwrap_or(-1)).collect(),
            ),
            piece_names(py, codes)?.0,
        ))?);
    }
    Ok(out)
}
