"""The least duration of a rest-to-rest move under box joint limits, and the move reaching it.

Under per-joint velocity and acceleration limits (no jerk limit: the robot files carry
none, and toppra keeps none), no trajectory from rest at ``qa`` to rest at ``qb`` is faster
than its slowest joint's own time-optimal move: each joint alone is a bang-(coast-)bang
profile of ``2 sqrt(d / a)`` (``d < v² / a``) or ``d / v + v / a`` seconds. Ruckig computes
these exactly (``max_jerk = inf``: its second-order profiles) and its time-synchronized move
(``Synchronization.Time``) reaches the bound: every joint time-optimal, stretched to the
slowest joint's time. Obstacles, torque limits, tool limits and a path only add
constraints, so the bound holds for any move between those rest states; a program of
stop-to-stop runs is bounded by the sum over its runs.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.ruckig_backend import _add_phases, _ppolys, _Ruckig

Array = NDArray[np.float64]

__all__ = ["joint_times", "lower_bound", "second_order", "synchronized_move"]


def second_order(limits: Limits) -> Limits:
    """``limits`` without a jerk limit (``jmax = inf``: Ruckig's second-order profiles)."""
    return replace(limits, jmax=np.full(limits.nq, math.inf))


def _solve(qa: Array, qb: Array, limits: Limits) -> tuple[_Ruckig, list, float]:
    """Ruckig's rest-to-rest move ``qa`` → ``qb`` under ``limits``' v and a only."""
    solver = _Ruckig(limits.nq, second_order(limits))
    profiles, duration = solver.segment(np.asarray(qa, float), np.asarray(qb, float))
    return solver, profiles, duration


def joint_times(qa: Array, qb: Array, limits: Limits) -> Array:
    """(nq,) each joint's own time-optimal rest-to-rest move from ``qa`` to ``qb`` [s].

    Under ``limits.vmax`` and ``limits.amax`` (its ``jmax`` is ignored).
    """
    solver = _solve(qa, qb, limits)[0]
    return np.array(solver.out.independent_min_durations, dtype=float)


def lower_bound(qa: Array, qb: Array, limits: Limits) -> float:
    """The least duration [s] of any move from rest at ``qa`` to rest at ``qb``.

    The slowest joint's own time-optimal move (:func:`joint_times`' largest).
    """
    return float(joint_times(qa, qb, limits).max())


def synchronized_move(qa: Array, qb: Array, limits: Limits) -> tuple[tuple[PPoly, ...], float]:
    """Ruckig's time-synchronized move from rest at ``qa`` to rest at ``qb``, at the bound.

    Each joint a time-optimal second-order profile stretched to the slowest joint's time;
    monotone per joint, so it stays between ``qa`` and ``qb``.

    Returns:
        One PPoly per joint (time [s] → q [rad or m], piecewise quadratic held as cubics),
        and the duration [s] (:func:`lower_bound`).
    """
    _, profiles, duration = _solve(qa, qb, limits)
    joints: list[list[list[float]]] = [[[], [], [], [], [0.0]] for _ in range(limits.nq)]
    for rows, prof in zip(joints, profiles, strict=True):
        _add_phases(rows, prof, 0.0, duration)
    return _ppolys(joints), duration
