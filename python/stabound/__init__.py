"""Exact stability boundaries for haptic rendering of virtual walls.

A haptic device is a damped mass sampled every ``T`` seconds that touches a virtual
spring-damper wall whose force arrives after a delay. Whether the loop is stable depends on
four normalized numbers (Hulin, Preusche and Hirzinger, IROS 2006):

========  ==========================  =====================
name      meaning                     definition
========  ==========================  =====================
alpha     virtual stiffness           ``K T**2 / m``
beta      virtual damping             ``B T / m``
delta     physical damping            ``b T / m``
d         delay factor                ``delay / T``
========  ==========================  =====================

Every function also takes the device in physical units as keyword arguments (``mass=``
kg, ``period=`` s, ``damping=`` N s/m, ``delay=`` s or ``delay_samples=``, and for walls
``stiffness=`` N/m and ``wall_damping=`` N s/m).

The numerics run in Rust (the ``stabound`` crate) on all cores with the GIL released; the
results do not depend on the number of threads.

>>> import stabound
>>> round(stabound.alpha_max(0.0, 0.0).alpha_max, 12)   # 12 - 8 sqrt 2
0.686291501015
>>> stabound.check(0.1, 0.3, 0.5, 1.0).verdict
'stable'

Bad input raises :class:`ValueError` with the library's message; a numerical failure
raises :class:`StaboundError`.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass
from typing import Any, NamedTuple, Optional, Union

import numpy as np

from . import _stabound
from ._stabound import StaboundError

__version__: str = _stabound.__version__

#: Stability methods accepted by ``method=`` of :func:`check` and :func:`analyze`, in the
#: order of :attr:`CheckResult.method_code`.
METHODS: tuple = tuple(_stabound.METHODS)
#: Verdict names, in the order of :attr:`CheckResult.code` (0 stable, 1 marginal, 2 unstable).
VERDICTS: tuple = tuple(_stabound.VERDICTS)
#: Boundary piece names, in the order of the codes in :attr:`Boundary.piece_code`.
PIECES: tuple = tuple(_stabound.PIECES)
#: Default half-width of the marginal band around the unit circle (``marginal_band=``).
DEFAULT_MARGINAL_BAND: float = _stabound.DEFAULT_MARGIN
#: Default refinement tolerance (in theta, rad) of :func:`alpha_max` and :func:`table`
#: (``theta_tol=``).
DEFAULT_THETA_TOL: float = _stabound.DEFAULT_AMAX_TOL
#: Old names of the two defaults above, kept working.
DEFAULT_MARGIN: float = DEFAULT_MARGINAL_BAND
DEFAULT_AMAX_TOL: float = DEFAULT_THETA_TOL
#: Default accuracy of :func:`boundary` points, in normalized units.
DEFAULT_BOUNDARY_TOL: float = _stabound.DEFAULT_BOUNDARY_TOL

__all__ = [
    "Amax",
    "AmaxMargin",
    "AmaxPhysical",
    "AmaxPhysicalMargin",
    "Boundary",
    "CheckResult",
    "DeltaBetaBoundary",
    "FigureText",
    "DEFAULT_AMAX_TOL",
    "DEFAULT_BOUNDARY_TOL",
    "DEFAULT_MARGIN",
    "DEFAULT_COLUMNS",
    "DEFAULT_MARGINAL_BAND",
    "DEFAULT_THETA_TOL",
    "LookupTable",
    "METHODS",
    "Passivity",
    "PIECES",
    "StaboundError",
    "StepResponse",
    "VERDICTS",
    "Witness",
    "alpha_max",
    "analyze",
    "boundary",
    "check",
    "figure",
    "normalize",
    "passivity",
    "scene",
    "scene_text",
    "step",
    "table",
]

_VERDICT_NAMES = np.array(VERDICTS)
_METHOD_NAMES = np.array(METHODS)
_PIECE_NAMES = np.array(PIECES)


# ---------------------------------------------------------------------------------------
# internal functions


def _f64(x: Any) -> np.ndarray:
    return np.asarray(x, dtype=np.float64)


def _flat(*arrays: Any) -> tuple:
    """Broadcast to one shape; return the shape and flat contiguous float64 copies."""
    bs = np.broadcast_arrays(*[_f64(a) for a in arrays])
    shape = bs[0].shape
    return shape, [np.ascontiguousarray(b, dtype=np.float64).reshape(-1) for b in bs]


def _out(shape: tuple, a: np.ndarray) -> Any:
    """``a`` in ``shape``; a Python scalar for a 0-d shape."""
    r = a.reshape(shape)
    return r.item() if r.ndim == 0 else r


def _delay(delay: Any, delay_samples: Any) -> tuple:
    if delay is not None and delay_samples is not None:
        raise ValueError("give delay= (s) or delay_samples=, not both")
    if delay is None and delay_samples is None:
        raise ValueError("missing delay= (s) or delay_samples=")
    return (delay_samples, True) if delay is None else (delay, False)


def _device(mass: Any, period: Any, damping: Any) -> None:
    missing = [n for n, v in (("mass", mass), ("period", period), ("damping", damping)) if v is None]
    if missing:
        raise ValueError("physical units need mass=, period= and damping=; missing " + ", ".join(f"{m}=" for m in missing))


def _physical(**kw: Any) -> bool:
    return any(v is not None for v in kw.values())


def _normalized_plants(delta, d, mass, period, damping, delay, delay_samples):
    """``(delta, d, physical)``: the plants given either way, physical ones normalized."""
    if _physical(mass=mass, period=period, damping=damping, delay=delay, delay_samples=delay_samples):
        if delta is not None or d is not None:
            raise ValueError(
                "give either delta and d, or mass=, period=, damping= and delay=|delay_samples=, not both"
            )
        _device(mass, period, damping)
        value, samples = _delay(delay, delay_samples)
        shape, (m, t, b, dl) = _flat(mass, period, damping, value)
        x, dd = _stabound.normalize_plants(m, t, b, dl, samples)
        return x.reshape(shape), dd.reshape(shape), True
    if delta is None or d is None:
        raise ValueError(
            "missing delta and d (or physical mass=, period=, damping= and delay=|delay_samples=)"
        )
    return delta, d, False


def _renamed(value: Any, old_value: Any, old: str, new: str, default: Any) -> Any:
    """``value`` of the argument ``new``, or that of its old name ``old`` (with a warning)."""
    if old_value is not None:
        if value is not None:
            raise ValueError(f"give {new}= only ({old}= is its old name)")
        warnings.warn(f"{old}= is now called {new}=", DeprecationWarning, stacklevel=3)
        return old_value
    return default if value is None else value


def _is_scalar(*xs: Any) -> bool:
    return all(np.ndim(x) == 0 for x in xs)


# ---------------------------------------------------------------------------------------
# point tests


class CheckResult(NamedTuple):
    """Point tests of :func:`check`: arrays of the broadcast shape (scalars for scalar input)."""

    #: Largest root modulus (NaN where ``radius=False``).
    spectral_radius: Any
    #: ``'stable'``, ``'marginal'`` or ``'unstable'``.
    verdict: Any
    #: Verdict codes: 0 stable, 1 marginal, 2 unstable (indices into :data:`VERDICTS`).
    code: Any
    #: ``code == 0``.
    stable: Any
    #: The method that decided (for ``'auto'``: ``'schur-cohn'``, ``'argument-principle'``
    #: or ``'certified'``).
    method: Any


def normalize(
    *,
    mass: Any,
    period: Any,
    damping: Any,
    delay: Any = None,
    delay_samples: Any = None,
    stiffness: Any = None,
    wall_damping: Any = None,
) -> tuple:
    """Normalized parameters of a device (and wall) in physical units, validated.

    Returns ``(delta, d)``, or ``(alpha, beta, delta, d)`` when ``stiffness=`` (N/m) is
    given (``wall_damping=`` N s/m defaults to 0). All arguments broadcast.

    >>> normalize(mass=1.0, period=0.001, damping=10.0, delay_samples=1)
    (0.01, 1.0)
    >>> normalize(mass=1.0, period=0.001, damping=0.0, delay=0.001, stiffness=1e5)
    (0.1, 0.0, 0.0, 1.0)
    """
    _device(mass, period, damping)
    value, samples = _delay(delay, delay_samples)
    if stiffness is None:
        if wall_damping is not None:
            raise ValueError("wall_damping= goes with stiffness=")
        shape, (m, t, b, dl) = _flat(mass, period, damping, value)
        return tuple(_out(shape, a) for a in _stabound.normalize_plants(m, t, b, dl, samples))
    wd = 0.0 if wall_damping is None else wall_damping
    shape, (m, t, b, dl, k, bw) = _flat(mass, period, damping, value, stiffness, wd)
    return tuple(_out(shape, a) for a in _stabound.normalize_walls(m, t, b, dl, samples, k, bw))


def _walls(alpha, beta, delta, d, mass, period, damping, delay, delay_samples, stiffness, wall_damping):
    """``(alpha, beta, delta, d, device)`` from either form of a wall."""
    physical = _physical(
        mass=mass, period=period, damping=damping, delay=delay, delay_samples=delay_samples,
        stiffness=stiffness, wall_damping=wall_damping,
    )
    if physical:
        if any(v is not None for v in (alpha, beta, delta, d)):
            raise ValueError(
                "give either normalized parameters (alpha, beta, delta, d) or physical ones "
                "(mass=, period=, damping=, stiffness=, wall_damping=, delay=|delay_samples=), not both"
            )
        for name, v in (("stiffness", stiffness), ("wall_damping", wall_damping)):
            if v is None:
                raise ValueError(f"missing {name}=")
        a, b, x, dd = normalize(
            mass=mass, period=period, damping=damping, delay=delay,
            delay_samples=delay_samples, stiffness=stiffness, wall_damping=wall_damping,
        )
        return a, b, x, dd, True
    for name, v in (("alpha", alpha), ("beta", beta), ("delta", delta), ("d", d)):
        if v is None:
            raise ValueError(f"missing {name}")
    return alpha, beta, delta, d, False


#: The loop elements' keywords, from the library's element list.
_ELEMENT_KEYS = tuple(_stabound.ELEMENT_KEYWORDS)


def _elements_tuple(named: tuple) -> dict:
    """The loop elements named, by keyword, as the compiled core takes them."""
    return {k: v for k, v in zip(_ELEMENT_KEYS, named) if v is not None}


def _one_device(mass, period, damping, delay, delay_samples) -> tuple:
    """One device in physical units for a loop with elements: ``(m, T, b, delay, samples)``."""
    for name, v in (("mass", mass), ("period", period), ("damping", damping)):
        if v is None:
            raise ValueError(
                f"missing {name}=: loop elements are given in physical units on one device "
                "(mass=, period=, damping=, delay=|delay_samples=)"
            )
    if (delay is None) == (delay_samples is None):
        raise ValueError("give the delay as delay= (s) or delay_samples=, one of them")
    samples = delay is None
    dl = delay_samples if samples else delay
    for name, v in (("mass", mass), ("period", period), ("damping", damping), ("delay", dl)):
        if np.ndim(v) != 0:
            raise ValueError(f"with loop elements {name}= is one number (one device)")
    return float(mass), float(period), float(damping), float(dl), samples


def check(
    alpha: Any = None,
    beta: Any = None,
    delta: Any = None,
    d: Any = None,
    *,
    method: str = "auto",
    marginal_band: Optional[float] = None,
    radius: bool = True,
    mass: Any = None,
    period: Any = None,
    damping: Any = None,
    stiffness: Any = None,
    wall_damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
    margin: Optional[float] = None,
    **elements: Any,
) -> CheckResult:
    """Test walls for stability: verdict and spectral radius of each point.

    ``alpha``, ``beta``, ``delta`` and ``d`` broadcast against each other (numpy rules);
    the result has their broadcast shape, or is scalar when all four are scalars. Or give
    the walls in physical units: ``mass=`` (kg), ``period=`` (s), ``damping=`` (N s/m),
    ``stiffness=`` (N/m), ``wall_damping=`` (N s/m) and ``delay=`` (s) or
    ``delay_samples=``, all broadcasting.

    ``method`` is one of :data:`METHODS` (``'auto'``: Schur-Cohn with a rounding-error
    guard, then a proven argument-principle count, then the certified stage (coefficient
    bounds and inclusion discs) where it cannot vouch; ``'marginal'`` where none can). A spectral radius within ``marginal_band`` (default
    :data:`DEFAULT_MARGINAL_BAND`; ``margin=`` is its old name) of 1 is ``'marginal'``. With
    ``radius=False`` only the verdicts are computed (faster: no roots) and the spectral
    radius is NaN.

    The points are tested in parallel with the GIL released; the results are the same for
    any number of threads and the same, bit for bit, as ``stabound check`` prints.

    >>> r = check([0.1, 5.0], 0.3, 0.5, 1.0)
    >>> r.verdict.tolist(), r.code.tolist()
    (['stable', 'unstable'], [0, 2])
    >>> check(alpha=0.1, beta=0.3, delta=0.5, d=1.0, method="schur-cohn").stable
    True
    >>> check(mass=1.0, period=1e-3, damping=0.0, stiffness=1e5, wall_damping=300.0, delay_samples=1).verdict
    'stable'

    Loop elements, in physical units on one device (scalar ``mass``, ``period``,
    ``damping`` and delay; the walls may be arrays), as ``stabound check`` takes them: an
    operator hand (``hand_mass=`` kg, ``hand_damping=`` N s/m, ``hand_stiffness=`` N/m), a
    compliant transmission (``handle_mass=``, ``transmission_stiffness=``,
    ``transmission_damping=``, ``encoder='motor'|'handle'``), an actuator lag
    (``actuator_time_constant=`` s) and a velocity filter (``velocity_filter_cutoff=`` Hz or
    ``velocity_filter_samples=``):

    >>> check(mass=0.1, period=1e-3, damping=0.0, delay_samples=1, stiffness=10800.0,
    ...       wall_damping=42.5, velocity_filter_cutoff=3.18).verdict
    'unstable'
    """
    band = _renamed(marginal_band, margin, "margin", "marginal_band", DEFAULT_MARGINAL_BAND)
    named = _named(elements)
    if any(v is not None for v in named):
        return _check_loop(
            alpha, beta, delta, d, method, band, radius, mass, period, damping, stiffness,
            wall_damping, delay, delay_samples, named,
        )
    alpha, beta, delta, d, _ = _walls(
        alpha, beta, delta, d, mass, period, damping, delay, delay_samples, stiffness, wall_damping
    )
    shape, (a, b, x, dd) = _flat(alpha, beta, delta, d)
    rho, code, mcode = _stabound.check(a, b, x, dd, str(method), float(band), bool(radius))
    return _check_result(shape, rho, code, mcode)


def _check_result(shape: tuple, rho: Any, code: Any, mcode: Any) -> CheckResult:
    """The compiled core's point-test columns as a :class:`CheckResult` of ``shape``."""
    return CheckResult(
        spectral_radius=_out(shape, rho),
        verdict=_out(shape, _VERDICT_NAMES[code]),
        code=_out(shape, code),
        stable=_out(shape, code == 0),
        method=_out(shape, _METHOD_NAMES[mcode]),
    )


