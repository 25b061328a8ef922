"""Collision-free PTPs through OMPL: every path re-checked densely here, honest failures."""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.planning import PlanStatus, plan_path
from tests.conftest import DATA, dense_first_contact, pinocchio_collides

ROBOT = so.load_robot("zavar2024")
POST = so.Cell([so.Cylinder("post", 0.03, 0.4, xyz=(0.3, 0.15, 0.0))])
QA, QB = np.array([-0.5, 0.5, 0.0, 0.0]), np.array([1.2, 0.5, 0.0, 0.0])


def dense_clear(checker, Q, step=1e-3):
    """Every configuration every ``step`` (rad or m) along the polyline Q is free."""
    return all(dense_first_contact(checker, a, b, step) is None
               for a, b in zip(Q[:-1], Q[1:], strict=True))


def dense_clear_trajectory(checker, traj, step=1e-3):
    """The timed trajectory sampled so no joint moves more than ``step`` between samples."""
    dt = step / traj.peaks()["velocity"].max()
    t = np.append(np.arange(0.0, traj.duration, dt), traj.duration)
    return not pinocchio_collides(checker, traj.evaluate(t)).any()


def test_planned_path_around_a_post_is_clear_and_reproducible():
    """The straight swing hits the post; the planned path avoids it (checked here every
    1e-3 rad), starts and ends where asked; the same seed gives the same path, another seed
    may give another.

    Mutation caught: the edge check skipped (checkMotion answering True): the planner then
    connects start and goal through the post and this test's dense check fails.
    Mutation caught: OMPL's seed not set (RNG.setSeed left out): two runs differ.
    """
    checker = so.CollisionChecker(ROBOT, POST)
    assert not dense_clear(checker, np.array([QA, QB]))
    a = plan_path(checker, QA, QB, seed=3)
    assert a.status == "solved" and a.success and a.planner == "RRTConnect"
    assert np.array_equal(a.path[0], QA) and np.array_equal(a.path[-1], QB)
    assert dense_clear(checker, a.path)
    b = plan_path(checker, QA, QB, seed=3)
    assert np.array_equal(a.path, b.path)
    assert a.length == pytest.approx(np.linalg.norm(np.diff(a.path, axis=0), axis=1).sum())
    assert "RRTConnect" in repr(a)


def test_straight_when_clear():
    """A segment proven clear is the path itself, no planner run."""
    checker = so.CollisionChecker(ROBOT, POST)
    qb = np.array([-1.0, 0.8, 0.02, 0.3])
    res = plan_path(checker, QA, qb)
    assert res.planner == "straight" and len(res.path) == 2 and res.tree_states == 0


def slot_cell(half_angle: float = 0.45) -> so.Cell:
    """Two walls from the column to beyond the arm's reach, at +-half_angle about x."""
    walls = []
    for name, a in (("left", half_angle), ("right", -half_angle)):
        r = 0.1 + 0.25  # the wall's middle: from r = 0.1 m to 0.6 m
        walls.append(so.Box(name, (0.5, 0.01, 0.3), xyz=(r * math.cos(a), r * math.sin(a),
                                                         -0.05), rpy=(0, 0, a)))
    return so.Cell(walls)


def test_enclosed_goal_ends_with_no_path_found():
    """The goal parks the arm in a slot between two walls that run from the column to
    beyond its reach: no motion leads in from a start outside. The status is no_path with
    what was tried, never unreachable, never a path; plan() raises NoPathFoundError.

    Mutation caught: a failed query reported as solved with OMPL's approximate path (any
    status but "Exact solution" accepted): a path through a wall comes back.
    """
    cell = slot_cell()
    checker = so.CollisionChecker(ROBOT, cell)
    goal, start = np.array([0.0, 0.0, 0.02, 0.0]), np.array([-1.5, 0.3, 0.02, 0.0])
    assert not checker.collides(goal) and not checker.collides(start)
    res = plan_path(checker, start, goal, time_limit=0.3)
    assert res.status == PlanStatus.NO_PATH and res.path is None and not res.success
    assert res.status != "unreachable"
    assert "no path found within the time limit" in res.message
    assert res.states > 0 and res.checks > 0 and res.tree_states > 0 and math.isnan(res.length)
    with pytest.raises(so.NoPathFoundError, match="no path found within the time limit") as e:
        so.plan(ROBOT, [so.PTP(goal)], start=start, cell=cell, time_limit=0.2)
    assert e.value.index == 0 and e.value.states > 0 and e.value.time_limit == 0.2


