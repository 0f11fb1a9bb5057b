"""Type stubs of the stabound package (see the docstrings in __init__.py)."""

import os
from dataclasses import dataclass
from typing import Any, NamedTuple, Optional, Sequence, TypedDict, Union, overload

from typing_extensions import Unpack, disjoint_base

import numpy as np
import numpy.typing as npt

__version__: str
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

METHODS: tuple[str, ...]
VERDICTS: tuple[str, ...]
PIECES: tuple[str, ...]
DEFAULT_MARGINAL_BAND: float
DEFAULT_THETA_TOL: float
DEFAULT_MARGIN: float
DEFAULT_AMAX_TOL: float
DEFAULT_BOUNDARY_TOL: float
DEFAULT_COLUMNS: int

_Array = npt.ArrayLike
_F = Union[float, npt.NDArray[np.float64]]

class StaboundError(RuntimeError): ...

class Interval(NamedTuple):
    """A set of devices: every value of one physical parameter from lo to hi."""

    lo: float
    hi: float

# a tuple subclass with its own __new__: no class derives from it and another base at once
@disjoint_base
class OneOf(tuple[float, ...]):
    """A finite set of devices: each of the values given, none between them."""

    def __new__(cls, *values: float) -> OneOf: ...

class RobustAmax(NamedTuple):
    alpha_max: float
    beta_at_max: float
    alpha_verified: float
    stiffness: float
    wall_damping: float
    stiffness_verified: float
    alpha_margin: Optional[float]
    beta_margin: Optional[float]
    stiffness_margin: Optional[float]
    members_examined: int
    verification: str
    verified: bool
    binding: tuple[str, ...]
    set: tuple[str, ...]
    proof_stopped: Optional[str] = ...

class SetCheck(NamedTuple):
    verdict: str
    stable: bool
    verification: str
    failing_member: Optional[str]
    set: tuple[str, ...]
    proof_stopped: Optional[str] = ...

#: A number, or an interval or a finite set of a set of devices.
_Spread = Union[float, Interval, OneOf]

class _LoopElements(TypedDict, total=False):
    """The loop elements, in physical units on one device (the keywords of check, alpha_max,
    boundary, table and step; an Interval or a OneOf of a number makes a set of devices for check,
    alpha_max, table and boundary)."""

    hand_mass: Optional[_Spread]
    hand_damping: Optional[_Spread]
    hand_stiffness: Optional[_Spread]
    handle_mass: Optional[_Spread]
    transmission_stiffness: Optional[_Spread]
    transmission_damping: Optional[_Spread]
    motor_damping: Optional[_Spread]
    handle_damping: Optional[_Spread]
    encoder: Optional[str]
    actuator_time_constant: Optional[_Spread]
    velocity_filter_cutoff: Optional[_Spread]
    velocity_filter_samples: Optional[int]
    velocity_filter_order: Optional[int]

class _Buzz(_LoopElements, total=False):
    """The loop elements and the quantizers and friction (the keywords of buzz)."""

    encoder_resolution: Optional[float]
    force_resolution: Optional[float]
    coulomb_friction: Optional[float]
    static_friction: Optional[float]

def buzz(
    *,
    mass: float,
    period: float,
    damping: float,
    stiffness: float,
    wall_damping: Optional[float] = ...,
    delay: Optional[float] = ...,
    delay_samples: Optional[float] = ...,
    **elements: Unpack[_Buzz],
) -> dict[str, Any]: ...

class CheckResult(NamedTuple):
    spectral_radius: Union[float, npt.NDArray[np.float64]]
    verdict: Union[str, npt.NDArray[np.str_]]
    code: Union[int, npt.NDArray[np.int8]]
    stable: Union[bool, npt.NDArray[np.bool_]]
    method: Union[str, npt.NDArray[np.str_]]

class Certified(NamedTuple):
    verdict: str
    certificate: str
    leaves: Optional[tuple[int, int, int]]

