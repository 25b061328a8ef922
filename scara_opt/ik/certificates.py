"""Certificates: checkable proofs that a target cannot be reached within ``tol``.

An IK status of ``"unreachable"`` is granted only with one of these (see
:mod:`scara_opt.ik.verdict`). Each states a lower bound on the residual of every
configuration within the joint limits, or, for the closed form's exhaustive search, that no
configuration reaches the target (with the limits widened by a tol-equivalent margin).

* SCARA-type chains (position and yaw targets): :func:`scara_certificate` (height, reach,
  the exhaustive closed form over the whole range of the redundant joints);
* chains whose revolute axes are all parallel, full-rotation targets:
  :func:`tilt_certificate` (the tool cannot tilt);
* any serial chain: :func:`reach_certificate` (the tip is never farther from the first
  joint's origin than the sum of the link offsets and strokes).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from scara_opt.ik.closed_form import range_of_sum
from scara_opt.ik.geometry import NotScaraError, ScaraGeometry, scara_geometry
from scara_opt.ik.planar_distance import ANGLE_SLACK, Domain, distance, link_ranges
from scara_opt.ik.result import Certificate, Reason
from scara_opt.ik.task import default_q0
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target


#: round-off allowed per unit of the lengths (or angles) a certificate adds up: 64 ulps
ROUND_OFF = 64.0 * float(np.finfo(float).eps)


def _reach(geom: ScaraGeometry, lo: float, hi: float) -> tuple[float, float]:
    """The shoulder-to-tip distances [m] the elbow's range [lo, hi] [rad] allows."""
    l1, l2 = geom.l1, geom.l2
    if hi - lo >= 2 * math.pi:
        cmin, cmax = -1.0, 1.0
    else:
        a, b = sorted(geom.phi2 - geom.phi1 + geom.s[geom.elbow] * np.array([lo, hi]))
        ends = (math.cos(a), math.cos(b))
        cmax = 1.0 if math.floor(b / (2 * math.pi)) >= math.ceil(a / (2 * math.pi)) \
            else max(ends)
        cmin = -1.0 if math.floor((b - math.pi) / (2 * math.pi)) >= math.ceil(
            (a - math.pi) / (2 * math.pi)) else min(ends)

    def r(c: float) -> float:
        return math.sqrt(max(l1 * l1 + l2 * l2 + 2 * l1 * l2 * c, 0.0))

    return r(cmin), r(cmax)


def _shoulder_distances(geom: ScaraGeometry, uv: Array, lo: Array,
                        hi: Array) -> tuple[float, float]:
    """Least and largest distance [m] from the target ``uv`` to the shoulder axis.

    Over the rails' ranges; the distance itself when there is no rail.
    """
    rails = geom.rails
    if not rails:
        r = float(np.linalg.norm(uv))
        return r, r
    D = geom.rail[rails]  # (k, 2)
    corners = np.array(np.meshgrid(*[(lo[k], hi[k]) for k in rails])).reshape(len(rails), -1)
    far = float(np.linalg.norm(uv[:, None] - D.T @ corners, axis=0).max())
    if len(rails) > 1:
        return 0.0, far  # the nearest point of a parallelogram: not needed for a bound
    d = D[0]
    t = float(np.clip((uv @ d) / (d @ d), lo[rails[0]], hi[rails[0]]))
    return float(np.linalg.norm(uv - t * d)), far


