r"""Closed-form IK of SCARA-type chains: every branch, over the whole range of redundant joints.

The geometry comes from :mod:`scara_opt.ik.geometry`.

With ``α₁ = φ₁ + s₁θ₁`` and ``γ = α₂ − α₁`` the in-plane link angles,

.. math:: \cos γ = \frac{r^2 - l_1^2 - l_2^2}{2 l_1 l_2}, \qquad
          α_1 = \operatorname{atan2}(v, u) - \operatorname{atan2}(l_2 \sin γ, l_1 + l_2 \cos γ)

for both signs of ``γ`` (elbow branches); each angle is then taken modulo 2π wherever it
fits within the joint limits (wrists such as peng2025's ±360° give two turns).

**Redundant joints** (a rail, every height joint but the last, every wrist but the last)
are solved over their whole range, in three independent groups:

* *heights*: the tip height is ``h₀ + Σ σ_k q_k`` over the height joints, whatever the
  others do; the reachable heights form one interval;
* *wrists*: the tool angle takes ``Σ s_k q_k`` over the wrists, whatever else; one
  interval of sums, taken modulo 2π;
* *rail*: the shoulder slides along a line; the rail values at which a branch exists
  form intervals whose ends lie where the shoulder, elbow or wrist meets a limit, or the
  arm stretches or folds: all such places are circles in the plane, so the ends are the
  roots of quadratics (:func:`rail_intervals`), and one closed-form test inside each
  piece decides it.

A redundant joint keeps its *held* value (``fixed`` by name, else ``q0``'s) when some branch
exists there; otherwise the nearest values that work are taken (a minimal move, see
:func:`_distribute`). Joints named in ``fixed`` are never moved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import overload

import numpy as np
from numpy.typing import NDArray

from scara_opt.ik.geometry import (
    COS_SLACK,
    HEIGHT_SLACK,
    NotScaraError,
    ScaraGeometry,
    held_values,
    scara_geometry,
)
from scara_opt.ik.task import LIMIT_SLACK, default_q0
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

Bools = NDArray[np.bool_]

# ---------------------------------------------------------------------- the search box
@dataclass(frozen=True)
class Box:
    """Joint ranges the closed form searches: the limits, with round-off slacks.

    Attributes:
        lower, upper: (nq,) finite ranges [rad or m] (continuous joints: one turn, ±π).
        slack: a joint value this far outside [lower, upper] is round-off, accepted and
            clipped [rad or m]; values the search sets itself stay within the range.
        cos_slack: how far |cos γ| may exceed 1 (round-off).
        height_slack: a height mismatch accepted when no joint moves the tip along n [m].
        angle_slack: a tool-angle mismatch accepted when no wrist turns the tool [rad].
    """

    lower: Array
    upper: Array
    slack: float = LIMIT_SLACK
    cos_slack: float = COS_SLACK
    height_slack: float = HEIGHT_SLACK
    angle_slack: float = COS_SLACK

    @classmethod
    def of(cls, robot: Robot) -> Box:
        """The robot's box: its limits (one turn for continuous joints), round-off slacks."""
        return cls(robot.sampling_lower, robot.sampling_upper)

    @overload
    def outer(self, k: int) -> tuple[float, float]: ...
    @overload
    def outer(self, k: list[int]) -> tuple[Array, Array]: ...

    def outer(self, k: int | list[int]) -> tuple[float, float] | tuple[Array, Array]:
        """The range of joints ``k`` with the round-off slack: what a solution may touch."""
        return self.lower[k] - self.slack, self.upper[k] + self.slack


def turns(values: Array | float, lo: float, hi: float) -> list[float]:
    """Every ``v + 2πk`` within [lo, hi]."""
    out: list[float] = []
    for v in np.atleast_1d(values):
        k0 = math.ceil((lo - v) / (2 * math.pi))
        k1 = math.floor((hi - v) / (2 * math.pi))
        out.extend(float(v + 2 * math.pi * k) for k in range(k0, k1 + 1))
    return out


def _distribute(total: float, signs: Array, held: Array, lo: Array, hi: Array,
                movable: Bools) -> Array | None:
    r"""Values ``x`` within [lo, hi] with ``signs @ x == total``, nearest to ``held``.

    Only the ``movable`` entries change; the nearest point in the Euclidean sense is
    :math:`x_k = \operatorname{clip}(h_k + λ s_k)` for the one λ that meets the total (a
    monotone piecewise-linear equation in λ, solved at its breakpoints). ``None`` when no
    such ``x`` exists.
    """
    x = held.copy()
    rest = total - float(signs[~movable] @ held[~movable])
    s, h, lo_m, hi_m = signs[movable], held[movable], lo[movable], hi[movable]
    if s.size == 0:
        return x if abs(rest) <= LIMIT_SLACK else None
    ends = np.concatenate([(lo_m - h) / s, (hi_m - h) / s])
    lam = np.unique(np.concatenate([ends, [0.0]]))
    g = np.array([float(s @ np.clip(h + v * s, lo_m, hi_m)) for v in lam])
    if not g[0] - LIMIT_SLACK <= rest <= g[-1] + LIMIT_SLACK:
        return None
    keep = np.concatenate([[True], np.diff(g) > 0])  # g is non-decreasing: drop flat parts
    v = float(np.interp(rest, g[keep], lam[keep]))
    x[movable] = np.clip(h + v * s, lo_m, hi_m)
    return x