def test_rack_is_cleared_by_lifting_the_quill():
    """A low wall across the whole reach, under the arms but over a lowered tool: the only
    way across lifts the quill, and the planned path does.

    Mutation caught: the quill left out of the planner's box (its joint held at the start's
    value): no path is then found.
    """
    wall = so.Box("rack", (0.02, 1.2, 0.03), xyz=(0.25, 0.0, -0.095), rpy=(0, 0, 0.0))
    checker = so.CollisionChecker(ROBOT, so.Cell([wall]))
    start = so.ik_all(ROBOT, so.Target([0.15, 0.25, -0.09]))[0].q
    goal = so.ik_all(ROBOT, so.Target([0.35, 0.1, -0.09]), q0=start)[0].q
    assert not checker.collides(start) and not checker.collides(goal)
    res = plan_path(checker, start, goal, seed=1)
    assert res.success and dense_clear(checker, res.path)
    assert res.path[:, 2].min() < min(start[2], goal[2]) - 0.01  # lifted (z = -d3 - 0.05)


def test_start_goal_and_time_limit_errors():
    """Start or goal in collision name the bodies and the depth; out of limits names the
    joint; a time limit <= 0 is refused."""
    checker = so.CollisionChecker(ROBOT, POST)
    inside = np.array([0.4636, 0.0, 0.0, 0.0])  # stretched toward the post
    assert checker.collides(inside)
    with pytest.raises(so.CollisionError, match=r"start is in collision: link\d and post .* mm "
                                                r"deep") as e:
        plan_path(checker, inside, QB)
    assert e.value.bodies[1] == "post" and e.value.depth > 0
    with pytest.raises(so.CollisionError, match="goal is in collision"):
        plan_path(checker, QA, inside)
    with pytest.raises(so.JointLimitError, match="joint 'theta1'"):
        plan_path(checker, np.array([3.0, 0.0, 0.0, 0.0]), QB)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(so.InputError, match="time_limit"):
            plan_path(checker, QA, QB, time_limit=bad)
    with pytest.raises(so.CollisionError, match="start is in collision"):
        so.plan(ROBOT, [so.PTP(QB)], start=inside, cell=POST)
    with pytest.raises(so.MoveCollisionError, match="move 0: PTP: the goal is in collision"):
        so.plan(ROBOT, [so.PTP(inside)], start=QA, cell=POST)
    with pytest.raises(so.InputError, match="time_limit"):
        so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=POST, time_limit=0)


def _just_clear(checker, gap):
    """A configuration between QA and the post whose clearance is in (0, gap] [m]."""
    inside = np.array([0.4636, 0.0, 0.0, 0.0])
    lo, hi = QA.copy(), inside
    for _ in range(80):
        mid = (lo + hi) / 2
        d = checker.clearance(mid).distance
        if 0 < d <= gap:
            return mid
        lo, hi = (mid, hi) if d > 0 else (lo, mid)
    raise AssertionError("no configuration found")  # pragma: no cover


def test_a_start_too_close_for_a_proof_is_named_not_timed_out():
    """A start 1 µm from the post: clear (``collides`` is False), but closer than the 0.01
    mm a proof needs: refused at once naming the start, the bodies and the gap, never "no
    path found within the time limit ... give more time".

    Mutation caught: ``check_provable`` doing nothing -> NO_PATH after the time limit,
    "RRTConnect grew 0 states"; fails.
    """
    checker = so.CollisionChecker(ROBOT, POST)
    q = _just_clear(checker, 2e-6)
    assert not checker.collides(q)
    with pytest.raises(so.CollisionError, match=r"start is 0\.00\d+ mm from contact \(link\d "
                                                r"and post\).* at least .* mm farther"):
        plan_path(checker, q, QB, time_limit=0.3)
    with pytest.raises(so.CollisionError, match="goal is"):
        so.plan(ROBOT, [so.PTP(q)], start=QB, cell=checker, time_limit=0.3)


def test_compiling_the_kernel_does_not_count_against_the_time_limit(monkeypatch):
    """The first query on a cold cache (the kernel's build simulated by a 1.5 s pause in
    ``edge_kernel``): solved within a 1 s limit, with the same path as a warm query.

    Mutation caught: the clock started before the prover is built (as before) -> NO_PATH
    (or another path) on the cold query; fails.
    """
    import time as clock

    from scara_opt.planning import ompl_backend

    warm = plan_path(so.CollisionChecker(ROBOT, POST), QA, QB, seed=5, time_limit=1.0)
    real = ompl_backend.EdgeProver.__init__

    def slow(self, *args, **kwargs):
        clock.sleep(1.5)
        real(self, *args, **kwargs)

    monkeypatch.setattr(ompl_backend.EdgeProver, "__init__", slow)
    cold = plan_path(so.CollisionChecker(ROBOT, POST), QA, QB, seed=5, time_limit=1.0)
    assert cold.success and np.array_equal(cold.path, warm.path)
    assert cold.time_s < 1.5


