//! Buzz: quantizers and dry friction on one wall (`stabound check` with
//! `--encoder-resolution`, `--force-resolution`, `--coulomb-friction`, `--static-friction`).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use stabound::buzz::{BuzzOptions, buzz as buzz_verdict, describing_function};
use stabound::elements::Loop;
use stabound::export::report::buzz_json;
use stabound::params::Device;

use crate::args::{self, delay_arg, number};
use crate::to_py;

/// The buzz verdict of one wall: the exact simulation of the nonlinear sampled loop with an
/// encoder resolution, a force resolution and dry friction (model document, section 10.3)
/// and the describing function's estimate beside it (section 10.2).
///
/// The device and the wall are in physical units (``mass=`` kg, ``period=`` s,
/// ``damping=`` N s/m, ``delay=`` s or ``delay_samples=``, ``stiffness=`` N/m,
/// ``wall_damping=`` N s/m, default 0), with at least one of ``encoder_resolution=`` (m
/// per count), ``force_resolution=`` (N), ``coulomb_friction=`` (N) and
/// ``static_friction=`` (N), and any loop elements of :func:`check`. Returns the ``buzz``
/// object of ``stabound check --format json``, number for number: ``sustained``,
/// ``diverged``, ``peak_counts``, ``period_samples``, ``runs`` (one per start of the
/// protocol: rest at 1, 3 and 10 counts, an impact at 1 count per sample; 20,000 samples,
/// the last 4,000 judged) and ``describing_function``.
///
/// >>> r = buzz(mass=0.1, period=1e-3, damping=10.0, delay_samples=1, stiffness=17000.0,
/// ...          wall_damping=30.0, encoder_resolution=1e-5)
/// >>> r["sustained"], r["peak_counts"] >= 1, len(r["runs"])
/// (True, True, 4)
/// >>> buzz(mass=0.1, period=1e-3, damping=10.0, delay_samples=1, stiffness=17000.0,
/// ...      wall_damping=30.0, encoder_resolution=1e-5, coulomb_friction=0.05)["sustained"]
/// False
#[pyfunction]
#[pyo3(signature = (*, mass, period, damping, stiffness, wall_damping=None, delay=None, delay_samples=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn buzz<'py>(
    py: Python<'py>,
    mass: &Bound<'py, PyAny>,
    period: &Bound<'py, PyAny>,
    damping: &Bound<'py, PyAny>,
    stiffness: &Bound<'py, PyAny>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let named = args::elements_and_nonlinear(elements)?;
    let (dl, samples) = delay_arg(delay, delay_samples, [mass, period, damping])?;
    let delay = args::delay_of(number(dl, args::delay_name(samples))?, samples);
    let device = Device::new(
        number(mass, "mass")?,
        number(period, "period")?,
        number(damping, "damping")?,
        delay,
    )
    .map_err(to_py)?;
    let k = number(stiffness, "stiffness")?;
    let bw = wall_damping.map_or(Ok(0.0), |b| number(b, "wall_damping"))?;
    let json = py
        .detach(|| {
            let lp = Loop::physical(&device, &named)?;
            let wall = device.wall(k, bw)?;
            let q = stabound::buzz::Nonlinear::from(&named).normalize(&device, k)?;
            let b = buzz_verdict(lp, &wall, &q, &BuzzOptions::default())?;
            let df = describing_function(lp, &wall)?;
            Ok::<_, stabound::Error>(buzz_json(&b, &df).to_string())
        })
        .map_err(to_py)?;
    py.import("json")?.call_method1("loads", (json,))
}
