"""Collision geometry, cells and the checker, against distances computed by hand."""

from __future__ import annotations

import logging
import math

import coal
import numpy as np
import pinocchio as pin
import pytest

import scara_opt as so
from scara_opt.collision.bound import body_weights
from scara_opt.collision.geometry import robot_geometry

from .conftest import DATA, random_q

ARM2R = DATA / "arm2r_collision.urdf"


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance from point p to segment ab (written here, independent of coal)."""
    t = np.clip(np.dot(p - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * (b - a))))


def test_2r_arm_and_post_distance_by_hand():
    """A planar 2R arm (cylinders of radius 20 mm) and a vertical post of radius 50 mm: the
    signed distances are the planar point-to-segment distances minus both radii, by hand.

    Mutation caught: the obstacle placed without its pose (at the origin), or the robot's
    geometry not moved by the joints (computeDistances without FK and placements), fails.
    """
    robot = so.Robot.from_urdf(ARM2R)
    post = so.Cylinder("post", radius=0.05, length=0.4, xyz=(0.32, 0.21, 0.0))
    checker = so.CollisionChecker(robot, so.Cell([post]))
    assert checker.pair_names == (("upper", "post"), ("fore", "post"))  # the URDF's links
    c = np.array([0.32, 0.21])
    for q1, q2 in [(0.4, -0.9), (0.1, 0.3), (-0.2, 1.4), (0.45, -1.2)]:
        elbow = 0.30 * np.array([math.cos(q1), math.sin(q1)])
        tip = elbow + 0.25 * np.array([math.cos(q1 + q2), math.sin(q1 + q2)])
        d = checker.distances(np.array([q1, q2]))
        for k, (a, b) in enumerate([(np.zeros(2), elbow), (elbow, tip)]):
            t = np.dot(c - a, b - a) / np.dot(b - a, b - a)
            if 0.02 < t < 0.98:  # the foot on the cylinder's side, not a flat end
                assert d[k] == pytest.approx(_segment_distance(c, a, b) - 0.07, abs=1e-6)
    q = np.array([0.4, -0.9])
    assert checker.clearance(q).distance == pytest.approx(checker.distances(q).min())


def test_capsule_robot_and_sphere_distance_by_hand():
    """zavar2024's capsules (radius keys of its robot file) and a sphere: the distance to the
    tool capsule is the point-to-segment distance minus both radii.

    Mutation caught: every link's radius taken from one row (the quill's 10 mm for the tool's
    15 mm) fails.
    """
    robot = so.load_robot("zavar2024")
    ball = so.Sphere("ball", radius=0.02, xyz=(0.30, 0.12, -0.13))
    checker = so.CollisionChecker(robot, so.Cell([ball]))
    k = checker.pair_names.index(("link4", "ball"))
    for q in ([0.3, 0.4, 0.01, 0.0], [0.2, 0.2, 0.04, 1.0], [0.5, -0.1, 0.0, 0.0]):
        q = np.array(q)
        T = robot.fk(q)
        tip = T[:3, 3]
        top = tip + np.array([0, 0, 0.05])  # the tool's 50 mm below the quill's frame
        want = _segment_distance(np.array(ball.xyz), top, tip) - 0.02 - 0.015
        assert checker.distances(q)[k] == pytest.approx(want, abs=1e-6)


def test_self_pairs_leave_out_adjacent_and_built_in_contacts():
    """Adjacent links are not checked against each other; a SCARA's tool against its arm 2
    (in contact at the reference pose: the quill passes through the arm) is left out too,
    and the forearm against the quill is checked.

    Mutation caught: dropping the reference-contact rule makes link2-link4 a checked pair
    that collides everywhere (every configuration in self-collision).
    """
    geom = robot_geometry(so.load_robot("zavar2024"))
    assert geom.skipped[("link1", "link2")] == "adjacent"
    assert geom.skipped[("link2", "link4")] == "in contact at the reference configuration"
    checked = {(geom.bodies[i].name, geom.bodies[j].name) for i, j in geom.pairs}
    assert ("link1", "link3_shaft") in checked
    checker = so.CollisionChecker(so.load_robot("zavar2024"))
    Q = random_q(checker.robot, 200, 0)
    assert not checker.collides_many(Q).any()  # the elbow limits keep the arms apart


def test_self_collision_is_found_when_the_arm_folds_back():
    """A 2R arm with capsules folds its forearm onto the base link: self-collision found."""
    robot = so.load_robot("fang").with_limits(theta2=(-3.1, 3.1))
    checker = so.CollisionChecker(robot)
    assert not checker.collides(np.array([0.0, 0.0, 0.0, 0.0]))
    assert checker.collides(np.array([0.0, 3.05, 0.0, 0.0]))
    c = checker.contacts(np.array([0.0, 3.05, 0.0, 0.0]))
    assert c and c[0].bodies[0] == "link1" and c[0].depth > 0


def test_srdf_and_allowed_pairs_and_unknown_body():
    """An SRDF's disable_collisions and allowed= leave pairs out; an unknown name is refused
    naming the bodies that exist.

    Mutation caught: ignoring the SRDF (the pair still checked), or accepting an unknown name
    silently.
    """
    robot = so.load_robot("fang")
    srdf = '<robot name="fang"><disable_collisions link1="link1" link2="link4" reason="x"/></robot>'
    geom = robot_geometry(robot, srdf=srdf)
    assert geom.skipped[("link1", "link4")] == "allowed"
    with pytest.raises(so.UnknownBodyError, match="no body named 'lnk4'.*link3_shaft"):
        robot_geometry(robot, allowed=[("link1", "lnk4")])
    cell = so.Cell([so.Box("nest", (0.05, 0.05, 0.05), xyz=(0.4, 0, -0.06))],
                   allowed=[("link4", "nest")])
    checker = so.CollisionChecker(robot, cell)
    assert ("link4", "nest") not in checker.pair_names
    assert checker.skipped[("link4", "nest")] == "allowed"
    bad = so.Cell([so.Box("nest", (0.05, 0.05, 0.05))], allowed=[("gripper", "nest")])
    with pytest.raises(so.UnknownBodyError, match="'gripper'"):
        so.CollisionChecker(robot, bad)


def test_missing_radius_and_missing_mesh_are_specific_errors(caplog):
    """A robot without <collision> and without radius keys, and a URDF whose collision mesh
    is missing, each get their own error; missing_mesh='capsule' is the explicit fallback.

    Mutation caught: a missing mesh skipped silently (no error, no warning).
    """
    ur5 = so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")
    with pytest.raises(so.CellError, match="radius"):
        robot_geometry(ur5)
    assert len(robot_geometry(ur5, radius=0.04).bodies) == 6
    robot = so.Robot.from_urdf(DATA / "missing_mesh.urdf")
    with pytest.raises(so.MeshNotFoundError, match="base.stl"):
        robot_geometry(robot)
    with caplog.at_level(logging.WARNING):
        geom = robot_geometry(robot, missing_mesh="capsule", radius=0.03)
    assert "cannot be found" in caplog.text
    assert [b.link for b in geom.bodies] == ["arm"]  # its box; the base has nothing to build


def test_radius_key_is_checked_in_the_robot_file(tmp_path):
    """A radius <= 0 in a robot file is refused when the file is loaded."""
    text = (DATA.parent.parent / "robots" / "zavar2024.toml").read_text()
    path = tmp_path / "r.toml"
    path.write_text(text.replace("radius = 0.035", "radius = -0.035", 1))
    with pytest.raises(so.URDFError, match="radius must be > 0"):
        so.load_robot(path)


CELL_FILE = """
name = "test cell"
length_unit = "mm"
angle_unit = "deg"
allowed = [["link4", "nest"]]

