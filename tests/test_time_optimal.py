"""objective="time": the lower bound beside every answer, the synchronized move at it, never
slower than objective="length"; every trajectory re-checked densely here."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.collision.continuous import prove_segment
from scara_opt.trajectory.bound import joint_times, lower_bound, synchronized_move
from scara_opt.trajectory.limits import resolve_limits
from tests.test_planning import POST, QA, QB, ROBOT, dense_clear_trajectory

LIMITS = resolve_limits(ROBOT, ROBOT.nq)
#: a low wall across the reach: crossing it lifts the quill (as test_planning's rack)
RACK = so.Cell([so.Box("rack", (0.02, 1.2, 0.03), xyz=(0.25, 0.0, -0.095))])


def own_time(d: float, v: float, a: float) -> float:
    """One joint's time-optimal rest-to-rest move over ``d`` under ``v``, ``a`` [s]."""
    d = abs(d)
    return 2 * math.sqrt(d / a) if d < v * v / a else d / v + v / a


def pairs(cell: so.Cell, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``n`` clear (start, goal) pairs of ROBOT in ``cell`` whose straight segment collides."""
    checker = so.CollisionChecker(ROBOT, cell)
    rng = np.random.default_rng(seed)
    lo = ROBOT.lower + 0.05 * (ROBOT.upper - ROBOT.lower)
    hi = ROBOT.upper - 0.05 * (ROBOT.upper - ROBOT.lower)
    out = []
    while len(out) < n:
        a, b = rng.uniform(lo, hi, (2, ROBOT.nq))
        if checker.collides(a) or checker.collides(b):
            continue
        if not prove_segment(checker, a, b).clear:
            out.append((a, b))
    return out


def test_the_bound_is_the_slowest_joints_own_time_optimal_move():
    """Each joint's time is its own bang-coast-bang move (both regimes), and the bound is
    the largest of them.

    Mutation caught: the bound taken as the fastest joint's time (``min`` for ``max`` in
    lower_bound) -> fails. Mutation caught: the jerk limit kept (Ruckig's third-order
    profiles, jmax = 10 amax): every joint's time grows -> fails.
    """
    qa = np.array([-0.6, 1.2, 0.0, 0.0])
    qb = np.array([0.9, 1.15, 0.045, 1.0])  # theta1 coasts at vmax; the rest never reach it
    want = [own_time(b - a, v, acc) for a, b, v, acc in
            zip(qa, qb, LIMITS.vmax, LIMITS.amax, strict=True)]
    assert joint_times(qa, qb, LIMITS) == pytest.approx(want, rel=1e-9)
    assert lower_bound(qa, qb, LIMITS) == pytest.approx(max(want), rel=1e-9)
    assert max(want) > 2 * min(want)  # the fastest joint would be a wrong bound


def test_the_synchronized_move_reaches_the_bound_within_the_limits():
    """Ruckig's time-synchronized move ends at the goal at rest, at the bound, every joint
    within its velocity and acceleration limits and between its start and goal.

    Mutation caught: the move timed under doubled acceleration limits (second_order with
    2 amax): it is shorter than the joints allow, acceleration ratio 2 -> fails.
    """
    qa = np.array([-0.6, 1.2, 0.0, 0.0])
    qb = np.array([0.9, 1.0, 0.04, 1.0])
    pieces, T = synchronized_move(qa, qb, LIMITS)
    traj = so.Trajectory(pieces, LIMITS, "ruckig", np.array([qa, qb]), np.array([0.0, T]))
    assert T == pytest.approx(lower_bound(qa, qb, LIMITS), rel=1e-12)
    q, qd, _ = traj.sample(np.array([0.0, T]))
    assert np.allclose(q, [qa, qb], atol=1e-12) and np.allclose(qd, 0.0, atol=1e-12)
    ratios = traj.check_limits()
    assert ratios["velocity"].max() <= 1 + 1e-9 and ratios["acceleration"].max() <= 1 + 1e-9
    lo, hi = traj.position_range()
    assert (lo >= np.minimum(qa, qb) - 1e-12).all() and (hi <= np.maximum(qa, qb) + 1e-12).all()


def test_where_the_synchronized_move_is_clear_the_answer_is_it_at_the_bound():
    """In empty space and in a cell where the synchronized move is proven clear, a PTP
    planned with objective="time" lasts its lower bound to 1e-6 relative, is clear by the
    dense check here, and its limits hold; objective="length" is slower there.

    Mutation caught: the synchronized move not tried (objective ignored): the duration is
    toppra's along the straight line, above the bound -> fails.
    """
    qa, qb = np.array([-1.5, 0.5, 0.0, 0.0]), np.array([-0.5, 1.5, 0.0, 0.0])
    # theta1 bound by its speed, theta2 by its acceleration: the straight line is slower
    kw = {"vmax": [1.0, 10.0, 0.5, 6.28], "amax": [100.0, 3.0, 2.0, 25.0]}
    checker = so.CollisionChecker(ROBOT, POST)
    for cell in (None, POST):
        fast = so.plan(ROBOT, [so.PTP(qb)], start=qa, cell=cell, objective="time", **kw)
        slow = so.plan(ROBOT, [so.PTP(qb)], start=qa, cell=cell, objective="length", **kw)
        assert fast.duration == pytest.approx(fast.lower_bound, rel=1e-6)
        assert fast.bound_ratio == pytest.approx(1.0, rel=1e-6)
        assert slow.duration > fast.duration * 1.1 and slow.lower_bound == fast.lower_bound
        assert np.allclose(fast.evaluate(np.array([fast.duration]))[0], qb, atol=1e-9)
        ratios = fast.check_limits()
        assert ratios["velocity"].max() <= 1 + 1e-9
        assert ratios["acceleration"].max() <= 1 + 1e-9
        assert "time-synchronized" in fast.notes
    assert dense_clear_trajectory(checker, fast)
    assert fast.check_collisions().clear


def test_duration_is_never_below_the_bound_and_time_never_slower_than_length():
    """On pairs through a post and over a rack (the straight segment collides), both
    objectives give dense-clear trajectories within the joint limits and no faster than
    their bound, which is lower_bound(start, goal); the time objective is never slower than
    the length objective (same seed), and faster on at least half of the pairs.

    Mutation caught: objective="time" ignored in plan() (timed as "length"): no pair is
    faster -> fails. Mutation caught: the candidates' proof skipped (proven() answering
    True): a trajectory through the post or the rack comes back -> the dense check fails.
    Mutation caught: the candidates timed under doubled acceleration limits (second_order
    with 2 amax): their acceleration ratio is 2 -> fails.
    """
    faster = 0
    total = 0
    for cell, seed in ((POST, 1), (RACK, 2)):
        checker = so.CollisionChecker(ROBOT, cell)
        for k, (a, b) in enumerate(pairs(cell, 4, seed)):
            got = {obj: so.plan(ROBOT, [so.PTP(b)], start=a, cell=cell, seed=k, objective=obj)
                   for obj in ("time", "length")}
            for traj in got.values():
                assert traj.lower_bound == pytest.approx(lower_bound(a, b, LIMITS), rel=1e-12)
                assert traj.duration >= traj.lower_bound * (1 - 1e-9)
                assert dense_clear_trajectory(checker, traj)
                ratios = traj.check_limits()
                assert ratios["velocity"].max() <= 1 + 1e-6
                assert ratios["acceleration"].max() <= 1 + 1e-6
                lo, hi = traj.position_range()
                assert (lo >= ROBOT.lower - 1e-9).all() and (hi <= ROBOT.upper + 1e-9).all()
            assert got["time"].duration <= got["length"].duration * (1 + 1e-9)
            faster += got["time"].duration < got["length"].duration * (1 - 1e-3)
            total += 1
    assert faster >= total // 2


def test_time_objective_same_seed_same_result():
    """The same seed gives the same trajectory under objective="time".

    Mutation caught: the restarts' seeds taken from the clock (time.perf_counter_ns())
    -> the two trajectories differ.
    """
    a, b = pairs(POST, 1, 5)[0]
    one = so.plan(ROBOT, [so.PTP(b)], start=a, cell=POST, seed=3, objective="time")
    two = so.plan(ROBOT, [so.PTP(b)], start=a, cell=POST, seed=3, objective="time")
    t = np.linspace(0.0, one.duration, 200)
    assert one.duration == two.duration and np.array_equal(one.evaluate(t), two.evaluate(t))


def test_a_bad_objective_is_refused():
    """An objective other than length or time is an InputError naming both.

    Mutation caught: check_objective testing only for a string -> no error.
    """
    with pytest.raises(so.InputError, match="'length'.*'time'"):
        so.plan(ROBOT, [so.PTP(QB)], start=QA, objective="speed")
    with pytest.raises(so.InputError, match="objective"):
        so.cycle_time(ROBOT, across=0.2, objective="fast")


def test_the_bound_of_a_program_sums_its_stops_and_shows_in_repr():
    """A program of PTPs and a LIN has one bound per stop-to-stop run, summed; repr shows
    the bound and the ratio.

    Mutation caught: the bound of the last run only (bounds overwritten, not appended)
    -> fails.
    """
    q1, q2 = np.array([-0.2, 1.0, 0.02, 0.3]), np.array([0.5, 0.6, 0.0, 0.0])
    traj = so.plan(ROBOT, [so.PTP(q1), so.PTP(q2)], start=QA, objective="time")
    want = lower_bound(QA, q1, LIMITS) + lower_bound(q1, q2, LIMITS)
    assert traj.lower_bound == pytest.approx(want, rel=1e-12)
    assert traj.duration == pytest.approx(want, rel=1e-6)
    assert f"lower bound {want:.4f} s (x1.000)" in repr(traj)
    lin = so.plan(ROBOT, [so.PTP(q1), so.LIN(so.Target(ROBOT.position(q2)))], start=QA)
    assert len(lin.run_bounds) == 2 and lin.duration >= lin.lower_bound


def test_cycle_in_a_cell_with_the_time_objective():
    """The standard cycle in a cell with objective="time": proven clear by the dense check
    here, no slower than with "length", no faster than its lower bound, which it reports.

    Mutation caught: cycle_time not passing objective= on to plan(): the durations are
    equal and the PTPs are not the synchronized moves (the notes) -> fails.
    """
    from scara_opt.motion.cycle import place_cycle

    A, B, _, _ = place_cycle(ROBOT, 0.025, 0.2, 0.025)
    mid = (A + B) / 2
    cell = so.Cell([so.Box("block", (0.04, 0.04, 0.04), xyz=(mid[0], mid[1], -0.075))])
    # a generous limit: a first call's imports and caches must not cut the simplifier
    length = so.cycle_time(ROBOT, across=0.2, cell=cell, time_limit=10.0)
    fast = so.cycle_time(ROBOT, across=0.2, cell=cell, objective="time", time_limit=10.0)
    assert fast.durations["toppra"] < length.durations["toppra"]
    assert fast.durations["toppra"] >= fast.lower_bound * (1 - 1e-9)
    assert fast.lower_bound == pytest.approx(length.lower_bound, rel=1e-9)
    assert dense_clear_trajectory(so.CollisionChecker(ROBOT, cell), fast.trajectory)
    assert "objective time" in repr(fast) and "lower bound" in repr(fast)


def test_cli_plan_reports_the_bound_and_takes_the_objective(capsys):
    """``scara-opt plan --objective time`` prints the bound and the ratio, and its JSON
    carries them, ``bound_ratio`` the duration over the bound.

    Mutation caught: the JSON's bound_ratio as bound / duration -> fails.
    """
    from scara_opt.cli import main

    args = ["plan", "zavar2024", "--start", "-20", "50", "10", "0", "--goal", "-100", "60",
            "40", "0", "--deg", "--mm", "--cell"]
    cell = "examples/scara_cell.toml"
    assert main([*args, cell, "--objective", "time", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["objective"] == "time"
    assert out["duration_s"] >= out["lower_bound_s"] * (1 - 1e-9)
    assert out["bound_ratio"] == pytest.approx(out["duration_s"] / out["lower_bound_s"])
    assert main([*args, cell, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["objective"] == "length" and out["bound_ratio"] > 1.05
    assert out["bound_ratio"] == pytest.approx(out["duration_s"] / out["lower_bound_s"])
    assert main([*args, cell]) == 0
    text = capsys.readouterr().out
    assert "objective length: lower bound" in text and "duration / bound" in text


def test_another_seed_is_planned_while_the_path_is_far_from_the_bound():
    """Across the example cell's rack (the standard cycle's upper corners), the length
    objective's path detours (4.5 times the bound); the time objective plans again with
    other seeds and keeps the fastest, within 1.15 times the bound, dense-clear here, and
    says how many paths it planned.

    Mutation caught: RESTARTS = 1 (one path only): the detour is kept, 4.5 times the
    bound -> fails.
    """
    cell = so.load_cell("examples/scara_cell.toml")
    checker = so.CollisionChecker(ROBOT, cell)
    a, b = np.array([0.763, -1.7817, 0.0115, 0.0]), np.array([2.0659, -1.7817, 0.0115, 0.0])
    slow = so.plan(ROBOT, [so.PTP(b)], start=a, cell=checker, seed=0, time_limit=10.0)
    fast = so.plan(ROBOT, [so.PTP(b)], start=a, cell=checker, seed=0, time_limit=10.0,
                   objective="time")
    assert slow.bound_ratio > 3 and fast.bound_ratio < 1.15
    assert "paths planned (another seed each)" in fast.notes
    assert dense_clear_trajectory(checker, fast)


def test_a_program_file_and_the_cli_take_the_objective(tmp_path, capsys):
    """A program file's ``objective = "time"`` reaches plan(); a misspelt one is a
    ProgramError naming both values; ``scara-opt cycle --objective time`` prints the bound.

    Mutation caught: Program.plan not passing its objective on -> the PTP is toppra's,
    above the bound -> fails.
    """
    from scara_opt.cli import main

    text = ('robot = "zavar2024"\nlength_unit = "mm"\nangle_unit = "deg"\n'
            'start = [-40, 60, 10, 0]\nobjective = "{}"\n\n[[moves]]\ntype = "PTP"\n'
            'joints = [20, 30, 20, 45]\n')
    path = tmp_path / "p.toml"
    path.write_text(text.format("time"))
    traj = so.load_program(path).plan()
    assert traj.objective == "time" and traj.duration == pytest.approx(traj.lower_bound,
                                                                       rel=1e-6)
    path.write_text(text.format("fastest"))
    with pytest.raises(so.errors.ProgramError, match="length, time"):
        so.load_program(path)
    assert main(["cycle", "zavar2024", "--across", "200", "--objective", "time"]) == 0
    out = capsys.readouterr().out
    assert "lower bound" in out and "objective time" in out


def test_candidates_past_the_limit_are_never_timed_and_none_faster_is_lost():
    """``candidates(..., limit=L)`` skips the ways whose time metric (each edge's slowest
    joint at full speed) is at least ``L``: every candidate lasts at least its way's
    metric, so the candidates faster than ``L`` are exactly those of the unpruned list,
    and some ways are skipped. On a 5-waypoint polyline of ROBOT and random ones.

    Mutation caught: the bound doubled (``2 * time_metric(Q, vmax) >= duration`` in
    ``cannot_beat``) -> a candidate faster than L lost, fails.
    """
    from scara_opt.motion.fastest import candidates, time_metric

    rng = np.random.default_rng(4)
    lo, hi = ROBOT.lower + 0.1 * (ROBOT.upper - ROBOT.lower), ROBOT.upper - 0.1 * (
        ROBOT.upper - ROBOT.lower)
    for _ in range(4):
        Q = rng.uniform(lo, hi, (5, ROBOT.nq))
        full = candidates(Q, LIMITS)
        for T, traj, _ in full:  # the premise: no timing beats its points' metric
            assert T >= time_metric(traj.waypoints, LIMITS.vmax)
        L = float(np.median([c[0] for c in full]))
        pruned = candidates(Q, LIMITS, limit=L)
        assert len(pruned) < len(full)
        assert [c[0] for c in pruned if c[0] < L] == [c[0] for c in full if c[0] < L]


def test_a_restart_path_that_cannot_beat_the_best_is_not_timed(monkeypatch):
    """The example cell's detour pair (as above): a path planned again whose time metric is
    no less than the best duration is not timed (fewer timings: 1 of its 5 paths planned
    again is skipped), and the answer is the one timing every path gives (the same
    trajectory to the bit).

    Mutation caught: the comparison turned (``time_metric(Q, vmax) < duration`` in
    ``cannot_beat``) -> the paths that could win are skipped: 2.9953 s against 0.7145 s,
    fails.
    """
    from scara_opt.motion import clearance, fastest

    cell = so.load_cell("examples/scara_cell.toml")
    checker = so.CollisionChecker(ROBOT, cell)
    a, b = np.array([0.763, -1.7817, 0.0115, 0.0]), np.array([2.0659, -1.7817, 0.0115, 0.0])
    real = clearance.CellPlanning.timed_clear
    timings: list[int] = []

    def counting(self, *args):
        timings[-1] += 1
        return real(self, *args)

    monkeypatch.setattr(clearance.CellPlanning, "timed_clear", counting)
    timings.append(0)
    pruned = so.plan(ROBOT, [so.PTP(b)], start=a, cell=checker, seed=0, time_limit=10.0,
                     objective="time")
    monkeypatch.setattr(fastest, "cannot_beat", lambda Q, vmax, duration: False)
    timings.append(0)
    every = so.plan(ROBOT, [so.PTP(b)], start=a, cell=checker, seed=0, time_limit=10.0,
                    objective="time")
    assert timings[0] < timings[1] and pruned.duration == every.duration
    t = np.linspace(0.0, every.duration, 200)
    np.testing.assert_array_equal(pruned.evaluate(t), every.evaluate(t))
