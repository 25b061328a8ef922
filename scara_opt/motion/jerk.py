r"""A jerk-limited variant: Ruckig along the path parameter, under constant bounds on it.

The joint path :math:`q(s)`, :math:`s \in [0, 1]`, is the same spline as toppra's
(:mod:`scara_opt.motion.timing`). Bounds on :math:`\dot s` and :math:`\ddot s` that hold on the
whole run are derived from the limits (conservatively):

* :math:`V` = the smallest first-order bound over the grid (joint velocity, tool speed, yaw
  rate), lowered where the centripetal terms :math:`|q''| V^2` or :math:`|p''| V^2` would
  take more than half of the joint or tool acceleration;
* :math:`U` = the smallest :math:`(a_{max} - |q''| V^2) / |q'|` (and the same for the tool),
  so :math:`|q' \ddot s + q'' \dot s^2| \le a_{max}` for any :math:`|\ddot s| \le U`;
* path jerk :math:`J = 10/s \times U` (the toolkit's default jerk ratio).

Ruckig times :math:`s: 0 \to 1` rest to rest under (V, U, J); :math:`q(s(t))` is then written
exactly as degree-9 polynomials between the breakpoints of :math:`s(t)` and the times it
crosses the spline's knots. Slower than toppra (constant bounds, jerk-limited), smooth in
acceleration. Its limit ratios are checked like toppra's (exact joints, 1 kHz tool).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.model.robot import Robot
from scara_opt.motion.timing import _factor
from scara_opt.motion.tool_limits import ToolProfile, path_derivatives
from scara_opt.trajectory.limits import JERK_PER_ACCELERATION, Limits, resolve_limits
from scara_opt.trajectory.passing import bounds_grid, check_bounds, compose, path_bounds
from scara_opt.trajectory.registry import time_parameterize
from scara_opt.trajectory.spline import geometric_path
from scara_opt.trajectory.toppra_backend import chord_parameter
from scara_opt.trajectory.trajectory import Trajectory, stretch

Array = NDArray[np.float64]


def _bounds(robot: Robot, path: Any, s: Array, limits: Limits,
            tool: ToolProfile) -> tuple[float, float]:
    """The joints' bounds (:func:`~scara_opt.trajectory.passing.path_bounds`), then the tool's."""
    grid = bounds_grid(s)
    dp, ddp, dyaw = path_derivatives(robot, path, grid)
    sp, spp = np.linalg.norm(dp, axis=1), np.linalg.norm(ddp, axis=1)
    with np.errstate(divide="ignore"):
        cap = float(np.min(tool.at("speed", grid, s) / sp))
        if dyaw is not None:
            cap = min(cap, float(np.min(tool.at("yaw_rate", grid, s) / np.abs(dyaw))))
        acc = tool.at("acceleration", grid, s)
        if np.isfinite(acc).any():
            cap = min(cap, float(np.min(np.sqrt(0.5 * acc / spp))))
        V, U, _, _ = path_bounds(path, s, limits, cap)
        if np.isfinite(acc).any():
            U = min(U, float(np.min((acc - spp * V**2) / sp)))
    check_bounds(V, U, "the jerk-limited variant")
    return V, U


def jerk_limited_section(robot: Robot, Q: Array, limits: Limits,
                         tool: ToolProfile) -> tuple[tuple[PPoly, ...], str, Array]:
    """Like :func:`~scara_opt.motion.timing.time_section`, jerk-limited along the path."""
    s = chord_parameter(Q, limits.vmax)
    path = geometric_path(s, Q)
    V, U = _bounds(robot, path, s, limits, tool)
    one = resolve_limits(None, 1, V, U, JERK_PER_ACCELERATION * U, need_jerk=True)
    ps = time_parameterize([[0.0], [1.0]], None, method="ruckig", vmax=one.vmax,
                           amax=one.amax, jmax=one.jmax).pieces[0]
    pieces, knots = compose(path.cspl, ps, s)
    traj = Trajectory(pieces, limits, "ruckig", Q, knots)
    factor = _factor(robot, traj, tool, knots)
    note = f"ruckig along s: |s'| <= {V:.4g}/s, |s''| <= {U:.4g}/s², |s'''| <= {10 * U:.4g}/s³"
    if factor > 1.0:  # the bounds hold on the sampled grid; between, a hair above
        factor *= 1.0 + 1e-6
        pieces = tuple(stretch(p, factor) for p in pieces)
        knots = knots * factor
        note += f", time stretched x {factor:.6f} (bounds sampled on a grid)"
    return pieces, note, knots