[[obstacles]]
name = "post"
type = "cylinder"
radius = 30
length = 400
xyz = [250, 150, 0]

[[obstacles]]
name = "nest"
type = "box"
size = [50, 50, 50]
xyz = [400, 0, -60]
rpy = [0, 0, 90]
"""


def test_cell_file_reads_units_and_obstacles(tmp_path):
    """A cell file in mm and degrees gives obstacles in metres and radians."""
    path = tmp_path / "cell.toml"
    path.write_text(CELL_FILE)
    cell = so.load_cell(path)
    assert cell.names == ["post", "nest"]
    assert cell["post"].radius == pytest.approx(0.03)
    assert cell["post"].xyz == pytest.approx((0.25, 0.15, 0.0))
    assert cell["nest"].rpy[2] == pytest.approx(math.pi / 2)
    assert cell.allowed == (("link4", "nest"),)
    assert "post" in repr(cell)


@pytest.mark.parametrize("edit, match", [
    # in the file's unit, with the file's name (issue 38: "-0.005 [m]", no file)
    (("radius = 30", "radius = 0"), r"cell\.toml.*radius 0 mm: a size must be > 0"),
    (("size = [50, 50, 50]", "size = [50, -5, 50]"),
     r"cell\.toml.*size \[50, -5, 50\] mm: a size must be > 0"),
    (("radius = 30", "raduis = 30"), "did you mean 'radius'"),
    (('type = "box"', 'type = "cube"'), "type must be one of"),
    (("length = 400", ""), "needs length"),
    (('length_unit = "mm"', 'length_unit = "furlong"'), "length_unit must be one of"),
    (('name = "nest"', 'name = "post"'), "two obstacles are named 'post'"),
    (("xyz = [250, 150, 0]", "xyz = [250, 150]"), "xyz must be a list of 3 numbers"),
    (("[[obstacles]]\nname = \"post\"", "[[obstacles]\nname = \"post\""), "not valid TOML"),
])
def test_malformed_cell_files_are_refused(tmp_path, edit, match):
    """Each malformed cell file gets a CellError saying what to change.

    Mutation caught: a zero radius or a misspelt key accepted (an obstacle silently of no
    size, or missing).
    """
    path = tmp_path / "cell.toml"
    path.write_text(CELL_FILE.replace(*edit, 1))
    with pytest.raises(so.CellError, match=match):
        so.load_cell(path)


def test_mesh_obstacle_and_missing_mesh(tmp_path):
    """A mesh obstacle from an STL (relative to the cell file) collides like its box (but
    where a body touches it to round-off, 1e-9 m); a missing mesh file is a
    MeshNotFoundError."""
    import trimesh

    trimesh.creation.box((100, 100, 100)).export(tmp_path / "block.stl")
    (tmp_path / "cell.toml").write_text(
        'length_unit = "mm"\n[[obstacles]]\nname = "block"\ntype = "mesh"\n'
        'file = "block.stl"\nxyz = [300, 0, -80]\n')
    cell = so.load_cell(tmp_path / "cell.toml")
    box = so.Cell([so.Box("block", (0.1, 0.1, 0.1), xyz=(0.3, 0, -0.08))])
    robot = so.load_robot("zavar2024")
    a, b = so.CollisionChecker(robot, cell), so.CollisionChecker(robot, box)
    Q = random_q(robot, 300, 1)
    sure = np.abs(b.clearance_many(Q)) > 1e-9
    assert (a.collides_many(Q) == b.collides_many(Q))[sure].all() and a.collides_many(Q).any()
    (tmp_path / "block.stl").unlink()
    with pytest.raises(so.MeshNotFoundError, match="block.stl"):
        so.load_cell(tmp_path / "cell.toml")


@pytest.mark.parametrize("make, match", [
    (lambda: so.Box("b", (0.1, 0.0, 0.1)), "size"),
    (lambda: so.Sphere("s", -0.1), "radius"),
    (lambda: so.Cylinder("c", 0.1, math.nan), "length"),
    (lambda: so.Capsule("c", 0.1, 0.2, xyz=(0, 0)), "xyz"),
    (lambda: so.Box("", (0.1, 0.1, 0.1)), "name"),
    (lambda: so.Cell([so.Sphere("s", 0.1), "table"]), "Box, Cylinder"),
    (lambda: so.Box("b", (10**400, 1, 1)), "size must be 3 finite numbers"),
    (lambda: so.Box("b", (1, 1, 1), xyz=(10**400, 0, 0)), "xyz must be 3 finite"),
    (lambda: so.Sphere("s", 10**400), "radius must be a finite number"),
    (lambda: so.Box("b", (1, 1, 1), xyz=(1e300, 0, 0)), "beyond 10000 m"),
    (lambda: so.Box("b", (1e-300, 1, 1)), r"size\[0\] 1e-300 m is outside"),
    (lambda: so.Box("b\0x", (1, 1, 1)), "control character"),
    (lambda: so.Cell([so.Box("b", (1, 1, 1))], name="c\0"), "control character"),
    (lambda: so.Mesh("m", path="a\0b.stl"), "NUL byte"),
    (lambda: so.Cell([so.Sphere("a", 0.1), so.Sphere("b", 0.1, xyz=(1, 0, 0))],
                     allowed=[("a", "b")]), "names two obstacles"),
])
def test_bad_obstacles_in_python(make, match):
    """Zero, negative or NaN sizes, integers beyond any float, positions beyond 10 km,
    sizes below 1 µm, control characters in names, a NUL in a path, an allowed pair of two
    obstacles, and non-obstacles: each a CellError naming what was wrong.

    Mutation caught: ``_finite`` without its OverflowError guard -> OverflowError; fails.
    Mutation caught: ``MAX_EXTENT`` not checked -> the box at 1e300 m accepted ("0.000 mm
    deep" later); fails. Mutation caught: ``check_text`` accepting control characters ->
    fails.
    """
    with pytest.raises(so.CellError, match=match):
        make()


def test_bad_paths_and_pairs_are_specific_errors(tmp_path):
    """A cell file with a radius of 1 followed by 400 zeros, a NUL in a cell file's path or
    an export's, an allowed pair of two obstacles given to the checker: specific errors,
    never OverflowError or ValueError.

    Mutation caught: ``cell._float`` without its guard -> OverflowError; fails. Mutation
    caught: ``to_csv`` without ``check_path`` -> ValueError (embedded null byte); fails.
    """
    big = tmp_path / "big.toml"
    big.write_text('length_unit = "m"\n[[obstacles]]\nname = "b"\ntype = "sphere"\n'
                   f"radius = 1{'0' * 400}\n")
    with pytest.raises(so.CellError, match="too large"):
        so.load_cell(big)
    with pytest.raises(so.CellError, match="NUL byte"):
        so.load_cell("a\0b.toml")
    robot = so.load_robot("zavar2024")
    traj = so.plan(robot, [so.PTP([0.1, 0.1, 0.01, 0.1])], start=np.zeros(4))
    for write in (traj.to_csv, traj.to_json, traj.to_ros_yaml):
        with pytest.raises(so.InputError, match="NUL byte"):
            write(str(tmp_path / "a\0b.txt"))
    two = so.Cell([so.Sphere("a", 0.02, xyz=(1, 1, 0)), so.Sphere("b", 0.02, xyz=(2, 1, 0))])
    with pytest.raises(so.CellError, match="names two obstacles"):
        so.CollisionChecker(robot, two, allowed=[("a", "b")])


def test_batch_agrees_with_the_loop_and_the_distances():
    """collides_many (one call) gives the loop's answers; a configuration collides exactly
    when its smallest distance is <= 0; a margin counts as contact.

    Mutation caught: the batch's rows read in reverse order (``Qa[::-1]`` into the kernel):
    its answers then differ from the loop's.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Cylinder("post", 0.03, 0.4, xyz=(0.25, 0.15, 0.0)),
                    so.Box("rack", (0.1, 0.3, 0.05), xyz=(0.0, 0.3, -0.1))])
    checker = so.CollisionChecker(robot, cell)
    Q = random_q(robot, 500, 2)
    loop = np.array([checker.collides(q) for q in Q])
    assert (checker.collides_many(Q) == loop).all()
    assert 0.05 < loop.mean() < 0.95
    assert ((checker.clearance_many(Q) <= 0) == loop).all()
    wide = so.CollisionChecker(robot, cell, margin=0.01)
    assert (wide.collides_many(Q) == (checker.clearance_many(Q) < 0.01)).all()