def _group(candidates: list[float], signs: Array, held: Array, lo: Array, hi: Array,
           movable: Bools, slack: float = LIMIT_SLACK) -> list[Array]:
    """Values of a group of additive joints (heights or wrists) meeting one of ``candidates``.

    The last joint of the group is solved; the others keep ``held`` when that works for
    some candidate (all such solutions are returned; ``slack`` is round-off), else the
    nearest values that work (moving only ``movable`` joints, within [lo, hi]) for each
    candidate are returned, nearest first.
    """
    last = len(signs) - 1
    found: list[Array] = []
    for total in candidates:
        v = (total - float(signs[:last] @ held[:last])) / signs[last]
        if lo[last] - slack <= v <= hi[last] + slack:
            x = held.copy()
            x[last] = v
            found.append(x)
    if found or not movable[:last].any():
        return found
    movable = movable.copy()
    movable[last] = True  # the solved joint moves freely, so the held ones move least
    moved = [m for total in candidates
             if (m := _distribute(total, signs, _solved_at_limit(total, signs, held, lo, hi),
                                  lo, hi, movable)) is not None]
    return sorted(moved, key=lambda m: float(np.sum((m[:last] - held[:last]) ** 2)))


def _solved_at_limit(total: float, signs: Array, held: Array, lo: Array, hi: Array) -> Array:
    """``held`` with the group's last joint at the value that leaves the least to move."""
    x = held.copy()
    last = len(signs) - 1
    x[last] = np.clip((total - float(signs[:last] @ held[:last])) / signs[last], lo[last],
                      hi[last])
    return x


def range_of_sum(signs: Array, lo: Array, hi: Array) -> tuple[float, float]:
    """The interval of ``signs @ x`` over the box [lo, hi]."""
    a, b = signs * lo, signs * hi
    return float(np.minimum(a, b).sum()), float(np.maximum(a, b).sum())


# ---------------------------------------------------------------------- one rail value
def link_angles(geom: ScaraGeometry, uv: Array, c: float) -> list[tuple[float, float]]:
    """(α, γ) [rad] of the elbow branches placing the tip at ``uv`` (2,).

    ``uv`` [m] relative to the shoulder axis; ``c`` = cos γ, |c| <= 1. Two branches, one
    where the arm is stretched or folded.
    """
    g = math.acos(c)
    return [(math.atan2(uv[1], uv[0]) - math.atan2(geom.l2 * math.sin(gamma),
                                                   geom.l1 + geom.l2 * math.cos(gamma)), gamma)
            for gamma in {g, -g}]


def _planar(geom: ScaraGeometry, uv: Array, box: Box) -> list[tuple[float, float]]:
    """(shoulder, elbow) values [rad] placing the tip at ``uv``: every branch and turn.

    ``uv`` is relative to the shoulder axis, in plane coordinates [m].
    """
    sh, el = geom.shoulder, geom.elbow
    c = (float(uv @ uv) - geom.l1**2 - geom.l2**2) / (2 * geom.l1 * geom.l2)
    if abs(c) > 1 + box.cos_slack:
        return []
    out = []
    for a1, gamma in link_angles(geom, uv, max(-1.0, min(1.0, c))):
        t1 = geom.s[sh] * (a1 - geom.phi1)
        t2 = geom.s[el] * (gamma - (geom.phi2 - geom.phi1))
        out += [(v1, v2) for v1 in turns(t1, *box.outer(sh))
                for v2 in turns(t2, *box.outer(el))]
    return out