class CertifiedAmax(NamedTuple):
    alpha_max: _F
    beta_at_max: _F
    alpha_lo: _F
    alpha_hi: _F
    certificate: str
    stiffness: Optional[_F] = ...
    wall_damping: Optional[_F] = ...
    stiffness_lo: Optional[_F] = ...
    stiffness_hi: Optional[_F] = ...
    members: int = ...
    set: Optional[tuple[str, ...]] = ...

class SetCertified(NamedTuple):
    verdict: str
    certificate: str
    members: int
    deciding_member: Optional[str]
    set: tuple[str, ...]

class Amax(NamedTuple):
    alpha_max: _F
    beta_at_max: _F

class AmaxPhysical(NamedTuple):
    alpha_max: _F
    beta_at_max: _F
    stiffness: _F
    wall_damping: _F

class AmaxMargin(NamedTuple):
    alpha_max: _F
    beta_at_max: _F
    alpha_margin: _F
    beta_margin: _F

class AmaxPhysicalMargin(NamedTuple):
    alpha_max: _F
    beta_at_max: _F
    stiffness: _F
    wall_damping: _F
    alpha_margin: _F
    beta_margin: _F
    stiffness_margin: _F

class Witness(NamedTuple):
    alpha: float
    beta: float
    delta: float
    margin: float
    verdict: str

@dataclass(frozen=True)
class Passivity:
    plane: str
    at: float
    d: float
    filter: str
    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    theta: npt.NDArray[np.float64]
    edge: npt.NDArray[np.str_]
    tol: float
    stable_x: Optional[npt.NDArray[np.float64]]
    stable_y: Optional[npt.NDArray[np.float64]]
    stable_points: Optional[str]
    alpha_max_passive: Optional[float]
    beta_at_max: Optional[float]
    alpha_max_at_beta: Optional[float]
    inside: Optional[bool]
    passive_area: Optional[float]
    stable_area: Optional[float]
    passive_share_of_stable: Optional[float]
    stable_share_of_passive: Optional[float]
    passive_share_error: Optional[float]
    passive_share_bound: Optional[float]
    stable_method: Optional[str]
    passive_unstable: Optional[Witness]
    stable_not_passive: Optional[Witness]
    stiffness_max: Optional[float] = ...
    wall_damping_at_max: Optional[float] = ...

def passivity(
    delta: Optional[float] = ...,
    d: Optional[float] = ...,
    *,
    plane: str = ...,
    alpha: Optional[float] = ...,
    beta: Optional[float] = ...,
    filter_pole: Optional[float] = ...,
    velocity_filter_cutoff: Optional[float] = ...,
    velocity_filter_order: Optional[int] = ...,
    velocity_filter_samples: Optional[int] = ...,
    mass: Optional[float] = ...,
    period: Optional[float] = ...,
    damping: Optional[float] = ...,
    delay: Optional[float] = ...,
    delay_samples: Optional[float] = ...,
    stiffness: Optional[float] = ...,
    wall_damping: Optional[float] = ...,
    tol: Optional[float] = ...,
    columns: Optional[int] = ...,
) -> Passivity: ...

class Boundary(NamedTuple):
    delta: float
    d: float
    alpha: npt.NDArray[np.float64]
    beta: npt.NDArray[np.float64]
    piece: npt.NDArray[np.str_]
    piece_code: npt.NDArray[np.int8]

@dataclass(frozen=True)
class LookupTable:
    delta: npt.NDArray[np.float64]
    d: npt.NDArray[np.float64]
    alpha_max: npt.NDArray[np.float64]
    beta_at_max: npt.NDArray[np.float64]
    stiffness: Optional[npt.NDArray[np.float64]]
    wall_damping: Optional[npt.NDArray[np.float64]]
    csv: str
    json: str
    c_header: str
    rust: str
    certificate: Optional[str] = ...
    boxes: Optional[int] = ...
    grown: Optional[tuple[int, int]] = ...

@dataclass(frozen=True)
class StepResponse:
    damping: float
    stiffness: float
    wall_damping: float
    alpha: float
    beta: float
    delta: float
    d: float
    verdict: str
    final_value: Optional[float]
    peak: float
    settling_time: Optional[float]
    time: npt.NDArray[np.float64]
    position: npt.NDArray[np.float64]
    samples: npt.NDArray[np.float64]
    elements: tuple[str, ...] = ...