def _check_loop(alpha, beta, delta, d, method, band, radius, mass, period, damping, stiffness,
                wall_damping, delay, delay_samples, named) -> CheckResult:
    """:func:`check` with loop elements: one device, walls broadcast."""
    if any(v is not None for v in (alpha, beta, delta, d)):
        raise ValueError(
            "loop elements are given in physical units: give the device (mass=, period=, "
            "damping=, delay=|delay_samples=) and the walls (stiffness=, wall_damping=)"
        )
    for name, v in (("mass", mass), ("period", period), ("damping", damping),
                    ("stiffness", stiffness), ("wall_damping", wall_damping)):
        if v is None:
            raise ValueError(f"missing {name}=")
    if (delay is None) == (delay_samples is None):
        raise ValueError("give the delay as delay= (s) or delay_samples=, one of them")
    for name, v in (("mass", mass), ("period", period), ("damping", damping),
                    ("delay", delay if delay is not None else delay_samples)):
        if np.ndim(v) != 0:
            raise ValueError(f"with loop elements {name}= is one number (one device)")
    a, b, _, _ = normalize(
        mass=mass, period=period, damping=damping, delay=delay,
        delay_samples=delay_samples, stiffness=stiffness, wall_damping=wall_damping,
    )
    shape, (fa, fb) = _flat(a, b)
    samples = delay is None
    dl = float(delay_samples if samples else delay)
    elements = _elements_tuple(named)
    rho, code, mcode = _stabound.check_loop(
        fa, fb, float(mass), float(period), float(damping), dl, samples, elements,
        str(method), float(band), bool(radius),
    )
    return _check_result(shape, rho, code, mcode)


