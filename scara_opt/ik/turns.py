r"""Whole turns of revolute joints: of the equivalent angles, the one nearest a reference.

A revolute joint whose range spans a turn or more (a ±2π wrist, a continuous joint)
reaches the same pose at :math:`q_k + 2πm` for every integer :math:`m` that keeps it within
its limits. Every method that honours ``q0`` returns, of these, the one nearest ``q0``
(:meth:`scara_opt.ik.base.Solver.solve` applies :func:`nearest_turn` to each answer), so
a path warm-started point by point never winds a joint round where it need not.

Only joints whose whole turns leave the forward kinematics unchanged are turned: a
revolute joint followed by a mimic joint with a non-integer multiplier (or a prismatic
one) is left as it is.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

TURN = 2.0 * math.pi


def turn_joints(robot: Robot) -> tuple[tuple[int, float, float], ...]:
    """``(k, lower, upper)`` of each joint that can take another whole turn within its limits.

    Revolute joints (continuous ones too) spanning at least one turn whose turns leave
    the FK unchanged (no mimic follower with a non-integer multiplier). Made once per
    robot (its limits never change: :meth:`~scara_opt.Robot.with_limits` makes a new one).
    """
    cached = robot.__dict__.get("_turn_joints")
    if cached is not None:
        return cached
    followers: dict[int, list] = {}
    for j in robot.chain:
        if j.mimic:
            followers.setdefault(j.index, []).append(j)
    out = []
    for k, (kind, lo, hi) in enumerate(zip(robot.joint_types, robot.lower, robot.upper,
                                           strict=True)):
        periodic = kind == "revolute" and all(
            f.kind == "revolute" and float(f.scaling).is_integer()
            for f in followers.get(k, []))
        if periodic and hi - lo >= TURN:
            out.append((k, float(lo), float(hi)))
    table = tuple(out)
    robot.__dict__["_turn_joints"] = table
    return table


def nearest_turn(robot: Robot, q: Array, q_ref: Array) -> Array:
    """``q`` (nq,) with each turnable joint at its whole turn nearest ``q_ref`` (nq,).

    Each joint :math:`k` of :func:`turn_joints` takes :math:`q_k + 2πm`, :math:`m` the
    integer nearest :math:`(q_{ref,k} - q_k) / 2π` among those within the limits (the
    distance is convex in :math:`m`, so the clipped optimum is the optimum). The pose is
    the same; ``q`` is returned itself when no joint turns (no copy: the robots without
    such joints pay one dictionary look-up).
    """
    table = robot.__dict__.get("_turn_joints")
    if table is None:
        table = turn_joints(robot)
    if not table:
        return q
    out = None
    for k, lo, hi in table:
        v, ref = float(q[k]), float(q_ref[k])
        m = _bounded(round((ref - v) / TURN), v, lo, hi)
        if m:
            if out is None:
                out = np.array(q, dtype=float)
            out[k] = min(max(v + m * TURN, lo), hi)  # round-off only: m keeps it inside
    return q if out is None else out


def _bounded(m: int, v: float, lo: float, hi: float) -> int:
    """``m`` clipped to the turns that keep ``v + 2πm`` within ``[lo, hi]`` (either may be inf)."""
    if math.isfinite(lo):
        m = max(m, math.ceil((lo - v) / TURN))
    if math.isfinite(hi):
        m = min(m, math.floor((hi - v) / TURN))
    return m


def nearest_turns(robot: Robot, Q: Array, Q_ref: Array) -> Array:
    """:func:`nearest_turn` of each row of ``Q`` (n, nq) to the same row of ``Q_ref`` (n, nq)."""
    table = turn_joints(robot)
    if not table:
        return Q
    out = np.array(Q, dtype=float)
    for k, lo, hi in table:
        v, ref = out[:, k], np.asarray(Q_ref, dtype=float)[:, k]
        m = np.round((ref - v) / TURN)
        with np.errstate(invalid="ignore"):
            m = np.clip(m, np.ceil((lo - v) / TURN), np.floor((hi - v) / TURN))
        out[:, k] = np.clip(v + m * TURN, lo, hi)
    return out
