//! Certified verdicts (`certify`): `stabound check --certify` for one wall or a box of walls
//! of the paper's loop.

use std::path::PathBuf;

use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use stabound::certificate::{BoxClaim, Claim, WallBox, certify as certify_wall, certify_box};
use stabound::params::{Plant, Wall};
use stabound::stability::DEFAULT_MARGIN;

use crate::args::{number, whole};
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
#[pyfunction]
#[pyo3(signature = (alpha, beta, delta, d, *, marginal_band=None, leaves=None, path=None))]
#[allow(clippy::too_many_arguments)]
pub fn certify<'py>(
    py: Python<'py>,
    alpha: &Bound<'py, PyAny>,
    beta: &Bound<'py, PyAny>,
    delta: &Bound<'py, PyAny>,
    d: &Bound<'py, PyAny>,
    marginal_band: Option<&Bound<'py, PyAny>>,
    leaves: Option<&Bound<'py, PyAny>>,
    path: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let (a0, a1, a_box) = side(alpha, "alpha")?;
    let (b0, b1, b_box) = side(beta, "beta")?;
    let plant = Plant::new(number(delta, "delta")?, number(d, "d")?).map_err(to_py)?;
    let band = marginal_band.map_or(Ok(DEFAULT_MARGIN), |b| number(b, "marginal_band"))?;
    let max_leaves = leaves.map_or(Ok(LEAVES), |n| whole(n, "leaves"))?;
    let (low, high) = (
        Wall::new(a0, b0).map_err(to_py)?,
        Wall::new(a1, b1).map_err(to_py)?,
    );
    let boxed = a_box || b_box;
    let (verdict, text, counts) = interruptible(py, move |_| -> stabound::Result<_> {
        if boxed {
            let cert = certify_box(plant, &WallBox::new(low, high)?, max_leaves)?;
            let verdict = match cert.claim() {
                BoxClaim::Stable => "stable",
                BoxClaim::Unstable => "unstable",
                _ => "not proved",
            };
            Ok((verdict, cert.to_json(), Some(cert.counts())))
        } else {
            let cert = certify_wall(plant, &low, band)?;
            let verdict = match cert.claim() {
                Claim::Stable => "stable",
                Claim::Marginal { .. } => "marginal",
                _ => "unstable",
            };
            Ok((verdict, cert.to_json(), None))
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
