//! The compiled core of the `stabound` Python package (`stabound._stabound`).
//!
//! Each function here takes flat, contiguous `float64` arrays (the pure-Python layer in
//! `stabound/__init__.py` broadcasts, flattens and reshapes) and calls the library once per
//! element. Work runs with the interpreter detached (other Python threads keep running) on
//! rayon's pool, in chunks: between chunks the interpreter is re-attached to look for
//! Ctrl-C. Every element is computed on its own and results are collected in input order,
//! so they do not depend on the number of threads; when several elements fail, the error
//! reported is that of the first one in input order.
//!
//! Library errors keep their message: bad input (`InvalidParameter`, `InvalidRequest`)
//! becomes `ValueError`, anything else `stabound.StaboundError`.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use stabound::VelocityFilter;
use stabound::amax::{AmaxOptions, Precision, alpha_max, amax_table, amax_table_loop};
use stabound::boundary::{self, Boundary, SweepOptions};
use stabound::elements::{Loop, LoopChecker, PhysicalElements, list};
use stabound::export::{
    DeviceScale, c::to_c_header, csv::to_csv_bytes, json::lookup_json, lookup_rows, rust::to_rust,
};
use stabound::figures::loop_margin_wall;
use stabound::params::{Delay, Device, Normalized, Plant, Wall};
use stabound::passivity::figures::{
    COMPANION_DELAYS, companion, companion_names, stable_delta_beta,
};
use stabound::passivity::{Criterion, PassiveRegion, Witness, compare};
use stabound::passivity::{
    DEFAULT_COLUMNS, Summary, compare_loop, compare_loop_delta_beta, filter_name,
};
use stabound::scene::{Scene, SceneFormat};
use stabound::sim::{StepOptions, loop_step_response};
use stabound::stability::{Checker, Method, Options, Verdict};

create_exception!(
    stabound,
    StaboundError,
    PyRuntimeError,
    "A numerical method failed (no convergence, a result that could not be trusted); bad input raises ValueError instead."
);

/// Elements per detached chunk: small enough that Ctrl-C is seen within tens of
/// milliseconds (an alpha_max is about 20 us, a point test about 1 us), large enough that
/// the re-attach between chunks costs nothing measurable.
const CHUNK: usize = 4096;

/// The Python exception for a library error, with the library's message.
fn to_py(e: stabound::Error) -> PyErr {
    match e {
        stabound::Error::InvalidParameter { .. } | stabound::Error::InvalidRequest(_) => {
            PyValueError::new_err(e.to_string())
        }
        _ => StaboundError::new_err(e.to_string()),
    }
}

/// The elements of a 1-D array, copied (so that no Python code can change them while the
/// interpreter is detached).
fn values(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    a.as_array().iter().copied().collect()
}

/// `n` from arrays that must all have `n` elements.
fn common_len(arrays: &[&[f64]]) -> PyResult<usize> {
    let n = arrays.first().map_or(0, |a| a.len());
    if arrays.iter().any(|a| a.len() != n) {
        return Err(PyValueError::new_err(
            "the arrays must have the same number of elements",
        ));
    }
    Ok(n)
}

/// The first error in order, else all the values.
fn first_error<R>(results: Vec<stabound::Result<R>>) -> PyResult<Vec<R>> {
    results.into_iter().collect::<Result<_, _>>().map_err(to_py)
}

/// `f` of every element of `items`, in parallel with the interpreter detached, in chunks
/// (module docs).
fn par_map<T, R, F>(py: Python<'_>, items: &[T], f: F) -> PyResult<Vec<R>>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> stabound::Result<R> + Sync,
{
    let mut out = Vec::with_capacity(items.len());
    for chunk in items.chunks(CHUNK) {
        let part: Vec<stabound::Result<R>> = py.detach(|| chunk.par_iter().map(&f).collect());
        out.extend(first_error(part)?);
        py.check_signals()?;
    }
    Ok(out)
}

/// Every point-test method, in the order of `METHODS` (and of the method codes): the ones a
/// caller may request, then `certified`, the last stage that vouches where the others
/// cannot (it may also be requested).
const METHODS_ALL: [Method; 6] = [
    Method::Auto,
    Method::SchurCohn,
    Method::Eigen,
    Method::StateSpace,
    Method::ArgumentPrinciple,
    Method::Certified,
];

/// A stability method by its command-line name (`schur_cohn` is accepted for `schur-cohn`).
fn method(name: &str) -> PyResult<Method> {
    let key = name.replace('_', "-");
    METHODS_ALL
        .iter()
        .copied()
        .find(|m| m.name() == key)
        .ok_or_else(|| {
            let names: Vec<String> = METHODS_ALL
                .iter()
                .map(|m| format!("'{}'", m.name()))
                .collect();
            PyValueError::new_err(format!(
                "invalid method = '{name}': expected one of {}",
                names.join(", ")
            ))
        })
}

fn verdict_code(v: Verdict) -> i8 {
    match v {
        Verdict::Stable => 0,
        Verdict::Marginal => 1,
        Verdict::Unstable => 2,
    }
}

/// The index of `m` in `METHODS_ALL` (the order of `METHODS`).
fn method_code(m: Method) -> i8 {
    METHODS_ALL
        .iter()
        .position(|&x| x == m)
        .and_then(|i| i8::try_from(i).ok())
        .unwrap_or(-1)
}

/// One point test: (spectral radius, verdict code, method code).
type Point = (f64, i8, i8);

/// The columns of point tests as numpy arrays: radii, verdict codes, method codes.
#[allow(clippy::type_complexity)]
fn point_arrays<'py>(
    py: Python<'py>,
    out: &[Point],
) -> (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i8>>,
    Bound<'py, PyArray1<i8>>,
) {
    (
        PyArray1::from_vec(py, out.iter().map(|p| p.0).collect()),
        PyArray1::from_vec(py, out.iter().map(|p| p.1).collect()),
        PyArray1::from_vec(py, out.iter().map(|p| p.2).collect()),
    )
}

