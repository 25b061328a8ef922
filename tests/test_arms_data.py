"""The UR5 and Panda test arms (tests/data): fresh URDFs, FK equal to a hand-written DH product.

The DH numbers below are typed in again from the published tables (Universal Robots' UR5 CB3
standard DH; Franka's modified DH), NOT read from the TOML files, and the link transforms are
the textbook closed-form matrices (Spong's standard ``A_i``, Craig's modified ``T_i``), not
scara_opt.model.dh's product of elementary rotations: a typo in a TOML file or a bug in the DH ->
URDF machinery makes these tests fail.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from scara_opt.model.dh import dh_to_urdf
from scara_opt.model.dh_file import load_dh
from tests.conftest import DATA, random_q

ARMS = ["ur5_dh", "panda_dh"]
HALF_PI = math.pi / 2

# UR5 (CB3), standard DH: rows (d, a, alpha) [m, m, rad], theta offsets 0.
UR5_DH = [(0.089159, 0.0, HALF_PI), (0.0, -0.425, 0.0), (0.0, -0.39225, 0.0),
          (0.10915, 0.0, HALF_PI), (0.09465, 0.0, -HALF_PI), (0.0823, 0.0, 0.0)]
# Panda, modified (Craig) DH: rows (a_{i-1}, d_i, alpha_{i-1}) [m, m, rad]; then the flange.
PANDA_DH = [(0.0, 0.333, 0.0), (0.0, 0.0, -HALF_PI), (0.0, 0.316, HALF_PI),
            (0.0825, 0.0, HALF_PI), (-0.0825, 0.384, -HALF_PI), (0.0, 0.0, HALF_PI),
            (0.088, 0.0, HALF_PI)]
PANDA_FLANGE_D = 0.107


def standard_link(theta: float, d: float, a: float, alpha: float) -> np.ndarray:
    """Spong's A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha), written out (4, 4)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct],
                     [st, ct * ca, -ct * sa, a * st],
                     [0.0, sa, ca, d],
                     [0.0, 0.0, 0.0, 1.0]])


def modified_link(a: float, alpha: float, theta: float, d: float) -> np.ndarray:
    """Craig's T_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i), written out (4, 4)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st, 0.0, a],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0.0, 0.0, 0.0, 1.0]])


def ur5_fk(q: np.ndarray) -> np.ndarray:
    """UR5 flange pose (4, 4) [m] in the base frame: the product of the six A_i."""
    T = np.eye(4)
    for qi, (d, a, alpha) in zip(q, UR5_DH, strict=True):
        T = T @ standard_link(qi, d, a, alpha)
    return T


def panda_fk(q: np.ndarray) -> np.ndarray:
    """Panda flange pose (4, 4) [m] in the base frame: seven T_i, then the flange T_z(0.107)."""
    T = np.eye(4)
    for qi, (a, d, alpha) in zip(q, PANDA_DH, strict=True):
        T = T @ modified_link(a, alpha, qi, d)
    return T @ modified_link(0.0, 0.0, 0.0, PANDA_FLANGE_D)


@pytest.mark.parametrize("name", ARMS)
def test_arm_urdf_is_up_to_date_with_its_toml(name):
    """Regenerating tests/data/<name>.urdf from its TOML gives the committed file byte for byte.

    Mutation: alpha of UR5 row 5 flipped to +pi/2 in ur5_dh.toml (URDF not regenerated) -> fails.
    """
    expected = dh_to_urdf(load_dh(DATA / f"{name}.toml"))
    assert (DATA / f"{name}.urdf").read_text() == expected, (
        f"tests/data/{name}.urdf is stale: run "
        "python -c \"from scara_opt.model.dh_file import regenerate; regenerate('tests/data')\""
    )


def _configurations(robot, seed: int) -> np.ndarray:
    """q = 0, the limits' corners and midpoint, and 30 random in-limit q: (33, nq) [rad]."""
    return np.vstack([np.zeros(robot.nq), robot.lower, robot.upper,
                      (robot.lower + robot.upper) / 2, random_q(robot, 30, seed=seed)])