def test_a_first_call_loads_its_libraries_before_the_clock_starts():
    """In a fresh interpreter, once a cell plan's clock starts, toppra and OMPL are loaded:
    their imports (toppra's pulls in matplotlib, 1-2 s) never count against the limit (the
    bundled pick-and-place program, 1 s, found no path for its PTP on a busy machine).

    Mutation caught: the imports dropped from ``CellPlanning.start_clock`` -> toppra not
    yet loaded when the clock starts; fails.
    """
    import subprocess
    import sys

    code = ("import sys, scara_opt as so\n"
            "from scara_opt.motion.clearance import CellPlanning\n"
            "r = so.load_robot('zavar2024')\n"
            "c = CellPlanning(so.CollisionChecker(r, so.Cell([so.Sphere('s', 0.01, "
            "xyz=(0.3, 0.3, 0.0))])), 1.0, 0)\n"
            "assert 'toppra' not in sys.modules\n"
            "c.start_clock()\n"
            "print(all(m in sys.modules for m in ('toppra', 'ompl.geometric', "
            "'toppra.solverwrapper.cy_seidel_solverwrapper')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "True", out.stderr


def test_ptp_in_a_cell_is_timed_and_proven_clear_again():
    """A PTP around the post: toppra's trajectory (not the planned polyline) is clear at
    1e-3 rad steps, within the joint limits, and check_limits says so.

    Mutation caught: the planned path timed through its vertices alone and the timed
    trajectory not checked again (the polyline trusted): the spline then leaves the joint
    limits between waypoints (the assertion on ``position_range``).
    """
    checker = so.CollisionChecker(ROBOT, POST)
    for seed in range(4):
        traj = so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=POST, seed=seed)
        assert dense_clear_trajectory(checker, traj)
        lo, hi = traj.position_range()
        assert (lo >= ROBOT.lower - 1e-9).all() and (hi <= ROBOT.upper + 1e-9).all()
        ratios = traj.check_limits()
        assert ratios["clearance"][0] <= 1 and ratios["velocity"].max() <= 1 + 1e-9
        assert "planned around the cell" in traj.notes


def test_ptp_target_takes_a_clear_ik_branch():
    """A Target whose nearest IK branch puts the forearm through a post takes the other
    branch, which is clear.

    Mutation caught: the PTP goal taken as the nearest IK solution without looking at the
    cell: a MoveCollisionError for the goal.
    """
    cell = so.Cell([so.Cylinder("post", 0.02, 0.4, xyz=(0.25, 0.1, 0.0))])
    target = so.Target([0.23, 0.18, -0.07])
    checker = so.CollisionChecker(ROBOT, cell)
    start = np.array([-1.29, 1.5, 0.02, 0.0])
    near, far = so.ik_all(ROBOT, target, q0=start)
    assert checker.collides(near.q) and not checker.collides(far.q)
    traj = so.plan(ROBOT, [so.PTP(target)], start=start, cell=cell)
    assert np.allclose(traj.waypoints[-1], far.q)
    assert dense_clear_trajectory(checker, traj)


def test_out_of_limits_start_or_goal_refused_with_or_without_a_cell():
    """A joint goal or a start outside the limits is refused naming the joint, in a cell or
    not (before, plan() timed a PTP to theta1 = 5.2 rad on a +-2.09 rad joint).

    Mutation caught: the PTP joint goal checked for its shape only (robot.check_q).
    """
    far = np.array([5.2, 0.0, 0.0, 0.0])
    for cell in (None, POST):
        with pytest.raises(so.MoveError, match="PTP goal: joint 'theta1' = 5.2 rad is outside"):
            so.plan(ROBOT, [so.PTP(far)], start=QA, cell=cell)
        with pytest.raises(so.JointLimitError, match="start: joint 'theta1'"):
            so.plan(ROBOT, [so.PTP(QB)], start=far, cell=cell)


def test_cycle_time_in_a_cell_plans_around_a_block():
    """A block on the straight way between the cycle's pick and place: the cycle is planned
    around it (same placement), proven clear, and takes longer than without it; a cell that
    blocks every placement is refused saying so.

    Mutation caught: cycle_time ignoring cell= (the straight PTP through the block: the
    dense check here fails).
    """
    from scara_opt.motion.cycle import place_cycle

    A, B, _, _ = place_cycle(ROBOT, 0.025, 0.2, 0.025)
    mid = (A + B) / 2
    cell = so.Cell([so.Box("block", (0.04, 0.04, 0.04), xyz=(mid[0], mid[1], -0.075))])
    free = so.cycle_time(ROBOT, across=0.2)
    res = so.cycle_time(ROBOT, across=0.2, cell=cell)
    assert np.allclose(res.pick, A) and np.allclose(res.place, B)
    checker = so.CollisionChecker(ROBOT, cell)
    assert dense_clear_trajectory(checker, res.trajectory)
    assert res.durations["toppra"] > free.durations["toppra"]
    wall = so.Cell([so.Box("floor", (2, 2, 0.02), xyz=(0, 0, -0.08))])
    with pytest.raises(so.InputError, match="plans clear of the cell"):
        so.cycle_time(ROBOT, across=0.2, cell=wall)


def test_ptp_in_a_cell_under_torque_limits():
    """A PTP planned around the post and timed by toppra under the robot's torque limits:
    torques within them (1 kHz RNEA) and the trajectory proven clear."""
    traj = so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=POST, torque_limits=True, seed=1)
    ratios = traj.check_limits()
    assert ratios["torque"].max() <= 1 + 1e-6 and ratios["clearance"][0] <= 1
    assert dense_clear_trajectory(so.CollisionChecker(ROBOT, POST), traj)


