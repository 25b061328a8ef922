"""Copies of a :class:`~scara_opt.model.robot.Robot`: new joint limits, and pickling.

A copy shares the constructor's attributes (:data:`CORE`) but none of the caches (casadi
Functions, IPOPT solvers, the SCARA geometry), which belong to one set of limits.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from scara_opt.checks import describe, is_real
from scara_opt.errors import JointLimitError

if TYPE_CHECKING:
    from scara_opt.model.robot import Robot

#: the attributes :class:`Robot`'s constructor sets; everything else in its ``__dict__`` is a
#: cache (casadi Functions, IPOPT solvers, the SCARA geometry, ...) that a copy must not share
CORE = ("tip", "_init_args", "model", "locked", "name", "source", "notes", "metadata",
         "chain", "tip_id", "tip_placement", "_acceleration", "_velocity")


_REBUILT: dict[tuple, Robot] = {}


def rebuild_robot(cls: type[Robot], init_args: tuple, metadata: dict, limits: tuple) -> Robot:
    """Unpickle a :class:`Robot` (see :meth:`Robot.__reduce__`); one instance per process."""
    key = (init_args, limits)
    if key not in _REBUILT:
        text, tip, name, where, source, notes, mesh_dir = init_args
        robot = cls(text, tip, name=name, where=where, source=source, notes=notes,
                    mesh_dir=mesh_dir, metadata=metadata)
        lower, upper = np.array(limits[0]), np.array(limits[1])
        if not (np.array_equal(lower, robot.lower) and np.array_equal(upper, robot.upper)):
            robot = robot.with_limits(**{n: (lo, hi) for n, lo, hi in
                                         zip(robot.joint_names, lower, upper, strict=True)})
        _REBUILT[key] = robot
    return _REBUILT[key]


def with_limits(robot: Robot, ranges: Mapping[str, object]) -> Robot:
    """``robot`` with the position limits of ``ranges`` ({joint name: (lower, upper)}) replaced.

    See :meth:`Robot.with_limits` (the public entry point, with the errors raised).
    """
    # a fresh object with the constructor's attributes, none of the caches (copy.copy
    # would go through __reduce__ and hand back the per-process rebuilt robot itself)
    new = object.__new__(type(robot))
    new.__dict__.update({k: robot.__dict__[k] for k in CORE})
    new.model = pin.Model(robot.model)
    new.metadata = dict(robot.metadata)
    new._local = threading.local()
    lower, upper = new.model.lowerPositionLimit.copy(), new.model.upperPositionLimit.copy()
    for name, value in ranges.items():
        if name not in robot.joint_names:
            raise JointLimitError(f"with_limits: no joint named {name!r}; joints: "
                                  f"{robot.joint_names}", joint=name)
        pair = tuple(value) if isinstance(value, (tuple, list, np.ndarray)) else ()
        if len(pair) != 2 or not all(map(is_real, pair)):
            raise JointLimitError(f"with_limits: {name} needs a (lower, upper) pair of "
                                  f"numbers [rad or m]; got {describe(value)}", joint=name)
        try:
            lo, hi = (float(v) for v in pair)
        except OverflowError:  # ints beyond the float range
            lo, hi = -math.inf, math.inf
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi
                and math.isfinite(hi - lo)):
            raise JointLimitError(
                f"with_limits: joint {name!r} range ({lo}, {hi}) is not finite with lower < "
                "upper (and a finite width); pass (lower, upper) in rad or m", joint=name)
        k = robot.joint_names.index(name)
        lower[k], upper[k] = lo, hi
    new.model.lowerPositionLimit, new.model.upperPositionLimit = lower, upper
    return new

