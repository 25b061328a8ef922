r"""Cartesian paths as lists of :class:`~scara_opt.Target`: circles, lines, cutting contours.

Every generator returns a list of targets (feed it to :func:`~scara_opt.trajectory.ik_path`);
:func:`to_array` gives the array form, one row ``[x, y, z]`` or ``[x, y, z, yaw]`` per point
[m, rad]. Tool angles follow the robot's convention (:meth:`~scara_opt.Robot.yaw`): the angle
about :attr:`~scara_opt.Robot.yaw_axis` from the plane axis ``e1`` toward ``e2`` of
:meth:`~scara_opt.Robot.yaw_basis`. A *tangent* tool angle is the direction of travel in that
plane, unwrapped along the path (a closed contour turns it by :math:`\pm 2π`).

Presets reproduce the papers' paths: :func:`zavar2024_circle` (zavar2024 Table 3) and
:func:`nguyen_contour` (a representative stand-in for nguyen's Fig. 6/7 cutting path).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import (
    check_flag,
    check_memory,
    check_real,
    count_text,
    describe,
    float_array,
    is_real,
    memory_guard,
)
from scara_opt.errors import InputError
from scara_opt.target import MAX_ANGLE, MAX_COORDINATE, Target

Array = NDArray[np.float64]

#: estimated memory of one path point [bytes]: the Target object, its arrays and the
#: generator's temporaries (measured: 250 to 320 B)
BYTES_PER_TARGET = 400

#: zavar2024 Table 3 [cm], as printed except point 7: printed (14, 7.75), a sign typo for
#: (14, −7.75) (the ten points go round the circle clockwise, 30° apart)
ZAVAR2024_TABLE3_CM = (
    (-14.0, 7.75), (-8.0, 13.85), (0.0, 16.0), (8.0, 13.85), (14.0, 7.75),
    (16.0, 0.0), (14.0, -7.75), (8.0, -13.85), (0.0, -16.0), (-8.0, -13.85),
)
#: height of zavar2024's circle [m] (Table 3: z = −6 cm)
ZAVAR2024_TABLE3_Z = -0.06
#: the reachable variant of the circle (ROBOTS.md): the same angles at r = 0.30 m, z = −0.07 m
ZAVAR2024_REACHABLE_RADIUS = 0.30
ZAVAR2024_REACHABLE_Z = -0.07


def _vector(value: ArrayLike, n: int, what: str) -> Array:
    try:
        arr = float_array(value, what)
    except InputError:
        raise InputError(f"{what} must be {n} numbers; got {describe(value)}") from None
    if arr.shape != (n,) or not np.isfinite(arr).all():
        raise InputError(f"{what} must be {n} finite numbers; got {describe(value)}")
    return arr


def _positive(value: object, what: str) -> float:
    """A length [m] > 0 and at most MAX_COORDINATE (beyond, the path's arithmetic overflows)."""
    return check_real(what, value, 0.0, MAX_COORDINATE, low_open=True)


def _count(n: object, least: int, call: str) -> int:
    """``n`` points, an integer >= ``least`` whose targets fit in memory (see BYTES_PER_TARGET)."""
    if (isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer))
            or n < least):
        raise InputError(f"n must be an integer >= {least}; got {describe(n)}")
    check_memory(f"{call}(n={count_text(int(n))})", int(n), BYTES_PER_TARGET, "lower n")
    return int(n)


def _distinct(P: Array, fix: str) -> None:
    """Refuse consecutive points that coincide: a path must move from point to point.

    Raises:
        InputError: names the first pair and ``fix``, what to change.
    """
    same = np.flatnonzero((np.diff(P, axis=0) == 0.0).all(axis=1))
    if same.size:
        i = int(same[0])
        raise InputError(f"points {i} and {i + 1} of the path coincide at {P[i].tolist()} m "
                         f"({same.size} such pair(s)): {fix}")


def _targets(P: Array, yaw: Array | None) -> list[Target]:
    if yaw is None:
        return [Target(p) for p in P]
    return [Target(p, yaw=float(a)) for p, a in zip(P, yaw, strict=True)]