/// Point tests of `(alpha, beta, delta, d)` rows; consecutive rows of one plant share one
/// checker (the same checker a fresh one would be: it depends only on the plant).
fn check_rows(rows: &[[f64; 4]], options: Options, radius: bool) -> Vec<stabound::Result<Point>> {
    let mut out = Vec::with_capacity(rows.len());
    let mut cached: Option<((u64, u64), Checker)> = None;
    for r in rows {
        let one = (|| {
            let (plant, wall) = (Plant::new(r[2], r[3])?, Wall::new(r[0], r[1])?);
            let key = (plant.delta().to_bits(), plant.d().to_bits());
            let checker = match &cached {
                Some((k, c)) if *k == key => c,
                _ => &cached.insert((key, Checker::new(&plant, options)?)).1,
            };
            if radius {
                let a = checker.analyze(&wall)?;
                Ok((
                    a.spectral_radius,
                    verdict_code(a.verdict),
                    method_code(a.method),
                ))
            } else {
                let dec = checker.decide(&wall)?;
                Ok((f64::NAN, verdict_code(dec.verdict), method_code(dec.method)))
            }
        })();
        out.push(one);
    }
    out
}

/// The loop elements as the Python layer passes them: a dict from the element list's
/// keywords (`hand_mass`, ..., physical units) to values; `None` values are not named.
type ElementArgs<'py> = Bound<'py, PyDict>;

/// The named elements, each keyword and value read by the library's element list (the
/// checks of the values are the library's, in [`Loop::with_physical`]).
fn named_elements(elements: ElementArgs<'_>) -> PyResult<PhysicalElements> {
    let mut named = PhysicalElements::default();
    for (k, v) in elements.iter() {
        let key: String = k.extract()?;
        let Some(p) = list::param(&key) else {
            return Err(PyTypeError::new_err(format!(
                "unexpected keyword argument: {key}"
            )));
        };
        if v.is_none() {
            continue;
        }
        let value = match p.accepts {
            list::Accepts::Count { .. } => list::Value::Count(v.extract().map_err(|_| {
                PyValueError::new_err(format!("invalid {key} = {v}: give {}", p.expects()))
            })?),
            list::Accepts::Choice(_) => p.read(&v.extract::<String>()?).map_err(to_py)?,
            _ => list::Value::Number(v.extract()?),
        };
        p.set(&mut named, value);
    }
    Ok(named)
}

/// The loop of one device (delay in seconds, or in samples when `samples`) with the named
/// elements.
fn loop_of(
    mass: f64,
    period: f64,
    damping: f64,
    delay: f64,
    samples: bool,
    elements: ElementArgs,
) -> PyResult<Loop> {
    let delay = if samples {
        Delay::Samples(delay)
    } else {
        Delay::Seconds(delay)
    };
    let named = named_elements(elements)?;
    Device::new(mass, period, damping, delay)
        .and_then(|device| Loop::new(device.plant()?).with_physical(&device, &named))
        .map_err(to_py)
}

/// `alpha_max` and the `beta` where it is reached for one device with loop elements, from
/// the loop's exact boundary.
#[pyfunction]
#[pyo3(signature = (mass, period, damping, delay, samples, elements, beta_min=None, beta_max=None))]
#[allow(clippy::too_many_arguments)]
fn alpha_max_loop(
    py: Python<'_>,
    mass: f64,
    period: f64,
    damping: f64,
    delay: f64,
    samples: bool,
    elements: ElementArgs,
    beta_min: Option<f64>,
    beta_max: Option<f64>,
) -> PyResult<(f64, f64)> {
    let lp = loop_of(mass, period, damping, delay, samples, elements)?;
    let opts = AmaxOptions::default()
        .with_beta_limits(beta_min, beta_max)
        .map_err(to_py)?;
    let a = py
        .detach(|| stabound::elements::loop_alpha_max(&lp, &opts))
        .map_err(to_py)?;
    Ok((a.alpha_max, a.beta_at_max))
}

