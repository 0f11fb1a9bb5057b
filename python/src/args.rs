//! Python arguments to the library's numbers: strict conversion (a number is a `float` or an
//! `int`, or an array of them; strings, bools, dates, masked arrays and objects are refused
//! rather than read as numbers), numpy's broadcasting, and errors that name the array entry
//! at fault.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyString};
use stabound::elements::{PhysicalElements, list};
use stabound::request::{DeviceInputs, Given, Takes};
use stabound::robust::{self, Quantity};

use crate::to_py;

/// A numeric argument: its name, its shape (empty for a scalar) and its values in C order.
#[derive(Debug, Clone)]
pub struct Floats {
    pub name: &'static str,
    pub shape: Vec<usize>,
    pub values: Vec<f64>,
}

impl Floats {
    /// One number.
    pub fn scalar(name: &'static str, v: f64) -> Self {
        Self {
            name,
            shape: Vec::new(),
            values: vec![v],
        }
    }

    pub fn is_scalar(&self) -> bool {
        self.shape.is_empty()
    }

    /// The values spread to `shape` (which broadcasting gave), in C order.
    pub fn spread(&self, shape: &[usize]) -> Vec<f64> {
        if self.shape == shape {
            return self.values.clone();
        }
        let n: usize = shape.iter().product();
        (0..n)
            .map(|i| self.values[source(i, shape, &self.shape)])
            .collect()
    }

    /// The values of a 1-D axis (any shape, flattened).
    pub fn axis(&self) -> &[f64] {
        &self.values
    }
}

/// The flat index into an input of `from` shape of output element `i` of `shape` (numpy's
/// broadcasting: trailing axes aligned, axes of length 1 repeated).
fn source(i: usize, shape: &[usize], from: &[usize]) -> usize {
    let coords = unravel(i, shape);
    let skip = shape.len() - from.len();
    from.iter()
        .zip(&coords[skip..])
        .fold(0, |k, (&len, &c)| k * len + if len == 1 { 0 } else { c })
}

/// The multi-index of flat index `i` in `shape` (C order).
fn unravel(mut i: usize, shape: &[usize]) -> Vec<usize> {
    let mut c = vec![0; shape.len()];
    for (k, &len) in shape.iter().enumerate().rev() {
        if len > 0 {
            c[k] = i % len;
            i /= len;
        }
    }
    c
}

/// numpy's lazily imported helpers: `asarray`, `ascontiguousarray`, `float64` and
/// `ma.MaskedArray`.
fn numpy_attr(py: Python<'_>, which: usize) -> PyResult<Bound<'_, PyAny>> {
    static CELLS: [PyOnceLock<Py<PyAny>>; 4] = [
        PyOnceLock::new(),
        PyOnceLock::new(),
        PyOnceLock::new(),
        PyOnceLock::new(),
    ];
    let path = ["asarray", "ascontiguousarray", "float64", "ma.MaskedArray"][which];
    CELLS[which]
        .get_or_try_init(py, || {
            let mut obj: Bound<'_, PyAny> = py.import("numpy")?.into_any();
            for part in path.split('.') {
                obj = obj.getattr(part)?;
            }
            Ok::<_, PyErr>(obj.unbind())
        })
        .map(|o| o.bind(py).clone())
}

/// A refusal of `obj` for `name`, saying what is taken instead.
fn not_a_number(name: &str, obj: &Bound<'_, PyAny>, what: &str) -> PyErr {
    let shown = obj
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into());
    let shown = if shown.chars().count() > 60 {
        format!("{}...", shown.chars().take(60).collect::<String>())
    } else {
        shown
    };
    PyTypeError::new_err(format!(
        "invalid {name} = {shown}: {what}; give a number (float or int) or an array of numbers"
    ))
}

