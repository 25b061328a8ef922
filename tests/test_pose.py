"""Poses: Target from a 4×4 matrix or a pinocchio.SE3, Robot.fk_se3, RPY and quaternions."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import scara_opt as so
from scara_opt import pose
from tests.conftest import BUNDLED, paper_fk


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _random_q(robot, seed):
    rng = np.random.default_rng(seed)
    lo, hi = robot.sampling_lower, robot.sampling_upper
    return lo + (hi - lo) * (0.1 + 0.8 * rng.random(robot.nq))


def test_fk_se3_is_the_papers_pose(robots):
    """fk_se3 returns a pinocchio.SE3 equal to the pose each paper's own FK gives
    (conftest.paper_fk, typed in from the papers: an independent reference), at 20
    configurations per robot; fk keeps returning the same pose as a 4×4 array.

    Mutations caught: fk_se3 returning ``pin.SE3(self.fk(q)).inverse()``; its rotation
    transposed. (Before, this test compared fk_se3 with the fk it is built from.)
    """
    for name, robot in robots.items():
        for k in range(20):
            q = _random_q(robot, k)
            M = robot.fk_se3(q)
            assert isinstance(M, pin.SE3)
            p, R = paper_fk(name, q)
            np.testing.assert_allclose(M.translation, p, atol=1e-12)
            np.testing.assert_allclose(M.rotation, R, atol=1e-12)
            T = robot.fk(q)
            assert isinstance(T, np.ndarray) and T.shape == (4, 4)
            np.testing.assert_allclose(T[:3, :3], R, atol=1e-12)
            np.testing.assert_allclose(T[:3, 3], p, atol=1e-12)


@pytest.mark.parametrize("name", [*BUNDLED, "arm6"])
@pytest.mark.parametrize("form", ["matrix", "se3", "from_pose", "nested_list"])
def test_round_trip_fk_target_ik_fk(robots, arm6, name, form):
    """fk(q) -> Target -> solve_ik -> fk gives the same pose, for every input form.

    The IK may land on another branch (elbow, redundancy): the pose is compared, not q.
    Mutation caught: as_pose returning the last row ``T[3, :3]`` as the position.
    """
    robot = arm6 if name == "arm6" else robots[name]
    for seed in range(3):
        q = _random_q(robot, seed)
        T = robot.fk(q)
        if form == "matrix":
            target = so.Target(T)
        elif form == "se3":
            target = so.Target(robot.fk_se3(q))
        elif form == "from_pose":
            target = so.Target.from_pose(robot.fk_se3(q))
        else:
            target = so.Target(T.tolist())
        assert target.kind == "rotation"
        np.testing.assert_allclose(target.position, T[:3, 3], atol=0)
        res = so.solve_ik(robot, target, seed=seed)
        assert res.success, (name, seed, str(res))
        np.testing.assert_allclose(robot.fk(res.q), T, atol=1e-8)


def _bad(T_change):
    T = np.eye(4)
    T[:3, 3] = [0.3, 0.1, -0.06]
    T_change(T)
    return T


@pytest.mark.parametrize("T, match", [
    (_bad(lambda T: T.__setitem__((3, 3), 2.0)), r"last row \[0, 0, 0, 1\]"),
    (_bad(lambda T: T.__setitem__((3, 0), 0.1)), r"last row \[0, 0, 0, 1\]"),
    (_bad(lambda T: T.__setitem__((0, 3), np.nan)), "NaN or inf"),
    (_bad(lambda T: T.__setitem__((0, 0), 1.01)), "not a proper rotation"),
    (_bad(lambda T: T.__setitem__((2, 2), -1.0)), "not a proper rotation"),  # reflection
    (_bad(lambda T: T.__setitem__((0, 0), 1 + 1e-5)), "not a proper rotation"),
    (np.eye(3), r"shape \(4, 4\)"),
])
def test_bad_poses_are_refused(T, match):
    """A pose that is not a finite rigid transform raises TargetError, an InputError.

    Mutation caught: ROTATION_TOL raised from 1e-6 to 1e-2 (the 1e-5 case passes);
    TargetError back to a sibling of InputError.
    """
    with pytest.raises(so.TargetError, match=match):
        so.Target.from_pose(T)
    with pytest.raises(so.InputError, match=match):
        so.Target.from_pose(T)
    with pytest.raises(ValueError):
        so.Target(T) if T.shape == (4, 4) else so.Target.from_pose(T)


def test_rotation_tolerance_is_the_stated_one():
    """A rotation off by 1e-7 (inside ROTATION_TOL = 1e-6) is accepted and kept as given."""
    T = np.eye(4)
    T[0, 0] += 1e-7
    assert pose.ROTATION_TOL == 1e-6
    np.testing.assert_array_equal(so.Target(T).rotation, T[:3, :3])


def test_a_pose_with_yaw_or_rotation_is_ambiguous():
    """Target(T, yaw=...) would give the rotation twice: refused."""
    with pytest.raises(so.TargetError, match="already fixes the rotation"):
        so.Target(np.eye(4), yaw=0.1)
    with pytest.raises(so.TargetError, match="already fixes the rotation"):
        so.Target(pin.SE3.Identity(), rotation=np.eye(3))


def test_rpy_is_zyx_fixed_axes_like_pinocchio_and_rtb():
    """rpy (r, p, y) is Rz(y) Ry(p) Rx(r); matrix_to_rpy inverts it.

    Mutation caught: rpy_to_matrix passing (y, p, r) to pinocchio.
    """
    r, p, y = 0.3, -0.4, 1.2
    R = pose.rpy_to_matrix([r, p, y])
    np.testing.assert_allclose(R, _rz(y) @ _ry(p) @ _rx(r), atol=1e-14)
    np.testing.assert_allclose(pose.matrix_to_rpy(R), [r, p, y], atol=1e-12)


def test_quaternions_are_scalar_first():
    """(w, x, y, z) = (cos a/2, 0, 0, sin a/2) is Rz(a); matrix_to_quat gives w >= 0.

    Mutation caught: quat_to_matrix reading (x, y, z, w).
    """
    a = 0.8
    q = [np.cos(a / 2), 0.0, 0.0, np.sin(a / 2)]
    np.testing.assert_allclose(pose.quat_to_matrix(q), _rz(a), atol=1e-14)
    np.testing.assert_allclose(pose.matrix_to_quat(_rz(a)), q, atol=1e-14)
    w = pose.matrix_to_quat(_rz(3.0) @ _rx(2.0))[0]
    assert w >= 0
    # four typed decimals are accepted and normalised; a zero quaternion is not
    np.testing.assert_allclose(pose.quat_to_matrix([0.7071, 0, 0, 0.7071]), _rz(np.pi / 2),
                               atol=1e-12)
    with pytest.raises(so.TargetError, match="unit quaternion"):
        pose.quat_to_matrix([0, 0, 0, 0])
    with pytest.raises(so.TargetError, match="unit quaternion"):
        pose.quat_to_matrix([1, 1, 1, 1])
