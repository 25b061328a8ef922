"""Robot: FK against the papers' closed forms, batches, Jacobians, limits and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import scara_opt as so
from tests.conftest import BUNDLED, DATA, IN, ROOT, paper_fk, random_q


@pytest.mark.parametrize("name", BUNDLED)
def test_fk_equals_the_papers_closed_form(robots, name):
    """Pinocchio FK of each bundled robot equals its paper's closed-form FK on 200 random q."""
    robot = robots[name]
    for q in random_q(robot, 200, seed=1):
        p, R = paper_fk(name, q)
        T = robot.fk(q)
        np.testing.assert_allclose(T[:3, 3], p, atol=1e-12)
        np.testing.assert_allclose(T[:3, :3], R, atol=1e-12)


def test_inverted5_reference_pose(robots):
    """inverted5 Fig. 3: q = (0, 0, 0, 0, 3.94 in) puts the tip at (7.87, 0, -3.94) in."""
    p = robots["inverted5"].position([0, 0, 0, 0, 3.94 * IN]) / IN
    np.testing.assert_allclose(p, [7.87, 0.0, -3.94], atol=1e-9)


def test_peng2025_height_at_zero(robots):
    """peng2025 eq. 4.6: at zero joints z = 172 mm (62 + 70 + 40), x = 540 mm."""
    p = robots["peng2025"].position(np.zeros(4)) * 1000
    np.testing.assert_allclose(p, [540.0, 0.0, 172.0], atol=1e-9)


@pytest.mark.parametrize("name", BUNDLED + ["arm6"])
def test_fk_batch_matches_pinocchio(robots, arm6, name):
    """fk_batch (numpy walk of the model) equals Pinocchio's fk on 500 random q."""
    robot = arm6 if name == "arm6" else robots[name]
    Q = random_q(robot, 500, seed=2)
    expected = np.array([robot.fk(q) for q in Q])
    np.testing.assert_allclose(robot.fk_batch(Q), expected, atol=1e-12)
    np.testing.assert_allclose(robot.positions(Q), expected[:, :3, 3], atol=1e-12)


@pytest.mark.parametrize("name", BUNDLED + ["arm6"])
def test_jacobian_matches_finite_differences(robots, arm6, name):
    """The world-aligned tip Jacobian's linear rows match central differences of position."""
    robot = arm6 if name == "arm6" else robots[name]
    h = 1e-6
    for q in random_q(robot, 20, seed=3):
        J = robot.jacobian(q)
        assert J.shape == (6, robot.nq)
        fd = np.column_stack([(robot.position(q + h * e) - robot.position(q - h * e)) / (2 * h)
                              for e in np.eye(robot.nq)])
        np.testing.assert_allclose(J[:3], fd, atol=1e-8)


def test_jacobian_angular_rows_follow_yaw(robots):
    """For a SCARA the angular rows are the yaw axis on each revolute joint, zero on prismatic."""
    robot = robots["zavar2024"]
    J = robot.jacobian([0.3, -0.4, 0.01, 0.5])
    np.testing.assert_allclose(J[3:], [[0, 0, 0, 0], [0, 0, 0, 0], [1, 1, 0, 1]], atol=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)  # the same examples every run
@given(st.lists(st.floats(-1e3, 1e3), min_size=4, max_size=4))
def test_fk_is_defined_for_any_finite_q(q):
    """FK accepts finite q outside the limits (limits are within_limits' business)."""
    robot = so.load_robot("zavar2024")
    T = robot.fk(q)
    assert np.isfinite(T).all()
    np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-9)


def test_within_limits(robots):
    """within_limits is true inside, false outside, and works on batches."""
    robot = robots["zavar2024"]
    assert robot.within_limits([0, 0, 0.01, 0])
    assert not robot.within_limits([0, 0, 0.05, 0])  # d3 stroke is [0, 0.048] m
    Q = np.array([[0, 0, 0.01, 0], [3.0, 0, 0.01, 0]])
    assert robot.within_limits(Q).tolist() == [True, False]


