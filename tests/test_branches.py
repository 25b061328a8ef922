"""The global branch choice along a path (scara_opt.trajectory.branches and ik_path).

References: the geometry of zavar2024's arc (θ1 = angle − 41.4° on one elbow branch stays
within ±120° from −50° to 110°: arccos(0.30 / (2 · 0.2)) = 41.4°), hand-built walks whose
least-cost answer is worked out in each docstring, and the greedy walk as a bound (the
global walk has no more jumps, and with as many no more weighted travel).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.errors import InputError
from scara_opt.ik.result import Status
from scara_opt.ik.verdict import judge
from scara_opt.trajectory.branches import _layered_walk, least_cost_walk
from scara_opt.trajectory.path import JudgedResults
from tests.conftest import ROOT


def arc41() -> list[so.Target]:
    """The issue's arc: 41 points, r = 0.30 m, z = -0.07 m, from -50° to 110° about the base."""
    return so.paths.circle((0, 0), 0.30, -0.07, 41, start=math.radians(-50),
                           sweep=math.radians(160))


def weighted(robot: so.Robot, jp) -> float:
    return float((jp.travel / robot.velocity_limit).sum())


@pytest.mark.parametrize("method", ["auto", "lm", "ipopt", "analytic"])
def test_one_branch_covers_the_arc_so_no_jump(robots, method):
    """The 41-point arc on zavar2024: one elbow branch all along, θ1 = angle − 41.4°.

    Before: auto, lm and ipopt started on the other branch and flipped the elbow at point
    33 (θ2 by 2.891 rad); the greedy walk still does. Mutation caught: the closed form's
    first branch dropped (``valid[:, 0] = False`` after solve_batch in branches.py) ->
    the flip at 33 comes back, fails.
    """
    robot = robots["zavar2024"]
    jp = so.ik_path(robot, arc41(), method=method)
    assert jp.ok and jp.branches == "global", jp.summary()
    angles = np.degrees([math.atan2(t.position[1], t.position[0]) for t in jp.targets])
    np.testing.assert_allclose(np.degrees(jp.q[:, 0]), angles - 41.4096, atol=1e-3)
    greedy = so.ik_path(robot, arc41(), method=method, branches="greedy")
    assert [j.index for j in greedy.jumps] == [33]
    assert abs(greedy.jumps[0].delta[1]) == pytest.approx(2.891, abs=1e-3)


def test_the_wrist_starts_on_the_turn_that_lasts_the_path(robots):
    """A tangent tool on a 500° arc needs fang's ±360° wrist started near its lower end.

    The greedy walk starts the wrist at +61° (the turn nearest zero) and hits +360° at step
    36; the global walk starts it at -299° and ends at +174°, no jump. Mutation caught: the
    closed form's turns not enumerated (``for k, lo, hi in turn_joints(robot)`` -> ``in ()``)
    -> the jump at 36, fails.
    """
    fang = so.load_robot("fang")
    z = fang.position(np.zeros(4))[2]
    ts = so.paths.circle((0.30, 0.0), 0.05, z, 60, start=0.0, sweep=math.radians(500),
                         yaw="tangent")
    greedy = so.ik_path(fang, ts, branches="greedy")
    assert [j.index for j in greedy.jumps] == [36]
    jp = so.ik_path(fang, ts)
    assert jp.ok, jp.summary()
    assert np.degrees(jp.q[0, 3]) == pytest.approx(-298.955, abs=1e-2)
    assert weighted(fang, jp) < weighted(fang, greedy)


def test_fewest_jumps_first_then_the_least_weighted_travel():
    """Hand-built: the walk without a jump wins over a cheaper one with a jump.

    Two joints, threshold 1 each, weights 1 and 10. From (0, 0), point 1 offers (1.5, 0)
    (a jump in joint 0, travel 1.5) and (0.5, 0.5) (travel 0.5 + 5 = 5.5); point 2 is
    (1.5, 0). The no-jump walk costs 5.5 + 1 + 5 = 11.5 against 1.5 with one jump: the
    no-jump walk is chosen. Mutation caught: the jump penalty dropped (``penalty = 1.0 +
    ...`` -> ``penalty = 0.0``) -> the cheaper walk with a jump, fails.
    """
    Q = np.array([[[0.0, 0.0], [0.0, 0.0]], [[1.5, 0.0], [0.5, 0.5]], [[1.5, 0.0], [1.5, 0.0]]])
    valid = np.array([[True, False], [True, True], [True, False]])
    w = least_cost_walk(Q, valid, np.array([1.0, 1.0]), np.array([1.0, 10.0]))
    assert w.choice.tolist() == [0, 1, 0] and w.jumps == () and w.travel == pytest.approx(11.5)
    free = least_cost_walk(Q, valid, np.array([9.0, 9.0]), np.array([1.0, 10.0]))
    assert free.choice.tolist() == [0, 0, 0] and free.travel == pytest.approx(1.5)


