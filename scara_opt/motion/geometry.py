"""Cartesian geometry of LIN and CIRC moves: the tool points they pass, sampled by arc length.

Positions [m], yaw [rad]. A LIN is the straight segment; a CIRC the arc of the unique circle
through start, via and goal, from start through via to goal. Yaw is interpolated linearly in
arc length from the start yaw to the goal yaw taken at the nearest turn (|Δyaw| <= π).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: below this sine of the angle at the start, the three CIRC points count as collinear
COLLINEAR_SINE = 1e-6


def nearest_turn(yaw: float, reference: float) -> float:
    """``yaw + 2πk`` nearest to ``reference`` [rad]."""
    return reference + math.remainder(yaw - reference, 2.0 * math.pi)


def count(length: float, step: float, least: int = 8) -> int:
    """Number of samples (>= ``least``) so that consecutive ones are at most ``step`` apart."""
    return max(least, math.ceil(length / step) + 1)


def line(p0: Array, p1: Array, step: float) -> tuple[Array, Array]:
    """Points (n, 3) along the segment and their fraction of the length (n,) in [0, 1]."""
    n = count(float(np.linalg.norm(p1 - p0)), step)
    f = np.linspace(0.0, 1.0, n)
    return p0 + f[:, None] * (p1 - p0), f


def circle(p0: Array, via: Array, p1: Array) -> tuple[Array, float, Array, Array, float] | None:
    """Circle through three points: ``(centre, radius, u, w, sweep)`` or ``None`` if collinear.

    ``u`` points from the centre to ``p0``, ``w`` is in the plane, 90° ahead in the sense of
    travel, and ``sweep`` is the angle [rad] from ``p0`` through ``via`` to ``p1`` (0, 2π).
    """
    a, b = via - p0, p1 - p0
    n = np.cross(a, b)
    nn = float(np.linalg.norm(n))
    scale = float(np.linalg.norm(a) * np.linalg.norm(b))
    if scale == 0.0 or nn <= COLLINEAR_SINE * scale:
        return None
    # circumcentre of the triangle (p0, via, p1)
    centre = p0 + (np.dot(a, a) * np.cross(b, n) + np.dot(b, b) * np.cross(n, a)) / (2 * nn**2)
    r = float(np.linalg.norm(p0 - centre))
    u = (p0 - centre) / r
    w = np.cross(n / nn, u)

    def angle(p: Array) -> float:
        d = p - centre
        return math.atan2(float(np.dot(d, w)), float(np.dot(d, u))) % (2.0 * math.pi)

    return centre, r, u, w, angle(p1)


def arc(centre: Array, r: float, u: Array, w: Array, sweep: float,
        step: float) -> tuple[Array, Array]:
    """Points (n, 3) on the arc and their fraction of its length (n,)."""
    n = count(r * sweep, step)
    f = np.linspace(0.0, 1.0, n)
    th = f * sweep
    return centre + r * (np.cos(th)[:, None] * u + np.sin(th)[:, None] * w), f
