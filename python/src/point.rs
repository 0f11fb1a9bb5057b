//! Point tests (`check`, `analyze`) and the conversion of physical units (`normalize`).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyFloat, PyString, PyTuple};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Device, Normalized, Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict};

use crate::args::{self, Floats, broadcast, delay_name, delay_of, floats, located};
use crate::work::{first_error, interruptible, par_map};
use crate::{class, renamed, to_py};
use stabound::request;
use stabound::request::{DeviceInputs, Given, Input, Takes};
use stabound::robust::{Quantity, RobustCheck, robust_check};

/// Every point-test method, in the order of `METHODS` (and of the method codes).
pub const METHODS_ALL: [Method; 6] = [
    Method::Auto,
    Method::SchurCohn,
    Method::Eigen,
    Method::StateSpace,
    Method::ArgumentPrinciple,
    Method::Certified,
];

/// Verdict names in the order of the verdict codes.
pub const VERDICTS: [&str; 3] = ["stable", "marginal", "unstable"];

/// Up to this many points run on the calling thread (interpreter detached); more run where
/// Ctrl-C is watched (`work`), whose thread start (tens of us) is small against them.
const SMALL: usize = 16;

/// Rows of one plant share a checker in blocks of this many; the split is fixed, not per
/// thread, so results do not depend on the number of threads.
const BLOCK: usize = 64;