def scara_certificate(robot: Robot, target: Target, tol: float) -> Certificate | None:
    """A proof that no configuration within the limits reaches ``target`` within ``tol``.

    Three arguments, tried in order, each exact for a SCARA-type chain:

    1. **height**: the tip's height along the tool axis is the base height plus the
       strokes, whatever the other joints do; outside their range by more than ``tol``
       plus a round-off margin (:func:`_margin`: the FK the solvers are judged by can put
       the tip a few ulps beyond the exact range);
    2. **reach**: the shoulder-to-tip distance lies in an interval set by the elbow's
       range (the arm stretched, or folded as far as the elbow allows); the target's
       distance from the shoulder axis (over the rail's range) is outside it by more than
       ``tol`` plus the same margin: beyond reach, or inside the hole around the base;
    3. **joint limits**: the least distance in the plane from the target to every tip
       position the shoulder, elbow (and rail) limits allow, among the configurations
       whose tool angle is within ``tol`` of a yaw target's (the wrists' range taken
       whole), exceeds ``√(tol² − Δh²)``, ``Δh`` the least height error. Computed
       exactly by :mod:`scara_opt.ik.planar_distance` (its docstring gives the argument),
       less a round-off margin (:func:`_margin`). Then every configuration misses by more
       than ``tol``: in the plane and height together, or in the tool angle.

    Returns:
        The :class:`Certificate`, or ``None`` where no proof exists (the target is
        reachable, the robot is not SCARA-type, the target is a full rotation, or several
        rail joints).
    """
    try:
        geom = scara_geometry(robot)
    except NotScaraError:
        return None
    if target.kind == "rotation":
        return None
    lo, hi = robot.lower, robot.upper
    p = target.position
    heights = geom.heights
    hmin, hmax = range_of_sum(geom.sigma[heights], lo[heights], hi[heights]) if heights \
        else (0.0, 0.0)
    h = float(p @ geom.n) - geom.h0
    dz = max(hmin - h, h - hmax, 0.0)
    slack = _margin(geom, geom.plane(p) - geom.base,
                    abs(geom.h0) + abs(hmin) + abs(hmax) + float(np.abs(p).sum()))
    if dz - slack > tol:
        return Certificate(Reason.HEIGHT, dz, (
            f"the tip's height along the tool axis is {geom.h0:.6g} m plus the strokes, "
            f"[{geom.h0 + hmin:.6g}, {geom.h0 + hmax:.6g}] m whatever the other joints do; "
            f"the target's is {geom.h0 + h:.6g} m, {dz:.4g} m away"))
    rmin, rmax = _reach(geom, float(lo[geom.elbow]), float(hi[geom.elbow]))
    uv = geom.plane(p) - geom.base
    near, far = _shoulder_distances(geom, uv, lo, hi)
    rail = " (over the rail's range)" if geom.rails else ""
    slack = _margin(geom, uv, float(np.abs(geom.rail).sum()) * float(np.abs(
        np.concatenate([lo[geom.rails], hi[geom.rails]])).max(initial=0.0)))
    if near - rmax - slack > tol:
        return Certificate(Reason.BEYOND_REACH, near - rmax, (
            f"the tip is at most {rmax:.6g} m from the shoulder axis (links {geom.l1:.6g} + "
            f"{geom.l2:.6g} m, elbow range); the target is {near:.6g} m from it{rail}, "
            f"{near - rmax:.4g} m too far"))
    if rmin - far - slack > tol:
        return Certificate(Reason.INSIDE_HOLE, rmin - far, (
            f"the elbow's range keeps the tip at least {rmin:.6g} m from the shoulder axis; "
            f"the target is {far:.6g} m from it{rail}, {rmin - far:.4g} m inside that hole"))
    return _limits_certificate(robot, geom, target, tol, uv, dz)


def _margin(geom: ScaraGeometry, uv: Array, rail: float) -> float:
    """What round-off can take from a distance the planar model computes [m].

    64 ulps of the lengths involved, plus the planar model's own disagreement with the
    robot's FK (:attr:`~scara_opt.ik.geometry.ScaraGeometry.fk_error`, measured when the
    geometry was read).
    """
    scale = geom.l1 + geom.l2 + float(np.abs(uv).sum()) + rail
    return ROUND_OFF * scale + 4.0 * geom.fk_error


