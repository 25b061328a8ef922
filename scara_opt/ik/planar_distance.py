r"""How near a SCARA's planar arm can bring its tip to a point, within its joint limits: exactly.

The arm of a SCARA-type chain (:mod:`scara_opt.ik.geometry`) places its tip in the plane at

.. math:: F(α, γ) = l_1 e(α) + l_2 e(α + γ), \qquad e(φ) = (\cos φ, \sin φ),

with ``α`` link 1's angle and ``γ`` the elbow's (both affine in the joint values, so the
joint limits make a rectangle of ``(α, γ)``), plus ``t d`` for a rail joint. A tool angle
within ``β`` of a target's adds a band :math:`S_{lo} ≤ α + γ ≤ S_{hi}` (modulo 2π) to the
rectangle; each band makes a convex polygon ``D`` of ``(α, γ)``.

**The argument** (a reader can check it line by line):

1. Where the Jacobian of ``F`` is regular (:math:`\det = l_1 l_2 \sin γ ≠ 0`), ``F`` is a
   local diffeomorphism, so it maps interior points of ``D`` to interior points of
   ``F(D)``. The boundary of ``F(D)`` therefore lies in ``F(∂D) ∪ F(D ∩ \{γ ∈ πℤ\})``.
2. Every edge of ``D`` keeps ``α``, ``γ`` or ``α + γ`` constant, and so does a singular
   line (``γ = kπ``): each maps onto an **arc of a circle** (centre ``l_1 e(α)``, radius
   ``l_2``; centre 0, radius ``|l_1 + l_2 e(γ)|``; centre ``l_2 e(α+γ)``, radius ``l_1``).
3. A point ``x`` outside the closed set ``F(D)`` is nearest to it at a boundary point, so
   its distance to ``F(D)`` is its distance to those arcs (they lie in ``F(D)``, so the
   distance is not smaller either). With a rail, the tip reaches ``uv`` where the segment
   ``{uv − t d}`` meets ``F(D)``; the segment is connected, so if it meets ``F(D)`` without
   touching the arcs it lies inside ``F(D)``, end points included. Hence: **either the
   segment's first end is in** ``F(D)`` (:func:`reaches` decides it by the closed form),
   **or the least distance from the segment to the arcs is the least distance from the
   target to anything the limits allow** (:func:`segment_arc_distance`, exact: end points,
   the arc's perpendiculars and crossings are every candidate for a minimum).

Every test in floating point leans the safe way: ranges are widened by :data:`ANGLE_SLACK`,
an arc point "inside" when within it, a candidate kept when in doubt; each of these can only
lower the distance found, never raise it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scara_opt.ik.closed_form import link_angles, turns
from scara_opt.ik.geometry import ScaraGeometry
from scara_opt.model.robot import Array

#: joint-angle ranges and the arcs' ends are widened by this much [rad] (round-off)
ANGLE_SLACK = 1e-12
_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class Arc:
    """Points ``centre + radius e(φ)`` for φ in [start, stop] [m, rad].

    A full circle where ``stop - start >= 2π``.
    """

    centre: Array
    radius: float
    start: float
    stop: float

    def full(self) -> bool:
        """The whole circle."""
        return self.stop - self.start >= _TWO_PI

    def covers(self, phi: float) -> bool:
        """Whether the angle ``phi`` [rad] lies on the arc (within :data:`ANGLE_SLACK`)."""
        if self.full():
            return True
        d = (phi - self.start) % _TWO_PI
        return d <= self.stop - self.start + ANGLE_SLACK or d >= _TWO_PI - ANGLE_SLACK

    def ends(self) -> list[Array]:
        """The two end points (none for a full circle)."""
        if self.full():
            return []
        return [self.centre + self.radius * np.array([math.cos(a), math.sin(a)])
                for a in (self.start, self.stop)]


@dataclass(frozen=True)
class Domain:
    """Link angles a SCARA's limits allow [rad]: a rectangle, cut by a tool-angle band.

    α in [a_lo, a_hi], γ in [g_lo, g_hi], and α + γ in [s_lo, s_hi] (``±inf``: no band).
    """

    a_lo: float
    a_hi: float
    g_lo: float
    g_hi: float
    s_lo: float = -math.inf
    s_hi: float = math.inf

    def contains(self, a: float, g: float) -> bool:
        """Whether (α, γ) lies in the domain, within :data:`ANGLE_SLACK`."""
        e = ANGLE_SLACK
        return (self.a_lo - e <= a <= self.a_hi + e and self.g_lo - e <= g <= self.g_hi + e
                and self.s_lo - e <= a + g <= self.s_hi + e)


def link_ranges(geom: ScaraGeometry, lower: Array, upper: Array) -> tuple[float, ...]:
    """(α_lo, α_hi, γ_lo, γ_hi) [rad] of link 1's angle and the elbow angle."""
    sh, el = geom.shoulder, geom.elbow
    a = sorted(geom.phi1 + geom.s[sh] * np.array([lower[sh], upper[sh]]))
    g = sorted(geom.phi2 - geom.phi1 + geom.s[el] * np.array([lower[el], upper[el]]))
    return a[0], a[1], g[0], g[1]


def _span(lo: float, hi: float) -> tuple[float, float] | None:
    """[lo, hi] widened by the slack, or None if empty."""
    return (lo - ANGLE_SLACK, hi + ANGLE_SLACK) if lo <= hi + 2 * ANGLE_SLACK else None


