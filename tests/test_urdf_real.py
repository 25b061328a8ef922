"""Real-world URDFs: trees reduced to the path to the tip, continuous and mimic joints, meshes.

The independent reference is Pinocchio on the *full* model, built straight from the file
(continuous joints as its (cos, sin) pair, every joint independent), with the locked and
mimic joint values typed in from the URDFs under ``tests/data/``.
"""

from __future__ import annotations

import logging
import pickle

import numpy as np
import pinocchio as pin
import pytest

import scara_opt as so
from scara_opt.ik.analytic import solve_batch
from scara_opt.model.catalogue import ROBOTS_EXTRA, example_robot_data_urdf
from tests.conftest import DATA

GRIPPER = DATA / "gripper_arm.urdf"
CONTINUOUS = DATA / "continuous_arm.urdf"
MIMIC = DATA / "mimic_arm.urdf"
MISSING_MESH = DATA / "missing_mesh.urdf"

#: locked joints of gripper_arm: left finger mid-range (0 is outside [0.01, 0.04] m), the
#: right finger follows it (multiplier 1, offset 0), the camera pan mid-range [0.5, 1.5] rad
GRIPPER_LOCKED = {"left_finger_joint": 0.025, "right_finger_joint": 0.025, "camera_pan": 1.0}
#: mimic_arm's side branch: the leader mid-range [0.2, 0.6], the follower 2 * 0.4 + 0.1
MIMIC_LOCKED = {"side_leader": 0.4, "side_follower": 0.9}


def mimic_values(q: np.ndarray) -> dict[str, float]:
    """mimic_arm.urdf's relations typed in: j3 = -0.5 j1 + 0.2, j5 = 2 j2 - 0.01."""
    return {"j1": q[0], "j2": q[1], "j3": -0.5 * q[0] + 0.2, "j4": q[2],
            "j5": 2.0 * q[1] - 0.01}


def full_model_fk(path, tip: str, values: dict[str, float]) -> np.ndarray:
    """Tip pose by Pinocchio on the unreduced model of ``path``, every joint set by name."""
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    q = pin.neutral(model)
    for k in range(1, model.njoints):
        jm, v = model.joints[k], values[model.names[k]]
        q[jm.idx_q:jm.idx_q + jm.nq] = [np.cos(v), np.sin(v)] if jm.nq == 2 else [v]
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(tip)].homogeneous


def random_q(robot: so.Robot, n: int, seed: int) -> np.ndarray:
    """``n`` configurations (n, nq) in the sampling box (continuous joints: 3 turns each way)."""
    lo = np.where(np.isfinite(robot.lower), robot.lower, -6 * np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, 6 * np.pi)
    return np.random.default_rng(seed).uniform(lo, hi, (n, robot.nq))


@pytest.fixture(scope="module")
def gripper() -> so.Robot:
    return so.Robot.from_urdf(GRIPPER, tip="tcp")


@pytest.fixture(scope="module")
def continuous() -> so.Robot:
    return so.Robot.from_urdf(CONTINUOUS, tip="tool")


@pytest.fixture(scope="module")
def mimic() -> so.Robot:
    return so.Robot.from_urdf(MIMIC, tip="tip")


@pytest.fixture(scope="module")
def robots(gripper, continuous, mimic) -> dict[str, so.Robot]:
    return {"gripper": gripper, "continuous": continuous, "mimic": mimic}


# ---------------------------------------------------------------------------- trees
def test_tree_keeps_the_path_to_the_tip_and_locks_the_rest(gripper):
    """gripper_arm to tcp: the six arm joints; fingers and camera locked at their reference."""
    assert gripper.nq == 6 and gripper.tip == "tcp"
    assert gripper.joint_names == ["j1", "j2", "j3", "j4", "j5", "j6"]
    assert gripper.locked == pytest.approx(GRIPPER_LOCKED)
    np.testing.assert_allclose(gripper.velocity_limit, [2, 2, 2.5, 3, 3, 3])


@pytest.mark.parametrize("tip, names", [
    ("left_finger", ["j1", "j2", "j3", "j4", "j5", "j6", "left_finger_joint"]),
    ("right_finger", ["j1", "j2", "j3", "j4", "j5", "j6"]),   # its leader is off the path
    ("camera", ["j1", "j2", "camera_pan"]),
])
def test_other_tips_keep_their_own_path(tip, names):
    """Each tip keeps the joints on its own path; a mimic joint whose leader is off it is locked."""
    robot = so.Robot.from_urdf(GRIPPER, tip=tip)
    assert robot.joint_names == names
    assert set(robot.locked) == {"left_finger_joint", "right_finger_joint", "camera_pan", "j3",
                                 "j4", "j5", "j6"} - set(names)


