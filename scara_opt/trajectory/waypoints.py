"""The waypoints a timing method may use: checked once, with a message that says what to do."""

from __future__ import annotations

import logging
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import InputError, JointLimitError, TrajectoryError
from scara_opt.model.joint_checks import LIMIT_SLACK  # round-off off the limits [rad or m]
from scara_opt.model.robot import Robot

if TYPE_CHECKING:
    from scara_opt.trajectory.path import JointPath

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

#: a joint path as given: a JointPath, an (n, nq) array, or a list of (nq,) joint vectors
Waypoints: TypeAlias = "JointPath | ArrayLike | Sequence[ArrayLike]"

#: consecutive waypoints closer than this in every joint are duplicates [rad or m]
DUPLICATE_TOL = 1e-9
#: most values (n × nq) that the fast path of :func:`prepare_waypoints` checks in a Python
#: loop; beyond, numpy's checks of the whole array are faster
FAST_SIZE = 64

_F64 = np.dtype(np.float64)
#: the largest float: the bound of a joint without limits, so that ±inf and NaN never pass
_BIG = sys.float_info.max


def prepare_waypoints(path: Waypoints, robot: Robot | None, *, allow_jumps: bool = False,
                      drop_duplicates: bool = False) -> Array:
    """The (n, nq) waypoint array of a JointPath or array, validated.

    Args:
        path: a :class:`~scara_opt.trajectory.path.JointPath` or an (n, nq) array [rad or m].
        robot: checks the joint count and position limits (``None``: not checked).
        allow_jumps: accept a JointPath that reports jumps (logged as a warning).
        drop_duplicates: remove consecutive duplicate waypoints (logged) instead of refusing.

    Raises:
        TrajectoryError: unsolved points or jumps in a JointPath; fewer than two waypoints;
            consecutive duplicates (unless ``drop_duplicates``).
        InputError: not a numeric (n, nq) array, NaN/inf, or a joint count unlike the robot's.
        JointLimitError: a waypoint outside the robot's joint limits.
    """
    if _plain(path, robot):  # the common case: nothing to convert, refuse or drop
        return np.array(path, dtype=float)
    from scara_opt.trajectory.path import JointPath

    if isinstance(path, JointPath):
        path.raise_if_invalid(allow_jumps=allow_jumps)
        if path.jumps:
            log.warning("timing a joint path with %d jump(s) (allow_jumps=True): %s",
                        len(path.jumps), "; ".join(str(j) for j in path.jumps))
        Q = np.array(path.q, dtype=float)
    else:
        try:
            Q = np.array(float_array(path, "path"), dtype=float)
        except InputError:
            raise InputError("path must be a JointPath or a numeric (n, nq) array of joint "
                             f"waypoints [rad or m]; got {describe(path)}") from None
    if Q.ndim != 2 or Q.shape[1] < 1:
        raise InputError(f"path must have shape (n, nq), one row per waypoint; got shape "
                         f"{Q.shape}")
    if not np.isfinite(Q).all():
        rows = np.flatnonzero(~np.isfinite(Q).all(axis=1))
        raise InputError(f"waypoints {rows[:10].tolist()} have NaN or inf values; pass finite "
                         "joint values")
    if robot is not None and Q.shape[1] != robot.nq:
        raise InputError(f"the path has {Q.shape[1]} joints but robot {robot.name!r} has "
                         f"{robot.nq} ({robot.joint_names}); pass shape (n, {robot.nq})")
    if Q.shape[0] < 2:
        raise TrajectoryError(f"a trajectory needs at least two waypoints; got {Q.shape[0]}: "
                              "add the start (or goal) configuration")
    if robot is not None:
        _check_position_limits(Q, robot)
    return _without_duplicates(Q, drop_duplicates)


def _plain(path: object, robot: Robot | None) -> bool:
    """Whether ``path`` passes every check of :func:`prepare_waypoints` as it is: its fast path.

    True iff ``path`` is a float64 ndarray (n, nq), n >= 2, nq >= 1 (the robot's nq), of at
    most :data:`FAST_SIZE` values, all finite and within the robot's joint limits (with
    :data:`LIMIT_SLACK`), and no two consecutive rows are duplicates. Anything else gives
    False, never an error: the full checks then run. A Python loop over the values, ~2 µs
    for two waypoints of 4 joints against ~15 µs of numpy calls on so small an array.
    """
    if (type(path) is not np.ndarray or path.dtype is not _F64 or path.ndim != 2
            or path.shape[0] < 2 or path.shape[1] < 1 or path.size > FAST_SIZE):
        return False
    if robot is None:
        bounds = [(-_BIG, _BIG)] * path.shape[1]
    elif path.shape[1] != robot.nq:
        return False
    else:
        bounds = [(lo - LIMIT_SLACK, hi + LIMIT_SLACK) for lo, hi in robot.limit_pairs()]
    rows = path.tolist()
    for row in rows:
        for v, (lo, hi) in zip(row, bounds, strict=True):
            if not lo <= v <= hi:  # NaN fails both
                return False
    return all(max(abs(b - a) for a, b in zip(r0, r1, strict=True)) > DUPLICATE_TOL
               for r0, r1 in zip(rows, rows[1:], strict=False))


def _check_position_limits(Q: Array, robot: Robot) -> None:
    over = (Q < robot.lower - LIMIT_SLACK) | (Q > robot.upper + LIMIT_SLACK)
    if over.any():
        i, k = (int(v) for v in np.argwhere(over)[0])
        name = robot.joint_names[k]
        unit = "rad" if robot.joint_types[k] == "revolute" else "m"
        raise JointLimitError(
            f"waypoint {i}: joint {name!r} = {Q[i, k]:.6g} {unit} is outside "
            f"[{robot.lower[k]:.6g}, {robot.upper[k]:.6g}] {unit} ({int(over.sum())} value(s) "
            "out of limits in all); pass waypoints within the joint limits", joint=name)


def _without_duplicates(Q: Array, drop: bool) -> Array:
    same = np.flatnonzero(np.abs(np.diff(Q, axis=0)).max(axis=1) <= DUPLICATE_TOL) + 1
    if not same.size:
        return Q
    keep = np.ones(len(Q), dtype=bool)
    keep[same] = False
    if keep.sum() < 2:  # no advice helps: dropping the duplicates leaves a single point
        raise TrajectoryError(f"fewer than two distinct waypoints (all equal within "
                              f"{DUPLICATE_TOL:g}): the path does not move, there is no move "
                              "to time; the robot just stays at its first waypoint")
    if not drop:
        raise TrajectoryError(
            f"waypoints {[(int(i) - 1, int(i)) for i in same[:10]]} are consecutive "
            f"duplicates (equal within {DUPLICATE_TOL:g}); a zero-length segment cannot be "
            "timed: remove them or pass drop_duplicates=True")
    log.info("dropped %d consecutive duplicate waypoint(s): %s", same.size, same.tolist())
    return Q[keep]