def analyze(
    alpha: Optional[float] = None,
    beta: Optional[float] = None,
    delta: Optional[float] = None,
    d: Optional[float] = None,
    *,
    method: str = "auto",
    marginal_band: Optional[float] = None,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Optional[float] = None,
    stiffness: Optional[float] = None,
    wall_damping: Optional[float] = None,
    delay: Optional[float] = None,
    delay_samples: Optional[float] = None,
    margin: Optional[float] = None,
) -> dict:
    """Everything ``stabound check --format json`` reports for one wall, with the roots.

    Keys: ``stable``, ``verdict``, ``spectral_radius``, ``roots`` (complex array),
    ``degree``, ``method``, ``margin`` (the marginal band, under the key the command line's
    JSON uses), ``alpha``, ``beta``, ``delta``, ``d``, and for a
    wall in physical units ``physical`` (mass, period, damping, stiffness, wall_damping,
    delay_samples).

    >>> r = analyze(0.1, 0.3, 0.5, 1.0)
    >>> r["verdict"], r["degree"], len(r["roots"])
    ('stable', 4, 4)
    """
    band = _renamed(marginal_band, margin, "margin", "marginal_band", DEFAULT_MARGINAL_BAND)
    alpha, beta, delta, d, physical = _walls(
        alpha, beta, delta, d, mass, period, damping, delay, delay_samples, stiffness, wall_damping
    )
    if not _is_scalar(alpha, beta, delta, d):
        raise ValueError("analyze takes one wall (scalars); use check() for arrays")
    device = (float(mass), float(period), float(damping)) if physical else None
    return _stabound.analyze(
        float(alpha), float(beta), float(delta), float(d), str(method), float(band), device
    )


# ---------------------------------------------------------------------------------------
# alpha_max


class Amax(NamedTuple):
    """:func:`alpha_max` of normalized plants."""

    #: Maximum stable stiffness over all (admissible) beta.
    alpha_max: Any
    #: The beta at which it is reached.
    beta_at_max: Any

    def __str__(self) -> str:
        # print() shows the headline number; repr() keeps both fields
        return str(self.alpha_max)


class AmaxPhysical(NamedTuple):
    """:func:`alpha_max` of devices in physical units."""

    #: Maximum stable normalized stiffness.
    alpha_max: Any
    #: The normalized damping at which it is reached.
    beta_at_max: Any
    #: ``K_max`` in N/m.
    stiffness: Any
    #: The wall damping ``B`` in N s/m at ``K_max``.
    wall_damping: Any


def alpha_max(
    delta: Any = None,
    d: Any = None,
    *,
    beta_min: Optional[float] = None,
    beta_max: Optional[float] = None,
    theta_tol: Optional[float] = None,
    margin: Optional[float] = None,
    mass: Any = None,
    period: Any = None,
    damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
    tol: Optional[float] = None,
    wall_damping_min: Optional[float] = None,
    wall_damping_max: Optional[float] = None,
    **elements: Any,
) -> Union[Amax, AmaxPhysical, "AmaxMargin", "AmaxPhysicalMargin"]:
    """Maximum stable stiffness ``alpha_max`` and the ``beta`` where it is reached.

    ``delta`` and ``d`` broadcast; scalar in, scalar out. ``beta_min`` / ``beta_max``
    restrict the admissible virtual damping (e.g. ``beta_min=0`` when negative damping
    cannot be rendered); ``theta_tol`` is the refinement tolerance in theta (rad), in
    ``[1e-15, 1e-2]`` (``tol=`` is its old name). ``margin=F`` (a fraction in ``(0, 1]``, as
    ``stabound amax --margin``) adds ``alpha_margin = F * alpha_max`` and ``beta_margin``
    (and, in physical units, ``stiffness_margin`` in N/m): :class:`AmaxMargin` /
    :class:`AmaxPhysicalMargin`. Or give devices as ``mass=``, ``period=``, ``damping=`` and
    ``delay=`` / ``delay_samples=`` (broadcasting): the result then also has ``stiffness``
    (``K_max``, N/m) and ``wall_damping`` (N s/m), and the damping limits may be given
    as wall dampings in N s/m, ``wall_damping_min=`` / ``wall_damping_max=`` (the physical
    ``beta_min`` / ``beta_max``, ``beta = B T / m``; they need one device mass and period,
    as ``stabound amax --wall-damping-min``).

    Computed in parallel with the GIL released; the same numbers, bit for bit, as
    ``stabound amax``.

    >>> round(alpha_max(0.0, 0.0).alpha_max, 12)     # 12 - 8 sqrt 2 (paper, Remark 4)
    0.686291501015
    >>> a, b = alpha_max([0.0, 0.1, 1.0], 1.0)
    >>> (0.75 * a).round(3).tolist()                  # paper Section VIII
    [0.108, 0.149, 0.656]
    >>> round(alpha_max(mass=1.0, period=1e-3, damping=0.0, delay_samples=1).stiffness)
    144469
    >>> round(alpha_max(0.0, 1.0, margin=0.75).alpha_margin, 6)    # paper Section VIII
    0.108352

    Without negative wall damping (``B >= 0``) a device keeps its ``alpha_max`` (its
    optimal ``beta`` is positive), and with ``B <= 0`` the optimum is at ``B = 0``:

    >>> dev = dict(mass=1.0, period=1e-3, damping=100.0, delay_samples=1)
    >>> bool(alpha_max(**dev, wall_damping_min=0.0) == alpha_max(**dev))
    True
    >>> alpha_max(**dev, wall_damping_max=0.0).wall_damping
    0.0

    Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
    ``velocity_filter_cutoff=``) on one device in physical units give ``alpha_max`` of that
    loop, read from its exact boundary (to 1e-9):

    >>> bare = alpha_max(mass=0.1, period=1e-3, damping=0.0, delay_samples=1).stiffness
    >>> lp = alpha_max(mass=0.1, period=1e-3, damping=0.0, delay_samples=1,
    ...                velocity_filter_cutoff=30.0).stiffness
    >>> bool(lp < bare)
    True
    """
    theta_tol = _renamed(theta_tol, tol, "tol", "theta_tol", DEFAULT_THETA_TOL)
    beta_min = _beta_limit("min", beta_min, wall_damping_min, mass, period)
    beta_max = _beta_limit("max", beta_max, wall_damping_max, mass, period)
    if elements:
        return _alpha_max_loop(delta, d, beta_min, beta_max, margin, mass, period, damping,
                               delay, delay_samples, elements)
    if margin is not None and not (np.ndim(margin) == 0 and 0.0 < float(margin) <= 1.0):
        raise ValueError(f"margin = {margin} must be a fraction in (0, 1], e.g. 0.75")
    delta, d, physical = _normalized_plants(delta, d, mass, period, damping, delay, delay_samples)
    shape, (x, dd) = _flat(delta, d)
    a, b = _stabound.alpha_max(x, dd, float(theta_tol), beta_min, beta_max)
    # as the command line: F * alpha_max, one IEEE product
    am = None if margin is None else float(margin) * a
    if not physical:
        if am is None:
            return Amax(_out(shape, a), _out(shape, b))
        return AmaxMargin(_out(shape, a), _out(shape, b), _out(shape, am), _out(shape, b))
    shape2, (m, t, a2, b2) = _flat(mass, period, a.reshape(shape), b.reshape(shape))
    k, bw = _stabound.device_scale(m, t, a2, b2)
    if am is None:
        return AmaxPhysical(_out(shape, a), _out(shape, b), _out(shape2, k), _out(shape2, bw))
    _, (_, _, am2) = _flat(mass, period, am.reshape(shape))
    km, _ = _stabound.device_scale(m, t, am2, b2)
    return AmaxPhysicalMargin(
        _out(shape, a), _out(shape, b), _out(shape2, k), _out(shape2, bw),
        _out(shape, am), _out(shape, b), _out(shape2, km),
    )