/// `obj` as numbers (module docs).
pub fn floats(obj: &Bound<'_, PyAny>, name: &'static str) -> PyResult<Floats> {
    // the fast path: a Python float (numpy's float64 is one) or int
    if let Ok(f) = obj.cast::<PyFloat>() {
        return Ok(Floats::scalar(name, f.value()));
    }
    if obj.is_instance_of::<PyBool>() {
        return Err(not_a_number(name, obj, "a bool is not a number here"));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(Floats::scalar(name, obj.extract::<f64>()?));
    }
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(not_a_number(name, obj, "a string is not read as a number"));
    }
    let py = obj.py();
    for (set, what) in [("Interval", "an Interval"), ("OneOf", "a OneOf")] {
        if obj.is_instance(&crate::class(py, set)?)? {
            return Err(not_a_number(
                name,
                obj,
                &format!(
                    "{what} (a set of devices) is taken by alpha_max, table, check and boundary for a physical parameter of the device or of a loop element"
                ),
            ));
        }
    }
    if obj.is_instance(&numpy_attr(py, 3)?)? {
        return Err(not_a_number(
            name,
            obj,
            "a masked array is not read (its masked entries would count); pass a.filled(...) or the unmasked entries",
        ));
    }
    let a = numpy_attr(py, 0)?.call1((obj,))?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        let dtype = a.getattr("dtype")?.str()?.to_string();
        return Err(not_a_number(
            name,
            obj,
            &format!("an array of {dtype} is not read as numbers"),
        ));
    }
    let a = numpy_attr(py, 1)?.call1((a, numpy_attr(py, 2)?))?;
    let a = a.cast::<PyArrayDyn<f64>>()?;
    let shape = a.shape().to_vec();
    let values = a.readonly().as_slice()?.to_vec();
    Ok(Floats {
        name,
        shape,
        values,
    })
}

/// `obj` as one number.
pub fn number(obj: &Bound<'_, PyAny>, name: &'static str) -> PyResult<f64> {
    let f = floats(obj, name)?;
    if !f.is_scalar() {
        return Err(PyValueError::new_err(format!("{name}= is one number")));
    }
    Ok(f.values[0])
}

/// One parameter's spread over a set of devices: a quantity and its interval or values.
pub type Spread = (Quantity, robust::Spread);

/// `obj` given as `stabound.Interval(lo, hi)` or `stabound.OneOf(a, b, ...)` (a set of
/// devices): its smallest value as a Python float, which the rest reads as the one number
/// of the set's reference member, and the spread of `q`, checked by the library when the
/// set is built; anything else passes through unchanged.
pub fn interval<'py>(
    obj: Option<&Bound<'py, PyAny>>,
    name: &'static str,
    q: impl FnOnce() -> stabound::Result<Quantity>,
) -> PyResult<(Option<Bound<'py, PyAny>>, Option<Spread>)> {
    let Some(obj) = obj else {
        return Ok((None, None));
    };
    let py = obj.py();
    let spread = if obj.is_instance(&crate::class(py, "Interval")?)? {
        robust::Spread::Interval(
            number(&obj.get_item(0)?, name)?,
            number(&obj.get_item(1)?, name)?,
        )
    } else if obj.is_instance(&crate::class(py, "OneOf")?)? {
        let values = obj
            .try_iter()?
            .map(|v| number(&v?, name))
            .collect::<PyResult<Vec<f64>>>()?;
        robust::Spread::Values(values)
    } else {
        return Ok((None, None));
    };
    // an empty OneOf has no smallest value: the library refuses the empty list by name
    let low = spread.low();
    let low = (if low.is_nan() { 0.0 } else { low })
        .into_pyobject(py)?
        .into_any();
    Ok((Some(low), Some((q().map_err(to_py)?, spread))))
}

/// An optional number.
pub fn opt_number(obj: Option<&Bound<'_, PyAny>>, name: &'static str) -> PyResult<Option<f64>> {
    obj.map(|o| number(o, name)).transpose()
}

