"""Motions proven clear: segments and timed trajectories, checked against dense sampling.

The dense checks here are the tests' own: configurations every 1e-3 rad (or m) of joint
motion, each asked of Pinocchio + coal one at a time.
"""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so
from scara_opt.collision.continuous import VelocityBound, prove_segment
from tests.conftest import DATA, dense_first_contact, pinocchio_collides

THIN = so.Cell([so.Box("plate", (0.004, 0.5, 0.4), xyz=(0.28, 0.05, -0.05), rpy=(0, 0, 0.3)),
                so.Cylinder("post", 0.01, 0.4, xyz=(0.15, -0.25, 0.0))])


def random_segments(robot, checker, n, seed):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        qa, qb = rng.uniform(robot.lower, robot.upper, (2, robot.nq))
        qb = qa + (qb - qa) * rng.uniform(0.2, 1.0)
        if not checker.collides(qa) and not checker.collides(qb):
            out.append((qa, qb))
    return out


def test_segment_proof_agrees_with_a_dense_check():
    """Over 300 random segments past a 4 mm plate and a 10 mm post, a segment proven clear
    has no contact at 1e-3 rad steps, and every segment the dense check finds colliding is
    refused, its first contact located where the dense check puts it.

    Mutation caught: ``locate`` dropped (the proof stops at any contact): the reported
    fraction then lies past the dense check's first contact.
    """
    robot = so.load_robot("zavar2024")
    checker = so.CollisionChecker(robot, THIN)
    hits = 0
    for qa, qb in random_segments(robot, checker, 300, seed=0):
        proof = prove_segment(checker, qa, qb, locate=True)
        first = dense_first_contact(checker, qa, qb)
        if proof.clear:
            assert first is None, (qa, qb)
        else:
            assert proof.contact.touching
            if first is not None:
                hits += 1
                step = 1e-3 / np.abs(qb - qa).max()
                assert proof.contact.at <= first + 1e-6
                assert proof.contact.at >= first - 2 * step
    assert hits > 20  # the thin plate is crossed often


def test_swing_through_a_thin_plate_is_not_stepped_over():
    """A stretched arm swings 63 degrees through a 3 mm plate, both ends well clear of it:
    the rule splits (the bound exceeds the clearances' sum) and finds the contact, where
    half the bound would have passed the whole swing at once.

    Mutation caught: the bound halved (the checker's weights x 0.5): the swing is then
    "proven" clear in one step.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Box("plate", (0.15, 0.003, 0.2), xyz=(0.375, 0.0, 0.0))])
    checker = so.CollisionChecker(robot, cell)
    qa, qb = np.array([-0.3, 0.0, 0.02, 0.0]), np.array([0.8, 0.0, 0.02, 0.0])
    d = checker.distances(qa) + checker.distances(qb)
    M = checker.weights @ np.abs(qb - qa)
    assert (d > M / 2).all() and not (d > M).all()  # the case the mutation gets wrong
    proof = prove_segment(checker, qa, qb)
    assert not proof.clear and proof.contact.bodies == ("link2", "plate")
    assert dense_first_contact(checker, qa, qb) is not None


def test_proof_reports_clearance_and_counts():
    """A segment far from everything is proven with few checks and a positive clearance
    no larger than the smallest distance met along it."""
    robot = so.load_robot("zavar2024")
    checker = so.CollisionChecker(robot, THIN)
    qa, qb = np.array([-2.0, 0.3, 0.0, 0.0]), np.array([-1.5, 0.6, 0.02, 0.5])
    proof = prove_segment(checker, qa, qb)
    assert proof.clear and proof.contact is None
    s = np.linspace(0, 1, 2001)[:, None]
    sampled = checker.clearance_many(qa + s * (qb - qa)).min()
    assert 0 < proof.clearance <= sampled + 1e-9
    assert proof.evaluations < 20


@pytest.mark.parametrize("method, groups", [("toppra", 1), ("ruckig", 4)])
def test_velocity_bound_covers_the_trajectory_speed(method, groups):
    """The interval bound on |q̇| is never below |q̇| sampled inside the interval (toppra's
    degree-6 pieces, whose joints share their breakpoints and are looked up together;
    ruckig's, whose joints each have their own; random intervals).

    Mutation caught: the sparse table's query reading only the first piece of an interval
    (``b = a``): intervals spanning a speed peak then get a bound below it. Mutation
    caught: joints grouped without comparing their breakpoints (all with the first
    joint's): ruckig's other joints are then looked up in the wrong pieces.
    """
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize(np.array([[-1.0, 0.5, 0.0, 0.0], [0.2, -0.4, 0.03, 1.0],
                                          [1.0, 0.9, 0.01, -0.5]]), robot, method=method)
    vb = VelocityBound(traj)
    assert len(vb.groups) == groups
    rng = np.random.default_rng(1)
    t0 = rng.uniform(0, traj.duration, 400)
    t1 = np.minimum(t0 + rng.uniform(0, 0.4, 400), traj.duration)
    bounds = vb(t0, t1)
    for k in range(400):
        ts = np.linspace(t0[k], t1[k], 50)
        speed = np.abs(traj.evaluate(ts, 1)).max(axis=0)
        assert (speed <= bounds[k] + 1e-9).all()


def _dense_trajectory_contact(checker, traj):
    peak = traj.peaks()["velocity"].max()
    t = np.arange(0.0, traj.duration, 1e-3 / peak)
    hit = pinocchio_collides(checker, traj.evaluate(t))
    return float(t[np.argmax(hit)]) if hit.any() else None


def test_trajectory_first_contact_time_bodies_depth():
    """A timed move through a post: the first contact's time matches a dense check (every
    1e-3 rad of joint motion), the bodies are the arm and the post, the depth the deepest
    overlap sampled.

    Mutation caught: the depth read at the located start of the contact (``contact.depth``,
    about 0) instead of the deepest overlap while it lasts.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Cylinder("post", 0.03, 0.4, xyz=(0.3, 0.15, 0.0))])
    traj = so.time_parameterize(np.array([[-0.5, 0.5, 0.0, 0.0], [1.2, 0.5, 0.0, 0.0]]), robot)
    report = traj.check_collisions(cell, robot)
    checker = so.CollisionChecker(robot, cell)
    first = _dense_trajectory_contact(checker, traj)
    assert not report.clear and report.touching
    assert report.bodies == ("link2", "post")
    assert first - 2e-3 <= report.time <= first + 1e-4
    t = np.linspace(report.time, traj.duration, 3000)
    k = checker.pair_names.index(("link2", "post"))
    deepest = -checker.distances_many(traj.evaluate(t))[:, k].min()
    assert report.depth == pytest.approx(deepest, abs=2e-3)
    assert "link2-post" in repr(report)


