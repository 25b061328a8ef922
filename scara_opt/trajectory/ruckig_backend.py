"""Jerk-limited timing with Ruckig: time-optimal under velocity, acceleration and jerk limits.

Ruckig (the free, open-source version installed from PyPI) computes a time-optimal
trajectory between two kinematic states; passing *intermediate* waypoints at speed needs
Ruckig Pro (or its cloud API, which needs the network). So the community version's
answer between two waypoints is a rest-to-rest move, every joint synchronised to arrive
together (Ruckig's ``Synchronization.Time``); through three or more waypoints this backend
keeps moving instead, in the shorter of two ways chosen from the path
(:mod:`scara_opt.trajectory.passing`): Ruckig moves joined at non-zero waypoint
velocities taken from the path's tangent, or Ruckig along the path parameter of toppra's
spline. ``Trajectory.notes`` says which.

Each joint of a Ruckig profile is seven phases of constant jerk; the phases are read from
``Trajectory.profiles`` and turned into exact piecewise cubics (checked against
``Trajectory.at_time`` in the tests), so sampling and the limit check need no Ruckig call.
The conversion works on the Python floats Ruckig hands over, joint by joint, and makes
one numpy array at the end. All joints and segments at once in numpy (~20 calls of about
a microsecond each on so few numbers) took twice as long on one segment of fang's
(79 µs against 39 µs for the whole backend); it is faster only on long chains of
segments (1.4 ms against 1.8 ms for 99).

Jerk limit: robots carry none; the default is
:data:`~scara_opt.trajectory.limits.JERK_PER_ACCELERATION` × amax (10/s × amax: the
acceleration limit is reached in 0.1 s).
"""

from __future__ import annotations

import math
import threading
from itertools import accumulate, chain, compress

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.trajectory import passing
from scara_opt.trajectory.limits import (
    JERK_PER_ACCELERATION,
    LIMIT_RANGES,
    Limits,
    resolve_limits,
)
from scara_opt.trajectory.methods import TimingMethod
from scara_opt.trajectory.trajectory import Trajectory, stretch

Array = NDArray[np.float64]

#: phases shorter than this are dropped when building the piecewise cubic [s]
_MIN_PHASE = 1e-14
#: a joint whose phases end this much before the segment's duration rests at its target [s]
_EARLY = 1e-12
#: a joined segment may leave the position limits by this much (round-off) [rad or m]
_POSITION_SLACK = 1e-9


def _add_phases(rows: list[list[float]], prof: object, start: float, duration: float) -> None:
    """Append one joint's constant-jerk phases of one segment to its pieces.

    Args:
        rows: the joint's pieces so far, five lists: the coefficients of each piece's cubic
            in its local time, highest power first (``j/6``, ``a/2``, ``v``, ``p`` at its
            start), then the breaks [s] (one more: the first is 0).
        prof: Ruckig's ``Profile`` of the joint: ``t``, ``j`` (7,) phase durations [s] and
            jerks; ``a``, ``v``, ``p`` (8,) acceleration, velocity and position at the phase
            boundaries.
        start: when the segment starts [s].
        duration: the segment's duration [s]; its last piece ends exactly there.

    Phases up to :data:`_MIN_PHASE` are dropped; a joint whose phases end early (or that
    does not move) rests at its target until ``duration``.

    Raises:
        TrajectoryError: the phases end after ``duration``.
    """
    t, j, a, v, p = prof.t, prof.j, prof.a, prof.v, prof.p
    kept = [ti > _MIN_PHASE for ti in t]  # (7,): a, v, p at the phases' starts
    ends = list(accumulate(compress(t, kept)))
    rest = not ends or ends[-1] < duration - _EARLY
    if rest:
        ends.append(duration)
    elif len(ends) > 1 and ends[-2] > duration:
        raise TrajectoryError(f"ruckig's phases end at {ends[-2]!r} s, after its duration "
                              f"{duration!r} s; this should not happen, please report it")
    else:
        ends[-1] = duration
    jerk, acc, vel, pos, breaks = rows
    jerk += [x / 6 for x in compress(j, kept)]
    acc += [x / 2 for x in compress(a, kept)]
    vel += compress(v, kept)
    pos += compress(p, kept)
    breaks += [end + start for end in ends]
    if rest:
        jerk.append(0.0)
        acc.append(0.0)
        vel.append(0.0)
        pos.append(p[-1])


