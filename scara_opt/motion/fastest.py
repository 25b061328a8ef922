"""``objective="time"``: the PTP of least duration proven clear, judged by time, not length.

A planned path is short in joint space (OMPL's L2 norm adds radians and metres); toppra
then times it. Under ``objective="time"`` :func:`~scara_opt.motion.plan` judges each
stop-to-stop PTP by its timed duration instead, every candidate proven clear by the
proof of every trajectory (:func:`~scara_opt.collision.continuous.check_path` on the
motion itself, time as its parameter: :func:`as_path`):

1. **The bound itself.** Ruckig's time-synchronized move from start to goal
   (:func:`~scara_opt.trajectory.bound.synchronized_move`): each joint time-optimal,
   stretched to the slowest joint's time, so its duration *is* the lower bound. Where it
   is proven clear (in empty space always) it is the answer.
2. Otherwise the path planned as for ``objective="length"`` (the same seed, the same
   path), and **more paths with other seeds** while the fastest timing is far from the
   bound (:func:`restarts`: a path around the other side of an obstacle often differs by
   seconds); the fastest is **shortcut by time**: each interior waypoint that a proven
   edge can skip is dropped, the one saving the most time metric first (each joint's
   travel over its speed limit, the slowest joint's per edge: :func:`time_metric`).
3. **Candidates judged by their timed duration**: toppra along the (shortcut) path's
   spline, as ``"length"`` times it, and Ruckig's second-order moves (no jerk limit, as
   toppra's) through the path, and from the start through one or two of its points
   (waypoints and edge middles) to the goal, joined at velocities from the path or
   resting at each point (:func:`candidates`). Fastest first, each is proven until one
   is clear (at most :data:`PROOFS`); the fastest proven one is kept. The ``"length"``
   answer is always among them, so ``"time"`` is never slower.

Everything after the planner stops at the time limit (``plan``'s ``time_limit``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.collision.checker import CollisionChecker
from scara_opt.collision.continuous import check_path
from scara_opt.errors import InputError
from scara_opt.trajectory.bound import lower_bound, second_order, synchronized_move
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.passing import passing_velocities
from scara_opt.trajectory.ruckig_backend import _timed_pieces
from scara_opt.trajectory.trajectory import Trajectory

if TYPE_CHECKING:
    from scara_opt.motion.clearance import CellPlanning

Array = NDArray[np.float64]

#: the objectives of :func:`~scara_opt.motion.plan`
OBJECTIVES = ("length", "time")

#: pairs of via points tried (those of least time metric), and the most candidates proven
PAIRS = 20
PROOFS = 12

#: paths planned for one PTP at most (another seed each), while the fastest timing found
#: is above CLOSE x the lower bound and the time limit lasts; SEED_STRIDE apart, so they
#: never take the seed of another move of the program (move i plans with seed + i)
RESTARTS = 6
CLOSE = 1.1
SEED_STRIDE = 1_000_003

#: the share of the time limit the restarts leave for timing and proving
RESERVE = 0.5


def check_objective(objective: object) -> str:
    """``objective`` if it is one of :data:`OBJECTIVES`.

    Raises:
        InputError: anything else.
    """
    if not isinstance(objective, str) or objective not in OBJECTIVES:
        raise InputError(f"objective must be one of {list(OBJECTIVES)}: 'length' (the path "
                         f"short in joint space, then timed) or 'time' (the least duration "
                         f"found); got {objective!r}")
    return objective


def time_metric(Q: Array, vmax: Array) -> float:
    """Sum over the edges of ``Q`` (n, nq) of the slowest joint's travel over its speed [s]."""
    if len(Q) < 2:
        return 0.0
    return float((np.abs(np.diff(Q, axis=0)) / vmax).max(axis=1).sum())


def cannot_beat(Q: Array, vmax: Array, duration: float) -> bool:
    """Whether no timing through the points ``Q`` (n, nq) in order is shorter than ``duration``.

    Between two consecutive points each joint travels at least its difference at no more
    than ``vmax`` (nq,): any such timing lasts at least :func:`time_metric` [s].
    """
    return time_metric(Q, vmax) >= duration


def as_path(pieces: tuple[PPoly, ...]) -> PPoly:
    """One vector PPoly (values (nq,)) of per-joint PPolys, on the union of their breaks.

    The same motion, time as its parameter: :func:`~scara_opt.collision.continuous.
    check_path` proving it clear proves the timed trajectory clear.
    """
    x = np.unique(np.concatenate([p.x for p in pieces]))
    k = pieces[0].c.shape[0]
    c = np.empty((k, len(x) - 1, len(pieces)))
    for j, p in enumerate(pieces):
        for nu in range(k):
            c[k - 1 - nu, :, j] = p(x[:-1], nu) / math.factorial(nu)
    return PPoly(c, x, extrapolate=False)


