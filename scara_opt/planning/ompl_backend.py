"""OMPL's RRTConnect and PathSimplifier, with every state and edge checked by our proof.

OMPL (the ``ompl`` wheel, nanobind bindings) samples and connects; it never decides what
is free. The state validity checker and the motion validator are :class:`EdgeProver`: a
state is valid when every pair of bodies is farther than the margin, an edge when the
conservative rule of :mod:`scara_opt.collision.continuous` proves the straight joint
segment clear. OMPL's own discrete motion validator (states every ``resolution`` of the
space's extent) is not used: it steps over thin obstacles.

The OMPL objects of one query are made and dropped inside :func:`rrt_connect`, and the
Python callbacks hold no reference back to them: no reference cycle through C++ survives
the call (nanobind would report the leak at exit). OMPL's console output is silenced during
the call and its global random seed set from ``seed`` (OMPL wants a seed > 0: ``seed + 1``);
a lock keeps concurrent queries from interleaving their seeds.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from operator import itemgetter
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.collision.checker import CollisionChecker
from scara_opt.collision.continuous import DISTANCE_TOL, RESOLUTION
from scara_opt.collision.edge_kernel import NativeProver

Array = NDArray[np.float64]

#: a SCARA's gaps (above, below) of each pair along its axis at one configuration [m]
Heights = tuple[list[float], list[float]]

__all__ = ["EdgeProver", "OmplRun", "box_space", "import_ompl", "rrt_connect", "start_and_goal"]

_LOCK = threading.Lock()

#: RRTConnect's longest extension, as a fraction of the joint box's diagonal (OMPL's default
#: is 0.2; long edges far from obstacles are proven in few steps here: 0.4 planned the
#: cells of benchmarks/bench_plan.py 15-45 % faster than 0.2). 0.25, tried with the mesh
#: kernel's warm GJK (10 pairs a cell, medians a call): the SCARAs and the capsule arm
#: about 6 % faster and durations 1-2 % shorter, but the UR5's meshes on the benchmark's
#: pairs 74, 50, 94 against 67, 60, 57 ms per cell: kept 0.4
RANGE = 0.4

#: rounds of partial shortcuts (after one rope shortcut), and steps of B-spline smoothing,
#: in :func:`simplify_path`
SHORTCUT_ROUNDS = 1
SMOOTHING_STEPS = 2

#: the rope shortcut's spacing of the states it puts on the path is OMPL's default (1.0 in
#: the space's units) or this fraction of the joint box's diagonal, the larger: it asks
#: for an edge from every state to each state beyond it, and 1.0 is 0.035 of the UR5's
#: box. Tried on the cells of benchmarks/bench_plan.py (10 pairs a cell, the same seeds,
#: medians a call, sums of the durations): the UR5's meshes 65.4 -> 51.4 ms (a busy
#: machine; bench_plan's own run: 67.7 -> 35.0 ms, 2.45 -> 1.33 of OMPL's), durations
#: +0.8 %; the capsule arm, the IRB-like and the large SCARA 4-11 % faster, durations
#: -0.8 to +0.3 %; 0.2 was faster still but its durations up to 2.4 % longer. As a
#: fraction alone (0.73 on the 0.2 + 0.2 m SCARA, finer than 1.0) it lengthened the
#: guide's pick-and-place move past the rack from 0.87 to 1.26 s
ROPE_DELTA = 0.1

#: how far [m] a piece of a proven edge may stray from it (rounding) and still be taken as
#: proven (:meth:`EdgeProver.inside_known`): half the proofs' tolerance
SUBSEGMENT_SLACK = DISTANCE_TOL / 2

#: install hint when the wheel is missing
OMPL_HINT = "pip install ompl (OMPL's Python wheel, 2.0 or later)"


def import_ompl() -> tuple[ModuleType, ModuleType, ModuleType]:
    """``(ompl.base, ompl.geometric, ompl.util)``, or ModuleNotFoundError naming the wheel."""
    try:
        from ompl import base as ob
        from ompl import geometric as og
        from ompl import util as ou
    except ImportError as exc:
        raise ModuleNotFoundError(f"planning around obstacles needs OMPL ({exc}); "
                                  f"{OMPL_HINT}", name="ompl") from None
    return ob, og, ou


class EdgeProver:
    """States and straight joint edges checked by the conservative rule, with counts.

    Distances are cached per configuration (OMPL asks for the same states many times).
    Where the checker's compiled kernel runs (:mod:`~scara_opt.collision.edge_kernel`: a
    compiler), states and edges are proven in C++ (:class:`~scara_opt.collision.
    edge_kernel.NativeProver`), with the same verdicts and counts as the Python form below
    (``native=False``, or no compiler) for primitives (for meshes, as sound, other counts):
    its distances are Python floats, with a few pairs plain loops beat numpy's per-call
    overhead.

    Attributes:
        states: configurations whose distances were all computed (states asked about).
        midpoints: configurations inside edges where some pairs' distances were computed.
        edges: edges asked about; ``proven``: those proven clear.
        known: the edges proven so far, both directions (an edge asked again, as the
            simplified path's are at the end, is not proven again), and the pieces of
            proven edges found by :meth:`inside_known`.
        refused: the edges the rule did not prove, both directions: asked again (OMPL's
            rope shortcut asks the same far edges after each shortcut it takes), they are
            refused at once; the rule's verdict on an edge is the same every time.
        pieces: whether :meth:`edge` looks for the edge on a proven one
            (:meth:`inside_known`): on for the simplified path's final check with meshes,
            where OMPL's pieces of edges are.
        deadline: a ``time.perf_counter()`` instant (``inf``: none) after which an edge
            not proven yet is answered "not proven" at once: the simplifier then keeps the
            path it has (every edge of which is proven). ``late`` counts those answers.
    """

    def __init__(self, checker: CollisionChecker, native: bool = True) -> None:
        self.checker = checker
        self.shift = checker.margin + DISTANCE_TOL
        self.W = checker.weights
        self.cache: dict[tuple[float, ...], list[float]] = {}
        gaps = checker.gaps
        self.gaps: dict[tuple[float, ...], Heights] = {}
        self._gaps = None if gaps is None else (gaps[0], gaps[1] - self.shift,
                                                 gaps[2] - self.shift)
        self._states = 0
        self._midpoints = 0
        self.edges = 0
        self.proven = 0
        self.late = 0
        self.deadline = math.inf
        self.known: set[tuple[tuple[float, ...], tuple[float, ...]]] = set()
        self.refused: set[tuple[tuple[float, ...], tuple[float, ...]]] = set()
        self.pieces = False
        self._lines: list[tuple[Array, Array]] = []  # the edges proven by the rule
        self._stacked: tuple[Array, Array, Array] | None = None  # as arrays: P, D, |D|^2
        self._data = checker._data()
        self._meshy = checker._meshes.any
        self._model = checker.robot.model
        kernel = checker._kernel() if native else None
        self._native = None if kernel is None else NativeProver(kernel, self.W, self._gaps)

    @functools.cached_property
    def _linear(self) -> bool:
        """Whether the robot's joints interpolate linearly (see :func:`_linear`).

        Found once, and only by the Python form: walking pinocchio's joints costs ~0.1 ms.
        """
        return _linear(self._model)

    @property
    def states(self) -> int:
        """Configurations whose distances were all computed (states asked about)."""
        return self._states if self._native is None else self._native.states

    @property
    def midpoints(self) -> int:
        """Configurations inside edges where some pairs' distances were computed."""
        return self._midpoints if self._native is None else self._native.midpoints

    def distances(self, key: tuple[float, ...]) -> list[float]:
        """Signed distances minus margin and tolerance (npairs,) at ``key`` (cached)."""
        if self._native is not None:
            return self._native.distances(key)
        D = self.cache.get(key)
        if D is None:
            D = self.cache[key] = self._compute(np.array(key))
        return D

    def heights(self, key: tuple[float, ...]) -> Heights | None:
        """Gaps above and below each pair's obstacle along a SCARA's axis at ``key``.

        Less the margin and tolerance; ``None`` for other robots; cached.
        """
        if self._gaps is None:
            return None
        G = self.gaps.get(key)
        if G is None:
            A, a, b = self._gaps
            h = A @ np.array(key)
            G = self.gaps[key] = ((h + a).tolist(), (b - h).tolist())
        return G

    def _compute(self, q: Array) -> list[float]:
        import pinocchio as pin

        self._states += 1
        shift = self.shift
        if self._meshy:  # the checker's rules for meshes (the inside test of a solid)
            return (self.checker.pair_distances(q[None, :], None, "rest")[0] - shift).tolist()
        data, gdata, results = self._data
        pin.computeDistances(self._model, data, self.checker.model, gdata, q)
        return [r.min_distance - shift for r in results]

    @property
    def configurations(self) -> int:
        """Configurations checked: whole states and midpoints of edges."""
        return self.states + self.midpoints

    def valid(self, key: tuple[float, ...]) -> bool:
        """Whether every pair is farther than the margin at ``key``."""
        if self._native is not None:
            return self._native.valid(key)
        return min(self.distances(key), default=1.0) > 0

    def edge(self, a: tuple[float, ...], b: tuple[float, ...]) -> bool:
        """Whether the straight segment from ``a`` to ``b`` is proven clear.

        The rule of :mod:`scara_opt.collision.continuous` on one segment, its intervals
        taken middle first (a collision is found early): for an interval of length ``w`` (a
        fraction of the segment), the pairs with ``w M < D0 + D1`` are proven on it; for
        the others, their distances at its middle are computed (a contact there ends it)
        and both halves are queued with them alone (:meth:`_split`).
        """
        self.edges += 1
        if (a, b) in self.known:
            return True
        if self.pieces and self.inside_known(a, b):
            self.known.add((a, b))
            self.known.add((b, a))
            return True
        if (a, b) in self.refused:
            return False
        if time.perf_counter() > self.deadline:  # out of time: not proven, not tried
            self.late += 1
            return False
        if self._native is not None:  # the same rule, compiled
            clear = self._native.edge(a, b, RESOLUTION)
        else:
            clear = self._prove(a, b)
        if not clear:
            self.refused.add((a, b))
            self.refused.add((b, a))
            return False
        self.proven += 1
        self.known.add((a, b))
        self.known.add((b, a))
        if a != b:
            self._lines.append((np.array(a), np.array(b)))
        return True

    def inside_known(self, a: tuple[float, ...], b: tuple[float, ...]) -> bool:
        r"""Whether ``a`` -> ``b`` lies on an edge proven by the rule (to rounding).

        As OMPL's pieces of edges do: the smoother halves every edge (twice), a shortcut
        keeps the part of an edge up to the point it leaves from, all ending at rounded
        points. For a proven edge from :math:`p` along :math:`d`, let :math:`t_x = (x - p)
        \cdot d / |d|^2` and :math:`e_x = x - p - t_x d` for :math:`x = a, b`. With both
        :math:`t \in [0, 1]`, the point :math:`(1 - s) a + s b` is :math:`(1 - s) e_a + s
        e_b` off the edge's point at :math:`(1 - s) t_a + s t_b`. A pair's distance on
        the proven edge is more than margin + :data:`DISTANCE_TOL` (the proof), and a move
        by :math:`x` changes it by at most :math:`W |x|` (:mod:`~scara_opt.collision.
        bound`), here at most :math:`\max(W |e_a|, W |e_b|)`; this accepts only
        :math:`\le` :data:`SUBSEGMENT_SLACK` for every pair, so every pair stays more than
        the margin apart.
        """
        if not self._lines:
            return False
        if self._stacked is None or len(self._stacked[0]) != len(self._lines):
            P = np.array([p for p, _ in self._lines])
            D = np.array([q for _, q in self._lines]) - P
            self._stacked = P, D, np.einsum("ij,ij->i", D, D)
        P, D, dd = self._stacked
        ends, ts = [], []
        for x in (np.array(a), np.array(b)):
            t = np.einsum("ij,ij->i", x - P, D) / dd
            ends.append(x)
            ts.append(t)
        on = (ts[0] >= 0) & (ts[0] <= 1) & (ts[1] >= 0) & (ts[1] <= 1)
        if not on.any():
            return False
        P, D = P[on], D[on]
        stray = np.zeros(len(P))
        for x, t in zip(ends, ts, strict=True):
            e = np.abs(x - P - t[on, None] * D)
            stray = np.maximum(stray, (e @ self.W.T).max(axis=1, initial=0.0))
        return bool((stray <= SUBSEGMENT_SLACK).any())

    def _prove(self, a: tuple[float, ...], b: tuple[float, ...]) -> bool:
        """:meth:`edge`'s rule in Python: from the ends, then :meth:`_split`."""
        Da = self.distances(a)
        if min(Da, default=1.0) <= 0:  # refused at its start: its end is not computed
            return False
        Db = self.distances(b)
        if min(Db, default=1.0) <= 0:
            return False
        qa = np.array(a)
        dq = np.array(b) - qa
        M = (self.W @ np.abs(dq)).tolist()
        pairs = [k for k, (m, d0, d1) in enumerate(zip(M, Da, Db, strict=True))
                 if not m < d0 + d1]
        ga, gb = self.heights(a), self.heights(b)
        G = None if ga is None or gb is None else (ga, gb)
        if G is not None and pairs:  # apart along the axis at both ends: all along (affine)
            pairs = [k for k in pairs if not _apart(G, k, 0.0, 1.0)]
        return not pairs or self._split(a, b, M, pairs, Da, Db, G)

    def _split(self, a: tuple[float, ...], b: tuple[float, ...], M: list[float],
               pairs: list[int], Da: list[float], Db: list[float],
               G: tuple[Heights, Heights] | None) -> bool:
        """The intervals of :meth:`edge` not proven from the ends alone, split until they are.

        ``pairs``: those not proven on the whole segment; ``M`` their bounds (all pairs'),
        ``Da``, ``Db`` the distances at the ends (less margin and tolerance). Each pair's
        stretches of the segment where it is apart along a SCARA's axis (``G``) are worked
        out once (:func:`_apart_spans`).
        """
        import pinocchio as pin

        data, gdata, _ = self._data
        model, gmodel, shift = self._model, self.checker.model, self.shift
        distance, place = pin.computeDistance, pin.updateGeometryPlacements
        qa, qb = np.array(a), np.array(b)
        if self._linear:  # pinocchio's interpolation: qa + s (qb - qa) in one call
            interpolate, mdl = pin.interpolate, self._model

            def config(s: float) -> Array:
                return interpolate(mdl, qa, qb, s)
        else:
            dq = qb - qa

            def config(s: float) -> Array:
                return qa + s * dq
        spans = None if G is None else {k: _apart_spans(G, k) for k in pairs}
        wide = RESOLUTION / min(M[k] for k in pairs)  # wider intervals do not graze
        queue = deque([(0.5, 0.0, pairs, [Da[k] for k in pairs], [Db[k] for k in pairs])])
        while queue:
            h, s0, pairs, D0, D1 = queue.popleft()  # h: half the interval's length
            if 2 * h < wide and 2 * h * max(M[k] for k in pairs) < RESOLUTION:
                return False  # grazing: not proven
            self._midpoints += 1
            if self._meshy:  # the checker's bounds for meshes
                Dm = (self.checker.pair_distances(config(s0 + h)[None, :], np.array(pairs))[0]
                      - shift).tolist()
            else:
                place(model, data, gmodel, gdata, config(s0 + h))
                Dm = [distance(gmodel, gdata, k).min_distance - shift for k in pairs]
            if min(Dm) <= 0:
                return False
            for lo, d_lo, d_hi in ((s0, D0, Dm), (s0 + h, Dm, D1)):
                hi = lo + h
                if spans is None:
                    open_ = [i for i, k in enumerate(pairs) if not h * M[k] < d_lo[i] + d_hi[i]]
                else:
                    open_ = [i for i, k in enumerate(pairs)
                             if not h * M[k] < d_lo[i] + d_hi[i]
                             and not ((sp := spans[k])[0] < lo and hi < sp[1]
                                      or sp[2] < lo and hi < sp[3])]
                if open_:
                    queue.append((h / 2, lo, [pairs[i] for i in open_],
                                  [d_lo[i] for i in open_], [d_hi[i] for i in open_]))
        return True

    def path(self, Q: Array) -> bool:
        """Whether every edge of the polyline ``Q`` (n, nq) is proven clear."""
        keys = [tuple(q) for q in Q.tolist()]
        return all(self.edge(a, b) for a, b in zip(keys, keys[1:], strict=False))


def _apart_spans(G: tuple[Heights, Heights], k: int) -> tuple[float, float, float, float]:
    """Where pair ``k`` is apart along the axis on a segment: ``(u0, u1, v0, v1)``.

    Its gap above the obstacle is positive for ``u0 < s < u1``, below for ``v0 < s < v1``
    (empty spans: ``(inf, -inf)``); the gaps are affine in ``s`` from their values ``G``
    at the two ends. An interval ``[lo, hi]`` is apart when it lies inside either span.
    """
    (up_a, down_a), (up_b, down_b) = G
    return (*_positive(up_a[k], up_b[k]), *_positive(down_a[k], down_b[k]))


def _positive(ga: float, gb: float) -> tuple[float, float]:
    """The open span of ``s`` where ``(1 - s) ga + s gb > 0`` (``(inf, -inf)``: none)."""
    if ga > 0 and gb > 0:
        return -math.inf, math.inf
    if ga > 0:
        return -math.inf, ga / (ga - gb)
    if gb > 0:
        return ga / (ga - gb), math.inf
    return math.inf, -math.inf


def _apart(G: tuple[Heights, Heights], k: int, s0: float, s1: float) -> bool:
    """Whether pair ``k`` stays apart along the axis on ``[s0, s1]`` of a segment.

    ``G``: the gaps (above, below) at the segment's two ends; they are affine along it.
    """
    (up_a, down_a), (up_b, down_b) = G
    ua, ub = up_a[k], up_b[k]
    if (1 - s0) * ua + s0 * ub > 0 and (1 - s1) * ua + s1 * ub > 0:
        return True
    da, db = down_a[k], down_b[k]
    return (1 - s0) * da + s0 * db > 0 and (1 - s1) * da + s1 * db > 0


#: pinocchio's joints whose interpolation is ``qa + s (qb - qa)``, as numpy computes it
LINEAR_JOINTS = frozenset(f"JointModel{k}" for k in (
    "RX", "RY", "RZ", "RevoluteUnaligned", "PX", "PY", "PZ", "PrismaticUnaligned"))


def _linear(model: Any) -> bool:
    """Whether every joint of the pinocchio ``model`` interpolates linearly (see above)."""
    joints = list(model.joints)[1:]  # the first is the universe
    return all(j.shortname() in LINEAR_JOINTS for j in joints)


@dataclass(frozen=True)
class OmplRun:
    """What one OMPL query did.

    Attributes:
        path: (n, nq) the simplified path's vertices, or ``None`` when none was found.
        raw: (m, nq) the planner's path before simplification (``None`` likewise).
        planner_states: states in the planner's two trees.
        plan_s, simplify_s: time spent planning and simplifying [s].
        cut: the simplifier was stopped by the time limit (it returned the best path it had
            proven by then).
    """

    path: Array | None
    raw: Array | None
    planner_states: int
    plan_s: float
    simplify_s: float
    cut: bool = False


def rrt_connect(prover: EdgeProver, start: Array, goal: Array, lower: Array, upper: Array,
                time_limit: float, seed: int, simplify: bool = True,
                range_: float | None = None) -> OmplRun:
    """OMPL RRTConnect from ``start`` to ``goal``, then OMPL's PathSimplifier.

    Every state and edge, the simplifier's too, is checked through ``prover``.

    Args:
        prover: the state and edge checks.
        start: (nq,) the first configuration (valid).
        goal: (nq,) the last configuration (valid).
        lower: (nq,) the lower corner of the joint box sampled [rad or m].
        upper: (nq,) its upper corner [rad or m].
        time_limit: wall-clock limit for planning and simplifying together [s].
        seed: OMPL's random seed is ``seed + 1``.
        simplify: run the simplifier.
        range_: RRTConnect's longest extension; default :data:`RANGE` times the box's
            diagonal.
    """
    ob, og, ou = import_ompl()
    nq = len(start)
    get = itemgetter(*range(nq)) if nq > 1 else (lambda s: (s[0],))
    with _LOCK:
        level = ou.getLogLevel()
        ou.setLogLevel(ou.LOG_NONE)
        try:
            return _solve(ob, og, ou, prover, get, start, goal, lower, upper, time_limit,
                          seed, simplify, range_)
        finally:
            ou.setLogLevel(level)


def box_space(ob: ModuleType, lower: Array, upper: Array) -> Any:
    """OMPL's ``RealVectorStateSpace`` of the joint box [lower, upper] (nq,) each."""
    nq = len(lower)
    space = ob.RealVectorStateSpace(nq)
    bounds = ob.RealVectorBounds(nq)
    for k in range(nq):
        bounds.setLow(k, float(lower[k]))
        bounds.setHigh(k, float(upper[k]))
    space.setBounds(bounds)
    return space


def start_and_goal(ob: ModuleType, space: Any, si: Any, start: Array, goal: Array) -> Any:
    """OMPL's ``ProblemDefinition`` from ``start`` to ``goal`` (nq,) each."""
    a, b = space.allocState(), space.allocState()
    for k in range(len(start)):
        a[k], b[k] = float(start[k]), float(goal[k])
    pdef = ob.ProblemDefinition(si)
    pdef.setStartAndGoalStates(a, b)
    return pdef


def _solve(ob: ModuleType, og: ModuleType, ou: ModuleType, prover: EdgeProver,
           get: Callable, start: Array, goal: Array, lower: Array, upper: Array,
           time_limit: float, seed: int, simplify: bool, range_: float | None) -> OmplRun:
    ou.RNG.setSeed(int(seed) + 1)
    deadline = time.perf_counter() + time_limit
    prover.deadline = deadline  # the simplifier's edges too: the whole run within the limit
    space = box_space(ob, lower, upper)
    si = ob.SpaceInformation(space)
    valid, edge = prover.valid, prover.edge
    validator: Any = ob.MotionValidator  # OMPL's class (the wheel has no types)

    class Motion(validator):
        def checkMotion(self, s1: Any, s2: Any) -> bool:  # noqa: N802 (OMPL's name)
            return edge(get(s1), get(s2))

    si.setStateValidityChecker(lambda s: valid(get(s)))
    si.setMotionValidator(Motion(si))
    si.setup()
    pdef = start_and_goal(ob, space, si, start, goal)
    planner = og.RRTConnect(si)
    planner.setRange(float(range_) if range_ is not None else RANGE * extent(lower, upper))
    planner.setProblemDefinition(pdef)
    planner.setup()
    begin = time.perf_counter()
    status = planner.solve(ob.timedPlannerTerminationCondition(time_limit))
    plan_s = time.perf_counter() - begin
    pd = ob.PlannerData(si)
    planner.getPlannerData(pd)
    states = pd.numVertices()
    if str(status) != "Exact solution":
        return OmplRun(None, None, states, plan_s, 0.0)
    path = pdef.getSolutionPath()
    raw = np.array([get(path.getState(i)) for i in range(path.getStateCount())])
    begin = time.perf_counter()
    late = prover.late
    if simplify:
        simplify_path(og, si, path)
    prover.deadline = math.inf  # the path's own edges are all proven: asked again, known
    # or pieces of proven edges (the smoother's halves), looked up where a proof costs more
    # than the lookup: with meshes (a primitive SCARA's calls are 7 % faster without)
    prover.pieces = prover._meshy
    vertices = np.array([get(path.getState(i)) for i in range(path.getStateCount())])
    return OmplRun(vertices, raw, states, plan_s, time.perf_counter() - begin,
                   prover.late > late)


def simplify_path(og: ModuleType, si: Any, path: Any) -> None:
    """Shorten and smooth ``path`` in place with OMPL's PathSimplifier (its checks are ours).

    Vertex reduction, one rope shortcut (OMPL 2's ``ropeShortcutPath``: the path pulled
    taut against the obstacles, its states :data:`ROPE_DELTA` of the box apart), up to
    :data:`SHORTCUT_ROUNDS` rounds of partial shortcuts (segments between points anywhere
    on the path), close vertices collapsed, vertices reduced again, then
    :data:`SMOOTHING_STEPS` steps of B-spline smoothing (each corner cut where the new
    segments are proven clear). Chosen by measurement on the cells of
    benchmarks/bench_plan.py (25-40 pairs each, median path length of the timed trajectory
    against OMPL's simplified one, and time against OMPL's plan + simplify): 6 partial
    rounds alone 1.045 and 0.64; the rope alone 1.006 and 0.64; the rope and 4 rounds 0.983
    and 0.84; the rope and 6 rounds 0.981 and 0.92; OMPL's whole ``simplify`` (0.05 s)
    1.066 and 0.86. Once the rest of a call had become faster (issue 37's compiled toppra
    passes), one round instead of 4 (10 pairs a cell, the same seeds): calls 8-29 %
    faster (UR5 meshes 199 -> 145 ms, Panda 33 -> 21 ms), total durations +0.1 to +0.7 %,
    per-pair path length median <= +0.5 %, 90th percentile <= +4.3 %.
    """
    ps = og.PathSimplifier(si)
    ps.reduceVertices(path)
    ps.ropeShortcutPath(path, max(1.0, ROPE_DELTA * si.getMaximumExtent()))
    for _ in range(SHORTCUT_ROUNDS):
        if not ps.partialShortcutPath(path):
            break
    ps.collapseCloseVertices(path)
    ps.reduceVertices(path)
    ps.smoothBSpline(path, SMOOTHING_STEPS)


def extent(lower: Array, upper: Array) -> float:
    """The box's diagonal (OMPL's maximum extent of a real vector space) [rad or m]."""
    return float(math.sqrt(float(np.sum((np.asarray(upper) - np.asarray(lower)) ** 2))))