/// A stability method by its command-line name (`schur_cohn` is taken for `schur-cohn`).
pub fn method(name: &str) -> PyResult<Method> {
    // compared byte by byte with `_` read as `-` (both ASCII), without a copy of the name
    let same = |m: &Method| {
        let key = m.name().as_bytes();
        key.len() == name.len()
            && key
                .iter()
                .zip(name.bytes())
                .all(|(&k, b)| k == if b == b'_' { b'-' } else { b })
    };
    METHODS_ALL.iter().copied().find(same).ok_or_else(|| {
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

fn verdict_code(v: Verdict) -> u8 {
    match v {
        Verdict::Stable => 0,
        Verdict::Marginal => 1,
        Verdict::Unstable => 2,
    }
}

fn method_code(m: Method) -> u8 {
    METHODS_ALL
        .iter()
        .position(|&x| x == m)
        .and_then(|i| u8::try_from(i).ok())
        .unwrap_or(0)
}

/// One point test: (spectral radius, verdict code, method code).
type Point = (f64, u8, u8);

/// One wall on a checker: the radius only when asked (it costs the roots).
fn point(c: &Checker, wall: &Wall, radius: bool) -> stabound::Result<Point> {
    if radius {
        let a = c.analyze(wall)?;
        Ok((
            a.spectral_radius,
            verdict_code(a.verdict),
            method_code(a.method),
        ))
    } else {
        let d = c.decide(wall)?;
        Ok((f64::NAN, verdict_code(d.verdict), method_code(d.method)))
    }
}

/// Point tests of `(alpha, beta, delta, d)` rows; consecutive rows of one plant share one
/// checker (the same a fresh one would be: it depends only on the plant).
fn check_rows(rows: &[[f64; 4]], options: Options, radius: bool) -> Vec<stabound::Result<Point>> {
    let mut cached: Option<((u64, u64), Checker)> = None;
    rows.iter()
        .map(|r| {
            let (plant, wall) = (Plant::new(r[2], r[3])?, Wall::new(r[0], r[1])?);
            let key = (plant.delta().to_bits(), plant.d().to_bits());
            let checker = match &cached {
                Some((k, c)) if *k == key => c,
                _ => &cached.insert((key, Checker::new(plant, options)?)).1,
            };
            point(checker, &wall, radius)
        })
        .collect()
}

/// The walls of `check` and `analyze`, given either way, as broadcast normalized rows.
pub struct Walls {
    pub shape: Vec<usize>,
    pub rows: Vec<[f64; 4]>,
    /// The physical inputs (for naming an entry at fault), empty for normalized ones.
    pub inputs: Vec<Floats>,
    pub samples: bool,
    /// Whether the inputs are a device in physical units.
    pub physical: bool,
}

/// The low ends of a device's intervals (mass, damping, delay, delay_samples), owned.
pub type Lows<'py> = [Option<Bound<'py, PyAny>>; 4];

/// Devices in physical units: `mass`, `period`, `damping` and the delay required.
pub struct DeviceArgs<'a, 'py> {
    pub mass: Option<&'a Bound<'py, PyAny>>,
    pub period: Option<&'a Bound<'py, PyAny>>,
    pub damping: Option<&'a Bound<'py, PyAny>>,
    pub delay: Option<&'a Bound<'py, PyAny>>,
    pub delay_samples: Option<&'a Bound<'py, PyAny>>,
}

impl<'a, 'py> DeviceArgs<'a, 'py> {
    pub fn any(&self) -> bool {
        [
            self.mass,
            self.period,
            self.damping,
            self.delay,
            self.delay_samples,
        ]
        .iter()
        .any(Option::is_some)
    }

    /// The device's parameters given as `stabound.Interval` (a set of devices): their low
    /// ends (mass, damping, delay, delay_samples; `None` where not an interval), read with
    /// [`DeviceArgs::with_lows`], and the intervals.
    pub fn intervals(&self) -> PyResult<(Lows<'py>, Vec<args::Spread>)> {
        let mut spreads = Vec::new();
        let mut lows = [None, None, None, None];
        let given = [
            (self.mass, "mass", Quantity::Mass),
            (self.damping, "damping", Quantity::Damping),
            (self.delay, "delay", Quantity::Delay),
            (self.delay_samples, "delay_samples", Quantity::Delay),
        ];
        for (k, (obj, name, q)) in given.into_iter().enumerate() {
            let (low, spread) = args::interval(obj, name, || Ok(q))?;
            lows[k] = low;
            spreads.extend(spread);
        }
        Ok((lows, spreads))
    }

    /// The same device with the low ends `lows` of [`DeviceArgs::intervals`] in place of
    /// the intervals.
    pub fn with_lows<'b>(&'b self, lows: &'b Lows<'py>) -> DeviceArgs<'b, 'py>
    where
        'a: 'b,
    {
        DeviceArgs {
            mass: lows[0].as_ref().or(self.mass),
            period: self.period,
            damping: lows[1].as_ref().or(self.damping),
            delay: lows[2].as_ref().or(self.delay),
            delay_samples: lows[3].as_ref().or(self.delay_samples),
        }
    }

    /// The device's inputs as the library's request layer takes them.
    pub fn request(&self) -> DeviceInputs<&'a Bound<'py, PyAny>> {
        DeviceInputs {
            mass: self.mass,
            period: self.period,
            damping: self.damping,
            delay: self.delay,
            delay_samples: self.delay_samples,
            ..DeviceInputs::default()
        }
    }

    /// The four device inputs and whether the delay is in samples (the library's request
    /// layer refuses a missing one).
    pub fn inputs(&self) -> PyResult<(Vec<Floats>, bool)> {
        let given = self
            .request()
            .resolve_physical(Takes::Plants)
            .map_err(to_py)?;
        Ok(device_floats(given)?.0)
    }

    /// One device (scalars), for loop elements.
    pub fn one(&self, what: &str) -> PyResult<Device> {
        let (inputs, samples) = self.inputs()?;
        for f in &inputs {
            if !f.is_scalar() {
                return Err(PyValueError::new_err(format!(
                    "with {what} {}= is one number (one device)",
                    f.name.trim_end_matches("_samples")
                )));
            }
        }
        let v = |k: usize| inputs[k].values[0];
        Device::new(v(0), v(1), v(2), delay_of(v(3), samples)).map_err(to_py)
    }
}

/// The library's names of device inputs mapped to argument names.
pub fn aliases(samples: bool) -> [(&'static str, &'static str); 2] {
    [
        ("delay", delay_name(samples)),
        ("wall damping", "wall_damping"),
    ]
}

/// Broadcast physical devices (and walls, when `walls` is `Some((stiffness, wall_damping))`)
/// to normalized rows `(alpha, beta, delta, d)` (alpha and beta NaN without walls).
#[allow(clippy::needless_range_loop)] // row i reads column k at i, for six columns
pub fn physical_rows(
    device: &DeviceArgs<'_, '_>,
    walls: Option<(&Bound<'_, PyAny>, &Bound<'_, PyAny>)>,
) -> PyResult<Walls> {
    let (mut inputs, samples) = device.inputs()?;
    if let Some((k, bw)) = walls {
        inputs.push(floats(k, "stiffness")?);
        inputs.push(floats(bw, "wall_damping")?);
    }
    let refs: Vec<&Floats> = inputs.iter().collect();
    let shape = broadcast(&refs)?;
    let cols: Vec<Vec<f64>> = inputs.iter().map(|f| f.spread(&shape)).collect();
    let n: usize = shape.iter().product();
    let mut rows = Vec::with_capacity(n);
    for i in 0..n {
        let one = || -> stabound::Result<[f64; 4]> {
            let dev = Device::new(
                cols[0][i],
                cols[1][i],
                cols[2][i],
                delay_of(cols[3][i], samples),
            )?;
            if walls.is_some() {
                let p = dev.normalize(cols[4][i], cols[5][i])?;
                Ok([p.alpha(), p.beta(), p.delta(), p.d()])
            } else {
                let p = dev.plant()?;
                Ok([f64::NAN, f64::NAN, p.delta(), p.d()])
            }
        };
        rows.push(one().map_err(|e| located(e, i, &shape, &refs, &aliases(samples)))?);
    }
    Ok(Walls {
        shape,
        rows,
        inputs,
        samples,
        physical: true,
    })
}

/// The device's floats of a request given in physical units, whether the delay is in
/// samples, and the wall's `(stiffness, wall_damping)` when the request takes walls.
#[allow(clippy::type_complexity)]
fn device_floats<'a, 'py>(
    given: Given<&'a Bound<'py, PyAny>>,
) -> PyResult<(
    (Vec<Floats>, bool),
    Option<(&'a Bound<'py, PyAny>, &'a Bound<'py, PyAny>)>,
)> {
    let samples = matches!(
        given,
        Given::Physical {
            in_samples: true,
            ..
        }
    );
    let wall = match given {
        Given::Physical { wall, .. } => wall,
        Given::Normalized { .. } => None,
    };
    let mut inputs = Vec::with_capacity(4);
    given.try_map(|i, obj| -> PyResult<()> {
        if !matches!(i, Input::Stiffness | Input::WallDamping) {
            inputs.push(floats(obj, i.keyword())?);
        }
        Ok(())
    })?;
    Ok(((inputs, samples), wall))
}

/// The walls of `check` / `analyze` in either form (the library's request layer decides
/// which, and refuses mixed or missing inputs).
fn walls(
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    device: &DeviceArgs<'_, '_>,
    stiffness: Option<&Bound<'_, PyAny>>,
    wall_damping: Option<&Bound<'_, PyAny>>,
) -> PyResult<Walls> {
    let [alpha, beta, delta, d] = normalized;
    let given = DeviceInputs {
        alpha,
        beta,
        delta,
        d,
        stiffness,
        wall_damping,
        ..device.request()
    }
    .resolve(Takes::Walls)
    .map_err(to_py)?;
    if given.is_physical() {
        return physical_rows(device, stiffness.zip(wall_damping));
    }
    let mut inputs = Vec::with_capacity(4);
    for (obj, name) in normalized.iter().zip(["alpha", "beta", "delta", "d"]) {
        inputs.push(floats(obj.expect("resolved"), name)?);
    }
    let refs: Vec<&Floats> = inputs.iter().collect();
    let shape = broadcast(&refs)?;
    let cols: Vec<Vec<f64>> = inputs.iter().map(|f| f.spread(&shape)).collect();
    let rows = (0..cols[0].len())
        .map(|i| [cols[0][i], cols[1][i], cols[2][i], cols[3][i]])
        .collect();
    Ok(Walls {
        shape,
        rows,
        inputs,
        samples: false,
        physical: false,
    })
}

/// The `CheckResult` of point tests in `shape`: Python scalars for a scalar shape.
fn check_result(
    py: Python<'_>,
    shape: &[usize],
    pts: &[Point],
    radius: bool,
) -> PyResult<Py<PyAny>> {
    if shape.is_empty() {
        return scalar_result(py, pts[0], radius);
    }
    let cls = class(py, "CheckResult")?;
    let arr = |v: Vec<f64>| PyArray1::from_vec(py, v).reshape(shape.to_vec());
    let codes =
        PyArray1::from_vec(py, pts.iter().map(|p| p.1 as i8).collect()).reshape(shape.to_vec())?;
    let mcodes = PyArray1::from_vec(py, pts.iter().map(|p| p.2 as i8).collect());
    let stable =
        PyArray1::from_vec(py, pts.iter().map(|p| p.1 == 0).collect()).reshape(shape.to_vec())?;
    let verdicts = class(py, "_VERDICT_NAMES")?.get_item(&codes)?;
    let methods = class(py, "_METHOD_NAMES")?
        .get_item(mcodes)?
        .call_method1("reshape", (PyTuple::new(py, shape)?,))?;
    let out = (
        arr(pts.iter().map(|p| p.0).collect())?,
        verdicts,
        codes,
        stable,
        methods,
    );
    Ok(cls.call1(out)?.unbind())
}

/// `check` of normalized rows (the paper's loop).
fn check_paper(py: Python<'_>, w: Walls, options: Options, radius: bool) -> PyResult<Py<PyAny>> {
    let Walls {
        shape,
        rows,
        inputs,
        samples,
        ..
    } = w;
    let out = if rows.len() <= SMALL {
        py.detach(|| first_error(check_rows(&rows, options, radius)))
    } else {
        interruptible(py, move |cancel| {
            let blocks: Vec<&[[f64; 4]]> = rows.chunks(BLOCK).collect();
            let parts = par_map(&blocks, cancel, |b| Ok(check_rows(b, options, radius)));
            match parts {
                Ok(parts) => first_error(parts.into_iter().flatten().collect()),
                Err(e) => Err(e),
            }
        })?
    };
    let refs: Vec<&Floats> = inputs.iter().collect();
    let pts = out.map_err(|(i, e)| located(e, i, &shape, &refs, &aliases(samples)))?;
    check_result(py, &shape, &pts, radius)
}

/// `check` of one wall given as four Python floats, the commonest call, without the
/// broadcasting machinery and without releasing the GIL (one verdict takes less time than a
/// release and a re-acquisition). `None` when the arguments are anything else, or when the
/// wall is refused: the general path then answers, with its error message.
fn check_one(
    py: Python<'_>,
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    options: Options,
    radius: bool,
) -> Option<Py<PyAny>> {
    let mut v = [0.0; 4];
    for (x, obj) in v.iter_mut().zip(normalized) {
        *x = obj?.cast_exact::<PyFloat>().ok()?.value();
    }
    let (plant, wall) = (Plant::new(v[2], v[3]).ok()?, Wall::new(v[0], v[1]).ok()?);
    // read in place: moving the checker out of the `Result` copies it
    let checker = Checker::new(plant, options);
    let pt = point(checker.as_ref().ok()?, &wall, radius).ok()?;
    scalar_result(py, pt, radius).ok()
}

/// The `CheckResult` of one point test, with the verdict and method names interned once.
///
/// A verdict-only result (`radius=False`: the radius is NaN) is one of 3 x 6 (verdict x
/// method), built on first use and shared after, as Python shares its small ints: a named
/// tuple of a float, strings, an int and a bool is immutable, so no caller can tell a
/// shared one from a fresh one except by `is` (and two of them with the same verdict and
/// method compare equal: `==` on tuples takes an item identical to itself as equal, NaN
/// included). The shared result costs a reference count against a tuple's construction and
/// destruction, which cost more than the verdict.
fn scalar_result(py: Python<'_>, pt: Point, radius: bool) -> PyResult<Py<PyAny>> {
    static SHARED: PyOnceLock<Vec<Py<PyAny>>> = PyOnceLock::new();
    if radius {
        return fresh_result(py, pt);
    }
    let shared = SHARED.get_or_try_init(py, || -> PyResult<_> {
        let mut all = Vec::with_capacity(VERDICTS.len() * METHODS_ALL.len());
        for v in 0..VERDICTS.len() {
            for m in 0..METHODS_ALL.len() {
                // both indices are below 6: the casts are exact
                all.push(fresh_result(py, (f64::NAN, v as u8, m as u8))?);
            }
        }
        Ok(all)
    })?;
    let (_, v, m) = pt;
    match shared.get(usize::from(v) * METHODS_ALL.len() + usize::from(m)) {
        Some(r) => Ok(r.clone_ref(py)),
        None => fresh_result(py, pt),
    }
}

/// A new `CheckResult` of one point test, built by `tuple.__new__` as the named tuple's own
/// `_make` does (its Python-level `__new__` costs more than the verdict).
fn fresh_result(py: Python<'_>, (r, v, m): Point) -> PyResult<Py<PyAny>> {
    static MAKE: PyOnceLock<(Py<PyAny>, Py<PyAny>)> = PyOnceLock::new();
    static NAMES: PyOnceLock<Vec<Py<PyString>>> = PyOnceLock::new();
    let (new, cls) = MAKE.get_or_try_init(py, || -> PyResult<_> {
        let new = py.get_type::<PyTuple>().getattr("__new__")?;
        Ok((new.unbind(), class(py, "CheckResult")?.unbind()))
    })?;
    let names = NAMES.get_or_init(py, || {
        VERDICTS
            .iter()
            .copied()
            .chain(METHODS_ALL.iter().map(|m| m.name()))
            .map(|n| PyString::intern(py, n).unbind())
            .collect()
    });
    let fields = (
        r,
        names[usize::from(v)].clone_ref(py),
        v,
        v == 0,
        names[VERDICTS.len() + usize::from(m)].clone_ref(py),
    );
    Ok(new
        .bind(py)
        .call1((cls.bind(py), fields.into_pyobject(py)?))?
        .unbind())
}

/// `check` of walls on one device with loop elements.
#[allow(clippy::too_many_arguments)]
fn check_loop(
    py: Python<'_>,
    device: &DeviceArgs<'_, '_>,
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    stiffness: Option<&Bound<'_, PyAny>>,
    wall_damping: Option<&Bound<'_, PyAny>>,
    named: &PhysicalElements,
    options: Options,
    radius: bool,
) -> PyResult<Py<PyAny>> {
    if normalized.iter().any(Option::is_some) {
        return Err(PyValueError::new_err(
            "loop elements are given in physical units: give the device (mass=, period=, damping=, delay=|delay_samples=) and the walls (stiffness=, wall_damping=)",
        ));
    }
    let dev = device.one("loop elements")?;
    let (Some(k), Some(bw)) = (stiffness, wall_damping) else {
        let name = if stiffness.is_none() {
            "stiffness"
        } else {
            "wall_damping"
        };
        return Err(PyValueError::new_err(format!("missing {name}=")));
    };
    let (k, bw) = (floats(k, "stiffness")?, floats(bw, "wall_damping")?);
    let shape = broadcast(&[&k, &bw])?;
    let (ks, bws) = (k.spread(&shape), bw.spread(&shape));
    let lp = Loop::physical(&dev, named).map_err(to_py)?;
    let checker = Checker::new(lp, options).map_err(to_py)?;
    let walls: Vec<(f64, f64)> = ks.into_iter().zip(bws).collect();
    let out = interruptible(py, move |cancel| {
        par_map(&walls, cancel, |&(k, b)| {
            point(&checker, &dev.wall(k, b)?, radius)
        })
    })?;
    let pts = out.map_err(|(i, e)| located(e, i, &shape, &[&k, &bw], &aliases(true)))?;
    check_result(py, &shape, &pts, radius)
}

/// Test walls for stability: verdict and spectral radius of each point.
///
/// ``alpha``, ``beta``, ``delta`` and ``d`` broadcast against each other (numpy rules);
/// the result has their broadcast shape, or is scalar when all four are scalars. Or give
/// the walls in physical units: ``mass=`` (kg), ``period=`` (s), ``damping=`` (N s/m),
/// ``stiffness=`` (N/m), ``wall_damping=`` (N s/m) and ``delay=`` (s) or
/// ``delay_samples=``, all broadcasting.
///
/// ``method`` is one of :data:`METHODS` (``'auto'``: Schur-Cohn with a rounding-error
/// guard, then a proven argument-principle count, then the certified stage (coefficient
/// bounds and inclusion discs) where it cannot vouch; ``'marginal'`` where none can). A spectral radius within ``marginal_band`` (default
/// :data:`DEFAULT_MARGINAL_BAND`; ``margin=`` is its old name) of 1 is ``'marginal'``. With
/// ``radius=False`` only the verdicts are computed (faster: no roots) and the spectral
/// radius is NaN; a scalar result is then one shared object per verdict and method (two
/// such results with the same verdict and method are equal, NaN and all). ``radius=False``
/// gives the verdicts and methods of ``stabound check --batch``'s default output,
/// ``radius=True`` also the radius of its ``--radius`` column.
///
/// Arrays of walls are tested with the GIL released, in parallel beyond 16 walls. One wall
/// given as four Python floats is tested on the calling thread with the GIL held: its
/// verdict takes less time than releasing and re-acquiring the GIL. The results are the
/// same for any number of threads and the same, bit for bit, as ``stabound check`` prints.
///
/// >>> r = check([0.1, 5.0], 0.3, 0.5, 1.0)
/// >>> r.verdict.tolist(), r.code.tolist()
/// (['stable', 'unstable'], [0, 2])
/// >>> check(alpha=0.1, beta=0.3, delta=0.5, d=1.0, method="schur-cohn").stable
/// True
/// >>> check(mass=1.0, period=1e-3, damping=0.0, stiffness=1e5, wall_damping=300.0, delay_samples=1).verdict
/// 'stable'
///
/// Loop elements, in physical units on one device (scalar ``mass``, ``period``,
/// ``damping`` and delay; the walls may be arrays), as ``stabound check`` takes them: an
/// operator hand (``hand_mass=`` kg, ``hand_damping=`` N s/m, ``hand_stiffness=`` N/m), a
/// compliant transmission (``handle_mass=``, ``transmission_stiffness=``,
/// ``transmission_damping=``, ``encoder='motor'|'handle'``), an actuator lag
/// (``actuator_time_constant=`` s) and a velocity filter (``velocity_filter_cutoff=`` Hz or
/// ``velocity_filter_samples=``):
///
/// >>> check(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=10800.0,
/// ...       wall_damping=42.5, velocity_filter_cutoff=3.18).verdict
/// 'unstable'
///
/// Arrays may hold floats or ints; strings, bools, dates, masked arrays and objects are refused (TypeError). A bad array entry is named with its index: ``alpha[3]: invalid alpha = NaN: ...``.
#[pyfunction]
#[pyo3(signature = (alpha=None, beta=None, delta=None, d=None, *, method="auto", marginal_band=None, radius=true, mass=None, period=None, damping=None, stiffness=None, wall_damping=None, delay=None, delay_samples=None, margin=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn check<'py>(
    py: Python<'py>,
    alpha: Option<&Bound<'py, PyAny>>,
    beta: Option<&Bound<'py, PyAny>>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    method: &str,
    marginal_band: Option<&Bound<'py, PyAny>>,
    radius: bool,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let options = point_options(py, method, marginal_band, margin)?;
    let device_given = [
        mass,
        period,
        damping,
        stiffness,
        wall_damping,
        delay,
        delay_samples,
    ];
    if device_given.iter().all(Option::is_none)
        && elements.is_none_or(|e| e.is_empty())
        && let Some(one) = check_one(py, [alpha, beta, delta, d], options, radius)
    {
        return Ok(one);
    }
    let (named, mut spreads) = args::elements_and_intervals(elements)?;
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
    let normalized = [alpha, beta, delta, d];
    if !spreads.is_empty()
        && let Some(set) = check_set(
            py,
            &device,
            normalized,
            [stiffness, wall_damping],
            &named,
            &spreads,
        )?
    {
        return Ok(set);
    }
    if named.any() {
        return check_loop(
            py,
            &device,
            normalized,
            stiffness,
            wall_damping,
            &named,
            options,
            radius,
        );
    }
    let w = walls(normalized, &device, stiffness, wall_damping)?;
    check_paper(py, w, options, radius)
}

