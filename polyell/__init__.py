"""polyell: exact acceleration polytopes and dynamic manipulability ellipsoids.

Implements P. Chiacchio, "A new dynamic manipulability ellipsoid for redundant
manipulators", Robotica 18 (2000), and compares both ellipsoid definitions with the
exact task-space acceleration polytope.
"""

from polyell import robots
from polyell.analysis import ELLIPSOID_KINDS, Analysis, InverseSolution, analyze
from polyell.comparison import (
    COMPARED_KINDS,
    SCORE_NAMES,
    Candidate,
    Comparison,
    Scores,
    TableLayout,
    compare,
    limits_table,
)
from polyell.errors import (
    InputError,
    MissingDependencyError,
    PolyellError,
    ProjectedInputWarning,
    SolverError,
    StorageError,
    UndefinedEllipsoidError,
    UnreachableAccelerationError,
)
from polyell.geometry import (
    AFFINE_RTOL,
    RANK_RTOL,
    AffineSubspace,
    DirectionalLimits,
    Ellipsoid,
    Polytope,
)
from polyell.models import Dynamics, Payload, PlanarArm, UrdfRobot
from polyell.studies import grid, limits_along, local_cluster, random_configurations, sweep

__version__ = "0.1.0"

__all__ = [
    "AFFINE_RTOL",
    "COMPARED_KINDS",
    "ELLIPSOID_KINDS",
    "RANK_RTOL",
    "SCORE_NAMES",
    "AffineSubspace",
    "Analysis",
    "Candidate",
    "Comparison",
    "DirectionalLimits",
    "Dynamics",
    "Ellipsoid",
    "InputError",
    "InverseSolution",
    "MissingDependencyError",
    "Payload",
    "PlanarArm",
    "PolyellError",
    "Polytope",
    "ProjectedInputWarning",
    "Scores",
    "SolverError",
    "StorageError",
    "TableLayout",
    "UndefinedEllipsoidError",
    "UnreachableAccelerationError",
    "UrdfRobot",
    "__version__",
    "analyze",
    "compare",
    "grid",
    "limits_along",
    "limits_table",
    "local_cluster",
    "random_configurations",
    "robots",
    "sweep",
]