def _beta_limit(end: str, beta: Optional[float], wall_damping: Optional[float],
                mass: Any, period: Any) -> Optional[float]:
    """The normalized ``beta_<end>`` of :func:`alpha_max`, from ``wall_damping_<end>=`` (N s/m)
    as ``stabound amax`` converts ``--wall-damping-<end>``: ``B * T / m``."""
    if wall_damping is None:
        return beta
    name = f"wall_damping_{end}"
    if beta is not None:
        raise ValueError(f"give beta_{end}= or {name}=, not both (they are the same limit)")
    if mass is None or period is None:
        raise ValueError(
            f"{name}= is a wall damping in N s/m and needs the device in physical units: give "
            f"mass=, period=, damping= and delay=|delay_samples=, or the normalized beta_{end}="
        )
    if np.ndim(mass) != 0 or np.ndim(period) != 0:
        raise ValueError(f"with {name}= mass= and period= are one number each (one device)")
    if np.ndim(wall_damping) != 0:
        raise ValueError(f"{name}= is one number")
    # the same IEEE operations, in the same order, as the command line
    return float(wall_damping) * float(period) / float(mass)


def _named(elements: dict) -> tuple:
    """The element keywords in core order; an unknown keyword is a TypeError, as Python's."""
    unknown = sorted(set(elements) - set(_ELEMENT_KEYS))
    if unknown:
        raise TypeError(f"unexpected keyword argument(s): {', '.join(unknown)}")
    return tuple(elements.get(k) for k in _ELEMENT_KEYS)


def _alpha_max_loop(delta, d, beta_min, beta_max, margin, mass, period, damping, delay,
                    delay_samples, elements) -> Any:
    """:func:`alpha_max` of one device with loop elements."""
    named = _named(elements)
    if delta is not None or d is not None:
        raise ValueError("loop elements are given in physical units: give the device "
                         "(mass=, period=, damping=, delay=|delay_samples=), not delta and d")
    m, t, b, dl, samples = _one_device(mass, period, damping, delay, delay_samples)
    a, beta = _stabound.alpha_max_loop(m, t, b, dl, samples, _elements_tuple(named),
                                       beta_min, beta_max)
    k, bw = _stabound.device_scale(_f64([m]), _f64([t]), _f64([a]), _f64([beta]))
    if margin is None:
        return AmaxPhysical(a, beta, float(k[0]), float(bw[0]))
    am = float(margin) * a
    km, _ = _stabound.device_scale(_f64([m]), _f64([t]), _f64([am]), _f64([beta]))
    return AmaxPhysicalMargin(a, beta, float(k[0]), float(bw[0]), am, beta, float(km[0]))


class AmaxMargin(NamedTuple):
    """:func:`alpha_max` of normalized plants with ``margin=F`` (``stabound amax --margin``)."""

    alpha_max: Any
    beta_at_max: Any
    #: ``F * alpha_max``.
    alpha_margin: Any
    #: The damping to render with it (the one at ``alpha_max``).
    beta_margin: Any


class AmaxPhysicalMargin(NamedTuple):
    """:func:`alpha_max` of devices in physical units with ``margin=F``."""

    alpha_max: Any
    beta_at_max: Any
    stiffness: Any
    wall_damping: Any
    alpha_margin: Any
    beta_margin: Any
    #: ``F * K_max`` in N/m (the command line's ``K_margin``).
    stiffness_margin: Any


# ---------------------------------------------------------------------------------------
# boundaries


class Boundary(NamedTuple):
    """One stability boundary in the (alpha, beta) plane: a closed polyline.

    It runs counterclockwise (the stable region on the left), starts at ``(0, -delta)`` and
    its last point repeats the first. ``piece[i]`` names what the segment from point ``i``
    to the next lies on: ``'curve'`` (complex roots on the unit circle), ``'alpha-zero'``
    (the root ``z = 1``), ``'minus-one'`` (the root ``z = -1``), ``'bisection'`` (found by
    the bisection engine).
    """

    delta: float
    d: float
    alpha: np.ndarray
    beta: np.ndarray
    #: Piece names (strings).
    piece: np.ndarray
    #: Piece codes, indices into :data:`PIECES`.
    piece_code: np.ndarray


class DeltaBetaBoundary(NamedTuple):
    """Stability boundary in the (delta, beta) plane at one ``(alpha, d)``, by bisection.

    The vertices of one or more closed loops, in order; ``loop[i]`` numbers the loop of
    vertex ``i``. ``piece[i]`` is ``'bisection'`` for a point on the stability boundary and
    ``'clipped'`` where the loop follows the edge of the requested delta range instead.
    """

    alpha: float
    d: float
    delta: np.ndarray
    beta: np.ndarray
    loop: np.ndarray
    piece: np.ndarray


def _delta_beta_loop(named: tuple, mass, period, damping, delay, delay_samples) -> tuple:
    """``(device, elements)`` of loop elements in the delta-beta plane: the device is only
    ``(mass, period)`` (the axes, delta and d, stay normalized), as ``stabound boundary
    --plane delta-beta`` with element flags."""
    for name, v in (("damping", damping), ("delay", delay), ("delay_samples", delay_samples)):
        if v is not None:
            raise ValueError(
                f"{name}= is not taken in the delta-beta plane: its axes stay normalized (give "
                "delta and d); the loop elements need only mass= and period="
            )
    for name, v in (("mass", mass), ("period", period)):
        if v is None:
            raise ValueError(
                f"missing {name}=: loop elements are given in physical units; give the device's "
                "mass= and period= (the delta-beta plane's axes stay normalized)"
            )
        if np.ndim(v) != 0:
            raise ValueError(f"with loop elements {name}= is one number (one device)")
    return (float(mass), float(period)), _elements_tuple(named)


