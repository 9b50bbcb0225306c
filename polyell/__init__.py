"""polyell: exact capacity polytopes of robot arms and the manipulability ellipsoids.

Implements P. Chiacchio, "A new dynamic manipulability ellipsoid for redundant
manipulators", Robotica 18 (2000), and compares both ellipsoid definitions with the
exact task-space acceleration polytope; the velocity and static force capacities are
compared the same way.
"""

from polyell import robots
from polyell.capacities import CAPACITIES, ELLIPSOID_KINDS, Analysis, InverseSolution, analyze
from polyell.comparison import (
    COMPARED_KINDS,
    SCORE_NAMES,
    Candidate,
    Comparison,
    Scores,
    SetComparison,
    SetScores,
    TableLayout,
    compare,
    limits_table,
)
from polyell.comparison.long_form import to_long, to_wide
from polyell.errors import (
    DeratingWarning,
    InputError,
    JointLimitWarning,
    MissingDependencyError,
    PolyellError,
    PolyellWarning,
    ProjectedInputWarning,
    SolverError,
    StorageError,
    TableWidthWarning,
    UndefinedEllipsoidError,
    UnreachableAccelerationError,
)
from polyell.geometry import (
    AFFINE_RTOL,
    RANK_RTOL,
    AffineSubspace,
    DirectionalLimits,
    Ellipsoid,
    HPolytope,
    Polytope,
)
from polyell.models import Dynamics, Payload, PlanarArm, TorqueSpeed, UrdfRobot
from polyell.models.kinematics import Kinematics
from polyell.models.self_motion import SelfMotion, self_motion
from polyell.studies import grid, limits_along, local_cluster, random_configurations, sweep
from polyell.studies.posture import PostureChoice, posture_choice
from polyell.studies.posture_tables import write_posture_tables
from polyell.studies.posture_targets import PostureChoiceOverTargets, posture_choice_over_targets

__version__ = "0.1.0"

__all__ = [
    "AFFINE_RTOL",
    "CAPACITIES",
    "COMPARED_KINDS",
    "ELLIPSOID_KINDS",
    "RANK_RTOL",
    "SCORE_NAMES",
    "AffineSubspace",
    "Analysis",
    "Candidate",
    "Comparison",
    "DeratingWarning",
    "DirectionalLimits",
    "Dynamics",
    "Ellipsoid",
    "HPolytope",
    "InputError",
    "InverseSolution",
    "JointLimitWarning",
    "Kinematics",
    "MissingDependencyError",
    "Payload",
    "PlanarArm",
    "PolyellError",
    "PolyellWarning",
    "Polytope",
    "PostureChoice",
    "PostureChoiceOverTargets",
    "ProjectedInputWarning",
    "Scores",
    "SelfMotion",
    "SetComparison",
    "SetScores",
    "SolverError",
    "StorageError",
    "TableLayout",
    "TableWidthWarning",
    "TorqueSpeed",
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
    "posture_choice",
    "posture_choice_over_targets",
    "random_configurations",
    "robots",
    "self_motion",
    "sweep",
    "to_long",
    "to_wide",
    "write_posture_tables",
]