def _yaws(yaw: object, n: int, tangent: Array | None) -> Array | None:
    """``None``, a constant (n,) yaw, or the tangent angles."""
    if yaw is None:
        return None
    if isinstance(yaw, str):
        if yaw != "tangent":
            raise InputError(f"yaw must be None, a number [rad] or 'tangent'; got {yaw!r}")
        return tangent
    if not is_real(yaw):
        raise InputError(f"yaw must be None, a number [rad] or 'tangent'; got {describe(yaw)}")
    value = check_real("yaw", yaw, unit="rad")
    return np.full(n, value)


def circle(center: ArrayLike, radius: float, z: float, n: int | None = None, *,
           angles: ArrayLike | None = None, start: float = 0.0, sweep: float = 2 * math.pi,
           yaw: float | str | None = None) -> list[Target]:
    """Points on a horizontal circle (normal +z, the SCARA tool axis).

    Args:
        center: (2,) centre ``(x, y)`` [m].
        radius: radius [m].
        z: height [m].
        n: number of points, evenly spaced from ``start`` over ``sweep``; a full turn
            (``|sweep| = 2π``) does not repeat the first point. Give ``n`` or ``angles``.
        angles: (n,) polar angles of the points [rad], instead of ``n``.
        start: polar angle of the first point [rad].
        sweep: signed angle covered [rad] (negative: clockwise).
        yaw: ``None`` (position only), a constant tool angle [rad], or ``"tangent"``
            (direction of travel, for a robot whose yaw basis is world (x, y)).

    Raises:
        InputError: bad centre, radius (zero included), count or angles; both or neither of
            ``n``/``angles``; points that coincide (equal angles, or a sweep too small for
            ``n`` points); more points than :data:`scara_opt.checks.MAX_BYTES` allow.
    """
    c = _vector(center, 2, "center (x, y) [m]")
    r = _positive(radius, "radius [m]")
    zz = check_real("z", z, unit="m")
    if (n is None) == (angles is None):
        raise InputError("give either n= (evenly spaced points) or angles= [rad], not both")
    if angles is not None:
        try:
            th = float_array(angles, "angles")
        except InputError:
            th = np.array(np.nan)
        if (th.ndim != 1 or th.size < 1 or not np.isfinite(th).all()
                or np.abs(th).max() > MAX_ANGLE):
            raise InputError(f"angles must be a 1-D array of finite angles within "
                             f"±{MAX_ANGLE:g} [rad]; got {describe(angles)}")
    else:
        count = _count(n, 1, "circle")
        a0 = check_real("start", start, -MAX_ANGLE, MAX_ANGLE, unit="rad")
        span = check_real("sweep", sweep, -MAX_ANGLE, MAX_ANGLE, unit="rad")
        if span == 0:
            raise InputError("sweep must not be 0: give the signed angle covered [rad], e.g. "
                             "2 * math.pi for a full turn")
        full = math.isclose(abs(span), 2 * math.pi)
        steps = count if full else max(count - 1, 1)
        with memory_guard(f"circle(n={count:,})", count * BYTES_PER_TARGET, "lower n"):
            th = a0 + span * np.arange(count) / steps
    P = np.column_stack([c[0] + r * np.cos(th), c[1] + r * np.sin(th), np.full(th.size, zz)])
    _distinct(P, "give distinct angles=, or a larger sweep= (or radius=) for this many points")
    direction = np.sign(np.diff(th)).mean() if th.size > 1 else np.sign(sweep)
    tangent = th + math.copysign(math.pi / 2, direction if direction else 1.0)
    return _targets(P, _yaws(yaw, th.size, tangent))


