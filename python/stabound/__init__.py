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
#: Default half-width of the marginal band around the unit circle.
DEFAULT_MARGIN: float = _stabound.DEFAULT_MARGIN
#: Default refinement tolerance (in theta, rad) of :func:`alpha_max` and :func:`table`.
DEFAULT_AMAX_TOL: float = _stabound.DEFAULT_AMAX_TOL
#: Default accuracy of :func:`boundary` points, in normalized units.
DEFAULT_BOUNDARY_TOL: float = _stabound.DEFAULT_BOUNDARY_TOL

__all__ = [
    "Amax",
    "AmaxPhysical",
    "Boundary",
    "CheckResult",
    "DeltaBetaBoundary",
    "DEFAULT_AMAX_TOL",
    "DEFAULT_BOUNDARY_TOL",
    "DEFAULT_MARGIN",
    "LookupTable",
    "METHODS",
    "PIECES",
    "StaboundError",
    "StepResponse",
    "VERDICTS",
    "alpha_max",
    "analyze",
    "boundary",
    "check",
    "normalize",
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


def check(
    alpha: Any = None,
    beta: Any = None,
    delta: Any = None,
    d: Any = None,
    *,
    method: str = "auto",
    margin: float = DEFAULT_MARGIN,
    radius: bool = True,
    mass: Any = None,
    period: Any = None,
    damping: Any = None,
    stiffness: Any = None,
    wall_damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
    hand_mass: Optional[float] = None,
    hand_damping: Optional[float] = None,
    hand_stiffness: Optional[float] = None,
    handle_mass: Optional[float] = None,
    transmission_stiffness: Optional[float] = None,
    transmission_damping: Optional[float] = None,
    encoder: Optional[str] = None,
    actuator_time_constant: Optional[float] = None,
    velocity_filter_cutoff: Optional[float] = None,
    velocity_filter_samples: Optional[int] = None,
) -> CheckResult:
    """Test walls for stability: verdict and spectral radius of each point.

    ``alpha``, ``beta``, ``delta`` and ``d`` broadcast against each other (numpy rules);
    the result has their broadcast shape, or is scalar when all four are scalars. Or give
    the walls in physical units: ``mass=`` (kg), ``period=`` (s), ``damping=`` (N s/m),
    ``stiffness=`` (N/m), ``wall_damping=`` (N s/m) and ``delay=`` (s) or
    ``delay_samples=``, all broadcasting.

    ``method`` is one of :data:`METHODS` (``'auto'``: Schur-Cohn with a rounding-error
    guard, then a proven argument-principle count, then the certified stage (coefficient
    bounds and inclusion discs) where it cannot vouch; ``'marginal'`` where none can). A spectral radius within ``margin`` of 1 is ``'marginal'``. With
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
    named = (hand_mass, hand_damping, hand_stiffness, handle_mass, transmission_stiffness,
             transmission_damping, encoder, actuator_time_constant, velocity_filter_cutoff,
             velocity_filter_samples)
    if any(v is not None for v in named):
        return _check_loop(
            alpha, beta, delta, d, method, margin, radius, mass, period, damping, stiffness,
            wall_damping, delay, delay_samples, named,
        )
    alpha, beta, delta, d, _ = _walls(
        alpha, beta, delta, d, mass, period, damping, delay, delay_samples, stiffness, wall_damping
    )
    shape, (a, b, x, dd) = _flat(alpha, beta, delta, d)
    rho, code, mcode = _stabound.check(a, b, x, dd, str(method), float(margin), bool(radius))
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


def _check_loop(alpha, beta, delta, d, method, margin, radius, mass, period, damping, stiffness,
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
    hm, hb, hk, m2, kc, bc, enc, tau, fc, n = named
    opt = lambda v: None if v is None else float(v)  # noqa: E731
    elements = (opt(hm), opt(hb), opt(hk), opt(m2), opt(kc), opt(bc),
                None if enc is None else str(enc), opt(tau), opt(fc),
                None if n is None else int(n))
    rho, code, mcode = _stabound.check_loop(
        fa, fb, float(mass), float(period), float(damping), dl, samples, elements,
        str(method), float(margin), bool(radius),
    )
    return _check_result(shape, rho, code, mcode)


def analyze(
    alpha: Optional[float] = None,
    beta: Optional[float] = None,
    delta: Optional[float] = None,
    d: Optional[float] = None,
    *,
    method: str = "auto",
    margin: float = DEFAULT_MARGIN,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Optional[float] = None,
    stiffness: Optional[float] = None,
    wall_damping: Optional[float] = None,
    delay: Optional[float] = None,
    delay_samples: Optional[float] = None,
) -> dict:
    """Everything ``stabound check --format json`` reports for one wall, with the roots.

    Keys: ``stable``, ``verdict``, ``spectral_radius``, ``roots`` (complex array),
    ``degree``, ``method``, ``margin``, ``alpha``, ``beta``, ``delta``, ``d``, and for a
    wall in physical units ``physical`` (mass, period, damping, stiffness, wall_damping,
    delay_samples).

    >>> r = analyze(0.1, 0.3, 0.5, 1.0)
    >>> r["verdict"], r["degree"], len(r["roots"])
    ('stable', 4, 4)
    """
    alpha, beta, delta, d, physical = _walls(
        alpha, beta, delta, d, mass, period, damping, delay, delay_samples, stiffness, wall_damping
    )
    if not _is_scalar(alpha, beta, delta, d):
        raise ValueError("analyze takes one wall (scalars); use check() for arrays")
    device = (float(mass), float(period), float(damping)) if physical else None
    return _stabound.analyze(
        float(alpha), float(beta), float(delta), float(d), str(method), float(margin), device
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
    tol: float = DEFAULT_AMAX_TOL,
    mass: Any = None,
    period: Any = None,
    damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
) -> Union[Amax, AmaxPhysical]:
    """Maximum stable stiffness ``alpha_max`` and the ``beta`` where it is reached.

    ``delta`` and ``d`` broadcast; scalar in, scalar out. ``beta_min`` / ``beta_max``
    restrict the admissible virtual damping (e.g. ``beta_min=0`` when negative damping
    cannot be rendered); ``tol`` is the refinement tolerance in theta (rad), in
    ``[1e-15, 1e-2]``. Or give devices as ``mass=``, ``period=``, ``damping=`` and
    ``delay=`` / ``delay_samples=`` (broadcasting): the result then also has ``stiffness``
    (``K_max``, N/m) and ``wall_damping`` (N s/m).

    Computed in parallel with the GIL released; the same numbers, bit for bit, as
    ``stabound amax``.

    >>> round(alpha_max(0.0, 0.0).alpha_max, 12)     # 12 - 8 sqrt 2 (paper, Remark 4)
    0.686291501015
    >>> a, b = alpha_max([0.0, 0.1, 1.0], 1.0)
    >>> (0.75 * a).round(3).tolist()                  # paper Section VIII
    [0.108, 0.149, 0.656]
    >>> round(alpha_max(mass=1.0, period=1e-3, damping=0.0, delay_samples=1).stiffness)
    144469
    """
    delta, d, physical = _normalized_plants(delta, d, mass, period, damping, delay, delay_samples)
    shape, (x, dd) = _flat(delta, d)
    a, b = _stabound.alpha_max(x, dd, float(tol), beta_min, beta_max)
    if not physical:
        return Amax(_out(shape, a), _out(shape, b))
    shape2, (m, t, a2, b2) = _flat(mass, period, a.reshape(shape), b.reshape(shape))
    k, bw = _stabound.device_scale(m, t, a2, b2)
    return AmaxPhysical(_out(shape, a), _out(shape, b), _out(shape2, k), _out(shape2, bw))


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


def boundary(
    delta: Any = None,
    d: Any = None,
    *,
    tol: float = DEFAULT_BOUNDARY_TOL,
    method: Optional[str] = None,
    plane: str = "alpha-beta",
    alpha: Any = None,
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
    """
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
            for (a, dd, x, b, lp, cl) in _stabound.boundary_delta_beta(alphas, ds, lo, hi, float(tol))
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
    tol: float = DEFAULT_AMAX_TOL,
    mass: Optional[float] = None,
    period: Optional[float] = None,
    damping: Any = None,
    delay: Any = None,
    delay_samples: Any = None,
) -> LookupTable:
    """A lookup table of ``alpha_max`` for firmware: arrays and the C / Rust / CSV / JSON text.

    ``delta`` and ``d`` are the strictly increasing axes (1-D). Or, in physical units:
    ``mass=`` and ``period=`` (scalars), ``damping=`` (N s/m, the axis) and ``delay=`` (s)
    or ``delay_samples=`` (the other axis); the table then has ``stiffness`` and
    ``wall_damping`` too. With ``conservative=True`` every node is lowered just enough that
    linear interpolation never exceeds the true ``alpha_max`` at the test points.

    >>> t = table([0.0, 0.5, 1.0], [0.0, 1.0])
    >>> t.alpha_max.shape, t.c_header.count("{") > 0
    ((2, 3), True)
    """
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
    deltas = [float(v) for v in np.atleast_1d(_f64(delta)).reshape(-1)]
    ds = [float(v) for v in np.atleast_1d(_f64(d)).reshape(-1)]
    r = _stabound.table(deltas, ds, float(tol), beta_min, beta_max, bool(conservative), scale)
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


