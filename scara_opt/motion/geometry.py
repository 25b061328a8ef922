"""Cartesian geometry of LIN and CIRC moves: the tool points they pass, sampled by arc length.

Positions [m], yaw [rad]. A LIN is the straight segment; a CIRC the arc of the unique circle
through start, via and goal, from start through via to goal. Yaw is interpolated linearly in
arc length from the start yaw to the goal yaw taken at the nearest turn (|Δyaw| <= π).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import MoveError

Array = NDArray[np.float64]

#: share by which a blend radius may exceed half a tool path: the path's length comes from
#: the FK of its joint values (a 25 mm stroke measures 0.024999999999999994 m)
BLEND_SLACK = 1e-9

#: below this sine of the angle at the start, the three CIRC points count as collinear
COLLINEAR_SINE = 1e-6


def nearest_turn(yaw: float, reference: float) -> float:
    """``yaw + 2πk`` nearest to ``reference`` [rad]."""
    return reference + math.remainder(yaw - reference, 2.0 * math.pi)


def check_blend(index: int, radius: float, half: float) -> None:
    """Refuse a blend radius above ``half`` [m], half the shorter of two tool paths.

    Up to round-off (:data:`BLEND_SLACK`) it is allowed: a radius of exactly half a 25 mm
    stroke passes. The largest radius named is itself allowed (10 significant digits).

    Raises:
        MoveError: naming the move, the radius and the largest one allowed.
    """
    if radius > half * (1.0 + BLEND_SLACK):
        raise MoveError(index, f"blend radius {radius:.10g} m is more than half of this or the "
                               f"next move's tool path ({2 * half:.10g} m); pass blend <= "
                               f"{half:.10g}")


def count(length: float, step: float, least: int = 8) -> int:
    """Number of samples (>= ``least``) so that consecutive ones are at most ``step`` apart."""
    return max(least, math.ceil(length / step) + 1)


def corner_count(radius: float, step: float) -> int:
    """Samples (odd, >= 5) of a blend corner of ``radius`` [m]: at most ``step`` apart.

    Odd, so that the corner's middle (Bézier parameter 1/2) is a sample: where a move turns
    back along itself (a LIN down, blended into a LIN up), the corner's ends coincide and its
    samples are mirror images about the middle; an even count would put two equal samples
    next to each other (a zero step, which the spline through them cannot take).
    """
    n = count(2.0 * radius, step, least=5)
    return n + 1 - n % 2


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


class Curve:
    """A LIN or CIRC tool path by arc-length fraction: :meth:`at` (m,) in [0, 1] → (m, 3) [m].

    ``circle`` is ``None`` for a line, else the ``(centre, radius, u, w, sweep)`` of
    :func:`circle`.
    """

    def __init__(self, start: Array, end: Array,
                 circle: tuple[Array, float, Array, Array, float] | None = None) -> None:
        self.start, self.end, self.circle = start, end, circle
        self.length = (float(np.linalg.norm(end - start)) if circle is None
                       else circle[1] * circle[4])

    def at(self, f: Array) -> Array:
        """Points (m, 3) at arc-length fractions ``f`` (m,)."""
        f = np.asarray(f, dtype=float)
        if self.circle is None:
            return self.start + f[:, None] * (self.end - self.start)
        centre, r, u, w, sweep = self.circle
        th = f * sweep
        return centre + r * (np.cos(th)[:, None] * u + np.sin(th)[:, None] * w)


def bezier(a: Array, corner: Array, b: Array, n: int) -> Array:
    """Quadratic Bézier (n, 3) from ``a`` to ``b`` with control point ``corner``.

    It lies in the triangle (a, corner, b), so within max(|a - corner|, |b - corner|) of the
    corner, and passes it at ``|a + b - 2 corner| / 4``.
    """
    t = np.linspace(0.0, 1.0, n)[:, None]
    return (1 - t) ** 2 * a + 2 * t * (1 - t) * corner + t**2 * b
