"""IK along a Cartesian path or through poses: a :class:`JointPath`, its problems reported.

:func:`ik_path` chooses the branch sequence over the whole path by default
(``branches="global"``, :mod:`scara_opt.trajectory.branches`): every IK solution of every
point (the closed form's elbow branches and whole turns on SCARA-type robots and on the 6R
arms it serves; the distinct solutions of a seeded multi-start elsewhere), then the walk
of least joint travel weighted by each joint's speed limit (``objective="travel"``), or,
for a Cartesian path to follow, the walk with the fewest jumps and the least travel among
those (``objective="fewest_jumps"``). Where one branch
covers the whole path there is no jump; where none does, each jump names the point that
forces it. ``branches="greedy"`` solves the targets in order instead, each from the
previous solution (``q0``): a solver that honours ``q0`` stays on the previous branch and
takes each joint's whole turn nearest it, but the first point's branch is chosen without
a look at the rest. Nothing is hidden: every point keeps its status and residual, and a
step of any joint above the jump threshold (an elbow flip, a 2π wrist turn, a redundant
joint sliding away) is listed in :attr:`JointPath.jumps`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import InputError, TrajectoryError
from scara_opt.ik.base import Solver, check_seed, check_tol
from scara_opt.ik.registry import get_solver
from scara_opt.ik.result import IKResult, SolverOutput, Status
from scara_opt.ik.task import default_q0, wrap_angle
from scara_opt.ik.verdict import judge
from scara_opt.model.robot import Robot, check_robot
from scara_opt.paths import as_targets
from scara_opt.target import Target
from scara_opt.trajectory import branches as walk

Array = NDArray[np.float64]

#: default jump thresholds per step: revolute joints [rad], prismatic joints [m]
REVOLUTE_JUMP = math.pi / 2
PRISMATIC_JUMP = 0.1

#: the branch choices of :func:`ik_path`
BRANCHES = ("global", "greedy")
#: what the global choice minimises: the travel alone, or the jumps first
OBJECTIVES = ("travel", "fewest_jumps")
#: the methods that return the solution nearest ``q0``: ``branches="global"`` by default
NEAREST_METHODS = ("auto", "lm", "ipopt", "analytic")


@dataclass(frozen=True)
class Jump:
    """A step between two consecutive path points larger than the jump threshold.

    Attributes:
        index: the step from point ``index - 1`` to point ``index``.
        delta: (nq,) joint change over the step [rad or m].
        joints: names of the joints whose change exceeds their threshold.
        forced_by: the first point that the configuration before the jump cannot reach
            without one (``branches="global"``: no branch goes on from there), or ``None``
            (not known: the greedy walk).
    """

    index: int
    delta: Array
    joints: tuple[str, ...]
    forced_by: int | None = None

    def __str__(self) -> str:
        why = ("" if self.forced_by is None
               else f" (forced: the branch before it does not reach point {self.forced_by})")
        return (f"step {self.index - 1}→{self.index}: joints {', '.join(self.joints)} move by "
                f"{np.array2string(self.delta, precision=3, separator=', ')}{why}")


@dataclass(frozen=True, repr=False, eq=False)
class JointPath:
    """Joint configurations along a Cartesian path, with each point's verdict.

    Attributes:
        q: (n, nq) joint values [rad or m], within the joint limits.
        targets: the n targets.
        status: per point, the IK :class:`~scara_opt.ik.result.Status`.
        error: (n,) honest residuals max(|Δp| [m], |Δangle| [rad]).
        position_error: (n, 3) ``p(q) - p*`` [m].
        angle_error: (n,) wrapped tool-angle error [rad] (0 for position-only targets).
        jumps: steps larger than ``jump_threshold`` (see :class:`Jump`).
        jump_threshold: (nq,) per-joint step threshold [rad or m].
        method: IK method used.
        joint_names: one name per joint.
        results: the per-point :class:`~scara_opt.IKResult` (closed-form points of a global
            walk are judged by the verdict when first read).
        time_s: wall-clock time of all solves [s].
        branches: how the branch sequence was chosen, ``"global"`` or ``"greedy"``.
    """

    q: Array
    targets: tuple[Target, ...]
    status: tuple[Status, ...]
    error: Array
    position_error: Array
    angle_error: Array
    jumps: tuple[Jump, ...]
    jump_threshold: Array
    method: str
    joint_names: tuple[str, ...]
    results: Sequence[IKResult]
    time_s: float = 0.0
    branches: str = "greedy"

    def __len__(self) -> int:
        return int(self.q.shape[0])

    @property
    def solved(self) -> NDArray[np.bool_]:
        """(n,) whether each point was reached within tolerance."""
        return np.array([s == Status.SOLVED for s in self.status], dtype=bool)

    @property
    def unsolved(self) -> list[int]:
        """Indices of the points not reached (unreachable, failed or out of budget)."""
        return [int(i) for i in np.flatnonzero(~self.solved)]

    @property
    def forced(self) -> list[int]:
        """The points that force each jump (see :attr:`Jump.forced_by`), where known."""
        return [j.forced_by for j in self.jumps if j.forced_by is not None]

    @property
    def travel(self) -> Array:
        """(nq,) total joint travel along the path, ``sum |Δq|`` per joint [rad or m]."""
        return np.abs(np.diff(self.q, axis=0)).sum(axis=0)

    @property
    def ok(self) -> bool:
        """Every point solved and no jump: the joint path follows the Cartesian path."""
        return not self.unsolved and not self.jumps

    def problems(self) -> list[str]:
        """One line per unsolved point and per jump; empty when :attr:`ok`."""
        out = [f"point {i}: {self.status[i].value}, residual {self.error[i]:.3g} "
               f"(target {self.targets[i]})" for i in self.unsolved]
        return out + [f"jump at {j}" for j in self.jumps]

    def raise_if_invalid(self, allow_jumps: bool = False) -> JointPath:
        """Raise unless every point is solved (and, unless ``allow_jumps``, no jump); else self.

        Raises:
            TrajectoryError: listing the unsolved points and jumps, with what to do.
        """
        bad = self.unsolved
        if bad:
            raise TrajectoryError(
                f"{len(bad)} of {len(self)} path points were not reached by {self.method!r}: "
                + "; ".join(self.problems()[:len(bad)][:5])
                + "; move the targets into the workspace, or drop those points with "
                  "path.subset(path.solved)")
        if self.jumps and not allow_jumps:
            raise TrajectoryError(
                f"the joint path jumps {len(self.jumps)} time(s) (a branch change, a wrist "
                f"turn, or points too far apart): " + "; ".join(str(j) for j in self.jumps[:5])
                + "; sample the path more finely, start from another q_start, split the path "
                  "at the jump, or pass allow_jumps=True to time it anyway")
        return self

    def subset(self, keep: ArrayLike | slice) -> JointPath:
        """A JointPath of the selected points (mask (n,), indices or a slice), jumps recomputed.

        Raises:
            InputError: a mask of the wrong length or indices out of range.
        """
        idx = np.arange(len(self))
        try:
            sel = idx[keep if isinstance(keep, slice) else np.asarray(keep)]
        except (IndexError, ValueError):
            raise InputError(f"keep must be a boolean mask of length {len(self)} or indices "
                             f"in [0, {len(self)})") from None
        sel = np.atleast_1d(sel)
        return _assemble(self.q[sel], [self.results[i] for i in sel],
                         [self.targets[i] for i in sel], self.jump_threshold, self.method,
                         self.joint_names, self.time_s, self.branches)

    def summary(self) -> str:
        """One line: points solved, largest errors, jumps."""
        if not len(self):
            return f"{self.method}: no points"
        steps = ", ".join(str(j.index) for j in self.jumps)
        jumps = f"jumps at steps {steps}" if steps else "no jumps"
        if self.forced:
            jumps += f" (forced by points {', '.join(map(str, self.forced))})"
        return (f"{self.method} ({self.branches} branches): {int(self.solved.sum())}/{len(self)} "
                f"points solved, max "
                f"position error {np.linalg.norm(self.position_error, axis=1).max():.3g} m, "
                f"max angle error {np.abs(self.angle_error).max():.3g} rad, {jumps}")

    def __repr__(self) -> str:
        return f"JointPath({self.summary()})"

    __str__ = __repr__


def find_jumps(Q: Array, threshold: Array, names: Sequence[str],
               forced: dict[int, int | None] | None = None) -> tuple[Jump, ...]:
    """Steps of ``Q`` (n, nq) where some joint moves more than ``threshold`` (nq,).

    ``forced``: the point forcing each jump, by step (see :attr:`Jump.forced_by`).
    """
    dQ = np.diff(Q, axis=0)
    out = []
    for i in np.flatnonzero((np.abs(dQ) > threshold).any(axis=1)):
        over = np.abs(dQ[i]) > threshold
        out.append(Jump(int(i) + 1, dQ[i].copy(),
                        tuple(n for n, o in zip(names, over, strict=True) if o),
                        None if forced is None else forced.get(int(i) + 1)))
    return tuple(out)


def _threshold(robot: Robot, jump_threshold: ArrayLike | None) -> Array:
    if jump_threshold is None:
        return np.array([REVOLUTE_JUMP if k == "revolute" else PRISMATIC_JUMP
                         for k in robot.joint_types])
    try:
        arr = np.broadcast_to(float_array(jump_threshold, "jump_threshold"), (robot.nq,)).copy()
    except (InputError, ValueError):
        raise InputError(f"jump_threshold must be a number or ({robot.nq},) per joint "
                         f"[rad or m]; got {describe(jump_threshold)}") from None
    if np.isnan(arr).any() or (arr <= 0).any():
        raise InputError(f"jump_threshold must be positive (inf disables a joint); got {arr}")
    return arr


def _assemble(Q: Array, results: Sequence[IKResult], targets: Sequence[Target],
              threshold: Array, method: str, names: Sequence[str], time_s: float,
              branches: str = "greedy", forced: dict[int, int | None] | None = None
              ) -> JointPath:
    return JointPath(
        q=np.asarray(Q, dtype=float), targets=tuple(targets),
        status=tuple(r.status for r in results),
        error=np.array([r.error for r in results]),
        position_error=np.array([r.position_error for r in results]).reshape(-1, 3),
        angle_error=np.array([0.0 if r.yaw_error is None else r.yaw_error for r in results]),
        jumps=find_jumps(np.asarray(Q), threshold, names, forced), jump_threshold=threshold,
        method=method, joint_names=tuple(names), results=tuple(results), time_s=time_s,
        branches=branches)


def ik_path(robot: Robot, targets: Sequence[Target] | ArrayLike, method: str = "auto",
            q_start: ArrayLike | None = None, jump_threshold: ArrayLike | None = None,
            seed: int | None = 0, tol: float = 1e-9, branches: str | None = None,
            objective: str = "travel", **options: Any) -> JointPath:
    """Inverse kinematics along a path or through poses: one solution per point.

    Args:
        robot: the robot.
        targets: a sequence of :class:`~scara_opt.Target` or an (n, 3) / (n, 4) array
            ``[x, y, z(, yaw)]`` [m, rad] (see :mod:`scara_opt.paths`).
        method: any registered IK method (:func:`~scara_opt.solvers`); default ``"auto"``
            (the fast ``"lm"`` solver, IPOPT only for its misses).
        q_start: (nq,) configuration the path starts from (not itself part of the path):
            the greedy walk's first ``q0``; the global choice counts its step to the first
            point in the travel and keeps its branch there wherever some walk can (a jump
            off it counts before the path's own). ``None``: no preference.
        jump_threshold: per-step joint change above which a step is a jump, scalar or (nq,)
            [rad or m] (``inf`` disables a joint); default π/2 rad for revolute joints
            (elbow flips, 2π wrist turns) and 0.1 m for prismatic ones (a redundant rail
            sliding away). ``objective="fewest_jumps"`` takes it as a hard limit. A jump
            can also mean the points are too far apart: sample more finely.
        seed: seed of point 0; point ``i`` uses ``seed + i`` (``None``: unseeded); the
            global multi-start draws its starts from it too.
        tol: residual [m, rad] below which a point counts as solved.
        branches: ``"global"`` (the default for the methods that return the solution
            nearest ``q0``: ``"auto"``, ``"lm"``, ``"ipopt"``, ``"analytic"``): every
            solution of every point, then the walk of least cost by ``objective``
            (:mod:`.branches`). On a
            SCARA-type robot without redundant joints the closed form lists the solutions
            (both elbow branches, every whole turn), whatever the method (their results say
            ``method="analytic"``); the method solves only the points it misses, whose
            verdicts say why. Elsewhere the method's own multi-start finds them; where the
            robot has joints to spare for the targets (a continuum of solutions) the greedy
            walk is kept unless another track has fewer jumps.
            ``"greedy"`` (the default for the metaheuristics): each point from the
            previous solution, in order.
        objective: the global choice's cost. ``"travel"`` (default; poses to visit): the
            least joint travel Σ |Δq_k| / vmax_k [s] over every listed solution
            sequence, the step from ``q_start`` included: where the closed form
            lists every solution (SCARAs, the 6R arms it serves), no sequence of IK
            solutions within the limits travels less; jumps are taken where they save
            travel, and reported. ``"fewest_jumps"`` (a Cartesian path to follow, where a
            jump breaks the path; LIN and CIRC moves use it): the fewest jumps first (a
            jump off ``q_start`` before the path's own), then the least travel.
        **options: options of the IK method (an unknown one raises SolverOptionError).

    Returns:
        JointPath: every point, solved or not, with statuses, residuals and jumps (each
        global jump names the point forcing it). Check :attr:`JointPath.ok` or call
        :meth:`JointPath.raise_if_invalid`.

    Raises:
        InputError: ``robot`` not a Robot; malformed targets, threshold, ``seed``, ``tol``,
            ``branches`` (``"global"`` with a method that does not honour ``q0``) or
            ``objective``.
        UnknownSolverError, SolverOptionError, JointLimitError, TargetError: as for
            :func:`~scara_opt.solve_ik`.
    """
    check_robot(robot)
    ts = as_targets(targets)
    threshold = _threshold(robot, jump_threshold)
    check_seed(seed)
    tol = check_tol(tol)
    solver = get_solver(method, **options)
    choice = _branches(branches, method)
    if not isinstance(objective, str) or objective not in OBJECTIVES:
        raise InputError(f"objective must be one of {list(OBJECTIVES)}; got "
                         f"{describe(objective)}: 'travel' for poses to visit, "
                         "'fewest_jumps' for a Cartesian path to follow")
    fewest = objective == "fewest_jumps"
    q0 = None if q_start is None else robot.check_q(q_start, "q_start")
    start = time.perf_counter()
    if choice == "global":
        return _global(robot, ts, solver, method, q0, threshold, seed, tol, start, fewest)
    results: list[IKResult] = []
    for i, target in enumerate(ts):
        res = solver.solve(robot, target, q0=q0, seed=None if seed is None else seed + i,
                           tol=tol)
        results.append(res)
        q0 = res.q
    elapsed = time.perf_counter() - start
    Q = np.array([r.q for r in results])
    return _assemble(Q, results, ts, threshold, method, robot.joint_names, elapsed)


def _branches(branches: object, method: str) -> str:
    """The branch choice: as given, else global for the methods nearest ``q0``.

    Raises:
        InputError: not one of :data:`BRANCHES`, or global with another method.
    """
    if branches is None:
        return "global" if method in NEAREST_METHODS else "greedy"
    if branches not in BRANCHES:
        raise InputError(f"branches must be one of {list(BRANCHES)}; got {describe(branches)}")
    if branches == "global" and method not in NEAREST_METHODS:
        raise InputError(f"branches='global' needs a method that returns the solution nearest "
                         f"q0 ({', '.join(NEAREST_METHODS)}); {method!r} does not: use one of "
                         "them, or branches='greedy'")
    return str(branches)


def _global(robot: Robot, ts: list[Target], solver: Solver, method: str, q_start: Array | None,
            threshold: Array, seed: int | None, tol: float, start: float,
            fewest: bool) -> JointPath:
    """:func:`ik_path` with ``branches="global"`` (see :mod:`scara_opt.trajectory.branches`)."""
    weights = walk.travel_weights(robot)
    q_ref = default_q0(robot) if q_start is None else q_start
    listed = walk.candidates_closed_form(robot, ts, q_ref)
    if listed is None:
        arm = walk.candidates_arm(robot, ts, q_ref, tol)
        if arm is not None:
            return _global_arm(robot, ts, solver, method, q_start, q_ref, threshold, seed, tol,
                               start, arm, fewest)
        Q, valid, kept = walk.candidates_searched(robot, ts, solver, q_start, seed, tol)
        w = walk.least_cost_walk(Q, valid, threshold, weights, q_start, fewest)
        if walk.redundant(robot, ts):  # a continuum: the greedy walk unless it jumps more
            first = walk.least_cost_walk(Q[:, :1], valid[:, :1], threshold, weights, q_start,
                                         fewest)
            if (first.start_jump, len(first.jumps)) <= (w.start_jump, len(w.jumps)):
                w = first
        picked = [kept[i][k] for i, k in enumerate(w.choice)]
        return _assemble(Q[np.arange(len(ts)), w.choice], picked, ts, threshold, method,
                         robot.joint_names, time.perf_counter() - start, "global",
                         dict(zip(w.jumps, w.forced_by, strict=True)))
    Q, valid = listed
    known: dict[int, IKResult] = {}
    verdicts = _Verdicts(robot, ts, solver, q_ref, seed, tol, Q, valid, known)
    verdicts.where_none()
    rows = np.arange(len(ts))
    while True:  # a chosen candidate the FK does not confirm within tol is struck off
        w = walk.least_cost_walk(Q, valid, threshold, weights, q_start, fewest)
        Qc = Q[rows, w.choice]
        dp, dang = _residuals(robot, ts, Qc)
        err = np.maximum(np.linalg.norm(dp, axis=1), np.abs(dang))
        bad = [int(i) for i in np.flatnonzero(~(err <= tol)) if int(i) not in known]
        if not bad:
            break
        verdicts.strike(bad, w.choice)
    for i in [int(k) for k in np.flatnonzero(err > tol / 2)]:
        # near tol: the verdict's own numbers decide
        known.setdefault(i, judge(robot, ts[i], SolverOutput(q=Qc[i], evaluations=1),
                                       tol=tol, method="analytic", seed=None, time_s=0.0))
    results = JudgedResults(robot, ts, Qc, tol, known)
    status = tuple(known[i].status if i in known else Status.SOLVED for i in rows.tolist())
    for i, r in known.items():
        dp[i], dang[i], err[i] = r.position_error, r.yaw_error or 0.0, r.error
    return JointPath(
        q=Qc, targets=tuple(ts), status=status, error=err, position_error=dp,
        angle_error=dang, jumps=find_jumps(Qc, threshold, robot.joint_names,
                                          dict(zip(w.jumps, w.forced_by, strict=True))),
        jump_threshold=threshold, method=method, joint_names=tuple(robot.joint_names),
        results=results, time_s=time.perf_counter() - start, branches="global")


@dataclass
class _Verdicts:
    """The global choice's candidates (``Q``, ``valid``) and the points the method judged.

    A point without a candidate gets the method's own solve (its verdict says why), as
    its one candidate; ``known`` holds those results by point.
    """

    robot: Robot
    ts: list[Target]
    solver: Solver
    q_ref: Array
    seed: int | None
    tol: float
    Q: Array
    valid: NDArray[np.bool_]
    known: dict[int, IKResult]

    def judge_by_method(self, i: int) -> None:
        """Point ``i``'s result from the method, its ``q`` the point's one candidate."""
        self.known[i] = self.solver.solve(self.robot, self.ts[i], q0=self.q_ref,
                                          seed=None if self.seed is None else self.seed + i,
                                          tol=self.tol)
        self.Q[i, 0], self.valid[i, 0] = self.known[i].q, True

    def where_none(self) -> None:
        """The method's verdict for every point no candidate reaches."""
        for i in np.flatnonzero(~self.valid.any(axis=1)):
            self.judge_by_method(int(i))

    def strike(self, bad: list[int], choice: NDArray[np.intp]) -> None:
        """Strike off the chosen candidates of the points ``bad``.

        A point left without any gets the method's verdict.
        """
        for i in bad:
            self.valid[i, choice[i]] = False
            if not self.valid[i].any():
                self.judge_by_method(i)


def _global_arm(robot: Robot, ts: list[Target], solver: Solver, method: str,
                q_start: Array | None, q_ref: Array, threshold: Array, seed: int | None,
                tol: float, start: float, arm: tuple[Array, NDArray[np.bool_], str],
                fewest: bool) -> JointPath:
    """The global choice over every solution of a 6R arm's closed form (:func:`_global`).

    A point without any keeps the method's verdict; a chosen candidate the verdict does
    not confirm within ``tol`` is struck off and the walk chosen again.
    """
    Q, valid, route = arm
    weights = walk.travel_weights(robot)
    known: dict[int, IKResult] = {}
    verdicts = _Verdicts(robot, ts, solver, q_ref, seed, tol, Q, valid, known)
    verdicts.where_none()
    while True:
        w = walk.least_cost_walk(Q, valid, threshold, weights, q_start, fewest)
        results = [known.get(i) or judge(robot, t, SolverOutput(q=Q[i, k].copy(), evaluations=1,
                                                                route=route),
                                         tol=tol, method="analytic", seed=None, time_s=0.0)
                   for i, (t, k) in enumerate(zip(ts, w.choice, strict=True))]
        bad = [i for i, r in enumerate(results) if not r.success and i not in known]
        if not bad:
            break
        verdicts.strike(bad, w.choice)
    return _assemble(Q[np.arange(len(ts)), w.choice], results, ts, threshold, method,
                     robot.joint_names, time.perf_counter() - start, "global",
                     dict(zip(w.jumps, w.forced_by, strict=True)))


def _residuals(robot: Robot, ts: Sequence[Target], Q: Array) -> tuple[Array, Array]:
    """Position errors (n, 3) [m] and wrapped yaw errors (n,) [rad] (0 without yaw), by FK."""
    if all(t.kind == "position" for t in ts):
        return robot.positions(Q) - [t.position for t in ts], np.zeros(len(ts))
    T = robot.fk_batch(Q)
    e1, e2 = robot.yaw_basis()
    x = T[:, :3, 0]
    yaw = np.arctan2(x @ e2, x @ e1) - [t.yaw if t.kind == "yaw" else 0.0 for t in ts]
    dang = np.where([t.kind == "yaw" for t in ts], wrap_angle(yaw), 0.0)
    return T[:, :3, 3] - [t.position for t in ts], dang


class JudgedResults(Sequence[IKResult]):
    """The per-point results of closed-form configurations, judged when first read.

    Judging a point (:func:`scara_opt.ik.verdict.judge`: FK, residual, status) costs
    ~40 µs; a 1,000-point path needs its statuses and residuals at once (computed in one
    batch FK, each well within ``tol``), its :class:`~scara_opt.IKResult` objects rarely.
    Points already judged (``known``) are returned as they are.
    """

    def __init__(self, robot: Robot, targets: Sequence[Target], Q: Array, tol: float,
                 known: dict[int, IKResult]) -> None:
        self._args = (robot, targets, Q, tol)
        self._known = dict(known)

    def __len__(self) -> int:
        return len(self._args[1])

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        k = range(len(self))[i]  # IndexError out of range; negative indices count back
        if k not in self._known:
            robot, targets, Q, tol = self._args
            self._known[k] = judge(robot, targets[k], SolverOutput(q=Q[k].copy(), evaluations=1),
                                   tol=tol, method="analytic", seed=None, time_s=0.0)
        return self._known[k]