/// `obj` as a whole number `>= 0` (an `int`; a float such as 2.5 is refused, not cut).
pub fn whole(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    if obj.is_instance_of::<PyBool>() || obj.is_instance_of::<PyFloat>() {
        return Err(not_whole(name, obj));
    }
    let v: i64 = obj.extract().map_err(|_| not_whole(name, obj))?;
    usize::try_from(v).map_err(|_| {
        PyValueError::new_err(format!(
            "invalid {name} = {v}: give a whole number >= 0 (an int)"
        ))
    })
}

pub fn not_whole(name: &str, obj: &Bound<'_, PyAny>) -> PyErr {
    let shown = obj.repr().map(|r| r.to_string()).unwrap_or_default();
    PyValueError::new_err(format!(
        "invalid {name} = {shown}: give a whole number (an int); it is not rounded"
    ))
}

/// The shape all `inputs` broadcast to, as numpy's rules give it.
pub fn broadcast(inputs: &[&Floats]) -> PyResult<Vec<usize>> {
    let ndim = inputs.iter().map(|f| f.shape.len()).max().unwrap_or(0);
    let mut shape = vec![1usize; ndim];
    for f in inputs {
        let skip = ndim - f.shape.len();
        for (k, &len) in f.shape.iter().enumerate() {
            let s = &mut shape[skip + k];
            if *s == 1 {
                *s = len;
            } else if len != 1 && len != *s {
                let shapes: Vec<String> = inputs
                    .iter()
                    .filter(|g| !g.is_scalar())
                    .map(|g| format!("{} {:?}", g.name, g.shape))
                    .collect();
                return Err(PyValueError::new_err(format!(
                    "shape mismatch: {} cannot be broadcast to one shape",
                    shapes.join(", ")
                )));
            }
        }
    }
    Ok(shape)
}

/// The library's error for output element `i` of `shape`, naming the array entry at fault:
/// `damping[3]: invalid damping = NaN: ...` (the input the library names, at its own index),
/// else the position in the broadcast result. `aliases` maps the library's names to argument
/// names (`delay` is the argument `delay_samples` when the delay is in samples).
pub fn located(
    e: stabound::Error,
    i: usize,
    shape: &[usize],
    inputs: &[&Floats],
    aliases: &[(&str, &str)],
) -> PyErr {
    if shape.is_empty() {
        return to_py(e);
    }
    let named = match &e {
        stabound::Error::InvalidParameter { name, .. } => {
            let arg = aliases
                .iter()
                .find(|(lib, _)| lib == name)
                .map_or(*name, |(_, arg)| *arg);
            inputs.iter().find(|f| f.name == arg)
        }
        _ => None,
    };
    let at = match named {
        Some(f) if f.is_scalar() => return to_py(e),
        Some(f) => format!(
            "{}[{}]",
            f.name,
            join(&unravel(source(i, shape, &f.shape), &f.shape))
        ),
        None => format!("at index [{}]", join(&unravel(i, shape))),
    };
    crate::to_py_at(e, &at)
}

fn join(c: &[usize]) -> String {
    c.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The delay of one device whose `[mass, period, damping]` are given: `delay=` (s) or
/// `delay_samples=`, exactly one of them (the library's request layer resolves it), and
/// whether it is in samples.
pub fn delay_arg<'a, 'py>(
    delay: Option<&'a Bound<'py, PyAny>>,
    delay_samples: Option<&'a Bound<'py, PyAny>>,
    device: [&'a Bound<'py, PyAny>; 3],
) -> PyResult<(&'a Bound<'py, PyAny>, bool)> {
    let given = DeviceInputs {
        mass: Some(device[0]),
        period: Some(device[1]),
        damping: Some(device[2]),
        delay,
        delay_samples,
        ..DeviceInputs::default()
    }
    .resolve_physical(Takes::Plants)
    .map_err(to_py)?;
    match given {
        Given::Physical {
            delay, in_samples, ..
        } => Ok((delay, in_samples)),
        Given::Normalized { .. } => Err(PyValueError::new_err(
            "missing delay= (s) or delay_samples=",
        )),
    }
}

/// The delay as the library takes it.
pub use stabound::request::delay as delay_of;

/// The argument name of the delay.
pub fn delay_name(samples: bool) -> &'static str {
    if samples { "delay_samples" } else { "delay" }
}