/// The (alpha, beta) boundary of one device with loop elements: `(delta, d, alpha, beta,
/// piece codes)`.
#[pyfunction]
#[pyo3(signature = (mass, period, damping, delay, samples, elements, tol, method_name))]
#[allow(clippy::too_many_arguments)]
fn boundary_loop<'py>(
    py: Python<'py>,
    mass: f64,
    period: f64,
    damping: f64,
    delay: f64,
    samples: bool,
    elements: ElementArgs,
    tol: f64,
    method_name: &str,
) -> PyResult<Bound<'py, PyList>> {
    let lp = loop_of(mass, period, damping, delay, samples, elements)?;
    let options = SweepOptions {
        engine: engine(method_name)?,
        tol,
    };
    let b = py
        .detach(|| boundary::loop_boundary(&lp, &options))
        .map_err(to_py)?;
    curves_list(py, std::slice::from_ref(&b))
}

/// Point tests of flat arrays of walls `(alpha, beta)` on one device with loop elements in
/// physical units (`delay` in seconds, or in samples when `samples`): (spectral radius,
/// verdict code, deciding method code), as `stabound check` with the element flags.
#[pyfunction]
#[pyo3(signature = (alpha, beta, mass, period, damping, delay, samples, elements, method_name, margin, radius))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn check_loop<'py>(
    py: Python<'py>,
    alpha: PyReadonlyArray1<'py, f64>,
    beta: PyReadonlyArray1<'py, f64>,
    mass: f64,
    period: f64,
    damping: f64,
    delay: f64,
    samples: bool,
    elements: ElementArgs,
    method_name: &str,
    margin: f64,
    radius: bool,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i8>>,
    Bound<'py, PyArray1<i8>>,
)> {
    let options = Options {
        method: method(method_name)?,
        margin,
    };
    let lp = loop_of(mass, period, damping, delay, samples, elements)?;
    let checker = LoopChecker::new(&lp, options).map_err(to_py)?;
    let (a, b) = (values(&alpha), values(&beta));
    let n = common_len(&[&a, &b])?;
    let walls: Vec<(f64, f64)> = (0..n).map(|i| (a[i], b[i])).collect();
    let out: Vec<Point> = par_map(py, &walls, |&(alpha, beta)| {
        let wall = Wall::new(alpha, beta)?;
        if radius {
            let r = checker.analyze(&wall)?;
            Ok((
                r.spectral_radius,
                verdict_code(r.verdict),
                method_code(r.method),
            ))
        } else {
            let v = checker.decide(&wall)?;
            Ok((f64::NAN, verdict_code(v.verdict), method_code(v.method)))
        }
    })?;
    Ok(point_arrays(py, &out))
}

/// Point tests of flat arrays: (spectral radius, verdict code, deciding method code).
#[pyfunction]
#[pyo3(signature = (alpha, beta, delta, d, method_name, margin, radius))]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn check<'py>(
    py: Python<'py>,
    alpha: PyReadonlyArray1<'py, f64>,
    beta: PyReadonlyArray1<'py, f64>,
    delta: PyReadonlyArray1<'py, f64>,
    d: PyReadonlyArray1<'py, f64>,
    method_name: &str,
    margin: f64,
    radius: bool,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i8>>,
    Bound<'py, PyArray1<i8>>,
)> {
    let options = Options {
        method: method(method_name)?,
        margin,
    };
    options.validate().map_err(to_py)?;
    let (a, b, x, dd) = (values(&alpha), values(&beta), values(&delta), values(&d));
    let n = common_len(&[&a, &b, &x, &dd])?;
    let rows: Vec<[f64; 4]> = (0..n).map(|i| [a[i], b[i], x[i], dd[i]]).collect();
    let mut out: Vec<Point> = Vec::with_capacity(n);
    // Blocks of 64 rows share a cached checker; the block split is fixed, not per thread.
    for chunk in rows.chunks(CHUNK) {
        let part: Vec<stabound::Result<Point>> = py.detach(|| {
            chunk
                .par_chunks(64)
                .flat_map_iter(|block| check_rows(block, options, radius))
                .collect()
        });
        out.extend(first_error(part)?);
        py.check_signals()?;
    }
    Ok(point_arrays(py, &out))
}