def _ppolys(joints: list[list[list[float]]]) -> tuple[PPoly, ...]:
    """One PPoly per joint from its four coefficient rows (m,) and breaks (m + 1,).

    Every joint's numbers go through one numpy call; each PPoly's ``c`` (4, m) and ``x``
    are C-contiguous views of that array (a numpy call per joint costs ~1 µs more).
    """
    flat = np.fromiter(chain.from_iterable(chain.from_iterable(joints)), dtype=float)
    pieces, start = [], 0
    for rows in joints:
        m = len(rows[0])
        c = flat[start:start + 4 * m].reshape(4, m)
        x = flat[start + 4 * m:start + 5 * m + 1]
        start += 5 * m + 1
        # from checked parts (increasing breaks, finite coefficients): skip PPoly's checks
        pieces.append(PPoly.construct_fast(c, x, extrapolate=False))
    return tuple(pieces)


#: this thread's Ruckig calculator, input and output per joint count, made on first use
_LOCAL = threading.local()


class _Ruckig:
    """Ruckig's calculator, input and output for rest-to-rest segments under ``limits``.

    One set per thread and joint count, made once and kept: making them costs ~5 µs, a
    tenth of timing a fang move. Each use sets the limits and each segment the positions;
    the start and target velocities and accelerations stay 0 and every other input
    Ruckig's default; ``calculate`` overwrites the output. Threads never share a set.
    """

    def __init__(self, nq: int, limits: Limits) -> None:
        import ruckig

        if limits.jmax is None:
            raise TrajectoryError("ruckig needs jerk limits; resolve them with need_jerk=True")
        sets = _LOCAL.__dict__.setdefault("sets", {})
        if nq not in sets:
            inp = ruckig.InputParameter(nq)
            inp.current_velocity = inp.current_acceleration = [0.0] * nq
            inp.target_velocity = inp.target_acceleration = [0.0] * nq
            inp.synchronization = ruckig.Synchronization.Time
            sets[nq] = ruckig.Ruckig(nq), inp, ruckig.Trajectory(nq), [False]
        self.otg, self.inp, self.out, self.moving = sets[nq]
        if self.moving[0]:  # a joined timing left velocities set: back to rest to rest
            self.inp.current_velocity = self.inp.target_velocity = [0.0] * nq
            self.moving[0] = False
        self.inp.max_velocity = limits.vmax.tolist()
        self.inp.max_acceleration = limits.amax.tolist()
        self.inp.max_jerk = limits.jmax.tolist()

    def segment(self, qa: Array, qb: Array, va: Array | None = None,
                vb: Array | None = None) -> tuple[list, float]:
        """Ruckig's per-joint ``Profile`` and the duration [s] of the move ``qa`` → ``qb``.

        ``va``, ``vb``: the velocities at ``qa`` and ``qb`` (default: at rest); the
        accelerations there are 0.

        Raises:
            TrajectoryError: Ruckig refused or failed, or needed a brake pre-trajectory.
        """
        import ruckig

        self.inp.current_position, self.inp.target_position = qa.tolist(), qb.tolist()
        if va is not None:
            self.inp.current_velocity, self.inp.target_velocity = va.tolist(), vb.tolist()
            self.moving[0] = True
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
            raise TrajectoryError("ruckig needed a brake pre-trajectory on a move that starts "
                                  "within the limits; this should not happen, please report it")
        return profiles, float(self.out.duration)

    def leaves(self, limits: Limits) -> bool:
        """Whether the last segment leaves the position limits between its ends."""
        return any(e.min < lo - _POSITION_SLACK or e.max > hi + _POSITION_SLACK
                   for e, lo, hi in zip(self.out.position_extrema, limits.lower, limits.upper,
                                        strict=True))


def _timed_pieces(Q: Array, limits: Limits, V: Array | None = None
                  ) -> tuple[tuple[PPoly, ...], list[float]]:
    """Ruckig moves through ``Q`` (n, nq), laid end to end in time.

    ``V`` (n, nq): the velocities at the waypoints (default: rest at each). A segment that
    would leave the position limits gets its end velocities set to 0 (the segment before
    it is then timed again), so it runs rest to rest on the straight joint line.

    Returns:
        One PPoly per joint (time [s] → q [rad or m]), and the (n,) waypoint times [s].
    """
    nq = Q.shape[1]
    solver = _Ruckig(nq, limits)
    # per joint: the coefficient rows j/6, a/2, v, p of its pieces, then its breaks [s]
    joints: list[list[list[float]]] = [[[], [], [], [], [0.0]] for _ in range(nq)]
    times = [0.0]
    if V is not None:
        V = _within_position_limits(solver, Q, V, limits)
    for i in range(len(Q) - 1):
        profiles, T = (solver.segment(Q[i], Q[i + 1]) if V is None
                       else solver.segment(Q[i], Q[i + 1], V[i], V[i + 1]))
        t0 = times[-1]
        for rows, prof in zip(joints, profiles, strict=True):
            _add_phases(rows, prof, t0, T)
        times.append(T + t0)
    return _ppolys(joints), times