def test_last_resort_stops_at_every_waypoint(monkeypatch):
    """When no spline through the planned waypoints is proven clear, the section is timed
    straight from waypoint to waypoint, at rest at each (exactly the proven polyline): the
    joint speed is zero at every waypoint and the dense check holds.

    Mutation caught: the segments timed but not laid end to end in time (each from t = 0):
    the waypoint times then do not increase and the speeds there are not zero.
    """
    import importlib

    clearance = importlib.import_module("scara_opt.motion.clearance")
    monkeypatch.setattr(clearance, "RETRIES", -2)  # no spline tried: the last resort
    traj = so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=POST, seed=3)
    assert "stopping at each waypoint" in traj.notes
    knots = traj.profiles[0][0]
    assert len(knots) > 2 and (np.diff(knots) > 0).all()
    assert np.abs(traj.evaluate(knots, 1)).max() < 1e-9
    assert dense_clear_trajectory(so.CollisionChecker(ROBOT, POST), traj)


def test_edge_prover_remembers_its_verdicts():
    """An edge proven once is not proven again, in either direction (no configuration is
    computed: the simplified path's final re-check costs nothing for the edges it kept); an
    edge that was refused is refused again, in either direction, also without computing
    (OMPL's rope shortcut asks the same far edges after each shortcut).

    Mutation caught: the cache not consulted (``if (a, b) in self.known`` dropped): the
    second pass computes midpoints again. Mutation caught: an edge remembered before it is
    proven (``known.add`` at the top of ``edge``): the refused swing through the post
    passes on the second ask. Mutation caught: refusals not remembered (``if (a, b) in
    self.refused`` dropped): the second ask computes configurations again.
    """
    from scara_opt.planning.ompl_backend import EdgeProver

    checker = so.CollisionChecker(ROBOT, POST)
    path = plan_path(checker, QA, QB, seed=3).path
    prover = EdgeProver(checker)
    assert prover.path(path) and prover.midpoints > 0
    before = prover.configurations
    assert prover.path(path) and prover.path(path[::-1].copy())
    assert prover.configurations == before
    a, b = tuple(QA.tolist()), tuple(QB.tolist())
    assert not prover.edge(a, b)
    before = prover.configurations
    assert not prover.edge(a, b) and not prover.edge(b, a)
    assert prover.configurations == before


def test_pieces_of_a_proven_edge_are_known_and_a_stray_piece_is_proven():
    """The pieces OMPL makes of proven edges (halves ``a + 0.5 (c - a)``, halves of those,
    rounded) are taken as proven without computing a configuration. Refused or proven
    anew: a piece whose end strays a few hundredths of a radian off its edge, into the post
    (0.05 rad here); one reaching past
    the edge's end; one 0.8 of the slack off and then one from there 0.8 off again.

    Mutation caught: the stray not bounded (``inside_known`` taking any t in [0, 1]): the
    piece into the post passes. Mutation caught: pieces not looked for (``inside_known``
    returning False): the halves compute midpoints. Mutation caught: t not bounded by 1:
    the piece past the end passes unproven. Mutation caught: the stray of the first end
    only (``zip(ends[:1], ...)``): the piece into the post passes.
    """
    from scara_opt.planning.ompl_backend import SUBSEGMENT_SLACK, EdgeProver

    checker = so.CollisionChecker(ROBOT, POST)
    path = plan_path(checker, QA, QB, seed=3).path
    prover = EdgeProver(checker)
    assert prover.path(path)
    before = prover.configurations
    prover.pieces = True  # as for a simplified path's final check

    def key(q):
        return tuple(q.tolist())

    for a, c in zip(path[:-1], path[1:], strict=True):
        m = a + 0.5 * (c - a)
        m1, m2 = a + 0.5 * (m - a), m + 0.5 * (c - m)
        for x, y in ((a, m), (m, c), (c, m), (a, m1), (m1, m), (m1, m2), (m2, c)):
            assert prover.edge(key(x), key(y))
    assert prover.configurations == before
    a, c, stray = next((a, c, m) for d in (0.02, -0.02, 0.05, -0.05, 0.1, -0.1)
                       for a, c in zip(path[:-1], path[1:], strict=True)
                       if checker.collides(m := a + 0.5 * (c - a) + np.array([d, 0, 0, 0])))
    assert not prover.edge(key(a), key(stray))
    before = prover.configurations
    prover.edge(key(a + 0.5 * (c - a)), key(c + 0.3 * (c - a)))
    assert prover.configurations > before

    def off(x, d):  # 0.8 of the slack off the line along d, 0.4 of the way
        u = np.array([0.3, -0.2, 0.01, 0.5])
        u -= (u @ d) / (d @ d) * d
        return x + 0.4 * d + 0.8 * SUBSEGMENT_SLACK / float((prover.W @ np.abs(u)).max()) * u

    y = off(a, c - a)
    before = prover.configurations
    assert prover.edge(key(a), key(y)) and prover.configurations == before
    z = off(y, c - y)
    assert prover.edge(key(y), key(z)) and prover.configurations > before