def test_tip_none_picks_the_longest_chain_and_says_so(caplog):
    """tip=None takes the end link with the most joint coordinates and logs which one."""
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        robot = so.Robot.from_urdf(GRIPPER)
    assert robot.tip == "left_finger" and robot.nq == 7
    assert any("'left_finger'" in r.getMessage() and "tip=" in r.getMessage()
               for r in caplog.records)


def test_unknown_tip_lists_the_frames():
    """A tip that is not a link raises FrameNotFoundError naming the links that exist."""
    with pytest.raises(so.FrameNotFoundError, match=r"'gripper'.*frames that exist:.*tcp"):
        so.Robot.from_urdf(GRIPPER, tip="gripper")


def test_a_tip_without_movable_joints_is_refused():
    """A tip on the root side of every movable joint leaves nothing to move: URDFError."""
    with pytest.raises(so.URDFError, match="no movable joint.*'base_link'.*tip="):
        so.Robot.from_urdf(GRIPPER, tip="base_link")


@pytest.mark.parametrize("tip", ["tcp", "right_finger", "camera"])
def test_reduced_fk_equals_full_model_fk_at_the_lock_reference(tip):
    """FK of the reduced robot = Pinocchio FK of the full model with the locked joints at
    their reference (the right finger's pose shows the mid-range lock of the left one)."""
    robot = so.Robot.from_urdf(GRIPPER, tip=tip)
    for q in random_q(robot, 20, seed=1):
        values = {**GRIPPER_LOCKED, "j1": 0.0, "j2": 0.0, "j3": 0.0, "j4": 0.0, "j5": 0.0,
                  "j6": 0.0, **dict(zip(robot.joint_names, q, strict=True))}
        np.testing.assert_allclose(robot.fk(q), full_model_fk(GRIPPER, tip, values), atol=1e-12)


def test_continuous_and_mimic_fk_equal_full_model_fk(continuous, mimic):
    """Continuous joints (angle -> Pinocchio's cos/sin) and mimic joints on the path (their
    relation typed in) give the full model's FK, with the side branches locked."""
    for q in random_q(continuous, 20, seed=2):
        values = {"fan_joint": 0.0, **dict(zip(continuous.joint_names, q, strict=True))}
        np.testing.assert_allclose(continuous.fk(q), full_model_fk(CONTINUOUS, "tool", values),
                                   atol=1e-12)
    for q in random_q(mimic, 20, seed=3):
        values = {**MIMIC_LOCKED, **mimic_values(q)}
        np.testing.assert_allclose(mimic.fk(q), full_model_fk(MIMIC, "tip", values), atol=1e-12)


# ---------------------------------------------------------------------------- continuous
def test_continuous_joints_are_one_unbounded_angle(continuous):
    """Three continuous joints: one angle each, limits ±inf, sampling box ±π."""
    assert continuous.nq == continuous.model.nq == continuous.model.nv == 5
    assert continuous.joint_names == ["turntable", "shoulder", "twist", "slide", "spindle"]
    assert continuous.locked == {"fan_joint": 0.0}
    unbounded = np.array([True, False, True, False, True])
    assert np.all(np.isinf(continuous.lower) == unbounded)
    assert np.all(np.isinf(continuous.upper) == unbounded)
    np.testing.assert_allclose(continuous.sampling_lower, [-np.pi, -1.5, -np.pi, -0.05, -np.pi])
    np.testing.assert_allclose(continuous.sampling_upper, [np.pi, 1.5, np.pi, 0.1, np.pi])
    assert continuous.within_limits([40.0, 0.0, -40.0, 0.0, 1e3])
    np.testing.assert_allclose(continuous.fk([2 * np.pi, 0.3, 0, 0, 0]),
                               continuous.fk([0, 0.3, 0, 0, 0]), atol=1e-12)


def test_with_limits_can_bound_a_continuous_joint(continuous):
    """with_limits on a continuous joint makes it bounded, and the sampling box follows."""
    bounded = continuous.with_limits(turntable=(-1.0, 2.0))
    assert bounded.sampling_lower[0] == -1.0 and bounded.sampling_upper[0] == 2.0
    assert np.isinf(continuous.lower[0])