def proven(checker: CollisionChecker, pieces: tuple[PPoly, ...]) -> int | None:
    """The checks of the proof that the motion ``pieces`` is clear, or None (not proven)."""
    proof = check_path(checker, as_path(pieces))
    return proof.evaluations if proof.clear else None


def synchronized(Q: Array, limits: Limits, cellp: CellPlanning | None
                 ) -> tuple[tuple, str, Array] | None:
    """The synchronized move ``Q[0]`` → ``Q[-1]`` if proven clear (no cell: always), or None.

    Returns:
        The pieces (one PPoly per joint), the note, and the knots ``[0, T]`` [s].
    """
    pieces, T = synchronized_move(Q[0], Q[-1], limits)
    knots = np.array([0.0, T])
    note = ("Ruckig's time-synchronized move (each joint time-optimal, the slowest joint's "
            "time: at the lower bound)")
    if cellp is None:
        return pieces, note, knots
    checks = proven(cellp.checker, pieces)
    if checks is None:
        return None
    return pieces, note + f", proven clear ({checks} checks)", knots


def shortcut(Q: Array, vmax: Array, edge: Callable[[Array, Array], bool],
             deadline: float = math.inf) -> Array:
    """``Q`` with each interior waypoint dropped that a proven edge skips, by time saved.

    ``edge(a, b)``: whether the straight segment ``a`` → ``b`` is proven clear. Greedy:
    the waypoint whose removal saves the most :func:`time_metric` first, again until none
    (or until ``deadline``, a ``time.perf_counter()`` instant).
    """
    Q = Q.copy()
    while len(Q) > 2:
        saves = [time_metric(Q[k - 1:k + 2], vmax) - time_metric(Q[[k - 1, k + 1]], vmax)
                 for k in range(1, len(Q) - 1)]
        for k in np.argsort(saves, kind="stable")[::-1] + 1:
            if time.perf_counter() > deadline:
                return Q
            if edge(Q[k - 1], Q[k + 1]):
                Q = np.delete(Q, k, axis=0)
                break
        else:
            return Q
    return Q


def _timings(rows: Array, limits: Limits) -> list[tuple[float, Trajectory, str]]:
    """Ruckig's second-order moves through ``rows``: joined at velocities, and resting."""
    two = second_order(limits)
    out = []
    for V, how in ((passing_velocities(rows, two) if len(rows) > 2 else None,
                    "Ruckig's second-order moves joined at velocities from the path"),
                   (None, "Ruckig's time-synchronized moves, resting at each point")):
        pieces, times = _timed_pieces(rows, two, V)
        out.append((times[-1], Trajectory(pieces, limits, "ruckig", rows, np.array(times)),
                    how))
        if len(rows) == 2:
            break
    return out


def candidates(Q: Array, limits: Limits, deadline: float = math.inf, pairs: int = PAIRS,
               limit: float = math.inf) -> list[tuple[float, Trajectory, str]]:
    """Ruckig timings through ``Q``, and through up to two of its points, fastest first.

    The points: ``Q``'s interior waypoints and the middles of its edges, one at a time,
    then the ``pairs`` pairs (in path order) of least time metric; each way from ``Q[0]``
    through them to ``Q[-1]``. Made until ``deadline`` (a ``time.perf_counter()``
    instant). A way whose :func:`time_metric` is at least ``limit`` [s] is not timed: a
    timing through its points in order moves each joint at least its travel between them
    at no more than its speed limit, so none of its timings is faster than ``limit``.
    """
    mids = (Q[:-1] + Q[1:]) / 2
    pool = np.empty((2 * len(Q) - 1, Q.shape[1]))
    pool[0::2], pool[1::2] = Q, mids
    pool = pool[1:-1]
    a, b = Q[:1], Q[-1:]
    ways = [Q] if len(Q) > 2 else []
    ways += [np.vstack([a, pool[[i]], b]) for i in range(len(pool))]
    two = [(time_metric(np.vstack([a, pool[[i, j]], b]), limits.vmax), i, j)
           for i in range(len(pool)) for j in range(i + 1, len(pool))]
    two.sort()
    ways += [np.vstack([a, pool[[i, j]], b]) for _, i, j in two[:pairs]]
    found = []
    for rows in ways:
        if time.perf_counter() > deadline:
            break
        if not cannot_beat(rows, limits.vmax, limit):
            found += _timings(rows, limits)
    found.sort(key=lambda c: c[0])
    return found


