"""DH tables to URDF: the bundled files are fresh, the conventions agree, bad files fail clearly."""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.model.dh import DHJoint, DHRobot, dh_to_urdf
from scara_opt.model.dh_file import bundled_dir, load_dh
from tests.conftest import BUNDLED, DATA, random_q
from tests.test_arms_data import modified_link, standard_link


@pytest.mark.parametrize("name", BUNDLED)
def test_committed_urdf_is_not_stale(name):
    """Regenerating each bundled URDF from its TOML gives the committed file byte for byte."""
    folder = bundled_dir()
    expected = dh_to_urdf(load_dh(folder / f"{name}.toml"))
    assert (folder / f"{name}.urdf").read_text() == expected, (
        f"robots/{name}.urdf is stale: run python -m scara_opt.model.dh_file"
    )


def test_every_bundled_robot_has_a_source_and_units():
    """Each robot file names its paper (a [citation], no path outside the repo) and its units."""
    import tomllib

    for name in BUNDLED:
        data = tomllib.loads((bundled_dir() / f"{name}.toml").read_text())
        assert data["source"] and "seeds/" not in data["source"] and "citation" in data
        assert data["length_unit"] in ("m", "mm", "in") and data["angle_unit"] == "deg"


def test_modified_dh_matches_standard_dh_for_a_planar_arm():
    """A 3R planar arm written in standard and in modified DH reaches the same tool pose."""
    lim = dict(lower=-3.0, upper=3.0)
    std = DHRobot("std", (DHJoint("j1", "revolute", a=0.3, **lim),
                          DHJoint("j2", "revolute", a=0.2, **lim),
                          DHJoint("j3", "revolute", a=0.1, **lim)))
    mod = DHRobot("mod", (DHJoint("j1", "revolute", **lim),
                          DHJoint("j2", "revolute", a=0.3, **lim),
                          DHJoint("j3", "revolute", a=0.2, **lim),
                          DHJoint("tip", "fixed", a=0.1)), convention="modified")
    rs, rm = so.Robot.from_dh(std), so.Robot.from_dh(mod)
    Q = random_q(rs, 200, seed=4)
    np.testing.assert_allclose(rs.fk_batch(Q), rm.fk_batch(Q), atol=1e-12)


def test_sign_and_offset_enter_the_joint_variable():
    """A row theta = offset + sign*q: sign -1 and a 90 deg offset turn the arm the other way."""
    row = DHJoint("j", "revolute", a=1.0, theta=math.pi / 2, sign=-1.0, lower=-1, upper=1)
    robot = so.Robot.from_dh(DHRobot("one", (row,)))
    np.testing.assert_allclose(robot.position([0.3]), [math.cos(math.pi / 2 - 0.3),
                                                       math.sin(math.pi / 2 - 0.3), 0], atol=1e-12)


def test_inverted_limits_raise_joint_limit_error():
    """A DH row whose lower limit is above its upper limit is refused with the joint named."""
    with pytest.raises(so.JointLimitError, match="'j2'.*not below"):
        DHJoint("j2", "revolute", lower=1.0, upper=-1.0)


def test_bad_robot_files_raise_urdf_error(tmp_path):
    """Missing file, bad TOML, unknown unit, unknown joint type: each a URDFError saying which."""
    with pytest.raises(so.URDFError, match="does not exist"):
        load_dh(tmp_path / "none.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = [")
    with pytest.raises(so.URDFError, match="not valid TOML"):
        load_dh(bad)
    bad.write_text('length_unit = "furlong"\nangle_unit = "deg"\n[[joints]]\ntype="revolute"\n')
    with pytest.raises(so.URDFError, match="length_unit"):
        load_dh(bad)
    bad.write_text('length_unit = "m"\nangle_unit = "deg"\n[[joints]]\ntype="helical"\n')
    with pytest.raises(so.URDFError, match="helical"):
        load_dh(bad)
    bad.write_text('length_unit = "m"\nangle_unit = "deg"\n[[joints]]\ntype="fixed"\na=1\n')
    with pytest.raises(so.URDFError, match="no movable joint"):
        load_dh(bad)