/// The full analysis of one point, as the command line's JSON: verdict, spectral radius,
/// roots, degree, method. With `device = (mass, period, damping)` also the physical wall.
#[pyfunction]
#[pyo3(signature = (alpha, beta, delta, d, method_name, margin, device=None))]
#[allow(clippy::too_many_arguments)]
fn analyze<'py>(
    py: Python<'py>,
    alpha: f64,
    beta: f64,
    delta: f64,
    d: f64,
    method_name: &str,
    margin: f64,
    device: Option<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = Options {
        method: method(method_name)?,
        margin,
    };
    let params = Normalized::new(alpha, beta, delta, d).map_err(to_py)?;
    let a = py
        .detach(|| {
            let (plant, wall) = params.split()?;
            Checker::new(&plant, options)?.analyze(&wall)
        })
        .map_err(to_py)?;
    let out = PyDict::new(py);
    out.set_item("stable", a.verdict.is_stable())?;
    out.set_item("verdict", a.verdict.name())?;
    out.set_item("spectral_radius", a.spectral_radius)?;
    let roots: Vec<numpy::Complex64> = a
        .roots
        .iter()
        .map(|z| numpy::Complex64::new(z.re, z.im))
        .collect();
    out.set_item("roots", PyArray1::from_vec(py, roots))?;
    out.set_item("degree", a.degree)?;
    out.set_item("method", a.method.name())?;
    out.set_item("margin", margin)?;
    out.set_item("alpha", alpha)?;
    out.set_item("beta", beta)?;
    out.set_item("delta", delta)?;
    out.set_item("d", d)?;
    if let Some((mass, period, damping)) = device {
        let dev = Device::new(mass, period, damping, Delay::Samples(d)).map_err(to_py)?;
        let phys = PyDict::new(py);
        phys.set_item("mass", mass)?;
        phys.set_item("period", period)?;
        phys.set_item("damping", damping)?;
        phys.set_item("stiffness", dev.stiffness(alpha))?;
        phys.set_item("wall_damping", dev.wall_damping(beta))?;
        phys.set_item("delay_samples", d)?;
        out.set_item("physical", phys)?;
    }
    Ok(out)
}

/// A device of element `i`.
fn device_at(
    m: &[f64],
    t: &[f64],
    b: &[f64],
    delay: &[f64],
    samples: bool,
    i: usize,
) -> stabound::Result<Device> {
    let delay = if samples {
        Delay::Samples(delay[i])
    } else {
        Delay::Seconds(delay[i])
    };
    Device::new(m[i], t[i], b[i], delay)
}

/// `(delta, d)` of devices in physical units (validated by the library).
#[pyfunction]
#[allow(clippy::type_complexity)]
fn normalize_plants<'py>(
    py: Python<'py>,
    mass: PyReadonlyArray1<'py, f64>,
    period: PyReadonlyArray1<'py, f64>,
    damping: PyReadonlyArray1<'py, f64>,
    delay: PyReadonlyArray1<'py, f64>,
    samples: bool,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let (m, t, b, dl) = (
        values(&mass),
        values(&period),
        values(&damping),
        values(&delay),
    );
    let n = common_len(&[&m, &t, &b, &dl])?;
    let plants = first_error(
        (0..n)
            .map(|i| device_at(&m, &t, &b, &dl, samples, i)?.plant())
            .collect(),
    )?;
    Ok((
        PyArray1::from_vec(py, plants.iter().map(Plant::delta).collect()),
        PyArray1::from_vec(py, plants.iter().map(Plant::d).collect()),
    ))
}

/// `(alpha, beta, delta, d)` of physical walls on physical devices (validated).
#[pyfunction]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn normalize_walls<'py>(
    py: Python<'py>,
    mass: PyReadonlyArray1<'py, f64>,
    period: PyReadonlyArray1<'py, f64>,
    damping: PyReadonlyArray1<'py, f64>,
    delay: PyReadonlyArray1<'py, f64>,
    samples: bool,
    stiffness: PyReadonlyArray1<'py, f64>,
    wall_damping: PyReadonlyArray1<'py, f64>,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let (m, t, b, dl) = (
        values(&mass),
        values(&period),
        values(&damping),
        values(&delay),
    );
    let (k, bw) = (values(&stiffness), values(&wall_damping));
    let n = common_len(&[&m, &t, &b, &dl, &k, &bw])?;
    let ps: Vec<Normalized> = first_error(
        (0..n)
            .map(|i| device_at(&m, &t, &b, &dl, samples, i)?.normalize(k[i], bw[i]))
            .collect(),
    )?;
    let col = |f: fn(&Normalized) -> f64| PyArray1::from_vec(py, ps.iter().map(f).collect());
    Ok((
        col(|p| p.alpha()),
        col(|p| p.beta()),
        col(|p| p.delta()),
        col(|p| p.d()),
    ))
}

/// Physical stiffness `K` and damping `B` of normalized `alpha`, `beta` for devices of mass
/// and period (the conversion of the command line's tables).
#[pyfunction]
#[allow(clippy::type_complexity)]
fn device_scale<'py>(
    py: Python<'py>,
    mass: PyReadonlyArray1<'py, f64>,
    period: PyReadonlyArray1<'py, f64>,
    alpha: PyReadonlyArray1<'py, f64>,
    beta: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let (m, t, a, b) = (
        values(&mass),
        values(&period),
        values(&alpha),
        values(&beta),
    );
    let n = common_len(&[&m, &t, &a, &b])?;
    let u = |i: usize| DeviceScale {
        mass: m[i],
        period: t[i],
    };
    Ok((
        PyArray1::from_vec(py, (0..n).map(|i| u(i).k(a[i])).collect()),
        PyArray1::from_vec(py, (0..n).map(|i| u(i).b(b[i])).collect()),
    ))
}

/// `alpha_max` options, validated.
fn amax_options(tol: f64, beta_min: Option<f64>, beta_max: Option<f64>) -> PyResult<AmaxOptions> {
    AmaxOptions::new(tol)
        .and_then(|o| o.with_beta_limits(beta_min, beta_max))
        .map_err(to_py)
}

