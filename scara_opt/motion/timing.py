"""Time one stop-to-stop section of a program with TOPP-RA: joint and tool limits together.

The joint path is toppra's cubic spline through the section's joint waypoints (chord
parameter, as in :mod:`scara_opt.trajectory.toppra_backend`); the constraints are the joint
velocity and acceleration limits and the tool limits of :mod:`scara_opt.motion.tool_limits`,
all scaled by ``1 - margin``. The result is then checked as the user would check it: joint
ratios exactly (:meth:`~scara_opt.Trajectory.check_limits`), tool ratios by FK finite
differences at :data:`CHECK_DT`. Any ratio still above 1 is removed by stretching time
uniformly (speed / f, acceleration / f²) and said in the notes: nothing is exceeded silently.
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.model.robot import Robot
from scara_opt.motion.tool_limits import (
    ToolProfile,
    acceleration_constraint,
    speed_constraint,
    tool_peaks,
)
from scara_opt.trajectory.dynamics import RobotDynamics
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.spline import geometric_path
from scara_opt.trajectory.toppra_backend import chord_parameter, solve_on_grid
from scara_opt.trajectory.trajectory import Trajectory, stretch

if TYPE_CHECKING:
    from toppra import SplineInterpolator  # untyped: Any to mypy

Array = NDArray[np.float64]

#: what to do when toppra fails on a section, or stalls on a grid interval
FAILED = "check the limits and the path"
STALLED = "a limit is so low the motion never ends; raise it"

#: sampling step of the independent tool-limit check [s] (1 kHz)
CHECK_DT = 1e-3

#: toppra limits are scaled by 1 - MARGIN (the grid enforces them at grid points only)
MARGIN = 0.005

#: largest time stretch applied silently to remove discretisation overshoot (else an error)
MAX_STRETCH = 1.05

#: grid doublings tried while a ratio (joints exact, tool at 1 kHz) exceeds 1 by more than MARGIN
REFINE = 2

#: at least this many grid intervals per section
MIN_GRID = 100


def tool_ratios(robot: Robot, traj: Trajectory, tool: ToolProfile, knots: Array,
                dt: float = CHECK_DT) -> dict[str, float]:
    """Worst ratio of the tip's speed, acceleration, yaw rate to the limit in force (0: none).

    ``knots`` (n,): the times [s] of the waypoints the profile's intervals join. Speeds
    (between samples) are judged at the middle of their step, accelerations at the sample.
    """
    if not any(tool.limited(name) for name in ("speed", "acceleration", "yaw_rate")):
        return {"speed": 0.0, "acceleration": 0.0, "yaw_rate": 0.0}  # nothing to sample
    t = traj.times(min(dt, traj.duration / 4))
    peaks = tool_peaks(robot, traj.evaluate(t), float(t[1] - t[0]))
    mid = (t[1:] + t[:-1]) / 2
    where = {"speed": mid, "acceleration": t[1:-1], "yaw_rate": mid}
    out = {}
    for name, values in peaks.items():
        if not values.size or not tool.limited(name):
            out[name] = 0.0
            continue
        limit = tool.at(name, where[name], knots)
        out[name] = float((values / limit).max())
    return out


def _joint_peaks(traj: Trajectory) -> tuple[float, float]:
    """Largest joint velocity and acceleration ratios: exact, or bounds both proven <= 1.

    First the peaks' Bernstein bounds (:meth:`~scara_opt.trajectory.Trajectory.peak_bounds`,
    never below the peaks): where both ratios they give are <= 1, they are returned, as
    the stretch they imply (:func:`_factor`: ``max(1, ...)``) is none, as the exact peaks'
    is; else the exact peaks (polynomial extrema).
    """
    def ratios(values: dict[str, Array]) -> tuple[float, float]:
        return (float((values["velocity"] / traj.limits.vmax).max()),
                float((values["acceleration"] / traj.limits.amax).max()))

    jv, ja = ratios(traj.peak_bounds())
    if jv <= 1.0 and ja <= 1.0:
        return jv, ja
    return ratios(traj.peaks())


def _factor(robot: Robot, traj: Trajectory, tool: ToolProfile, knots: Array,
            joint: tuple[float, float] | None = None,
            dynamics: RobotDynamics | None = None) -> float:
    """Smallest time stretch (>= 1) bringing every joint, tool and torque ratio to <= 1.

    Joint peaks exact (piecewise-polynomial extrema); ``joint``: those peaks if known.
    ``dynamics``: torques sampled at 1 kHz (gravity does not scale with the stretch).
    """
    jv, ja = _joint_peaks(traj) if joint is None else joint
    ratios = tool_ratios(robot, traj, tool, knots)
    torque = 1.0 if dynamics is None else dynamics.stretch_factor(traj)
    return max(1.0, jv, ratios["speed"], ratios["yaw_rate"], math.sqrt(ja),
               math.sqrt(ratios["acceleration"]), torque)


def section_spline(Q: Array, limits: Limits) -> SplineInterpolator:
    """The joint path :func:`time_section` times: toppra's cubic spline through ``Q`` (n, nq).

    Parameterised by the chord parameter (:func:`~scara_opt.trajectory.toppra_backend.
    chord_parameter`) in [0, 1]; its ``cspl`` is the path as a scipy ``CubicSpline``. The
    last few are kept: a section proven clear along its spline is then timed along the
    very same object.
    """
    Q = np.ascontiguousarray(Q, dtype=float)
    vmax = np.ascontiguousarray(limits.vmax, dtype=float)
    return _spline(Q.tobytes(), Q.shape, vmax.tobytes())


@functools.lru_cache(maxsize=8)
def _spline(q: bytes, shape: tuple[int, ...], vmax: bytes) -> SplineInterpolator:
    Q = np.frombuffer(q).reshape(shape)
    return geometric_path(chord_parameter(Q, np.frombuffer(vmax)), Q)


@functools.lru_cache(maxsize=8)
def _joint_constraints(vmax: bytes, amax: bytes) -> tuple:
    """toppra's joint velocity and acceleration constraints (interpolation), kept by limits."""
    import toppra.constraint as constraint

    return (constraint.JointVelocityConstraint(np.frombuffer(vmax)),
            constraint.JointAccelerationConstraint(
                np.frombuffer(amax),
                discretization_scheme=constraint.DiscretizationType.Interpolation))


