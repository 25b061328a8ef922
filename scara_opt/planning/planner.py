"""``plan_path(checker, start, goal)``: a joint path around the cell's obstacles, proven clear.

1. The start and the goal are checked: inside the joint limits
   (:class:`~scara_opt.errors.JointLimitError`) and clear of the cell
   (:class:`~scara_opt.errors.CollisionError`, naming the bodies and the depth), and
   farther from it than the proofs' tolerance (:func:`check_provable`). The clock of
   ``time_limit`` starts after that, once the compiled kernel is built (its compilation,
   once per machine, never counts against the limit).
2. The straight joint segment is tried first: when the conservative rule proves it clear,
   it is the path.
3. Otherwise OMPL's RRTConnect searches the joint box (a SCARA's quill included: lifting it
   is how a rack is cleared), then OMPL's PathSimplifier shortens and smooths the path
   (:mod:`~scara_opt.planning.ompl_backend`). Every state and every edge, the simplifier's
   included, is checked by the conservative rule; the final path is proven edge by edge
   once more before it is returned.

**Honest failure.** A sampling planner proves nothing when it finds nothing: the status is
then ``"no_path"`` ("no path found within the time limit"), with what was tried, never
``"unreachable"``.
"""

from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import check_flag, check_int, check_real, describe
from scara_opt.collision.checker import DISTANCE_TOL, CollisionChecker
from scara_opt.errors import CollisionError, InputError
from scara_opt.model.joint_checks import check_within_limits
from scara_opt.planning.ompl_backend import EdgeProver, rrt_connect

Array = NDArray[np.float64]

__all__ = ["PathPlan", "PlanStatus", "check_clear", "check_provable", "plan_path"]

#: default wall-clock limit of one query [s]
TIME_LIMIT = 1.0

#: the largest seed: OMPL seeds its generator with ``seed + 1``, an unsigned 64-bit integer
SEED_MAX = 2**64 - 2

#: the planner samples within the joint limits inset by this fraction of each range (a
#: spline timed through its waypoints then has room to round them without leaving the
#: limits); the start and the goal may lie anywhere within the limits
LIMIT_INSET = 0.002


class PlanStatus(str, enum.Enum):  # noqa: UP042  (as ik.Status: value semantics)
    """How a planning query ended (compares equal to its value)."""

    SOLVED = "solved"
    NO_PATH = "no_path"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True, repr=False)
class PathPlan:
    """A planned joint path, or the honest record of not finding one.

    Attributes:
        status: ``"solved"`` or ``"no_path"``.
        path: (n, nq) waypoints, start and goal included, every straight edge between them
            proven clear; ``None`` when not solved.
        message: what happened, in words (never empty).
        planner: ``"straight"`` (the segment was clear) or ``"RRTConnect"``.
        time_s: wall-clock time of the whole query [s].
        states: configurations whose distances were computed.
        checks: edges checked (the planner's and the simplifier's).
        tree_states: states in RRTConnect's trees (0 for a straight path).
        length: joint-space length of the path, ``sum |Δq|_2`` [rad, m mixed as OMPL does].
        seed: the seed it was planned with.
    """

    status: PlanStatus
    path: Array | None
    message: str
    planner: str
    time_s: float
    states: int
    checks: int
    tree_states: int
    length: float
    seed: int

    @property
    def success(self) -> bool:
        """Whether a path was found."""
        return self.status is PlanStatus.SOLVED

    def __repr__(self) -> str:
        what = (f"{len(self.path)} waypoints, length {self.length:.4g}"
                if self.path is not None else self.message)
        return (f"PathPlan({self.status.value}: {what}; {self.planner}, "
                f"{self.time_s * 1e3:.1f} ms, {self.states} configurations and "
                f"{self.checks} edges checked, {self.tree_states} tree states)")


def path_length(Q: Array) -> float:
    """Joint-space length ``sum ‖Δq‖₂`` of a polyline (n, nq)."""
    return float(np.linalg.norm(np.diff(Q, axis=0), axis=1).sum()) if len(Q) > 1 else 0.0


def check_clear(checker: CollisionChecker, q: Array, what: str) -> None:
    """Refuse a configuration in collision, naming the bodies and the depth.

    Raises:
        CollisionError: ``q`` is closer than the margin to an obstacle or itself.
    """
    contacts = checker.contacts(q)
    if contacts:
        c = contacts[0]
        how = (f"{c.depth * 1e3:.3f} mm deep" if c.distance <= 0 else
               f"{c.distance * 1e3:.3f} mm apart, less than the margin "
               f"{checker.margin * 1e3:g} mm")
        raise CollisionError(f"the {what} is in collision: {c.bodies[0]} and {c.bodies[1]} "
                             f"{how}; move the {what} clear of the cell", c.bodies, c.depth)