/// `alpha_max` and the `beta` where it is reached, for each `(delta, d)`.
#[pyfunction]
#[pyo3(name = "alpha_max", signature = (delta, d, tol, beta_min=None, beta_max=None))]
#[allow(clippy::type_complexity)]
fn alpha_max_py<'py>(
    py: Python<'py>,
    delta: PyReadonlyArray1<'py, f64>,
    d: PyReadonlyArray1<'py, f64>,
    tol: f64,
    beta_min: Option<f64>,
    beta_max: Option<f64>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let opts = amax_options(tol, beta_min, beta_max)?;
    let (x, dd) = (values(&delta), values(&d));
    let n = common_len(&[&x, &dd])?;
    let pairs: Vec<(f64, f64)> = (0..n).map(|i| (x[i], dd[i])).collect();
    let res = par_map(py, &pairs, |&(x, d)| alpha_max(&Plant::new(x, d)?, &opts))?;
    Ok((
        PyArray1::from_vec(py, res.iter().map(|r| r.alpha_max).collect()),
        PyArray1::from_vec(py, res.iter().map(|r| r.beta_at_max).collect()),
    ))
}

/// Piece codes are indices into this list.
const PIECES: [boundary::Piece; 6] = [
    boundary::Piece::Curve,
    boundary::Piece::AlphaZero,
    boundary::Piece::MinusOne,
    boundary::Piece::Bisection,
    boundary::Piece::Clipped,
    boundary::Piece::PlusOne,
];

/// Boundaries in the (alpha, beta) plane for every `delta` (outer) and `d` (inner): a list
/// of `(delta, d, alpha, beta, piece codes)`.
#[pyfunction]
#[pyo3(name = "boundary", signature = (deltas, ds, tol, method_name))]
fn boundary_py<'py>(
    py: Python<'py>,
    deltas: Vec<f64>,
    ds: Vec<f64>,
    tol: f64,
    method_name: &str,
) -> PyResult<Bound<'py, PyList>> {
    let options = SweepOptions {
        engine: engine(method_name)?,
        tol,
    };
    let curves = py
        .detach(|| boundary::sweep(&deltas, &ds, &options, None))
        .map_err(to_py)?;
    curves_list(py, &curves)
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

/// Boundaries as a list of `(delta, d, alpha, beta, piece codes)`.
fn curves_list<'py>(py: Python<'py>, curves: &[Boundary]) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for b in curves {
        let piece: Vec<i8> = b
            .points
            .iter()
            .map(|p| {
                PIECES
                    .iter()
                    .position(|&q| q == p.piece)
                    .and_then(|i| i8::try_from(i).ok())
                    .unwrap_or(-1)
            })
            .collect();
        out.append((
            b.delta,
            b.d,
            PyArray1::from_vec(py, b.points.iter().map(|p| p.x).collect()),
            PyArray1::from_vec(py, b.points.iter().map(|p| p.y).collect()),
            PyArray1::from_vec(py, piece),
        ))?;
    }
    Ok(out)
}

/// One delta-beta contour: `(alpha, d, delta, beta, loop index, clipped)` per vertex.
type DeltaBetaCurve<'py> = (
    f64,
    f64,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<bool>>,
);

/// Boundaries in the (delta, beta) plane (bisection engine) for every `alpha` (outer) and
/// `d` (inner), over `delta` in `[lo, hi]`, as the command line's `--plane delta-beta`.
/// With `elements` on a device `(mass, period)`, each curve is that of the loop with those
/// elements (the axes stay normalized), one curve after the other as the command line.
#[pyfunction]
#[pyo3(signature = (alphas, ds, lo, hi, tol, device=None, elements=None))]
#[allow(clippy::too_many_arguments)]
fn boundary_delta_beta<'py>(
    py: Python<'py>,
    alphas: Vec<f64>,
    ds: Vec<f64>,
    lo: f64,
    hi: f64,
    tol: f64,
    device: Option<(f64, f64)>,
    elements: Option<ElementArgs>,
) -> PyResult<Vec<DeltaBetaCurve<'py>>> {
    let elements = match (elements, device) {
        (None, None) => None,
        (Some(e), Some(dev)) => Some((named_elements(e)?, dev)),
        (Some(_), None) => {
            return Err(PyValueError::new_err(
                "loop elements are given in physical units: give the device's mass and period",
            ));
        }
        (None, Some(_)) => {
            return Err(PyValueError::new_err(
                "the device's mass and period in the delta-beta plane belong to loop elements: name an element too, or leave them out",
            ));
        }
    };
    for &al in &alphas {
        stabound::params::Wall::new(al, 0.0).map_err(to_py)?;
        if al < 0.0 {
            return Err(PyValueError::new_err(format!(
                "invalid alpha = {al}: stiffness must be >= 0 (no wall with alpha < 0 is stable)"
            )));
        }
    }
    for &d in &ds {
        Plant::new(lo, d).map_err(to_py)?;
        Plant::new(hi, d).map_err(to_py)?;
    }
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
    let contours = py.detach(|| match &elements {
        None => first_error(
            requests
                .par_iter()
                .map(|&(alpha, d)| boundary::bisect(&plane_of(alpha, d)?, &options))
                .collect(),
        ),
        // one loop per curve, in order (each contour uses every core itself)
        Some((named, (m, t))) => requests
            .iter()
            .map(|&(alpha, d)| {
                let device = Device::new(*m, *t, 0.0, Delay::Samples(d))?;
                let lp = Loop::new(Plant::new(lo, d)?).with_physical(&device, named)?;
                boundary::bisect_loop_plane(&lp, &plane_of(alpha, d)?, &options)
            })
            .collect::<stabound::Result<Vec<_>>>()
            .map_err(to_py),
    })?;
    let mut out = Vec::with_capacity(contours.len());
    for (c, &(alpha, d)) in contours.iter().zip(&requests) {
        let pts = || {
            c.loops
                .iter()
                .enumerate()
                .flat_map(|(i, l)| l.iter().map(move |p| (i, p)))
        };
        out.push((
            alpha,
            d,
            PyArray1::from_vec(py, pts().map(|(_, p)| p.x).collect()),
            PyArray1::from_vec(py, pts().map(|(_, p)| p.y).collect()),
            PyArray1::from_vec(
                py,
                pts().map(|(i, _)| i64::try_from(i).unwrap_or(-1)).collect(),
            ),
            PyArray1::from_vec(py, pts().map(|(_, p)| p.clipped()).collect()),
        ));
    }
    Ok(out)
}

