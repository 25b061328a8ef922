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

import numpy as np

from scara_opt.ik.closed_form import Box, make_task, range_of_sum, search_solutions
from scara_opt.ik.geometry import NotScaraError, ScaraGeometry, scara_geometry
from scara_opt.ik.result import Certificate, Reason
from scara_opt.ik.task import default_q0
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target


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
       strokes, whatever the other joints do; outside their range by more than ``tol``;
    2. **reach**: the shoulder-to-tip distance lies in an interval set by the elbow's
       range (the arm stretched, or folded as far as the elbow allows); the target's
       distance from the shoulder axis (over the rail's range) is outside it by more than
       ``tol``: beyond reach, or inside the hole around the base;
    3. **no branch**: the closed form over the whole range of every redundant joint, with
       every joint limit widened so that a target within ``tol`` of a reachable one would
       be found (by ``2 tol / min(l1, l2, 1 m)`` rad and ``2 tol`` m), finds no branch.

    Returns:
        The :class:`Certificate`, or ``None`` where no proof exists (the target is
        reachable, the robot is not SCARA-type, the target is a full rotation, or a
        search would be incomplete: several rail joints).
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
    if dz > tol:
        return Certificate(Reason.HEIGHT, dz, (
            f"the tip's height along the tool axis is {geom.h0:.6g} m plus the strokes, "
            f"[{geom.h0 + hmin:.6g}, {geom.h0 + hmax:.6g}] m whatever the other joints do; "
            f"the target's is {geom.h0 + h:.6g} m, {dz:.4g} m away"))
    rmin, rmax = _reach(geom, float(lo[geom.elbow]), float(hi[geom.elbow]))
    near, far = _shoulder_distances(geom, geom.plane(p) - geom.base, lo, hi)
    rail = " (over the rail's range)" if geom.rails else ""
    if near - rmax > tol:
        return Certificate(Reason.BEYOND_REACH, near - rmax, (
            f"the tip is at most {rmax:.6g} m from the shoulder axis (links {geom.l1:.6g} + "
            f"{geom.l2:.6g} m, elbow range); the target is {near:.6g} m from it{rail}, "
            f"{near - rmax:.4g} m too far"))
    if rmin - far > tol:
        return Certificate(Reason.INSIDE_HOLE, rmin - far, (
            f"the elbow's range keeps the tip at least {rmin:.6g} m from the shoulder axis; "
            f"the target is {far:.6g} m from it{rail}, {rmin - far:.4g} m inside that hole"))
    box = Box.of(robot, geom, tol)
    movable = np.zeros(robot.nq, dtype=bool)
    movable[list(geom.redundant)] = True
    sols = search_solutions(make_task(robot, geom, target, default_q0(robot), movable, box))
    if sols is None or sols:
        return None
    names = [robot.joint_names[k] for k in geom.redundant]
    over = f" over the whole range of {', '.join(names)}" if names else ""
    return Certificate(Reason.NO_BRANCH, 0.0, (
        f"the closed form{over} finds no branch within the joint limits, even with them "
        f"widened by {box.upper[geom.elbow] - robot.sampling_upper[geom.elbow]:.2g} rad for "
        f"tol {tol:g}: the shoulder, elbow or wrist limits exclude the target"))




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
    if dist - reach <= tol:
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
    n = robot.yaw_axis
    if target.kind != "rotation" or n is None:
        return None
    R_ref = robot.fk(default_q0(robot))[:3, :3]
    v = target.rotation @ (R_ref.T @ n)
    bound = math.atan2(float(np.linalg.norm(np.cross(n, v))), float(n @ v))
    if bound <= tol:
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
