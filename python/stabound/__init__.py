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

The numerics run in Rust (the ``stabound`` crate) on all cores with the GIL released (except
:func:`check` of one wall given as four floats, whose verdict takes less time than a release
of the GIL); the results do not depend on the number of threads. The functions are those of the compiled
core, which converts, broadcasts and validates every argument with the library's own checks
(the same as the command line's): numbers are floats or ints or arrays of them (strings,
bools, dates, masked arrays are refused with TypeError), and a bad array entry is named by
its index. Long calls react to Ctrl-C (KeyboardInterrupt).

>>> import stabound
>>> round(stabound.alpha_max(0.0, 0.0).alpha_max, 12)   # 12 - 8 sqrt 2
0.686291501015
>>> stabound.check(0.1, 0.3, 0.5, 1.0).verdict
'stable'

Bad input raises :class:`ValueError` with the library's message; a numerical failure
raises :class:`StaboundError`.

A set of devices (the command line's ``LO..HI`` and ``one-of:LIST``): give a physical
parameter as :class:`Interval` ``(lo, hi)`` (``delay_samples=Interval(1, 3)``,
``hand_mass=Interval(0.2, 0.5)``; the device's mass, damping and delay, and every number of
a loop element) or as the finite set :class:`OneOf` ``(a, b, ...)``
(``delay_samples=OneOf(1, 2, 3)``: each value, none between). A plain tuple or list stays an
array of values, one result each (numpy's broadcasting), so a set has its own type. :func:`alpha_max`, :func:`table` and :func:`check` then answer for
every member; with a hand they include the device with the hand let go unless
``always_gripped=True`` (:func:`check` tests the device as given), as the command line does.
:func:`boundary` gives the robust region (the walls stable for every member, one
:class:`Boundary` in the set's reference normalization, the rows of ``stabound boundary``
with an interval) and with ``members=True`` also each member's own curve
(:class:`MemberBoundary`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, Optional

import numpy as np

from . import _stabound
from ._stabound import (
    StaboundError,
    alpha_max,
    analyze,
    boundary,
    buzz,
    certify,
    certify_alpha_max,
    check,
    figure,
    normalize,
    passivity,
    scene,
    scene_text,
    step,
    table,
)

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
    "Interval",
    "OneOf",
    "RobustAmax",
    "SetCheck",
    "SetCertified",
    "AmaxMargin",
    "AmaxPhysical",
    "AmaxPhysicalMargin",
    "Boundary",
    "CheckResult",
    "Certified",
    "CertifiedAmax",
    "DeltaBetaBoundary",
    "MemberBoundary",
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
    "buzz",
    "certify",
    "certify_alpha_max",
    "check",
    "figure",
    "normalize",
    "passivity",
    "scene",
    "scene_text",
    "step",
    "table",
]


#: Default lines per half of a column comparison (:func:`passivity` ``columns=``).
DEFAULT_COLUMNS: int = _stabound.DEFAULT_COLUMNS

# names by code, for the compiled core's arrays of codes
_VERDICT_NAMES = np.array(VERDICTS)
_METHOD_NAMES = np.array(METHODS)
_PIECE_NAMES = np.array(PIECES)


# ---------------------------------------------------------------------------------------
# result types (the compiled core returns these)

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
    #: ``F`` times the stiffest wall whose every stiffness from the margin wall up is stable
    #: at its damping: ``F * alpha_max`` unless loop elements make the stable stiffnesses at
    #: the optimum's damping more than one range.
    alpha_margin: Any
    #: The damping to render with it (the one at ``alpha_max``, or that wall's).
    beta_margin: Any
    #: ``alpha_margin`` in N/m (the command line's ``K_margin_N_per_m``).
    stiffness_margin: Any


class Interval(NamedTuple):
    """A set of devices: every value of one physical parameter from ``lo`` to ``hi``
    (``LO..HI`` on the command line). A tuple or list is an array of values instead."""

    lo: float
    hi: float


class OneOf(tuple):
    """A finite set of devices: each of the values given, and none between them
    (``one-of:1,2,3`` on the command line), e.g. ``delay_samples=OneOf(1, 2, 3)`` for a
    product that ships with one of three delays. Beside :class:`Interval` (every value from
    ``lo`` to ``hi``); a plain tuple or list stays an array of values, one result each.
    The set is answered for every member: checking each is exhaustive.

    >>> r = alpha_max(mass=1.0, period=1.0, damping=0.5, delay_samples=OneOf(1, 2, 3))
    >>> r.binding, r.members_examined, r.alpha_verified == r.alpha_max
    (('delay = 3 samples',), 3, True)
    """

    def __new__(cls, *values: float) -> "OneOf":
        if not values:
            raise ValueError("OneOf takes at least one value, e.g. OneOf(1, 2, 3)")
        return super().__new__(cls, values)

    def __repr__(self) -> str:
        return f"OneOf({', '.join(repr(v) for v in self)})"


class RobustAmax(NamedTuple):
    """:func:`alpha_max` of a set of devices (``stabound amax`` with an interval, a finite
    set or a hand that can let go): the largest stiffness for which one damping is stable
    for every member, in the reference member's normalization (every interval at its low
    end, every list at its smallest value)."""

    #: The robust optimum, normalized on the reference member.
    alpha_max: float
    beta_at_max: float
    #: The stiffness shown stable for every member (``alpha_max`` when :attr:`verified`).
    alpha_verified: float
    #: ``K_max``, ``B`` and the verified stiffness in N/m and N s/m.
    stiffness: float
    wall_damping: float
    stiffness_verified: float
    #: With ``margin=F``: ``F * alpha_verified``, its damping and its stiffness in N/m.
    alpha_margin: Optional[float]
    beta_margin: Optional[float]
    stiffness_margin: Optional[float]
    #: How many members were examined.
    members_examined: int
    #: How the optimum was shown for the whole set, as ``stabound amax`` words it.
    verification: str
    #: Whether it holds over the whole set (else a ``UserWarning`` says so).
    verified: bool
    #: The members that bind the optimum.
    binding: tuple
    #: The set, as the reports describe it.
    set: tuple
    #: Where the sampling argument verified it: why the box proof stopped short (the cell
    #: budget spent, a member too close to the boundary to separate, or a parameter the
    #: proof does not cover), as the end of :attr:`verification` words it; else None.
    proof_stopped: Optional[str] = None


class SetCheck(NamedTuple):
    """:func:`check` of one wall on a set of devices (``stabound check`` with an interval)."""

    #: ``'stable'`` for every member, else the failing member's verdict (``'marginal'``
    #: when the sampling left it undecided).
    verdict: str
    #: Stable for every member.
    stable: bool
    #: How it was shown, as ``stabound check`` words it.
    verification: str
    #: A member the wall is not stable on, or None.
    failing_member: Optional[str]
    #: The set, as the reports describe it.
    set: tuple
    #: Where the sampling argument showed it: why the box proof stopped short, as the end
    #: of :attr:`verification` words it; else None.
    proof_stopped: Optional[str] = None


class Certified(NamedTuple):
    """:func:`certify`: a verdict proven in interval arithmetic, and its certificate."""

    #: One wall: ``'stable'``, ``'unstable'`` or ``'marginal'``; a box, or an interval of
    #: delays: ``'stable'`` or ``'unstable'`` for every wall or delay of it, or
    #: ``'not proved'``.
    verdict: str
    #: The certificate (JSON text, as ``stabound check --certify`` writes it).
    certificate: str
    #: A box's leaves, or an interval of delays' cells, ``(stable, unstable, undecided)``;
    #: None for one wall.
    leaves: Optional[tuple]


class CertifiedAmax(NamedTuple):
    """:func:`certify_alpha_max`: ``alpha_max`` and an enclosure of it proven in interval
    arithmetic, ``alpha_lo <= alpha_max < alpha_hi``, with its certificate. The numeric
    fields are floats for one row, and arrays of the grid's shape for a grid:
    ``(len(d), len(delta))``, or ``(len(delay), len(damping))`` for a device (an input
    given as one number adds no axis)."""

    #: The stiffest stable wall found (the robust one over a set of devices).
    alpha_max: Any
    #: The damping where it is reached.
    beta_at_max: Any
    #: The wall ``(alpha_lo, beta_at_max)`` is certified stable (for every member of a set).
    alpha_lo: Any
    #: No wall at ``alpha_hi`` or stiffer, with a damping of the range, is stable (where the
    #: budget did not prove that, only the walls at ``alpha_hi``; the checker says which).
    alpha_hi: Any
    #: The certificate (JSON text, as ``stabound amax ... --certify FILE`` writes it): one
    #: row's own, or one holding every row of a grid.
    certificate: str
    #: ``K_max`` in N/m (a device in physical units only), else None.
    stiffness: Optional[Any] = None
    #: ``B`` at ``K_max`` in N s/m (physical units only).
    wall_damping: Optional[Any] = None
    #: ``alpha_lo`` as a stiffness in N/m (physical units only).
    stiffness_lo: Optional[Any] = None
    #: ``alpha_hi`` as a stiffness in N/m (physical units only).
    stiffness_hi: Optional[Any] = None
    #: The devices each row proves: 1 for one loop, else the set's members.
    members: int = 1
    #: The set (of the first row of a grid), as the reports describe it; None for one loop.
    set: Optional[tuple] = None


class SetCertified(NamedTuple):
    """:func:`certify` over a finite set of devices (a loop element's values or a device
    value given as :class:`OneOf`): the verdict proven in interval arithmetic for every
    member, and its certificate (kind ``set``: one certificate per member)."""

    #: ``'stable'`` for every member (at every wall of the box), else the deciding member's:
    #: ``'unstable'`` (a member proved unstable fails the set), ``'marginal'`` or
    #: ``'not proved'``.
    verdict: str
    #: The certificate (JSON text, as ``stabound check ... one-of:LIST --certify`` writes it).
    certificate: str
    #: The number of members (every combination of the lists' values).
    members: int
    #: The member that decides the verdict, as the reports name it; None when stable.
    deciding_member: Optional[str]
    #: The set, as the reports describe it.
    set: tuple


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


class MemberBoundary(NamedTuple):
    """One member of a set of devices and its own stability boundary, in the set's reference
    normalization (``boundary(..., members=True)``: the curves ``stabound boundary --members``
    draws beside the robust region)."""

    #: The member, as the command line labels it (e.g. ``'delay = 3 samples'``).
    label: str
    boundary: Boundary


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
    #: With ``certify=``: the certificate (JSON text, as ``stabound table --conservative
    #: --certify FILE`` writes it); else None.
    certificate: Optional[str] = None
    #: With ``certify=``: the boxes proving the cells (over every member of a set).
    boxes: Optional[int] = None
    #: With ``certify=``, where no lowering proved some cells within ``certify_boxes``:
    #: ``(cells, largest budget)``, those cells' number and the most boxes a cell's budget
    #: grew to before its nodes were lowered; else None.
    grown: Optional[tuple] = None


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


class FigureText(NamedTuple):
    """A figure as ``stabound figure`` (or ``passivity --figures-dir``) writes its files."""

    #: The file name without extension, e.g. ``'fig05'`` or ``'fig08-d1'``.
    name: str
    #: The drawing (SVG text).
    svg: str
    #: The data (CSV text).
    csv: str


# the compiled functions' docstrings hold examples too: doctest finds them here
__test__ = {f.__name__: f.__doc__ for f in (
    alpha_max, analyze, boundary, buzz, check, figure, normalize, passivity, scene, scene_text, step, table,
)}
