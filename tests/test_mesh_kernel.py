"""Mesh robots and mesh fixtures: bounds that never exceed the exact distance, true verdicts.

The UR5 here is example-robot-data's URDF with its own collision meshes (446-1,176 triangles
a link), copied into tests/data with its package:// layout. Every reference is coal's own
exact BVH distance, asked with a fresh request through Pinocchio, and for closed meshes the
winding number of a point (scara_opt.collision.mesh_bounds), written in numpy.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
import trimesh

import scara_opt as so
from scara_opt.collision.mesh_bounds import mesh_parts, winding_number
from tests.conftest import DATA, pinocchio_distances

UR5_URDF = DATA / "example-robot-data" / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"
SCARA = so.load_robot("zavar2024")


def ur5() -> so.Robot:
    robot = so.Robot.from_urdf(UR5_URDF, tip="ee_link")
    return robot.with_limits(**{n: (-math.pi, math.pi) for n in robot.joint_names})


def _bracket(path):
    """A closed STL fixture in mm: a U of three boxes (one mesh, three closed shells)."""
    parts = [trimesh.creation.box((200, 20, 150)), trimesh.creation.box((200, 20, 150)),
             trimesh.creation.box((20, 200, 150))]
    parts[0].apply_translation((0, -90, 0))
    parts[1].apply_translation((0, 90, 0))
    parts[2].apply_translation((-90, 0, 0))
    trimesh.util.concatenate(parts).export(path)
    return path


def table_cell(tmp_path):
    """A table the UR5's base stands 3 mm into, a box, and the STL bracket."""
    stl = _bracket(tmp_path / "bracket.stl")
    return so.Cell([so.Box("table", (1.2, 1.2, 0.04), xyz=(0, 0, 0.003 - 0.02)),
                    so.Box("box", (0.2, 0.2, 0.3), xyz=(0.45, 0.25, 0.15)),
                    so.Mesh("bracket", stl, scale=(1e-3,) * 3, xyz=(-0.1, -0.45, 0.25))])


def _reference(checker, Q, surface=False):
    """(n, npairs) coal's exact distances (fresh), a body inside a closed mesh negated
    (``surface``: also the distances not negated)."""
    import pinocchio as pin

    D = pinocchio_distances(checker, Q)
    plain = D.copy()
    model = checker.model
    data, gdata = checker.robot.model.createData(), pin.GeometryData(model)
    parts = [mesh_parts(o.geometry) if hasattr(o.geometry, "num_tris") else None
             for o in model.geometryObjects]
    for i, q in enumerate(Q):
        pin.updateGeometryPlacements(checker.robot.model, data, model, gdata, q)
        for k, (a, b) in enumerate(checker.pairs.tolist()):
            if D[i, k] <= 0:
                continue
            for outer, body in ((a, b), (b, a)):
                p = parts[outer]
                if p is None or not p.closed:
                    continue
                point = p.point if parts[body] is not None else np.zeros(3)
                if parts[body] is not None:
                    point = parts[body].point
                x = gdata.oMg[outer].actInv(gdata.oMg[body].act(point))
                if abs(winding_number(p, x)) > 0.5:
                    D[i, k] = -D[i, k]
                    break
    return (D, plain) if surface else D


def test_a_mesh_robot_loads_with_link_names_and_its_mounting_left_out(tmp_path, caplog):
    """The UR5 from its URDF (package:// meshes found from the URDF's folder): bodies named
    by link (no "_0"), the base on its table found always in contact, reported and left out,
    so a start is not refused; allowed= takes the link's name; an unknown name lists them.

    Mutation caught: bodies named as Pinocchio names them (``base_link_0``) -> fails.
    Mutation caught: ``always_touching`` returning nothing -> "the start is in collision:
    base_link and table 3.000 mm deep"; fails.
    """
    robot = ur5()
    with caplog.at_level(logging.INFO, logger="scara_opt.collision.checker"):
        checker = so.CollisionChecker(robot, table_cell(tmp_path))
    names = [b.name for b in checker.geometry.bodies]
    assert names == ["base_link", "shoulder_link", "upper_arm_link", "forearm_link",
                     "wrist_1_link", "wrist_2_link", "wrist_3_link", "ee_link"]
    assert list(checker.always) == [("base_link", "table")]
    assert "fixed in the world" in checker.skipped[("base_link", "table")]
    assert "base_link and table are always in contact" in caplog.text
    q = np.array([0.0, -1.2, 1.0, -1.0, -1.5, 0.0])
    traj = so.plan(robot, [so.PTP(q - 0.2)], start=q, cell=checker, amax=5.0)
    assert traj.duration > 0
    kept = so.CollisionChecker(robot, checker.cell, check_touching=True)
    assert ("base_link", "table") in kept.pair_names
    with pytest.raises(so.CollisionError, match=r"base_link and table \d\.\d{3} mm deep"):
        so.plan(robot, [so.PTP(q - 0.2)], start=q, cell=kept, amax=5.0)
    named = so.CollisionChecker(robot, checker.cell, check_touching=True,
                                allowed=[("base_link", "table")])
    assert ("base_link", "table") not in named.pair_names
    with pytest.raises(so.UnknownBodyError, match="no body named 'base'.*base_link.*ee_link"):
        so.CollisionChecker(robot, checker.cell, allowed=[("base", "table")])


