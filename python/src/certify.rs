//! Certified verdicts (`certify`): `stabound check --certify` for one wall (normalized, or
//! in physical units with loop elements) or a box of walls of the paper's loop.

use std::path::PathBuf;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use stabound::certificate::{
    BoxClaim, Claim, DelayClaim, SetClaim, WallBox, certify as certify_wall, certify_box,
    certify_delays, certify_set, certify_set_box,
};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Plant, Wall, outward};
use stabound::request::{self, DeviceInputs, Takes};
use stabound::robust::Quantity;
use stabound::stability::DEFAULT_MARGIN;

use crate::args::{self, Spread, number, opt_number, whole};
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
/// A finite set of devices, a loop element's values or the device's given as :class:`OneOf`
/// (``hand_mass=OneOf(0.2, 0.3)``; ``stabound check ... one-of:LIST --certify``), is
/// certified member by member, in physical units: the wall ``stiffness=``,
/// ``wall_damping=`` (or a box of walls, either as :class:`Interval`) for every combination
/// of the lists' values (the device's mass, damping and delay among them: each member
/// stated in the normalization of the smallest mass, one physical wall for all). The result is a :class:`SetCertified`: ``'stable'`` for every member, else the
/// deciding member's verdict and name, the number of members, and the certificate (kind
/// ``set``, the command line's, byte for byte). An interval of a loop element is not
/// certified: give its values as a list.
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
/// >>> c = certify(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=1000.0,
/// ...             wall_damping=5.0, hand_mass=OneOf(0.2, 0.3), hand_damping=2.0,
/// ...             hand_stiffness=300.0)
/// >>> c.verdict, c.members, c.deciding_member, c.set[0]
/// ('stable', 2, None, 'hand mass 0.2 or 0.3 kg')
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
    let (named, mut spreads) = args::elements_and_intervals(elements)?;
    let is_interval = |o: Option<&Bound<'py, PyAny>>| -> PyResult<bool> {
        o.map_or(Ok(false), |o| o.is_instance(&class(py, "Interval")?))
    };
    let is_one_of = |o: Option<&Bound<'py, PyAny>>| -> PyResult<bool> {
        o.map_or(Ok(false), |o| o.is_instance(&class(py, "OneOf")?))
    };
    // a finite set of devices: a loop element's list (or interval, which the library
    // refuses by name), or a list of a device value
    let own = [
        (mass, "mass", Quantity::Mass),
        (damping, "damping", Quantity::Damping),
        (delay, "delay", Quantity::Delay),
        (delay_samples, "delay_samples", Quantity::Delay),
    ];
    let mut listed = !spreads.is_empty();
    for (obj, _, _) in own {
        listed |= is_one_of(obj)?;
    }
    if listed {
        if alpha.is_some() || beta.is_some() || delta.is_some() || d.is_some() {
            return Err(PyValueError::new_err(
                "a set of devices is given in physical units: give mass=, period=, damping=, stiffness=, wall_damping= and delay= or delay_samples=, without alpha=, beta=, delta= and d=",
            ));
        }
        let mut lows: [Option<Bound<'py, PyAny>>; 4] = [None, None, None, None];
        for (k, (obj, name, q)) in own.into_iter().enumerate() {
            let (low, spread) = args::interval(obj, name, || Ok(q))?;
            lows[k] = low;
            spreads.extend(spread);
        }
        let device = [
            lows[0].as_ref().or(mass),
            period,
            lows[1].as_ref().or(damping),
            lows[2].as_ref().or(delay),
            lows[3].as_ref().or(delay_samples),
        ];
        return certify_on_set(
            py,
            device,
            [stiffness, wall_damping],
            &named,
            &spreads,
            (band, max_leaves),
            path,
        );
    }
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
                Ok((verdict_of(cert.claim()), cert.to_json(), None))
            }
        }
    })?
    .map_err(to_py)?;
    write(path, &text)?;
    class(py, "Certified")?.call1((verdict, text, counts))
}

/// Writes the certificate `text` to `path` when given.
pub(crate) fn write(path: Option<PathBuf>, text: &str) -> PyResult<()> {
    if let Some(path) = path {
        std::fs::write(&path, text).map_err(|e| {
            PyOSError::new_err(format!(
                "cannot write the certificate to {}: {e}",
                path.display()
            ))
        })?;
    }
    Ok(())
}

/// A side `(lo, hi)` of a box of walls normalized from physical units, widened outward
/// ([`outward`], as the command line widens it) when it is a range (`lo < hi` in physical
/// units).
fn widened(lo: f64, hi: f64, range: bool) -> (f64, f64) {
    if range { outward(lo, hi) } else { (lo, hi) }
}