def test_load_robot_accepts_a_dh_toml_path(tmp_path):
    """load_robot takes a path to a user's own DH file as well as a bundled name."""
    path = tmp_path / "mine.toml"
    path.write_text(
        'name = "mine"\nlength_unit = "mm"\nangle_unit = "deg"\n'
        '[[joints]]\nname = "q1"\ntype = "revolute"\na = 250\nlower = -90\nupper = 90\n'
    )
    robot = so.load_robot(path)
    assert robot.name == "mine" and robot.nq == 1
    np.testing.assert_allclose(robot.position([0.0]), [0.25, 0, 0], atol=1e-15)
    np.testing.assert_allclose(robot.upper, [math.pi / 2])


HEAD = 'length_unit = "mm"\nangle_unit = "deg"\n'
ROW = '[[joints]]\nname = "q1"\ntype = "revolute"\na = 250\nlower = -90\nupper = 90\n'


@pytest.mark.parametrize("text, match", [
    (HEAD + ROW + "[tool]\nxyz = [nan, 0, 0]\n", r"\[tool\]: xyz must be a list of 3 finite"),
    (HEAD + ROW + "[tool]\nrpy = [inf, 0, 0]\n", r"\[tool\]: rpy must be a list of 3 finite"),
    (HEAD + ROW + "[tool]\nxyz = [0, 0]\n", r"xyz must be a list of 3 finite.*got \[0, 0\]"),
    (HEAD + ROW + '[tool]\nxyz = [0, "1", 0]\n', "xyz must be a list of 3 finite"),
    (HEAD + "tool = 5\n" + ROW, r"\[tool\] must be a TOML table"),
    (HEAD + "joints = [1, 2]\n", "joints entry 1 must be a TOML table"),
    (HEAD + ROW + "alpha = nan\n", "joint 'q1': alpha must be a finite number, got nan"),
    (HEAD + ROW + "velocity = inf\n", "joint 'q1': velocity must be a finite number"),
    (HEAD + ROW + "alfa = 180\n",
     "joint 'q1' has unknown key.*'alfa'.*did you mean 'alpha'.*accepted keys: name, type, a,"),
    ('lenght_unit = "mm"\n' + HEAD + ROW,
     "unknown key.*'lenght_unit'.*did you mean 'length_unit'.*accepted keys: name, title"),
    (HEAD + ROW + "[tool]\nxyz = [0, 0, 1]\nrp = [0, 0, 0]\n",
     r"\[tool\] has unknown key.*'rp'.*accepted keys: xyz, rpy"),
])
def test_bad_entries_in_a_robot_file_raise_urdf_error(tmp_path, text, match):
    """Non-finite or mis-shaped values, non-table entries and misspelt keys: URDFError."""
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(so.URDFError, match=match):
        load_dh(path)


