"""IK targets: a tip position, optionally a tool angle (yaw) or a full rotation."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import TargetError

Array = NDArray[np.float64]


def _finite_array(value: object, shape: tuple[int, ...], what: str) -> Array:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TargetError(f"{what} must be numeric with shape {shape}; got {value!r}") from None
    if arr.shape != shape:
        raise TargetError(f"{what} must have shape {shape}; got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise TargetError(f"{what} has NaN or inf entries ({arr.tolist()}); pass finite values")
    return arr


@dataclass(frozen=True)
class Target:
    """Where the tip should go.

    Attributes:
        position: (3,) tip position in the world frame [m].
        yaw: tool angle [rad] about the robot's :attr:`~scara_opt.Robot.yaw_axis`, or ``None``.
        rotation: (3, 3) tip orientation, or ``None``. At most one of ``yaw``/``rotation``.
        weights: ``(w_position, w_angle)`` of the task error in the cost; default ``(1, 1)``.

    Raises:
        TargetError: wrong shapes, NaN/inf, both yaw and rotation, an improper rotation,
            or non-positive weights.
    """

    position: Array
    yaw: float | None = None
    rotation: Array | None = None
    weights: tuple[float, float] = field(default=(1.0, 1.0))

    def __init__(self, position: object, yaw: float | None = None,
                 rotation: object | None = None,
                 weights: tuple[float, float] | None = None) -> None:
        pos = _finite_array(position, (3,), "target position [m]")
        pos.flags.writeable = False
        object.__setattr__(self, "position", pos)
        if yaw is not None and rotation is not None:
            raise TargetError("give either yaw= or rotation=, not both")
        if yaw is not None:
            try:
                yaw = float(yaw)  # type: ignore[arg-type]
            except (TypeError, ValueError):
                raise TargetError(f"yaw must be a number [rad]; got {yaw!r}") from None
            if not math.isfinite(yaw):
                raise TargetError(f"yaw must be finite [rad]; got {yaw}")
        object.__setattr__(self, "yaw", yaw)
        rot = None
        if rotation is not None:
            rot = _finite_array(rotation, (3, 3), "target rotation")
            if (np.abs(rot @ rot.T - np.eye(3)).max() > 1e-6
                    or abs(np.linalg.det(rot) - 1.0) > 1e-6):
                raise TargetError(
                    "target rotation is not a proper rotation matrix (R Rᵀ = I, det R = +1 "
                    "to 1e-6); orthonormalise it first"
                )
            rot.flags.writeable = False
        object.__setattr__(self, "rotation", rot)
        try:
            w = (1.0, 1.0) if weights is None else tuple(float(v) for v in weights)
        except (TypeError, ValueError):
            w = ()
        if len(w) != 2 or not all(math.isfinite(v) and v > 0 for v in w):
            raise TargetError(
                f"weights must be two positive numbers (position, angle); got {weights!r}")
        object.__setattr__(self, "weights", w)

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


def as_target(target: Target | object) -> Target:
    """A :class:`Target` from a Target or a bare (3,) position."""
    return target if isinstance(target, Target) else Target(target)
