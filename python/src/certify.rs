//! Certified verdicts (`certify`): `stabound check --certify` for one wall (normalized, or
//! in physical units with loop elements) or a box of walls of the paper's loop.

use std::path::PathBuf;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use stabound::certificate::{
    BoxClaim, Claim, DelayClaim, WallBox, certify as certify_wall, certify_box, certify_delays,
};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Plant, Wall};
use stabound::request::{DeviceInputs, Takes};
use stabound::stability::DEFAULT_MARGIN;

use crate::args::{self, number, opt_number, whole};
use crate::work::interruptible;
use crate::{class, to_py};

/// The most leaves a box is halved into when `leaves=` is not given (as the command line's
/// `--certify-leaves`).
const LEAVES: usize = 1024;

/// A side of the box of walls: `(lo, hi)` of a `stabound.Interval`, or `(v, v)` of a number,
/// and whether it was an interval.
fn side(obj: &Bound<'_, PyAny>, name: &'static str) -> PyResult<(f64, f64, bool)> {
    if obj.is_instance(&class(obj.py(), "Interval")?)? {
        let lo = number(&obj.get_item(0)?, name)?;
        Ok((lo, number(&obj.get_item(1)?, name)?, true))
    } else {
        let v = number(obj, name)?;
        Ok((v, v, false))
    }
}