def line(start: ArrayLike, end: ArrayLike, n: int, yaw: float | str | None = None) -> list[Target]:
    """``n`` evenly spaced points from ``start`` to ``end`` (both included).

    Args:
        start: (3,) first position [m].
        end: (3,) last position [m].
        n: number of points, >= 2.
        yaw: ``None``, a constant tool angle [rad], or ``"tangent"`` (direction of travel
            in the world x-y plane).

    Raises:
        InputError: bad positions or ``n``; ``start == end`` (no line), or ends so close that
            points coincide; a vertical line with ``yaw="tangent"``; more points than
            :data:`scara_opt.checks.MAX_BYTES` allow.
    """
    a, b = _vector(start, 3, "start [m]"), _vector(end, 3, "end [m]")
    count = _count(n, 2, "line")
    if np.array_equal(a, b):
        raise InputError(f"start and end are the same point {a.tolist()} m: a line needs two "
                         "distinct ends (for a single target, use [Target(start)])")
    with memory_guard(f"line(n={count:,})", count * BYTES_PER_TARGET, "lower n"):
        P = a + np.linspace(0.0, 1.0, count)[:, None] * (b - a)
    _distinct(P, "the ends are too close for this many points; lower n")
    d = b - a
    if yaw == "tangent" and math.hypot(d[0], d[1]) == 0.0:
        raise InputError("a vertical or zero-length line has no tangent direction; give yaw=")
    return _targets(P, _yaws(yaw, count, np.full(count, math.atan2(d[1], d[0]))))


def point_to_point(start: ArrayLike, end: ArrayLike, yaw_start: float | None = None,
                   yaw_end: float | None = None) -> list[Target]:
    """The two targets of a point-to-point move (joint interpolation in between).

    Args:
        start: (3,) start position [m].
        end: (3,) goal position [m].
        yaw_start: tool angle at the start [rad], or ``None`` (position-only move).
        yaw_end: tool angle at the goal [rad], or ``None`` (with ``yaw_start``).

    Raises:
        InputError: bad positions, only one of the two yaws, or no move (same position and
            same tool angle at both ends).
    """
    a, b = _vector(start, 3, "start [m]"), _vector(end, 3, "end [m]")
    if (yaw_start is None) != (yaw_end is None):
        raise InputError("give both yaw_start and yaw_end [rad], or neither")
    same_yaw = yaw_start is None or (is_real(yaw_start) and is_real(yaw_end)
                                     and yaw_start == yaw_end)
    if np.array_equal(a, b) and same_yaw:
        raise InputError(f"start and end are the same pose ({a.tolist()} m"
                         + ("" if yaw_start is None else f", yaw {yaw_start!r} rad")
                         + "): there is no move; give a different end (or another yaw)")
    if yaw_start is None:
        return [Target(a), Target(b)]
    return [Target(a, yaw=yaw_start), Target(b, yaw=yaw_end)]


def _rounded_rectangle_uv(s: Array, width: float, height: float,
                          rc: float) -> tuple[Array, Array, Array]:
    """Plane points (u, v) and unwrapped tangent angles at arc lengths ``s`` [m].

    Counter-clockwise from the middle of the bottom side, heading +u; centred on (0, 0).
    """
    sx, sy = width / 2 - rc, height / 2 - rc
    u, v, ang = np.zeros_like(s), np.zeros_like(s), np.zeros_like(s)
    p = np.array([0.0, -height / 2])
    s0 = 0.0
    centres = [(sx, -sy), (sx, sy), (-sx, sy), (-sx, -sy), (sx, -sy)]
    for j, centre in enumerate(centres):
        heading = j * math.pi / 2
        direction = np.array([math.cos(heading), math.sin(heading)])
        if j < 4:
            arc_start = np.asarray(centre) + rc * np.array([math.sin(heading),
                                                             -math.cos(heading)])
            straight = float(np.linalg.norm(arc_start - p))
        else:  # back along the bottom to the start
            straight = sx
        m = (s >= s0) & (s <= s0 + straight)
        u[m], v[m] = (p + np.outer(s[m] - s0, direction)).T
        ang[m] = heading
        s0 += straight
        if j == 4:
            break
        phi = np.clip((s - s0) / rc, 0.0, math.pi / 2)
        m = (s > s0) & (s <= s0 + rc * math.pi / 2)
        u[m] = centre[0] + rc * np.sin(heading + phi[m])
        v[m] = centre[1] - rc * np.cos(heading + phi[m])
        ang[m] = heading + phi[m]
        s0 += rc * math.pi / 2
        p = np.asarray(centre) + rc * np.array([math.cos(heading), math.sin(heading)])
    return u, v, ang


