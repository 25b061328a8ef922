r"""The branch sequence of a path, chosen over the whole path (Descartes-style).

Every point of the path has several IK solutions (elbow branches, wrist turns, the
shoulder's ±2π turns of an arm). :func:`candidates_closed_form` lists all of them at once
on SCARA-type robots (the closed form's branches and every whole turn within the limits),
:func:`candidates_arm` on the 6R arms a closed form serves (full poses: every branch and
turn, up to 8 × 2⁵ a point on a UR); :func:`candidates_searched` collects, on other
robots, the distinct solutions a seeded multi-start finds, each point's solves also
continuing every solution of the point before (so every track, the greedy walk's first,
is followed). :func:`least_cost_walk` then picks
one solution per point by a shortest-path search over the layered graph (SciPy's
Dijkstra). Its cost is the joint travel weighted by each joint's speed limit,
:math:`\sum_k |Δq_k| / v_{max,k}` (the time each joint needs at full speed), the step from a
given start configuration included. A step where some joint moves more than its jump
threshold is a *jump*. With ``fewest_jumps`` (a Cartesian path to follow, where a jump
breaks it) the threshold is a hard limit: the fewest jumps first, a jump off the start
configuration before all of the path's own, then the least travel among those walks.
Without (poses to visit, where every step is a free move), the least travel alone: no
sequence of the candidates travels less, and the jumps it takes are reported. Where one
branch covers the whole path there is no jump; where none does, each jump names the point
that forces it: the first point that the configuration before the jump cannot reach
without one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import breadth_first_order, dijkstra

from scara_opt.ik.arm_geometry import arm_model
from scara_opt.ik.arm_route import all_solutions
from scara_opt.ik.base import Solver
from scara_opt.ik.geometry import NotScaraError, ScaraGeometry, scara_geometry, solve_batch
from scara_opt.ik.result import IKResult
from scara_opt.ik.turns import TURN, turn_joints
from scara_opt.model.robot import Robot
from scara_opt.target import Target

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]

#: solutions closer than this in every joint are the same [rad or m]
DISTINCT = 1e-6
#: fresh random starts of the multi-start at the first point, and at every later point
FIRST_STARTS, LATER_STARTS = 8, 2
#: most solutions kept per point by the multi-start (continuations of the tracks first)
MAX_CANDIDATES = 8
#: task dimension of each target kind (position, tool angle, rotation)
TASK_DIMENSION = {"position": 3, "yaw": 4, "rotation": 6}


@dataclass(frozen=True)
class Walk:
    """The least-cost choice of one candidate per point.

    Attributes:
        choice: (n,) index of the chosen candidate of each point.
        jumps: steps ``i`` (point ``i - 1`` to ``i``) above the threshold.
        forced_by: per jump, the first point that the configuration before it cannot
            reach without a jump (``None`` if it could: not on a least-cost walk).
        start_jump: the step from ``q_start`` to point 0 is above the threshold.
        travel: the weighted joint travel of the walk [s].
    """

    choice: NDArray[np.intp]
    jumps: tuple[int, ...]
    forced_by: tuple[int | None, ...]
    start_jump: bool
    travel: float


def travel_weights(robot: Robot) -> Array:
    """(nq,) weights of the joint travel: ``1 / vmax`` [s/rad or s/m], ones without limits.

    Where a joint has no finite velocity limit, every joint weighs 1 (travel in rad and m).
    """
    v = robot.velocity_limit
    if np.isfinite(v).all() and (v > 0).all():
        return 1.0 / v
    return np.ones(robot.nq)


def _steps(A: Array, B: Array, threshold: Array, w: Array) -> tuple[Array, Mask]:
    """Weighted travel and over-threshold flag of every pair: ``A`` (..., Ka, nq) to ``B``."""
    D = np.abs(B[..., None, :, :] - A[..., :, None, :])  # (..., Ka, Kb, nq)
    return D @ w, np.asarray((D > threshold).any(axis=-1))


#: above this many step entries (n - 1) K² nq, the walk goes layer by layer (memory)
LAYERED = 4_000_000


def least_cost_walk(Q: Array, valid: Mask, threshold: Array, weights: Array,
                    q_start: Array | None = None, fewest_jumps: bool = True) -> Walk:
    """The walk through one valid candidate per point of least travel (fewest jumps first).

    Args:
        Q: (n, K, nq) candidates of each point [rad or m] (rows where ``valid`` is False
            are ignored).
        valid: (n, K) which candidates exist; every point needs at least one.
        threshold: (nq,) per-joint step above which a step is a jump [rad or m].
        weights: (nq,) travel weights (:func:`travel_weights`).
        q_start: (nq,) configuration before point 0, or ``None``: its step to point 0
            counts in the travel, and a jump off it before all of the path's own (the
            walk keeps q_start's branch at point 0 wherever some walk can).
        fewest_jumps: the fewest jumps first, then the least travel among those walks;
            ``False``: the least travel alone (jumps are only reported).

    Returns:
        Walk: the choice, its jumps and what forces each. Small candidate sets go through
        SciPy's Dijkstra over the whole layered graph at once; sets above
        :data:`LAYERED` (an arm's every branch and turn, 256 a point on a UR) through the
        same order of walks layer by layer (:func:`_layered_walk`): the same optimum.
    """
    n, K, nq = Q.shape
    if q_start is not None:
        t0, o0 = _steps(q_start[None, :], Q[0], threshold, weights)
        t0, o0 = t0[0], o0[0]
    else:
        t0, o0 = np.zeros(K), np.zeros(K, dtype=bool)
    if (n - 1) * K * K * nq > LAYERED:
        return _layered_walk(Q, valid, threshold, weights, t0, o0, fewest_jumps)
    travel, over = _steps(Q[:-1], Q[1:], threshold, weights)  # (n-1, K, K)
    edge = valid[:-1, :, None] & valid[1:, None, :]
    # a jump costs more than any walk's whole travel: the fewest jumps win, then travel;
    # without fewest_jumps a jump costs its travel alone
    penalty = 0.0
    if fewest_jumps:
        finite = np.where(edge, travel, 0.0)
        penalty = 1.0 + float(finite.max(axis=(1, 2)).sum()) + float(np.where(valid[0], t0,
                                                                               0.0).max())
    # nodes: 0 the source, 1 + i*K + k the candidates, 1 + n*K the sink
    i, a, b = np.nonzero(edge)
    src = np.flatnonzero(valid[0])
    last = np.flatnonzero(valid[-1])
    rows = np.concatenate([np.zeros(src.size, np.intp), 1 + i * K + a, 1 + (n - 1) * K + last])
    cols = np.concatenate([1 + src, 1 + (i + 1) * K + b, np.full(last.size, 1 + n * K)])
    # a jump off q_start counts before all of the path's own (n - 1 at most)
    cost = np.concatenate([t0[src] + n * penalty * o0[src],
                           travel[i, a, b] + penalty * over[i, a, b], np.zeros(last.size)])
    graph = csr_matrix((cost, (rows, cols)), shape=(n * K + 2, n * K + 2))
    dist, pred = dijkstra(graph, indices=0, return_predecessors=True)
    if not math.isfinite(dist[-1]):  # pragma: no cover - every point has a candidate
        raise ValueError("no walk through the candidates: a point has none")
    nodes = []
    node = pred[-1]
    while node > 0:
        nodes.append(node)
        node = pred[node]
    choice = (np.array(nodes[::-1], dtype=np.intp) - 1) % K
    steps = np.arange(n - 1)
    jumped = over[steps, choice[:-1], choice[1:]]
    jumps = tuple(int(s) + 1 for s in np.flatnonzero(jumped))
    forced = _forcing_points(edge & ~over, jumps, choice) if jumps else ()
    walked = float(travel[steps, choice[:-1], choice[1:]].sum()) + float(t0[choice[0]])
    return Walk(choice, jumps, forced, bool(o0[choice[0]]), walked)


def _layered_walk(Q: Array, valid: Mask, threshold: Array, weights: Array, t0: Array,
                  o0: Mask, fewest_jumps: bool = True) -> Walk:
    """:func:`least_cost_walk` by dynamic programming over the layers (Viterbi).

    Each candidate keeps the best (jumps, travel) of the walks reaching it, compared in
    that order (a jump off ``q_start`` counts as ``n``; without ``fewest_jumps`` no jump
    counts, travel alone); one layer's steps (K, K, nq)
    exist at a time, so memory grows with ``n K²`` booleans (the steps within the
    threshold, for the forcing points), not ``n K² nq`` floats.
    """
    n, K, _ = Q.shape
    big = np.iinfo(np.int64).max // 4
    counts = int(fewest_jumps)  # what a jump adds to a walk's count
    J = np.where(valid[0], counts * n * o0.astype(np.int64), big)
    T = np.where(valid[0], t0, np.inf)
    pred = np.zeros((n - 1, K), dtype=np.intp)
    allowed = np.zeros((n - 1, K, K), dtype=bool)
    cols = np.arange(K)
    for i in range(n - 1):
        travel, over = _steps(Q[i], Q[i + 1], threshold, weights)
        edge = valid[i][:, None] & valid[i + 1][None, :]
        allowed[i] = edge & ~over
        Jc = np.where(edge, J[:, None] + counts * over, big)
        best_j = Jc.min(axis=0)
        Tc = np.where(Jc == best_j[None, :], T[:, None] + travel, np.inf)
        pred[i] = Tc.argmin(axis=0)
        J = np.where(valid[i + 1], best_j, big)
        T = np.where(valid[i + 1], Tc[pred[i], cols], np.inf)
    ends = np.flatnonzero(J == J.min())
    end = int(ends[np.argmin(T[ends])])
    if J[end] >= big:  # pragma: no cover - every point has a candidate
        raise ValueError("no walk through the candidates: a point has none")
    choice = np.zeros(n, dtype=np.intp)
    choice[-1] = end
    for i in range(n - 2, -1, -1):
        choice[i] = pred[i, choice[i + 1]]
    steps = np.arange(n - 1)
    jumped = ~allowed[steps, choice[:-1], choice[1:]]
    jumps = tuple(int(s) + 1 for s in np.flatnonzero(jumped))
    forced = _forcing_points(allowed, jumps, choice) if jumps else ()
    d = np.abs(np.diff(Q[np.arange(n), choice], axis=0))
    walked = float((d @ weights).sum()) + float(t0[choice[0]])
    return Walk(choice, jumps, forced, bool(o0[choice[0]]), walked)


def redundant(robot: Robot, targets: Sequence[Target]) -> bool:
    """Whether some target leaves the robot joints to spare: its solutions form a continuum.

    There the multi-start's tracks are samples of the continuum rather than branches, and
    their travels compare arbitrary choices (a track riding on a joint limit may travel
    least): the caller keeps the first track, the greedy walk, unless another has fewer
    jumps.
    """
    return any(TASK_DIMENSION[t.kind] < robot.nq for t in targets)


def _forcing_points(allowed: Mask, jumps: tuple[int, ...],
                    choice: NDArray[np.intp]) -> tuple[int | None, ...]:
    """Per jump at step ``j``, the first point candidate ``choice[j - 1]`` reaches by a jump.

    ``None`` where it reaches the end without one. A breadth-first search (SciPy) over
    the steps within the threshold, ``allowed`` (n - 1, K, K): the first layer after the
    last one it reaches.
    """
    m, K, _ = allowed.shape
    i, a, b = np.nonzero(allowed)
    graph = csr_matrix((np.ones(i.size), (i * K + a, (i + 1) * K + b)),
                       shape=((m + 1) * K, (m + 1) * K))
    out = []
    for j in jumps:
        reached = breadth_first_order(graph, (j - 1) * K + int(choice[j - 1]), directed=True,
                                      return_predecessors=False)
        last = int(reached.max()) // K
        out.append(None if last == m else last + 1)
    return tuple(out)


def _geometry(robot: Robot) -> ScaraGeometry | None:
    try:
        return scara_geometry(robot)
    except NotScaraError:
        return None


def candidates_closed_form(robot: Robot, targets: Sequence[Target],
                           q_ref: Array) -> tuple[Array, Mask] | None:
    """Every closed-form solution of every target: (n, K, nq) and (n, K) valid, or ``None``.

    Both elbow branches and each whole turn of the turnable joints (:mod:`scara_opt.ik.turns`)
    within the limits. A position-only target leaves the wrist where ``q_ref`` has it.
    ``None`` where the closed form does not list every solution: a robot that is not
    SCARA-type or has redundant joints, rotation targets, or position and yaw targets mixed.
    Candidates are checked here against the limits only; the caller checks residuals.
    """
    g = _geometry(robot)
    kinds = {t.kind for t in targets}
    if g is None or g.redundant or len(kinds) != 1 or "rotation" in kinds:
        return None
    P = np.array([t.position for t in targets])
    yaws = np.array([t.yaw for t in targets]) if kinds == {"yaw"} else None
    if yaws is not None and g.wrist < 0:
        return None
    Q, valid = solve_batch(robot, P, yaws)
    if yaws is None and g.wrist >= 0:
        Q[:, :, g.wrist] = q_ref[g.wrist]
    solved = {g.shoulder, g.elbow} | ({g.wrist} if yaws is not None else set())
    for k, lo, hi in turn_joints(robot):
        if k not in solved:
            continue
        if math.isfinite(hi - lo):  # solve_batch puts each angle within π of mid-range
            M = math.floor(((hi - lo) / 2 + math.pi) / TURN)
        else:  # a continuous joint: the turns about q_ref's
            Q[:, :, k] += TURN * np.round((q_ref[k] - Q[:, :, k]) / TURN)
            M = 1
        m = np.arange(-M, M + 1)
        Q = np.repeat(Q, m.size, axis=1)
        valid = np.repeat(valid, m.size, axis=1)
        Q[:, :, k] += np.tile(m * TURN, Q.shape[1] // m.size)[None, :]
        valid &= (Q[:, :, k] >= lo) & (Q[:, :, k] <= hi)
    return Q, valid


def candidates_arm(robot: Robot, targets: Sequence[Target], q_ref: Array,
                   tol: float) -> tuple[Array, Mask, str] | None:
    """Every solution of every full pose on a 6R arm that a closed form serves, or ``None``.

    Every branch and every whole turn within the limits (:func:`~scara_opt.ik.arm_route.
    all_solutions`): (n, K, nq), (n, K) valid, and the route. ``None`` unless every target
    is a full pose and the robot is a 6R arm of :mod:`~scara_opt.ik.arm_geometry`'s cases
    (a 7R arm's held joint would be sampled: its solutions are a continuum).
    """
    if any(t.rotation is None for t in targets):
        return None
    model = arm_model(robot)
    if model is None or model.held is not None:
        return None
    found = []
    route = ""
    for t in targets:
        sols, route = all_solutions(robot, model, t, q_ref, tol)
        found.append(sols)
    K = max(1, max(len(f) for f in found))
    Q = np.zeros((len(targets), K, robot.nq))
    valid = np.zeros((len(targets), K), dtype=bool)
    for i, sols in enumerate(found):
        if sols:
            Q[i, :len(sols)] = sols
            valid[i, :len(sols)] = True
    return Q, valid, route


def candidates_searched(robot: Robot, targets: Sequence[Target], solver: Solver,
                        q_start: Array | None, seed: int | None, tol: float
                        ) -> tuple[Array, Mask, list[list[IKResult]]]:
    """The distinct solutions a seeded multi-start finds at each point, tracks continued.

    At point ``i`` the solver runs from each solution kept at point ``i - 1`` (``q0``;
    ``q_start`` for point 0), then from :data:`FIRST_STARTS` (point 0) or
    :data:`LATER_STARTS` fresh uniform starts; the solved, distinct answers are kept, at
    most :data:`MAX_CANDIDATES`, continuations first. Point ``i`` solves with seed
    ``seed + i``, as the greedy walk does, so the first track is the greedy walk. A point
    nothing solves keeps its first answer alone (its verdict says why).

    Returns:
        ``(Q, valid, results)``: (n, K, nq), (n, K), and the results of each point's kept
        candidates.
    """
    rng = np.random.default_rng(seed)
    lo, hi = robot.sampling_lower, robot.sampling_upper
    kept: list[list[IKResult]] = []
    prev: list[Array | None] = [q_start]
    for i, target in enumerate(targets):
        fresh = rng.uniform(lo, hi, (FIRST_STARTS if i == 0 else LATER_STARTS, robot.nq))
        s = None if seed is None else seed + i
        found: list[IKResult] = []
        first = None
        for q0 in [*prev, *fresh]:
            res = solver.solve(robot, target, q0=q0, seed=s, tol=tol)
            if first is None:
                first = res
            if res.success and all(np.abs(res.q - r.q).max() > DISTINCT for r in found):
                found.append(res)
                if len(found) == MAX_CANDIDATES:
                    break
        if not found:
            assert first is not None, "every point is solved from at least one start"
            found = [first]
        kept.append(found)
        prev = [r.q for r in found]
    K = max(len(f) for f in kept)
    Q = np.zeros((len(targets), K, robot.nq))
    valid = np.zeros((len(targets), K), dtype=bool)
    for i, found in enumerate(kept):
        Q[i, :len(found)] = [r.q for r in found]
        valid[i, :len(found)] = True
    return Q, valid, kept