@pytest.fixture(scope="module")
def mesh_checker(tmp_path_factory):
    return so.CollisionChecker(ur5(), table_cell(tmp_path_factory.mktemp("cell")))


def test_the_bound_never_exceeds_the_exact_mesh_distance(mesh_checker):
    """600 random configurations of the UR5 among a table, a box and an STL bracket: for
    every pair, the proofs' bound (the trees of hulls, exact where small) is never above
    coal's exact distance, at rest never above the distance with the solids; the reported
    distance is the reference's. The batch runs warm, as a query does: each hull's GJK
    support walk starts from its last vertex, and GJK's ray from the two balls' centres.

    Mutation caught: ``lower`` returning its bound plus 1 mm (``+ 1e-3`` for ``- 1e-9``) ->
    fails. Mutation caught: a node's hull built from half its triangles' vertices
    (``points[: len(points) // 2]`` in ``mesh_parts``) -> a bound above the distance; fails.
    Mutation caught: where the surfaces meet, ``bound`` returning ``lower``'s value (about
    -2e-6 m: its GJK runs without EPA) instead of the holding balls' depth -> 142 bounds of
    4,300 above the signed distance (seen); fails.
    """
    checker = mesh_checker
    robot = checker.robot
    Q = np.random.default_rng(0).uniform(robot.lower, robot.upper, (600, robot.nq))
    ref, surface = _reference(checker, Q, surface=True)
    bound = checker.pair_distances(Q, None, "bound")
    rest = checker.pair_distances(Q, None, "rest")
    exact = checker.distances_many(Q)
    assert (bound <= surface + 1e-9).all(), float((bound - surface).max())
    assert (rest <= np.maximum(ref, 0.0) + 1e-9).all()
    assert ((rest <= 0) | (ref > 0)).all()  # a body inside a solid: a contact at rest
    apart = ref > 1e-9
    assert np.abs(exact[apart] - ref[apart]).max() < 1e-9
    assert ((exact <= 0) == (ref <= 0))[np.abs(ref) > 1e-9].all()
    assert (bound > 0.02).mean() > 0.3 and ((bound > 0) & (bound < 0.02)).any()


def test_mesh_verdicts_agree_with_the_reference(mesh_checker, monkeypatch):
    """600 configurations: ``collides``, ``collides_many`` (1 and 2 threads) and the
    Python form all say contact exactly where the reference distance is <= 0 (away from
    1e-9 m), and the collision check costs what Pinocchio's does (measured in the
    benchmark, not here).

    With a 5 mm margin, the same against the reference's 5 mm.

    Mutation caught: the quick stage trusting coal's collision test to say "free" too
    (``rest`` skipped) -> the pairs within the margin missed; fails.
    """
    checker = mesh_checker
    robot = checker.robot
    rng = np.random.default_rng(1)
    Q = rng.uniform(robot.lower, robot.upper, (600, robot.nq))
    ref = _reference(checker, Q)
    want = (ref <= 0).any(axis=1)
    sure = (np.abs(ref) > 1e-9).all(axis=1)
    assert np.array_equal(checker.collides_many(Q)[sure], want[sure])
    assert np.array_equal(checker.collides_many(Q, threads=2)[sure], want[sure])
    assert [checker.collides(q) for q in Q[:100]] == want[:100].tolist()
    python = so.CollisionChecker(robot, checker.cell)
    monkeypatch.setattr(python, "_kernel", lambda: None)
    assert np.array_equal(python.collides_many(Q[:300])[sure[:300]], want[:300][sure[:300]])
    assert 0.2 < want.mean() < 0.95
    wide = checker.with_margin(0.005)  # within 5 mm but apart: coal's test says nothing
    near = (ref < 0.005).any(axis=1)
    sure = (np.abs(ref - 0.005) > 1e-9).all(axis=1)
    assert np.array_equal(wide.collides_many(Q)[sure], near[sure])
    assert (near & ~want).any()