def test_the_final_check_of_a_simplified_path_proves_nothing_again(monkeypatch, tmp_path):
    """Around the post as an STL mesh (4 seeds): the simplified path's final check, edge by
    edge, computes no configuration: its edges were proven in the simplifier or are pieces
    of such edges.

    Mutation caught: pieces not looked for in the final check (``prover.pieces`` left
    False in ``_solve``): the smoother's halves are proven again.
    """
    import trimesh

    from scara_opt.planning import ompl_backend

    computed = []
    real = ompl_backend.EdgeProver.path

    def path(self, Q):
        before = self.configurations
        clear = real(self, Q)
        computed.append(self.configurations - before)
        return clear

    monkeypatch.setattr(ompl_backend.EdgeProver, "path", path)
    stl = tmp_path / "post.stl"
    trimesh.creation.cylinder(radius=30.0, height=400.0, sections=24).export(stl)
    post = so.Cell([so.Mesh("post", stl, scale=(1e-3,) * 3, xyz=(0.3, 0.15, 0.0))])
    checker = so.CollisionChecker(ROBOT, post)
    for seed in range(4):
        assert plan_path(checker, QA, QB, seed=seed).status == "solved"
    assert len(computed) == 4 and computed == [0, 0, 0, 0]


def test_a_spline_through_the_waypoints_that_hits_the_cell_is_not_timed():
    """A proven polyline (5 waypoints, zavar2024 around a column) whose toppra spline through
    the waypoints alone cuts 5.5 mm into the column: the section is timed through more
    points, after their spline is proven, and the trajectory is clear (dense check here)
    and within the joint limits.

    Mutation caught: the spline's proof ignored (``_spline_clear`` returning the failed
    proof): the first spline is timed and the dense check finds the column.
    """
    from scara_opt.collision.continuous import check_path
    from scara_opt.motion.timing import section_spline
    from scara_opt.planning.ompl_backend import EdgeProver
    from scara_opt.trajectory.limits import resolve_limits

    cell = so.Cell([so.Cylinder("column", 0.03, 0.4, xyz=(0.28, 0.12, 0.0))])
    checker = so.CollisionChecker(ROBOT, cell)
    Q = np.array([[1.84, 1.437, 0.037, -0.44], [0.398, 1.687, 0.041, -0.598],
                  [-1.043, 1.936, 0.045, -0.757], [-0.226, 0.307, 0.041, 0.161],
                  [0.592, -1.322, 0.036, 1.079]])
    limits = resolve_limits(ROBOT, ROBOT.nq, None, None)
    assert EdgeProver(checker).path(Q)
    first = check_path(checker, section_spline(Q, limits).cspl)
    assert not first.clear and first.contact.depth > 0.005

    traj, note = time_planned(checker, Q, limits)
    assert "(attempt 1)" not in note and "proven clear (the spline it follows" in note
    assert dense_clear_trajectory(checker, traj)
    lo, hi = traj.position_range()
    assert (lo >= ROBOT.lower - 1e-9).all() and (hi <= ROBOT.upper + 1e-9).all()


def time_planned(checker, Q, limits):
    """CellPlanning.timed_clear of the planned polyline Q with toppra: (trajectory, note)."""
    import importlib

    from scara_opt.motion.timing import time_section
    from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
    from scara_opt.planning.planner import PathPlan

    clearance = importlib.import_module("scara_opt.motion.clearance")

    def timed(rows, owner):
        profile = ToolProfile.per_point([ToolLimits()] * len(rows))
        return (*time_section(ROBOT, rows, limits, profile), profile)

    cp = clearance.CellPlanning(checker, 1.0, 0)
    cp.plans[0] = PathPlan(PlanStatus.SOLVED, Q, "", "RRTConnect", 0.0, 0, 0, 0, 0.0, 0)
    part, note, knots, _ = cp.timed_clear([(0, so.PTP(Q[-1]))], Q, [0] * len(Q), timed,
                                          limits, "toppra", 0.0)
    return so.Trajectory(part, limits, "toppra", Q, knots), note


def test_a_spline_through_the_waypoints_that_leaves_the_limits_is_not_timed():
    """A planned polyline with a corner 4 mrad inside theta1's upper limit: the spline
    through its waypoints alone overshoots the limit by 0.9 mrad (its exact range); the
    section is timed through more points and stays within the limits.

    Mutation caught: the spline's range not checked (``_spline_clear`` without the limit
    test): the trajectory comes back beyond the limit.
    """
    from scara_opt.motion.timing import section_spline
    from scara_opt.trajectory.limits import resolve_limits
    from scara_opt.trajectory.trajectory import cubic_range

    checker = so.CollisionChecker(ROBOT)  # its own links only
    Q = np.array([[0.5, -1.5, 0.02, 0.0], [2.09, 0.0, 0.02, 0.0], [1.6, 1.0, 0.02, 0.0],
                  [1.0, 1.2, 0.02, 0.0]])
    limits = resolve_limits(ROBOT, ROBOT.nq, None, None)
    assert cubic_range(section_spline(Q, limits).cspl)[1][0] > ROBOT.upper[0] + 5e-4
    traj, note = time_planned(checker, Q, limits)
    assert "(attempt 1)" not in note
    lo, hi = traj.position_range()
    assert (lo >= ROBOT.lower - 1e-9).all() and (hi <= ROBOT.upper + 1e-9).all()