/// A verdict proven in interval arithmetic, with its certificate (``stabound check
/// --certify``): for one wall, or with ``alpha`` or ``beta`` given as :class:`Interval`
/// ``(lo, hi)``, for every wall of the box (the box is halved into at most ``leaves``
/// leaves). The certificate is the command line's, byte for byte; the standalone checker
/// (``python -m stabound.verify_certificate FILE``, Python's standard library only) replays
/// it. With ``path=`` it is also written to that file.
///
/// One wall may also be given in physical units, as :func:`check` takes it: ``mass=`` (kg),
/// ``period=`` (s), ``damping=`` (N s/m), ``stiffness=`` (N/m), ``wall_damping=`` (N s/m)
/// and ``delay=`` (s) or ``delay_samples=``, each one number, with loop elements by keyword
/// (``hand_mass=``, ``velocity_filter_cutoff=``, ... as :func:`check`); the certificate then
/// records the loop's normalized elements. A box of walls is given in normalized units.
///
/// A set of devices that differ in their delay, ``delay_samples=Interval(lo, hi)`` (the
/// paper's loop, every other value one number), is certified for the one wall at every
/// delay of the interval (``stabound check --delay-samples LO..HI --certify``; at most
/// ``leaves`` cells of delay): ``'stable'`` or ``'unstable'`` at every delay, or ``'not
/// proved'``, with the counts of stable, unstable and undecided cells in
/// :attr:`Certified.leaves`.
///
/// The verdict of one wall is ``'stable'``, ``'unstable'`` or ``'marginal'`` (the spectral
/// radius within ``marginal_band`` of 1); that of a box is ``'stable'`` or ``'unstable'``
/// for every wall of it, or ``'not proved'``, with the counts of stable, unstable and
/// undecided leaves in :attr:`Certified.leaves`.
///
/// >>> c = certify(Interval(0.1, 0.2), Interval(0.3, 0.4), 0.5, 1.0)
/// >>> c.verdict, c.certificate.startswith('{')
/// ('stable', True)
/// >>> certify(0.1, 0.3, 0.5, 1.0).leaves is None
/// True
/// >>> c = certify(mass=1.0, period=1e-3, damping=0.0, stiffness=1e5, wall_damping=300.0,
/// ...             delay_samples=1, hand_mass=0.2, hand_damping=5.0, hand_stiffness=500.0)
/// >>> c.verdict, '"hand"' in c.certificate
/// ('stable', True)
/// >>> c = certify(mass=1.0, period=1.0, damping=0.5, stiffness=0.1, wall_damping=0.3,
/// ...             delay_samples=Interval(1, 3))
/// >>> c.verdict, c.leaves[1:]
/// ('stable', (0, 0))
#[pyfunction]
#[pyo3(signature = (alpha=None, beta=None, delta=None, d=None, *, marginal_band=None, leaves=None, path=None, mass=None, period=None, damping=None, stiffness=None, wall_damping=None, delay=None, delay_samples=None, **elements))]
#[allow(clippy::too_many_arguments)]
pub fn certify<'py>(
    py: Python<'py>,
    alpha: Option<&Bound<'py, PyAny>>,
    beta: Option<&Bound<'py, PyAny>>,
    delta: Option<&Bound<'py, PyAny>>,
    d: Option<&Bound<'py, PyAny>>,
    marginal_band: Option<&Bound<'py, PyAny>>,
    leaves: Option<&Bound<'py, PyAny>>,
    path: Option<PathBuf>,
    mass: Option<&Bound<'py, PyAny>>,
    period: Option<&Bound<'py, PyAny>>,
    damping: Option<&Bound<'py, PyAny>>,
    stiffness: Option<&Bound<'py, PyAny>>,
    wall_damping: Option<&Bound<'py, PyAny>>,
    delay: Option<&Bound<'py, PyAny>>,
    delay_samples: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let band = marginal_band.map_or(Ok(DEFAULT_MARGIN), |b| number(b, "marginal_band"))?;
    let max_leaves = leaves.map_or(Ok(LEAVES), |n| whole(n, "leaves"))?;
    let named = args::elements(elements)?;
    let is_interval = |o: Option<&Bound<'py, PyAny>>| -> PyResult<bool> {
        o.map_or(Ok(false), |o| o.is_instance(&class(py, "Interval")?))
    };
    let physical = [
        mass,
        period,
        damping,
        stiffness,
        wall_damping,
        delay,
        delay_samples,
    ];
    if is_interval(mass)? || is_interval(period)? || is_interval(damping)? || is_interval(delay)? {
        return Err(PyValueError::new_err(
            "certify over a set of devices proves one wall of the paper's loop at every delay of an interval in samples (delay_samples=Interval(lo, hi)): give mass=, period=, damping= and the wall as one number each",
        ));
    }
    if is_interval(stiffness)? || is_interval(wall_damping)? {
        return Err(PyValueError::new_err(
            "a box of walls is given in normalized units (alpha= and beta= as Interval, with delta= and d=); in physical units certify one wall (one stiffness= and one wall_damping=), or use stabound check --stiffness LO..HI --wall-damping LO..HI --certify FILE",
        ));
    }
    let boxed = is_interval(alpha)? || is_interval(beta)?;
    let job = if boxed {
        if physical.iter().any(Option::is_some) || named.any() {
            return Err(PyValueError::new_err(
                "a box of walls (alpha= or beta= as Interval) is on the paper's loop in normalized units: leave out the device in physical units and the loop elements",
            ));
        }
        let (Some(alpha), Some(beta), Some(delta), Some(d)) = (alpha, beta, delta, d) else {
            return Err(PyValueError::new_err(
                "a box of walls needs alpha=, beta=, delta= and d=",
            ));
        };
        let (a0, a1, _) = side(alpha, "alpha")?;
        let (b0, b1, _) = side(beta, "beta")?;
        let plant = Plant::new(number(delta, "delta")?, number(d, "d")?).map_err(to_py)?;
        let walls = (
            Wall::new(a0, b0).map_err(to_py)?,
            Wall::new(a1, b1).map_err(to_py)?,
        );
        Job::Box(plant, walls)
    } else if is_interval(delay_samples)? {
        let (lo, hi, _) = side(delay_samples.expect("an interval"), "delay_samples")?;
        let low = lo.into_pyobject(py)?.into_any();
        let mut at_low = physical;
        at_low[6] = Some(&low);
        let (lp, wall) = one_wall([alpha, beta, delta, d], at_low, &named)?;
        Job::Delays(lp, wall, (lo, hi))
    } else {
        Job::Wall(one_wall([alpha, beta, delta, d], physical, &named)?)
    };
    let (verdict, text, counts) = interruptible(py, move |_| -> stabound::Result<_> {
        match job {
            Job::Box(plant, (low, high)) => {
                let cert = certify_box(plant, &WallBox::new(low, high)?, max_leaves)?;
                let verdict = match cert.claim() {
                    BoxClaim::Stable => "stable",
                    BoxClaim::Unstable => "unstable",
                    _ => "not proved",
                };
                Ok((verdict, cert.to_json(), Some(cert.counts())))
            }
            Job::Delays(lp, wall, delays) => {
                let cert = certify_delays(lp, &wall, delays, max_leaves)?;
                let verdict = match cert.claim() {
                    DelayClaim::Stable => "stable",
                    DelayClaim::Unstable => "unstable",
                    _ => "not proved",
                };
                Ok((verdict, cert.to_json(), Some(cert.counts())))
            }
            Job::Wall((lp, wall)) => {
                let cert = certify_wall(lp, &wall, band)?;
                let verdict = match cert.claim() {
                    Claim::Stable => "stable",
                    Claim::Marginal { .. } => "marginal",
                    _ => "unstable",
                };
                Ok((verdict, cert.to_json(), None))
            }
        }
    })?
    .map_err(to_py)?;
    if let Some(path) = path {
        std::fs::write(&path, &text).map_err(|e| {
            PyOSError::new_err(format!(
                "cannot write the certificate to {}: {e}",
                path.display()
            ))
        })?;
    }
    class(py, "Certified")?.call1((verdict, text, counts))
}