/// A lookup table of `alpha_max` over `deltas x ds`: the arrays and the command line's four
/// text formats. `scale = (mass, period)` adds the physical columns; `elements` (physical
/// units on that device) makes every node, and every query the conservative check tests,
/// that loop's.
#[pyfunction]
#[pyo3(name = "table", signature = (deltas, ds, tol, beta_min, beta_max, conservative, scale=None, elements=None))]
#[allow(clippy::too_many_arguments)]
fn table_py<'py>(
    py: Python<'py>,
    deltas: Vec<f64>,
    ds: Vec<f64>,
    tol: f64,
    beta_min: Option<f64>,
    beta_max: Option<f64>,
    conservative: bool,
    scale: Option<(f64, f64)>,
    elements: Option<ElementArgs>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = amax_options(tol, beta_min, beta_max)?;
    // the elements depend on the device's mass and period only: the loop of the first
    // node carries them to every node
    let lp = match (elements, scale, deltas.first(), ds.first()) {
        (None, ..) => None,
        (Some(e), Some((m, t)), Some(&x), Some(&d)) => Some(loop_of(m, t, x * m / t, d, true, e)?),
        (Some(_), None, ..) => {
            return Err(PyValueError::new_err(
                "loop elements are given in physical units: give the device (mass=, period=, damping=, delay=|delay_samples=)",
            ));
        }
        // an empty axis: the table's own check refuses it
        (Some(_), ..) => None,
    };
    let t = py
        .detach(|| match &lp {
            None => amax_table(&deltas, &ds, &opts, conservative),
            Some(lp) => amax_table_loop(&deltas, &ds, lp, &opts, conservative, Precision::Double),
        })
        .map_err(to_py)?;
    let units = scale.map(|(mass, period)| DeviceScale { mass, period });
    let out = PyDict::new(py);
    let grid = |v: &[Vec<f64>]| {
        PyArray2::from_vec2(py, v).map_err(|e| PyValueError::new_err(e.to_string()))
    };
    out.set_item("delta", PyArray1::from_slice(py, &t.delta))?;
    out.set_item("d", PyArray1::from_slice(py, &t.d))?;
    out.set_item("alpha_max", grid(&t.alpha_max)?)?;
    out.set_item("beta_at_max", grid(&t.beta_at_max)?)?;
    if let Some(u) = units {
        out.set_item("stiffness", grid(&u.stiffness(&t.alpha_max))?)?;
        out.set_item("wall_damping", grid(&u.wall_damping(&t.beta_at_max))?)?;
    }
    let all = 0..t.delta.len() * t.d.len();
    let csv = String::from_utf8_lossy(&to_csv_bytes(&lookup_rows(&t, &units, all))).into_owned();
    out.set_item("csv", csv)?;
    out.set_item("json", lookup_json(&t, &units))?;
    out.set_item("c_header", to_c_header(&t, &units))?;
    out.set_item("rust", to_rust(&t, &units))?;
    Ok(out)
}

/// Checks a scene, from a file (`path`) or from JSON text (`text`, named `origin` in
/// messages): the report as JSON text and as the command line's text.
#[pyfunction]
#[pyo3(signature = (path, text, origin, margin))]
fn scene(
    py: Python<'_>,
    path: Option<PathBuf>,
    text: Option<String>,
    origin: &str,
    margin: f64,
) -> PyResult<(String, String)> {
    let options = Options {
        margin,
        ..Options::default()
    };
    let report = py
        .detach(|| {
            let scene = match (&path, &text) {
                (Some(p), _) => Scene::read(p)?,
                (None, Some(t)) => Scene::parse(t, SceneFormat::Json, origin)?,
                (None, None) => {
                    return Err(stabound::Error::InvalidRequest(
                        "no scene given: pass a path or a dict".into(),
                    ));
                }
            };
            scene.check(&options)
        })
        .map_err(to_py)?;
    let json = serde_json::to_string(&report).map_err(|e| StaboundError::new_err(e.to_string()))?;
    Ok((json, report.to_text()))
}

