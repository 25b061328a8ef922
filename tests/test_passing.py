"""Ruckig through waypoints without stopping (scara_opt.trajectory.passing, ruckig_backend).

Independent checks at 1 kHz: by the mean value theorem the first, second and third
divided differences of positions sampled every 1 ms are the velocity, acceleration and
jerk at some instant, so each is at most the limit whatever the code computed for its
peaks. Positions are exact only to Ruckig's precision at the joins (about 1e-12 rad;
measured 2e-12), which an order-k difference divides by DT**k: the bound allows
2**k * POSITION_EPS / DT**k for it (8e-2 rad/s³ on the jerk, against limits of 10 to
10,000 rad/s³). References: toppra's time-optimal duration on the same waypoints, and the
same waypoints timed rest to rest, segment by segment.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.trajectory import ruckig_point_to_point

DT = 1e-3
#: position precision of the joins between Ruckig segments [rad or m] (measured 2e-12)
POSITION_EPS = 1e-11


def check_at_1khz(traj: so.Trajectory) -> None:
    """Velocity, acceleration and jerk within the limits by divided differences at 1 kHz."""
    t = np.arange(0.0, traj.duration, DT)
    q = traj.evaluate(t)
    lim = traj.limits
    for order, bound in ((1, lim.vmax), (2, lim.amax), (3, lim.jmax)):
        d = np.diff(q, n=order, axis=0) / DT**order
        slack = 2**order * POSITION_EPS / DT**order
        assert (np.abs(d).max(axis=0) <= bound * (1 + 1e-6) + slack).all(), (order, d)
    assert max(float(v.max()) for v in traj.check_limits().values()) <= 1 + 1e-6


def moving_at_waypoints(traj: so.Trajectory) -> np.ndarray:
    """The joint speed |qd| (max over joints) at each interior waypoint."""
    return np.abs(traj.evaluate(traj.waypoint_times[1:-1], 1)).max(axis=1)


def test_ruckig_runs_the_20_point_arc_within_13_tenths_of_toppra(robots):
    """The 20-point arc (r = 0.30 m, z = -0.07 m, -50° to 110°) on zavar2024: ruckig moves
    through every interior waypoint and takes at most 1.3x toppra's time.

    Before: rest to rest at every waypoint, 6.36 s against toppra's 1.14 s (5.6x); now
    1.24 s (1.08x), along the path. Mutation caught: the joined segments always kept
    (``return along if ... else joined`` -> ``return joined``) -> 10.06 s, fails.
    """
    robot = robots["zavar2024"]
    arc = so.paths.circle((0, 0), 0.30, -0.07, 20, start=math.radians(-50),
                          sweep=math.radians(160))
    jp = so.ik_path(robot, arc)
    toppra = so.time_parameterize(jp, robot, method="toppra")
    ruckig = so.time_parameterize(jp, robot, method="ruckig")
    assert ruckig.duration <= 1.3 * toppra.duration, (ruckig.duration, toppra.duration)
    assert (moving_at_waypoints(ruckig) > 0.1).all()
    np.testing.assert_allclose(ruckig.evaluate(ruckig.waypoint_times), jp.q, atol=1e-9)
    assert "no intermediate waypoints" in ruckig.notes
    check_at_1khz(ruckig)


def test_ruckig_joins_sparse_waypoints_at_speed(ur5_arm):
    """The UR5-class arm's 5 poses: segments joined at the path's velocities, faster than
    rest to rest, every limit held at 1 kHz.

    Measured: 6.63 s against 7.56 s rest to rest (toppra 6.78 s). Mutation caught: the
    waypoint velocities zeroed (``V = d1 * sd[:, None]`` -> ``V = 0 * d1``) -> rest to rest,
    fails.
    """
    Q = np.random.default_rng(2).uniform(ur5_arm.lower, ur5_arm.upper, (5, 6))
    targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(ur5_arm.fk, Q)]
    jp = so.ik_path(ur5_arm, targets)
    ruckig = so.time_parameterize(jp, ur5_arm, method="ruckig", allow_jumps=True)
    rest = sum(ruckig_point_to_point(a, b, ur5_arm).duration
               for a, b in zip(jp.q[:-1], jp.q[1:], strict=True))
    assert ruckig.duration < 0.95 * rest, (ruckig.duration, rest)
    assert "joined" in ruckig.notes and (moving_at_waypoints(ruckig) > 0.1).all()
    np.testing.assert_allclose(ruckig.evaluate(ruckig.waypoint_times), jp.q, atol=1e-9)
    check_at_1khz(ruckig)


@pytest.mark.parametrize("n", [3, 7])
def test_two_waypoints_stay_rest_to_rest_and_more_keep_moving(robots, n):
    """Two waypoints: Ruckig's rest-to-rest move; three or more: moving, within the limits."""
    robot = robots["fang"]
    q = np.linspace([0.0, 0.5, 0.0, 0.0], [1.0, 1.5, 0.03, 2.0], n)
    q[:, 0] += 0.2 * np.sin(np.linspace(0, math.pi, n))
    traj = so.time_parameterize(q, robot, method="ruckig")
    assert (moving_at_waypoints(traj) > 0).all()
    check_at_1khz(traj)
    pair = so.time_parameterize(q[:2], robot, method="ruckig")
    assert "rest to rest" in pair.notes
    np.testing.assert_allclose(pair.evaluate(pair.waypoint_times, 1), 0.0, atol=1e-12)