def time_section(robot: Robot, Q: Array, limits: Limits, tool: ToolProfile,
                 dynamics: RobotDynamics | None = None) -> tuple[tuple[PPoly, ...], str, Array]:
    """Fastest rest-to-rest timing of joint waypoints ``Q`` (n, nq) within all limits.

    ``tool``: the tool limits per waypoint interval. ``dynamics``: joint torque limits (and
    any payload) as well: toppra's torque constraint, checked at 1 kHz like the rest.

    Returns:
        One PPoly per joint (time from 0 [s] → q), a note on grid and stretch, and the
        waypoint times (n,) [s].

    Raises:
        TrajectoryError: toppra failed (its return code is given), or its result exceeds a
            limit by more than :data:`MAX_STRETCH` between grid points.
        DynamicsError: gravity alone exceeds a torque limit on the path.
    """
    path = section_spline(Q, limits)
    s = path.ss_waypoints
    scale = 1.0 - MARGIN
    cons = list(_joint_constraints((limits.vmax * scale).tobytes(),
                                   (limits.amax * scale).tobytes()))
    scaled = tool.scaled(scale)
    if tool.limited("speed") or tool.limited("yaw_rate"):
        cons.append(speed_constraint(robot, scaled, s))
    if tool.limited("acceleration"):
        cons.append(acceleration_constraint(robot, scaled, s))
    if dynamics is not None:
        dynamics.check_static(Q)
        cons.append(dynamics.toppra_constraint(scale))
    per = max(2, math.ceil(MIN_GRID / (len(Q) - 1)))
    for attempt in range(REFINE + 1):
        pieces, grid, knots = solve_on_grid(path, s, per, cons, FAILED, STALLED)
        traj = Trajectory(pieces, limits, "toppra", Q, np.array([0.0, pieces[0].x[-1]]))
        jv, ja = _joint_peaks(traj)
        factor = _factor(robot, traj, tool, knots, joint=(jv, ja), dynamics=dynamics)
        if attempt == REFINE or factor <= 1 + MARGIN:
            break
        per *= 2
    note = f"{len(grid) - 1} grid intervals"
    if factor > MAX_STRETCH:
        raise TrajectoryError(
            f"toppra's timing exceeds a limit by x {factor:.4g} between its grid points (a "
            "sharp turn of the joint path: points too close, or a near-singular pose); "
            "refusing to slow it down that much silently: check the moves, or raise step=")
    total = 1.0
    for _ in range(5):  # the 1 kHz samples fall elsewhere once stretched: check again
        if factor <= 1.0:
            break
        factor *= 1.0 + 1e-6
        total *= factor
        pieces = tuple(stretch(p, factor) for p in pieces)
        knots = knots * factor
        # joint peaks scale exactly (velocity / total, acceleration / total²)
        factor = _factor(robot, Trajectory(pieces, limits, "toppra", Q,
                                           np.array([0.0, pieces[0].x[-1]])), tool, knots,
                         joint=(jv / total, ja / total**2), dynamics=dynamics)
    if total > 1.0:
        note += f", time stretched x {total:.6f} (discretisation overshoot removed)"
    return pieces, note, knots
