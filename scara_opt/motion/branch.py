r"""SCARA arm branch (lefty / righty) and the joint values of each move's goal and path.

The branch is the side the forearm turns to: with the planar angles of the upper arm
:math:`a_1` and forearm :math:`a_2` about the yaw axis :math:`n`, ``"righty"`` is
:math:`\sin(a_2 - a_1) > 0` (counter-clockwise about ``n``, a right arm seen from above),
``"lefty"`` is :math:`< 0`; stretched out (0) belongs to neither. Robots that are not
SCARA-type have no branch: ``elbow=`` is refused for them.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import BranchError, MoveError
from scara_opt.ik.analytic import ik_all
from scara_opt.ik.geometry import NotScaraError, ScaraGeometry, scara_geometry, solve_batch
from scara_opt.ik.registry import get_solver
from scara_opt.model.joint_checks import check_within_limits
from scara_opt.model.robot import Robot
from scara_opt.target import Target
from scara_opt.trajectory.path import ik_path

Array = NDArray[np.float64]

#: |sin(a2 - a1)| below this counts as stretched out (no branch)
STRETCHED = 1e-6

SIGN = {"righty": 1, "lefty": -1}
NAME = {1: "righty", -1: "lefty", 0: "stretched (no branch)"}


def geometry(robot: Robot) -> ScaraGeometry | None:
    """The robot's SCARA geometry, or ``None`` if it is not SCARA-type."""
    try:
        return scara_geometry(robot)
    except NotScaraError:
        return None


def elbow_signs(robot: Robot, Q: Array) -> Array | None:
    """Branch of each configuration (n,): +1 righty, -1 lefty, 0 stretched; ``None``: no SCARA."""
    g = geometry(robot)
    return None if g is None else signs_of(g, Q)


def signs_of(g: ScaraGeometry, Q: Array) -> Array:
    """:func:`elbow_signs` (n,) of configurations ``Q`` (n, nq) or (nq,) of a SCARA ``g``."""
    rel = g.phi2 - g.phi1 + g.s[g.elbow] * np.atleast_2d(Q)[:, g.elbow]
    s = np.sin(rel)
    return np.where(np.abs(s) < STRETCHED, 0, np.sign(s)).astype(int)


def tool_pose(robot: Robot, q: Array) -> tuple[Array, float | None]:
    """Tip position (3,) [m] and unwrapped tool yaw [rad] (``None`` without a yaw axis)."""
    g = geometry(robot)
    if g is not None:
        p, yaw = g.fk(q[None, :])
        return robot.position(q), float(yaw[0])
    return robot.position(q), (robot.yaw(q) if robot.yaw_axis is not None else None)


def _check_branch(index: int, robot: Robot, q: Array, elbow: str | None, what: str) -> None:
    if elbow is None:
        return
    signs = elbow_signs(robot, q)
    if signs is None:
        raise MoveError(index, f"robot {robot.name!r} is not SCARA-type and has no elbow "
                               "branch; drop elbow=")
    if signs[0] != SIGN[elbow]:
        raise MoveError(index, f"{what} is {NAME[int(signs[0])]}, not {elbow}: change "
                               f"elbow= or the goal")


def ptp_goal(index: int, robot: Robot, goal: Target | Array, q_prev: Array,
             elbow: str | None) -> Array:
    """Joint goal of a PTP: the given vector, or the IK solution on ``elbow`` nearest ``q_prev``.

    Raises:
        MoveError: outside the joint limits, unreachable, or not on the asked branch.
    """
    if not isinstance(goal, Target):
        try:
            q = check_within_limits(robot, goal, "PTP goal")
        except ValueError as exc:
            raise MoveError(index, str(exc)) from None
        _check_branch(index, robot, q, elbow, "the joint goal")
        return q
    g = geometry(robot)
    if g is None:
        if elbow is not None:
            _check_branch(index, robot, q_prev, elbow, "")
        res = get_solver("auto").solve(robot, goal, q0=q_prev, seed=index, tol=1e-9)
        if not res.success:
            raise MoveError(index, f"PTP goal {goal} is unreachable (residual {res.error:.3g}); "
                                   "move it into the workspace")
        return res.q
    sols = [r.q for r in ik_all(robot, goal, q0=q_prev)]
    if not sols:
        raise MoveError(index, f"PTP goal {goal} is unreachable within the joint limits; "
                               "move it into the workspace")
    if elbow is not None:
        sols = [q for q in sols if signs_of(g, q)[0] == SIGN[elbow]]
        if not sols:
            raise MoveError(index, f"PTP goal {goal} is reachable only off the {elbow} branch "
                                   "within the joint limits; change elbow= or the goal")
    return sols[0]


def first_unreachable(robot: Robot, P: Array, yaws: Array | None, q_prev: Array) -> int | None:
    """Index of the first point the closed form cannot reach on ``q_prev``'s branch, if any.

    ``None`` also when the closed form does not apply (then nothing is known).
    """
    b = _branch_column(robot, yaws, q_prev)
    if b is None:
        return None
    _, valid = solve_batch(robot, P, yaws)
    bad = np.flatnonzero(~valid[:, b])
    return int(bad[0]) if bad.size else None


def _branch_column(robot: Robot, yaws: Array | None, q_prev: Array) -> int | None:
    """Column (0 or 1) of ``solve_batch``'s answers on ``q_prev``'s elbow branch.

    ``None`` where the closed form does not apply (no SCARA geometry, redundant joints, no
    wrist, no yaws) or ``q_prev`` is stretched out (on neither branch).
    """
    g = geometry(robot)
    if g is None or g.redundant or g.wrist < 0 or yaws is None:
        return None
    side = int(signs_of(g, q_prev)[0])
    return None if side == 0 else (0 if side > 0 else 1)