/// Step responses of one device per damping (the command line's `step`, with its loop
/// elements, one loop per device): a list of dicts.
#[pyfunction]
#[pyo3(signature = (mass, period, dampings, delay, samples, stiffness, wall_damping, margin, force, duration, points_per_period, settling_band, elements=None))]
#[allow(clippy::too_many_arguments)]
fn step<'py>(
    py: Python<'py>,
    mass: f64,
    period: f64,
    dampings: Vec<f64>,
    delay: f64,
    samples: bool,
    stiffness: Option<f64>,
    wall_damping: Option<f64>,
    margin: Option<f64>,
    force: f64,
    duration: f64,
    points_per_period: i64,
    settling_band: f64,
    elements: Option<ElementArgs>,
) -> PyResult<Bound<'py, PyList>> {
    let named = match elements {
        Some(e) => named_elements(e)?,
        None => PhysicalElements::default(),
    };
    let names: Vec<&str> = named.names();
    let delay = if samples {
        Delay::Samples(delay)
    } else {
        Delay::Seconds(delay)
    };
    let options = StepOptions {
        force,
        duration,
        // a negative count is as wrong as zero, which the library rejects with its message
        points_per_period: usize::try_from(points_per_period).unwrap_or(0),
    };
    let wall_for = |device: &Device, lp: &Loop| -> stabound::Result<(f64, f64)> {
        match (stiffness, margin) {
            (Some(k), None) => Ok((k, wall_damping.unwrap_or(0.0))),
            (None, Some(f)) => loop_margin_wall(device, lp, f),
            _ => Err(stabound::Error::InvalidRequest(
                "give the stiffness or the margin, not both and not neither".into(),
            )),
        }
    };
    let runs = py.detach(|| {
        first_error(
            dampings
                .par_iter()
                .map(|&b| {
                    let device = Device::new(mass, period, b, delay)?;
                    let plant = device.plant()?;
                    let lp = Loop::new(plant).with_physical(&device, &named)?;
                    let (k, bw) = wall_for(&device, &lp)?;
                    let wall = device.wall(k, bw)?;
                    let verdict = LoopChecker::new(&lp, Options::default())?.verdict(&wall)?;
                    let r = loop_step_response(&device, &lp, k, bw, &options)?;
                    Ok((device, plant, wall, k, bw, verdict, r))
                })
                .collect(),
        )
    })?;
    let out = PyList::empty(py);
    for (device, plant, wall, k, bw, verdict, r) in runs {
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
        o.set_item("settling_time", r.settling_time(settling_band))?;
        o.set_item("time", PyArray1::from_slice(py, &r.time))?;
        o.set_item("position", PyArray1::from_slice(py, &r.position))?;
        o.set_item("samples", PyArray1::from_slice(py, &r.samples))?;
        o.set_item("elements", names.clone())?;
        out.append(o)?;
    }
    Ok(out)
}

/// The velocity filter named by a low-pass pole, a low-pass cutoff (Hz, with the sampling
/// period in s) or a moving average (samples), at most one of them; none is `F = 1`.
fn velocity_filter(
    pole: Option<f64>,
    cutoff: Option<f64>,
    period: Option<f64>,
    samples: Option<usize>,
) -> PyResult<VelocityFilter> {
    let named = [pole.is_some(), cutoff.is_some(), samples.is_some()];
    if named.iter().filter(|&&x| x).count() > 1 {
        return Err(PyValueError::new_err(
            "name one velocity filter: filter_pole, velocity_filter_cutoff or velocity_filter_samples",
        ));
    }
    match (pole, cutoff, samples) {
        (Some(a), _, _) => VelocityFilter::low_pass(a),
        (_, Some(fc), _) => match period {
            Some(t) => VelocityFilter::low_pass_cutoff(fc, t),
            None => {
                return Err(PyValueError::new_err(
                    "velocity_filter_cutoff needs period= (the sampling period in s)",
                ));
            }
        },
        (_, _, Some(n)) => VelocityFilter::moving_average(n),
        _ => Ok(VelocityFilter::none()),
    }
    .map_err(to_py)
}

/// A witness wall as a dict, or None.
fn witness<'py>(py: Python<'py>, w: Option<Witness>) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(w) = w else { return Ok(None) };
    let o = PyDict::new(py);
    o.set_item("alpha", w.alpha)?;
    o.set_item("beta", w.beta)?;
    o.set_item("delta", w.delta)?;
    o.set_item("margin", w.margin)?;
    o.set_item("verdict", w.verdict.name())?;
    Ok(Some(o))
}