def yaw_domains(geom: ScaraGeometry, arm_lo: Array, arm_hi: Array, lo: Array, hi: Array,
                yaw: float | None, beta: float) -> list[Domain]:
    """The link angles the limits allow with the tool angle within ``beta`` [rad] of ``yaw``.

    One :class:`Domain` per turn of the band; the whole rectangle when the wrists' range,
    widened by ``beta``, covers a turn, or for ``yaw=None``.

    ``arm_lo``, ``arm_hi``: the shoulder's and elbow's ranges (one turn where continuous);
    ``lo``, ``hi``: the wrists' (``inf`` where continuous: any angle).
    """
    a_lo, a_hi, g_lo, g_hi = link_ranges(geom, arm_lo, arm_hi)
    wrists = geom.wrists
    w_lo, w_hi = range_of_sum(geom.s[wrists], lo[wrists], hi[wrists]) if wrists else (0, 0)
    if yaw is None or w_hi - w_lo + 2 * beta >= 2 * math.pi:
        return [Domain(a_lo, a_hi, g_lo, g_hi)]
    # yaw(q) = yaw0 + α + γ − φ2 + Σ s_k q_k (wrists): within beta of the target's when
    # α + γ lies in [c − w_hi − beta, c − w_lo + beta] modulo 2π
    c = yaw - geom.yaw0 + geom.phi2
    s_lo, s_hi = c - w_hi - beta - ANGLE_SLACK, c - w_lo + beta + ANGLE_SLACK
    k0 = math.ceil((a_lo + g_lo - s_hi) / (2 * math.pi))
    k1 = math.floor((a_hi + g_hi - s_lo) / (2 * math.pi))
    return [Domain(a_lo, a_hi, g_lo, g_hi, s_lo + 2 * math.pi * k, s_hi + 2 * math.pi * k)
            for k in range(k0, k1 + 1)]


def _limits_certificate(robot: Robot, geom: ScaraGeometry, target: Target, tol: float,
                        uv: Array, dz: float) -> Certificate | None:
    """Argument 3 of :func:`scara_certificate` (``dz``: the least height error [m])."""
    rails = geom.rails
    lo, hi = robot.lower, robot.upper
    if len(rails) > 1 or not np.isfinite(lo[rails]).all() or not np.isfinite(hi[rails]).all():
        return None  # several rails: a parallelogram of shoulder positions; or no end
    if rails:
        d = geom.rail[rails[0]]
        x0, x1 = uv - lo[rails[0]] * d, uv - hi[rails[0]] * d
        extent = float(np.abs(d).sum()) * float(hi[rails[0]] - lo[rails[0]])
    else:
        x0 = x1 = uv
        extent = 0.0
    margin = _margin(geom, uv, extent)
    dz_low = max(dz - margin, 0.0)

    arm_lo, arm_hi = robot.sampling_lower, robot.sampling_upper  # continuous: one turn

    def planar(beta: float) -> float:  # least planar distance with the angle within beta
        domains = yaw_domains(geom, arm_lo, arm_hi, lo, hi, target.yaw, beta)
        return distance(geom, domains, x0, x1) - margin

    dist = planar(tol)
    if math.hypot(max(dist, 0.0), dz_low) <= tol:
        return None
    bound = _residual_bound(planar, dz_low, tol) if target.yaw is not None \
        else math.hypot(dist, dz_low)
    names = [robot.joint_names[k] for k in (*rails, geom.shoulder, geom.elbow)]
    angle = (" with the tool angle within tol of the target's (the wrists' whole range)"
             if target.yaw is not None else "")
    return Certificate(Reason.NO_BRANCH, bound, (
        f"every configuration within the limits of {', '.join(names)}{angle} keeps the tip "
        f"at least {dist:.6g} m from the target in the plane (exact: the distance to the "
        f"arcs that bound what the limits reach), and {dz_low:.4g} m along the tool axis: "
        f"a residual of at least {math.hypot(dist, dz_low):.4g} > tol {tol:g}"))


def _residual_bound(planar: Callable[[float], float], dz: float, tol: float) -> float:
    """A lower bound [m, rad] on max(|Δp|, |Δangle|) over every configuration, > tol.

    For any β, a configuration either misses the angle by more than β or keeps the tip
    ``planar(β)`` from the target in the plane: the residual exceeds β wherever
    ``hypot(planar(β), dz) > β``. The largest such β is found to ~9 % by bisection in
    log(β) between tol (true: the certificate) and π.
    """
    def holds(beta: float) -> bool:
        return math.hypot(max(planar(beta), 0.0), dz) > beta

    at_pi = math.hypot(max(planar(math.pi), 0.0), dz)
    if at_pi > math.pi:  # holds(π)
        return at_pi
    lo, hi = math.log(tol), math.log(math.pi)
    for _ in range(8):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if holds(math.exp(mid)) else (lo, mid)
    return math.exp(lo)