def boundary(
    delta: Any = None,
    d: Any = None,
    *,
    tol: float = DEFAULT_BOUNDARY_TOL,
    method: Optional[str] = None,
    plane: str = "alpha-beta",
    alpha: Any = None,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Optional[float] = None,
    delay: Optional[float] = None,
    delay_samples: Optional[float] = None,
    **elements: Any,
) -> Any:
    """Stability boundaries in the (alpha, beta) plane, or in the (delta, beta) plane.

    ``plane='alpha-beta'`` (paper Figs. 5, 7, 8): one :class:`Boundary` for scalar ``delta``
    and ``d``; otherwise a list with one per ``(delta, d)``, ``delta`` outer and ``d`` inner
    (the order of ``stabound boundary``), at most 1000 curves. ``method`` is ``'exact'``
    (the default: D-decomposition, exact curve pieces) or ``'bisect'`` (grid of point tests
    and bisection).

    ``plane='delta-beta'`` (paper Figs. 6, 9): one :class:`DeltaBetaBoundary` per
    ``(alpha, d)`` (``alpha`` outer), by bisection, over delta from ``min(delta)`` to
    ``max(delta)`` (default 0 to 1); a single one for scalar ``alpha`` and ``d``.

    ``tol`` is the accuracy of every point and the largest deviation of the polyline from
    the true curve, in ``[1e-12, 1e-2]``. Computed in parallel with the GIL released.

    >>> b = boundary(0.0, 0.0, tol=1e-6)
    >>> float(b.alpha[0]), float(b.beta[0]), round(float(b.alpha.max()), 4)
    (0.0, -0.0, 0.6863)
    >>> [(c.delta, c.d) for c in boundary([0.0, 1.0], [0.0, 1.0], tol=1e-4)]
    [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]
    >>> c = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4)
    >>> float(c.delta.min()) >= 0.0, set(c.piece.tolist()) <= {"bisection", "clipped"}
    (True, True)

    Loop elements (the keywords of :func:`check`) on one device in physical units (``mass=``,
    ``period=``, ``damping=``, ``delay=`` or ``delay_samples=``) give that loop's boundary in
    the (alpha, beta) plane; a hand stiffness makes negative ``alpha`` stable:

    >>> h = boundary(mass=0.1, period=1e-3, damping=0.0, delay_samples=1,
    ...              hand_mass=0.05, hand_stiffness=200.0, tol=1e-6)
    >>> bool(h.alpha.min() < 0.0)
    True

    In the delta-beta plane the elements need only the device's ``mass=`` and ``period=``
    (delta and d stay normalized): a first-order velocity filter at 30 Hz shrinks the stable
    region of ``alpha = 0.5`` at one sample of delay:

    >>> bare = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4)
    >>> lp = boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-4,
    ...               mass=0.1, period=1e-3, velocity_filter_cutoff=30.0)
    >>> bool(lp.delta.min() > bare.delta.min())
    True
    """
    loop = None
    if elements and plane == "delta-beta":
        loop = _delta_beta_loop(_named(elements), mass, period, damping, delay, delay_samples)
    elif elements:
        named = _named(elements)
        if plane != "alpha-beta" or delta is not None or d is not None or alpha is not None:
            raise ValueError("loop elements: give the device (mass=, period=, damping=, "
                             "delay=|delay_samples=) in the alpha-beta plane, not delta, d or alpha")
        m, t, b, dl, samples = _one_device(mass, period, damping, delay, delay_samples)
        method = "exact" if method is None else method
        (x, dd, a, bb, p), = _stabound.boundary_loop(m, t, b, dl, samples, _elements_tuple(named),
                                                    float(tol), str(method))
        return Boundary(x, dd, a, bb, _PIECE_NAMES[p], p)
    if loop is None and any(v is not None for v in (mass, period, damping, delay, delay_samples)):
        raise ValueError("boundary takes a device in physical units only with loop elements; "
                         "otherwise give delta and d")
    if d is None:
        raise ValueError("missing d (delay factors)")
    ds = [float(v) for v in np.atleast_1d(_f64(d)).reshape(-1)]
    if plane == "delta-beta":
        if method not in (None, "bisect"):
            raise ValueError("method='exact' is for the alpha-beta plane; the delta-beta plane uses method='bisect'")
        if alpha is None:
            raise ValueError("missing alpha= for plane='delta-beta'")
        if delta is None:
            lo, hi = 0.0, 1.0
        else:
            v = np.atleast_1d(_f64(delta)).reshape(-1)
            lo, hi = (float(v.min()), float(v.max())) if v.size else (0.0, 0.0)
            if not hi > lo:
                raise ValueError(
                    "in the delta-beta plane delta gives the axis range: at least two different values, e.g. [0, 1]"
                )
        alphas = [float(v) for v in np.atleast_1d(_f64(alpha)).reshape(-1)]
        curves = [
            DeltaBetaBoundary(a, dd, x, b, lp, np.where(cl, "clipped", "bisection"))
            for (a, dd, x, b, lp, cl) in _stabound.boundary_delta_beta(
                alphas, ds, lo, hi, float(tol), *(loop or ())
            )
        ]
        return curves[0] if _is_scalar(alpha, d) else curves
    if plane != "alpha-beta":
        raise ValueError(f"invalid plane = '{plane}': expected 'alpha-beta' or 'delta-beta'")
    if alpha is not None:
        raise ValueError("alpha= belongs to plane='delta-beta'; in the alpha-beta plane give delta and d")
    if delta is None:
        raise ValueError("missing delta (physical damping)")
    deltas = [float(v) for v in np.atleast_1d(_f64(delta)).reshape(-1)]
    method = "exact" if method is None else method
    curves = [
        Boundary(x, dd, a, b, _PIECE_NAMES[p], p)
        for (x, dd, a, b, p) in _stabound.boundary(deltas, ds, float(tol), str(method))
    ]
    return curves[0] if _is_scalar(delta, d) else curves


# ---------------------------------------------------------------------------------------
# lookup tables


@dataclass(frozen=True)
class LookupTable:
    """A lookup table of ``alpha_max`` over ``delta x d`` (:func:`table`)."""

    #: The delta axis (normalized), length ``nx``.
    delta: np.ndarray
    #: The d axis, length ``nd``.
    d: np.ndarray
    #: ``alpha_max[i, j]`` at ``d[i]``, ``delta[j]``, shape ``(nd, nx)``.
    alpha_max: np.ndarray
    #: The beta at each maximum, shape ``(nd, nx)``.
    beta_at_max: np.ndarray
    #: ``K_max`` in N/m (tables in physical units only).
    stiffness: Optional[np.ndarray]
    #: ``B`` at ``K_max`` in N s/m (tables in physical units only).
    wall_damping: Optional[np.ndarray]
    #: The table as ``stabound table --format csv`` writes it.
    csv: str
    #: ... as ``--format json``.
    json: str
    #: ... as ``--format c``: a C header for firmware.
    c_header: str
    #: ... as ``--format rust``: a Rust module.
    rust: str