def test_limits_and_properties_of_zavar2024(robots):
    """zavar2024 Table 1: theta in +-120 deg, d3 in [0, 0.048] m; velocity/acceleration given."""
    robot = robots["zavar2024"]
    assert robot.nq == 4 and robot.joint_types == ["revolute", "revolute", "prismatic", "revolute"]
    np.testing.assert_allclose(robot.lower, np.radians([-120, -120, 0, -120]) * [1, 1, 0, 1])
    np.testing.assert_allclose(robot.upper[2], 0.048)
    assert np.all(robot.velocity_limit > 0) and np.all(np.isfinite(robot.acceleration_limit))


@pytest.mark.parametrize(("name", "lower", "upper"), [
    # zavar2024 Table 1: theta +-120 deg, d3 0-48 mm
    ("zavar2024", [-120, -120, 0, -120], [120, 120, 48, 120]),
    # peng2025 Sec. 2: J0 stroke 0-40 mm, J1 +-90 deg, J2 +-164 deg, J3 +-360 deg
    ("peng2025", [0, -90, -164, -360], [40, 90, 164, 360]),
    # fang Sec. 2: J1 +-120 deg, J2 +-150 deg, J3 about +-48 mm, J4 +-360 deg
    ("fang", [-120, -150, -48, -360], [120, 150, 48, 360]),
])
def test_joint_limits_are_the_papers(robots, name, lower, upper):
    """The bundled limits are the papers' (ROBOTS.md), in degrees and millimetres here."""
    robot = robots[name]
    scale = np.where(np.array(robot.joint_types) == "revolute", 180 / np.pi, 1000.0)
    np.testing.assert_allclose(robot.lower * scale, lower, atol=1e-9)
    np.testing.assert_allclose(robot.upper * scale, upper, atol=1e-9)


def test_yaw_axis_and_tool_angle(robots, arm6):
    """SCARAs turn about +z, nguyen's tool about -y (A = theta2+theta3+theta5); arm6 has none."""
    np.testing.assert_allclose(robots["zavar2024"].yaw_axis, [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(robots["nguyen"].yaw_axis, [0, -1, 0], atol=1e-12)
    q = [0.1, 0.4, -0.3, 0.05, 1.0]
    assert robots["nguyen"].yaw(q) == pytest.approx(0.4 - 0.3 + 1.0)
    assert robots["zavar2024"].yaw([0.5, 0.6, 0.01, -0.2]) == pytest.approx(0.9)
    assert arm6.yaw_axis is None
    with pytest.raises(so.TargetError, match="rotation="):
        arm6.yaw(np.zeros(6))


# ---------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("q, match", [
    ([0, 0, 0], r"shape \(4,\)"),
    ([[0, 0, 0, 0]], r"shape \(4,\)"),
    ([0, np.nan, 0, 0], "non-finite.*theta2"),
    ([0, 0, np.inf, 0], "non-finite.*d3"),
    (["a", 0, 0, 0], "numeric"),
])
def test_bad_q_raises_input_error(robots, q, match):
    """A q of the wrong length, NaN, inf or non-numeric raises InputError naming the problem."""
    with pytest.raises(so.InputError, match=match):
        robots["zavar2024"].fk(q)


def test_bad_batch_raises_input_error(robots):
    """fk_batch refuses a (n, wrong) array and NaN rows, naming the rows."""
    robot = robots["zavar2024"]
    with pytest.raises(so.InputError, match=r"shape \(n, 4\)"):
        robot.fk_batch(np.zeros((3, 5)))
    Q = np.zeros((3, 4))
    Q[1, 0] = np.nan
    with pytest.raises(so.InputError, match=r"rows \[1\]"):
        robot.fk_batch(Q)


def test_missing_file_and_unknown_robot():
    """A missing URDF is a URDFError; an unknown robot name lists the bundled ones."""
    with pytest.raises(so.URDFError, match="does not exist"):
        so.Robot.from_urdf("/nonexistent/robot.urdf")
    with pytest.raises(so.RobotNotFoundError, match="zavar2024"):
        so.load_robot("no_such_robot")


