r"""How far a robot body can move when its joints move: the bound behind every proof.

Let a body *b* ride on joint *i* of the serial chain, and let joints
:math:`1..i` move. A point *p* of *b* moves with speed

.. math:: |\dot p| \le \sum_{j \le i} |\dot q_j|\, r_j(b),

where, for a revolute joint *j*, :math:`r_j(b)` bounds the distance from joint *j*'s axis to
any point of *b* (:math:`|\omega_j \times (p - o_j)|` is that distance times
:math:`|\dot q_j|`), and for a prismatic joint :math:`r_j = 1`. The radii are bounded once
per robot, for every configuration (:func:`body_weights`): for *j* = *i* exactly, from the
body's support points in its own frame; for *j* < *i*, the distance from axis *j* to the next
joint's origin :math:`o_{j+1}` (constant under rotations about axis *j*; over the stroke of a
prismatic joint *j+1*), plus the longest way from :math:`o_{j+1}` to any point of *b*
along the chain (each link's length, a prismatic joint's at either end of its stroke, then
the body's farthest point from its frame's origin: the triangle inequality). A mimic joint
adds :math:`|s|` times its radius to its leader's column.

For two robot bodies on joints :math:`i_1 \le i_2`, joints up to :math:`i_1` move both
rigidly and leave their distance unchanged: only the joints after :math:`i_1` count
(:func:`pair_weights`). An obstacle does not move.

"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.collision.geometry import Body, reference_configuration
from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

__all__ = ["body_weights", "height_gaps", "height_range", "pair_weights"]


def _hop(robot: Robot, k: int) -> Array:
    """Origins (2, 3) of model joint ``k``'s moving frame in joint ``k - 1``'s frame.

    At both ends of joint ``k``'s stroke when it is prismatic (the same point twice otherwise).
    """
    cj = robot.chain[k - 1]
    P = cj.placement
    if cj.kind != "prismatic":
        return np.array([P[:3, 3], P[:3, 3]])
    lo, hi = robot.lower[cj.index], robot.upper[cj.index]
    v = np.array([cj.scaling * lo + cj.offset, cj.scaling * hi + cj.offset])
    return P[:3, 3] + np.outer(v, P[:3, :3] @ cj.axis)


def _axis_distance(points: Array, axis: Array) -> Array:
    """Distances (k,) of ``points`` (k, 3) from the line through the origin along ``axis``."""
    return np.linalg.norm(points - np.outer(points @ axis, axis), axis=1)


def body_weights(robot: Robot, body: Body, after: int = 0) -> Array:
    r"""Bound (nq,) on the speed of any point of ``body`` per unit joint speed [m/rad or m/m].

    Column ``q`` index: :math:`\sum_j |s_j| r_j(b)` over the chain joints driven by that
    coordinate, up to the body's own joint, leaving out joints ``<= after`` (the module
    docstring). Zero for a body fixed in the world.
    """
    w = np.zeros(robot.nq)
    i = body.joint
    reach = float(np.linalg.norm(body.points, axis=1).max()) + body.pad  # |p - o_i|
    for j in range(i, after, -1):
        cj = robot.chain[j - 1]
        if cj.kind == "prismatic":
            r = 1.0
        elif j == i:
            r = float(_axis_distance(body.points, cj.axis).max()) + body.pad
        else:  # reach bounds |p - o_{j+1}|
            r = float(_axis_distance(_hop(robot, j + 1), cj.axis).max()) + reach
        w[cj.index] += abs(cj.scaling) * r
        if j < i:  # for joint j - 1: |p - o_j| <= |p - o_{j+1}| + |o_{j+1} - o_j|
            reach += float(np.linalg.norm(_hop(robot, j + 1), axis=1).max())
    return w


def pair_weights(robot: Robot, bodies: tuple[Body, ...] | list[Body], pairs: ArrayLike) -> Array:
    """Bound (npairs, nq) on how fast each checked pair's distance can change per joint speed.

    Robot body against obstacle: the body's :func:`body_weights`; two robot bodies: only
    the joints after the lower one's (see the module docstring).
    """
    per_body = [body_weights(robot, b) for b in bodies]
    pairs = np.asarray(pairs, dtype=int).reshape(-1, 2)
    out = np.zeros((len(pairs), robot.nq))
    for p, (i, j) in enumerate(pairs):
        a, b = bodies[i], bodies[j]
        if b.joint == 0:
            out[p] = per_body[i]
        elif a.joint == 0:
            out[p] = per_body[j]
        else:
            lo, hi = (a, b) if a.joint <= b.joint else (b, a)
            out[p] = body_weights(robot, hi, after=lo.joint)
    return out


def height_range(robot: Robot, body: Body, n: Array, fixed: bool = False
                 ) -> tuple[float, float]:
    r"""Smallest and largest :math:`n \cdot p` of ``body`` over all ``q`` within the limits [m].

    For a robot whose revolute axes are all parallel to ``n`` (a SCARA). Rotations about
    *n* leave every vector's component along *n* unchanged, so
    :math:`n \cdot p(q) = n \cdot p(q_0) + \sum_j (n \cdot a_j)(v_j - v_{j,0})` over the
    prismatic joints *j* up to the body's (world axis :math:`a_j`, whose component along
    *n* is constant too): exact, over the limits, from the reference configuration
    :math:`q_0`. With ``fixed``, the range at :math:`q_0` alone.
    """
    q0 = reference_configuration(robot)
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, q0)
    M = data.oMi[body.joint]
    h = (body.points @ M.rotation.T + M.translation) @ n
    lo, hi = float(h.min()) - body.pad, float(h.max()) + body.pad
    k = 0 if fixed else body.joint
    while k > 0:
        cj = robot.chain[k - 1]
        if cj.kind == "prismatic":
            c = float(n @ (data.oMi[k].rotation @ cj.axis)) * cj.scaling
            span = (c * (robot.lower[cj.index] - q0[cj.index]),
                    c * (robot.upper[cj.index] - q0[cj.index]))
            lo, hi = lo + min(span), hi + max(span)
        k = robot.model.parents[k]
    return lo, hi


def height_gaps(robot: Robot, bodies: list[Body], pairs: ArrayLike,
                obstacles: dict[int, tuple[float, float]]) -> tuple[Array, Array, Array] | None:
    r"""Each pair's separation along a SCARA's common axis, as affine functions of ``q``.

    For a robot whose revolute axes are all parallel to ``n`` (else ``None``): a robot
    body's range along *n* moves only with the prismatic joints, linearly
    (:func:`height_range`), so for a pair (body, obstacle) the gap above the obstacle
    :math:`g_+(q) = A q + a` and below it :math:`g_-(q) = -A q + b` are exact and affine
    in ``q``. Where either is positive the pair is apart by at least that much; along a
    straight joint segment it is positive throughout when it is at both ends.

    Args:
        robot: the robot.
        bodies: every body (robot bodies first, obstacles after).
        pairs: (npairs, 2) body indices.
        obstacles: ``{body index: (lowest, highest)}`` of each obstacle along *n* [m].

    Returns:
        ``(A (npairs, nq), a (npairs,), b (npairs,))``; ``a = b = -inf`` for pairs of two
        robot bodies (both move).
    """
    n = robot.yaw_axis
    if n is None:
        return None
    q0 = reference_configuration(robot)
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, q0)
    pairs = np.asarray(pairs, dtype=int).reshape(-1, 2)
    A = np.zeros((len(pairs), robot.nq))
    a = np.full(len(pairs), -np.inf)
    b = np.full(len(pairs), -np.inf)
    for p, (i, j) in enumerate(pairs):
        if j not in obstacles:
            continue
        body = bodies[i]
        lo, hi = height_range(robot, body, n, fixed=True)
        k = body.joint
        while k > 0:
            cj = robot.chain[k - 1]
            if cj.kind == "prismatic":
                A[p, cj.index] += float(n @ (data.oMi[k].rotation @ cj.axis)) * cj.scaling
            k = robot.model.parents[k]
        o_lo, o_hi = obstacles[j]
        a[p] = lo - float(A[p] @ q0) - o_hi
        b[p] = o_lo - hi + float(A[p] @ q0)
    return A, a, b