def test_ur5_fk_is_the_standard_dh_product(ur5_arm):
    """UR5 FK (Pinocchio, from the generated URDF) equals the hand-written standard DH product.

    Mutation: alpha of row 5 flipped to +pi/2 in ur5_dh.toml and the URDF regenerated -> fails.
    Mutation: d4 = 0.10900 (the serie-1 value) in ur5_dh.toml, URDF regenerated -> fails.
    """
    for q in _configurations(ur5_arm, seed=11):
        np.testing.assert_allclose(ur5_arm.fk(q), ur5_fk(q), rtol=0, atol=1e-12,
                                   err_msg=f"q = {q.tolist()}")


def test_panda_fk_is_the_modified_dh_product(panda_arm):
    """Panda FK (Pinocchio, from the generated URDF) equals the hand-written modified DH product.

    Mutation: alpha of joint 4 flipped to -pi/2 in panda_dh.toml, URDF regenerated -> fails.
    Mutation: convention = "standard" in panda_dh.toml, URDF regenerated -> fails.
    Mutation: flange row d = 0.103 in panda_dh.toml, URDF regenerated -> fails.
    """
    for q in _configurations(panda_arm, seed=12):
        np.testing.assert_allclose(panda_arm.fk(q), panda_fk(q), rtol=0, atol=1e-12,
                                   err_msg=f"q = {q.tolist()}")


def test_ur5_zero_pose_is_the_known_value(ur5_arm):
    """UR5 at q = 0: flange at (-0.81725, -0.19145, -0.005491) m, x along base x, z along -y.

    x = a2 + a3, y = -(d4 + d6), z = d1 - d5; checked by the hand product and by the robot.
    Mutation: a3 = -0.39243 (serie 1) in ur5_dh.toml, URDF regenerated -> fails.
    """
    expected = np.eye(4)
    expected[:3, :3] = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]
    expected[:3, 3] = [-0.81725, -0.19145, -0.005491]
    np.testing.assert_allclose(ur5_fk(np.zeros(6)), expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ur5_arm.fk(np.zeros(6)), expected, rtol=0, atol=1e-12)


def test_panda_zero_pose_is_the_known_value(panda_arm):
    """Panda at q = 0 (q4 = 0 lies outside its range; FK is still defined): flange at
    (0.088, 0, 0.926) m, pointing down: x = a7, z = d1 + d3 + d5 - d_flange, R = diag(1, -1, -1).

    Mutation: flange row d = 0.103 in panda_dh.toml, URDF regenerated -> fails.
    """
    expected = np.diag([1.0, -1.0, -1.0, 1.0])
    expected[:3, 3] = [0.088, 0.0, 0.926]
    np.testing.assert_allclose(panda_fk(np.zeros(7)), expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(panda_arm.fk(np.zeros(7)), expected, rtol=0, atol=1e-12)


def test_arm_limits_are_the_published_ones(ur5_arm, panda_arm):
    """Joint ranges [rad], speeds [rad/s] and (Panda) accelerations [rad/s^2] as published.

    Mutation: Panda q4 upper = 0.0698 (sign lost) in panda_dh.toml, URDF regenerated -> fails.
    """
    assert ur5_arm.nq == 6 and ur5_arm.tip == "tool"
    np.testing.assert_array_equal(ur5_arm.lower, np.full(6, -2 * math.pi))
    np.testing.assert_array_equal(ur5_arm.upper, np.full(6, 2 * math.pi))
    np.testing.assert_array_equal(ur5_arm.velocity_limit, np.full(6, math.pi))
    assert panda_arm.nq == 7 and panda_arm.tip == "tool"
    np.testing.assert_array_equal(
        panda_arm.lower, [-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
    np.testing.assert_array_equal(
        panda_arm.upper, [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])
    np.testing.assert_array_equal(panda_arm.velocity_limit, [2.175] * 4 + [2.61] * 3)
    np.testing.assert_array_equal(panda_arm.acceleration_limit,
                                  [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0])