def fastest(cellp: CellPlanning, index: int, Q: Array, best: tuple, timed: Callable,
            limits: Limits, method: str) -> tuple:
    """The fastest proven timing of PTP ``index``'s planned path ``Q`` (see the module).

    ``best``: the ``"length"`` answer (pieces, note, knots, profile), kept unless a
    candidate is proven faster.
    """
    from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
    from scara_opt.planning.ompl_backend import EdgeProver

    if time.perf_counter() > cellp.deadline:
        return best
    checker = cellp.checker
    prover = EdgeProver(checker)
    Qs = shortcut(Q, limits.vmax, lambda a, b: prover.edge(tuple(a.tolist()),
                                                           tuple(b.tolist())), cellp.deadline)
    cut = f"; shortcut by time from {len(Q)} to {len(Qs)} waypoints"
    found = [(best, "")]
    if len(Qs) < len(Q) and time.perf_counter() < cellp.deadline:
        found.append((cellp._planned_timing(index, Qs, timed, limits, method), cut))
    limit = min(float(f[0][2][-1]) for f in found)
    proofs = 0
    for T, traj, how in candidates(Qs, limits, cellp.deadline, limit=limit):
        if T >= limit or proofs >= PROOFS or time.perf_counter() > cellp.deadline:
            break
        proofs += 1
        if not cellp._inside(traj):
            continue
        checks = proven(checker, traj.pieces)
        if checks is not None:
            rows = traj.waypoints
            found.append(((traj.pieces, f"{how}, through {len(rows)} points of the "
                           f"planned path, proven clear ({checks} checks)",
                           traj.waypoint_times,
                           ToolProfile.per_point([ToolLimits()] * len(rows))), ""))
            break
    (part, note, knots, profile), how = min(found, key=lambda f: float(f[0][2][-1]))
    if how == "" and note == best[1]:
        return best
    return (part, f"{note}{how}; objective time: {float(knots[-1]):.4f} s against "
                  f"{float(best[2][-1]):.4f} s timed by length", knots, profile)


def restarts(cellp: CellPlanning, run: list, Q: Array, timed: Callable, limits: Limits,
             method: str, t0: float) -> tuple[Array, tuple]:
    """The fastest proven timing of a PTP over paths planned with several seeds.

    ``Q``: the path planned with the move's own seed (``cellp.plans[index]``). Each path
    is timed as under ``"length"`` (:meth:`~scara_opt.motion.clearance.CellPlanning.
    timed_clear`); another path is planned (a homotopy class of its own often differs by
    seconds) while the best is above :data:`CLOSE` x the lower bound, up to
    :data:`RESTARTS` paths, within the time limit less its :data:`RESERVE` share (kept for
    timing and proving: no timing is cut short by the limit). A path that
    :func:`cannot_beat` the best duration is not timed: each timing of it passes through
    its waypoints (the hugging points lie on its segments). The same seed gives the same
    result as long as the restarts end within that share. The fastest is then improved by
    :func:`fastest`.

    Returns:
        The chosen path, and what ``timed_clear`` returned for it.
    """
    from scara_opt.planning.planner import SEED_MAX, plan_path

    index = run[0][0]
    bound = lower_bound(Q[0], Q[-1], limits)
    best_q, best = Q, cellp.timed_clear(run, Q, [index] * len(Q), timed, limits, method, t0)
    best_plan, tries = cellp.plans[index], 1
    reserve = RESERVE * cellp.time_limit  # kept for timing and proving what was found
    while (cellp.planned(index) and tries < RESTARTS and float(best[2][-1]) > CLOSE * bound
           and cellp.left() > reserve):
        seed = (cellp.seed + index + tries * SEED_STRIDE) % (SEED_MAX + 1)
        tries += 1
        res = plan_path(cellp.checker, Q[0], Q[-1], time_limit=cellp.left() - reserve,
                        seed=seed)
        if res.path is None or cannot_beat(res.path, limits.vmax, float(best[2][-1])):
            continue
        cellp.plans[index] = res
        got = cellp.timed_clear(run, res.path, [index] * len(res.path), timed, limits, method,
                                t0)
        if float(got[2][-1]) < float(best[2][-1]):
            best_q, best, best_plan = res.path, got, res
    cellp.plans[index] = best_plan
    if cellp.planned(index) and method == "toppra":
        best = fastest(cellp, index, best_q, best, timed, limits, method)
    if tries > 1:
        part, note, knots, profile = best
        best = (part, f"{note}; the fastest of {tries} paths planned (another seed each)",
                knots, profile)
    return best_q, best
