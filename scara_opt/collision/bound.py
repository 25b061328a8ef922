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
from numpy.typing import NDArray

from scara_opt.collision.geometry import Body
from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

__all__ = ["body_weights", "pair_weights"]


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


def pair_weights(robot: Robot, bodies: tuple[Body, ...] | list[Body], pairs: object) -> Array:
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