/// One wall on a set of devices (`stabound check` with an interval): the verdict for every
/// member as a `SetCheck`; `None` when the intervals leave one device.
fn check_set(
    py: Python<'_>,
    device: &DeviceArgs<'_, '_>,
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    wall: [Option<&Bound<'_, PyAny>>; 2],
    named: &PhysicalElements,
    spreads: &[args::Spread],
) -> PyResult<Option<Py<PyAny>>> {
    let [alpha, beta, delta, d] = normalized;
    let given = DeviceInputs {
        alpha,
        beta,
        delta,
        d,
        stiffness: wall[0],
        wall_damping: wall[1],
        ..device.request()
    }
    .resolve(Takes::Walls)
    .map_err(to_py)?;
    given
        .physical_for("sets of devices", true, Takes::Walls)
        .map_err(to_py)?;
    let Given::Physical {
        wall: Some((k, b)), ..
    } = given
    else {
        return Ok(None);
    };
    let (k, b) = (
        args::number(k, "stiffness")?,
        args::number(b, "wall_damping")?,
    );
    let dev = device.one("a set of devices")?;
    // a point test checks the device as given: the hand is not let go
    let Some(set) = request::device_set(&dev, named, spreads, false, false).map_err(to_py)? else {
        return Ok(None);
    };
    let wall = set.reference().device().wall(k, b).map_err(to_py)?;
    let (found, set) =
        interruptible(py, move |_| robust_check(&set, &wall).map(|f| (f, set)))?.map_err(to_py)?;
    let (verdict, shown, member) = match &found {
        RobustCheck::Stable(how) => (Verdict::Stable, how.describe(), None),
        RobustCheck::Fails(m, v) => (
            *v,
            "a member on which the wall is not stable".to_string(),
            Some(set.describe_member(m)),
        ),
        RobustCheck::Undecided { samples, shortfall } => (
            Verdict::Marginal,
            format!(
                "UNDECIDED: after {samples} members some cells of the set still fall short by {shortfall:e}"
            ),
            None,
        ),
        _ => (Verdict::Marginal, "undecided".to_string(), None),
    };
    let stopped = match &found {
        RobustCheck::Stable(how) => how.proof_stop().map(|p| p.describe()),
        _ => None,
    };
    let items = (
        verdict.name(),
        matches!(found, RobustCheck::Stable(_)),
        shown,
        member,
        PyTuple::new(py, set.describe())?,
        stopped,
    );
    Ok(Some(class(py, "SetCheck")?.call1(items)?.unbind()))
}

/// The point-test options of `method=` and the marginal band (`margin=` its old name).
fn point_options(
    py: Python<'_>,
    method_name: &str,
    band: Option<&Bound<'_, PyAny>>,
    old: Option<&Bound<'_, PyAny>>,
) -> PyResult<Options> {
    let band = renamed(py, band, old, "margin", "marginal_band")?;
    let method = method(method_name)?;
    let Some(band) = band else {
        // the library's default band, valid by its definition
        return Ok(Options {
            method,
            ..Options::default()
        });
    };
    let options = Options {
        method,
        margin: args::number(&band, "marginal_band")?,
    };
    options.validate().map_err(to_py)?;
    Ok(options)
}

/// Everything ``stabound check --format json`` reports for one wall, with the roots.
///
/// Keys: ``stable``, ``verdict``, ``spectral_radius``, ``roots`` (complex array),
/// ``degree``, ``method``, ``marginal_band``, ``alpha``, ``beta``, ``delta``, ``d``, and for a
/// wall in physical units ``physical`` (``mass_kg``, ``period_s``, ``damping_Ns_per_m``,
/// ``stiffness_N_per_m``, ``wall_damping_Ns_per_m``, ``delay_samples``).
///
/// >>> r = analyze(0.1, 0.3, 0.5, 1.0)
/// >>> r["verdict"], r["degree"], len(r["roots"])
/// ('stable', 4, 4)
#[pyfunction]
#[pyo3(signature = (alpha=None, beta=None, delta=None, d=None, *, method="auto", marginal_band=None, mass=None, period=None, damping=None, stiffness=None, wall_damping=None, delay=None, delay_samples=None, margin=None))]
#[allow(clippy::too_many_arguments)]
pub fn analyze<'py>(
    py: Python<'py>,
    alpha: Option<&Bound<'py, PyAny>>,
    beta: Option<&Bound<'py, PyAny>>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    method: &str,
    marginal_band: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = point_options(py, method, marginal_band, margin)?;
    let device = DeviceArgs {
        mass,
        period,
        damping,
        delay,
        delay_samples,
    };
    let w = walls([alpha, beta, delta, d], &device, stiffness, wall_damping)?;
    if !w.shape.is_empty() {
        return Err(PyValueError::new_err(
            "analyze takes one wall (scalars); use check() for arrays",
        ));
    }
    let [alpha, beta, delta, d] = w.rows[0];
    let params = Normalized::new(alpha, beta, delta, d).map_err(to_py)?;
    let a = py
        .detach(|| {
            let (plant, wall) = params.split()?;
            Checker::new(plant, options)?.analyze(&wall)
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
    out.set_item("marginal_band", options.margin)?;
    out.set_item("alpha", alpha)?;
    out.set_item("beta", beta)?;
    out.set_item("delta", delta)?;
    out.set_item("d", d)?;
    if w.physical {
        let v = |k: usize| w.inputs[k].values[0];
        let dev = Device::new(v(0), v(1), v(2), delay_of(d, true)).map_err(to_py)?;
        let phys = PyDict::new(py);
        phys.set_item("mass_kg", v(0))?;
        phys.set_item("period_s", v(1))?;
        phys.set_item("damping_Ns_per_m", v(2))?;
        phys.set_item("stiffness_N_per_m", dev.stiffness(alpha))?;
        phys.set_item("wall_damping_Ns_per_m", dev.wall_damping(beta))?;
        phys.set_item("delay_samples", d)?;
        out.set_item("physical", phys)?;
    }
    Ok(out)
}

/// Columns of rows in `shape`: Python floats for a scalar shape, else arrays.
pub fn columns<'py>(
    py: Python<'py>,
    shape: &[usize],
    cols: impl IntoIterator<Item = Vec<f64>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let items: Vec<Py<PyAny>> = cols
        .into_iter()
        .map(|c| -> PyResult<Py<PyAny>> {
            if shape.is_empty() {
                Ok(c[0].into_pyobject(py)?.into_any().unbind())
            } else {
                Ok(PyArray1::from_vec(py, c)
                    .reshape(shape.to_vec())?
                    .into_any()
                    .unbind())
            }
        })
        .collect::<PyResult<_>>()?;
    PyTuple::new(py, items)
}

/// Normalized parameters of a device (and wall) in physical units, validated.
///
/// Returns ``(delta, d)``, or ``(alpha, beta, delta, d)`` when ``stiffness=`` (N/m) is
/// given (``wall_damping=`` N s/m defaults to 0). All arguments broadcast.
///
/// >>> normalize(mass=1.0, period=0.001, damping=10.0, delay_samples=1)
/// (0.01, 1.0)
/// >>> normalize(mass=1.0, period=0.001, damping=0.0, delay=0.001, stiffness=1e5)
/// (0.1, 0.0, 0.0, 1.0)
#[pyfunction]
#[pyo3(signature = (*, mass, period, damping, delay=None, delay_samples=None, stiffness=None, wall_damping=None))]
#[allow(clippy::too_many_arguments)]
pub fn normalize<'py>(
    py: Python<'py>,
    mass: &Bound<'py, PyAny>,
    period: &Bound<'py, PyAny>,
    damping: &Bound<'py, PyAny>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let device = DeviceArgs {
        mass: Some(mass),
        period: Some(period),
        damping: Some(damping),
        delay,
        delay_samples,
    };
    let zero = 0.0f64.into_pyobject(py)?.into_any();
    let walls = match (stiffness, wall_damping) {
        (None, Some(_)) => {
            return Err(PyValueError::new_err("wall_damping= goes with stiffness="));
        }
        (None, None) => None,
        (Some(k), bw) => Some((k, bw.unwrap_or(&zero))),
    };
    let w = physical_rows(&device, walls)?;
    let col = |k: usize| w.rows.iter().map(|r| r[k]).collect::<Vec<f64>>();
    let keep: &[usize] = if walls.is_some() {
        &[0, 1, 2, 3]
    } else {
        &[2, 3]
    };
    columns(py, &w.shape, keep.iter().map(|&k| col(k)))
}