def test_trajectory_clear_and_input_errors():
    """A move away from the obstacles is proven clear (its report says so); check_collisions
    refuses a Cell without a robot, a robot of another size and a non-cell."""
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize(np.array([[-2.0, 0.3, 0.0, 0.0], [-1.5, 0.6, 0.02, 0.5]]),
                                robot)
    report = traj.check_collisions(so.CollisionChecker(robot, THIN))
    assert report.clear and report.clearance > 0 and report.ratio == 0
    with pytest.raises(so.InputError, match="needs the robot"):
        traj.check_collisions(THIN)
    with pytest.raises(so.InputError, match="4 joints"):
        traj.check_collisions(THIN, so.load_robot("nguyen"))
    with pytest.raises(so.InputError, match="Cell or a CollisionChecker"):
        traj.check_collisions("cell.toml", robot)


def test_lin_through_an_obstacle_is_refused_naming_move_time_bodies():
    """A LIN across a post is refused: the move's index, the time of the contact and the
    bodies are in the error; the same program without the post plans.

    Mutation caught: LIN/CIRC sections not proven (only PTPs): the program would plan.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Cylinder("post", 0.01, 0.12, xyz=(0.30, 0.0, -0.14))])  # top at -80 mm
    moves = [so.PTP(so.Target([0.30, -0.10, -0.07])), so.LIN(so.Target([0.30, 0.10, -0.07])),
             so.LIN(so.Target([0.25, 0.10, -0.07]))]
    so.plan(robot, moves)
    with pytest.raises(so.MoveCollisionError) as info:
        so.plan(robot, moves, cell=cell)
    err = info.value
    assert err.index == 1 and "link4" in err.bodies and "post" in err.bodies
    assert err.time > 0 and err.depth > 0
    assert isinstance(err, so.CollisionError) and isinstance(err, so.MoveError)
    assert "move 1" in str(err) and "post" in str(err)


def test_circ_through_an_obstacle_is_refused():
    """A CIRC whose arc crosses a sphere is refused naming that move."""
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Sphere("ball", 0.02, xyz=(0.35, 0.0, -0.09))])
    moves = [so.PTP(so.Target([0.30, -0.05, -0.07])),
             so.CIRC([0.35, 0.0, -0.07], so.Target([0.30, 0.05, -0.07]))]
    with pytest.raises(so.MoveCollisionError, match="move 1: CIRC hits the cell") as info:
        so.plan(robot, moves, cell=cell)
    assert info.value.bodies == ("link4", "ball")


def test_planned_program_has_a_clearance_row():
    """A program planned in a cell has check_limits()['clearance'] <= 1 (proven clear with
    its margin); one planned without a cell has no such row."""
    robot = so.load_robot("zavar2024")
    moves = [so.PTP(so.Target([0.30, -0.10, -0.07])), so.LIN(so.Target([0.30, 0.10, -0.07]))]
    cell = so.Cell([so.Cylinder("pin", 0.01, 0.12, xyz=(0.2, 0.2, -0.14))])
    traj = so.plan(robot, moves, cell=cell, margin=0.002)
    ratios = traj.check_limits()
    assert 0 < ratios["clearance"][0] <= 1
    assert traj.check_collisions().clearance >= 0.002
    assert "clearance" not in so.plan(robot, moves).check_limits()
    with pytest.raises(so.InputError, match="without a cell"):
        so.plan(robot, moves).check_collisions()


def test_height_gaps_agree_with_a_dense_check():
    """Over low bars under a SCARA's arms (only the lowered tool reaches them), the proofs
    that use the height gaps (segments, the planner's edges, timed trajectories) never call
    a colliding motion clear (dense checks at 1e-3 rad), and do prove motions above them.

    Mutation caught: the prismatic joint's sign dropped from the gaps (``A`` taken as
    ``abs(A)``): lowering the tool then looks like lifting it, and motions into the bars
    are "proven" clear.
    """
    from scara_opt.planning.ompl_backend import EdgeProver

    robot = so.load_robot("zavar2024")
    bars = so.Cell([so.Box(f"bar{k}", (0.012, 0.5, 0.03), xyz=(0.16 + 0.09 * k, 0.0, -0.09))
                    for k in range(3)])
    checker = so.CollisionChecker(robot, bars)
    assert checker.gaps is not None
    prover = EdgeProver(checker)
    proven = 0
    for qa, qb in random_segments(robot, checker, 150, seed=5):
        first = dense_first_contact(checker, qa, qb)
        clear = prove_segment(checker, qa, qb).clear
        assert prover.edge(tuple(qa), tuple(qb)) == clear or first is None
        if clear:
            proven += 1
            assert first is None
            traj = so.time_parameterize(np.array([qa, qb]), robot)
            assert traj.check_collisions(checker).clear
    assert proven > 30


# ---------------------------------------------------------------------------- clearances
def _plate_under_link1():
    """zavar2024 and a 2 mm plate 0.5 mm under link1 (left out of the checks: apart)."""
    from scara_opt.collision.bound import height_range
    from scara_opt.collision.geometry import robot_geometry

    robot = so.load_robot("zavar2024")
    body = robot_geometry(robot).bodies[0]
    lowest = height_range(robot, body, robot.yaw_axis)[0]
    plate = so.Box("plate", (0.3, 0.3, 0.002), xyz=(0.2, 0.0, lowest - 0.0005 - 0.001))
    return robot, so.CollisionChecker(robot, so.Cell([plate]))


def test_a_reported_clearance_covers_the_pairs_left_out():
    """A plate 0.5 mm under link1, out of the checks as never within reach: clearance(q)
    says 0.500 mm link1-plate (was 150 mm link1-link4), the plan's report proves no more
    than 0.5 mm and finds 0.5 mm, and a segment's proof claims no more either.

    Mutation caught: ``clearance`` over the checked pairs only (``self`` for
    ``self.everything``) -> 35 mm; fails. Mutation caught: ``_every_pair`` returning the
    proof unchanged -> the short segment's proof claims 35 mm; fails.
    """
    robot, checker = _plate_under_link1()
    assert ("link1", "plate") in checker.apart and ("link1", "plate") not in checker.pair_names
    c = checker.clearance(np.zeros(4))
    assert c.bodies == ("link1", "plate") and abs(c.distance - 0.0005) < 1e-9
    assert abs(checker.clearance_many(np.zeros((2, 4)))[0] - 0.0005) < 1e-9
    short = prove_segment(checker, np.zeros(4), np.array([0.01, 0.0, 0.0, 0.0]))
    assert short.clear and short.clearance <= 0.0005 + 1e-12  # its checked pairs: >= 35 mm
    traj = so.plan(robot, [so.PTP([0.5, 0.5, 0.01, 0.2])], start=np.zeros(4), cell=checker)
    report = traj.check_collisions()
    assert report.clear and report.clearance <= 0.0005 + 1e-12
    assert abs(report.least.distance - 0.0005) < 1e-9 and report.least.bodies == c.bodies


def _planned(seed, n):
    robot = so.load_robot("zavar2024")
    cell = so.load_cell(DATA.parent.parent / "examples" / "scara_cell.toml")
    checker = so.CollisionChecker(robot, cell)
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        a, b = rng.uniform(robot.lower, robot.upper, (2, 4))
        if min(checker.clearance(a).distance, checker.clearance(b).distance) < 1e-3:
            continue
        try:
            out.append(so.plan(robot, [so.PTP(b)], start=a, cell=checker, seed=seed))
        except so.ScaraOptError:
            continue
    return checker, out


def test_least_clearance_is_found_to_its_tolerance():
    """Eight trajectories planned in the example cell: the least clearance lies within 0.1
    mm of a 20,000-sample dense minimum, and the proven bound is never above it.

    Mutation caught: the bound of an interval without its motion term (``(Dlo + Dhi) / 2``)
    -> the proven bound above the dense minimum; fails.
    """
    checker, trajs = _planned(4, 8)
    tol = 1e-4
    for traj in trajs:
        rep = traj.check_collisions()
        t = np.linspace(0.0, traj.duration, 20001)
        dense = checker.clearance_many(traj.evaluate(t))
        c = rep.least
        assert c.converged and c.tolerance == tol
        assert c.lower <= dense.min() + 1e-12 and rep.clearance <= dense.min() + 1e-12
        assert c.distance - c.lower <= tol + 1e-12
        assert abs(c.distance - dense.min()) <= tol
        assert "least clearance" in repr(rep) and "proven >=" in repr(rep)


def test_the_least_clearance_does_not_depend_on_the_margin_asked():
    """The same trajectory checked by its own checker and by a 2 mm checker: the same least
    clearance (to the tolerance), where the proof's bound alone said 2.010 and 0.048 mm.

    Mutation caught: ``least_clearance`` run on the checker's pairs shifted by its margin
    (``D - checker.margin``) -> the 2 mm checker's value 2 mm lower; fails.
    """
    checker, (traj,) = _planned(7, 1)
    own = traj.check_collisions()
    margin = own.least.distance / 2
    wide = traj.check_collisions(checker.with_margin(margin))
    assert wide.clear and wide.margin == margin and own.margin == 0.0
    assert abs(wide.least.distance - own.least.distance) <= 1e-4


def test_least_bounds_random_lipschitz_functions():
    """``least`` on 300 random sums of sines with known slopes, 2-6 "pairs" each, to 0.1 mm
    and to 30 mm: the proven bound never above the dense minimum, the value found within the
    tolerance of it.

    Mutation caught: the least found not updated at midpoints (``Dm[i, j] < best`` never)
    -> the value off by more than the tolerance; fails. Mutation caught: an interval closed
    when its bound is within twice the tolerance (``best - 2 * tol``) -> fails.
    """
    from scara_opt.collision.continuous import least

    rng = np.random.default_rng(0)
    grid = np.linspace(0.0, 1.0, 200_001)
    for _ in range(300):
        k = int(rng.integers(2, 7))
        c, a = rng.uniform(0.0, 0.2, k), rng.uniform(0.0, 0.1, (k, 3))
        w, phi = rng.uniform(1.0, 40.0, (k, 3)), rng.uniform(0, 6.3, (k, 3))
        slope = (a * w).sum(axis=1)

        def dist(s, cols=None, c=c, a=a, w=w, phi=phi):
            d = c[:, None] + (a[:, :, None] * np.sin(w[:, :, None] * s + phi[:, :, None])
                              ).sum(axis=1)
            return (d.T if cols is None else d[cols].T)

        s0 = np.linspace(0.0, 1.0, 5)
        true = dist(grid).min()
        for tol in (1e-4, 0.03):
            value, at, pair, lower, ok, _ = least(
                s0, dist(s0), lambda s: s[:, None],
                lambda lo, hi, slope=slope: np.outer(hi - lo, slope),
                lambda Q, cols, d=dist: d(Q[:, 0], cols), tol)
            assert ok and lower <= true + 1e-12 and value - true <= tol + 1e-12
            assert value - lower <= tol + 1e-12