def test_section_spline_and_toppra_constraints_are_kept_by_their_inputs():
    """The spline a section is proven along is the object toppra times (kept by waypoints
    and velocity limits), and toppra's joint constraints are kept by both limits: other
    limits give another spline and another timing.

    Mutation caught: the spline kept by the waypoints alone (``vmax`` out of the key): the
    chord parameter of other velocity limits is not recomputed. Mutation caught: the
    constraints kept by the velocity limits alone: halving the acceleration limits does
    not slow the section.
    """
    from scara_opt.motion.timing import section_spline, time_section
    from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
    from scara_opt.trajectory.limits import resolve_limits
    from scara_opt.trajectory.toppra_backend import chord_parameter

    Q = np.array([QA, [0.2, 1.4, 0.01, 0.3], QB])
    fast = resolve_limits(ROBOT, ROBOT.nq, None, None)
    spline = section_spline(Q, fast)
    assert section_spline(Q.copy(), fast) is spline
    vmax = ROBOT.velocity_limit * np.array([1.0, 0.2, 1.0, 1.0])
    other = resolve_limits(ROBOT, ROBOT.nq, vmax, None)
    assert np.array_equal(section_spline(Q, other).ss_waypoints, chord_parameter(Q, vmax))
    profile = ToolProfile.per_point([ToolLimits()] * len(Q))
    slow = resolve_limits(ROBOT, ROBOT.nq, None, ROBOT.acceleration_limit / 2)
    t_fast = time_section(ROBOT, Q, fast, profile)[2][-1]
    t_slow = time_section(ROBOT, Q, slow, profile)[2][-1]
    assert t_slow > 1.05 * t_fast


def test_apart_spans_agree_with_the_gaps_at_both_ends():
    """The span of a segment where a pair is apart along a SCARA's axis, worked out once per
    edge, says what the gaps at an interval's two ends say (positive at both: apart all
    along, the gaps being affine), on random gaps and intervals, ends included.

    Mutation caught: a gap falling to zero at ``s*`` taken as positive beyond it (the span
    ``(-inf, s*)`` written ``(s*, inf)``): intervals past ``s*`` are called apart.
    Mutation caught: a gap of exactly zero at an end taken as positive (``ga >= 0``): an
    interval starting where the bodies are level is called apart.
    """
    from scara_opt.planning.ompl_backend import _apart, _apart_spans

    rng = np.random.default_rng(4)
    for _ in range(400):
        up = rng.normal(size=(2, 3)).round(1)  # rounded: gaps of exactly 0 occur too
        down = rng.normal(size=(2, 3)).round(1)
        G = ((up[0].tolist(), down[0].tolist()), (up[1].tolist(), down[1].tolist()))
        for k in range(3):
            u0, u1, v0, v1 = _apart_spans(G, k)
            for lo, hi in (sorted(rng.uniform(0, 1, 2)), (0.0, 1.0), (0.0, 0.5), (0.5, 1.0)):
                inside = u0 < lo and hi < u1 or v0 < lo and hi < v1
                assert inside == _apart(G, k, lo, hi), (G, k, lo, hi)


def test_edges_interpolate_as_numpy_only_on_linear_joints():
    """An edge's configurations come from pinocchio's interpolation only for a model whose
    joints are all revolute or prismatic about one axis, where it is ``qa + s (qb - qa)`` to
    the bit; a continuous joint (cos/sin coordinates) keeps numpy's.

    Mutation caught: ``_linear`` true for any model: the continuous joint's model passes.
    """
    import pinocchio as pin

    from scara_opt.planning.ompl_backend import _linear

    robot = so.load_robot("zavar2024")
    assert _linear(robot.model)
    qa, qb = np.array([0.1, 0.2, -0.05, 0.3]), np.array([1.0, -0.5, -0.02, 1.2])
    for s in np.linspace(0.0, 1.0, 17):
        assert np.array_equal(pin.interpolate(robot.model, qa, qb, s), qa + s * (qb - qa))
    urdf = ("<robot name='c'><link name='a'/><link name='b'/><joint name='j' type='continuous'>"
            "<parent link='a'/><child link='b'/><axis xyz='0 0 1'/></joint></robot>")
    assert not _linear(pin.buildModelFromXML(urdf))


