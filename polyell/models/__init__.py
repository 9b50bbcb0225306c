"""Robot models: the dynamic quantities at a configuration, and arms that produce them."""

from polyell.models.dynamics import Dynamics
from polyell.models.planar_arm import PlanarArm

__all__ = ["Dynamics", "PlanarArm"]
