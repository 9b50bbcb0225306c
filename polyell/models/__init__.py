"""Robot models: the dynamic quantities at a configuration, and arms that produce them."""

from polyell.models.dynamics import Dynamics
from polyell.models.planar_arm import PlanarArm
from polyell.models.torque_speed import TorqueSpeed
from polyell.models.urdf import Payload, UrdfRobot

__all__ = ["Dynamics", "Payload", "PlanarArm", "TorqueSpeed", "UrdfRobot"]