def test_the_simplifier_shortens_every_path_and_keeps_it_clear():
    """Around a post, six seeds: the simplified path (rope shortcut, partial shortcuts,
    smoothing) is at most 0.8 of the planner's raw path each time (measured: 0.51-0.68),
    starts and ends where asked, and is clear by the dense check here.

    Mutation caught: simplify_path doing nothing: the ratio is 1.
    """
    checker = so.CollisionChecker(ROBOT, POST)
    for seed in range(6):
        short = plan_path(checker, QA, QB, seed=seed)
        raw = plan_path(checker, QA, QB, seed=seed, simplify=False)
        assert short.length <= 0.8 * raw.length
        assert np.array_equal(short.path[0], QA) and np.array_equal(short.path[-1], QB)
        assert dense_clear(checker, short.path)


def _close_pass():
    """zavar2024 in the example cell, and the first random clear pair (seeded) whose plan at
    no margin passes within 2 mm of the cell (0.44 mm from the column when this was found),
    with that plan."""
    cell = so.load_cell(DATA.parent.parent / "examples" / "scara_cell.toml")
    checker = so.CollisionChecker(ROBOT, cell)
    rng = np.random.default_rng(0)
    for _ in range(200):
        a, b = rng.uniform(ROBOT.lower, ROBOT.upper, (2, 4))
        if min(checker.clearance(a).distance, checker.clearance(b).distance) <= 2.1e-3:
            continue
        loose = so.plan(ROBOT, [so.PTP(b)], start=a, cell=checker)
        if loose.check_collisions().least.distance < 0.002:
            return cell, checker, a, b, loose
    raise AssertionError("no pair passing within 2 mm found")  # pragma: no cover


def test_a_margin_asked_for_is_kept_on_every_route():
    """margin=2 mm on every route that takes it: plan with a checker (which has none) and
    with a Cell, cycle_time with a checker, check_collisions of a Trajectory and of a
    MotionTrajectory; each keeps or reports against 2 mm, and the planned move stays 2 mm
    clear by a dense check; margin= without a cell is refused.

    Mutation caught: ``make_checker`` keeping a checker's own margin (as before) -> the
    plan with a checker passes within 0.44 mm of the column; fails. Mutation caught:
    ``in_cell`` accepting a margin without a cell -> no error; fails.
    """
    cell, checker, a, b, loose = _close_pass()  # the symptom without a margin
    wide = so.CollisionChecker(ROBOT, cell, margin=0.002)
    for route in (checker, cell):
        traj = so.plan(ROBOT, [so.PTP(b)], start=a, cell=route, margin=0.002)
        assert traj.checker.margin == 0.002
        report = traj.check_collisions()
        assert report.clear and report.margin == 0.002 and report.least.distance >= 0.002
        assert dense_clear_trajectory(wide, traj)
    res = so.cycle_time(ROBOT, across=0.2, cell=checker, margin=0.002)
    assert res.trajectory.checker.margin == 0.002
    timed = so.time_parameterize(np.array([a, b]), ROBOT)
    assert timed.check_collisions(checker, margin=0.002).margin == 0.002
    assert timed.check_collisions(cell, ROBOT, margin=0.002).margin == 0.002
    assert loose.check_collisions(margin=0.002).margin == 0.002
    assert loose.check_collisions().margin == 0.0
    with pytest.raises(so.InputError, match="margin"):
        so.plan(ROBOT, [so.PTP(b)], start=a, margin=0.002)
    with pytest.raises(so.InputError, match="margin"):
        so.cycle_time(ROBOT, margin=0.002)


def test_the_largest_seed_is_refused_before_any_work():
    """seed=2**64-1 (OMPL's seed + 1 would not fit in its unsigned 64 bits) is an InputError
    naming the range even where the straight segment is blocked (it was a TypeError from
    OMPL), and the largest seed it takes plans.

    Mutation caught: ``SEED_MAX`` not passed to ``check_int`` -> TypeError from OMPL; fails.
    """
    checker = so.CollisionChecker(ROBOT, POST)
    with pytest.raises(so.InputError,
                       match=r"seed must be an integer in \[0, 18446744073709551614\]"):
        plan_path(checker, QA, QB, seed=2**64 - 1)
    with pytest.raises(so.InputError, match="seed"):
        so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=checker, seed=2**64 - 1)
    assert plan_path(checker, QA, QB, seed=2**64 - 2).success


class _Clock:
    """A stand-in for ``time``: ``perf_counter`` advances ``step`` s at every call."""

    def __init__(self, step):
        self.now, self.step = 0.0, step

    def perf_counter(self):
        self.now += self.step
        return self.now


def test_the_simplifier_stops_at_the_time_limit(monkeypatch):
    """With a clock that stands still while RRTConnect plans and runs 50 ms at each reading
    in the simplifier, a 1 s limit ends the simplifier part way: the path is the shortest
    proven by then (every edge proven, the dense check clear), and the plan says the
    simplifier was stopped.

    Mutation caught: ``EdgeProver.edge`` ignoring its deadline (the simplifier unbounded,
    as before) -> no edge answered late, the message says nothing; fails.
    """
    from scara_opt.planning import ompl_backend

    checker = so.CollisionChecker(ROBOT, POST)
    clock, simplify = _Clock(0.0), ompl_backend.simplify_path

    def slow_simplify(*args):
        clock.step = 0.05
        simplify(*args)

    monkeypatch.setattr(ompl_backend, "time", clock)
    monkeypatch.setattr(ompl_backend, "simplify_path", slow_simplify)
    res = plan_path(checker, QA, QB, seed=3, time_limit=1.0)
    assert res.success and "stopped at the time limit" in res.message
    assert dense_clear(checker, res.path)
    monkeypatch.undo()
    free = plan_path(checker, QA, QB, seed=3, time_limit=1.0)
    assert "stopped at the time limit" not in free.message