# ---------------------------------------------------------------------------- mimic
def test_mimic_joints_on_the_path_are_not_coordinates(mimic):
    """mimic_arm: j3 and j5 follow j1 and j2, so q = (j1, j2, j4); five joint frames drawn."""
    assert mimic.nq == 3 and mimic.joint_names == ["j1", "j2", "j4"]
    assert mimic.joint_types == ["revolute", "revolute", "prismatic"]
    assert [j.name for j in mimic.chain] == ["j1", "j2", "j3", "j4", "j5"]
    j3 = mimic.chain[2]
    assert (j3.mimic, j3.index, j3.scaling, j3.offset) == (True, 0, -0.5, 0.2)
    assert mimic.locked == pytest.approx(MIMIC_LOCKED)
    assert mimic.joint_origins(np.zeros((2, 3))).shape == (2, 6, 3)
    assert mimic.jacobian(np.zeros(3)).shape == (6, 3)


@pytest.mark.parametrize("mimic_xml, match", [
    ('<mimic joint="nope"/>', "follows 'nope'.*not a movable joint"),
    ('<mimic joint="j2"/>', "follows 'j2', itself a mimic joint.*'j1'"),
])
def test_bad_mimic_raises_urdf_error(tmp_path, mimic_xml, match):
    """A mimic joint must follow an existing movable joint that is not a mimic itself."""
    joint = ('<joint name="{n}" type="revolute"><parent link="{p}"/><child link="{c}"/>'
             '<limit lower="-1" upper="1" effort="0" velocity="1"/>{m}</joint>')
    text = ('<robot name="r"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>'
            + joint.format(n="j1", p="a", c="b", m="")
            + joint.format(n="j2", p="b", c="c", m='<mimic joint="j1"/>')
            + joint.format(n="j3", p="c", c="d", m=mimic_xml) + "</robot>")
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(so.URDFError, match=match):
        so.Robot.from_urdf(path)


def test_mimic_leader_after_its_follower_on_the_path_is_refused(tmp_path):
    """Pinocchio needs the leader first: a clear URDFError; off the path the pair is locked."""
    joint = ('<joint name="{n}" type="revolute"><parent link="{p}"/><child link="{c}"/>'
             '<limit lower="-1" upper="1" effort="0" velocity="1"/>{m}</joint>')
    text = ('<robot name="r"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>'
            + joint.format(n="j1", p="a", c="b", m='<mimic joint="j3" multiplier="2"/>')
            + joint.format(n="j2", p="b", c="c", m="")
            + joint.format(n="j3", p="c", c="d", m="") + "</robot>")
    path = tmp_path / "late_leader.urdf"
    path.write_text(text)
    with pytest.raises(so.URDFError, match="'j1' follows 'j3', which comes after it.*leader "
                                           "joint before its mimic joint.*swap their roles"):
        so.Robot.from_urdf(path, tip="d")
    robot = so.Robot.from_urdf(path, tip="c")  # j3 off the path: j1 locked with it
    assert robot.joint_names == ["j2"] and robot.locked == {"j1": 0.0, "j3": 0.0}


def test_floating_joint_is_refused(tmp_path):
    """A floating joint is not a serial-chain joint: URDFError naming it and the remedy."""
    path = tmp_path / "f.urdf"
    path.write_text('<robot name="r"><link name="a"/><link name="b"/><joint name="free" '
                    'type="floating"><parent link="a"/><child link="b"/></joint></robot>')
    with pytest.raises(so.URDFError, match="'free' is 'floating'.*fixed"):
        so.Robot.from_urdf(path)


# ---------------------------------------------------------------------------- numerics
@pytest.mark.parametrize("name", ["gripper", "continuous", "mimic"])
def test_fk_batch_and_symbolic_fk_agree_with_fk(robots, name):
    """fk_batch (numpy) and symbolic_fk (casadi) equal Pinocchio's fk to 1e-12."""
    robot = robots[name]
    n = 200
    Q = random_q(robot, n, seed=4)
    T = np.array([robot.fk(q) for q in Q])
    np.testing.assert_allclose(robot.fk_batch(Q), T, atol=1e-12, rtol=0)
    P, R = robot.symbolic_fk.map(n)(Q.T)
    np.testing.assert_allclose(np.asarray(P).T, T[:, :3, 3], atol=1e-12, rtol=0)
    np.testing.assert_allclose(np.asarray(R).reshape(3, n, 3).transpose(1, 0, 2), T[:, :3, :3],
                               atol=1e-12, rtol=0)