def test_checker_input_errors():
    """A bad q, cell or margin is an InputError naming it."""
    checker = so.CollisionChecker(so.load_robot("zavar2024"))
    with pytest.raises(so.InputError, match="shape"):
        checker.collides(np.zeros(3))
    with pytest.raises(so.InputError, match="non-finite"):
        checker.collides(np.array([0.0, math.nan, 0.0, 0.0]))
    with pytest.raises(so.InputError, match="cell must be"):
        so.CollisionChecker(checker.robot, [so.Sphere("s", 0.1)])
    with pytest.raises(so.InputError, match="margin"):
        so.CollisionChecker(checker.robot, margin=-0.01)


@pytest.mark.parametrize("name", ["zavar2024", "fang", "peng2025"])
def test_motion_bound_holds_for_sampled_motions(name):
    """No support point of any body moves farther than the bound, over 300 random short
    joint motions (displacements by FK of the body frames, independent of the bound).

    Mutation caught: the bound halved (each weight x 0.5), or the distance from axis j to
    the next joint's origin left out of r_j (only the reach along the chain), fails.
    """
    robot = so.load_robot(name)
    geom = robot_geometry(robot)
    rng = np.random.default_rng(3)
    data = robot.model.createData()
    worst = 0.0
    for _ in range(300):
        q = rng.uniform(robot.lower, robot.upper)
        dq = rng.normal(size=robot.nq) * 0.02
        dq[[k for k, t in enumerate(robot.joint_types) if t == "prismatic"]] *= 0.1
        moved = []
        for x in (q, q + dq):
            pin.forwardKinematics(robot.model, data, x)
            moved.append([data.oMi[b.joint].act(p) for b in geom.bodies for p in b.points])
        i = 0
        for b in geom.bodies:
            w = body_weights(robot, b)
            for _ in b.points:
                step = np.linalg.norm(moved[1][i] - moved[0][i])
                worst = max(worst, step / (w @ np.abs(dq)))
                i += 1
    assert worst <= 1.0 + 1e-9  # round-off when only a prismatic joint moves (exact bound)
    assert worst > 0.5  # the bound is not wildly loose on these chains