def test_a_program_past_its_time_limit_is_timed_the_way_proven_by_construction(monkeypatch):
    """so.plan whose clock runs out while the planned PTP is timed: no more spline tries
    after the first (the time limit bounds the whole call), the section stops at each
    waypoint, proven clear (the dense check agrees), and its note says why.

    Mutation caught: ``timed_clear`` trying every spline whatever the time -> the note says
    "attempt"; fails.
    """
    from scara_opt.motion import clearance

    checker = so.CollisionChecker(ROBOT, POST)
    real = clearance.CellPlanning.joints

    def joints(self, *args):
        path = real(self, *args)
        self.deadline = -math.inf  # as if the planning had used the whole limit
        return path

    monkeypatch.setattr(clearance.CellPlanning, "joints", joints)
    monkeypatch.setattr(clearance.CellPlanning, "_spline_clear", lambda self, rows, limits:
                        None)  # the first spline is not proven: a retry would follow
    traj = so.plan(ROBOT, [so.PTP(QB)], start=QA, cell=checker, time_limit=1.0)
    assert "stopping at each waypoint (the time limit was reached)" in traj.notes
    assert dense_clear_trajectory(checker, traj)


def test_a_section_timed_with_peak_bounds_is_the_one_timed_with_exact_peaks(monkeypatch):
    """``_joint_peaks`` returns the peaks' Bernstein bounds where both ratios are <= 1
    (no stretch, as with the exact peaks) and the exact peaks otherwise: the timed
    sections of random polylines are the same to the bit as with the exact peaks alone.

    Mutation caught: the bounds returned whatever they are (the ``<= 1.0`` test
    dropped): sections stretched more than the exact peaks need.
    """
    from scara_opt.motion import timing
    from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
    from scara_opt.trajectory.limits import resolve_limits

    limits = resolve_limits(ROBOT, ROBOT.nq, None, None)
    rng = np.random.default_rng(5)
    mid, half = (ROBOT.lower + ROBOT.upper) / 2, (ROBOT.upper - ROBOT.lower) / 2
    sections = [rng.uniform(mid - 0.6 * half, mid + 0.6 * half, (int(rng.integers(2, 6)), 4))
                for _ in range(30)]

    def timed_all():
        out = []
        for Q in sections:
            profile = ToolProfile.per_point([ToolLimits()] * len(Q))
            out.append(timing.time_section(ROBOT, Q, limits, profile))
        return out

    with_bounds = timed_all()

    def exact(traj):
        peaks = traj.peaks()
        return (float((peaks["velocity"] / traj.limits.vmax).max()),
                float((peaks["acceleration"] / traj.limits.amax).max()))

    monkeypatch.setattr(timing, "_joint_peaks", exact)
    for (pieces, note, knots), (ref, ref_note, ref_knots) in zip(with_bounds, timed_all(),
                                                                  strict=True):
        assert note == ref_note and np.array_equal(knots, ref_knots)
        for p, r in zip(pieces, ref, strict=True):
            assert np.array_equal(p.c, r.c) and np.array_equal(p.x, r.x)


@pytest.mark.parametrize(("extent", "delta"), [(5.0, 1.0), (28.8, 2.88)])
def test_the_rope_spaces_its_states_by_the_box_or_by_ompls_default(extent, delta):
    """The rope shortcut's states are 0.1 of the joint box's diagonal apart, never closer
    than OMPL's default 1.0 (a 0.2 + 0.2 m SCARA's box: 1.0; the UR5's: 2.88), and the
    simplifier's steps run in their order.

    Mutation caught: ``max(1.0, ...)`` dropped: the small box's spacing is 0.5. Mutation
    caught: the spacing not passed (OMPL's default 1.0 then): both cases fail.
    """
    from types import SimpleNamespace

    from scara_opt.planning.ompl_backend import simplify_path

    calls: list[tuple] = []

    class Simplifier:
        def __init__(self, si):
            pass

        def __getattr__(self, name):
            return lambda path, *args: calls.append((name, *args)) and False

    si = SimpleNamespace(getMaximumExtent=lambda: extent)
    simplify_path(SimpleNamespace(PathSimplifier=Simplifier), si, object())
    assert [c[0] for c in calls] == ["reduceVertices", "ropeShortcutPath",
                                     "partialShortcutPath", "collapseCloseVertices",
                                     "reduceVertices", "smoothBSpline"]
    assert calls[1][1:] == pytest.approx((delta,))