def test_the_travel_objective_takes_the_cheaper_walk_with_a_jump():
    """The same hand-built candidates, ``fewest_jumps=False`` (ik_path's ``"travel"``): the
    walk of travel 1.5 with its jump at step 1, reported, over the 11.5 without.

    Mutation caught: the flag ignored (``if fewest_jumps:`` -> ``if True:``, or the layered
    walk's ``counts = int(fewest_jumps)`` -> ``1``) -> the no-jump walk, fails.
    """
    Q = np.array([[[0.0, 0.0], [0.0, 0.0]], [[1.5, 0.0], [0.5, 0.5]], [[1.5, 0.0], [1.5, 0.0]]])
    valid = np.array([[True, False], [True, True], [True, False]])
    thr, w = np.array([1.0, 1.0]), np.array([1.0, 10.0])
    for walked in (least_cost_walk(Q, valid, thr, w, fewest_jumps=False),
                   _layered_walk(Q, valid, thr, w, np.zeros(2), np.zeros(2, bool), False)):
        assert walked.choice.tolist() == [0, 0, 0] and walked.jumps == (1,)
        assert walked.travel == pytest.approx(1.5)


def test_a_jump_off_q_start_counts_before_the_paths_own():
    """Hand-built: the walk keeps q_start's branch at point 0 and jumps later instead.

    Two joints, threshold 1, weights 1 and 10, q_start (0, 0). Point 0: (0.2, 0.1) | (3.0,
    0); point 1: (-0.5, 0.1) | (3.2, 0); point 2: (3.3, 0). Leaving q_start at once (3.0,
    3.2, 3.3) travels 3.3 with a jump off q_start; staying, (0.2, 0.1) -> (3.2, 0) -> (3.3,
    0) travels 1.2 + 4.0 + 0.1 = 5.3 with a jump at step 1, forced by point 2 (from (0.2,
    0.1) only (-0.5, 0.1) is within reach, and nothing from there). Mutation caught: the
    start's jump weighed like the path's (``n * penalty`` -> ``penalty``) -> the walk
    leaves q_start, fails.
    """
    Q = np.array([[[0.2, 0.1], [3.0, 0.0]], [[-0.5, 0.1], [3.2, 0.0]],
                  [[3.3, 0.0], [3.3, 0.0]]])
    valid = np.array([[True, True], [True, True], [True, False]])
    w = least_cost_walk(Q, valid, np.array([1.0, 1.0]), np.array([1.0, 10.0]),
                        q_start=np.zeros(2))
    assert w.choice.tolist() == [0, 1, 0] and w.jumps == (1,) and w.forced_by == (2,)
    assert not w.start_jump and w.travel == pytest.approx(5.3)


def test_global_walk_on_the_arm_beats_the_greedy_one(ur5_arm):
    """UR5-class arm, the issue's 5 full poses: less weighted travel than greedy; with
    ``objective="fewest_jumps"``, fewer jumps (less travel if tied).

    The global walk chooses among every closed-form solution and turn of each pose
    (:func:`~scara_opt.trajectory.branches.candidates_arm`). Measured: greedy 4 jumps /
    22.8 rad, fewest jumps 3 jumps / 23.3 rad (the multi-start's of before: 3 jumps / 33.6
    rad), travel 4 jumps / 22.8 rad or less. Mutation caught: the arm's candidates not used
    (``candidates_arm`` returning None) -> fails.
    """
    Q = np.random.default_rng(2).uniform(ur5_arm.lower, ur5_arm.upper, (5, 6))
    targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(ur5_arm.fk, Q)]
    greedy = so.ik_path(ur5_arm, targets, branches="greedy")
    jp = so.ik_path(ur5_arm, targets, objective="fewest_jumps")
    assert jp.branches == "global" and jp.solved.all()
    assert (len(jp.jumps), weighted(ur5_arm, jp)) <= (len(greedy.jumps),
                                                      weighted(ur5_arm, greedy))
    assert len(jp.jumps) < len(greedy.jumps) and jp.travel.sum() <= 35.3
    assert all(j.forced_by is not None and j.forced_by >= j.index for j in jp.jumps)
    least = so.ik_path(ur5_arm, targets)
    assert least.solved.all() and weighted(ur5_arm, least) <= weighted(ur5_arm, greedy) + 1e-9
    assert weighted(ur5_arm, least) <= weighted(ur5_arm, jp) + 1e-9