def normalize(
    *,
    mass: _Array,
    period: _Array,
    damping: _Array,
    delay: Optional[_Array] = ...,
    delay_samples: Optional[_Array] = ...,
    stiffness: Optional[_Array] = ...,
    wall_damping: Optional[_Array] = ...,
) -> tuple[_F, ...]: ...
def check(
    alpha: Optional[_Array] = ...,
    beta: Optional[_Array] = ...,
    delta: Optional[_Array] = ...,
    d: Optional[_Array] = ...,
    *,
    method: str = ...,
    marginal_band: Optional[float] = ...,
    radius: bool = ...,
    mass: Optional[Union[_Array, Interval, OneOf]] = ...,
    period: Optional[_Array] = ...,
    damping: Optional[Union[_Array, Interval, OneOf]] = ...,
    stiffness: Optional[_Array] = ...,
    wall_damping: Optional[_Array] = ...,
    delay: Optional[Union[_Array, Interval, OneOf]] = ...,
    delay_samples: Optional[Union[_Array, Interval, OneOf]] = ...,
    margin: Optional[float] = ...,
    **elements: Unpack[_LoopElements],
) -> Union[CheckResult, SetCheck]: ...
def certify(
    alpha: Optional[Union[float, Interval]] = ...,
    beta: Optional[Union[float, Interval]] = ...,
    delta: Optional[float] = ...,
    d: Optional[float] = ...,
    *,
    marginal_band: Optional[float] = ...,
    leaves: Optional[int] = ...,
    path: Optional[Union[str, os.PathLike[str]]] = ...,
    mass: Optional[Union[float, OneOf]] = ...,
    period: Optional[float] = ...,
    damping: Optional[Union[float, OneOf]] = ...,
    stiffness: Optional[Union[float, Interval]] = ...,
    wall_damping: Optional[Union[float, Interval]] = ...,
    delay: Optional[Union[float, OneOf]] = ...,
    delay_samples: Optional[Union[float, Interval, OneOf]] = ...,
    **elements: Unpack[_LoopElements],
) -> Union[Certified, SetCertified]: ...
def certify_alpha_max(
    delta: Optional[_Array] = ...,
    d: Optional[_Array] = ...,
    *,
    beta_min: Optional[float] = ...,
    beta_max: Optional[float] = ...,
    wall_damping_min: Optional[float] = ...,
    wall_damping_max: Optional[float] = ...,
    theta_tol: Optional[float] = ...,
    mass: Optional[Union[float, OneOf]] = ...,
    period: Optional[float] = ...,
    damping: Optional[Union[_Array, OneOf]] = ...,
    delay: Optional[Union[_Array, OneOf]] = ...,
    delay_samples: Optional[Union[_Array, OneOf]] = ...,
    always_gripped: bool = ...,
    path: Optional[Union[str, os.PathLike[str]]] = ...,
    **elements: Unpack[_LoopElements],
) -> CertifiedAmax: ...
def analyze(
    alpha: Optional[float] = ...,
    beta: Optional[float] = ...,
    delta: Optional[float] = ...,
    d: Optional[float] = ...,
    *,
    method: str = ...,
    marginal_band: Optional[float] = ...,
    mass: Optional[float] = ...,
    period: Optional[float] = ...,
    damping: Optional[float] = ...,
    stiffness: Optional[float] = ...,
    wall_damping: Optional[float] = ...,
    delay: Optional[float] = ...,
    delay_samples: Optional[float] = ...,
    margin: Optional[float] = ...,
) -> dict[str, Any]: ...
def alpha_max(
    delta: Optional[_Array] = ...,
    d: Optional[_Array] = ...,
    *,
    beta_min: Optional[float] = ...,
    beta_max: Optional[float] = ...,
    theta_tol: Optional[float] = ...,
    margin: Optional[float] = ...,
    mass: Optional[Union[_Array, Interval, OneOf]] = ...,
    period: Optional[_Array] = ...,
    damping: Optional[Union[_Array, Interval, OneOf]] = ...,
    delay: Optional[Union[_Array, Interval, OneOf]] = ...,
    delay_samples: Optional[Union[_Array, Interval, OneOf]] = ...,
    tol: Optional[float] = ...,
    wall_damping_min: Optional[float] = ...,
    wall_damping_max: Optional[float] = ...,
    always_gripped: bool = ...,
    **elements: Unpack[_LoopElements],
) -> Union[Amax, AmaxPhysical, AmaxMargin, AmaxPhysicalMargin, RobustAmax]: ...
class DeltaBetaBoundary(NamedTuple):
    alpha: float
    d: float
    delta: npt.NDArray[np.float64]
    beta: npt.NDArray[np.float64]
    loop: npt.NDArray[np.int64]
    piece: npt.NDArray[np.str_]

