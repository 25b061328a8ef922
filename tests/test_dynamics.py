"""Torque-limited timing: inertial data, Pinocchio's RNEA in toppra, payloads, bad input.

The references are independent of the code under test: hand-computed bang-bang minimum
times of a single body under a torque (force) limit, a payload compared with the same mass
written into the URDF, and a hand-computed merged body of a locked joint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.model.dh_file import load_dh
from scara_opt.trajectory.dynamics import RobotDynamics

G = 9.81
BIG = 1e3  # vmax, amax that never bind [rad/s, rad/s² or m/s, m/s²]


def link_urdf(mass: float = 2.0, r: float = 0.5, effort: float = 4.0, extra: str = "") -> str:
    """One revolute joint about the vertical z axis, a point mass ``mass`` at ``r`` on x."""
    return f"""<robot name="pendulum"><link name="base"/>
<link name="arm"><inertial><origin xyz="{r} 0 0"/><mass value="{mass}"/>
<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
<link name="tip"/>{extra}
<joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="{effort}" velocity="100"/></joint>
<joint name="t" type="fixed"><parent link="arm"/><child link="tip"/>
<origin xyz="{r} 0 0"/></joint></robot>"""


def lift_urdf(mass: float = 2.0, effort: float = 40.0) -> str:
    """One prismatic joint along +z (against gravity) moving a body of ``mass``."""
    return f"""<robot name="lift"><link name="base"/>