/// What [`certify`] proves: one wall on a loop, a box of walls of the paper's loop, or one
/// wall of the paper's loop at every delay of an interval (samples).
enum Job {
    Wall((Loop, Wall)),
    Box(Plant, (Wall, Wall)),
    Delays(Loop, Wall, (f64, f64)),
}

/// The loop and the wall of one wall given as `stabound check --certify` takes it:
/// normalized (`[alpha, beta, delta, d]`) or in physical units (`[mass, period, damping,
/// stiffness, wall_damping, delay, delay_samples]`, with the loop elements `named`), each
/// one number, resolved by the library's request layer as the command line resolves its
/// flags (so the certificate is the same, byte for byte).
fn one_wall(
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    physical: [Option<&Bound<'_, PyAny>>; 7],
    named: &PhysicalElements,
) -> PyResult<(Loop, Wall)> {
    let [alpha, beta, delta, d] = normalized;
    let [
        mass,
        period,
        damping,
        stiffness,
        wall_damping,
        delay,
        delay_samples,
    ] = physical;
    let given = DeviceInputs {
        alpha: opt_number(alpha, "alpha")?,
        beta: opt_number(beta, "beta")?,
        delta: opt_number(delta, "delta")?,
        d: opt_number(d, "d")?,
        mass: opt_number(mass, "mass")?,
        period: opt_number(period, "period")?,
        damping: opt_number(damping, "damping")?,
        delay: opt_number(delay, "delay")?,
        delay_samples: opt_number(delay_samples, "delay_samples")?,
        stiffness: opt_number(stiffness, "stiffness")?,
        wall_damping: opt_number(wall_damping, "wall_damping")?,
    };
    let given = if named.any() {
        given.resolve_physical(Takes::Walls)
    } else {
        given.resolve(Takes::Walls)
    }
    .map_err(to_py)?;
    let (plant, wall) = given.normalized().and_then(|n| n.split()).map_err(to_py)?;
    let lp = match given.device().map_err(to_py)? {
        Some(dev) => Loop::physical(&dev, named).map_err(to_py)?,
        None => Loop::new(plant),
    };
    Ok((lp, wall))
}