def test_a_path_too_long_is_a_urdf_error_not_an_os_error():
    """load_robot('a' * 5000) raised OSError [Errno 36]: now a URDFError that says why, in
    short, and lists the bundled robots; Robot.from_urdf likewise.

    Mutation caught: ``path.stat()``'s OSError not caught in load_robot -> OSError; fails.
    """
    with pytest.raises(so.URDFError, match=r"'a{56}\.\.\. \(5,000 characters\) cannot be "
                                           r"looked up: File name too long; .*zavar2024"):
        so.load_robot("a" * 5000)
    with pytest.raises(so.URDFError, match="cannot be read: File name too long"):
        so.Robot.from_urdf("a" * 5000 + ".urdf")


def test_urdfdom_says_nothing_on_stderr_and_its_words_reach_the_error(capfd):
    """A joint origin of 4 numbers: urdfdom's C++ ``Error:`` lines went to the process's
    stderr before the clean exception; now stderr stays empty and the URDFError carries
    urdfdom's reasons (the one line the command line prints).

    Mutation caught: ``urdfdom_messages`` a no-op -> the lines on fd 2; fails.
    """
    text = (ROOT / "robots" / "zavar2024.urdf").read_text()
    joint_origin = '<child link="link1"/>\n    <origin xyz="0.0 0.0 0.0" rpy="0.0 -0.0 0.0"/>'
    bad = text.replace(joint_origin, '<child link="link1"/><origin xyz="1 2 3 4"/>', 1)
    assert bad != text
    capfd.readouterr()
    with pytest.raises(so.URDFError, match=r"\(urdfdom: Parser found 4 elements but 3 "
                                           r"expected while parsing vector \[1 2 3 4\]; "
                                           r"Malformed parent origin element"):
        so.Robot(bad, "tool")
    assert capfd.readouterr().err == ""


def _write(tmp_path, text):
    path = tmp_path / "r.urdf"
    path.write_text(text)
    return path


LINK = '<link name="{}"/>'
JOINT = ('<joint name="{n}" type="{t}"><parent link="{p}"/><child link="{c}"/>'
         '<axis xyz="0 0 1"/><limit lower="{lo}" upper="{hi}" effort="0" velocity="1"/></joint>')


def _urdf(links, joints):
    body = "".join(LINK.format(name) for name in links)
    for n, t, p, c, *lim in joints:
        lo, hi = lim if lim else (-1, 1)
        body += JOINT.format(n=n, t=t, p=p, c=c, lo=lo, hi=hi)
    return f'<robot name="r">{body}</robot>'


def test_malformed_xml_raises_urdf_error(tmp_path):
    """Broken XML fails with the parser's line/column before Pinocchio sees it."""
    with pytest.raises(so.URDFError, match="not well-formed XML.*line 1"):
        so.Robot.from_urdf(_write(tmp_path, '<robot name="x"><link name='))
    with pytest.raises(so.URDFError, match="<robot>"):
        so.Robot.from_urdf(_write(tmp_path, "<notrobot/>"))


def test_branching_tree_keeps_the_path_to_the_tip(tmp_path):
    """A tree loads: tip=None takes the longest chain, a named tip locks the other branch."""
    text = _urdf(["b", "l1", "l2", "l3"], [("j1", "revolute", "b", "l1"),
                                            ("j2", "revolute", "l1", "l2"),
                                            ("j3", "revolute", "l1", "l3")])
    assert so.Robot.from_urdf(_write(tmp_path, text)).tip == "l2"  # first of two as long
    robot = so.Robot.from_urdf(_write(tmp_path, text), tip="l3")
    assert robot.joint_names == ["j1", "j3"] and robot.locked == {"j2": 0.0}


def test_unknown_tip_lists_the_frames(tmp_path):
    """A tip that is not a link (no path to it) raises FrameNotFoundError listing the links."""
    text = _urdf(["b", "l1"], [("j1", "revolute", "b", "l1")])
    with pytest.raises(so.FrameNotFoundError, match="'tool'.*frames that exist: b, l1"):
        so.Robot.from_urdf(_write(tmp_path, text), tip="tool")


