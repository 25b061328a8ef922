"""Whole turns (scara_opt.ik.turns): every method that honours q0 returns the turn nearest it.

The UR5-class arm of tests/data has ±2π on every joint: each pose is reached at up to
three angles per joint. Reference: the pose itself (FK by Pinocchio) and, per joint, the
other turns q ± 2π within the limits, none of which may be nearer q0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik.turns import nearest_turn, turn_joints
from tests.conftest import DATA

TURN = 2 * math.pi


def ur5_case(robot: so.Robot) -> tuple[np.ndarray, list[so.Target]]:
    """The issue's case: 5 full poses, FK of configurations uniform in the limits (seed 2)."""
    Q = np.random.default_rng(2).uniform(robot.lower, robot.upper, (5, robot.nq))
    return Q, [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(robot.fk, Q)]


def nearer_turn(robot: so.Robot, q: np.ndarray, q0: np.ndarray) -> list[str]:
    """Joints for which q ± 2π lies within the limits and nearer q0 than q."""
    out = []
    for k, name in enumerate(robot.joint_names):
        for alt in (q[k] - TURN, q[k] + TURN):
            if robot.lower[k] <= alt <= robot.upper[k] and abs(alt - q0[k]) < abs(q[k] - q0[k]):
                out.append(name)
    return out


@pytest.mark.parametrize("method", ["auto", "lm", "ipopt"])
def test_methods_that_honour_q0_return_the_turn_nearest_it(ur5_arm, method):
    """From each pose's configuration, the next pose's answer has no joint a turn nearer q0.

    Before: ipopt from Q[1] answered shoulder_pan = 5.44 rad where -0.85 rad reaches the
    same pose (|q - q0| summed 20.5 rad against 9.0). Mutation caught: the turn applied
    in the base (``nearest_turn(robot, out.q, q0a)`` -> ``out.q``) -> fails.
    """
    Q, targets = ur5_case(ur5_arm)
    for i in range(4):
        res = so.solve_ik(ur5_arm, targets[i + 1], method=method, q0=Q[i])
        assert res.success and ur5_arm.within_limits(res.q)
        assert not nearer_turn(ur5_arm, res.q, Q[i]), (i, res.q, Q[i])
    res = so.solve_ik(ur5_arm, targets[2], method="ipopt", q0=Q[1])
    assert res.q[0] == pytest.approx(-0.85, abs=0.01)


def test_solve_many_takes_the_turn_nearest_each_q0(ur5_arm):
    """solve_many with one q0 per target answers as solve_ik does: no joint a turn nearer.

    20 full poses and 20 unrelated q0s, uniform in the limits (seed 0). Before: 15 of the
    20 answers had a joint a whole turn farther from its q0 than needed.
    Mutation caught: the batch's turn skipped (``if Q_ref is not None`` -> ``if False`` in
    lm_batch._result) -> fails.
    """
    rng = np.random.default_rng(0)
    Q = rng.uniform(ur5_arm.lower, ur5_arm.upper, (20, 6))
    Q0 = rng.uniform(ur5_arm.lower, ur5_arm.upper, (20, 6))
    targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(ur5_arm.fk, Q)]
    batch = so.solve_many(ur5_arm, targets, q0s=Q0)
    assert batch.success.all()
    for i in range(20):
        assert not nearer_turn(ur5_arm, batch.q[i], Q0[i]), (i, batch.q[i], Q0[i])


def test_metaheuristic_and_closed_form_answers_take_the_turn_nearest_q0(robots):
    """fang's ±360° wrist: pso's and the closed form's wrist is the one nearest q0's.

    Mutation caught: the turn left to the solver (the base's call removed) -> pso answers
    a wrist a turn away from q0 = 5.5 rad, fails.
    """
    robot = robots["fang"]
    q_true = np.array([0.3, 0.9, 0.01, 0.4])
    target = so.Target(robot.position(q_true), yaw=robot.yaw(q_true))
    q0 = np.array([0.3, 0.9, 0.01, 3.0])
    for method, opts in (("pso", {"population": 40, "iterations": 100}), ("analytic", {})):
        res = so.solve_ik(robot, target, method=method, q0=q0, seed=1, **opts)
        assert not nearer_turn(robot, res.q, q0), (method, res.q)
        assert res.q[3] == pytest.approx(0.4, abs=0.05)


def test_turnable_joints_and_the_pose_they_keep(ur5_arm):
    """Turned joints keep the FK; leaders of fractional or prismatic mimics are never turned.

    mimic_arm's j3 follows j1 with multiplier -0.5 (a turn of j1 moves j3 by half a turn),
    the prismatic j5 follows j2. Mutation caught: the follower check dropped (``all(...)``
    -> ``True``) -> j1 and j2 listed, fails.
    """
    mimic = so.Robot.from_urdf(DATA / "mimic_arm.urdf", tip="tip").with_limits(
        j1=(-7.0, 7.0), j2=(-7.0, 7.0))
    assert turn_joints(mimic) == ()
    assert [k for k, _, _ in turn_joints(ur5_arm)] == list(range(6))
    q = np.array([0.5, -6.0, 2.0, 0.3, -0.2, 6.0])
    turned = nearest_turn(ur5_arm, q, np.zeros(6))
    np.testing.assert_allclose(turned, [0.5, -6.0 + TURN, 2.0, 0.3, -0.2, 6.0 - TURN])
    np.testing.assert_allclose(ur5_arm.fk(turned), ur5_arm.fk(q), atol=1e-12)
    cont = so.Robot.from_urdf(DATA / "continuous_arm.urdf")
    names = [cont.joint_names[k] for k, _, _ in turn_joints(cont)]
    assert "shoulder" not in names and {"turntable"} <= set(names)
    q = np.zeros(cont.nq)
    q[cont.joint_names.index("turntable")] = 10.0
    near = nearest_turn(cont, q, np.zeros(cont.nq))
    assert near[cont.joint_names.index("turntable")] == pytest.approx(10.0 - 2 * TURN)
    np.testing.assert_allclose(cont.fk(near), cont.fk(q), atol=1e-12)
    zavar = so.load_robot("zavar2024")  # ±120°: no other turn, the same array back
    q = np.array([0.1, 0.2, 0.01, 0.3])
    assert turn_joints(zavar) == () and nearest_turn(zavar, q, q + 6) is q


def test_ur5_path_travel_and_timing_after_the_turns(ur5_arm):
    """ik_path through the 5 poses: no joint a turn off, travel below the hand-unwrapped one.

    Before: 58.6 rad of travel (35.3 unwrapped by hand), toppra refused the path (its
    spline left ±2π by 0.29 rad), ruckig 11.8 s. Now the greedy walk travels 31.5 rad and
    the global one 33.6 rad (one jump fewer); toppra times both. Mutation caught: the
    base's turn removed -> the greedy travel is 58.6 rad, fails.
    """
    Q, targets = ur5_case(ur5_arm)
    for branches in ("greedy", "global"):
        jp = so.ik_path(ur5_arm, targets, branches=branches)
        assert jp.solved.all()
        for i in range(1, len(jp)):
            assert not nearer_turn(ur5_arm, jp.q[i], jp.q[i - 1]), (branches, i)
        assert jp.travel.sum() <= 35.3, branches
        traj = so.time_parameterize(jp, ur5_arm, method="toppra", allow_jumps=True)
        assert max(float(v.max()) for v in traj.check_limits().values()) <= 1 + 1e-9
