"""The planar tool angle (yaw) of chains whose revolute axes are all parallel (SCARA).

A mixin of :class:`~scara_opt.model.robot.Robot` (it reads the Pinocchio model, its
``chain``, limits and :meth:`fk`).
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.errors import TargetError

if TYPE_CHECKING:
    from scara_opt.model.urdf_tree import ChainJoint

Array = NDArray[np.float64]


class ToolAngle:
    """:attr:`yaw_axis`, :meth:`yaw` and :meth:`yaw_basis` of a robot."""

    name: str
    model: pin.Model
    data: pin.Data
    chain: tuple[ChainJoint, ...]

    if TYPE_CHECKING:  # Robot's read-only properties and methods
        @property
        def nq(self) -> int: ...  # noqa: D102
        @property
        def lower(self) -> Array: ...  # noqa: D102
        @property
        def upper(self) -> Array: ...  # noqa: D102
        def fk(self, q: ArrayLike) -> Array: ...  # noqa: D102

    @cached_property
    def yaw_axis(self) -> Array | None:
        """World axis (3,) about which the tool turns, if every revolute axis is parallel.

        That holds for SCARA-type chains (and stays true for every ``q``, since rotating
        about parallel axes keeps them parallel). ``None`` otherwise: such a robot has no
        single tool angle, and a yaw target is refused for it.
        """
        q0 = np.clip(np.zeros(self.nq), self.lower, self.upper)
        data = self.data
        pin.forwardKinematics(self.model, data, q0)
        axes = [data.oMi[k].rotation @ j.axis
                for k, j in enumerate(self.chain, start=1) if j.kind == "revolute"]
        if not axes:
            return None
        n = axes[0] / np.linalg.norm(axes[0])
        if all(np.linalg.norm(np.cross(n, a)) < 1e-9 for a in axes[1:]):
            return n
        return None

    def yaw(self, q: ArrayLike) -> float:
        """Tool angle [rad] about :attr:`yaw_axis`, in (-π, π].

        Measured as the angle of the tool's x-axis in the plane normal to the axis, from
        the world axis of :meth:`yaw_basis` ``e1`` toward ``e2`` (for a SCARA with a
        vertical axis: the angle from world x to the tool x-axis, :math:`θ_1+θ_2+θ_4`).

        Raises:
            TargetError: the robot has no yaw axis (see :attr:`yaw_axis`).
        """
        e1, e2 = self.yaw_basis()
        x = self.fk(q)[:3, 0]
        return float(math.atan2(x @ e2, x @ e1))

    def yaw_basis(self) -> tuple[Array, Array]:
        """Orthonormal (e1, e2) spanning the plane normal to :attr:`yaw_axis`, e1 × e2 = axis.

        Computed once (read-only arrays): every yaw cost and error uses it.
        """
        basis: tuple[Array, Array] | None = self.__dict__.get("_yaw_basis")
        if basis is not None:
            return basis
        n = self.yaw_axis
        if n is None:
            raise TargetError(
                f"robot {self.name!r} has no single tool-angle axis (its revolute axes are not "
                "all parallel); give a full rotation= instead of yaw="
            )
        ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = ref - (ref @ n) * n
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        e1.setflags(write=False)
        e2.setflags(write=False)
        self.__dict__["_yaw_basis"] = (e1, e2)
        return e1, e2
