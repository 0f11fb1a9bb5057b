//! Scenes (`stabound scene`) and the paper's figures (`stabound figure`).

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyInt, PyString};
use stabound::figures::passivity::{COMPANION_DELAYS, companion, companion_names};
use stabound::scene::{Scene, SceneFormat};
use stabound::stability::Options;

use crate::args::number;
use crate::work::interruptible;
use crate::{StaboundError, renamed, to_py};

/// The report of a scene from a path or a dict: (JSON text, the command line's text).
fn report(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    band: Option<&Bound<'_, PyAny>>,
    old: Option<&Bound<'_, PyAny>>,
) -> PyResult<(String, String)> {
    let margin = match renamed(py, band, old, "margin", "marginal_band")? {
        Some(b) => number(&b, "marginal_band")?,
        None => stabound::stability::DEFAULT_MARGIN,
    };
    let options = Options {
        margin,
        ..Options::default()
    };
    enum Source {
        Path(std::path::PathBuf),
        Text(String),
    }
    let src = if source.is_instance_of::<PyDict>() {
        let kw = PyDict::new(py);
        kw.set_item("allow_nan", false)?;
        let text = py
            .import("json")?
            .call_method("dumps", (source,), Some(&kw))
            .map_err(|e| {
                PyValueError::new_err(format!(
                    "the scene dict cannot be written as JSON: {}",
                    e.value(py)
                ))
            })?;
        Source::Text(text.extract()?)
    } else if source.is_instance_of::<PyString>()
        || source.is_instance_of::<PyBytes>()
        || source.hasattr("__fspath__")?
    {
        let os = py.import("os")?;
        let path = os.call_method1("fsdecode", (os.call_method1("fspath", (source,))?,))?;
        Source::Path(path.extract::<String>()?.into())
    } else {
        return Err(PyTypeError::new_err(
            "scene() takes a path (str or os.PathLike) or a dict",
        ));
    };
    let report = interruptible(py, move |_| {
        let scene = match &src {
            Source::Path(p) => Scene::read(p)?,
            Source::Text(t) => Scene::parse(t, SceneFormat::Json, "<dict>")?,
        };
        scene.check(&options)
    })?
    .map_err(to_py)?;
    let json = serde_json::to_string(&report).map_err(|e| StaboundError::new_err(e.to_string()))?;
    Ok((json, report.to_text()))
}

/// Check every wall of a scene: verdict, margins, stable dampings, suggested damping.
///
/// ``source`` is a scene file (TOML, or JSON for a ``.json`` name) or a dict of the same
/// structure: ``{"device": [{"mass_kg": ..., "period_s": ..., "damping_Ns_per_m": ...,
/// "delay_s" or "delay_samples": ..., "wall": [{"stiffness_N_per_m": ...,
/// "damping_Ns_per_m": ...}]}]}`` (``name`` optional everywhere). Returns the report as
/// ``stabound scene --format json`` writes it, as a dict. ``marginal_band`` is the
/// half-width of the marginal band (``--marginal-band``; ``margin=`` is its old name).
///
/// >>> r = scene({"device": [{"mass_kg": 1.0, "period_s": 0.001, "damping_Ns_per_m": 0.0,
/// ...     "delay_samples": 1, "wall": [{"stiffness_N_per_m": 1e5, "damping_Ns_per_m": 300.0}]}]})
/// >>> r["devices"][0]["walls"][0]["verdict"]
/// 'stable'
#[pyfunction]
#[pyo3(signature = (source, *, marginal_band=None, margin=None))]
pub fn scene<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    marginal_band: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (json, _) = report(py, source, marginal_band, margin)?;
    py.import("json")?.call_method1("loads", (json,))
}

/// The report of :func:`scene` as the text ``stabound scene`` prints.
#[pyfunction]
#[pyo3(signature = (source, *, marginal_band=None, margin=None))]
pub fn scene_text<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    marginal_band: Option<&Bound<'py, PyAny>>,
    margin: Option<&Bound<'py, PyAny>>,
) -> PyResult<String> {
    Ok(report(py, source, marginal_band, margin)?.1)
}

/// The paper's figure ``which`` (5 to 11) as SVG and CSV text, or by name one of the
/// passivity companions of Figs. 8 and 9 for d = 1, 2, 4 (``'fig08-d1'`` ... ``'fig09-d4'``).
///
/// >>> f = figure(10)
/// >>> f.name, f.svg.startswith("<svg"), f.csv.splitlines()[0].startswith("series")
/// ('fig10', True, True)
#[pyfunction]
pub fn figure<'py>(py: Python<'py>, which: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let wrong = || {
        PyValueError::new_err(
            "give a figure number (5 to 11) or a companion's name such as 'fig08-d1'",
        )
    };
    let request = if which.is_instance_of::<PyBool>() {
        return Err(wrong());
    } else if which.is_instance_of::<PyInt>() || which.hasattr("__index__")? {
        let n: i64 = which.extract()?;
        let n = u32::try_from(n).map_err(|_| {
            PyValueError::new_err(format!(
                "the paper has no figure {n} with data; give one of 5, 6, 7, 8, 9, 10, 11"
            ))
        })?;
        Ok(n)
    } else if let Ok(name) = which.extract::<String>() {
        Err(name)
    } else {
        return Err(wrong());
    };
    let data = py
        .detach(|| match &request {
            Ok(n) => stabound::figures::figure(*n),
            Err(nm) => match companion_names().iter().position(|c| c == nm) {
                Some(i) => {
                    let (fig, k) = (if i < 3 { 8 } else { 9 }, i % 3);
                    companion(fig, COMPANION_DELAYS[k])
                }
                None => Err(stabound::Error::InvalidRequest(format!(
                    "no figure named '{nm}'; give a number 5 to 11 or one of {}",
                    companion_names().join(", ")
                ))),
            },
        })
        .map_err(to_py)?;
    let svg = data.to_svg().map_err(to_py)?;
    crate::class(py, "FigureText")?.call1((data.name.clone(), svg, data.to_csv()))
}
