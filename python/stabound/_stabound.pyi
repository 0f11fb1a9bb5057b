"""The compiled core (private): the functions of the stabound package, which documents them."""

from stabound import StaboundError as StaboundError
from stabound import alpha_max as alpha_max
from stabound import analyze as analyze
from stabound import boundary as boundary
from stabound import buzz as buzz
from stabound import certify as certify
from stabound import certify_alpha_max as certify_alpha_max
from stabound import check as check
from stabound import figure as figure
from stabound import normalize as normalize
from stabound import passivity as passivity
from stabound import scene as scene
from stabound import scene_text as scene_text
from stabound import step as step
from stabound import table as table

METHODS: list[str]
ELEMENT_KEYWORDS: list[str]
NONLINEAR_KEYWORDS: list[str]
VERDICTS: list[str]
PIECES: list[str]
DEFAULT_MARGIN: float
DEFAULT_AMAX_TOL: float
DEFAULT_BOUNDARY_TOL: float
DEFAULT_COLUMNS: int
__version__: str
__all__ = [
    "StaboundError",
    "alpha_max",
    "table",
    "boundary",
    "buzz",
    "certify",
    "certify_alpha_max",
    "passivity",
    "analyze",
    "check",
    "normalize",
    "figure",
    "scene",
    "scene_text",
    "step",
    "METHODS",
    "ELEMENT_KEYWORDS",
    "NONLINEAR_KEYWORDS",
    "VERDICTS",
    "PIECES",
    "DEFAULT_MARGIN",
    "DEFAULT_AMAX_TOL",
    "DEFAULT_BOUNDARY_TOL",
    "DEFAULT_COLUMNS",
    "__version__",
]
