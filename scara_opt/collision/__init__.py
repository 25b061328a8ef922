"""Collision geometry and cells: which configurations and motions are clear of obstacles.

* :mod:`~scara_opt.collision.geometry`: the robot's collision bodies (URDF ``<collision>``,
  or capsules from a robot file's ``radius`` keys) and its self-collision pairs;
* :mod:`~scara_opt.collision.obstacles`, :mod:`~scara_opt.collision.cell`: the obstacles of
  a cell (box, cylinder, capsule, sphere, mesh) from Python or a TOML cell file;
* :mod:`~scara_opt.collision.checker`: :class:`CollisionChecker`, ``collides(q)``,
  ``clearance(q)`` and their batch forms (Pinocchio + coal);
* :mod:`~scara_opt.collision.continuous`: motions proven clear, not sampled: between two
  checked configurations, a bound on how far any point of the robot moves must stay below
  the clearance measured at them, or the interval is split.
"""

from scara_opt.collision.cell import Cell, load_cell
from scara_opt.collision.checker import Clearance, CollisionChecker
from scara_opt.collision.geometry import RobotGeometry, robot_geometry
from scara_opt.collision.obstacles import Box, Capsule, Cylinder, Mesh, Obstacle, Sphere

__all__ = ["Box", "Capsule", "Cell", "Clearance", "CollisionChecker", "Cylinder", "Mesh",
           "Obstacle", "RobotGeometry", "Sphere", "load_cell", "robot_geometry"]