R = "revolute"


@pytest.mark.parametrize("links, joints, match", [
    (["a", "b", "c"], [("j1", R, "a", "b"), ("j2", R, "b", "c"), ("j3", R, "c", "b")],
     r"joints 'j3', 'j2' form a cycle \(c -> b -> c\)"),
    (["a", "b", "c"], [("j1", R, "a", "b"), ("j2", R, "a", "c"), ("j3", R, "b", "c")],
     "link 'c' is the child of two joints, 'j2' and 'j3'.*at most one parent joint"),
    (["a", "b"], [("j1", R, "a", "b"), ("j2", R, "b", "zz")],
     "joint 'j2' has child link 'zz', which is not declared; add <link name=\"zz\"/>"),
    (["a", "b"], [("j1", R, "a", "b"), ("j2", R, "zz", "b")],
     "joint 'j2' has parent link 'zz', which is not declared"),
    (["a", "b", "c"], [("j1", R, "a", "b"), ("j1", R, "b", "c")],
     "joint name.*'j1' are used more than once"),
    (["a", "b", "b"], [("j1", R, "a", "b")], "link name.*'b' are used more than once"),
])
@pytest.mark.parametrize("tip", [None, "b"])
def test_broken_trees_raise_urdf_error(tmp_path, links, joints, match, tip):
    """Cycles, two parents, undeclared links and duplicate names fail before Pinocchio."""
    with pytest.raises(so.URDFError, match=match):  # the cycle with a tip used to hang
        so.Robot.from_urdf(_write(tmp_path, _urdf(links, joints)), tip=tip)


def test_non_utf8_file_raises_urdf_error(tmp_path):
    """Binary junk is a URDFError, not a bare UnicodeDecodeError."""
    path = tmp_path / "junk.urdf"
    path.write_bytes(b"\xff\xfe\x00bad")
    with pytest.raises(so.URDFError, match="'.*junk.urdf' is not UTF-8 text.*URDF"):
        so.Robot.from_urdf(path)


def test_inverted_urdf_limits_and_unsupported_joints(tmp_path):
    """lower >= upper is a JointLimitError; a floating joint is refused with a remedy."""
    text = _urdf(["b", "l1"], [("j1", "revolute", "b", "l1", 1, -1)])
    with pytest.raises(so.JointLimitError, match="'j1'.*swap"):
        so.Robot.from_urdf(_write(tmp_path, text))
    text = _urdf(["b", "l1"], [("j1", "floating", "b", "l1")])
    with pytest.raises(so.URDFError, match="'j1' is 'floating'.*fixed"):
        so.Robot.from_urdf(_write(tmp_path, text))


def test_urdf_with_only_fixed_joints_is_refused(tmp_path):
    """A URDF without a movable joint cannot be a robot: URDFError."""
    text = '<robot name="r"><link name="a"/><link name="b"/><joint name="f" type="fixed">' \
           '<parent link="a"/><child link="b"/></joint></robot>'
    with pytest.raises(so.URDFError, match="no movable joint"):
        so.Robot.from_urdf(_write(tmp_path, text))


def test_general_arm_loads_with_its_tip(arm6):
    """A 6-joint arm with rotated origins loads; its tip defaults to the last link."""
    assert arm6.nq == 6 and arm6.tip == "tool0"
    assert arm6.joint_types.count("prismatic") == 1
    assert np.isinf(arm6.acceleration_limit).all()  # URDF carries none
    assert so.Robot.from_urdf(DATA / "arm6.urdf", tip="wrist3").tip == "wrist3"