/// `certify` on a finite set of devices (`stabound check ... one-of:LIST --certify`): the
/// device in physical units (`[mass, period, damping, delay, delay_samples]`, the low end of
/// each list), the wall `[stiffness, wall_damping]` (each one number or an `Interval`: a box
/// of walls), the loop elements `named` and the sets `spreads`. Every member is proved by
/// the library ([`certify_set`], [`certify_set_box`]), which refuses an interval by name; a
/// set of one member is certified as one loop.
fn certify_on_set<'py>(
    py: Python<'py>,
    device: [Option<&Bound<'py, PyAny>>; 5],
    wall: [Option<&Bound<'py, PyAny>>; 2],
    named: &PhysicalElements,
    spreads: &[Spread],
    (band, max_leaves): (f64, usize),
    path: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let [mass, period, damping, delay, delay_samples] = device;
    let [stiffness, wall_damping] = wall;
    // a missing wall value is refused by the request layer below
    let unset = (f64::NAN, f64::NAN, false);
    let (k0, k1, k_range) = stiffness.map_or(Ok(unset), |o| side(o, "stiffness"))?;
    let (b0, b1, b_range) = wall_damping.map_or(Ok(unset), |o| side(o, "wall_damping"))?;
    // a side is a range when its interval is not one value, as the command line's LO..HI
    let (k_range, b_range) = (k_range && k0 < k1, b_range && b0 < b1);
    // the wall (a box's low corner) as Python numbers, read as one wall's are
    let k = stiffness.map(|_| k0.into_pyobject(py)).transpose()?;
    let b = wall_damping.map(|_| b0.into_pyobject(py)).transpose()?;
    let (k, b) = (k.map(Bound::into_any), b.map(Bound::into_any));
    let physical = [
        mass,
        period,
        damping,
        k.as_ref(),
        b.as_ref(),
        delay,
        delay_samples,
    ];
    let given = inputs([None; 4], physical)?
        .resolve_physical(Takes::Walls)
        .map_err(to_py)?;
    let low = given.normalized().map_err(to_py)?;
    let Some(dev) = given.device().map_err(to_py)? else {
        return Err(PyValueError::new_err(
            "a set of devices is given in physical units: give mass=, period=, damping=, stiffness=, wall_damping= and delay= or delay_samples=",
        ));
    };
    let boxed = k_range || b_range;
    // a check answers for the device as given: the hand is not let go
    let set = request::device_set(&dev, named, spreads, false, false).map_err(to_py)?;
    let Some(set) = set else {
        if boxed {
            return Err(PyValueError::new_err(
                "a box of walls in physical units is certified over a set of devices; for one device give the box in normalized units (alpha= and beta= as Interval, with delta= and d=)",
            ));
        }
        let lp = Loop::physical(&dev, named).map_err(to_py)?;
        let (_, wall) = low.split().map_err(to_py)?;
        let (verdict, text) = interruptible(py, move |_| {
            certify_wall(lp, &wall, band).map(|c| (verdict_of(c.claim()), c.to_json()))
        })?
        .map_err(to_py)?;
        write(path, &text)?;
        return class(py, "Certified")?.call1((verdict, text, None::<(usize, usize, usize)>));
    };
    let walls = if boxed {
        let high = dev.normalize(k1, b1).map_err(to_py)?;
        let (a0, a1) = widened(low.alpha(), high.alpha(), k_range);
        let (c0, c1) = widened(low.beta(), high.beta(), b_range);
        let corners = (Wall::new(a0, c0), Wall::new(a1, c1));
        Some(WallBox::new(corners.0.map_err(to_py)?, corners.1.map_err(to_py)?).map_err(to_py)?)
    } else {
        None
    };
    let wall = set.reference().device().wall(k0, b0).map_err(to_py)?;
    let (cert, set) = interruptible(py, move |_| -> stabound::Result<_> {
        let cert = match &walls {
            Some(w) => certify_set_box(&set, w, max_leaves)?,
            None => certify_set(&set, &wall, band)?,
        };
        Ok((cert, set))
    })?
    .map_err(to_py)?;
    let (verdict, member) = match cert.claim() {
        SetClaim::Stable => ("stable", None),
        SetClaim::Unstable { member } => ("unstable", Some(member)),
        SetClaim::Marginal { member } => ("marginal", Some(member)),
        SetClaim::NotProved { member } => ("not proved", Some(member)),
        _ => ("not proved", None),
    };
    let text = cert.to_json();
    write(path, &text)?;
    let deciding = member.and_then(|m| cert.member(m)).map(str::to_string);
    let described = PyTuple::new(py, set.describe())?;
    class(py, "SetCertified")?.call1((verdict, text, cert.members(), deciding, described))
}

/// The verdict of one wall's claim.
fn verdict_of(claim: Claim) -> &'static str {
    match claim {
        Claim::Stable => "stable",
        Claim::Marginal { .. } => "marginal",
        _ => "unstable",
    }
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
    let given = inputs(normalized, physical)?;
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

/// The inputs of the library's request layer: normalized (`[alpha, beta, delta, d]`) or in
/// physical units (`[mass, period, damping, stiffness, wall_damping, delay,
/// delay_samples]`), each one number.
fn inputs(
    normalized: [Option<&Bound<'_, PyAny>>; 4],
    physical: [Option<&Bound<'_, PyAny>>; 7],
) -> PyResult<DeviceInputs<f64>> {
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
    Ok(DeviceInputs {
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
    })
}
