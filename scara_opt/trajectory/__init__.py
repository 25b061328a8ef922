"""Joint paths from Cartesian paths, and their timing within joint limits.

Two steps, one direction: :func:`ik_path` turns targets into a branch-continuous
:class:`JointPath` (every point's status and residual, every jump reported), and
:func:`time_parameterize` times a joint path into a :class:`Trajectory` with one of the
registered methods:

- ``"toppra"``: time-optimal along a cubic spline through the waypoints (TOPP-RA;
  velocity and acceleration limits, with a documented safety margin);
- ``"ruckig"``: jerk-limited; rest to rest between two waypoints, moving through more
  (the community Ruckig has no intermediate waypoints: segments joined at velocities
  chosen from the path, or Ruckig along the path parameter, :mod:`.passing`);
- ``"quintic"``: rest-to-rest quintic per segment, for a given duration or the shortest
  within the limits (fang's Tables 2–3).

Every :class:`Trajectory` is a piecewise polynomial per joint; ``check_limits()`` gives the
exact largest ratio of |qd| / vmax and |qdd| / amax per joint. Limits default to the
robot's and are overridden per joint (``vmax``, ``amax``, ``jmax``); units are SI
[rad, m, s].

Torque limits (``"toppra"``): ``torque_limits=`` [N·m, N] and ``payload=`` add toppra's
joint-torque constraint from Pinocchio's inverse dynamics (:mod:`.dynamics`, gravity
included); ``check_limits()["torque"]`` is then the worst |τ| / τmax sampled at 1 kHz.
"""

from scara_opt.trajectory.dynamics import Payload, RobotDynamics
from scara_opt.trajectory.limits import JERK_PER_ACCELERATION, Limits, resolve_limits
from scara_opt.trajectory.path import JointPath, Jump, find_jumps, ik_path
from scara_opt.trajectory.quintic import quintic_blend, shortest_duration
from scara_opt.trajectory.registry import (
    get_timing,
    register_timing,
    ruckig_point_to_point,
    time_parameterize,
    timing_methods,
)
from scara_opt.trajectory.trajectory import Trajectory

__all__ = [
    "JERK_PER_ACCELERATION",
    "JointPath",
    "Jump",
    "Limits",
    "Payload",
    "RobotDynamics",
    "Trajectory",
    "find_jumps",
    "get_timing",
    "ik_path",
    "quintic_blend",
    "register_timing",
    "resolve_limits",
    "ruckig_point_to_point",
    "shortest_duration",
    "time_parameterize",
    "timing_methods",
]