def table(
    delta: Any = None,
    d: Any = None,
    *,
    conservative: bool = False,
    beta_min: Optional[float] = None,
    beta_max: Optional[float] = None,
    theta_tol: Optional[float] = None,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
    tol: Optional[float] = None,
    **elements: Any,
) -> LookupTable:
    """A lookup table of ``alpha_max`` for firmware: arrays and the C / Rust / CSV / JSON text.

    ``delta`` and ``d`` are the strictly increasing axes (1-D). Or, in physical units:
    ``mass=`` and ``period=`` (scalars), ``damping=`` (N s/m, the axis) and ``delay=`` (s)
    or ``delay_samples=`` (the other axis); the table then has ``stiffness`` and
    ``wall_damping`` too. With ``conservative=True`` every node is lowered just enough that
    linear interpolation never exceeds the true ``alpha_max`` at the test points.
    ``theta_tol`` is the refinement tolerance in theta, as for :func:`alpha_max` (``tol=``
    is its old name).

    >>> t = table([0.0, 0.5, 1.0], [0.0, 1.0])
    >>> t.alpha_max.shape, t.c_header.count("{") > 0
    ((2, 3), True)

    Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
    ``velocity_filter_cutoff=``) need the table in physical units; every node is then that
    loop's ``alpha_max`` (``stabound table`` with the element flags), the conservative check
    tests every query with the loop's own point test, and the C header lists the elements:

    >>> f = table(mass=0.1, period=1e-3, damping=[0.0, 2.0], delay_samples=[1],
    ...           velocity_filter_cutoff=30.0)
    >>> bool((f.stiffness < table(mass=0.1, period=1e-3, damping=[0.0, 2.0],
    ...                           delay_samples=[1]).stiffness).all())
    True
    >>> "low-pass velocity filter" in f.c_header
    True
    """
    named = _named(elements) if elements else None
    theta_tol = _renamed(theta_tol, tol, "tol", "theta_tol", DEFAULT_THETA_TOL)
    physical = _physical(mass=mass, period=period, damping=damping, delay=delay, delay_samples=delay_samples)
    scale = None
    if physical:
        if delta is not None or d is not None:
            raise ValueError(
                "give either delta and d, or mass=, period=, damping= and delay=|delay_samples=, not both"
            )
        _device(mass, period, damping)
        value, samples = _delay(delay, delay_samples)
        if np.ndim(mass) != 0 or np.ndim(period) != 0:
            raise ValueError("a table in physical units is for one device: mass= and period= are scalars")
        bs = np.atleast_1d(_f64(damping)).reshape(-1)
        dls = np.atleast_1d(_f64(value)).reshape(-1)
        m, t = float(mass), float(period)
        # as the command line does: delta from each damping, d from each delay
        delta, _ = normalize(mass=m, period=t, damping=bs, **{("delay_samples" if samples else "delay"): dls[0]})
        _, d = normalize(mass=m, period=t, damping=bs[0], **{("delay_samples" if samples else "delay"): dls})
        scale = (m, t)
    elif delta is None or d is None:
        raise ValueError(
            "missing delta and d (or physical mass=, period=, damping= and delay=|delay_samples=)"
        )
    elif named is not None:
        raise ValueError("loop elements are given in physical units: give the device "
                         "(mass=, period=, damping=, delay=|delay_samples=), not delta and d")
    deltas = [float(v) for v in np.atleast_1d(_f64(delta)).reshape(-1)]
    ds = [float(v) for v in np.atleast_1d(_f64(d)).reshape(-1)]
    r = _stabound.table(deltas, ds, float(theta_tol), beta_min, beta_max, bool(conservative), scale,
                        None if named is None else _elements_tuple(named))
    return LookupTable(
        delta=r["delta"],
        d=r["d"],
        alpha_max=r["alpha_max"],
        beta_at_max=r["beta_at_max"],
        stiffness=r.get("stiffness"),
        wall_damping=r.get("wall_damping"),
        csv=r["csv"],
        json=r["json"],
        c_header=r["c_header"],
        rust=r["rust"],
    )


# ---------------------------------------------------------------------------------------
# scenes