@dataclass
class _Task:
    """One target in the geometry's terms, with what is held and what may move."""

    geom: ScaraGeometry
    box: Box
    uv: Array            # target in plane coordinates, relative to the shoulder base at q = 0
    height: float        # target height above h0 along n [m]
    yaw: float | None    # target tool angle [rad]
    held: Array          # (nq,) held values of every joint
    movable: Bools       # (nq,): redundant joints that may leave their held value

    def wrist_candidates(self, q: Array) -> tuple[list[int], list[float]]:
        """The wrists and the sums ``Σ s_k q_k`` over them that give the target's yaw at ``q``."""
        geom, wrists = self.geom, self.geom.wrists
        if self.yaw is None:
            return wrists, []
        arm = geom.s[geom.shoulder] * q[geom.shoulder] + geom.s[geom.elbow] * q[geom.elbow]
        need = self.yaw - geom.yaw0 - arm
        if not wrists:
            ok = abs(math.remainder(need, 2 * math.pi)) <= self.box.angle_slack
            return wrists, [0.0] if ok else []
        lo, hi = range_of_sum(geom.s[wrists], *self.box.outer(wrists))
        return wrists, turns(need, lo, hi)

    def complete(self, q: Array) -> list[Array]:
        """Every solution from ``q`` (rail, shoulder, elbow set): heights and wrists."""
        geom, box = self.geom, self.box
        heights = geom.heights
        if heights:
            groups = _group([self.height], geom.sigma[heights], self.held[heights],
                            box.lower[heights], box.upper[heights], self.movable[heights],
                            box.slack)
        elif abs(self.height) <= box.height_slack:
            groups = [np.zeros(0)]
        else:
            groups = []
        out = []
        for hv in groups:
            qh = q.copy()
            qh[heights] = hv
            if self.yaw is None:
                out.append(qh)
                continue
            wrists, totals = self.wrist_candidates(qh)
            if not wrists:
                out += [qh] if totals else []
                continue
            for wv in _group(totals, geom.s[wrists], self.held[wrists], box.lower[wrists],
                             box.upper[wrists], self.movable[wrists], box.slack):
                qw = qh.copy()
                qw[wrists] = wv
                out.append(qw)
        return out

    def at_rail(self, t: Array) -> list[Array]:
        """Every solution with the rail joints at ``t`` (values of :attr:`ScaraGeometry.rails`)."""
        geom = self.geom
        rails = geom.rails
        q = self.held.copy()
        q[rails] = t
        out = []
        for v1, v2 in _planar(geom, self.uv - t @ geom.rail[rails], self.box):
            qa = q.copy()
            qa[geom.shoulder], qa[geom.elbow] = v1, v2
            out += self.complete(qa)
        return out


def make_task(robot: Robot, geom: ScaraGeometry, target: Target, held: Array, movable: Bools,
          box: Box) -> _Task:
    """The :class:`_Task` of ``target``: held values, movable redundant joints, the box."""
    p = target.position
    return _Task(geom, box, geom.plane(p) - geom.base, float(p @ geom.n) - geom.h0,
                 target.yaw, held, movable)


# ---------------------------------------------------------------------- the rail
def _circles(task: _Task) -> list[tuple[Array, float]]:
    """Circles (centre (2,), radius [m]) holding every place where the reachable set changes.

    Stretched and folded arm, shoulder, elbow and wrist limits, in plane coordinates
    relative to the shoulder axis at q = 0.
    """
    geom, box = task.geom, task.box
    l1, l2 = geom.l1, geom.l2
    zero = np.zeros(2)
    out = [(zero, l1 + l2), (zero, abs(l1 - l2))]
    sh, el = geom.shoulder, geom.elbow
    for v in (box.lower[el], box.upper[el]):
        gamma = geom.phi2 - geom.phi1 + geom.s[el] * v
        out.append((zero, math.sqrt(max(l1**2 + l2**2 + 2 * l1 * l2 * math.cos(gamma), 0.0))))
    for v in (box.lower[sh], box.upper[sh]):
        a1 = geom.phi1 + geom.s[sh] * v
        out.append((l1 * np.array([math.cos(a1), math.sin(a1)]), l2))
    if task.yaw is not None:
        wrists = geom.wrists
        ends = [0.0] if not wrists else range_of_sum(geom.s[wrists], box.lower[wrists],
                                                      box.upper[wrists])
        for w in ends:  # link 2 at the angle that puts the wrists' sum at its end
            a2 = geom.phi2 + task.yaw - geom.yaw0 - w
            out.append((l2 * np.array([math.cos(a2), math.sin(a2)]), l1))
    return out