def test_pairs_out_of_reach_along_the_scara_axis_are_not_checked():
    """A table 27 mm below the tool's lowest reach and a shelf above the arms are never
    checked against the SCARA's bodies (their height ranges never meet); sampled over the
    joint box, those pairs' distances indeed never fall below the gap stated.

    Mutation caught: the prismatic stroke left out of the height range (the quill's
    reference height taken as its only one): the table is then pruned even when it is
    within the tool's reach (the second cell), and that pair's collisions are missed.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Box("table", (0.9, 0.9, 0.02), xyz=(0.1, 0.0, -0.15)),
                    so.Box("shelf", (0.2, 0.2, 0.02), xyz=(0.3, 0.0, 0.08))])
    checker = so.CollisionChecker(robot, cell)
    pruned = [k for k, why in checker.skipped.items() if why.startswith("never")]
    assert ("link4", "table") in pruned and ("link2", "shelf") in pruned
    Q = random_q(robot, 300, 4)
    model = checker.model  # every body is in it, checked or not
    data, gdata = robot.model.createData(), pin.GeometryData(model)
    names = [o.name for o in model.geometryObjects]
    for a, b in pruned:
        i, j = names.index(a), names.index(b)
        gap = float(checker.skipped[(a, b)].split("at least ")[1].split(" mm")[0]) * 1e-3
        for q in Q:
            pin.updateGeometryPlacements(robot.model, data, model, gdata, q)
            d = coal.distance(model.geometryObjects[i].geometry, gdata.oMg[i],
                              model.geometryObjects[j].geometry, gdata.oMg[j],
                              coal.DistanceRequest(), coal.DistanceResult())
            assert d >= gap - 1e-6
    lower = so.Cell([so.Box("table", (0.9, 0.9, 0.02), xyz=(0.1, 0.0, -0.11))])
    reach = so.CollisionChecker(robot, lower)
    assert ("link4", "table") in reach.pair_names  # within the tool's reach: checked
    assert reach.collides(np.array([0.3, 0.3, 0.048, 0.0]))


def test_cell_file_that_is_missing_a_folder_or_not_text(tmp_path):
    """A missing cell file, a folder and a binary file each get a CellError saying so."""
    with pytest.raises(so.CellError, match="does not exist"):
        so.load_cell(tmp_path / "nope.toml")
    with pytest.raises(so.CellError, match="cannot be read"):
        so.load_cell(tmp_path)
    (tmp_path / "bin.toml").write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(so.CellError, match="not UTF-8 text"):
        so.load_cell(tmp_path / "bin.toml")