def arcs(geom: ScaraGeometry, dom: Domain) -> list[Arc]:
    """The arcs holding the boundary of ``F(dom)`` (step 2 of the module's argument).

    The images of the domain's edges and of its singular lines (γ = kπ).
    """
    l1, l2 = geom.l1, geom.l2
    out = []

    def alpha_const(a: float, g0: float, g1: float) -> None:  # link 2 turns about the elbow
        if (s := _span(max(g0, dom.s_lo - a), min(g1, dom.s_hi - a))) is not None:
            out.append(Arc(l1 * np.array([math.cos(a), math.sin(a)]), l2, a + s[0], a + s[1]))

    def gamma_const(g: float) -> None:  # the folded arm turns about the shoulder
        if (s := _span(max(dom.a_lo, dom.s_lo - g), min(dom.a_hi, dom.s_hi - g))) is None:
            return
        w = complex(l1 + l2 * math.cos(g), l2 * math.sin(g))
        out.append(Arc(np.zeros(2), abs(w), s[0] + math.atan2(w.imag, w.real),
                       s[1] + math.atan2(w.imag, w.real)))

    def sum_const(sigma: float) -> None:  # link 2 keeps its direction, link 1 turns
        if (s := _span(max(dom.a_lo, sigma - dom.g_hi), min(dom.a_hi, sigma - dom.g_lo))):
            out.append(Arc(l2 * np.array([math.cos(sigma), math.sin(sigma)]), l1, *s))

    alpha_const(dom.a_lo, dom.g_lo, dom.g_hi)
    alpha_const(dom.a_hi, dom.g_lo, dom.g_hi)
    gamma_const(dom.g_lo)
    gamma_const(dom.g_hi)
    for sigma in (dom.s_lo, dom.s_hi):
        if math.isfinite(sigma):
            sum_const(sigma)
    for k in range(math.ceil(dom.g_lo / math.pi), math.floor(dom.g_hi / math.pi) + 1):
        gamma_const(k * math.pi)
    return out


def reaches(geom: ScaraGeometry, dom: Domain, x: Array) -> bool:
    """Whether ``x`` (2,) [m, relative to the shoulder axis] is in ``F(dom)``.

    The closed form's two elbow branches, at every turn, tested against the domain.
    """
    l1, l2 = geom.l1, geom.l2
    c = (float(x @ x) - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    if abs(c) > 1.0:
        return False
    for a, g in link_angles(geom, x, c):
        for gk in turns(g, dom.g_lo - ANGLE_SLACK, dom.g_hi + ANGLE_SLACK):
            for ak in turns(a, dom.a_lo - ANGLE_SLACK, dom.a_hi + ANGLE_SLACK):
                if dom.contains(ak, gk):
                    return True
    return False


def point_arc_distance(x: Array, arc: Arc) -> float:
    """The distance [m] from the point ``x`` (2,) to the arc.

    Radial where the ray from the centre through ``x`` meets the arc, else the nearer end.
    """
    w = x - arc.centre
    r = math.hypot(w[0], w[1])
    if r == 0.0 or arc.covers(math.atan2(w[1], w[0])):
        return abs(r - arc.radius)
    return min(math.hypot(*(x - p)) for p in arc.ends())


def _point_segment_distance(p: Array, x0: Array, x1: Array) -> float:
    d = x1 - x0
    dd = float(d @ d)
    t = 0.0 if dd == 0.0 else min(max(float((p - x0) @ d) / dd, 0.0), 1.0)
    return math.hypot(*(x0 + t * d - p))


def segment_arc_distance(x0: Array, x1: Array, arc: Arc) -> float:
    """The distance [m] between the segment [x0, x1] (2,) and the arc.

    The least over every candidate for a minimum of ``|x(t) − y(φ)|`` on the rectangle
    of (t, φ): the rectangle's sides (the segment's ends against the arc, the arc's ends against the
    segment); inside it, a crossing (distance 0) or a pair whose joining line is normal to
    both, which needs ``e(φ) ⊥ x1 − x0`` (two angles).
    """
    best = min(point_arc_distance(x0, arc), point_arc_distance(x1, arc))
    for p in arc.ends():
        best = min(best, _point_segment_distance(p, x0, x1))
    d = x1 - x0
    dd = float(d @ d)
    if dd == 0.0:
        return best
    slack = ANGLE_SLACK
    normal = math.atan2(d[1], d[0]) + 0.5 * math.pi
    for phi in (normal, normal + math.pi):
        if arc.covers(phi):
            y = arc.centre + arc.radius * np.array([math.cos(phi), math.sin(phi)])
            t = float((y - x0) @ d) / dd
            if -slack <= t <= 1.0 + slack:
                best = min(best, math.hypot(*(x0 + t * d - y)))
    w = x0 - arc.centre  # crossings: |w + t d| = R
    b, c = float(w @ d), float(w @ w) - arc.radius**2
    disc = b * b - dd * c
    if disc >= 0.0:
        for t in ((-b - math.sqrt(disc)) / dd, (-b + math.sqrt(disc)) / dd):
            p = w + t * d
            if -slack <= t <= 1.0 + slack and arc.covers(math.atan2(p[1], p[0])):
                return 0.0
    return best


def distance(geom: ScaraGeometry, domains: list[Domain], x0: Array, x1: Array) -> float:
    """The least distance [m] from the segment [x0, x1] to the tips ``F(D)`` of ``domains``.

    A point where ``x1 is x0``; 0 where ``x0`` is reached (the module's step 3).
    """
    best = math.inf
    for dom in domains:
        if reaches(geom, dom, x0):
            return 0.0
        for arc in arcs(geom, dom):
            best = min(best, segment_arc_distance(x0, x1, arc) if x1 is not x0
                       else point_arc_distance(x0, arc))
    return best