@pytest.mark.parametrize("name", ["gripper", "continuous", "mimic"])
def test_jacobian_matches_finite_differences(robots, name):
    """Linear rows vs central differences of position, angular rows vs log of the rotation
    change (mimic joints: the chain rule is in the leader's column)."""
    robot = robots[name]
    h = 1e-6
    for q in random_q(robot, 10, seed=5):
        J = robot.jacobian(q)
        for k, e in enumerate(np.eye(robot.nq)):
            Tp, Tm = robot.fk(q + h * e), robot.fk(q - h * e)
            np.testing.assert_allclose(J[:3, k], (Tp[:3, 3] - Tm[:3, 3]) / (2 * h), atol=1e-8)
            omega = pin.log3(Tp[:3, :3] @ Tm[:3, :3].T) / (2 * h)
            np.testing.assert_allclose(J[3:, k], omega, atol=1e-8)


def test_symbolic_jacobian_honours_the_mimic_chain_rule(mimic):
    """casadi's derivative of symbolic_fk equals Pinocchio's linear Jacobian with mimic joints."""
    import casadi as ca

    q = ca.SX.sym("q", mimic.nq)
    jac = ca.Function("j", [q], [ca.jacobian(mimic.symbolic_fk(q)[0], q)])
    for qv in random_q(mimic, 10, seed=6):
        np.testing.assert_allclose(np.asarray(jac(qv)), mimic.jacobian(qv)[:3], atol=1e-12)


def test_reduced_robot_pickles(gripper, mimic):
    """A reduced robot pickles (for process pools) with its tip, locks and FK."""
    for robot in (gripper, mimic):
        back = pickle.loads(pickle.dumps(robot))
        assert (back.tip, back.joint_names, back.locked) == (robot.tip, robot.joint_names,
                                                             robot.locked)
        q = random_q(robot, 1, seed=7)[0]
        np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=1e-15)


# ---------------------------------------------------------------------------- meshes
def test_missing_meshes_give_one_warning_and_no_exception(caplog):
    """Meshes of an uninstalled package and a missing relative file: one warning, FK works."""
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        robot = so.Robot.from_urdf(MISSING_MESH)
    warnings = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 1
    assert "3 mesh file(s) cannot be found" in warnings[0].getMessage()
    np.testing.assert_allclose(robot.position([0.0, 0.0]), [0.3, 0.0, 0.1], atol=1e-12)


def test_found_meshes_give_no_warning(tmp_path, caplog):
    """A mesh file that exists next to the URDF is not reported."""
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "arm.stl").write_text("solid arm\nendsolid arm\n")
    text = MISSING_MESH.read_text().replace("package://not_installed_description/", "")
    for name in ("base.dae", "base.stl"):
        (tmp_path / "meshes" / name).write_text("")
    (tmp_path / "r.urdf").write_text(text)
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        so.Robot.from_urdf(tmp_path / "r.urdf")
    assert not [r for r in caplog.records if "mesh" in r.getMessage()]


# ---------------------------------------------------------------------------- IK
def test_fk_ik_round_trip_on_the_gripper_arm(gripper):
    """IPOPT finds a q reaching fk(q_true) (position and rotation) for random q_true."""
    for seed, q_true in enumerate(random_q(gripper, 5, seed=8)):
        T = gripper.fk(q_true)
        res = so.solve_ik(gripper, so.Target(T[:3, 3], rotation=T[:3, :3]), seed=seed)
        assert res.success, res.message
        np.testing.assert_allclose(gripper.fk(res.q), T, atol=1e-8)


def test_fk_ik_round_trip_with_mimic_joints_on_the_path(mimic):
    """IPOPT works in the independent coordinates; the mimic joints follow (position targets)."""
    for seed, q_true in enumerate(random_q(mimic, 4, seed=9)):
        res = so.solve_ik(mimic, mimic.position(q_true), seed=seed)
        assert res.success, res.message
        np.testing.assert_allclose(mimic.position(res.q), mimic.position(q_true), atol=1e-8)


def test_fk_ik_round_trip_with_continuous_joints(continuous):
    """IPOPT reaches fk(q_true) for unbounded angles (restarts drawn within ±π)."""
    for seed, q_true in enumerate(random_q(continuous, 4, seed=9)):
        res = so.solve_ik(continuous, continuous.position(q_true), seed=seed)
        assert res.success, res.message
        np.testing.assert_allclose(continuous.position(res.q), continuous.position(q_true),
                                   atol=1e-8)