def rounded_rectangle(n: int, center: ArrayLike, width: float, height: float,
                      corner_radius: float, *, origin: ArrayLike = (0.0, 0.0, 0.0),
                      e1: ArrayLike = (1.0, 0.0, 0.0), e2: ArrayLike = (0.0, 1.0, 0.0),
                      clockwise: bool = False, closed: bool = True,
                      yaw: str | float | None = "tangent") -> list[Target]:
    """A closed rounded rectangle, points evenly spaced by arc length, tool tangent to it.

    The contour lies in the plane ``origin + u e1 + v e2``; ``(u, v)`` are plane coordinates.
    It is C¹ (straight sides joined by quarter circles), so the tangent angle is continuous.
    The first point is the middle of the bottom side (top side when ``clockwise``),
    travelling toward +e1.

    Args:
        n: number of distinct points, >= 4.
        center: (2,) centre ``(u, v)`` in the plane [m].
        width: outer size along ``e1`` [m].
        height: outer size along ``e2`` [m].
        corner_radius: radius of the corners [m], ``0 < r <= min(width, height) / 2``.
        origin: (3,) world point of plane coordinate (0, 0) [m].
        e1: (3,) first world axis of the plane; for a tangent tool angle ``(e1, e2)`` must
            be the robot's :meth:`~scara_opt.Robot.yaw_basis`.
        e2: (3,) second world axis, orthonormal to ``e1``.
        clockwise: travel direction (counter-clockwise, from e1 toward e2, by default).
        closed: append the first point again at the end, its tangent angle unwrapped
            (turned by ±2π), so the path ends where it started.
        yaw: ``"tangent"`` (default), a constant tool angle [rad], or ``None``.

    Raises:
        InputError: bad sizes, axes, counts or flags; more points than
            :data:`scara_opt.checks.MAX_BYTES` allow, or so many that they coincide.
    """
    count = _count(n, 4, "rounded_rectangle")
    check_flag("clockwise", clockwise)
    check_flag("closed", closed)
    c = _vector(center, 2, "center (u, v) [m]")
    w, h = _positive(width, "width [m]"), _positive(height, "height [m]")
    rc = _positive(corner_radius, "corner_radius [m]")
    if rc > min(w, h) / 2:
        raise InputError(f"corner_radius {rc} m exceeds half the smaller side "
                         f"({min(w, h) / 2} m); make it smaller")
    o, a1, a2 = _vector(origin, 3, "origin [m]"), _vector(e1, 3, "e1"), _vector(e2, 3, "e2")
    if abs(a1 @ a1 - 1) > 1e-9 or abs(a2 @ a2 - 1) > 1e-9 or abs(a1 @ a2) > 1e-9:
        raise InputError("e1 and e2 must be orthonormal (unit length, perpendicular)")
    total = 2 * (w - 2 * rc) + 2 * (h - 2 * rc) + 2 * math.pi * rc
    with memory_guard(f"rounded_rectangle(n={count:,})", count * BYTES_PER_TARGET, "lower n"):
        s = total * np.arange(count + int(bool(closed))) / count
        u, v, ang = _rounded_rectangle_uv(s, w, h, rc)
        if clockwise:  # mirror about the u axis: same rectangle, travelled the other way
            v, ang = -v, -ang
        uv = np.column_stack([u, v]) + c
        P = o + uv[:, :1] * a1 + uv[:, 1:] * a2
    _distinct(P, "the contour is too small for this many points; lower n")
    return _targets(P, _yaws(yaw, len(P), ang))