<link name="slide"><inertial><origin xyz="0 0 0"/><mass value="{mass}"/>
<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="z" type="prismatic"><parent link="base"/><child link="slide"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="{effort}" velocity="100"/></joint></robot>"""


def test_single_link_point_mass_matches_the_bang_bang_minimum_time():
    """A point mass m at r on a vertical axis, torque limit τ: T = 2 sqrt(Δθ m r² / τ) (1 %).

    Reference: full torque to the midpoint, full reverse torque to rest (gravity is along the
    axis, so it needs no torque). Measured: 0.25 % above (toppra's 0.5 % safety margin).
    Mutation: the JointTorqueConstraint not added in _solve -> fails (0.09 s, vmax/amax only).
    """
    robot = so.Robot(link_urdf(mass=2.0, r=0.5, effort=4.0), "tip")
    for dtheta in (0.5, 2.0):
        traj = so.time_parameterize([[-dtheta / 2], [dtheta / 2]], robot, vmax=BIG, amax=BIG,
                                    torque_limits=True)
        expected = 2.0 * math.sqrt(dtheta * 2.0 * 0.5**2 / 4.0)
        assert traj.duration == pytest.approx(expected, rel=0.01)
        assert traj.duration >= expected * (1 - 1e-6)
        ratio = traj.check_limits()["torque"]
        assert ratio.max() <= 1.0 + 1e-9 and ratio.max() > 0.99


def test_vertical_lift_matches_the_asymmetric_bang_bang_with_gravity():
    """A mass lifted against gravity by a force F: up at F/m - g, braked at F/m + g (1 %).

    v = sqrt(2 D a1 a2 / (a1 + a2)), T = v / a1 + v / a2: 0.2296 s for 0.2 m, 2 kg, 40 N
    (0.2000 s if gravity were forgotten).
    Mutation: RobotDynamics with model.gravity set to zero -> fails.
    """
    robot = so.Robot(lift_urdf(mass=2.0, effort=40.0), "slide")
    D, m, F = 0.2, 2.0, 40.0
    a1, a2 = F / m - G, F / m + G
    v = math.sqrt(2 * D * a1 * a2 / (a1 + a2))
    for path in ([[0.0], [D]], [[D], [0.0]]):  # up, and down (a1 and a2 swap roles)
        traj = so.time_parameterize(path, robot, vmax=BIG, amax=BIG, torque_limits=True)
        assert traj.duration == pytest.approx(v / a1 + v / a2, rel=0.01)
        assert traj.check_limits()["torque"].max() <= 1.0 + 1e-9


def test_payload_at_the_tip_equals_the_same_mass_written_in_the_urdf():
    """RNEA with payload=(m, com) at the tip = RNEA of a URDF with that body at the tip.

    Mutation: the payload appended at the joint origin (placement identity) -> fails.
    """
    body = ('<link name="load"><inertial><origin xyz="0.05 0.02 0"/><mass value="1.5"/>'
            '<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.003"/>'
            '</inertial></link><joint name="l" type="fixed"><parent link="tip"/>'
            '<child link="load"/></joint>')
    bare = RobotDynamics(so.Robot(link_urdf(), "tip"), payload=(
        1.5, [0.05, 0.02, 0.0], np.diag([0.001, 0.002, 0.003])))
    built = RobotDynamics(so.Robot(link_urdf(extra=body), "tip"))
    rng = np.random.default_rng(3)
    for q, v, a in rng.uniform(-2, 2, (20, 3, 1)):
        np.testing.assert_allclose(bare.rnea(q, v, a), built.rnea(q, v, a), rtol=1e-12)


def test_payload_point_mass_at_the_tip_adds_m_r_squared():
    """Payload 1 kg at the tip (r = 0.5 m): inertia 0.5 + 0.25 kg·m², T = 2 sqrt(Δθ I / τ)."""
    robot = so.Robot(link_urdf(mass=2.0, r=0.5, effort=4.0), "tip")
    traj = so.time_parameterize([[-1.0], [1.0]], robot, vmax=BIG, amax=BIG, payload=1.0)
    assert traj.duration == pytest.approx(2 * math.sqrt(2.0 * 0.75 / 4.0), rel=0.01)
    assert "payload 1 kg" in traj.notes


def test_payload_never_makes_a_move_faster():
    """fang's Table 2 move and a 5-point path, torque-bound: heavier is never faster.

    With the assumed rate limits lifted (vmax = amax = 1e3) the torques bind, so each added
    kilogram makes the move strictly slower; every result stays within its torque limits.
    Mutation: the payload's appendBodyToJoint skipped -> fails (equal durations).
    """
    robot = so.load_robot("fang")
    units = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])
    a, b = np.array([0.0, 0.0, 0.0, -15.0]), np.array([-64.4042, 128.8085, 15.15, -61.4099])
    paths = [np.array([a, b]) * units,
             np.array([a + (b - a) * s + [0, 0, 20 * math.sin(math.pi * s), 0]
                       for s in np.linspace(0, 1, 5)]) * units]
    for path in paths:
        durations = []
        for mass in (0.0, 0.5, 1.0, 2.0, 3.0):
            traj = so.time_parameterize(path, robot, vmax=BIG, amax=BIG,
                                        payload=(mass, [0.02, 0, -0.03]))
            assert traj.check_limits()["torque"].max() <= 1.0 + 1e-9
            durations.append(traj.duration)
        assert np.all(np.diff(durations) > 0), durations


def test_torque_excess_between_grid_points_is_removed_by_a_time_stretch():
    """No margin, a coarse grid: the 1 kHz check finds the excess and time is stretched.

    Mutation: stretch_factor returns 1.0 -> fails (no stretch); without its STRETCH_SLACK ->
    fails (1 + 3e-10 at the moved samples).
    """
    robot = so.load_robot("fang")
    path = np.array([[0.0, 0.0, 0.0, -0.26], [-0.6, 1.1, 0.02, -0.6], [-1.12, 2.25, 0.015, -1.07]])
    traj = so.time_parameterize(path, robot, vmax=BIG, amax=BIG, payload=2.0, margin=0.0,
                                min_grid=6, grid_per_segment=1, max_refine=0)
    assert "stretching time" in traj.notes
    assert traj.check_limits()["torque"].max() <= 1.0


def test_torque_limited_timing_is_never_faster_than_without():
    """Adding the torque constraint can only slow a move (same velocity/acceleration limits)."""
    robot = so.load_robot("zavar2024")
    path = [[0.0, 0.0, 0.0, 0.0], [1.5, -1.8, 0.04, 1.0], [-0.5, 1.2, 0.01, -1.0]]
    free = so.time_parameterize(path, robot)
    held = so.time_parameterize(path, robot, torque_limits=True, payload=2.0)
    assert held.duration >= free.duration * (1 - 1e-9)
    assert "torque" not in free.check_limits()


def test_check_torque_of_an_acceleration_limited_move_matches_i_times_amax():
    """A vel/acc-limited move's worst torque is I × peak acceleration (I = m r²), on request.

    Mutation: ratios() divides by the limit squared -> fails.
    """
    robot = so.Robot(link_urdf(mass=2.0, r=0.5, effort=4.0), "tip")
    traj = so.time_parameterize([[-1.0], [1.0]], robot, vmax=BIG, amax=3.0)
    assert "torque" not in traj.check_limits()
    peak = traj.peaks()["acceleration"][0]  # 3 x (1 - margin): exact, from the polynomials
    assert traj.check_torque(robot)[0] == pytest.approx(0.5 * peak / 4.0, rel=1e-6)
    assert traj.check_torque(robot, torque_limits=1.0)[0] == pytest.approx(0.5 * peak, rel=1e-6)


def test_inertias_of_locked_and_fixed_links_are_merged():
    """A locked side link (held at 1 rad) and a fixed tip link merge into their parent bodies.

    Hand-computed: joint j1 carries 2 kg at (0.1, 0) and 3 kg locked at
    (0.2 - 0.1 sin 1, 0.1 cos 1): 5 kg at their mass-weighted mean.
    """
    urdf = """<robot name="t"><link name="base"/>
<link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
<link name="l2"><inertial><origin xyz="0.05 0 0"/><mass value="1"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.003"/></inertial></link>
<link name="tipl"><inertial><origin xyz="0 0 0"/><mass value="0.5"/>
<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
<link name="side"><inertial><origin xyz="0 0.1 0"/><mass value="3"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.2 0 0"/>
<axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="5" velocity="1"/></joint>
<joint name="fx" type="fixed"><parent link="l2"/><child link="tipl"/><origin xyz="0.1 0 0"/>
</joint><joint name="js" type="revolute"><parent link="l1"/><child link="side"/>
<origin xyz="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="0.5" upper="1.5" effort="5"
velocity="1"/></joint></robot>"""
    robot = so.Robot(urdf, "tipl")
    assert robot.locked == {"js": 1.0} and robot.total_mass == pytest.approx(6.5)
    np.testing.assert_array_equal(robot.torque_limit, [10.0, 5.0])
    j1, j2 = robot.model.inertias[1], robot.model.inertias[2]
    side = np.array([0.2 - 0.1 * math.sin(1.0), 0.1 * math.cos(1.0), 0.0])
    assert j1.mass == pytest.approx(5.0)
    np.testing.assert_allclose(j1.lever, (2 * np.array([0.1, 0, 0]) + 3 * side) / 5, atol=1e-12)
    assert j2.mass == pytest.approx(1.5)
    np.testing.assert_allclose(j2.lever, [(0.05 + 0.5 * 0.1) / 1.5, 0, 0], atol=1e-12)


def test_bundled_robots_carry_inertias_and_torque_limits():
    """Every bundled robot states masses and effort limits, and says they are estimates."""
    import tomllib

    from scara_opt.model.dh_file import bundled_dir

    for name in so.list_robots():
        robot = so.load_robot(name)
        assert robot.has_inertia and np.isfinite(robot.torque_limit).all()
        text = (bundled_dir() / f"{name}.toml").read_text()
        assert "ESTIMATES" in tomllib.loads(text)["dynamics_source"]
    fang = so.load_robot("fang")
    np.testing.assert_array_equal(fang.torque_limit, [50.0, 16.0, 150.0, 3.0])
    assert fang.total_mass == pytest.approx(5.0)


# ---------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("kwargs, error, match", [
    ({"payload": -1.0}, so.InputError, r"mass must be a number in \[0, 1e\+06\] kg"),
    ({"payload": float("nan")}, so.InputError, r"mass must be a number in \[0, 1e\+06\] kg"),
    ({"payload": 1e308}, so.InputError, r"mass must be a number in \[0, 1e\+06\] kg"),
    ({"payload": (1.0, [0, 0, 1e308])}, so.InputError, r"com must be finite, within ±1000 m"),
    ({"payload": (1.0, [0, 0])}, so.InputError, r"com must have shape \(3,\)"),
    ({"payload": (1.0, [0, 0, np.inf])}, so.InputError, "must be finite"),
    ({"payload": (1.0, [0, 0, 0], -np.eye(3))}, so.InputError, "positive semi-definite"),
    ({"payload": "heavy"}, so.InputError, "entries must be numbers"),
    ({"torque_limits": 0.0}, so.InputError, "torque_limits for joint 'j' is 0"),
    ({"torque_limits": [np.nan]}, so.InputError, "torque_limits for joint 'j' is nan"),
    ({"torque_limits": [1.0, 2.0]}, so.InputError, r"shape \(1,\)"),
    ({"torque_limits": "max"}, so.InputError, "torque_limits must be True"),
    ({"payload": 1.0, "payload_frame": "gripper"}, so.FrameNotFoundError, "'gripper'"),
    ({"torque_limits": True, "method": "ruckig"}, so.InputError, "does not limit joint torque"),
    ({"payload": 1.0, "torque_limits": False}, so.InputError, "torque_limits=False"),
    ({"payload_frame": "tip"}, so.InputError, "without payload="),
    ({"payload": 100.0, "torque_limits": True}, None, None),
])
def test_bad_torque_input_raises_the_specific_error(kwargs, error, match):
    """Negative/NaN mass, a limit of zero or NaN, a missing frame, a method without torque.

    100 kg at r = 1 m on a vertical axis is fine (no gravity torque), only slow.
    Mutation: as_payload without the mass >= 0 test -> fails (negative mass accepted).
    """
    robot = so.Robot(link_urdf(), "tip")
    kwargs = {"vmax": BIG, "amax": BIG, **kwargs}
    if error is None:
        assert so.time_parameterize([[0.0], [1.0]], robot, **kwargs).duration > 1.0
        return
    with pytest.raises(error, match=match):
        so.time_parameterize([[0.0], [1.0]], robot, **kwargs)


def test_robot_without_inertias_or_torque_limits_refuses_torque_timing():
    """No <inertial>: DynamicsError; no effort=: DynamicsError unless torque_limits= given;
    a payload gravity cannot hold: DynamicsError naming the joint.

    Mutation: RobotDynamics without the has_inertia test -> fails.
    """
    bare = so.Robot(link_urdf().replace("<mass value=\"2.0\"/>", '<mass value="0"/>'), "tip")
    assert not bare.has_inertia
    with pytest.raises(so.DynamicsError, match="no inertial data"):
        so.time_parameterize([[0.0], [1.0]], bare, vmax=BIG, amax=BIG, torque_limits=True)
    no_effort = so.Robot(link_urdf(effort=0.0), "tip")
    assert np.isinf(no_effort.torque_limit).all()
    with pytest.raises(so.DynamicsError, match=r"no torque limit.*\['j'\]"):
        so.time_parameterize([[0.0], [1.0]], no_effort, vmax=BIG, amax=BIG, payload=1.0)
    assert so.time_parameterize([[0.0], [1.0]], no_effort, vmax=BIG, amax=BIG,
                                torque_limits=4.0).duration > 0
    lift = so.Robot(lift_urdf(mass=2.0, effort=40.0), "slide")
    with pytest.raises(so.DynamicsError, match="gravity alone.*'z'"):
        so.time_parameterize([[0.0], [0.1]], lift, vmax=BIG, amax=BIG, payload=3.0)
    with pytest.raises(so.InputError, match="need the robot"):
        so.time_parameterize([[0.0], [0.1]], None, vmax=1, amax=1, torque_limits=1.0)


HEAD = 'length_unit = "mm"\nangle_unit = "deg"\n'
ROW = '[[joints]]\nname = "q1"\ntype = "revolute"\na = 250\nlower = -90\nupper = 90\n'
GOOD = "mass = 2\ncom = [125, 0, 0]\ninertia = [0.001, 0, 0, 0.01, 0, 0.01]\neffort = 20\n"


@pytest.mark.parametrize("extra, match", [
    (GOOD.replace("mass = 2", "mass = -2"), "joint 'q1': mass must be > 0 .*got -2"),
    (GOOD.replace("mass = 2", "mass = 0"), "joint 'q1': mass must be > 0"),
    (GOOD.replace("effort = 20", "effort = 0"), "joint 'q1': effort must be > 0.*got 0"),
    (GOOD.replace("mass = 2", "mass = nan"), "joint 'q1': mass must be a finite number"),
    (GOOD.replace("[125, 0, 0]", "[125, nan, 0]"), "joint 'q1': com must be a list of 3"),
    (GOOD.replace("0.01, 0, 0.01]", "0.01, 0, -0.01]"), "joint 'q1': inertia .* not a body"),
    (GOOD.replace("[0.001, 0, 0, 0.01, 0, 0.01]", "[0.001, 0, 0, 0.001, 0, 0.01]"),
     "joint 'q1': inertia .* ixx \\+ iyy >= izz"),
    (GOOD.replace("[0.001, 0, 0, 0.01, 0, 0.01]", "[1, 2, 3]"), "inertia must be a list of 6"),
    ("com = [1, 0, 0]\n", "joint 'q1': com and inertia describe a mass"),
])
def test_bad_inertial_data_in_a_robot_file_raise_urdf_error(tmp_path, extra, match):
    """Negative or zero mass, zero effort, NaN, an impossible inertia: URDFError, joint named.

    Mutation: check_inertial without the triangle-inequality test -> fails.
    """
    path = tmp_path / "bad.toml"
    path.write_text(HEAD + ROW + extra)
    with pytest.raises(so.URDFError, match=match):
        load_dh(path)


def test_inertial_data_of_a_robot_file_reach_the_urdf_and_the_robot(tmp_path):
    """mass, com (file units), inertia and effort come through in SI: mm → m, kg·m² as given.

    Mutation: com not converted from the file's length unit -> fails; dh_to_urdf writing
    effort="0" -> fails (no torque limit).
    """
    path = tmp_path / "ok.toml"
    path.write_text(HEAD + ROW + GOOD)
    robot = so.load_robot(path)
    Y = robot.model.inertias[1]
    assert Y.mass == 2.0
    np.testing.assert_allclose(Y.lever, [0.125, 0, 0])
    np.testing.assert_allclose(Y.inertia, np.diag([0.001, 0.01, 0.01]), atol=1e-15)
    np.testing.assert_array_equal(robot.torque_limit, [20.0])
    assert robot.has_inertia


def test_fang_report_times_the_table_2_move_at_0_1_2_kg():
    """The fang report's beyond-the-paper rows are computed: torque-only time grows with the
    payload; within the assumed rate limits the torques stay below their limits.

    Mutation: payload_timing passes payload=0.0 whatever the mass -> fails.
    """
    from scara_opt.reports.fang import payload_timing

    table = payload_timing(so.load_robot("fang"))
    assert list(table["payload_kg"]) == [0.0, 1.0, 2.0]
    assert np.all(np.diff(table["torque_only_s"]) > 0)
    assert np.all(np.diff(table["assumed_limits_max_torque_ratio"]) > 0)
    assert (table[["assumed_limits_max_torque_ratio", "torque_only_max_torque_ratio"]]
            <= 1.0).all().all()


@pytest.mark.parametrize("old, new", [('<mass value="2.0"/>', '<mass value="-2"/>'),
                                      ('<origin xyz="0.5 0 0"/><mass', '<origin xyz="nan 0 0"/>'
                                       '<mass')])
def test_a_urdf_with_a_negative_mass_or_nan_inertial_is_refused(old, new):
    """<inertial> with a negative mass or a NaN centre of mass: URDFError naming the link.

    urdfdom drops the NaN one silently (the link then weighs nothing) and loads the
    negative mass. Mutation: Robot without check_urdf_inertials -> fails.
    """
    with pytest.raises(so.URDFError, match="link 'arm' has <(mass|inertial)"):
        so.Robot(link_urdf().replace(old, new, 1), "tip")


@pytest.mark.parametrize("inertia", ['ixx="0.01" ixy="0" ixz="0" iyy="-1" iyz="0" izz="0.01"',
                                     'ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" '
                                     'izz="0.01"',
                                     'ixx="0.01" ixy="0.02" ixz="0" iyy="0.01" iyz="0" '
                                     'izz="0.01"'])
def test_a_urdf_inertia_no_body_has_is_refused(inertia):
    """``iyy="-1"`` (a negative moment), ``izz > ixx + iyy`` (the triangle inequality
    broken) or a product that makes the matrix indefinite: URDFError naming the link and
    the rules, as a robot file's inertia is (they were loaded as given). The point mass of
    ``link_urdf`` (an all-zero inertia) stays valid.

    Mutation caught: check_urdf_inertials without ``check_inertia_matrix`` -> loads; fails.
    """
    zero = '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>'
    with pytest.raises(so.URDFError, match=r"link 'arm': <inertia>: .* is not a body's "
                                           r"inertia .* ixx \+ iyy >= izz"):
        so.Robot(link_urdf().replace(zero, f"<inertia {inertia}/>"), "tip")


def test_rnea_of_a_pendulum_in_a_vertical_plane_is_m_r2_qdd_plus_m_g_r_cos_q():
    """Axis along y (horizontal), point mass m at r on x: τ = m r² q̈ + m g r cos q.

    The sign: gravity along -z pulls the mass down, and rotating about -y lifts it, so the
    axis is written as -y to make τ = +m g r cos q at q = 0 hold the arm horizontal.
    Mutation: RobotDynamics with model.gravity set to zero -> fails.
    """
    urdf = link_urdf(mass=1.5, r=0.4).replace('<axis xyz="0 0 1"/>', '<axis xyz="0 -1 0"/>')
    dyn = RobotDynamics(so.Robot(urdf, "tip"))
    m, r = 1.5, 0.4
    for q, v, a in np.random.default_rng(5).uniform(-2, 2, (10, 3)):
        tau = dyn.rnea(np.array([q]), np.array([v]), np.array([a]))[0]
        assert tau == pytest.approx(m * r * r * a + m * G * r * math.cos(q), rel=1e-9)


@pytest.mark.parametrize("name", so.list_robots())
def test_every_bundled_robot_times_a_move_with_2_kg_within_its_torques(name):
    """Each bundled robot, a move between two seeded configurations with 2 kg: torque ratio
    <= 1 at 1 kHz, and never faster than without the torque limits."""
    robot = so.load_robot(name)
    rng = np.random.default_rng(11)
    lo, hi = robot.sampling_lower, robot.sampling_upper
    Q = lo + (hi - lo) * (0.3 + 0.4 * rng.random((2, robot.nq)))
    free = so.time_parameterize(Q, robot)
    held = so.time_parameterize(Q, robot, payload=2.0)
    assert held.check_limits()["torque"].max() <= 1.0
    assert held.duration >= free.duration * (1 - 1e-9)


def test_csv_of_a_torque_limited_trajectory_has_the_torques(tmp_path):
    """to_csv adds <joint>_torque_Nm / _N columns: m r² q̈ for the point mass, m (z̈ + g) for
    the lift, at each row.

    Mutation: every torque column suffixed _Nm (the prismatic one too) -> fails.
    """
    robot = so.Robot(link_urdf(mass=2.0, r=0.5, effort=4.0), "tip")
    traj = so.time_parameterize([[-1.0], [1.0]], robot, vmax=BIG, amax=BIG, torque_limits=True)
    data = np.genfromtxt(traj.to_csv(tmp_path / "t.csv", dt=0.01), delimiter=",", names=True)
    assert "j_torque_Nm" in data.dtype.names
    np.testing.assert_allclose(data["j_torque_Nm"], 0.5 * data["j_rad_per_s2"], atol=1e-9)
    assert np.abs(data["j_torque_Nm"]).max() <= 4.0
    lift = so.Robot(lift_urdf(), "slide")
    traj = so.time_parameterize([[0.0], [0.1]], lift, vmax=BIG, amax=BIG, torque_limits=True)
    data = np.genfromtxt(traj.to_csv(tmp_path / "l.csv"), delimiter=",", names=True)
    np.testing.assert_allclose(data["z_torque_N"], 2.0 * (data["z_m_per_s2"] + G), atol=1e-9)
