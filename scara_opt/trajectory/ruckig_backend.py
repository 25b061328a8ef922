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
from scara_opt.trajectory.trajectory import Trajectory

Array = NDArray[np.float64]

#: phases shorter than this are dropped when building the piecewise cubic [s]
_MIN_PHASE = 1e-14
#: a joint whose phases end this much before the segment's duration rests at its target [s]
_EARLY = 1e-12
#: slots per joint and segment: Ruckig's seven constant-jerk phases, then a rest at the target
_SLOTS = 8
#: where each slot's cubic coefficients (highest power first) sit in a profile row of
#: :func:`_read_profiles` (4, 8): jerk, acceleration, velocity and position at the start of
#: each phase, then the rest slot's 0, 0, 0 (the row's trailing 0) and final position
_COEFF_COLUMNS = np.array([[*range(7, 14), 38], [*range(14, 21), 38], [*range(22, 29), 38],
                           [*range(30, 38)]])
#: and what they are divided by: q = j t³/6 + a t²/2 + v t + p in each phase
_COEFF_DIVISORS = np.array([[6.0] * 7 + [1.0], [2.0] * 7 + [1.0], [1.0] * 8, [1.0] * 8])
_SLOT = np.arange(_SLOTS)


def _read_profiles(profiles: list) -> list[list[float]]:
    """Ruckig's per-joint ``Profile`` fields, one row of 39 numbers per joint.

    Each row: ``t``, ``j`` (7 each: phase durations [s], jerks), then ``a``, ``v``, ``p``
    (8 each: acceleration, velocity, position at the phase boundaries), as Ruckig gives
    them, and a 0 (the rest slot's zero coefficients, see :data:`_COEFF_COLUMNS`).
    """
    return [prof.t + prof.j + prof.a + prof.v + prof.p + [0.0] for prof in profiles]


def _phases(profile: Array, durations: Array) -> tuple[Array, Array, Array]:
    """Every segment's and joint's phases as the slots of piecewise cubics, all at once.

    Args:
        profile: (S, nq, 39), S segments' rows of :func:`_read_profiles`.
        durations: (S,) the segments' durations [s].

    Returns:
        ``(ends, coeffs, keep)``: ``ends`` (S, nq, 8) the end time of each slot in its
        segment [s], the last kept one exactly the duration (and every one after it);
        ``coeffs`` (S, nq, 4, 8) each slot's cubic in local time, highest power first;
        ``keep`` (S, nq, 8) the slots that are pieces: phases longer than
        :data:`_MIN_PHASE`, and the rest slot when the kept phases end early or there are
        none (the joint does not move). A dropped phase ends where the kept one before it
        does (its duration counts as 0), so ``ends`` never decreases along a segment.

    Raises:
        TrajectoryError: the kept phases do not fit in the duration (their ends decrease).
    """
    T = durations[:, None, None]
    t = profile[..., :7]
    phase = t > _MIN_PHASE
    ends = np.add.accumulate(np.where(phase, t, 0.0), axis=-1)
    rest = ~np.logical_or.reduce(phase, axis=-1) | (ends[..., 6] < T[..., 0] - _EARLY)
    keep = np.concatenate([phase, rest[..., None]], axis=-1)
    last = _SLOTS - 1 - np.argmax(keep[..., ::-1], axis=-1)   # the last kept slot
    ends = np.where(_SLOT >= last[..., None], T, np.concatenate([ends, ends[..., -1:]], -1))
    if (ends[..., 1:] < ends[..., :-1]).any():
        raise TrajectoryError("ruckig's phases do not fit in its duration (they end later); "
                              "this should not happen, please report it")
    return ends, profile.take(_COEFF_COLUMNS, axis=-1) / _COEFF_DIVISORS, keep


def _joint_pieces(ends: Array, coeffs: Array, keep: Array, times: Array) -> tuple[PPoly, ...]:
    """One PPoly per joint from consecutive segments' slots, laid end to end in time.

    Args:
        ends: (S, nq, 8), as :func:`_phases` gives them.
        coeffs: (S, nq, 4, 8).
        keep: (S, nq, 8).
        times: (S + 1,) the segments' start times, then the end [s].
    """
    nq = ends.shape[1]
    breaks = (ends + times[:-1, None, None]).transpose(1, 0, 2).reshape(nq, -1)
    kept = keep.transpose(1, 0, 2).reshape(nq, -1)
    c = coeffs.transpose(1, 2, 0, 3).reshape(nq, 4, -1)
    start = np.zeros(1)
    # from checked parts (non-decreasing breaks, see _phases): skip PPoly's checks
    return tuple(PPoly.construct_fast(c[k][:, kept[k]],
                                      np.concatenate([start, breaks[k][kept[k]]]),
                                      extrapolate=False) for k in range(nq))