def zavar2024_circle(reachable: bool = False) -> list[Target]:
    """The ten points of zavar2024's circular path (Table 3), position-only, in SI.

    The table (cm): radius 16 cm at z = −6 cm, from (−14, 7.75) clockwise in 30° steps to
    (−8, −13.85); point 7 is printed (14, 7.75), a sign typo fixed here to (14, −7.75).
    The text says 11 points, the table lists 10: these are the 10.

    That circle is out of zavar2024's reach (|θ2| <= 120° keeps the tip at least 0.2 m from
    the base axis; every point has r = 0.16 m). ``reachable=True`` gives the variant of
    ROBOTS.md instead: the same ten polar angles at r = 0.30 m, z = −0.07 m.

    Args:
        reachable: the reachable variant instead of the paper's points.

    Raises:
        InputError: ``reachable`` not True or False.
    """
    check_flag("reachable", reachable)
    xy = np.array(ZAVAR2024_TABLE3_CM) / 100.0
    if not reachable:
        return [Target((x, y, ZAVAR2024_TABLE3_Z)) for x, y in xy]
    return circle((0.0, 0.0), ZAVAR2024_REACHABLE_RADIUS, ZAVAR2024_REACHABLE_Z,
                  angles=np.arctan2(xy[:, 1], xy[:, 0]))


def nguyen_contour(n: int = 120, y: float = -0.13) -> list[Target]:
    """A representative closed cutting contour for ``nguyen``, tool angle tangent to it.

    nguyen's paper shows its cutting path only as a figure (Figs. 6, 7, 9: a nearly closed
    contour on the workpiece, the tool tangent to it) without coordinates; this is a
    stand-in, not the paper's data: a rounded rectangle 0.20 m (x) × 0.30 m (z) with
    0.04 m corners, centred at x = 0.40 m, z = 0.30 m, in the arm's plane y = ``y``,
    travelled counter-clockwise (from +x toward +z) once and closed. It lies inside
    nguyen's reachable workspace under the joint limits assumed in ``robots/nguyen.toml``
    (rail 0–0.6 m, |θ2|, |θ3| <= 150°, d4 0–0.1 m, so y in [−0.18, −0.08] m).

    The tool angle is nguyen's A = θ2 + θ3 + θ5 (eq. 7): the direction of travel in the
    x-z plane, measured from +x toward +z, i.e. the robot's yaw about its yaw axis −y.

    Args:
        n: number of distinct points (one more is appended to close the contour).
        y: plane of the arm [m], within [−0.18, −0.08].

    Raises:
        InputError: ``n`` or ``y`` malformed (see :func:`rounded_rectangle`).
    """
    y = check_real("y", y, unit="m")
    _count(n, 4, "nguyen_contour")
    return rounded_rectangle(n, (0.40, 0.30), 0.20, 0.30, 0.04, origin=(0.0, y, 0.0),
                             e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0))


def as_targets(targets: Target | Sequence[Target] | ArrayLike) -> list[Target]:
    """A list of :class:`Target` from targets, or an (n, 3) / (n, 4) array ``[x, y, z(, yaw)]``.

    Raises:
        InputError: an empty sequence, or an array of another shape or with NaN.
    """
    if isinstance(targets, Target):
        return [targets]
    if isinstance(targets, Sequence) and targets and all(isinstance(t, Target) for t in targets):
        return list(targets)
    try:
        arr = float_array(targets, "targets")
    except InputError:
        raise InputError("targets must be a sequence of Target or an (n, 3) / (n, 4) array "
                         f"[x, y, z(, yaw)] [m, rad]; got {describe(targets)}") from None
    if arr.ndim != 2 or arr.shape[0] < 1 or arr.shape[1] not in (3, 4):
        raise InputError(f"a target array must have shape (n, 3) or (n, 4) [x, y, z(, yaw)] "
                         f"with n >= 1; got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise InputError("the target array has NaN or inf entries; pass finite values")
    return _targets(arr[:, :3], arr[:, 3] if arr.shape[1] == 4 else None)


def to_array(targets: Sequence[Target]) -> Array:
    """The array form of targets: (n, 3) ``[x, y, z]``, or (n, 4) with yaw when all have one.

    Raises:
        InputError: some targets have a yaw and others not, or a target has a rotation.
    """
    ts = as_targets(targets)
    kinds = {t.kind for t in ts}
    if "rotation" in kinds or kinds == {"position", "yaw"}:
        raise InputError(f"to_array needs all targets position-only or all with a yaw; got "
                         f"kinds {sorted(kinds)}")
    P = np.array([t.position for t in ts])
    if kinds == {"yaw"}:
        return np.column_stack([P, [t.yaw for t in ts]])
    return P
