r"""Blending: consecutive LIN/CIRC moves run without stopping, each corner rounded within r.

A move with ``blend = r`` does not stop at its goal C: its path is cut at arc length ``r``
before C (point A), the next move's at ``r`` after C (point B), and a quadratic Bézier
A → (C) → B replaces the corner. The Bézier lies in the triangle (A, C, B), so every point of
it is within ``r`` of C and it misses C by :math:`|A + B - 2C| / 4 \le r / 2`. The yaw goes
linearly from A's to B's. The whole blended run is one joint path (IK on one branch) timed
in one go, each stretch under its own move's tool limits (a corner under the move it leaves,
the smaller of both where they meet). Runs with a PTP: :mod:`scara_opt.motion.blend_joint`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import MoveError
from scara_opt.model.robot import Robot
from scara_opt.motion import branch, geometry
from scara_opt.motion.moves import Move, goal_point
from scara_opt.target import Target

Array = NDArray[np.float64]

#: a span shorter than this [m] (radius = half the move) is one point
SAME = 1e-9


def _span(curve: geometry.Curve, a: float, b: float, step: float) -> Array:
    """Points of ``curve`` between arc lengths ``a`` and ``b`` [m], both ends included."""
    n = geometry.count(b - a, step, least=2) if b - a > SAME else 1
    return curve.at(np.linspace(a, b, n) / curve.length)


def blended_joints(section: list[tuple[int, Move]], robot: Robot, q_prev: Array, step: float,
                   move_curve: Callable[[int, Move, Robot, Array, float | None],
                                        tuple[geometry.Curve, float | None]]
                   ) -> tuple[Array, list[tuple[Array, float]], list[int]]:
    """Joint path (n, nq) of a blended run of LIN/CIRC moves from ``q_prev``, and its corners.

    Returns:
        ``(Q, corners, owner)``: Q's first row is ``q_prev``; corners are ``(C (3,), r)``;
        ``owner`` (n,) the move index of each row (a corner's points: the move it leaves).

    Raises:
        MoveError: a radius above half of the move's or the next move's tool path (naming
            the move and the largest radius allowed); the path errors of
            :func:`~scara_opt.motion.branch.path_joints`, naming the move the point is on.
    """
    p, yaw = branch.tool_pose(robot, q_prev)
    curves = []
    for index, move in section:
        curve, yaw1 = move_curve(index, move, robot, p, yaw)
        curves.append((curve, yaw, yaw1))
        p, yaw = curve.end, yaw1
    for j, (index, move) in enumerate(section[:-1]):
        geometry.check_blend(index, move.blend,
                             min(curves[j][0].length, curves[j + 1][0].length) / 2)
    P: list[Array] = []
    Y: list[Array | None] = []  # yaws: all None (no yaw axis) or none
    owner: list[int] = []
    corners: list[tuple[Array, float]] = []
    for j, (index, move) in enumerate(section):
        curve, y0, y1 = curves[j]
        a = section[j - 1][1].blend if j else 0.0
        b = curve.length - (move.blend if j < len(section) - 1 else 0.0)
        pts = _span(curve, a, b, step)
        f = np.linspace(a, b, len(pts)) / curve.length
        ys = None if y0 is None or y1 is None else y0 + f * (y1 - y0)
        if j:  # the Bézier from the previous move's cut to this one's
            prev = section[j - 1][1].blend
            A, C = P[-1][-1], curves[j - 1][0].end
            corner = geometry.bezier(A, C, pts[0], geometry.corner_count(prev, step))
            corners.append((C, prev))
            last = Y[-1]
            yb = None if ys is None or last is None else np.linspace(last[-1], ys[0], len(corner))
            P.append(corner[1:-1])
            Y.append(None if yb is None else yb[1:-1])
            owner += [section[j - 1][0]] * (len(corner) - 2)
        P.append(pts)
        Y.append(ys)
        owner += [index] * len(pts)
    P_all = np.vstack(P)
    yaws = [y for y in Y if y is not None]
    assert len(yaws) in (0, len(Y)), "every point of a run has a yaw, or none has"
    Y_all = np.concatenate(yaws) if yaws else None
    for index, move in section:
        if move.elbow is not None:
            branch.path_joints(index, move.kind, robot, P_all[:1], None if Y_all is None
                               else Y_all[:1], q_prev, move.elbow)
    Q = branch.path_joints(section[0][0], "blended run", robot, P_all[1:],
                           None if Y_all is None else Y_all[1:], q_prev, None, owner[1:])
    goal = goal_point(section[-1][0], section[-1][1].goal, robot.nq, "goal")
    if not isinstance(goal, Target) and np.abs(Q[-1] - goal).max() > 1e-6:
        raise MoveError(section[-1][0], "the blended run does not end at the joint goal "
                                        "(another branch or wrist turn); reach it with a PTP")
    return np.vstack([q_prev, Q]), corners, owner
