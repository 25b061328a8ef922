r"""Blending runs that contain a PTP: corners rounded in joint space, within r of the goal.

Each move of the run keeps its own joint path (a PTP its joint line, a LIN/CIRC the IK of
its tool points). At a corner C with ``blend = r`` the path is cut where the tip enters the
sphere of radius r about C on the move it leaves (point A, its last entry) and where it
leaves the sphere on the next move (point B, its first exit), both found by bisection on
the joint path, and the quadratic Bézier in joint space :math:`A \to q_C \to B` replaces
the corner. To first order in the joint offsets its tip is
:math:`C + (1-s)^2 (p_A - C) + s^2 (p_B - C)`, inside the sphere; every corner point is
checked by FK, and a corner that leaves the sphere is refused. The Bézier lies in the
convex hull of three in-limit configurations, so inside the joint box.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import MoveError
from scara_opt.model.robot import Robot
from scara_opt.motion import geometry
from scara_opt.motion.moves import PTP, Move

Array = NDArray[np.float64]

#: bisection steps locating where the tip crosses a blend sphere
BISECT = 40

#: samples of a PTP's joint line used to measure its tool path
PROBE = 65


def _ptp_line(robot: Robot, q0: Array, q1: Array, step: float) -> Array:
    """A PTP's joint line sampled so the tip moves at most about ``step`` [m] per sample."""
    f = np.linspace(0.0, 1.0, PROBE)[:, None]
    P = robot.positions(q0 + f * (q1 - q0))
    n = geometry.count(_tool_length(P), step, least=2)
    return q0 + np.linspace(0.0, 1.0, n)[:, None] * (q1 - q0)


def _crossing(robot: Robot, inside: Array, outside: Array, c: Array, r: float) -> Array:
    """The configuration between two (joint-linearly) where the tip is at distance r from c."""
    a, b = outside, inside
    for _ in range(BISECT):
        m = (a + b) / 2
        if np.linalg.norm(robot.position(m) - c) > r:
            a = m
        else:
            b = m
    return b


def _tool_length(P: Array) -> float:
    """Length [m] of the polyline through the tip positions ``P`` (n, 3)."""
    return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


def joint_blended(section: list[tuple[int, Move]], robot: Robot, q_prev: Array, step: float,
                  move_joints: Callable[..., Array]
                  ) -> tuple[Array, list[tuple[Array, float]], list[int]]:
    """Joint path (n, nq) of a blended run with a PTP in it, from ``q_prev``; its corners.

    Returns:
        ``(Q, corners, owner)`` as :func:`~scara_opt.motion.blend.blended_joints`.

    Raises:
        MoveError: a radius above half of this or the next move's tool path (naming the move
            and the largest radius allowed), a corner that leaves its sphere, and the errors
            of each move's own path.
    """
    paths, q = [], q_prev
    for index, move in section:
        Q = move_joints(index, move, robot, q, step)
        if isinstance(move, PTP):
            Q = _ptp_line(robot, Q[0], Q[-1], step)
        paths.append((Q, robot.positions(Q)))
        q = Q[-1]
    for j, (index, move) in enumerate(section[:-1]):
        geometry.check_blend(index, move.blend,
                             min(_tool_length(paths[j][1]), _tool_length(paths[j + 1][1])) / 2)
    rows, owner, corners = [q_prev[None, :]], [section[0][0]], []
    start = 1  # first row of the current move's path still to take
    for j, (index, move) in enumerate(section):
        Q, P = paths[j]
        if j == len(section) - 1:
            rows.append(Q[start:])
            owner += [index] * (len(Q) - start)
            break
        r, c = move.blend, P[-1]
        Qn, Pn = paths[j + 1]
        out = np.flatnonzero(np.linalg.norm(P[start:] - c, axis=1) > r) + start
        out_next = np.flatnonzero(np.linalg.norm(Pn - c, axis=1) > r)
        if not out.size or not out_next.size:
            raise MoveError(index, f"blend radius {r:g} m: the tip stays within it of this "
                                   "move's goal along the whole of this or the next move's "
                                   "remaining path; pass a smaller blend")
        a, b = int(out[-1]), int(out_next[0])  # last sample outside, first one outside
        A = _crossing(robot, Q[a + 1], Q[a], c, r)
        B = _crossing(robot, Qn[b - 1], Qn[b], c, r)
        s = np.linspace(0.0, 1.0, geometry.corner_count(r, step))[:, None]
        corner = (1 - s) ** 2 * A + 2 * s * (1 - s) * Q[-1] + s**2 * B
        dist = np.linalg.norm(robot.positions(corner) - c, axis=1)
        if dist.max() > r * (1 + 1e-9):
            raise MoveError(index, f"the joint-space corner of blend radius {r:g} m leaves its "
                                   f"sphere ({dist.max():.6g} m from the goal): a sharp turn "
                                   "of the joints there; pass a smaller blend")
        # a sample within a quarter step of A or B is dropped: near-duplicate waypoints
        # would make the spline degenerate (a sample lying on the sphere, e.g.)
        end = a if np.linalg.norm(P[a] - c) - r < step / 4 else a + 1
        rows += [Q[start:max(end, start)], corner]
        owner += [index] * (max(end, start) - start + len(corner))
        corners.append((c, r))
        start = b + 1 if np.linalg.norm(Pn[b] - c) - r < step / 4 and b + 1 < len(Qn) else b
    return np.vstack(rows), corners, owner