def _scene(source: Any, margin: float) -> tuple:
    if isinstance(source, dict):
        try:
            text = json.dumps(source, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise ValueError(f"the scene dict cannot be written as JSON: {e}") from None
        return _stabound.scene(None, text, "<dict>", float(margin))
    if isinstance(source, (str, bytes, os.PathLike)):
        return _stabound.scene(os.fsdecode(os.fspath(source)), None, "", float(margin))
    raise TypeError("scene() takes a path (str or os.PathLike) or a dict")


def scene(source: Union[str, os.PathLike, dict], *, margin: float = DEFAULT_MARGIN) -> dict:
    """Check every wall of a scene: verdict, margins, stable dampings, suggested damping.

    ``source`` is a scene file (TOML, or JSON for a ``.json`` name) or a dict of the same
    structure: ``{"device": [{"mass_kg": ..., "period_s": ..., "damping_Ns_per_m": ...,
    "delay_s" or "delay_samples": ..., "wall": [{"stiffness_N_per_m": ...,
    "damping_Ns_per_m": ...}]}]}`` (``name`` optional everywhere). Returns the report as
    ``stabound scene --format json`` writes it, as a dict.

    >>> r = scene({"device": [{"mass_kg": 1.0, "period_s": 0.001, "damping_Ns_per_m": 0.0,
    ...     "delay_samples": 1, "wall": [{"stiffness_N_per_m": 1e5, "damping_Ns_per_m": 300.0}]}]})
    >>> r["devices"][0]["walls"][0]["verdict"]
    'stable'
    """
    return json.loads(_scene(source, margin)[0])


def scene_text(source: Union[str, os.PathLike, dict], *, margin: float = DEFAULT_MARGIN) -> str:
    """The report of :func:`scene` as the text ``stabound scene`` prints."""
    return _scene(source, margin)[1]


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
    #: The value a stable response settles at (``F_H / K``), else None.
    final_value: Optional[float]
    #: Largest position.
    peak: float
    #: First time after which the response stays within ``settling_band`` of the final
    #: value (relative), or None.
    settling_time: Optional[float]
    #: Times (s), ``points_per_period`` per sampling period.
    time: np.ndarray
    #: Position (m) at ``time``, exact between the samples too.
    position: np.ndarray
    #: Position at the sampling instants.
    samples: np.ndarray


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
    """
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
    )
    out = [StepResponse(**r) for r in runs]
    return out[0] if scalar else out