def reach_bound(robot: Robot) -> tuple[Array, float]:
    """The first joint's origin (3,) [m] and the farthest the tip can be from it [m].

    Revolute joints turn about their own origin, so only the constant offsets between
    consecutive joint origins, the tip's offset and the prismatic strokes (their largest
    magnitude within the limits) add up: a triangle inequality, exact for any serial chain.
    ``inf`` when a prismatic joint has no finite limits. Cached on the robot.
    """
    cache = robot.__dict__.setdefault("_reach_bound", {})
    key = (robot.lower.tobytes(), robot.upper.tobytes())
    if key not in cache:
        lo, hi = robot.lower, robot.upper
        total = float(np.linalg.norm(robot.tip_placement[:3, 3]))
        for k, j in enumerate(robot.chain):
            if k > 0:
                total += float(np.linalg.norm(j.placement[:3, 3]))
            if j.kind == "prismatic":
                ends = j.scaling * np.array([lo[j.index], hi[j.index]]) + j.offset
                total += float(np.abs(ends).max())
        origin = robot.model.jointPlacements[1].translation.copy()
        cache[key] = (origin, total if math.isfinite(total) else math.inf)
    return cache[key]


def reach_certificate(robot: Robot, target: Target, tol: float) -> Certificate | None:
    """The target is farther from the first joint's origin than :func:`reach_bound` allows."""
    origin, reach = reach_bound(robot)
    dist = float(np.linalg.norm(target.position - origin))
    slack = ROUND_OFF * (dist + reach + float(np.abs(origin).sum()))  # the sums' round-off
    if dist - reach - slack <= tol:
        return None
    return Certificate(Reason.BEYOND_REACH, dist - reach, (
        f"the tip is never farther than {reach:.6g} m from the first joint's origin "
        f"({', '.join(f'{v:.4g}' for v in origin)}) m (the link offsets and strokes added up); "
        f"the target is {dist:.6g} m from it, {dist - reach:.4g} m too far"))


def tilt_certificate(robot: Robot, target: Target, tol: float) -> Certificate | None:
    """A full-rotation target that tilts the yaw axis of a robot whose tool cannot tilt.

    Where every revolute axis is parallel to the world axis ``n`` (:attr:`Robot.yaw_axis`,
    SCARA-type chains), every reachable orientation is ``R(q) = Rot(n, φ) R_ref`` for some
    angle φ (``R_ref`` the tool's orientation at any fixed configuration). The tool-frame
    vector ``u = R_refᵀ n`` is then always mapped to ``n``, so the rotation error angle of
    any ``q`` is at least the angle between ``n`` and ``R* u`` (a rotation by θ moves no unit
    vector by more than θ): a lower bound for every configuration, checked against ``tol``.
    """
    n, R_star = robot.yaw_axis, target.rotation
    if R_star is None or n is None:
        return None
    R_ref = robot.fk(default_q0(robot))[:3, :3]
    v = R_star @ (R_ref.T @ n)
    bound = math.atan2(float(np.linalg.norm(np.cross(n, v))), float(n @ v))
    if bound - ROUND_OFF * math.pi <= tol:  # the products' round-off [rad]
        return None
    return Certificate(Reason.TILT, bound, (
        f"every revolute axis is parallel to ({', '.join(f'{c:.4g}' for c in n)}): the tool "
        f"only turns about it, and the target's rotation tilts it by {bound:.6g} rad "
        f"({math.degrees(bound):.4g} deg), a lower bound on the rotation error of every "
        "configuration; give a rotation about that axis (or a yaw target)"))


def certify(robot: Robot, target: Target, tol: float) -> Certificate | None:
    """The first proof that ``target`` is out of reach within ``tol``, or ``None``.

    :func:`scara_certificate` where the closed form applies, :func:`tilt_certificate` for a
    full rotation on a chain whose tool cannot tilt, then :func:`reach_certificate`.
    """
    return (scara_certificate(robot, target, tol) or tilt_certificate(robot, target, tol)
            or reach_certificate(robot, target, tol))
