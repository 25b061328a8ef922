"""Jerk-limited timing with Ruckig: time-optimal under velocity, acceleration and jerk limits.

Ruckig (the free, open-source version installed from PyPI) computes a time-optimal
trajectory between two kinematic states; passing *intermediate* waypoints with non-zero
velocity needs Ruckig Pro (or its cloud API). So through several waypoints this backend
**stops at each waypoint**: a chain of rest-to-rest point-to-point motions, every joint
synchronised to arrive together (Ruckig's ``Synchronization.Time``). For a path of many
closely spaced waypoints that is much slower than toppra, which keeps moving through them.

Each joint of a Ruckig profile is seven phases of constant jerk; the phases are read from
``Trajectory.profiles`` and turned into exact piecewise cubics (checked against
``Trajectory.at_time`` in the tests), so sampling and the limit check need no Ruckig call.

Jerk limit: robots carry none; the default is
:data:`~scara_opt.trajectory.limits.JERK_PER_ACCELERATION` × amax (10/s × amax: the
acceleration limit is reached in 0.1 s).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.methods import TimingMethod
from scara_opt.trajectory.trajectory import Trajectory, concatenate

Array = NDArray[np.float64]

#: phases shorter than this are dropped when building the piecewise cubic [s]
_MIN_PHASE = 1e-14


def _profile_pieces(t: Array, j: Array, a: Array, v: Array, p: Array, duration: float) -> PPoly:
    """One joint's constant-jerk phases as a PPoly on [0, duration].

    ``t``, ``j`` (7,): phase durations [s] and jerks; ``a``, ``v``, ``p`` (8,): acceleration,
    velocity and position at the phase boundaries (Ruckig's ``Profile`` fields).
    """
    keep = t > _MIN_PHASE
    breaks = np.concatenate([[0.0], np.cumsum(t[keep])])
    coeffs = np.array([j[keep] / 6, a[:-1][keep] / 2, v[:-1][keep], p[:-1][keep]])
    if not keep.any():  # the joint does not move
        coeffs = np.array([[0.0], [0.0], [0.0], [p[-1]]])
        breaks = np.array([0.0, duration])
    elif breaks[-1] < duration - 1e-12:  # finished early: rest at the target
        coeffs = np.hstack([coeffs, [[0.0], [0.0], [0.0], [p[-1]]]])
        breaks = np.append(breaks, duration)
    else:
        breaks[-1] = duration
    # built from checked parts (increasing breaks, finite coefficients): skip PPoly's checks
    return PPoly.construct_fast(coeffs, breaks, extrapolate=False)


def ruckig_segment(qa: Array, qb: Array, limits: Limits) -> tuple[list[PPoly], float]:
    """Rest-to-rest Ruckig motion from ``qa`` to ``qb``: one PPoly per joint, and its duration."""
    import ruckig

    nq = len(qa)
    otg = ruckig.Ruckig(nq)
    inp = ruckig.InputParameter(nq)
    inp.current_position, inp.target_position = list(qa), list(qb)
    inp.current_velocity = inp.current_acceleration = [0.0] * nq
    inp.target_velocity = inp.target_acceleration = [0.0] * nq
    inp.max_velocity = list(limits.vmax)
    inp.max_acceleration = list(limits.amax)
    if limits.jmax is None:
        raise TrajectoryError("ruckig needs jerk limits; resolve them with need_jerk=True")
    inp.max_jerk = list(limits.jmax)
    inp.synchronization = ruckig.Synchronization.Time
    traj = ruckig.Trajectory(nq)
    try:
        result = otg.calculate(inp, traj)
    except (RuntimeError, ruckig.RuckigError) as exc:  # ruckig raises on invalid input
        raise TrajectoryError(f"ruckig refused the segment {qa} → {qb}: {exc}") from None
    except ValueError as exc:  # a result code the binding does not know, e.g. -101
        raise TrajectoryError(
            f"ruckig failed on the segment {qa} → {qb} ({exc}; -101 means the duration "
            "exceeds Ruckig's numerical range): raise vmax=/amax=/jmax= or use "
            "method='quintic'") from None
    if result not in (ruckig.Result.Working, ruckig.Result.Finished):
        raise TrajectoryError(f"ruckig failed on the segment {qa} → {qb}: {result}; check the "
                              "limits (they must be finite and positive)")
    T = float(traj.duration)
    profiles = traj.profiles[0]
    if any(prof.brake.duration > 0 for prof in profiles):
        raise TrajectoryError("ruckig needed a brake pre-trajectory on a rest-to-rest move; "
                              "this should not happen, please report it")
    fields = [np.array([getattr(prof, name) for prof in profiles], dtype=float)
              for name in ("t", "j", "a", "v", "p")]     # (nq, 7) or (nq, 8) each
    return [_profile_pieces(*(f[k] for f in fields), T) for k in range(nq)], T


def ruckig_trajectory(Q: Array, limits: Limits, duration: float | None = None) -> Trajectory:
    """Jerk-limited trajectory through ``Q`` (n, nq), stopping at every waypoint.

    Args:
        Q: waypoints [rad or m], validated by :func:`~scara_opt.trajectory.time_parameterize`.
        limits: joint velocity, acceleration and jerk limits.
        duration: must be ``None`` (the registry refuses a fixed duration for ruckig).

    Raises:
        TrajectoryError: Ruckig failed on a segment.
    """
    segments: list[list[PPoly]] = []
    durations: list[float] = []
    for qa, qb in zip(Q[:-1], Q[1:], strict=True):
        seg, T = ruckig_segment(qa, qb, limits)
        segments.append(seg)
        durations.append(T)
    pieces = tuple(concatenate([seg[k] for seg in segments]) for k in range(Q.shape[1]))
    times = np.concatenate([[0.0], np.cumsum(durations)])
    return Trajectory(pieces, limits, "ruckig", Q.copy(), times,
                      notes="free Ruckig: rest-to-rest between consecutive waypoints")


#: the registry entry (read by :mod:`scara_opt.trajectory.registry`)
METHOD = TimingMethod("ruckig", ruckig_trajectory, uses_jerk=True)