def test_a_robot_file_with_a_tool_and_every_key_loads(tmp_path):
    """title, source, notes, convention, [tool] and [footprint] are all accepted keys."""
    path = tmp_path / "ok.toml"
    path.write_text('name = "ok"\ntitle = "t"\nsource = "s"\nnotes = "n"\n'
                    'convention = "standard"\n' + HEAD + ROW + "sign = -1\nalpha = 0\nd = 0\n"
                    "theta = 0\nvelocity = 90\nacceleration = 360\n"
                    "[tool]\nxyz = [0, 0, -10]\nrpy = [0, 0, 90]\n"
                    '[footprint]\nshape = "circle"\ncenter = [0, 0]\nradius = 50\n')
    dh = load_dh(path)
    np.testing.assert_allclose(dh.tool[:3, 3], [0, 0, -0.01])
    np.testing.assert_allclose(dh.tool[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_tiny_limits_reach_the_urdf_exactly(tmp_path):
    """An acceleration of 1e-320 deg/s² stays 1.7e-322 rad/s², not "0" (no limit at all).

    Mutation: limits written with _fmt (|x| < 1e-15 -> "0", as before) -> fails (the URDF
    then holds acceleration="0", refused on loading).
    """
    path = tmp_path / "tiny.toml"
    path.write_text(HEAD + ROW + "acceleration = 1e-320\nvelocity = 1e-300\n")
    robot = so.load_robot(path)
    assert 0 < robot.acceleration_limit[0] < 1e-321
    assert robot.velocity_limit[0] == pytest.approx(1e-300 * math.pi / 180)


@pytest.mark.parametrize("text, match", [
    ("name = 5\n" + HEAD + ROW, "name must be a string"),
    (HEAD + "convention = 1\n" + ROW, "convention must be a string"),
    (HEAD + 'source = ["a"]\n' + ROW, "source must be a string"),
    (HEAD + "title = true\n" + ROW, "title must be a string"),
    (HEAD + ROW.replace('name = "q1"', "name = 7"), "joints entry 1: name must be a string"),
    (HEAD + ROW.replace('type = "revolute"', "type = 1"), "type must be a string"),
    ('length_unit = ["mm"]\nangle_unit = "deg"\n' + ROW, "length_unit must be one of"),
    ('length_unit = "mm"\nangle_unit = {a = 1}\n' + ROW, "angle_unit one of"),
])
def test_text_entries_of_a_robot_file_must_be_strings(tmp_path, text, match):
    """Names, type, convention and texts are TOML strings; units are one of the known names.

    Mutation: _text returns str(value) (name = 5 became "5") -> fails; the unit check
    without its isinstance test (a list raised TypeError: unhashable) -> fails.
    """
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(so.URDFError, match=match):
        load_dh(path)


def test_unreadable_robot_files_raise_urdf_error(tmp_path):
    """A folder or a binary file given as a robot file is a URDFError, not an OSError.

    Mutation: load_dh without its OSError / UnicodeDecodeError branches -> fails.
    """
    with pytest.raises(so.URDFError, match="cannot be read"):
        load_dh(tmp_path)
    binary = tmp_path / "robot.toml"
    binary.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(so.URDFError, match="not UTF-8"):
        load_dh(binary)


DH_FILES = [bundled_dir() / f"{name}.toml" for name in BUNDLED] + [
    DATA / "panda_dh.toml", DATA / "ur5_dh.toml"]


def _table_fk(dh: DHRobot, q: np.ndarray) -> np.ndarray:
    """Tool pose (4, 4) [m] from the table alone: each row's textbook DH matrix, then the tool."""
    T, k = np.eye(4), 0
    for j in dh.joints:
        theta, d = j.theta, j.d
        if j.type != "fixed":
            if j.type == "revolute":
                theta += j.sign * q[k]
            else:
                d += j.sign * q[k]
            k += 1
        T = T @ (standard_link(theta, d, j.a, j.alpha) if dh.convention == "standard"
                 else modified_link(j.a, j.alpha, theta, d))
    return T @ dh.tool


@pytest.mark.parametrize("path", DH_FILES, ids=lambda p: p.stem)
def test_written_urdf_loads_to_the_tables_model(path):
    """The URDF that dh_to_urdf writes (with yourdfpy) loads into Pinocchio as the table says:
    the tool pose at 30 seeded configurations equals the product of the rows' textbook DH
    matrices (not the writer's joint_frames) to 1e-12; each moving link's mass and centre of
    mass (exactly), inertia (to round-off: Pinocchio stores it about the centre of mass), and
    each joint's limits, velocity, effort and acceleration (the ``<scara_opt acceleration>``
    extension, exactly) are the table's.

    Mutations caught: the joint axis written +z whatever the row's sign (the FK fails on
    zavar2024's "−d3" row); the inertial origin left at the link frame (``_inertial``: the
    centre of mass fails on zavar2024); the acceleration element left out (ur5_dh: ``inf``
    instead of the table's value).
    """
    dh = load_dh(path)
    robot = so.Robot(dh_to_urdf(dh), tip="tool")
    movable = [j for j in dh.joints if j.type != "fixed"]
    for q in random_q(robot, 30, seed=3):
        np.testing.assert_allclose(robot.fk(q), _table_fk(dh, q), rtol=0, atol=1e-12)
    for field, values in (("lower", robot.lower), ("upper", robot.upper),
                          ("velocity", robot.velocity_limit),
                          ("acceleration", robot.acceleration_limit),
                          ("effort", robot.model.effortLimit)):
        assert list(values) == [getattr(j, field) for j in movable], field
    for k, j in enumerate(movable, start=1):
        inertia = robot.model.inertias[k]
        assert inertia.mass == j.mass
        assert list(inertia.lever) == list(j.com), j.name
        ixx, ixy, ixz, iyy, iyz, izz = j.inertia
        expected = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        np.testing.assert_allclose(inertia.inertia, expected, rtol=1e-12, atol=1e-15,
                                   err_msg=j.name)
