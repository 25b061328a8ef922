"""Symbolic forward kinematics in casadi, built by walking the Pinocchio model tree.

The PyPI ``pin`` wheel has no ``pinocchio.casadi``, so the expression is assembled here
from the joint placements, joint kinds and axes, and the tip placement that
:class:`~scara_opt.model.robot.Robot` reads from its Pinocchio model. It serves the exact
solvers (:mod:`scara_opt.ik.problem`) and, compiled and mapped, every batch FK
(:mod:`scara_opt.model.batch_fk`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

if TYPE_CHECKING:
    from scara_opt.model.urdf_tree import ChainJoint


def _rotation(axis: np.ndarray, angle: ca.SX) -> ca.SX:
    """3×3 rotation about a constant unit ``axis`` by a symbolic ``angle`` (Rodrigues)."""
    c, s = ca.cos(angle), ca.sin(angle)
    K = ca.SX(np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]))
    return ca.SX.eye(3) + s * K + (1 - c) * (K @ K)


def chain_walk(chain: Sequence[ChainJoint], tip_placement: np.ndarray,
               q: ca.SX, frames: list[tuple[ca.SX, ca.SX]] | None = None
               ) -> tuple[list[ca.SX], ca.SX, ca.SX]:
    """Walk the chain symbolically: every joint frame's origin, then the tip's p and R.

    A mimic joint of the chain moves by ``scaling * q[index] + offset``; every other joint
    by ``q[index]`` (continuous joints included: ``q`` holds their angle). ``frames``, when
    given, receives each joint's world frame ``(R, p)`` after its motion, in chain order
    (Pinocchio's ``oMi``).

    Returns:
        ``(origins, p, R)``: the world origin (3,) of each joint frame, in chain order; the
        tip position (3,) [m] and rotation (3×3).
    """
    R: ca.SX = ca.SX.eye(3)
    p: ca.SX = ca.SX.zeros(3)
    origins = []
    for j in chain:
        p = p + R @ ca.DM(j.placement[:3, 3])
        origins.append(p)
        if not np.array_equal(j.placement[:3, :3], np.eye(3)):
            R = R @ ca.DM(j.placement[:3, :3])
        value = j.scaling * q[j.index] + j.offset if j.mimic else q[j.index]
        if j.kind == "prismatic":
            p = p + (R @ ca.DM(j.axis)) * value
        else:
            R = R @ _rotation(j.axis, value)
        if frames is not None:
            frames.append((R, p))
    return origins, p + R @ ca.DM(tip_placement[:3, 3]), R @ ca.DM(tip_placement[:3, :3])


def build_symbolic_fk(chain: Sequence[ChainJoint], tip_placement: np.ndarray,
                      name: str = "fk") -> ca.Function:
    """casadi Function ``q (nq,) -> (p (3,), R (3×3))`` of the tip pose in the world frame.

    Args:
        chain: the movable joints in order (placement in the parent frame, kind, axis,
            the entry of ``q`` that drives it).
        tip_placement: 4×4 placement of the tip in the last joint's frame [m].
        name: the Function's name.
    """
    q = ca.SX.sym("q", sum(not j.mimic for j in chain))
    _, p, R = chain_walk(chain, tip_placement, q)
    return ca.Function(name, [q], [ca.simplify(p), ca.simplify(R)], ["q"], ["p", "R"])