def test_unreachable_target_with_continuous_joints_is_reported(continuous):
    """An unreachable target for a robot with continuous joints is a status, not a crash."""
    res = so.solve_ik(continuous, [5.0, 0.0, 0.0])
    assert res.status == "unreachable"


@pytest.fixture(scope="module")
def scara_wrist() -> so.Robot:
    return so.Robot.from_urdf(DATA / "scara_continuous_wrist.urdf", tip="tool")


@pytest.mark.parametrize("method, tol", [
    ("ipopt", 1e-9),
    ("analytic", 1e-9),
    ("pso", 1e-2),  # the wrist's range is the subject here, not the swarm's accuracy
])
def test_scara_with_a_continuous_wrist_solves_yaw_targets(scara_wrist, method, tol):
    """zavar2024 with an unbounded wrist: a yaw target 5 rad away from zero is solved."""
    assert np.isinf(scara_wrist.lower[3]) and scara_wrist.yaw_axis is not None
    q = np.array([0.3, 0.5, 0.01, 5.0])
    res = so.solve_ik(scara_wrist, so.Target(scara_wrist.position(q), yaw=scara_wrist.yaw(q)),
                      method=method, tol=tol)
    assert res.success, res.message


def test_closed_form_with_a_continuous_shoulder_and_wrist(tmp_path):
    """Unbounded shoulder and wrist: every closed-form route searches one turn, never inf."""
    text = (DATA / "scara_continuous_wrist.urdf").read_text()
    urdf = tmp_path / "scara_continuous.urdf"
    urdf.write_text(text.replace('<joint name="theta1" type="revolute">',
                                 '<joint name="theta1" type="continuous">'))
    robot = so.Robot.from_urdf(urdf, tip="tool")
    assert np.isinf(robot.lower[[0, 3]]).all()
    q = np.array([2.9, 0.5, 0.01, -3.0])
    target = so.Target(robot.position(q), yaw=robot.yaw(q))
    branches = so.ik_all(robot, target)
    assert len(branches) == 2  # elbow up and down, each angle within one turn
    for branch in branches:
        assert branch.success and np.all(np.abs(branch.q[[0, 3]]) <= np.pi + 1e-12)
    for method in ("analytic", "auto"):
        assert so.solve_ik(robot, target, method=method).success
    Q, valid = solve_batch(robot, target.position[None], yaws=[target.yaw])
    assert valid.all() and np.isfinite(Q).all()
    np.testing.assert_allclose(robot.positions(Q[0]), np.tile(target.position, (2, 1)),
                               atol=1e-12)


def test_workspace_of_a_robot_with_continuous_joints(scara_wrist):
    """The Monte Carlo workspace draws continuous joints within one turn."""
    from scara_opt.workspace_analysis import workspace

    assert workspace(scara_wrist, n=2000, seed=0).xy_area > 0


# ---------------------------------------------------------------------------- example-robot-data
def _example_robot(relative: str, tip: str) -> so.Robot:
    """A robot of the optional example-robot-data package, or skip naming the extra."""
    try:
        path = example_robot_data_urdf(relative)
    except ModuleNotFoundError:
        pytest.skip(f"example-robot-data is not installed: {ROBOTS_EXTRA}")
    return so.Robot.from_urdf(path, tip=tip)


@pytest.mark.parametrize("relative, tip, names, locked", [
    ("ur_description/urdf/ur5_robot.urdf", "tool0",
     ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
      "wrist_2_joint", "wrist_3_joint"], {}),
    ("panda_description/urdf/panda.urdf", "panda_hand_tcp",
     [f"panda_joint{k}" for k in range(1, 8)],
     {"panda_finger_joint1": 0.0, "panda_finger_joint2": 0.0}),
])
def test_example_robot_data_fk_ik_round_trip(relative, tip, names, locked):
    """UR5 and Panda (fingers locked) load as they ship, and IPOPT round-trips FK∘IK."""
    robot = _example_robot(relative, tip)
    assert robot.joint_names == names and robot.locked == locked
    Q = random_q(robot, 5, seed=10)
    np.testing.assert_allclose(robot.fk_batch(Q), [robot.fk(q) for q in Q], atol=1e-12)
    for seed, q_true in enumerate(Q):
        T = robot.fk(q_true)
        res = so.solve_ik(robot, so.Target(T[:3, 3], rotation=T[:3, :3]), seed=seed)
        assert res.success, res.message
        np.testing.assert_allclose(robot.fk(res.q), T, atol=1e-8)