def _stl_box(path, size_mm, open_face=False, subdivide=0):
    box = trimesh.creation.box(size_mm)
    for _ in range(subdivide):  # faces of many triangles: the tree's leaves are patches
        box = box.subdivide()
    if open_face:
        box = trimesh.Trimesh(box.vertices, box.faces[2:], process=False)
    box.export(path)
    return path


def test_a_body_inside_a_closed_mesh_is_a_contact_as_inside_a_box(tmp_path, caplog):
    """zavar2024's arm wholly inside a closed STL block: a contact, as inside the same Box
    (was collides False against -1035 mm for the Box); an open STL block is a surface (no
    contact inside it) and loading it says so.

    Mutation caught: the inside test left out of the kernel's verdict where the surfaces
    are apart (``rest``'s first branch ``false``) -> False for the finely meshed block
    (768 triangles: its tree's leaves are patches of faces); fails. Mutation caught: every
    mesh taken as closed (``is_closed`` returning True) -> the open block a contact; fails.
    """
    q = np.zeros(4)
    block = so.Box("block", (1.0, 1.0, 0.6), xyz=(0.0, 0.0, -0.05))
    closed = so.Mesh("block", _stl_box(tmp_path / "closed.stl", (1000, 1000, 600)),
                     scale=(1e-3,) * 3, xyz=block.xyz)
    fine = so.Mesh("block", _stl_box(tmp_path / "fine.stl", (1000, 1000, 600), subdivide=3),
                   scale=(1e-3,) * 3, xyz=block.xyz)
    for cell in (so.Cell([block]), so.Cell([closed]), so.Cell([fine])):
        checker = so.CollisionChecker(SCARA, cell, check_touching=True)
        assert checker.collides(q) and checker.collides_many(q[None])[0]
        assert checker.clearance(q).distance < 0
    with caplog.at_level(logging.WARNING):
        hollow = so.Mesh("block", _stl_box(tmp_path / "open.stl", (1000, 1000, 600),
                                           open_face=True), scale=(1e-3,) * 3, xyz=block.xyz)
        checker = so.CollisionChecker(SCARA, so.Cell([hollow]), check_touching=True)
    assert not checker.collides(q) and checker.clearance(q).distance > 0
    assert "is open" in caplog.text


def test_a_capsule_along_a_mesh_face_diagonal_is_a_contact(tmp_path, monkeypatch):
    """link1 of zavar2024 lying exactly along the diagonal of a mesh block's top face (coal's
    distance there is -DBL_MAX): a contact, no deeper than the bodies' balls allow, by the
    kernel and the Python form alike.

    Mutation caught: ``surface`` without its clamp -> clearance -1.8e308 m; fails.
    Mutation caught: the Python form's clamp left out (``MeshPairs.corrected``) -> fails.
    """
    stl = _stl_box(tmp_path / "block.stl", (141.42135623730951, 141.42135623730951, 50))
    cell = so.Cell([so.Mesh("block", stl, scale=(1e-3,) * 3, xyz=(0.1, 0.0, -0.025),
                            rpy=(0.0, 0.0, -math.pi / 4))])  # its top's diagonal along x
    q = np.zeros(4)
    for form in ("kernel", "python"):
        checker = so.CollisionChecker(SCARA, cell, check_touching=True)
        if form == "python":
            monkeypatch.setattr(checker, "_kernel", lambda: None)
        c = checker.clearance(q)
        assert checker.collides(q) and -1.0 < c.distance <= 0, (form, c)
        assert c.bodies[1] == "block"


