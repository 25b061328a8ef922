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

import math

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.model.robot import Robot
from scara_opt.motion.timing import _factor
from scara_opt.motion.tool_limits import UNLIMITED, ToolProfile, path_derivatives
from scara_opt.trajectory.limits import JERK_PER_ACCELERATION, Limits, resolve_limits
from scara_opt.trajectory.registry import time_parameterize
from scara_opt.trajectory.toppra_backend import chord_parameter
from scara_opt.trajectory.trajectory import Trajectory, stretch

Array = NDArray[np.float64]

#: grid points per waypoint interval at which the bounds are evaluated (at least 200 in all)
SAMPLES = 4


def _bounds(robot: Robot, path, s: Array, limits: Limits, tool: ToolProfile) -> tuple[float, float]:
    n = max(SAMPLES * (len(s) - 1), 200)
    grid = np.linspace(0.0, 1.0, n + 1)
    dq, ddq = np.abs(path(grid, 1)), np.abs(path(grid, 2))
    dp, ddp, dyaw = path_derivatives(robot, path, grid)
    sp, spp = np.linalg.norm(dp, axis=1), np.linalg.norm(ddp, axis=1)
    with np.errstate(divide="ignore"):
        V = float(np.min(limits.vmax / dq))
        V = min(V, float(np.min(tool.at("speed", grid, s) / sp)))
        if dyaw is not None:
            V = min(V, float(np.min(tool.at("yaw_rate", grid, s) / np.abs(dyaw))))
        V = min(V, float(np.min(np.sqrt(0.5 * limits.amax / ddq))))
        acc = tool.at("acceleration", grid, s)
        if (acc < UNLIMITED).any():
            V = min(V, float(np.min(np.sqrt(0.5 * acc / spp))))
        U = float(np.min((limits.amax - ddq * V**2) / dq))
        if (acc < UNLIMITED).any():
            U = min(U, float(np.min((acc - spp * V**2) / sp)))
    if not (math.isfinite(V) and math.isfinite(U) and V > 0 and U > 0):
        raise TrajectoryError("the jerk-limited variant found no positive bound on the path "
                              "speed or acceleration for this run; use method='toppra'")
    return V, U


def _compose(spline, ps: PPoly, knots: Array) -> tuple[tuple[PPoly, ...], Array]:
    """``q(s(t))`` exactly, as degree-9 PPolys; and the times ``s(t)`` reaches each knot."""
    hits = [0.0] + [float(ps.solve(k, extrapolate=False)[0]) for k in knots[1:-1]]
    hits.append(float(ps.x[-1]))
    br = np.unique(np.concatenate([ps.x, hits]))
    br = br[np.concatenate([[True], np.diff(br) > 1e-12])]
    nodes = (1 - np.cos(np.pi * (np.arange(10) + 0.5) / 10)) / 2  # Chebyshev on [0, 1]
    h = np.diff(br)
    tau = h[:, None] * nodes[None, :]  # (m, 10) local times
    sv = np.clip(ps(br[:-1, None] + tau), 0.0, 1.0)
    Qv = spline(sv.ravel()).reshape(len(h), 10, -1)  # (m, 10, nq)
    V = np.vander(nodes, 10)  # fit in the unit variable, then rescale to time
    coef = np.linalg.solve(V[None], Qv)  # (m, 10, nq), highest power first
    coef = coef / (h[:, None, None] ** np.arange(9, -1, -1)[None, :, None])
    pieces = tuple(PPoly(coef[:, :, k].T, br, extrapolate=False) for k in range(Qv.shape[2]))
    return pieces, np.array(hits)


def jerk_limited_section(robot: Robot, Q: Array, limits: Limits,
                         tool: ToolProfile) -> tuple[tuple[PPoly, ...], str, Array]:
    """Like :func:`~scara_opt.motion.timing.time_section`, jerk-limited along the path."""
    import toppra

    s = chord_parameter(Q, limits.vmax)
    path = toppra.SplineInterpolator(s, Q)
    V, U = _bounds(robot, path, s, limits, tool)
    one = resolve_limits(None, 1, V, U, JERK_PER_ACCELERATION * U, need_jerk=True)
    ps = time_parameterize([[0.0], [1.0]], None, method="ruckig", vmax=one.vmax,
                           amax=one.amax, jmax=one.jmax).pieces[0]
    pieces, knots = _compose(path.cspl, ps, s)
    traj = Trajectory(pieces, limits, "ruckig", Q, knots)
    factor = _factor(robot, traj, tool, knots)
    note = f"ruckig along s: |s'| <= {V:.4g}/s, |s''| <= {U:.4g}/s², |s'''| <= {10 * U:.4g}/s³"
    if factor > 1.0:  # the bounds hold on the sampled grid; between, a hair above
        factor *= 1.0 + 1e-6
        pieces = tuple(stretch(p, factor) for p in pieces)
        knots = knots * factor
        note += f", time stretched x {factor:.6f} (bounds sampled on a grid)"
    return pieces, note, knots
