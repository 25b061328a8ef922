"""Task errors and costs shared by every IK solver, evaluated for a whole batch at once."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import TargetError
from scara_opt.model.robot import Robot
from scara_opt.target import Target

Array = NDArray[np.float64]

#: joint values may leave the limits by this much through floating-point round-off [rad or m]
LIMIT_SLACK = 1e-10


def default_q0(robot: Robot) -> Array:
    """The start used when ``q0`` is None: zero where within the limits, else mid-range."""
    mid = 0.5 * (robot.sampling_lower + robot.sampling_upper)
    zero_ok = (robot.lower <= 0) & (robot.upper >= 0)
    return np.where(zero_ok, 0.0, mid)


def check_task(robot: Robot, target: Target) -> None:
    """Refuse a yaw target on a robot whose tool has no single turning axis.

    Raises:
        TargetError: ``target.yaw`` is set but ``robot.yaw_axis`` is ``None``.
    """
    if target.kind == "yaw" and robot.yaw_axis is None:
        raise TargetError(
            f"robot {robot.name!r} has no single tool-angle axis (its revolute axes are not all "
            "parallel), so yaw= is undefined; give rotation= (3×3) or a position-only target"
        )


def wrap_angle(a: Array | float) -> Array | float:
    """Angles wrapped to [-π, π)."""
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


def task_errors(robot: Robot, target: Target, Q: Array) -> tuple[Array, Array | None]:
    """Position errors (n, 3) [m] and angle errors (n,) [rad] (``None`` for position-only).

    The position error is ``p(q) - p*``. The angle error is the wrapped yaw difference for a
    yaw target and the rotation angle of :math:`R^{*T} R(q)` for a rotation target.
    """
    if target.kind == "position":  # positions only: no rotation blocks to assemble
        return robot.positions(Q) - target.position, None
    return errors_from_poses(robot, target, robot.fk_batch(Q))


def errors_from_poses(robot: Robot, target: Target, T: Array) -> tuple[Array, Array | None]:
    """:func:`task_errors` from tip poses ``T`` (n, 4, 4) already computed."""
    dp = T[:, :3, 3] - target.position
    if target.rotation is not None:  # (a Target has a yaw or a rotation, never both)
        # ||R - R*||_F = 2√2 sin(θ/2): stable for small angles, unlike acos of the trace
        frob = np.linalg.norm(T[:, :3, :3] - target.rotation, axis=(1, 2))
        return dp, 2.0 * np.arcsin(np.clip(frob / (2.0 * math.sqrt(2.0)), 0.0, 1.0))
    if target.yaw is not None:
        e1, e2 = robot.yaw_basis()
        x = T[:, :3, 0]
        yaw = np.arctan2(x @ e2, x @ e1)
        return dp, np.asarray(wrap_angle(yaw - target.yaw))
    return dp, None


def cost_from_errors(target: Target, dp: Array, dang: Array | None) -> Array:
    r"""Weighted Euclidean task error (n,).

    zavar2024 eq. 8 for a position target, :math:`\sqrt{w_p^2 |Δp|^2}`; with an angle,
    nguyen eq. 10, :math:`\sqrt{w_p^2 |Δp|^2 + w_a^2 Δ_A^2}` [m and rad together].
    """
    wp, wa = target.weights
    sq = wp**2 * np.einsum("ij,ij->i", dp, dp)
    if dang is not None:
        sq = sq + wa**2 * dang**2
    return np.sqrt(sq)


def cost_of(target: Target, dp: Array, dang: float | None) -> float:
    """:func:`cost_from_errors` of one configuration: ``dp`` (3,) [m], ``dang`` [rad]."""
    wp, wa = target.weights
    sq = wp**2 * float(dp.dot(dp))  # dot: the same BLAS sum as ``@``, without its ~0.4 µs
    return math.sqrt(sq if dang is None else sq + wa**2 * dang**2)


def cost_batch(robot: Robot, target: Target, Q: Array) -> Array:
    """Task cost (n,) of configurations ``Q`` (n, nq): one vectorised FK call."""
    return cost_from_errors(target, *task_errors(robot, target, Q))


def error_from(dp: Array, dang: float | None) -> float:
    """The honest residual of one solution: max(|Δp| [m], |Δangle| [rad]).

    NaN in ``dp`` gives NaN, inf gives inf (so ``error <= tol`` is False for both).
    """
    err = math.sqrt(float(dp.dot(dp)))  # dot: the same BLAS sum as ``@``, ~0.4 µs less
    return err if dang is None else max(err, abs(float(dang)))


def config_errors(robot: Robot, target: Target, q: Array) -> tuple[Array, float | None]:
    """Position error (3,) and angle error of one configuration (one Pinocchio FK).

    The same numbers as :func:`errors_from_poses`, with scalar arithmetic: this runs once
    per solve, where numpy's per-call cost on 3×3 blocks would dominate. ``q`` must be a
    finite float (nq,) array (the callers' solutions, checked or clipped already).

    Products are ``a.dot(b)`` (the same BLAS sums as ``a @ b``, ~0.4 µs less each) and the
    yaw is wrapped in Python floats (the same IEEE operations as :func:`wrap_angle`).
    """
    T = robot.fk_checked(q)
    dp = T[:3, 3] - target.position
    rotation = target.rotation
    if rotation is None:  # (a Target has a yaw or a rotation, never both)
        if target.yaw is None:
            return dp, None
        e1, e2 = robot.yaw_basis()
        x = T[:3, 0]
        yaw = math.atan2(float(x.dot(e2)), float(x.dot(e1))) - target.yaw
        return dp, (yaw + math.pi) % (2 * math.pi) - math.pi
    d = (T[:3, :3] - rotation).ravel()
    frob = math.sqrt(float(d.dot(d)))
    return dp, 2.0 * math.asin(min(frob / (2.0 * math.sqrt(2.0)), 1.0))
