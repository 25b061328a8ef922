"""Poses as Pinocchio and roboticstoolbox users write them: 4×4 matrices, SE3, RPY, quaternions.

Conventions (those of Pinocchio's ``pinocchio.rpy`` and of roboticstoolbox's default
``"zyx"`` order):

- **RPY** ``(roll, pitch, yaw)`` [rad] is ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``: roll about
  the fixed x axis first, then pitch about fixed y, then yaw about fixed z.
- **Quaternions** are ``(w, x, y, z)``, scalar first (roboticstoolbox's ``UnitQuaternion``,
  Eigen's constructor order); :func:`matrix_to_quat` returns the one with ``w >= 0``.
- A **pose** is a 4×4 homogeneous matrix ``[[R, p], [0, 0, 0, 1]]`` [m] or a ``pinocchio.SE3``.

Every function checks its input and raises :class:`~scara_opt.errors.TargetError` (a
``ValueError``) saying what is wrong.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import TargetError

Array = NDArray[np.float64]

#: tolerance of a proper rotation: ``max |R Rᵀ − I|`` and ``|det R − 1|`` at most this
ROTATION_TOL = 1e-6
#: tolerance of a pose's last row against ``[0, 0, 0, 1]``
BOTTOM_ROW_TOL = 1e-9
#: a quaternion's norm must lie within ``1 ± QUAT_NORM_TOL``; it is then normalised (values
#: typed with four decimals, such as 0.7071, are off by ~1e-5)
QUAT_NORM_TOL = 1e-3

__all__ = ["BOTTOM_ROW_TOL", "QUAT_NORM_TOL", "ROTATION_TOL", "as_pose", "check_rotation",
           "finite_array", "matrix_to_quat", "matrix_to_rpy", "quat_to_matrix", "rpy_to_matrix",
           "to_se3"]


def finite_array(value: ArrayLike, shape: tuple[int, ...], what: str) -> Array:
    """``value`` as a float array of ``shape`` with finite entries, or :class:`TargetError`."""
    try:
        arr = float_array(value, what, TargetError)
    except TargetError:
        raise TargetError(f"{what} must be numeric with shape {shape}; got "
                          f"{describe(value)}") from None
    if arr.shape != shape:
        raise TargetError(f"{what} must have shape {shape}; got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise TargetError(f"{what} has NaN or inf entries ({arr.tolist()}); pass finite values")
    return arr


def check_rotation(R: ArrayLike, what: str = "rotation") -> Array:
    """``R`` as a (3, 3) float array if it is a proper rotation within :data:`ROTATION_TOL`.

    Raises:
        TargetError: not numeric, wrong shape, NaN/inf, not orthonormal, or ``det R = -1``
            (a reflection).
    """
    rot = finite_array(R, (3, 3), what)
    ortho = float(np.abs(rot @ rot.T - np.eye(3)).max())
    det = float(np.linalg.det(rot))
    if ortho > ROTATION_TOL or abs(det - 1.0) > ROTATION_TOL:
        raise TargetError(
            f"{what} is not a proper rotation matrix (R Rᵀ = I and det R = +1 to "
            f"{ROTATION_TOL:g}; got max |R Rᵀ − I| = {ortho:.3g}, det R = {det:.6g}); "
            "orthonormalise it first (e.g. pinocchio.orthogonalProjection or an SVD)")
    return rot


def as_pose(pose: ArrayLike | pin.SE3, what: str = "pose") -> tuple[Array, Array]:
    """``(p (3,), R (3, 3))`` of a 4×4 homogeneous matrix or a ``pinocchio.SE3``.

    Raises:
        TargetError: not 4×4, NaN/inf, a last row other than ``[0, 0, 0, 1]`` (within
            :data:`BOTTOM_ROW_TOL`), or an improper rotation block.
    """
    if isinstance(pose, pin.SE3):
        pose = pose.homogeneous
    T = finite_array(pose, (4, 4), f"{what} (4×4 homogeneous matrix or pinocchio.SE3)")
    if np.abs(T[3] - [0.0, 0.0, 0.0, 1.0]).max() > BOTTOM_ROW_TOL:
        raise TargetError(f"{what} must have the last row [0, 0, 0, 1] of a homogeneous "
                          f"transform; got {T[3].tolist()}")
    return T[:3, 3].copy(), check_rotation(T[:3, :3], f"{what}'s rotation block")


def to_se3(pose: ArrayLike | pin.SE3) -> pin.SE3:
    """A ``pinocchio.SE3`` from a 4×4 homogeneous matrix (or a copy of an SE3), checked."""
    p, R = as_pose(pose)
    return pin.SE3(R, p)


def rpy_to_matrix(rpy: ArrayLike) -> Array:
    """Rotation (3, 3) of roll, pitch, yaw [rad]: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    r, p, y = finite_array(rpy, (3,), "rpy [rad]")
    return np.asarray(pin.rpy.rpyToMatrix(r, p, y), float)


def matrix_to_rpy(R: ArrayLike) -> Array:
    """``(roll, pitch, yaw)`` [rad] of a rotation; pitch in [−π/2, π/2] (Pinocchio's branch)."""
    return np.asarray(pin.rpy.matrixToRpy(check_rotation(R)), float)


def quat_to_matrix(wxyz: ArrayLike) -> Array:
    """Rotation (3, 3) of a quaternion ``(w, x, y, z)``, norm 1 within :data:`QUAT_NORM_TOL`.

    Raises:
        TargetError: not four finite numbers, or a norm too far from 1 (e.g. all zeros).
    """
    q = finite_array(wxyz, (4,), "quaternion (w, x, y, z)")
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > QUAT_NORM_TOL:
        raise TargetError(f"quaternion (w, x, y, z) = {q.tolist()} has norm {norm:.6g}; a "
                          f"rotation needs a unit quaternion (norm 1 within {QUAT_NORM_TOL:g}): "
                          "divide it by its norm first")
    w, x, y, z = q / norm
    return np.asarray(pin.Quaternion(w, x, y, z).toRotationMatrix(), float)


def matrix_to_quat(R: ArrayLike) -> Array:
    """Unit quaternion ``(w, x, y, z)`` of a rotation, with ``w >= 0``."""
    x, y, z, w = pin.Quaternion(check_rotation(R)).coeffs()
    q = np.array([w, x, y, z], float)
    return -q if q[0] < 0 else q