@pytest.mark.parametrize("axis, match", [
    ("0 0 0", "joint 'j1' has a zero-length axis.*give a unit axis"),
    ("nan 0 1", "joint 'j1' has axis.*not three finite numbers; give a unit axis"),
    ("0 inf 0", "joint 'j1' has axis.*not three finite numbers"),
    ("1 0", "joint 'j1' has axis.*not three finite numbers"),
])
@pytest.mark.parametrize("kind", ["revolute", "prismatic", "continuous"])
def test_zero_or_non_finite_axis_raises_urdf_error(tmp_path, axis, match, kind):
    """A movable joint's axis of 0 0 0 (FK would not be a rotation) or NaN/inf is refused."""
    text = _urdf(["b", "l1"], [("j1", kind, "b", "l1")]).replace('"0 0 1"', f'"{axis}"')
    with pytest.raises(so.URDFError, match=match):
        so.Robot.from_urdf(_write(tmp_path, text))


def test_non_unit_axis_is_normalised(tmp_path):
    """A non-zero axis of any length is a direction (URDF parsers normalise it)."""
    text = _urdf(["b", "l1"], [("j1", "revolute", "b", "l1")]).replace('"0 0 1"', '"0 0 2"')
    robot = so.Robot.from_urdf(_write(tmp_path, text))
    np.testing.assert_allclose(robot.chain[0].axis, [0, 0, 1])
    np.testing.assert_allclose(robot.fk([0.5])[:3, :3] @ robot.fk([0.5])[:3, :3].T, np.eye(3),
                               atol=1e-12)


# ---------------------------------------------------------------------- the robot-file extensions
ZAVAR_URDF = (DATA.parent.parent / "robots" / "zavar2024.urdf").read_text()
THETA1_ACC = '<scara_opt acceleration="12.566370614359172"/>'


@pytest.mark.parametrize("value", ["abc", "", "nan", "-5", "0", "inf", "-inf", "1e400"])
def test_bad_acceleration_element_raises_urdf_error_naming_joint_and_value(value):
    """<scara_opt acceleration=...> must be a finite number > 0; the message names both.

    Mutation: the value read with a bare float() (abc -> ValueError; NaN, -5, 0, inf loaded
    silently) -> fails.
    """
    text = ZAVAR_URDF.replace(THETA1_ACC, f'<scara_opt acceleration="{value}"/>', 1)
    with pytest.raises(so.URDFError, match=f"joint 'theta1' has <scara_opt acceleration=\"{value}\""
                                           r"/>; the acceleration limit must be a finite number"):
        so.Robot(text, "tool")


@pytest.mark.parametrize("old, new, match", [
    (THETA1_ACC, THETA1_ACC * 2, "joint 'theta1' has more than one <scara_opt/>"),
    (THETA1_ACC, '<scara_opt accel="12.5"/>', r"<scara_opt accel=\"12.5\"/>; the element takes "
                                              "acceleration only"),
    (THETA1_ACC, "<scara_opt/>", "takes acceleration only"),
    ('<origin xyz="0.0 0.0 -0.05" rpy="0.0 -0.0 0.0"/>',
     '<origin xyz="0 0 -0.05"/><scara_opt acceleration="2"/>', "on a fixed joint"),
    ('<link name="base_link"/>', '<link name="base_link"><scara_opt acceleration="2"/></link>',
     "outside any <joint>"),
])
def test_misplaced_or_misspelt_acceleration_elements_raise_urdf_error(old, new, match):
    """A second element, an unknown attribute, one on a fixed joint or outside a joint.

    Each was silently ignored (a misspelt attribute left the joint without its limit).
    Mutation: _accelerations reads only the first element of each joint, as before -> fails.
    """
    text = ZAVAR_URDF.replace(old, new, 1)
    with pytest.raises(so.URDFError, match=match):
        so.Robot(text, "tool")


def test_valid_acceleration_elements_are_read():
    """The bundled values come through; a joint without the element has no limit (inf)."""
    robot = so.Robot(ZAVAR_URDF.replace(THETA1_ACC, "", 1), "tool")
    np.testing.assert_allclose(robot.acceleration_limit,
                               [np.inf, 4 * np.pi, 2.0, 8 * np.pi])


@pytest.mark.parametrize("key, value", [("velocity", "nan"), ("velocity", "inf"),
                                        ("velocity", "-1.5"), ("effort", "nan")])