def _scene(source: Any, band: float) -> tuple:
    if isinstance(source, dict):
        try:
            text = json.dumps(source, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise ValueError(f"the scene dict cannot be written as JSON: {e}") from None
        return _stabound.scene(None, text, "<dict>", float(band))
    if isinstance(source, (str, bytes, os.PathLike)):
        return _stabound.scene(os.fsdecode(os.fspath(source)), None, "", float(band))
    raise TypeError("scene() takes a path (str or os.PathLike) or a dict")


def scene(
    source: Union[str, os.PathLike, dict],
    *,
    marginal_band: Optional[float] = None,
    margin: Optional[float] = None,
) -> dict:
    """Check every wall of a scene: verdict, margins, stable dampings, suggested damping.

    ``source`` is a scene file (TOML, or JSON for a ``.json`` name) or a dict of the same
    structure: ``{"device": [{"mass_kg": ..., "period_s": ..., "damping_Ns_per_m": ...,
    "delay_s" or "delay_samples": ..., "wall": [{"stiffness_N_per_m": ...,
    "damping_Ns_per_m": ...}]}]}`` (``name`` optional everywhere). Returns the report as
    ``stabound scene --format json`` writes it, as a dict. ``marginal_band`` is the
    half-width of the marginal band (``--marginal-band``; ``margin=`` is its old name).

    >>> r = scene({"device": [{"mass_kg": 1.0, "period_s": 0.001, "damping_Ns_per_m": 0.0,
    ...     "delay_samples": 1, "wall": [{"stiffness_N_per_m": 1e5, "damping_Ns_per_m": 300.0}]}]})
    >>> r["devices"][0]["walls"][0]["verdict"]
    'stable'
    """
    band = _renamed(marginal_band, margin, "margin", "marginal_band", DEFAULT_MARGINAL_BAND)
    return json.loads(_scene(source, band)[0])


def scene_text(
    source: Union[str, os.PathLike, dict],
    *,
    marginal_band: Optional[float] = None,
    margin: Optional[float] = None,
) -> str:
    """The report of :func:`scene` as the text ``stabound scene`` prints."""
    band = _renamed(marginal_band, margin, "margin", "marginal_band", DEFAULT_MARGINAL_BAND)
    return _scene(source, band)[1]


# ---------------------------------------------------------------------------------------
# step responses


@dataclass(frozen=True)
class StepResponse:
    """The response of the position to a step of operator force (:func:`step`)."""

    #: Physical damping ``b`` of the device, N s/m.
    damping: float
    #: Wall stiffness ``K``, N/m.
    stiffness: float
    #: Wall damping ``B``, N s/m.
    wall_damping: float
    alpha: float
    beta: float
    delta: float
    d: float
    #: ``'stable'``, ``'marginal'`` or ``'unstable'`` (an unstable response grows).
    verdict: str
    #: The value a stable response settles at (``F_H / K``; with a hand's stiffness ``k_h``
    #: to ground ``F_H / (K + k_h)``, and ``F_H / (K + k_h (1 + K / k_c))`` read on the motor
    #: side of a transmission), else None.
    final_value: Optional[float]
    #: Largest position.
    peak: float
    #: First time after which the response stays within ``settling_band`` of the final
    #: value (relative), or None.
    settling_time: Optional[float]
    #: Times (s), ``points_per_period`` per sampling period.
    time: np.ndarray
    #: Position (m) at ``time``, exact between the samples too (with a transmission, the
    #: side the encoder reads).
    position: np.ndarray
    #: Position at the sampling instants.
    samples: np.ndarray
    #: The loop elements modelled, as ``stabound step --format summary`` names them
    #: (``'hand'``, ``'actuator lag'``, ...); empty for the paper's loop.
    elements: tuple = ()


def step(
    *,
    mass: float,
    period: float,
    damping: Any,
    delay: Optional[float] = None,
    delay_samples: Optional[float] = None,
    stiffness: Optional[float] = None,
    wall_damping: Optional[float] = None,
    margin: Optional[float] = None,
    force: float = 1.0,
    duration: float = 0.05,
    points_per_period: int = 10,
    settling_band: float = 0.02,
    **elements: Any,
) -> Union[StepResponse, list]:
    """Step responses from operator force to position, exact between samples (paper Fig. 11).

    One device per value of ``damping`` (N s/m; a scalar gives one :class:`StepResponse`,
    a sequence a list). The wall is ``stiffness=`` (N/m) with ``wall_damping=`` (N s/m,
    default 0), or ``margin=F``: ``F * alpha_max`` with the damping at ``alpha_max``
    (paper Section VIII uses 0.75). ``force`` is the step in N, ``duration`` the simulated
    time in s.

    >>> r = step(mass=1.0, period=1e-3, damping=[0.0, 10.0], delay_samples=1, margin=0.75)
    >>> [x.verdict for x in r], float(r[0].time[-1])
    (['stable', 'stable'], 0.05)

    Loop elements (the keywords of :func:`check`: ``hand_mass=``, ...,
    ``velocity_filter_cutoff=``, as ``stabound step`` takes them) are modelled on each
    device; the operator's force acts on the handle, the position is the one the encoder
    reads, and ``margin=`` takes that loop's ``alpha_max``. A hand's spring to ground shares
    the static deflection with the wall:

    >>> r = step(mass=0.1, period=1e-3, damping=1.0, delay_samples=1, stiffness=2000.0,
    ...          duration=0.5, hand_mass=0.05, hand_stiffness=500.0)
    >>> r.elements, round(r.final_value * 2500.0, 12)
    (('hand',), 1.0)
    """
    named = _named(elements)
    value, samples = _delay(delay, delay_samples)
    if (stiffness is None) == (margin is None):
        raise ValueError("give stiffness= K or margin= F (one of them)")
    if margin is not None and wall_damping is not None:
        raise ValueError("wall_damping= goes with stiffness=; with margin= the damping is the one at alpha_max")
    if not (np.isfinite(settling_band) and settling_band > 0):
        raise ValueError("settling_band must be a positive number")
    scalar = np.ndim(damping) == 0
    bs = [float(v) for v in np.atleast_1d(_f64(damping)).reshape(-1)]
    if not bs:
        raise ValueError("damping= is empty; give at least one value")
    runs = _stabound.step(
        float(mass), float(period), bs, float(value), samples,
        None if stiffness is None else float(stiffness),
        None if wall_damping is None else float(wall_damping),
        None if margin is None else float(margin),
        float(force), float(duration), int(points_per_period), float(settling_band),
        _elements_tuple(named),
    )
    out = [StepResponse(**{**r, "elements": tuple(r["elements"])}) for r in runs]
    return out[0] if scalar else out


# ---------------------------------------------------------------------------------------
# passivity


class Witness(NamedTuple):
    """A wall found by :func:`passivity`'s comparison, with its evidence."""

    alpha: float
    beta: float
    #: Physical damping of the wall's device.
    delta: float
    #: The certified passivity margin's end that decides (> 0 passive, < 0 not passive).
    margin: float
    #: ``'stable'`` or ``'unstable'``.
    verdict: str


@dataclass(frozen=True)
class Passivity:
    """The passive region and its comparison with the stable region (:func:`passivity`).

    In the ``'alpha-beta'`` plane ``x`` is ``alpha`` (the region is a closed polygon, the
    last point repeating the first); in ``'delta-beta'`` it is ``delta`` (the edge
    ``delta = h(beta)`` from its top end to its bottom end). ``y`` is ``beta`` in both.
    """

    #: ``'alpha-beta'`` or ``'delta-beta'``.
    plane: str
    #: The fixed parameter: ``delta`` (alpha-beta plane) or ``alpha`` (delta-beta plane).
    at: float
    d: float
    #: The filter as ``stabound passivity --summary`` names it.
    filter: str
    #: Vertices of the passive edge.
    x: np.ndarray
    y: np.ndarray
    #: The active frequency (rad per sample) at each vertex.
    theta: np.ndarray
    #: What each vertex lies on: ``'envelope'``, ``'corner'``, ``'alpha-zero'``, ``'delta-max'``.
    edge: np.ndarray
    #: The tolerance the edge was traced to.
    tol: float
    #: The stable region's points (NaN pairs separate pieces), or None.
    stable_x: Optional[np.ndarray]
    stable_y: Optional[np.ndarray]
    #: How they were found: ``'exact'``, ``'columns'`` or ``'bisection'``.
    stable_points: Optional[str]
    #: Largest passive stiffness over beta, and the beta where it is reached (alpha-beta
    #: plane; None without a passive wall).
    alpha_max_passive: Optional[float]
    beta_at_max: Optional[float]
    #: Largest passive stiffness at ``beta=`` (None when not asked or none is passive).
    alpha_max_at_beta: Optional[float]
    #: Whether the passive region lies inside the stable one (None: not compared).
    inside: Optional[bool]
    passive_area: Optional[float]
    stable_area: Optional[float]
    passive_share_of_stable: Optional[float]
    stable_share_of_passive: Optional[float]
    #: Error estimate and bound of the passive share (NaN for the exact engine).
    passive_share_error: Optional[float]
    passive_share_bound: Optional[float]
    #: ``'exact'`` (D-decomposition) or ``'columns'`` (exact stable sets on lines).
    stable_method: Optional[str]
    #: A passive wall that is unstable, if one was found.
    passive_unstable: Optional[Witness]
    #: A stable wall that is not passive, if one was found.
    stable_not_passive: Optional[Witness]
    #: ``K`` (N/m) and ``B`` (N s/m) of the largest passive wall (with ``mass=``, ``period=``).
    stiffness_max: Optional[float] = None
    wall_damping_at_max: Optional[float] = None


#: Default lines per half of a column comparison (:func:`passivity` ``columns=``).
DEFAULT_COLUMNS: int = _stabound.DEFAULT_COLUMNS


def _passivity_normalized(delta, d, alpha, beta, damping, delay, delay_samples, stiffness,
                          wall_damping, mass, period) -> tuple:
    """``(delta, d, alpha, beta)`` of :func:`passivity` with the physical keywords converted
    through the library's device (``delta = b T / m``, ``d = delay / T``, ``alpha = K T^2 /
    m``, ``beta = B T / m``), as ``stabound passivity`` converts its physical flags."""
    for norm, norm_value, phys, phys_value in (
        ("delta", delta, "damping", damping),
        ("alpha", alpha, "stiffness", stiffness),
        ("beta", beta, "wall_damping", wall_damping),
        ("d", d, "delay_samples", delay_samples),
        ("d", d, "delay", delay),
        ("delay_samples", delay_samples, "delay", delay),
    ):
        if norm_value is not None and phys_value is not None:
            raise ValueError(f"give {norm}= or {phys}=, not both (they are the same parameter)")
    if delay is not None:
        if period is None:
            raise ValueError("delay= (in s) needs period= (the sampling period in s)")
        _, d = normalize(mass=1.0, period=period, damping=0.0, delay=delay)
    elif delay_samples is not None:
        d = delay_samples
    physical = [f"{n}=" for n, v in (("damping", damping), ("delay", delay),
                                     ("stiffness", stiffness), ("wall_damping", wall_damping))
                if v is not None]
    if physical != [] and physical != ["delay="]:  # a delay in s needs only the period
        if mass is None or period is None:
            one = len(physical) == 1
            raise ValueError(
                f"{', '.join(physical)} {'is' if one else 'are'} in physical units and "
                f"need{'s' if one else ''} the device: give mass= and period=, or the "
                "normalized delta, alpha=, beta="
            )
        b = 0.0 if damping is None else damping
        k = 0.0 if stiffness is None else stiffness
        bw = 0.0 if wall_damping is None else wall_damping
        a, bb, x, _ = normalize(mass=mass, period=period, damping=b, delay_samples=0.0,
                                stiffness=k, wall_damping=bw)
        delta = x if damping is not None else delta
        alpha = a if stiffness is not None else alpha
        beta = bb if wall_damping is not None else beta
    return delta, (0.0 if d is None else d), alpha, beta


def passivity(
    delta: Optional[float] = None,
    d: Optional[float] = None,
    *,
    plane: str = "alpha-beta",
    alpha: Optional[float] = None,
    beta: Optional[float] = None,
    filter_pole: Optional[float] = None,
    velocity_filter_cutoff: Optional[float] = None,
    velocity_filter_samples: Optional[int] = None,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Optional[float] = None,
    delay: Optional[float] = None,
    delay_samples: Optional[float] = None,
    stiffness: Optional[float] = None,
    wall_damping: Optional[float] = None,
    tol: float = 1e-7,
    columns: int = DEFAULT_COLUMNS,
) -> Passivity:
    """The passive region for a whole-sample delay and a velocity filter, and how it compares
    with the stable region (``stabound passivity``, the same numbers bit for bit).

    ``plane='alpha-beta'`` (the default) at physical damping ``delta``: the passive polygon,
    the largest passive stiffness (over beta, and at ``beta=``), and the comparison with the
    stable region (the exact boundary without a filter, exact stable sets on ``2 columns + 1``
    lines of constant beta with one). ``plane='delta-beta'`` at stiffness ``alpha=``, for
    delta up to ``delta`` (default 4): the passive edge and, for ``alpha > 0``, the comparison
    on lines of constant delta. ``d`` is the delay in whole samples (a fractional delay raises
    ValueError, saying why). The filter: ``filter_pole=a`` (first-order low-pass, ``0 <= a <
    1``), ``velocity_filter_cutoff=`` Hz with ``period=`` s, or ``velocity_filter_samples=N``
    (moving average). ``tol`` is the largest distance of the traced edge from the true one.
    With ``mass=`` (kg) and ``period=`` the largest passive wall is also given in N/m and
    N s/m, and the parameters may be given in physical units instead, as ``stabound
    passivity --damping ...``: ``damping=`` (N s/m) for ``delta``, ``stiffness=`` (N/m) for
    ``alpha=``, ``wall_damping=`` (N s/m) for ``beta=`` (converted through the device:
    ``delta = b T / m``, ``alpha = K T^2 / m``, ``beta = B T / m``), and ``delay=`` (s, a
    whole number of periods; needs only ``period=``) or ``delay_samples=`` for ``d``. A
    normalized parameter and its physical counterpart together raise ValueError, as does a
    physical one without the device.

    >>> p = passivity(1.0, 1)
    >>> round(p.alpha_max_passive, 6), p.inside           # (2 sqrt 2 - 2) delta at d = 1
    (0.828427, True)
    >>> round(passivity(2.0, 1, beta=0.0).alpha_max_at_beta, 6)   # Diolaiti: 2 delta / (1 + 2 d)
    1.333333
    >>> q = passivity(1.0, 1, velocity_filter_samples=2)
    >>> q.stable_method, q.inside, q.passive_unstable is None
    ('columns', True, True)
    >>> r = passivity(3.0, 1, plane="delta-beta", alpha=0.5)
    >>> r.inside, 0 < r.passive_share_of_stable < 1
    (True, True)

    The same device in physical units: b = 200 N s/m, m = 0.1 kg, T = 1 ms (delta = 2), one
    sample of delay; the largest passive stiffness is 2 (2 sqrt 2 - 2) = 1.656854 (K in N/m
    is alpha m / T^2), and at B = 0 N s/m it is 4/3:

    >>> s = passivity(damping=200.0, mass=0.1, period=1e-3, delay=1e-3, wall_damping=0.0)
    >>> round(s.alpha_max_passive, 6), round(s.stiffness_max), round(s.alpha_max_at_beta, 6)
    (1.656854, 165685, 1.333333)
    """
    delta, d, alpha, beta = _passivity_normalized(
        delta, d, alpha, beta, damping, delay, delay_samples, stiffness, wall_damping,
        mass, period,
    )
    if plane == "alpha-beta":
        if alpha is not None:
            raise ValueError("alpha= belongs to plane='delta-beta', as stiffness= does; in the "
                             "alpha-beta plane give delta (or damping=)")
        if delta is None:
            raise ValueError("missing delta (physical damping; or damping= in N s/m with mass= "
                             "and period=)")
        fixed, delta_max = float(delta), 0.0
    elif plane == "delta-beta":
        if alpha is None:
            raise ValueError("missing alpha= for plane='delta-beta' (or stiffness= in N/m with "
                             "mass= and period=)")
        if beta is not None:
            raise ValueError("beta= belongs to the alpha-beta plane, as wall_damping= does (the "
                             "largest passive stiffness at one delta)")
        fixed, delta_max = float(alpha), 4.0 if delta is None else float(delta)
    else:
        raise ValueError(f"invalid plane = '{plane}': expected 'alpha-beta' or 'delta-beta'")
    if mass is not None and period is None:
        raise ValueError("mass= needs period= (the sampling period in s)")
    if isinstance(columns, bool) or not isinstance(columns, (int, np.integer)) or columns < 0:
        raise ValueError(f"invalid columns = {columns!r}: give a whole number of lines, e.g. {DEFAULT_COLUMNS}")
    if velocity_filter_samples is not None and (
        isinstance(velocity_filter_samples, bool) or not isinstance(velocity_filter_samples, (int, np.integer))
        or velocity_filter_samples < 0
    ):
        raise ValueError(f"invalid velocity_filter_samples = {velocity_filter_samples!r}: give a whole number of samples")
    if mass is not None:
        normalize(mass=mass, period=period, damping=0.0, delay_samples=0.0)  # validates the device
    opt = lambda v: None if v is None else float(v)  # noqa: E731
    filt = (opt(filter_pole), opt(velocity_filter_cutoff), opt(period),
            None if velocity_filter_samples is None else int(velocity_filter_samples))
    r = _stabound.passivity(plane, fixed, float(d), filt, float(tol), int(columns), delta_max, opt(beta))
    wit = lambda w: None if w is None else Witness(**w)  # noqa: E731
    k = b = None
    if mass is not None and r.get("alpha_max_passive") is not None:
        ks, bs = _stabound.device_scale(
            _f64([mass]), _f64([period]), _f64([r["alpha_max_passive"]]), _f64([r["beta_at_max"]])
        )
        k, b = float(ks[0]), float(bs[0])
    return Passivity(
        plane=plane,
        at=fixed,
        d=float(d),
        filter=r["filter"],
        x=r["x"],
        y=r["y"],
        theta=r["theta"],
        edge=np.array(r["edge"], dtype=str),
        tol=r["tol"],
        stable_x=r.get("stable_x"),
        stable_y=r.get("stable_y"),
        stable_points=r.get("stable_points"),
        alpha_max_passive=r.get("alpha_max_passive"),
        beta_at_max=r.get("beta_at_max"),
        alpha_max_at_beta=r.get("alpha_max_at_beta"),
        inside=r.get("inside"),
        passive_area=r.get("passive_area"),
        stable_area=r.get("stable_area"),
        passive_share_of_stable=r.get("passive_share_of_stable"),
        stable_share_of_passive=r.get("stable_share_of_passive"),
        passive_share_error=r.get("passive_share_error"),
        passive_share_bound=r.get("passive_share_bound"),
        stable_method=r.get("stable_method"),
        passive_unstable=wit(r.get("passive_unstable")),
        stable_not_passive=wit(r.get("stable_not_passive")),
        stiffness_max=k,
        wall_damping_at_max=b,
    )


# ---------------------------------------------------------------------------------------
# figures


class FigureText(NamedTuple):
    """A figure as ``stabound figure`` (or ``passivity --figures-dir``) writes its files."""

    #: The file name without extension, e.g. ``'fig05'`` or ``'fig08-d1'``.
    name: str
    #: The drawing (SVG text).
    svg: str
    #: The data (CSV text).
    csv: str


def figure(which: Union[int, str]) -> FigureText:
    """The paper's figure ``which`` (5 to 11) as SVG and CSV text, or by name one of the
    passivity companions of Figs. 8 and 9 for d = 1, 2, 4 (``'fig08-d1'`` ... ``'fig09-d4'``).

    >>> f = figure(10)
    >>> f.name, f.svg.startswith("<svg"), f.csv.splitlines()[0].startswith("series")
    ('fig10', True, True)
    """
    if isinstance(which, bool):
        raise ValueError("give a figure number (5 to 11) or a companion's name such as 'fig08-d1'")
    if isinstance(which, (int, np.integer)):
        if which < 0:
            raise ValueError(f"the paper has no figure {which} with data; give one of 5, 6, 7, 8, 9, 10, 11")
        return FigureText(*_stabound.figure(int(which), None))
    if isinstance(which, str):
        return FigureText(*_stabound.figure(None, which))
    raise ValueError("give a figure number (5 to 11) or a companion's name such as 'fig08-d1'")