def _slotted_plate(path):
    """A 4 mm plate in mm with a 40 mm slot along x: two boxes in one mesh (its tree's one
    leaf holds both: that leaf's hull covers the slot)."""
    halves = [trimesh.creation.box((300, 95, 4)), trimesh.creation.box((300, 95, 4))]
    halves[0].apply_translation((0, -67.5, 0))
    halves[1].apply_translation((0, 67.5, 0))
    trimesh.util.concatenate(halves).export(path)
    return path


def test_a_quill_through_a_slot_of_a_thin_mesh_fixture_is_proven_clear(tmp_path):
    """zavar2024's quill (30 mm wide) moved along a 40 mm slot of a 4 mm STL plate: the
    hulls' bound there is no distance (the leaf's hull covers the slot), the exact one is 5
    mm: the LIN is proven clear, and a LIN across the slot's edge is refused.

    Mutation caught: the bound without its exact fallback (``bound`` returning the tree's
    bound below the shift) -> every configuration in the slot taken as a contact, the LIN
    refused; fails.
    """
    stl = _slotted_plate(tmp_path / "slot.stl")
    cell = so.Cell([so.Mesh("plate", stl, scale=(1e-3,) * 3, xyz=(0.3, 0.0, -0.08))])
    checker = so.CollisionChecker(SCARA, cell)
    a, b = so.Target([0.24, 0.0, -0.09]), so.Target([0.36, 0.0, -0.09])
    start = so.ik_all(SCARA, a)[0].q
    assert checker.pair_distances(start[None], None, "bound").min() > 0.004
    traj = so.plan(SCARA, [so.LIN(b, speed=0.1)], start=start, cell=checker)
    report = traj.check_collisions()
    assert report.clear and 0.004 < report.least.distance < 0.0051
    with pytest.raises(so.MoveCollisionError, match="plate"):
        so.plan(SCARA, [so.LIN(so.Target([0.3, 0.05, -0.09]))], start=start, cell=checker)


def test_bad_mesh_files_say_which_file_and_what_to_change(tmp_path, caplog):
    """A missing, unreadable, empty or millimetre mesh read as metres (a fixture 300 m wide)
    is a specific error naming the file and what to change; an open one loads with one
    warning naming it; so does a robot's link mesh in mm without its URDF scale.

    Mutation caught: ``Mesh._inspect`` without the extent check -> the 300 m bracket
    accepted; fails.
    """
    with pytest.raises(so.MeshNotFoundError, match="nowhere.stl"):
        so.Mesh("m", tmp_path / "nowhere.stl")
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(b"\x00\x01 not a mesh" * 10)
    with pytest.raises(so.CellError, match="garbage.stl"):
        so.Mesh("m", garbage)
    empty = tmp_path / "empty.stl"
    empty.write_text("solid e\nendsolid e\n")
    with pytest.raises(so.CellError, match="empty.stl"):
        so.Mesh("m", empty)
    big = _bracket(tmp_path / "bracket.stl")
    with pytest.raises(so.CellError, match=r"bracket.stl' spans 200 m.*scale = 0.001"):
        so.Mesh("bracket", big)
    with caplog.at_level(logging.WARNING):
        so.Mesh("lid", _stl_box(tmp_path / "lid.stl", (100, 100, 60), open_face=True),
                scale=(1e-3,) * 3)
    assert "lid.stl" in caplog.text and "is open" in caplog.text
    urdf = UR5_URDF.read_text().replace("meshes/ur5/collision/forearm.stl",
                                        "meshes/ur5/collision/forearm_mm.stl")
    mesh_dir = UR5_URDF.parent.parent / "meshes" / "ur5" / "collision"
    scaled = trimesh.load(mesh_dir / "forearm.stl")
    scaled.apply_scale(1000.0)
    work = tmp_path / "example-robot-data" / "robots" / "ur_description"
    (work / "urdf").mkdir(parents=True)
    (work / "meshes" / "ur5" / "collision").mkdir(parents=True)
    for f in mesh_dir.glob("*.stl"):
        (work / "meshes" / "ur5" / "collision" / f.name).write_bytes(f.read_bytes())
    scaled.export(work / "meshes" / "ur5" / "collision" / "forearm_mm.stl")
    (work / "urdf" / "ur5.urdf").write_text(urdf)
    robot = so.Robot.from_urdf(work / "urdf" / "ur5.urdf", tip="ee_link")
    with pytest.raises(so.CellError, match=r"forearm_link.*forearm_mm.stl.*spans .* m.*scale"):
        so.CollisionChecker(robot)
