r"""Quintic rest-to-rest interpolation (fang Tables 2–3; the Robotics Toolbox's ``jtraj``).

Each segment from :math:`q_a` to :math:`q_b` over :math:`T` is

.. math:: q(t) = q_a + (q_b - q_a)\, s(τ), \quad s(τ) = 10τ^3 - 15τ^4 + 6τ^5, \quad τ = t/T,

with zero velocity and acceleration at both ends. Its peaks are
:math:`\max|\dot q| = \tfrac{15}{8}|Δq|/T` (at τ = 1/2) and
:math:`\max|\ddot q| = \tfrac{10}{\sqrt 3}|Δq|/T^2` (at τ = 1/2 ∓ √3/6), so the shortest
duration within the limits is, over the joints,

.. math:: T_{min} = \max_j \max\left(\frac{15 |Δq_j|}{8 v_j},
          \sqrt{\frac{10 |Δq_j|}{\sqrt 3\, a_j}}\right).

Through more than two waypoints the robot stops at each (a chain of segments).

A fixed duration below the shortest one is refused (:class:`~scara_opt.errors.TrajectoryError`,
which gives the shortest); with ``enforce_limits=False`` it is timed anyway, logged as a
warning and recorded in :attr:`~scara_opt.trajectory.Trajectory.notes` with the worst ratio.
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.methods import TimingMethod, check_option_flag
from scara_opt.trajectory.trajectory import Trajectory, concatenate

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

#: peak of s'(τ) and of |s''(τ)| of the quintic blend
PEAK_VELOCITY = 15.0 / 8.0
PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)

#: a fixed duration may fall short of the shortest by this fraction (round-off)
DURATION_SLACK = 1e-12


def quintic_blend(tau: ArrayLike) -> Array:
    """The blend s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ at ``tau`` in [0, 1] (fang's Tables 2–3 use τ = k/35)."""
    t = np.asarray(tau, dtype=float)
    return t**3 * (10.0 + t * (-15.0 + 6.0 * t))


def shortest_duration(delta: ArrayLike, vmax: Array, amax: Array) -> float:
    """Shortest quintic duration [s] of a joint move ``delta`` (nq,) within ``vmax``, ``amax``."""
    d = np.abs(np.asarray(delta, dtype=float))
    return float(np.max(np.maximum(PEAK_VELOCITY * d / vmax,
                                   np.sqrt(PEAK_ACCELERATION * d / amax))))


def quintic_segment(qa: Array, qb: Array, duration: float) -> list[PPoly]:
    """One PPoly per joint of the quintic from ``qa`` to ``qb`` (nq,) over ``duration`` [s]."""
    T = float(duration)
    out = []
    for a, b in zip(qa, qb, strict=True):
        D = b - a
        c = np.array([6 * D / T**5, -15 * D / T**4, 10 * D / T**3, 0.0, 0.0, a])
        out.append(PPoly(c[:, None], np.array([0.0, T]), extrapolate=False))
    return out


def quintic_trajectory(Q: Array, limits: Limits, duration: float | None = None, *,
                       enforce_limits: bool = True) -> Trajectory:
    """Rest-to-rest quintic through the waypoints ``Q`` (n, nq) [rad or m].

    Args:
        Q: waypoints, validated by :func:`~scara_opt.trajectory.time_parameterize`.
        limits: joint limits.
        duration: total duration [s]; the segments share it in proportion to their own
            shortest durations. ``None``: every segment as short as the limits allow.
        enforce_limits: refuse a ``duration`` below the shortest within the limits (default).
            ``False`` times it anyway: the limits are exceeded, which is logged as a warning,
            written in ``notes`` and visible in
            :meth:`~scara_opt.trajectory.Trajectory.check_limits`.

    Returns:
        Trajectory: stops (zero velocity and acceleration) at every waypoint.

    Raises:
        TrajectoryError: ``duration`` below the shortest [s] (given in the message) while
            ``enforce_limits``.
        InputError: ``enforce_limits`` not True or False.
    """
    check_option_flag("quintic", "enforce_limits", enforce_limits)
    shortest = np.array([shortest_duration(b - a, limits.vmax, limits.amax)
                         for a, b in zip(Q[:-1], Q[1:], strict=True)])
    total = float(shortest.sum())
    too_short = duration is not None and duration < total * (1 - DURATION_SLACK)
    if too_short and enforce_limits:
        raise TrajectoryError(
            f"quintic duration {duration:.6g} s is below {total:.6g} s, the shortest that "
            f"respects the velocity/acceleration limits: pass duration >= "
            f"{math.ceil(total * 1e6) / 1e6:.6f} or duration=None (the shortest), raise "
            "vmax=/amax=, or pass enforce_limits=False to accept exceeding the limits")
    durations = shortest if duration is None else shortest * (duration / total)
    segments = [quintic_segment(a, b, T) for a, b, T in zip(Q[:-1], Q[1:], durations,
                                                             strict=True)]
    pieces = tuple(concatenate([seg[k] for seg in segments]) for k in range(Q.shape[1]))
    times = np.concatenate([[0.0], np.cumsum(durations)])
    note = "shortest within the limits" if duration is None else f"fixed duration {duration} s"
    traj = Trajectory(pieces, limits, "quintic", Q.copy(), times, notes=note)
    if too_short:
        worst = max(float(r.max()) for r in traj.check_limits().values())
        excess = (f"below the shortest within the limits ({total:.6g} s): limits exceeded, "
                  f"largest ratio {worst:.4g} (enforce_limits=False)")
        log.warning("quintic duration %.6g s is %s", duration, excess)
        traj = replace(traj, notes=f"{note}, {excess}")
    return traj


#: the registry entry (read by :mod:`scara_opt.trajectory.registry`)
METHOD = TimingMethod("quintic", quintic_trajectory, {"enforce_limits": True},
                      takes_duration=True)