class _Ruckig:
    """One Ruckig calculator, input and output for rest-to-rest segments under ``limits``.

    Reused for every segment of one trajectory (never shared between calls or threads).
    """

    def __init__(self, nq: int, limits: Limits) -> None:
        import ruckig

        if limits.jmax is None:
            raise TrajectoryError("ruckig needs jerk limits; resolve them with need_jerk=True")
        self.otg, self.inp, self.out = ruckig.Ruckig(nq), ruckig.InputParameter(nq), \
            ruckig.Trajectory(nq)
        inp = self.inp
        inp.current_velocity = inp.current_acceleration = [0.0] * nq
        inp.target_velocity = inp.target_acceleration = [0.0] * nq
        inp.max_velocity = limits.vmax.tolist()
        inp.max_acceleration = limits.amax.tolist()
        inp.max_jerk = limits.jmax.tolist()
        inp.synchronization = ruckig.Synchronization.Time

    def segment(self, qa: Array, qb: Array) -> tuple[list[list[float]], float]:
        """The profile rows (:func:`_read_profiles`) and duration [s] from ``qa`` to ``qb``.

        Raises:
            TrajectoryError: Ruckig refused or failed, or needed a brake pre-trajectory.
        """
        import ruckig

        self.inp.current_position, self.inp.target_position = qa.tolist(), qb.tolist()
        try:
            result = self.otg.calculate(self.inp, self.out)
        except (RuntimeError, ruckig.RuckigError) as exc:  # ruckig raises on invalid input
            raise TrajectoryError(f"ruckig refused the segment {qa} → {qb}: {exc}") from None
        except ValueError as exc:  # a result code the binding does not know, e.g. -101
            raise TrajectoryError(
                f"ruckig failed on the segment {qa} → {qb} ({exc}; -101 means the duration "
                "exceeds Ruckig's numerical range): raise vmax=/amax=/jmax= or use "
                "method='quintic'") from None
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise TrajectoryError(f"ruckig failed on the segment {qa} → {qb}: {result}; check "
                                  "the limits (they must be finite and positive)")
        profiles = self.out.profiles[0]
        if any(prof.brake.duration > 0 for prof in profiles):
            raise TrajectoryError("ruckig needed a brake pre-trajectory on a rest-to-rest "
                                  "move; this should not happen, please report it")
        return _read_profiles(profiles), float(self.out.duration)


def ruckig_segment(qa: Array, qb: Array, limits: Limits) -> tuple[list[PPoly], float]:
    """Rest-to-rest Ruckig motion from ``qa`` to ``qb``: one PPoly per joint, and its duration."""
    rows, T = _Ruckig(len(qa), limits).segment(qa, qb)
    times = np.array([0.0, T])
    return list(_joint_pieces(*_phases(np.array([rows], dtype=float), times[1:]), times)), T


def ruckig_trajectory(Q: Array, limits: Limits, duration: float | None = None) -> Trajectory:
    """Jerk-limited trajectory through ``Q`` (n, nq), stopping at every waypoint.

    Args:
        Q: waypoints [rad or m], validated by :func:`~scara_opt.trajectory.time_parameterize`.
        limits: joint velocity, acceleration and jerk limits.
        duration: must be ``None`` (the registry refuses a fixed duration for ruckig).

    Raises:
        TrajectoryError: Ruckig failed on a segment.
    """
    solver = _Ruckig(Q.shape[1], limits)
    rows, durations = zip(*(solver.segment(qa, qb) for qa, qb in zip(Q[:-1], Q[1:],
                                                                      strict=True)), strict=True)
    times = np.concatenate([[0.0], np.cumsum(durations)])
    pieces = _joint_pieces(*_phases(np.array(rows, dtype=float), np.array(durations)), times)
    return Trajectory(pieces, limits, "ruckig", Q.copy(), times,
                      notes="free Ruckig: rest-to-rest between consecutive waypoints")


#: the registry entry (read by :mod:`scara_opt.trajectory.registry`)
METHOD = TimingMethod("ruckig", ruckig_trajectory, uses_jerk=True)