def _within_position_limits(solver: _Ruckig, Q: Array, V: Array, limits: Limits) -> Array:
    """``V`` with both end velocities of each segment that leaves the position limits set to 0.

    Such a segment then runs rest to rest on the straight joint line between two waypoints
    within the limits; the segment before it, whose end velocity changed, is checked again.
    """
    V = V.copy()
    i = 0
    while i < len(Q) - 1:
        solver.segment(Q[i], Q[i + 1], V[i], V[i + 1])
        if solver.leaves(limits) and (V[i].any() or V[i + 1].any()):
            V[i] = V[i + 1] = 0.0
            i = max(i - 1, 0)
            continue
        i += 1
    return V


def ruckig_segment(qa: Array, qb: Array, limits: Limits) -> tuple[list[PPoly], float]:
    """Rest-to-rest Ruckig motion from ``qa`` to ``qb``: one PPoly per joint, and its duration."""
    pieces, times = _timed_pieces(np.array([qa, qb], dtype=float), limits)
    return list(pieces), times[-1]


def ruckig_trajectory(Q: Array, limits: Limits, duration: float | None = None) -> Trajectory:
    """Jerk-limited trajectory through ``Q`` (n, nq), moving through the interior waypoints.

    Two waypoints: Ruckig's time-optimal rest-to-rest move. Three or more: the shorter of
    Ruckig moves joined at velocities chosen from the path and Ruckig along the path
    parameter (:mod:`scara_opt.trajectory.passing`; the community Ruckig has no
    intermediate waypoints), both within the velocity, acceleration and jerk limits.

    Args:
        Q: waypoints [rad or m], validated by :func:`~scara_opt.trajectory.time_parameterize`.
        limits: joint velocity, acceleration and jerk limits.
        duration: must be ``None`` (the registry refuses a fixed duration for ruckig).

    Raises:
        TrajectoryError: Ruckig failed on a segment.
    """
    if len(Q) == 2:
        pieces, times = _timed_pieces(Q, limits)
        return Trajectory(pieces, limits, "ruckig", Q.copy(), np.array(times),
                          notes="ruckig: time-optimal rest to rest")
    pieces, times = _timed_pieces(Q, limits, passing.passing_velocities(Q, limits))
    joined = Trajectory(pieces, limits, "ruckig", Q.copy(), np.array(times),
                        notes="ruckig: segments joined at velocities chosen from the path "
                              "(community Ruckig: no intermediate waypoints)")
    along = along_path(Q, limits)
    return along if along is not None and along.duration < joined.duration else joined


def along_path(Q: Array, limits: Limits) -> Trajectory | None:
    """Ruckig along the path parameter of toppra's spline through ``Q`` (n, nq), or ``None``.

    See :mod:`scara_opt.trajectory.passing`; ``None`` where the path allows no positive
    bound on its speed (then the joined segments are used). Joint ratios above 1 left by
    the curvature terms are removed by a uniform time stretch, said in the notes.
    """
    cs, s = passing.spline(Q, limits)
    V, U, _, _ = passing.path_bounds(cs, s, limits)
    low = LIMIT_RANGES["vmax"][0]
    if not (V >= low and U >= low):  # NaN too: a path the joints cannot run along here
        return None
    V, U = min(V, LIMIT_RANGES["vmax"][1]), min(U, LIMIT_RANGES["amax"][1])
    one = resolve_limits(None, 1, V, U, JERK_PER_ACCELERATION * U, need_jerk=True)
    ps = _timed_pieces(np.array([[0.0], [1.0]]), one)[0][0]
    pieces, knots = passing.compose(cs, ps, s)
    traj = Trajectory(pieces, limits, "ruckig", Q.copy(), knots)
    ratios = traj.check_limits()
    factor = max(1.0, float(ratios["velocity"].max()), math.sqrt(ratios["acceleration"].max()),
                 float(np.cbrt(ratios["jerk"].max())))
    note = (f"ruckig along the path parameter (community Ruckig: no intermediate waypoints): "
            f"|s'| <= {V:.4g}/s, |s''| <= {U:.4g}/s²")
    if factor > 1.0:
        factor *= 1.0 + 1e-9
        pieces = tuple(stretch(p, factor) for p in pieces)
        knots = knots * factor
        note += f", time stretched x {factor:.6f} (the joint ratios of the composition)"
    return Trajectory(pieces, limits, "ruckig", Q.copy(), knots, notes=note)


#: the registry entry (read by :mod:`scara_opt.trajectory.registry`)
METHOD = TimingMethod("ruckig", ruckig_trajectory, uses_jerk=True)
