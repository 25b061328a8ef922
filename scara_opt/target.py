"""IK targets: a tip position, optionally a tool angle (yaw) or a full rotation.

A full pose can also be given as a 4×4 homogeneous matrix or a ``pinocchio.SE3`` (what
:meth:`~scara_opt.Robot.fk` and :meth:`~scara_opt.Robot.fk_se3` return):
``Target(T)`` or ``Target.from_pose(T)``. The conventions are in :mod:`scara_opt.pose`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, is_real
from scara_opt.errors import TargetError
from scara_opt.pose import as_pose, check_rotation, finite_array

Array = NDArray[np.float64]

#: largest target coordinate [m]: far beyond any robot's reach (a larger one is a unit or
#: data error), and small enough that squared errors never overflow
MAX_COORDINATE = 1e6
#: largest tool angle [rad] (about 160,000 turns): a float of this size still resolves
#: 1.2e-10 rad, finer than the default tolerance 1e-9; beyond ~1e15 rad it cannot tell turns
MAX_ANGLE = 1e6
#: range of each weight: ratios up to 1e12 between the position and angle terms, and
#: weighted squared errors that stay finite (1e200 squared overflows)
WEIGHT_RANGE = (1e-6, 1e6)


@dataclass(frozen=True)
class Target:
    """Where the tip should go.

    ``Target(position)``, ``Target(position, yaw=...)``, ``Target(position, rotation=R)``, or
    a whole pose in place of the position: ``Target(T)`` with ``T`` a 4×4 homogeneous matrix
    or a ``pinocchio.SE3`` (the same as :meth:`from_pose`).

    Attributes:
        position: (3,) tip position in the world frame [m].
        yaw: tool angle [rad] about the robot's :attr:`~scara_opt.Robot.yaw_axis`, or ``None``.
        rotation: (3, 3) tip orientation, or ``None``. At most one of ``yaw``/``rotation``.
        weights: ``(w_position, w_angle)`` of the task error in the cost; default ``(1, 1)``,
            each within :data:`WEIGHT_RANGE`.

    Raises:
        TargetError: wrong shapes, NaN/inf, strings or bools for numbers, a coordinate beyond
            :data:`MAX_COORDINATE`, a yaw beyond :data:`MAX_ANGLE`, both yaw and rotation, an
            improper rotation (tolerance :data:`scara_opt.pose.ROTATION_TOL`), a pose whose
            last row is not ``[0, 0, 0, 1]``, or weights outside :data:`WEIGHT_RANGE`.
    """

    position: Array
    yaw: float | None = None
    rotation: Array | None = None
    weights: tuple[float, float] = field(default=(1.0, 1.0))

    def __init__(self, position: ArrayLike | pin.SE3, yaw: float | None = None,
                 rotation: ArrayLike | None = None,
                 weights: tuple[float, float] | None = None) -> None:
        if _is_pose(position):
            if yaw is not None or rotation is not None:
                raise TargetError("a pose (4×4 matrix or SE3) already fixes the rotation: give "
                                  "no yaw= or rotation= with it")
            position, rotation = as_pose(position, "target pose")
        pos = _position(position)
        pos = pos.copy() if pos is position else pos
        pos.flags.writeable = False
        object.__setattr__(self, "position", pos)
        if yaw is not None and rotation is not None:
            raise TargetError("give either yaw= or rotation=, not both")
        if yaw is not None:
            if not is_real(yaw):
                raise TargetError(f"yaw must be a number [rad]; got {describe(yaw)}")
            try:
                yaw = float(yaw)
            except OverflowError:
                yaw = math.inf
            if not (math.isfinite(yaw) and abs(yaw) <= MAX_ANGLE):
                raise TargetError(f"yaw must be finite, within ±{MAX_ANGLE:g} rad (beyond, a "
                                  f"float cannot resolve the angle); got {yaw!r}")
        object.__setattr__(self, "yaw", yaw)
        rot = None
        if rotation is not None:
            rot = check_rotation(rotation, "target rotation")
            rot = rot.copy() if rot is rotation else rot
            rot.flags.writeable = False
        object.__setattr__(self, "rotation", rot)
        object.__setattr__(self, "weights", _weights(weights))

    @classmethod
    def from_pose(cls, pose: ArrayLike | pin.SE3,
                  weights: tuple[float, float] | None = None) -> Target:
        """A full-pose target from a 4×4 homogeneous matrix or a ``pinocchio.SE3`` [m].

        ``Target.from_pose(robot.fk(q))`` asks for the pose the tip has at ``q``.

        Raises:
            TargetError: not 4×4, NaN/inf, last row not ``[0, 0, 0, 1]``, or an improper
                rotation block.
        """
        p, R = as_pose(pose, "target pose")
        return cls(p, rotation=R, weights=weights)

    @property
    def kind(self) -> str:
        """``"position"``, ``"yaw"`` or ``"rotation"``: which task the target asks for."""
        if self.rotation is not None:
            return "rotation"
        return "yaw" if self.yaw is not None else "position"

    def __repr__(self) -> str:
        extra = ""
        if self.yaw is not None:
            extra = f", yaw={self.yaw:.6g}"
        elif self.rotation is not None:
            extra = ", rotation=<3x3>"
        return f"Target(position={np.array2string(self.position, precision=6)}{extra})"


def _position(value: ArrayLike) -> Array:
    """``value`` as a finite (3,) position [m] within ±:data:`MAX_COORDINATE`.

    A float (3,) array whose coordinates are all within the range (NaN and inf are not) is
    taken as it is, with three float comparisons instead of the ~3 µs of numpy checks
    (every solve of a bare position makes a Target); anything else is checked in full.

    Raises:
        TargetError: not numeric, not shape (3,), NaN/inf, or a coordinate out of range.
    """
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (3,):
        x, y, z = value.tolist()
        m = MAX_COORDINATE
        if -m <= x <= m and -m <= y <= m and -m <= z <= m:
            return value
    pos = finite_array(value, (3,), "target position [m]")
    if np.abs(pos).max() > MAX_COORDINATE:
        raise TargetError(f"target position {pos.tolist()} m has a coordinate beyond "
                          f"±{MAX_COORDINATE:g} m, far outside any robot's reach; positions "
                          "are in metres (a unit error?)")
    return pos


def _is_pose(value: object) -> bool:
    """True for a ``pinocchio.SE3`` or anything of shape (4, 4)."""
    if isinstance(value, pin.SE3):
        return True
    return getattr(value, "shape", None) == (4, 4) or (
        isinstance(value, (list, tuple)) and len(value) == 4
        and all(isinstance(r, (list, tuple, np.ndarray)) and len(r) == 4 for r in value))


def _weights(weights: object) -> tuple[float, float]:
    """``(w_position, w_angle)``, each a number within :data:`WEIGHT_RANGE`; default (1, 1)."""
    if weights is None:
        return (1.0, 1.0)
    lo, hi = WEIGHT_RANGE
    pair: tuple[object, ...] = ()
    if isinstance(weights, Iterable):
        try:
            pair = tuple(weights)
        except TypeError:  # a 0-d array
            pair = ()
    # `not v < lo` for `lo <= v`: typeshed's numbers.Real has __lt__ and __le__ only
    ok = [v for v in pair if is_real(v) and not v < lo and v <= hi]
    if len(pair) != 2 or len(ok) != 2:
        raise TargetError(f"weights must be two positive numbers (position, angle), each within "
                          f"[{lo:g}, {hi:g}] (their squares enter the cost); got "
                          f"{describe(weights)}")
    return float(ok[0]), float(ok[1])


def as_target(target: Target | ArrayLike) -> Target:
    """A :class:`Target` from a Target or a bare (3,) position."""
    return target if isinstance(target, Target) else Target(target)