def rail_intervals(task: _Task) -> list[tuple[float, float]]:
    """Closed intervals of the one movable rail's value [m] at which some branch exists.

    The ends lie on the roots of ``|uv - t d - c| = R`` over :func:`_circles`; between two
    consecutive roots the answer does not change, so one closed-form test at the middle
    decides each piece (and one at each root decides isolated points).
    """
    geom, box = task.geom, task.box
    k = [r for r in geom.rails if task.movable[r]][0]
    d = geom.rail[k]
    others = [r for r in geom.rails if r != k]
    uv = task.uv - task.held[others] @ geom.rail[others]
    lo, hi = float(box.lower[k]), float(box.upper[k])
    roots = [lo, hi]
    a = float(d @ d)
    for c, radius in _circles(task):
        w = uv - c
        b, cc = float(w @ d), float(w @ w) - radius**2
        disc = b * b - a * cc
        if disc >= 0:
            roots += [(b - math.sqrt(disc)) / a, (b + math.sqrt(disc)) / a]
    ts = np.unique([t for t in roots if lo <= t <= hi])
    t_all = task.held[geom.rails].copy()
    idx = geom.rails.index(k)

    def works(t: float) -> bool:
        t_all[idx] = t
        return bool(task.at_rail(t_all))

    pieces: list[tuple[float, float]] = []
    for i, t in enumerate(ts):
        if works(t):
            pieces.append((t, t))
        if i + 1 < len(ts) and works(0.5 * (t + ts[i + 1])):
            pieces.append((t, float(ts[i + 1])))
    merged: list[tuple[float, float]] = []
    for a0, b0 in pieces:
        if merged and a0 <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], b0))
        else:
            merged.append((a0, b0))
    return merged


def _nearest_in(intervals: list[tuple[float, float]], t: float) -> float | None:
    """The point of the union of closed ``intervals`` nearest to ``t``."""
    best = None
    for a, b in intervals:
        v = min(max(t, a), b)
        if best is None or abs(v - t) < abs(best - t):
            best = v
    return best


def search_solutions(task: _Task) -> list[Array] | None:
    """Every solution, the rail at its held value or the nearest that works.

    ``None`` when the search would not be complete (more than one movable rail joint).
    """
    geom = task.geom
    rails = geom.rails
    t_held = task.held[rails]
    found = task.at_rail(t_held)
    movable_rails = [r for r in rails if task.movable[r]]
    if found or not movable_rails:
        return found
    if len(movable_rails) > 1:
        return None
    k = movable_rails[0]
    idx = rails.index(k)
    intervals = rail_intervals(task)
    t = _nearest_in(intervals, float(t_held[idx]))
    if t is None:
        return []
    mid = next(0.5 * (a + b) for a, b in intervals if a <= t <= b)
    for frac in (0.0, 1e-9, 1e-6, 1e-3, 0.5):  # an end found by a root may need a nudge
        t_all = t_held.copy()
        t_all[idx] = t + frac * (mid - t)
        found = task.at_rail(t_all)
        if found:
            return found
    return []


# ---------------------------------------------------------------------- public entry points
def _check_kind(target: Target) -> None:
    if target.kind == "rotation":
        raise NotScaraError("the closed form takes position and yaw targets; for a full "
                            "rotation use method='ipopt'")


def solve_all(robot: Robot, target: Target, q_ref: Array,
              fixed: dict[str, float] | None = None) -> list[Array]:
    """Every closed-form solution (nq,) within the joint limits.

    Redundant joints named in ``fixed`` keep that value; the others keep ``q_ref``'s
    value when some branch exists there, else they take the nearest values at which one
    does (over their whole range; see the module docstring).

    Args:
        robot: a SCARA-type robot.
        target: position, with or without yaw (a rotation target is refused).
        q_ref: (nq,) reference: held values, and the wrist when no yaw is asked.
        fixed: values of redundant joints by name [rad or m], never moved.

    Returns:
        The solutions, ``[]`` when there is none with the ``fixed`` joints held.

    Raises:
        NotScaraError: not a SCARA-type robot, or a rotation target.
        InputError: a bad ``fixed`` entry.
    """
    geom = scara_geometry(robot)
    _check_kind(target)
    held = held_values(robot, geom, q_ref, fixed)
    movable = np.zeros(robot.nq, dtype=bool)
    names = set(fixed or {})
    for k in geom.redundant:
        movable[k] = robot.joint_names[k] not in names
    box = Box.of(robot)
    sols = search_solutions(make_task(robot, geom, target, held, movable, box))
    if sols is None:  # several movable rails: only the held values are searched
        sols = make_task(robot, geom, target, held, np.zeros_like(movable), box).at_rail(
            held[geom.rails])
    return [np.clip(q, robot.lower, robot.upper) for q in sols
            if np.all((q >= robot.lower - LIMIT_SLACK) & (q <= robot.upper + LIMIT_SLACK))]


def witness(robot: Robot, target: Target, q_ref: Array | None = None) -> Array | None:
    """A configuration that reaches ``target`` exactly (closed form, nearest ``q_ref``).

    ``None`` when the closed form does not apply or finds none.
    """
    try:
        sols = solve_all(robot, target, default_q0(robot) if q_ref is None else q_ref)
    except NotScaraError:
        return None
    ref = default_q0(robot) if q_ref is None else q_ref
    return min(sols, key=lambda q: float(np.linalg.norm(q - ref))) if sols else None