/// The loop elements named by keyword, in physical units on one device, each keyword and
/// its kind read from the library's element list (each one number, a whole number for a
/// count, a name for a choice such as `encoder='motor'`); an unknown keyword is a TypeError,
/// as Python's own. The values are checked by the library. The quantizers and friction
/// (nonlinear) are keywords of `buzz` only ([`elements_and_nonlinear`]).
pub fn elements(kw: Option<&Bound<'_, PyDict>>) -> PyResult<PhysicalElements> {
    elements_of(kw, false)
}

/// The loop elements and the quantizers and friction named by keyword, as [`elements`].
pub fn elements_and_nonlinear(kw: Option<&Bound<'_, PyDict>>) -> PyResult<PhysicalElements> {
    elements_of(kw, true)
}

fn elements_of(kw: Option<&Bound<'_, PyDict>>, nonlinear: bool) -> PyResult<PhysicalElements> {
    elements_spread(kw, nonlinear, None)
}

/// The loop elements named by keyword, as [`elements`], and the parameters given as
/// `stabound.Interval(lo, hi)` (the elements then hold `lo`).
pub fn elements_and_intervals(
    kw: Option<&Bound<'_, PyDict>>,
) -> PyResult<(PhysicalElements, Vec<Spread>)> {
    let mut spreads = Vec::new();
    let e = elements_spread(kw, false, Some(&mut spreads))?;
    Ok((e, spreads))
}

fn elements_spread(
    kw: Option<&Bound<'_, PyDict>>,
    nonlinear: bool,
    mut spreads: Option<&mut Vec<Spread>>,
) -> PyResult<PhysicalElements> {
    let mut e = PhysicalElements::default();
    let Some(kw) = kw else { return Ok(e) };
    for (key, value) in kw.iter() {
        let key: String = key.extract()?;
        let Some(p) = list::param(&key) else {
            return Err(PyTypeError::new_err(format!(
                "unexpected keyword argument '{key}'"
            )));
        };
        if p.element.nonlinear() && !nonlinear {
            return Err(PyTypeError::new_err(format!(
                "unexpected keyword argument '{key}' (the quantizers and friction are keywords of buzz())"
            )));
        }
        if value.is_none() {
            continue;
        }
        let v = match p.accepts {
            list::Accepts::Count { .. } => list::Value::Count(whole(&value, p.keyword)?),
            list::Accepts::Choice(_) => {
                let text: String = value.extract().map_err(|_| {
                    PyValueError::new_err(format!(
                        "invalid {} = {}: give {}",
                        p.keyword,
                        value.repr().map_or_else(|_| "?".into(), |r| r.to_string()),
                        p.expects()
                    ))
                })?;
                p.read(&text).map_err(to_py)?
            }
            _ => {
                if let Some(spreads) = spreads.as_deref_mut() {
                    let q = || Quantity::element(p.keyword);
                    if let (Some(low), Some(spread)) = interval(Some(&value), p.keyword, q)? {
                        spreads.push(spread);
                        p.set(&mut e, list::Value::Number(number(&low, p.keyword)?));
                        continue;
                    }
                }
                let f = floats(&value, p.keyword)?;
                if !f.is_scalar() {
                    return Err(PyValueError::new_err(format!(
                        "{}= is one number (loop elements are for one device)",
                        p.keyword
                    )));
                }
                list::Value::Number(f.values[0])
            }
        };
        p.set(&mut e, v);
    }
    e.validate().map_err(to_py)?;
    Ok(e)
}