class MemberBoundary(NamedTuple):
    label: str
    boundary: Boundary

def boundary(
    delta: Optional[_Array] = ...,
    d: Optional[_Array] = ...,
    *,
    tol: Optional[float] = ...,
    method: Optional[str] = ...,
    plane: str = ...,
    alpha: Optional[_Array] = ...,
    mass: Optional[Union[float, Interval]] = ...,
    period: Optional[float] = ...,
    damping: Optional[Union[float, Interval]] = ...,
    delay: Optional[Union[float, Interval]] = ...,
    delay_samples: Optional[Union[float, Interval]] = ...,
    members: bool = ...,
    always_gripped: bool = ...,
    **elements: Unpack[_LoopElements],
) -> Union[
    Boundary,
    list[Boundary],
    DeltaBetaBoundary,
    list[DeltaBetaBoundary],
    tuple[Boundary, list[MemberBoundary]],
]: ...
def table(
    delta: Optional[Sequence[float]] = ...,
    d: Optional[Sequence[float]] = ...,
    *,
    conservative: bool = ...,
    beta_min: Optional[float] = ...,
    beta_max: Optional[float] = ...,
    theta_tol: Optional[float] = ...,
    mass: Optional[_Spread] = ...,
    period: Optional[float] = ...,
    damping: Optional[Union[_Array, Interval, OneOf]] = ...,
    delay: Optional[Union[_Array, Interval, OneOf]] = ...,
    delay_samples: Optional[Union[_Array, Interval, OneOf]] = ...,
    tol: Optional[float] = ...,
    always_gripped: bool = ...,
    certify: Union[bool, str, os.PathLike[str], None] = ...,
    certify_boxes: Optional[int] = ...,
    **elements: Unpack[_LoopElements],
) -> LookupTable: ...
def scene(
    source: Union[str, os.PathLike[str], dict[str, Any]],
    *,
    marginal_band: Optional[float] = ...,
    margin: Optional[float] = ...,
) -> dict[str, Any]: ...
def scene_text(
    source: Union[str, os.PathLike[str], dict[str, Any]],
    *,
    marginal_band: Optional[float] = ...,
    margin: Optional[float] = ...,
) -> str: ...
@overload
def step(
    *,
    mass: float,
    period: float,
    damping: float,
    delay: Optional[float] = ...,
    delay_samples: Optional[float] = ...,
    stiffness: Optional[float] = ...,
    wall_damping: Optional[float] = ...,
    margin: Optional[float] = ...,
    force: Optional[float] = ...,
    duration: Optional[float] = ...,
    points_per_period: Optional[int] = ...,
    settling_band: Optional[float] = ...,
    **elements: Unpack[_LoopElements],
) -> StepResponse: ...
@overload
def step(
    *,
    mass: float,
    period: float,
    damping: Sequence[float],
    delay: Optional[float] = ...,
    delay_samples: Optional[float] = ...,
    stiffness: Optional[float] = ...,
    wall_damping: Optional[float] = ...,
    margin: Optional[float] = ...,
    force: Optional[float] = ...,
    duration: Optional[float] = ...,
    points_per_period: Optional[int] = ...,
    settling_band: Optional[float] = ...,
    **elements: Unpack[_LoopElements],
) -> list[StepResponse]: ...
class FigureText(NamedTuple):
    name: str
    svg: str
    csv: str

def figure(which: Union[int, str]) -> FigureText: ...
