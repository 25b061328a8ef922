r"""Time-optimal timing through waypoints with TOPP-RA (toppra): joint velocity and acceleration.

The geometric path is toppra's cubic :class:`~toppra.SplineInterpolator` through the
waypoints (built by :func:`~scara_opt.trajectory.spline.geometric_path`), parameterised
by the normalised chord length :math:`s_i = \sum \|Δq / v_{max}\|`
(so the spline bends where the joints move, not where they rest). TOPP-RA (toppra's
``TOPPRA`` with the ``seidel`` solver, interpolation discretisation of the acceleration
constraint; its two passes run by :mod:`~scara_opt.trajectory.toppra_passes`) computes
the fastest rest-to-rest path velocity :math:`\dot s` on a grid that contains every
waypoint and ``grid_per_segment`` points per segment (at least ``min_grid`` intervals in
all). Between grid points the path acceleration is constant, as in toppra's
``ParametrizeConstAccel``; :func:`timed_pieces` writes that result exactly as degree-6
polynomials in time (toppra's other output, a cubic spline re-fitted through the timed grid,
overshoots the acceleration limit by several percent at every switch of the bang-bang profile).

Safety margin. TOPP-RA enforces the limits at the grid points only; between them the joint
velocity :math:`q'(s)\dot s` and acceleration :math:`q'(s)u + q''(s)\dot s^2` can exceed them
slightly. So toppra gets the limits scaled by ``1 - margin`` (default ``margin = 0.005``,
0.5 %), and the exact peaks of the result are measured
(:meth:`~scara_opt.trajectory.Trajectory.check_limits`). While a ratio is still above 1 the
grid is doubled (at most ``max_refine`` times, default 3); whatever excess remains is removed
by stretching time uniformly by the smallest factor that brings every ratio to <= 1
(velocity scales with 1/factor, acceleration with 1/factor²). The grid used and any stretch
are recorded in :attr:`~scara_opt.trajectory.Trajectory.notes`. So every ratio of the
returned trajectory is <= 1 (to round-off), at any sampling.

Torque limits. With ``dynamics`` (a :class:`~scara_opt.trajectory.dynamics.RobotDynamics`)
toppra also gets its ``JointTorqueConstraint``, τ = RNEA(q, q̇, q̈) from Pinocchio (gravity
and payload included), with the limits scaled by ``1 - margin`` too. The torque is then
checked at 1 kHz, and any excess at the samples is removed by the same uniform time
stretch (``τ - g(q)`` scales with 1/factor²). So the returned ``check_limits()["torque"]``
is <= 1 at the 1 kHz samples (to round-off); between samples it is not proven.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline, PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.trajectory.dynamics import RobotDynamics
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.methods import TimingMethod, check_option
from scara_opt.trajectory.spline import geometric_path
from scara_opt.trajectory.toppra_passes import reachability_passes
from scara_opt.trajectory.trajectory import Trajectory, cubic_range, stretch

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

#: the spline may leave the joint position limits by this much (round-off) [rad or m]
POSITION_SLACK = 1e-9

OPTIONS = {"margin": 0.005, "grid_per_segment": 4, "min_grid": 100, "max_refine": 3}

#: most grid doublings allowed (``max_refine``): 2**10 = 1024 times the first grid
MAX_REFINE = 10


def check_options(margin: Any, grid_per_segment: Any, min_grid: Any, max_refine: Any) -> None:
    """Refuse toppra options outside their ranges (see :func:`toppra_trajectory`).

    Raises:
        InputError: names the option, the value, its range and the default.
    """
    check_option("toppra", "margin", margin, 0.0, 0.5, high_open=True,
                 default=OPTIONS["margin"])
    for name, value, low in (("grid_per_segment", grid_per_segment, 1),
                             ("min_grid", min_grid, 2)):
        check_option("toppra", name, value, low, integer=True, default=OPTIONS[name])
    check_option("toppra", "max_refine", max_refine, 0, MAX_REFINE, integer=True,
                 default=OPTIONS["max_refine"])


def chord_parameter(Q: Array, vmax: Array) -> Array:
    """Path parameters (n,) in [0, 1]: cumulative ``‖Δq / vmax‖``, normalised."""
    steps = np.linalg.norm(np.diff(Q, axis=0) / vmax, axis=1)
    s = np.concatenate([[0.0], np.cumsum(steps)])
    return s / s[-1]


def timed_pieces(spline: CubicSpline, grid: Array, sd: Array) -> tuple[Array, Array]:
    r"""The exact time parameterisation toppra computed, as degree-6 pieces in time.

    On grid interval ``i`` TOPP-RA's path acceleration is constant (toppra's
    ``ParametrizeConstAccel``): :math:`s(τ) = s_i + \dot s_i τ + \tfrac12 u_i τ^2` over
    :math:`Δt_i = 2 Δs_i / (\dot s_i + \dot s_{i+1})`. Composing the path's cubic piece
    with this quadratic gives a degree-6 polynomial in τ, computed here for all intervals
    at once.

    Returns:
        ``(t, c)``: breakpoints (N+1,) [s] and coefficients (7, N, nq), highest power first.
    """
    sd = np.maximum(sd, 0.0)
    ds = np.diff(grid)
    dt = 2.0 * ds / (sd[:-1] + sd[1:])
    u = (sd[1:] ** 2 - sd[:-1] ** 2) / (2.0 * ds)
    knots = spline.x
    k = np.clip(np.searchsorted(knots, grid[:-1], side="right") - 1, 0, len(knots) - 2)
    w = (grid[:-1] - knots[k], sd[:-1], 0.5 * u)  # s - knot = w0 + w1 τ + w2 τ², (N,) each
    powers = np.zeros((len(dt), 4, 7))  # [:, m, j]: the τ^j coefficient of (s - knot)^m
    powers[:, 0, 0] = 1.0
    for m in range(1, 4):
        for j, wj in enumerate(w):
            powers[:, m, j:j + 2 * m - 1] += powers[:, m - 1, :2 * m - 1] * wj[:, None]
    pc = spline.c[::-1, k, :].transpose(1, 0, 2)  # (N, 4, nq): the pieces, lowest power first
    coeffs = np.matmul(powers.transpose(0, 2, 1), pc)  # (N, 7, nq), lowest power first
    return np.concatenate([[0.0], np.cumsum(dt)]), coeffs.transpose(1, 0, 2)[::-1]


def toppra_trajectory(Q: Array, limits: Limits, duration: float | None = None, *,
                      margin: float = 0.005, grid_per_segment: int = 4,
                      min_grid: int = 100, max_refine: int = 3,
                      dynamics: RobotDynamics | None = None) -> Trajectory:
    """Time-optimal rest-to-rest trajectory through ``Q`` (n, nq) with TOPP-RA.

    Args:
        Q: waypoints [rad or m], validated by :func:`~scara_opt.trajectory.time_parameterize`.
        limits: joint velocity and acceleration limits.
        duration: must be ``None`` (the registry refuses a fixed duration for toppra).
        margin: fraction in [0, 0.5) by which toppra's limits are tightened (see the module
            docstring).
        grid_per_segment: TOPP-RA grid intervals per waypoint segment (first attempt),
            an integer >= 1.
        min_grid: least number of grid intervals in all, an integer >= 2 (a rest-to-rest
            profile needs an interior grid point).
        max_refine: how many times (an integer in [0, 10]) the grid may be doubled while
            the result still exceeds a limit (see the module docstring).
        dynamics: inverse dynamics and torque limits (with any payload) for a torque-limited
            timing, or ``None`` (velocity and acceleration limits only).

    Raises:
        TrajectoryError: toppra could not parameterise the path (its return code is given),
            or the grid is so coarse that the path speed is zero on a whole interval.
        InputError: an option outside its range (named in the message).
    """
    check_options(margin, grid_per_segment, min_grid, max_refine)
    s = chord_parameter(Q, limits.vmax)
    path = geometric_path(s, Q)
    if dynamics is not None:
        dynamics.check_static(path(np.linspace(0.0, 1.0, 201)))
    per_segment = max(int(grid_per_segment), math.ceil(min_grid / (len(Q) - 1)))
    for attempt in range(int(max_refine) + 1):
        pieces, times = _solve(path, s, per_segment, limits, 1.0 - float(margin), dynamics)
        factor = _overshoot(Trajectory(pieces, limits, "toppra", Q, times), dynamics)
        if factor == 1.0 or attempt == max_refine:
            break
        per_segment *= 2
        log.debug("toppra: overshoot x %.4f beyond the margin; grid refined to %d per segment",
                  factor, per_segment)
    _check_positions(Trajectory(pieces, limits, "toppra", Q, times), cubic_range(path.cspl))
    note = f"toppra, limits x (1 - {margin:g}), {per_segment} grid intervals per segment"
    if dynamics is not None:
        note += " (torque-limited" + (f", payload {dynamics.payload.mass:g} kg)"
                                      if dynamics.payload is not None else ")")
    total = 1.0
    for _ in range(3):  # a torque stretch moves the 1 kHz samples: check again
        if factor == 1.0:
            break
        pieces = tuple(stretch(p, factor) for p in pieces)
        times = times * factor
        total *= factor
        factor = _overshoot(Trajectory(pieces, limits, "toppra", Q, times), dynamics)
    if factor > 1.0:  # not seen in practice: the third stretch leaves round-off only
        log.warning("toppra: a limit is still exceeded by x %.3g after stretching; see "
                    "check_limits()", factor)
    if total > 1.0:
        note += f"; discretisation overshoot removed by stretching time x {total:.6f}"
        log.info("toppra: discretisation overshoot, time stretched by %.6f", total)
    return Trajectory(pieces, limits, "toppra", Q.copy(), times, notes=note, dynamics=dynamics)


def _solve(path: Any, s: Array, per_segment: int, limits: Limits, scale: float,
           dynamics: RobotDynamics | None = None) -> tuple[tuple[PPoly, ...], Array]:
    """One TOPP-RA solve on a grid of ``per_segment`` intervals per waypoint segment.

    Returns:
        One PPoly per joint and the waypoint times (n,) [s].
    """
    import toppra.constraint as constraint

    interpolation = constraint.DiscretizationType.Interpolation
    cons = [constraint.JointVelocityConstraint(limits.vmax * scale),
            constraint.JointAccelerationConstraint(limits.amax * scale,
                                                   discretization_scheme=interpolation)]
    if dynamics is not None:
        cons.append(dynamics.toppra_constraint(scale))
    failed = ("check the waypoints (nearly duplicate ones make the spline degenerate) or try "
              "method='ruckig'" + ("; under torque limits, also whether the limits can hold "
                                   "the payload along the path" if dynamics is not None else ""))
    stalled = (f"the grid is too coarse; raise grid_per_segment= or min_grid= (defaults "
               f"{OPTIONS['grid_per_segment']} and {OPTIONS['min_grid']})")
    pieces, _, times = solve_on_grid(path, s, per_segment, cons, failed, stalled)
    return pieces, times


def solve_on_grid(path: Any, s: Array, per_segment: int, cons: list, failed: str,
                  stalled: str) -> tuple[tuple[PPoly, ...], Array, Array]:
    """TOPP-RA with the constraints ``cons`` on ``per_segment`` grid intervals per waypoint.

    The waypoints are at the path parameter ``s`` (n,). ``failed`` / ``stalled``: what to do,
    appended to the error when toppra fails or when its path speed is zero at both ends of a
    grid interval (the motion would take forever).

    Returns:
        One PPoly per joint (time from 0 [s] → q), the grid, and the waypoint times (n,) [s].

    Raises:
        TrajectoryError: either failure, with toppra's return code or the interval.
    """
    frac = np.arange(per_segment) / per_segment
    grid = np.append((s[:-1, None] + np.diff(s)[:, None] * frac).ravel(), s[-1])
    sd, code = reachability_passes(cons, path, grid)  # toppra's TOPPRA, seidel solver
    if sd is None:
        raise TrajectoryError(f"toppra could not parameterise the path ({code}); " + failed)
    sd = np.maximum(sd, 0.0)
    stall = np.flatnonzero(sd[:-1] + sd[1:] <= 0.0)
    if stall.size:
        raise TrajectoryError(
            f"toppra's path speed is zero at both ends of grid interval {int(stall[0])} of "
            f"{len(grid) - 1}, so it would take forever: " + stalled)
    t, coeffs = timed_pieces(path.cspl, grid, sd)
    pieces = tuple(PPoly.construct_fast(np.ascontiguousarray(coeffs[:, :, k]), t,
                                        extrapolate=False)  # t finite, increasing: unchecked
                   for k in range(coeffs.shape[2]))
    return pieces, grid, t[::per_segment].copy()


def _check_positions(traj: Trajectory, span: tuple[Array, Array]) -> None:
    """Refuse a spline that leaves the joint position limits between the waypoints.

    ``span``: the smallest and largest value of each joint along the path (nq,) each: those
    of the path's cubic spline in ``s`` (:func:`~scara_opt.trajectory.trajectory.cubic_range`),
    which the timing traverses whole (the path speed is never negative).

    Raises:
        TrajectoryError: naming the joint, how far and between which waypoints.
    """
    lim = traj.limits
    lo, hi = span
    excess = np.maximum(lim.lower - lo, hi - lim.upper)
    if (excess > POSITION_SLACK).any():
        k = int(np.argmax(excess))
        t = traj.times(traj.duration / 2000)
        q = traj.evaluate(t)[:, k]
        worst = t[int(np.argmax(np.maximum(lim.lower[k] - q, q - lim.upper[k])))]
        i = int(np.searchsorted(traj.waypoint_times, worst, side="right")) - 1
        raise TrajectoryError(
            f"toppra's spline through the waypoints leaves the limits of joint "
            f"{lim.joint_names[k]!r}, [{lim.lower[k]:.6g}, {lim.upper[k]:.6g}] {lim.unit(k)} by "
            f"{excess[k]:.3g} {lim.unit(k)} between waypoints {i} and {i + 1}: add waypoints "
            "there (sample the path more finely), or use method='ruckig' (which keeps within "
            "the limits) or 'quintic' (which stops at every waypoint)")


def _overshoot(traj: Trajectory, dynamics: RobotDynamics | None = None) -> float:
    """Smallest time-stretch factor (>= 1) that brings every limit ratio to <= 1.

    Raises:
        DynamicsError: gravity alone exceeds a torque limit somewhere on the path.
    """
    ratios = traj.check_limits()
    factor = max(float(ratios["velocity"].max()), math.sqrt(float(ratios["acceleration"].max())))
    if dynamics is not None:
        factor = max(factor, dynamics.stretch_factor(traj))
    return factor * (1.0 + 1e-12) if factor > 1.0 else 1.0


#: the registry entry (read by :mod:`scara_opt.trajectory.registry`)
METHOD = TimingMethod("toppra", toppra_trajectory, OPTIONS, uses_torque=True)
