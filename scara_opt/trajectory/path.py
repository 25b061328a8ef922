"""IK along a Cartesian path: a branch-continuous :class:`JointPath`, its problems reported.

:func:`ik_path` solves the targets in order, each from the previous solution (``q0``), so a
solver that honours ``q0`` stays on the previous branch: IPOPT's regulariser and polish pull
toward it (for redundant robots: the solution locally nearest to it, minimal joint motion),
the closed form picks the nearest branch and wrist turn. Nothing is hidden: every point
keeps its status and residual, and a step of any joint above the jump threshold (an elbow
flip, a 2π wrist turn, a redundant joint sliding away) is listed in :attr:`JointPath.jumps`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import InputError, TrajectoryError
from scara_opt.ik.base import check_seed
from scara_opt.ik.registry import get_solver
from scara_opt.ik.result import IKResult, Status
from scara_opt.model.robot import Robot, check_robot
from scara_opt.paths import as_targets
from scara_opt.target import Target

Array = NDArray[np.float64]

#: default jump thresholds per step: revolute joints [rad], prismatic joints [m]
REVOLUTE_JUMP = math.pi / 2
PRISMATIC_JUMP = 0.1


@dataclass(frozen=True)
class Jump:
    """A step between two consecutive path points larger than the jump threshold.

    Attributes:
        index: the step from point ``index - 1`` to point ``index``.
        delta: (nq,) joint change over the step [rad or m].
        joints: names of the joints whose change exceeds their threshold.
    """

    index: int
    delta: Array
    joints: tuple[str, ...]

    def __str__(self) -> str:
        return (f"step {self.index - 1}→{self.index}: joints {', '.join(self.joints)} move by "
                f"{np.array2string(self.delta, precision=3, separator=', ')}")


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
        results: the per-point :class:`~scara_opt.IKResult`.
        time_s: wall-clock time of all solves [s].
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
    results: tuple[IKResult, ...]
    time_s: float = 0.0

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

    def subset(self, keep: object) -> JointPath:
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
                         self.joint_names, self.time_s)

    def summary(self) -> str:
        """One line: points solved, largest errors, jumps."""
        if not len(self):
            return f"{self.method}: no points"
        steps = ", ".join(str(j.index) for j in self.jumps)
        jumps = f"jumps at steps {steps}" if steps else "no jumps"
        return (f"{self.method}: {int(self.solved.sum())}/{len(self)} points solved, max "
                f"position error {np.linalg.norm(self.position_error, axis=1).max():.3g} m, "
                f"max angle error {np.abs(self.angle_error).max():.3g} rad, {jumps}")

    def __repr__(self) -> str:
        return f"JointPath({self.summary()})"

    __str__ = __repr__


def find_jumps(Q: Array, threshold: Array, names: Sequence[str]) -> tuple[Jump, ...]:
    """Steps of ``Q`` (n, nq) where some joint moves more than ``threshold`` (nq,)."""
    dQ = np.diff(Q, axis=0)
    out = []
    for i in np.flatnonzero((np.abs(dQ) > threshold).any(axis=1)):
        over = np.abs(dQ[i]) > threshold
        out.append(Jump(int(i) + 1, dQ[i].copy(), tuple(n for n, o in zip(names, over,
                                                                           strict=True) if o)))
    return tuple(out)


def _threshold(robot: Robot, jump_threshold: object | None) -> Array:
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
              threshold: Array, method: str, names: Sequence[str], time_s: float) -> JointPath:
    return JointPath(
        q=np.asarray(Q, dtype=float), targets=tuple(targets),
        status=tuple(r.status for r in results),
        error=np.array([r.error for r in results]),
        position_error=np.array([r.position_error for r in results]).reshape(-1, 3),
        angle_error=np.array([0.0 if r.yaw_error is None else r.yaw_error for r in results]),
        jumps=find_jumps(np.asarray(Q), threshold, names), jump_threshold=threshold,
        method=method, joint_names=tuple(names), results=tuple(results), time_s=time_s)


def ik_path(robot: Robot, targets: object, method: str = "auto", q_start: object | None = None,
            jump_threshold: object | None = None, seed: int | None = 0, tol: float = 1e-9,
            **options: Any) -> JointPath:
    """Inverse kinematics along a path, each point warm-started from the previous solution.

    Args:
        robot: the robot.
        targets: a sequence of :class:`~scara_opt.Target` or an (n, 3) / (n, 4) array
            ``[x, y, z(, yaw)]`` [m, rad] (see :mod:`scara_opt.paths`).
        method: any registered IK method (:func:`~scara_opt.solvers`); default ``"auto"``
            (the fast ``"lm"`` solver, IPOPT only for its misses). Methods that honour
            ``q0`` (``"auto"``, ``"lm"``, ``"ipopt"``, ``"analytic"``) keep the previous
            branch; a metaheuristic
            that ignores it may change branch, which then shows up in :attr:`JointPath.jumps`.
        q_start: (nq,) configuration the path starts from: the ``q0`` of the first point (not
            itself part of the path); ``None`` lets the solver choose.
        jump_threshold: per-step joint change above which a step is reported as a jump,
            scalar or (nq,) [rad or m] (``inf`` disables a joint); default π/2 rad for
            revolute joints (elbow flips, 2π wrist turns) and 0.1 m for prismatic ones
            (a redundant rail sliding away). A jump can also mean the points are too far
            apart for the motion between them: sample the path more finely.
        seed: seed of point 0; point ``i`` uses ``seed + i`` (``None``: unseeded).
        tol: residual [m, rad] below which a point counts as solved.
        **options: options of the IK method (an unknown one raises SolverOptionError).

    Returns:
        JointPath: every point, solved or not, with statuses, residuals and jumps.
        Check :attr:`JointPath.ok` or call :meth:`JointPath.raise_if_invalid`.

    Raises:
        InputError: ``robot`` not a Robot; malformed targets, threshold or ``seed``.
        UnknownSolverError, SolverOptionError, JointLimitError, TargetError: as for
            :func:`~scara_opt.solve_ik`.
    """
    check_robot(robot)
    ts = as_targets(targets)
    threshold = _threshold(robot, jump_threshold)
    check_seed(seed)
    solver = get_solver(method, **options)
    q0 = None if q_start is None else robot.check_q(q_start, "q_start")
    results: list[IKResult] = []
    start = time.perf_counter()
    for i, target in enumerate(ts):
        res = solver.solve(robot, target, q0=q0, seed=None if seed is None else seed + i,
                           tol=tol)
        results.append(res)
        q0 = res.q
    elapsed = time.perf_counter() - start
    Q = np.array([r.q for r in results])
    return _assemble(Q, results, ts, threshold, method, robot.joint_names, elapsed)