def check_provable(checker: CollisionChecker, q: Array, what: str) -> None:
    """Refuse a configuration clear of the cell but too close to it for any proof.

    A motion is proven clear only where every pair is farther than the margin plus
    :data:`~scara_opt.collision.checker.DISTANCE_TOL` (coal's distance tolerance, with ten
    times in hand): a start closer than that is free, yet no edge from it can be proven,
    and more time would not help.

    Raises:
        CollisionError: ``q`` within the margin plus the tolerance (bodies and gap named).
    """
    need = checker.margin + DISTANCE_TOL
    d = checker.pair_distances(q[None, :], None, "rest")[0]  # bounds: exact where small
    if not len(d) or d.min() > need:
        return
    d = checker.distances(q)
    k = int(np.argmin(d))
    if d[k] <= need:
        a, b = checker.pair_names[k]
        raise CollisionError(
            f"the {what} is {d[k] * 1e3:.4f} mm from contact ({a} and {b}): clear, but "
            f"closer than the {need * 1e3:g} mm a motion from it needs to be proven clear "
            f"(the margin plus coal's distance tolerance, {DISTANCE_TOL * 1e3:g} mm); move "
            f"the {what} at least {(need - d[k]) * 1e3:.4f} mm farther from {b}",
            (a, b), 0.0)


def plan_path(checker: CollisionChecker, start: ArrayLike, goal: ArrayLike, *,
              time_limit: float = TIME_LIMIT, seed: int = 0, simplify: bool = True
              ) -> PathPlan:
    """A joint path from ``start`` to ``goal`` clear of the checker's cell (see the module).

    Args:
        checker: the robot in its cell (its ``margin`` is kept all along).
        start: (nq,) the configuration to start from [rad or m].
        goal: (nq,) the configuration to reach [rad or m].
        time_limit: wall-clock limit for planning and simplifying together [s] (> 0): the
            simplifier stops at it with the shortest path proven by then (the message says
            so); the kernel's one-off compilation does not count.
        seed: OMPL's random seed (``seed + 1``): the same seed gives the same path.
        simplify: shorten and smooth the planner's path (OMPL's PathSimplifier).

    Returns:
        A :class:`PathPlan`; ``status`` ``"no_path"`` when nothing was found in time.

    Raises:
        InputError: bad shapes, a ``time_limit`` <= 0, a ``seed`` not an integer in
            [0, :data:`SEED_MAX`].
        JointLimitError: start or goal outside the joint limits.
        CollisionError: start or goal in collision (bodies and depth named), or closer
            to it than a proof can work with (:func:`check_provable`).
        ModuleNotFoundError: OMPL is not installed and the straight path is not clear.
    """
    if not isinstance(checker, CollisionChecker):
        raise InputError(f"checker must be a CollisionChecker(robot, cell); got "
                         f"{describe(checker)}")
    time_limit = check_real("time_limit", time_limit, 0.0, 3600.0, low_open=True, unit="s")
    seed = check_int("seed", seed, 0, SEED_MAX)
    check_flag("simplify", simplify)
    qa = check_within_limits(checker.robot, start, "start")
    qb = check_within_limits(checker.robot, goal, "goal")
    check_clear(checker, qa, "start")
    check_clear(checker, qb, "goal")
    check_provable(checker, qa, "start")
    check_provable(checker, qb, "goal")
    prover = EdgeProver(checker)  # builds the compiled kernel on a cold cache: not timed
    begin = time.perf_counter()
    ka, kb = tuple(qa.tolist()), tuple(qb.tolist())
    if prover.edge(ka, kb):
        Q = np.array([qa, qb])
        return PathPlan(PlanStatus.SOLVED, Q, "the straight joint segment is proven clear",
                        "straight", time.perf_counter() - begin, prover.configurations,
                        prover.edges, 0, path_length(Q), seed)
    robot = checker.robot
    inset = LIMIT_INSET * (robot.sampling_upper - robot.sampling_lower)
    lower = np.minimum(robot.sampling_lower + inset, np.minimum(qa, qb))
    upper = np.maximum(robot.sampling_upper - inset, np.maximum(qa, qb))
    left = time_limit - (time.perf_counter() - begin)
    run = rrt_connect(prover, qa, qb, lower, upper, max(left, 1e-3), seed, simplify)
    elapsed = time.perf_counter() - begin
    if run.path is None:
        return PathPlan(PlanStatus.NO_PATH, None,
                        f"no path found within the time limit ({time_limit:g} s): RRTConnect "
                        f"grew {run.planner_states} states in {run.plan_s:.3g} s, "
                        f"{prover.configurations} configurations and {prover.edges} edges "
                        "checked; "
                        "not a proof that none exists: give more time, another seed or a "
                        "smaller margin, or move the goal",
                        "RRTConnect", elapsed, prover.configurations, prover.edges,
                        run.planner_states, math.nan, seed)
    Q = run.path
    if not prover.path(Q):  # the simplifier's output proven once more, edge by edge
        if run.raw is None or not prover.path(run.raw):  # pragma: no cover - all proven
            raise RuntimeError("an edge of the planner's path is not proven clear")
        Q = run.raw
    Q[0], Q[-1] = qa, qb
    cut = " (stopped at the time limit: the shortest path proven by then)" if run.cut else ""
    return PathPlan(PlanStatus.SOLVED, Q, f"RRTConnect ({run.plan_s * 1e3:.1f} ms) and "
                    f"PathSimplifier ({run.simplify_s * 1e3:.1f} ms{cut}), every edge proven",
                    "RRTConnect", time.perf_counter() - begin, prover.configurations,
                    prover.edges, run.planner_states, path_length(Q), seed)