def closed_form_path(robot: Robot, P: Array, yaws: Array | None, q_prev: Array) -> Array | None:
    """Vectorised closed-form IK of a path on ``q_prev``'s branch, or ``None`` to fall back.

    Each revolute joint takes the turn nearest the previous point (``np.unwrap`` from
    ``q_prev``). ``None`` (use :func:`~scara_opt.ik_path`, which explains failures) when the
    robot has redundant joints or no wrist, the start is stretched out, or some point is out
    of reach, out of the limits, jumps, or misses its target by more than 1e-9.
    """
    b = _branch_column(robot, yaws, q_prev)
    g = geometry(robot)
    if b is None or g is None or yaws is None:  # (b is None already when g or yaws is)
        return None
    Q2, valid = solve_batch(robot, P, yaws)
    if not valid[:, b].all():
        return None
    Q = Q2[:, b, :].copy()
    revolute = np.flatnonzero(g.s)
    Q[:, revolute] = np.unwrap(np.vstack([q_prev[revolute], Q[:, revolute]]), axis=0)[1:]
    steps = np.abs(np.diff(np.vstack([q_prev, Q]), axis=0))
    if ((Q < robot.lower - 1e-12) | (Q > robot.upper + 1e-12)).any() \
            or (steps[:, revolute] > math.pi / 2).any():
        return None
    p, yaw = g.fk(Q)
    if np.abs(robot.positions(Q) - P).max() > 1e-9 or np.abs(yaw - yaws).max() > 1e-9:
        return None
    return Q


def path_joints(index: int, kind: str, robot: Robot, P: Array, yaws: Array | None,
                q_prev: Array, elbow: str | None, owner: list[int] | None = None) -> Array:
    """Joint path (n, nq) of a LIN/CIRC through positions ``P`` (n, 3), on one branch.

    ``owner`` (n,): the move index of each point, for the error (default ``index``).

    Raises:
        MoveError: a point unreachable, a joint jump, or the path leaving the start's branch
            (index of the point and its position named).
    """
    if elbow is not None:
        _check_branch(index, robot, q_prev, elbow,
                      f"the {kind} start (a {kind} keeps its branch; change it with a PTP)")
    fast = closed_form_path(robot, P, yaws, q_prev)
    if fast is not None:
        return fast
    stop = first_unreachable(robot, P, yaws, q_prev)
    if stop is not None:  # explain it with ik_path up to there only (slow on misses)
        _ik_path_joints(index, kind, robot, P[:stop + 1],
                        None if yaws is None else yaws[:stop + 1], q_prev, elbow,
                        None if owner is None else owner[:stop + 1], len(P))
    return _ik_path_joints(index, kind, robot, P, yaws, q_prev, elbow, owner, len(P))


def _ik_path_joints(index: int, kind: str, robot: Robot, P: Array, yaws: Array | None,
                    q_prev: Array, elbow: str | None, owner: list[int] | None,
                    total: int) -> Array:
    """:func:`path_joints` by :func:`~scara_opt.ik_path`, explaining any failure."""
    start = elbow_signs(robot, q_prev)
    targets = [Target(p, None if yaws is None else float(y))
               for p, y in zip(P, yaws if yaws is not None else [None] * len(P), strict=True)]
    jp = ik_path(robot, targets, q_start=q_prev, objective="fewest_jumps")  # a path to keep

    def who(i: int) -> int:
        return index if owner is None else owner[i]

    if jp.unsolved:
        i = jp.unsolved[0]
        where = f"point {i} of {total} at {np.round(P[i], 6).tolist()} m"
        if start is not None and ik_all(robot, targets[i]):
            side = NAME[int(start[0])]
            raise BranchError(who(i), f"{kind} leaves the {side} branch at {where}: it is "
                                      f"reachable there only on another branch; split the "
                                      "move there with a PTP that flips the elbow "
                                      "(plan(..., allow_flip=True) does it), or keep the path "
                                      "where this branch reaches", i, side)
        if yaws is not None and ik_all(robot, Target(P[i])):
            raise MoveError(who(i), f"{kind} {where} is reachable, but not with the tool yaw "
                                    f"{yaws[i]:.4g} rad the move gives it there (interpolated "
                                    "from the start's yaw to the goal's; held when the goal has "
                                    "none): the joint limits (the wrist's) exclude that yaw; "
                                    "give the goal a yaw, Target(position, yaw=), that turns "
                                    "the tool with the arm, or split the move")
        raise MoveError(who(i), f"{kind} {where} is unreachable (residual "
                                f"{jp.error[i]:.3g}); the path leaves the workspace (or passes "
                                "the base hole): move the goal, or go around with several "
                                "moves")
    Q = jp.q
    g = geometry(robot)
    if start is not None and g is not None:  # (g is None only where start is)
        signs = signs_of(g, Q)
        ref = start[0] if start[0] != 0 else (signs[signs != 0][:1] or [0])[0]
        off = np.flatnonzero((signs != ref) & (signs != 0))
        if off.size:
            i = int(off[0])
            raise BranchError(who(i), f"{kind} leaves the {NAME[int(ref)]} branch at point {i} "
                                      f"of {total}, {np.round(P[i], 6).tolist()} m: it cannot "
                                      "be done on one branch; split it there with a PTP that "
                                      "flips the elbow (plan(..., allow_flip=True) does it), or "
                                      "move the path away from the stretched arm", i,
                                      NAME[int(ref)])
    if jp.jumps:
        j = jp.jumps[0]
        raise MoveError(who(j.index), f"{kind} joint path jumps at point {j.index} of {total}, "
                               f"{np.round(P[j.index], 6).tolist()} m ({j}): a singular pose "
                               "or a wrist turn; move the path away from it")
    return Q
