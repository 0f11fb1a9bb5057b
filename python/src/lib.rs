//! The compiled core of the `stabound` Python package (`stabound._stabound`).
//!
//! The package's functions are these: each takes the arguments as Python gives them
//! (numbers or numpy arrays, broadcast here), converts them strictly (module `args`), calls
//! the library's validated constructors, and maps the library's typed errors to Python's:
//! bad input (`InvalidParameter`, `InvalidRequest`) is `ValueError` with the library's
//! message, naming the array entry at fault; anything else is `stabound.StaboundError`.
//! Work runs with the interpreter detached, on rayon's pool; long work watches for Ctrl-C
//! (module `work`). Every element is computed on its own and results are collected in input
//! order, so they do not depend on the number of threads; when several elements fail, the
//! error reported is that of the first one in input order. The package (`__init__.py`)
//! defines the result types and documents every function.

use numpy::PyArray1;
use pyo3::create_exception;
use pyo3::exceptions::{PyDeprecationWarning, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;

mod amax;
mod args;
mod buzz;
mod certified;
mod certify;
mod curves;
mod passivity;
mod point;
mod scene;
mod step;
mod work;

create_exception!(
    stabound,
    StaboundError,
    PyRuntimeError,
    "A numerical method failed (no convergence, a result that could not be trusted); bad input raises ValueError instead."
);

/// An input of the library's request layer as its keyword (`wall_damping_min=`).
fn keyword(i: stabound::request::Input) -> String {
    format!("{}=", i.keyword())
}

/// The Python exception for a library error, with the library's message.
pub(crate) fn to_py(e: stabound::Error) -> PyErr {
    match e {
        stabound::Error::Request(r) => PyValueError::new_err(r.message(&keyword)),
        stabound::Error::InvalidParameter { .. } | stabound::Error::InvalidRequest(_) => {
            PyValueError::new_err(e.to_string())
        }
        _ => StaboundError::new_err(e.to_string()),
    }
}

/// [`to_py`] with the place of the fault in front of the message (`damping[3]: ...`).
pub(crate) fn to_py_at(e: stabound::Error, at: &str) -> PyErr {
    match e {
        stabound::Error::Request(r) => {
            PyValueError::new_err(format!("{at}: {}", r.message(&keyword)))
        }
        stabound::Error::InvalidParameter { .. } | stabound::Error::InvalidRequest(_) => {
            PyValueError::new_err(format!("{at}: {e}"))
        }
        _ => StaboundError::new_err(format!("{at}: {e}")),
    }
}

/// A name of the `stabound` package (its result types, defined in Python).
pub(crate) fn class<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    static PACKAGE: PyOnceLock<Py<PyModule>> = PyOnceLock::new();
    PACKAGE
        .get_or_try_init(py, || py.import("stabound").map(Bound::unbind))?
        .bind(py)
        .getattr(name)
}

/// The argument `new`, or its old name `old` (with a DeprecationWarning); not both.
pub(crate) fn renamed<'py>(
    py: Python<'py>,
    value: Option<&Bound<'py, PyAny>>,
    old_value: Option<&Bound<'py, PyAny>>,
    old: &str,
    new: &str,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    match (value, old_value) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(format!(
            "give {new}= only ({old}= is its old name)"
        ))),
        (None, Some(v)) => {
            let msg = std::ffi::CString::new(format!("{old}= is now called {new}="))?;
            PyErr::warn(py, &py.get_type::<PyDeprecationWarning>(), &msg, 1)?;
            Ok(Some(v.clone()))
        }
        (v, None) => Ok(v.cloned()),
    }
}

/// The compiled core of stabound; use the `stabound` package, which documents every function.
#[pymodule]
mod _stabound {
    use super::*;

    #[pymodule_export]
    use super::StaboundError;
    #[pymodule_export]
    use super::amax::{alpha_max, table};
    #[pymodule_export]
    use super::buzz::buzz;
    #[pymodule_export]
    use super::certified::certify_alpha_max;
    #[pymodule_export]
    use super::certify::certify;
    #[pymodule_export]
    use super::curves::boundary_py;
    #[pymodule_export]
    use super::passivity::passivity;
    #[pymodule_export]
    use super::point::{analyze, check, normalize};
    #[pymodule_export]
    use super::scene::{figure, scene, scene_text};
    #[pymodule_export]
    use super::step::step;

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        let py = m.py();
        // numpy's API capsule and the borrow checker's, fetched now: fetched lazily, an
        // interrupt during the first call that makes an array would fail the fetch, and the
        // numpy crate panics there
        py.import("numpy")?; // an ImportError here, not a panic in the numpy crate
        {
            use numpy::PyArrayMethods;
            let probe = PyArray1::<f64>::zeros(py, 1, false);
            drop(probe.readonly());
        }
        let methods: Vec<&str> = point::METHODS_ALL.iter().map(|x| x.name()).collect();
        m.add("METHODS", methods)?;
        m.add("VERDICTS", point::VERDICTS.to_vec())?;
        m.add(
            "PIECES",
            curves::PIECES.iter().map(|p| p.name()).collect::<Vec<_>>(),
        )?;
        m.add(
            "ELEMENT_KEYWORDS",
            stabound::elements::list::PARAMS
                .iter()
                .filter(|p| !p.element.nonlinear())
                .map(|p| p.keyword)
                .collect::<Vec<_>>(),
        )?;
        m.add(
            "NONLINEAR_KEYWORDS",
            stabound::elements::list::PARAMS
                .iter()
                .filter(|p| p.element.nonlinear())
                .map(|p| p.keyword)
                .collect::<Vec<_>>(),
        )?;
        m.add("DEFAULT_MARGIN", stabound::stability::DEFAULT_MARGIN)?;
        m.add("DEFAULT_AMAX_TOL", stabound::amax::DEFAULT_THETA_TOL)?;
        m.add("DEFAULT_BOUNDARY_TOL", stabound::boundary::DEFAULT_TOL)?;
        m.add("DEFAULT_COLUMNS", stabound::passivity::DEFAULT_COLUMNS)?;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        Ok(())
    }
}