def test_bad_urdf_velocity_or_effort_names_the_joint(key, value):
    """<limit velocity/effort> must be finite and >= 0: the message names joint and value.

    Mutation: the check removed (Pinocchio's message names neither) -> fails.
    """
    old = f'{key}="3.141592653589793"' if key == "velocity" else 'effort="50.0"'
    text = ZAVAR_URDF.replace(old, f'{key}="{value}"', 1)
    with pytest.raises(so.URDFError, match=f"joint 'theta1' has <limit {key}=\"{value}\">"):
        so.Robot(text, "tool")


def test_a_range_whose_width_overflows_is_refused():
    """lower = -1e308, upper = 1e308: samplers would draw from an infinite width.

    Mutation: the width check removed -> fails (the robot loads).
    """
    text = ZAVAR_URDF.replace('lower="-2.0943951023931953" upper="2.0943951023931953"',
                              'lower="-1e308" upper="1e308"', 1)
    with pytest.raises(so.JointLimitError, match="width overflows"):
        so.Robot(text, "tool")


@pytest.mark.parametrize("call", [
    lambda: so.Robot.from_urdf(None), lambda: so.Robot.from_urdf(3),
    lambda: so.load_robot(None), lambda: so.load_robot(["zavar2024"]),
    lambda: so.Robot(None), lambda: so.load_robot("zavar2024", tip=[]),
    lambda: so.Robot.from_urdf(DATA / "arm6.urdf", tip=5)])
def test_loaders_refuse_arguments_of_the_wrong_type(call):
    """None, numbers and lists as a path, name, URDF text or tip are InputErrors.

    Mutation: load_robot/from_urdf/Robot without their type checks (TypeError from
    pathlib, or tip=[] silently taken as the default) -> fails.
    """
    with pytest.raises(so.InputError, match="must be"):
        call()


@pytest.mark.parametrize("tol", [None, "0.1", math.nan, -1.0, [0.1]])
def test_within_limits_checks_its_tolerance(robots, tol):
    """tol is a finite number >= 0 [rad or m].

    Mutation: the tol check removed (TypeError, or NaN answering False everywhere) -> fails.
    """
    with pytest.raises(so.InputError, match="tol must be"):
        robots["zavar2024"].within_limits(np.zeros(4), tol)


@pytest.mark.parametrize("value", [(True, 2.0), ("-1", "1"), (-1e308, 1e308), (0.0, 10**400),
                                   "ab", 1.0])
def test_with_limits_refuses_bools_strings_and_overflowing_ranges(robots, value):
    """A range is two numbers with lower < upper and a finite width.

    Mutation: the pair read with float(v) as before (True -> 1, "-1" -> -1.0 accepted,
    10**400 -> OverflowError) -> fails.
    """
    with pytest.raises(so.JointLimitError, match="theta1"):
        robots["zavar2024"].with_limits(theta1=value)


def test_check_q_refuses_numeric_strings(robots):
    """q = ["0", "0", "0", "0"] is not parsed as numbers.

    Mutation: check_q converts with np.asarray(q, dtype=float) -> fails.
    """
    with pytest.raises(so.InputError, match="must be numeric"):
        robots["zavar2024"].fk(["0", "0", "0", "0"])


def test_with_limits_returns_an_independent_robot():
    """Two with_limits copies are two robots, and unpickling the original gives its limits.

    Found while fuzzing: a is b, and pickle.loads(pickle.dumps(so.load_robot(name))) came
    back with the limits of the last with_limits copy (so process-pool workers could solve
    with wrong limits). Mutation caught: with_limits built with copy.copy (through
    __reduce__ and the per-process rebuilt robot) -> a is b.
    """
    import pickle

    base = so.Robot.from_urdf(DATA / "continuous_arm.urdf")
    a = base.with_limits(**{base.joint_names[0]: (-1.0, 1.0)})
    b = base.with_limits(**{base.joint_names[0]: (-0.5, 0.5)})
    assert a is not b and a.lower[0] == -1.0
    again = pickle.loads(pickle.dumps(base))
    np.testing.assert_array_equal(again.lower, base.lower)