def test_global_multi_start_on_an_unserved_arm_never_loses_the_greedy_walk(arm6):
    """arm6 (a prismatic joint: no closed form), 20 sequences of 5 full poses: the
    multi-start follows every track, the greedy one first, so the global walk never has
    more weighted travel than greedy (``objective="fewest_jumps"``: never more jumps, nor
    more weighted travel with as many).

    Mutation caught: the tracks not continued (``prev = [r.q for r in found]`` ->
    ``prev = [q_start]``) -> the greedy track is lost: worse than greedy on sequences 8,
    13, 15, 17 and 18, fails.
    """
    compared = 0
    for seed in range(20):
        Q = np.random.default_rng(seed).uniform(arm6.lower, arm6.upper, (5, 6))
        targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(arm6.fk, Q)]
        greedy = so.ik_path(arm6, targets, branches="greedy")
        jp = so.ik_path(arm6, targets, objective="fewest_jumps")
        least = so.ik_path(arm6, targets)
        assert jp.results[0].route == ""
        if not (jp.solved.all() and greedy.solved.all() and least.solved.all()):
            continue  # a pose a multi-start misses: no travel to compare
        compared += 1
        assert (len(jp.jumps), weighted(arm6, jp)) <= (len(greedy.jumps),
                                                      weighted(arm6, greedy) + 1e-9), seed
        assert weighted(arm6, least) <= weighted(arm6, greedy) + 1e-9, seed
    assert compared >= 15


def test_a_point_no_branch_reaches_keeps_its_verdict(robots):
    """A path through a point inside zavar2024's base hole: that point 'unreachable' with its
    certificate, the others solved; nothing skipped.

    Mutation caught: the points without a candidate not given to the method (``for i in
    np.flatnonzero(~valid.any(axis=1))`` -> ``for i in []`` in ``_global``) -> no walk
    (ValueError), fails.
    """
    robot = robots["zavar2024"]
    ts = [so.Target((0.30, 0.0, -0.07)), so.Target((0.10, 0.0, -0.07)),
          so.Target((0.30, 0.05, -0.07))]
    jp = so.ik_path(robot, ts)
    assert len(jp) == 3 and jp.unsolved == [1]
    assert jp.status[1] == Status.UNREACHABLE and "proof" in jp.results[1].message
    assert jp.error[1] == pytest.approx(jp.results[1].error)
    assert jp.solved[[0, 2]].all()


def test_judged_results_are_the_verdicts(robots):
    """The lazily judged results equal the verdict's, by index, negative index and slice."""
    robot = robots["zavar2024"]
    jp = so.ik_path(robot, arc41())
    assert isinstance(jp.results, JudgedResults) and len(jp.results) == 41
    for i in (0, 17, -1):
        r = jp.results[i]
        ref = judge(robot, jp.targets[i], so.ik.result.SolverOutput(q=jp.q[i], evaluations=1),
                    tol=1e-9, method="analytic", seed=None, time_s=0.0)
        assert r.status == ref.status == jp.status[i] and r.error == ref.error
        np.testing.assert_array_equal(r.q, jp.q[i])
    assert [r.q[0] for r in jp.results[2:5]] == list(jp.q[2:5, 0])
    with pytest.raises(IndexError):
        jp.results[41]
    part = jp.subset(slice(5, 9))
    assert part.ok and len(part.results) == 4


def test_branches_option_is_checked(robots):
    """branches is 'global' or 'greedy'; global needs a method nearest q0; pso defaults greedy."""
    robot = robots["zavar2024"]
    ts = arc41()[:3]
    with pytest.raises(InputError, match="branches must be one of"):
        so.ik_path(robot, ts, branches="best")
    with pytest.raises(InputError, match="needs a method that returns the solution nearest"):
        so.ik_path(robot, ts, method="pso", branches="global")
    jp = so.ik_path(robot, ts, method="pso", population=20, iterations=20)
    assert jp.branches == "greedy"
    with pytest.raises(InputError, match=r"objective must be one of \['travel', 'fewest_jumps'\]"):
        so.ik_path(robot, ts, objective="jumps")


def test_a_redundant_task_keeps_the_greedy_walk_unless_another_jumps_less():
    """arm6 (6 joints) on a 36-point line, position only: a continuum of solutions.

    The multi-start's tracks are samples of it; one rides the elbow's limit (3.14 rad) with
    less travel, and toppra's spline through it leaves the limit. The greedy track has no
    jump, so it is kept, and toppra times it. Mutation caught: the rule dropped (``if
    walk.redundant(robot, ts)`` -> ``if False``) -> the limit-riding track, toppra refuses.
    """
    robot = so.load_robot(str(ROOT / "examples" / "arm6.urdf"))
    ts = so.paths.line([0.6, 0.1, 0.2], [0.6, 0.3, 0.2], 36)
    jp = so.ik_path(robot, ts)
    greedy = so.ik_path(robot, ts, branches="greedy")
    assert jp.ok and np.array_equal(jp.q, greedy.q)
    assert so.time_parameterize(jp, robot, amax=5.0).duration > 0