/// What `stabound passivity` computes, as a dict: the passive edge (`x`, `y`, `theta`,
/// `edge`), the stable region's points and how they were found, the largest passive
/// stiffness (alpha-beta plane) and the comparison with the stable region.
#[pyfunction]
#[pyo3(signature = (plane, fixed, d, filter, tol, columns, delta_max, beta))]
#[allow(clippy::too_many_arguments)]
fn passivity<'py>(
    py: Python<'py>,
    plane: &str,
    fixed: f64,
    d: f64,
    filter: (Option<f64>, Option<f64>, Option<f64>, Option<usize>),
    tol: f64,
    columns: usize,
    delta_max: f64,
    beta: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let filter = velocity_filter(filter.0, filter.1, filter.2, filter.3)?;
    let crit = Criterion::new(d, filter).map_err(to_py)?;
    let out = PyDict::new(py);
    out.set_item("filter", filter_name(&filter))?;
    type Cmp = (
        PassiveRegion,
        Option<(Vec<(f64, f64)>, &'static str)>,
        Option<Summary>,
    );
    let (region, stable, verdicts): Cmp = match plane {
        "alpha-beta" => {
            let delta = fixed;
            let (cmp, best, at) = py
                .detach(|| -> stabound::Result<_> {
                    let cmp: Cmp = if filter.is_identity() {
                        let c = compare(delta, d, filter, tol)?;
                        let v = Summary::from(&c);
                        (c.region, Some((c.stable, "exact")), Some(v))
                    } else {
                        let c = compare_loop(delta, d, filter, columns, tol)?;
                        let v = Summary::from(&c);
                        (c.region, Some((c.stable_outline, "columns")), Some(v))
                    };
                    let best = crit.max_stiffness(delta, tol)?;
                    let at = match beta {
                        Some(b) => Some(crit.max_stiffness_at(delta, b, tol)?),
                        None => None,
                    };
                    Ok((cmp, best, at))
                })
                .map_err(to_py)?;
            out.set_item("alpha_max_passive", best.map(|b| b.0))?;
            out.set_item("beta_at_max", best.map(|b| b.1))?;
            out.set_item("alpha_max_at_beta", at.flatten())?;
            cmp
        }
        "delta-beta" => {
            let alpha = fixed;
            py.detach(|| -> stabound::Result<Cmp> {
                let cmp = if alpha > 0.0 {
                    Some(compare_loop_delta_beta(
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
            })
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

/// A figure's drawing and data: the paper's figure `number` (5 to 11, as `stabound figure`)
/// or, by `name`, a passivity companion (`fig08-d1`, ..., as `stabound passivity
/// --figures-dir`): `(name, svg text, csv text)`.
#[pyfunction]
#[pyo3(name = "figure", signature = (number, name))]
fn figure_py(
    number: Option<u32>,
    name: Option<String>,
    py: Python<'_>,
) -> PyResult<(String, String, String)> {
    let data = py
        .detach(|| match (number, &name) {
            (Some(n), _) => stabound::figures::figure(n),
            (None, Some(nm)) => {
                let found = companion_names().iter().position(|c| c == nm);
                match found {
                    Some(i) => {
                        let (fig, k) = (if i < 3 { 8 } else { 9 }, i % 3);
                        companion(fig, COMPANION_DELAYS[k])
                    }
                    None => Err(stabound::Error::InvalidRequest(format!(
                        "no figure named '{nm}'; give a number 5 to 11 or one of {}",
                        companion_names().join(", ")
                    ))),
                }
            }
            (None, None) => Err(stabound::Error::InvalidRequest(
                "give a figure number or name".into(),
            )),
        })
        .map_err(to_py)?;
    let svg = data.to_svg().map_err(to_py)?;
    Ok((data.name.clone(), svg, data.to_csv()))
}

/// The compiled core of stabound; use the `stabound` package, which documents every function.
#[pymodule]
mod _stabound {
    use super::*;

    #[pymodule_export]
    use super::{
        StaboundError, alpha_max_loop, alpha_max_py, analyze, boundary_delta_beta, boundary_loop,
        boundary_py, check, check_loop, device_scale, figure_py, normalize_plants, normalize_walls,
        passivity, scene, step, table_py,
    };

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        let methods: Vec<&str> = METHODS_ALL.iter().map(|x| x.name()).collect();
        m.add("METHODS", methods)?;
        m.add("VERDICTS", vec!["stable", "marginal", "unstable"])?;
        m.add(
            "ELEMENT_KEYWORDS",
            list::PARAMS.iter().map(|p| p.keyword).collect::<Vec<_>>(),
        )?;
        m.add(
            "PIECES",
            PIECES.iter().map(|p| p.name()).collect::<Vec<_>>(),
        )?;
        m.add("DEFAULT_MARGIN", stabound::stability::DEFAULT_MARGIN)?;
        m.add("DEFAULT_AMAX_TOL", stabound::amax::DEFAULT_THETA_TOL)?;
        m.add("DEFAULT_BOUNDARY_TOL", boundary::DEFAULT_TOL)?;
        m.add("DEFAULT_COLUMNS", DEFAULT_COLUMNS)?;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        Ok(())
    }
}
