"""Motion programs (scara_opt.motion): moves, tool limits, branches, bad input.

References are independent of the code under test: the tool speed and acceleration are
measured by FK finite differences at 1 kHz; the circle is rebuilt from its three points by
solving the perpendicular-bisector equations; the single-joint time is the textbook
trapezoid.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.errors import InputError, MoveError
from scara_opt.motion import CIRC, LIN, PTP, ToolLimits, plan
from scara_opt.motion.plan import move_joints
from scara_opt.motion.tool_limits import tool_peaks

Q0 = np.array([-1.0, 1.15, 0.01, 0.0])
#: tip at Q0 (zavar2024 eq. 5: a1 = a2 = 0.2 m, z = -d3 - 0.05 m)
P0 = np.array([0.2 * np.cos(-1.0) + 0.2 * np.cos(0.15), 0.2 * np.sin(-1.0) + 0.2 * np.sin(0.15),
               -0.06])


@pytest.fixture(scope="module")
def robot() -> so.Robot:
    return so.load_robot("zavar2024")


def _speeds(robot: so.Robot, traj: so.Trajectory) -> np.ndarray:
    t = traj.times(1e-3)
    return tool_peaks(robot, traj.evaluate(t), 1e-3)["speed"]


def test_lin_cruises_at_the_commanded_speed(robot):
    """A 0.3 m LIN at 0.25 m/s cruises at 0.25 m/s within 1 % (FK at 1 kHz) and never above.

    Mutation: the tool limits given to toppra scaled by 0.9 (``tool.scaled(scale)`` ->
    ``tool.scaled(scale * 0.9)`` in timing.py) -> the cruise is 10 % slow, fails.
    """
    p0 = robot.position(Q0)
    traj = plan(robot, [LIN(p0 + [0.0, 0.3, 0.0], speed=0.25)],
                ToolLimits(acceleration=3.0), start=Q0)
    v = _speeds(robot, traj)
    m = len(v)
    cruise = v[m // 4: 3 * m // 4]
    assert np.abs(cruise / 0.25 - 1).max() < 0.01
    assert v.max() <= 0.25
    assert traj.check_limits()["tool_speed"].max() <= 1.0


def _circumcentre(a, b, c):
    """Centre of the circle through a, b, c: equidistant, and in their plane."""
    n = np.cross(b - a, c - a)
    A = np.array([b - a, c - a, n])
    rhs = np.array([(b @ b - a @ a) / 2, (c @ c - a @ a) / 2, n @ a])
    return np.linalg.solve(A, rhs)


def test_circ_points_lie_on_the_circle(robot):
    """The FK of every joint point of a CIRC lies on the circle within 1e-9 m, in its plane.

    The trajectory sampled at 1 kHz stays within 1e-6 m (the joint spline between points).
    Mutation: the circumcentre's denominator ``2 * nn**2`` -> ``2 * nn`` (geometry.py) -> the
    points leave the circle, fails.
    """
    p0 = robot.position(Q0)
    via, goal = p0 + [0.05, 0.05, 0.0], p0 + [0.0, 0.1, 0.0]
    Q = move_joints(0, CIRC(via, goal), robot, Q0, 0.002)
    c = _circumcentre(p0, via, goal)
    r = np.linalg.norm(p0 - c)
    P = robot.positions(Q)
    assert np.abs(np.linalg.norm(P - c, axis=1) - r).max() < 1e-9
    assert np.abs(P[:, 2] - p0[2]).max() < 1e-9
    traj = plan(robot, [CIRC(via, goal, speed=0.2)], start=Q0)
    S = robot.positions(traj.evaluate(traj.times(1e-3)))
    assert np.abs(np.linalg.norm(S - c, axis=1) - r).max() < 1e-6


def test_single_joint_ptp_matches_the_trapezoid(robot):
    """A PTP moving theta1 alone takes the trapezoid time (limits x (1 - margin)), not longer.

    The trapezoid at the full limits is a lower bound; at the scaled limits the toppra time
    may exceed it only by the grid's round-off (1e-3).
    Mutation: MARGIN 0.005 -> 0.05 (timing.py) -> 5 % slower than the trapezoid, fails.
    """
    q1 = Q0 + [1.5, 0.0, 0.0, 0.0]
    traj = plan(robot, [PTP(q1)], start=Q0)
    v, a = robot.velocity_limit[0], robot.acceleration_limit[0]

    def trapezoid(v: float, a: float, d: float = 1.5) -> float:
        return d / v + v / a if d >= v * v / a else 2 * math.sqrt(d / a)

    assert trapezoid(v, a) <= traj.duration
    assert traj.duration <= trapezoid(v * 0.995, a * 0.995) * (1 + 1e-3)  # documented margin


def test_tool_acceleration_on_an_arc_is_honoured_without_stretch(robot):
    """On a tight arc the tool acceleration (tangential and centripetal) stays <= the limit.

    toppra honours it by itself (the notes show no time stretch) and the limit is reached
    (ratio >= 0.95).
    Mutation: the centripetal part dropped (``b = [along, across]`` -> ``[along, 0 * across]``
    in tool_limits.py) -> toppra goes too fast, the check stretches time, fails.
    """
    p0 = robot.position(Q0)
    traj = plan(robot, [CIRC(p0 + [0.04, 0.04, 0.0], p0 + [0.0, 0.08, 0.0])],
                ToolLimits(speed=0.3, acceleration=1.5), start=Q0)
    ratio = traj.check_limits()["tool_acceleration"].max()
    assert 0.95 <= ratio <= 1.0
    assert "stretched" not in traj.notes


def test_program_stops_at_every_goal_and_keeps_all_limits(robot):
    """Without blends every goal is reached at rest; all joint and tool ratios are <= 1."""
    p0 = robot.position(Q0)
    moves = [CIRC(p0 + [0.05, 0.05, 0], p0 + [0, 0.1, 0], speed=0.2),
             PTP(so.Target(p0 + [0, 0, -0.02]), elbow="lefty"),
             LIN(p0 + [0.05, 0.0, -0.02], speed=0.1)]
    traj = plan(robot, moves, ToolLimits(acceleration=2.0), start=Q0)
    q, qd, _ = traj.sample(traj.waypoint_times)
    assert np.allclose(q, traj.waypoints, atol=1e-9)
    assert np.abs(qd).max() < 1e-9
    for name, ratios in traj.check_limits().items():
        assert ratios.max() <= 1.0, name
    assert np.allclose(robot.position(traj.waypoints[-1]), p0 + [0.05, 0.0, -0.02], atol=1e-9)


def test_ptp_elbow_choice_and_lin_keeps_the_branch(robot):
    """elbow='lefty' on a PTP flips the arm; a LIN asked to be lefty from a righty start is
    refused, as is a LIN to a joint goal on the other branch.

    Mutation: SIGN = {"righty": 1, "lefty": -1} swapped (branch.py) -> the PTP lands righty.
    """
    from scara_opt.motion.branch import elbow_signs

    p0 = robot.position(Q0)
    assert elbow_signs(robot, Q0)[0] == 1
    traj = plan(robot, [PTP(so.Target(p0 + [0, 0.05, 0]), elbow="lefty")], start=Q0)
    assert elbow_signs(robot, traj.waypoints[-1])[0] == -1
    with pytest.raises(MoveError, match="move 0: .*righty, not lefty"):
        plan(robot, [LIN(p0 + [0, 0.05, 0], elbow="lefty")], start=Q0)
    lefty = traj.waypoints[-1]
    with pytest.raises(MoveError, match="move 1: .*reach that goal with a PTP"):
        plan(robot, [LIN(p0 + [0, 0.05, 0]), LIN(lefty)], start=Q0)


@pytest.mark.parametrize("moves, match", [
    ([CIRC(P0 + [0.02, 0.0, 0.0], P0 + [0.04, 0.0, 0.0])], "move 0: CIRC .* collinear"),
    ([LIN([0.3, 0.2, -0.06]), LIN([-0.3, 0.01, -0.06])], "move 1: LIN point .* unreachable"),
    ([PTP([0.5, 0.0, -0.06])], "move 0: PTP goal .* unreachable"),
    ([LIN([0.3, 0.2, -0.06], speed=0)], "move 0: LIN speed=0 .* > 0"),
    ([LIN([0.3, 0.2, -0.06], acceleration=-1.0)], "move 0: LIN acceleration=-1"),
    ([LIN([0.3, 0.2, -0.06], blend=0.5), LIN([0.3, 0.1, -0.06])], "move 0: blend radius 0.5"),
    ([LIN([0.3, 0.2, -0.06], blend=0.02)], "move 0: the last move has a blend"),
    ([LIN([0.3, 0.2, -0.06], elbow="left")], "move 0: elbow='left'"),
    ([LIN([0.3, 0.2])], "move 0: goal must be"),
    ([PTP(Q0)], "move 0: PTP goal is where the robot already is"),
])
def test_bad_moves_name_the_move_and_the_fix(robot, moves, match):
    """Each bad program raises MoveError naming the move index and what to change."""
    with pytest.raises(MoveError, match=match):
        plan(robot, moves, start=Q0)


def test_held_yaw_out_of_the_wrist_range_is_not_called_unreachable(robot):
    """A CIRC over 210° of zavar2024's reachable circle (ROBOTS.md) with the tool yaw held:
    every point is reachable, but the wrist (±120°) cannot hold the yaw. The error says so
    and names the fix, not "unreachable ... leaves the workspace".

    Mutation: the yaw branch in ``branch._ik_path_joints`` removed -> "unreachable", fails.
    """
    arc = so.paths.zavar2024_circle(reachable=True)[:8]
    assert all(so.ik_all(robot, t) for t in arc)
    with pytest.raises(MoveError, match=r"move 1: CIRC point \d+ of \d+ at .* is reachable, "
                                        r"but not with the tool yaw .* give the goal a yaw"):
        plan(robot, [PTP(arc[0]), CIRC(arc[3], arc[7])])


@pytest.mark.parametrize("kw", [{"speed": 0.0}, {"acceleration": -2.0},
                                {"yaw_rate": float("nan")}, {"speed": math.inf}])
def test_zero_negative_or_nonfinite_tool_limits_are_refused(kw):
    """ToolLimits refuses zero, negative, NaN and infinite limits, naming the limit."""
    name = next(iter(kw))
    with pytest.raises(InputError, match=f"tool {name} limit"):
        ToolLimits(**kw)


def test_zero_joint_limit_is_refused(robot):
    """A zero joint limit is refused before planning (the joint limits' own check)."""
    with pytest.raises(InputError, match="vmax"):
        plan(robot, [PTP(Q0 + 0.1)], start=Q0, vmax=0.0)


def test_exports_round_trip(robot, tmp_path):
    """CSV, JSON and ROS YAML hold the same samples; ROS stamps are exact and increasing.

    Mutation: ``stamp`` without the carry (``ns % 1_000_000_000`` -> ``ns``) -> nanosec
    beyond 1e9, fails.
    """
    import json

    from scara_opt.motion import export

    yaml = pytest.importorskip("yaml")
    traj = plan(robot, [PTP(Q0 + [0.3, 0.2, 0.01, 0.5])], start=Q0)
    t = traj.times(0.01)
    q, qd, qdd = traj.sample(t)
    csv = np.loadtxt(traj.to_csv(tmp_path / "t.csv", dt=0.01), delimiter=",", skiprows=1)
    header = (tmp_path / "t.csv").read_text().splitlines()[0].split(",")
    assert header[:5] == ["t_s", "theta1_rad", "theta2_rad", "d3_m", "theta4_rad"]
    assert np.allclose(csv[:, 0], t) and np.allclose(csv[:, 1], q[:, 0], atol=1e-9)
    data = json.loads(export.to_json(traj, tmp_path / "t.json").read_text())
    assert data["units"] == ["rad", "rad", "m", "rad"]
    assert np.allclose(data["qdd"], qdd)
    msg = yaml.safe_load(export.to_ros_yaml(traj, tmp_path / "t.yaml").read_text())
    assert msg["joint_names"] == robot.joint_names
    stamps = [p["time_from_start"] for p in msg["points"]]
    secs = np.array([s["sec"] + s["nanosec"] * 1e-9 for s in stamps])
    assert all(0 <= s["nanosec"] < 10**9 for s in stamps)
    assert np.all(np.diff(secs) > 0) and abs(secs[-1] - traj.duration) < 1e-9
    assert np.allclose([p["velocities"] for p in msg["points"]], qd)
    assert export.stamp(1.9999999999) == {"sec": 2, "nanosec": 0}


def test_cycle_time_places_the_standard_cycle_and_beats_the_quintic(robot):
    """The 25/305/25 mm cycle is placed with the strokes exact; toppra <= quintic baseline.

    The six corners are reached at rest, all limits hold; the ruckig and quintic times
    stop at the same corners.
    Mutation: the place corner raised by the up stroke (``B = centre + across / 2 * w
    + h_place * g.n`` -> ``... + (h_place + up) * g.n``) -> A-B is not 305 mm, fails.
    """
    from scara_opt.motion.cycle import cycle_time

    res = cycle_time(robot)
    P = robot.positions(res.corners)
    assert np.allclose(np.linalg.norm(P[0] - P[3]), 0.305, atol=1e-9)
    assert np.allclose(np.linalg.norm(P[1] - P[0]), 0.025, atol=1e-9)
    assert np.allclose(np.linalg.norm(P[3] - P[2]), 0.025, atol=1e-9)
    assert np.allclose(P[6], P[0], atol=1e-9)
    assert res.durations["toppra"] <= res.durations["quintic"]
    assert set(res.durations) == {"toppra", "ruckig", "quintic"}
    assert max(v.max() for v in res.trajectory.check_limits().values()) <= 1.0


def test_blended_cycle_runs_through_the_upper_corners_within_the_radius(robot, capsys):
    """``cycle_time(blend=0.01)`` adds ``toppra_blended``: faster than stopping, moving at
    the four upper corners, each within 10 mm, at rest at pick and place, limits <= 1; the
    stopping times are those without a blend. ``cycle --blend 10`` prints it; a radius
    above half the 25 mm stroke names 0.0125 m.

    Mutation: the blended plan built with ``program(0.0)`` -> as slow as stopping, fails.
    """
    from scara_opt.cli import main
    from scara_opt.motion.cycle import cycle_time

    plain, res = cycle_time(robot), cycle_time(robot, blend=0.01)
    assert {k: res.durations[k] for k in plain.durations} == plain.durations
    assert res.durations["toppra_blended"] < 0.95 * plain.durations["toppra"]
    dev = res.trajectory.blend_deviations()
    assert len(dev) == 4 and (dev > 0).all() and (dev <= 0.01).all()
    stops = np.isin(res.trajectory.waypoint_times, res.trajectory.stops)
    P = robot.positions(res.trajectory.waypoints[stops])
    assert np.allclose(P, robot.positions(res.corners[[0, 3, 6]]), atol=1e-9)
    assert max(v.max() for v in res.trajectory.check_limits().values()) <= 1.0
    assert main(["cycle", "zavar2024", "--blend", "10"]) == 0
    assert "toppra_blended" in capsys.readouterr().out
    with pytest.raises(InputError, match="blend <= 0.0125"):
        cycle_time(robot, blend=0.02)


def test_cycle_too_long_for_the_robot_says_what_to_shrink(robot):
    """An across stroke beyond the reach raises InputError asking for a shorter across=."""
    from scara_opt.motion.cycle import cycle_time

    with pytest.raises(InputError, match="shorter across="):
        cycle_time(robot, across=0.9)


def test_cli_cycle_writes_the_csv_at_dt(tmp_path, capsys):
    """``scara-opt cycle zavar2024 --out DIR --csv --plot --dt 0.002`` prints the three
    times and writes the CSV and figure into DIR; a second run into DIR is refused without
    ``--force`` (exit 2, the CSV untouched), and files without ``--out`` are bad input.

    Mutation caught: the cycle's files written without the OutputDir conflict check (the
    user's cycle.csv overwritten).
    """
    from scara_opt.cli import main

    code = main(["cycle", "zavar2024", "--out", str(tmp_path), "--csv", "--dt", "0.002",
                 "--plot"])
    assert code == 0
    out = capsys.readouterr().out
    assert "toppra" in out and "ruckig" in out and "quintic" in out
    csv = tmp_path / "cycle.csv"
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.allclose(np.diff(data[:-1, 0]), 0.002)
    assert (tmp_path / "cycle.png").stat().st_size > 0
    before = csv.read_bytes()
    assert main(["cycle", "zavar2024", "--out", str(tmp_path), "--csv", "--dt", "0.01"]) == 2
    assert csv.read_bytes() == before
    assert "--force" in capsys.readouterr().err
    assert main(["cycle", "zavar2024", "--csv"]) == 2
    assert "--out" in capsys.readouterr().err


def test_blended_corners_are_cut_within_the_radius_without_stopping(robot):
    """Blends keep the tip within r of each corner, never stop there, and save time.

    Reference: a 90° LIN-LIN corner rounded by the Bézier passes the corner at r√2/4.
    Mutation: the Bézier's control point moved off the corner (``geometry.bezier(A, C,
    pts[0], ...)`` -> ``geometry.bezier(A, 2 * C - A, pts[0], ...)`` in blend.py) -> the tip
    swings beyond r, fails.
    """
    moves = [LIN(P0 + [0, 0.1, 0], blend=0.02), LIN(P0 + [-0.08, 0.1, 0], blend=0.02),
             CIRC(P0 + [-0.12, 0.05, 0], P0 + [-0.08, 0.0, 0], blend=0.02), LIN(P0)]
    tool = ToolLimits(speed=0.3, acceleration=2.0)
    blended = plan(robot, moves, tool, start=Q0)
    stopped = plan(robot, [LIN(P0 + [0, 0.1, 0]), LIN(P0 + [-0.08, 0.1, 0]),
                           CIRC(P0 + [-0.12, 0.05, 0], P0 + [-0.08, 0.0, 0]), LIN(P0)],
                   tool, start=Q0)
    dev = blended.blend_deviations()
    radii = np.array([r for _, r, _ in blended.corners])
    assert len(dev) == 3 and (dev <= radii).all() and (dev > 0).all()
    assert abs(dev[0] - 0.02 * math.sqrt(2) / 4) < 1e-5
    t = blended.times(1e-3)
    P = robot.positions(blended.evaluate(t))
    for c, _, _ in blended.corners:  # moving (joint speed > 0.05) where it passes the corner
        i = int(np.argmin(np.linalg.norm(P - c, axis=1)))
        assert np.linalg.norm(blended.evaluate(t[i], 1)) > 0.05
    assert blended.duration < stopped.duration
    assert max(v.max() for v in blended.check_limits().values()) <= 1.0


def _up_across_down(robot, r):
    """The pick-and-place pattern: LIN 25 mm up, PTP 0.2 m across, LIN 25 mm down."""
    q0 = np.array([-1.0, 1.15, 0.035, 0.0])
    up = robot.position(q0) + [0.0, 0.0, 0.025]
    moves = [LIN(up, blend=r), PTP(so.Target(up + [0.0, 0.2, 0.0]), blend=r),
             LIN(up + [0.0, 0.2, -0.025])]
    return plan(robot, moves, ToolLimits(speed=0.5, acceleration=3.0), start=q0)


def test_blends_with_a_ptp_stay_in_the_sphere_and_on_the_moves_outside_it(robot):
    """LIN -> PTP -> LIN with blend 10 mm: each corner is passed moving, within r, and
    away from the corners' spheres the tip is on the unblended path (1 kHz FK, nearest
    sample of the stopped plan at 10 kHz within 0.2 mm; measured 0.05 mm); ends at the
    goal; all ratios <= 1; faster.

    Mutations (blend_joint.py): the Bézier's control point ``Q[-1]`` -> ``2 * Q[-1] - A``
    -> the corner leaves its sphere, refused, fails; the cuts 3 samples outside the sphere
    (``a, b = int(out[-1]) - 3, int(out_next[0]) + 3``) -> the tip leaves the path outside
    the sphere, fails.
    """
    r = 0.01
    blended, stopped = _up_across_down(robot, r), _up_across_down(robot, 0.0)
    dev = blended.blend_deviations()
    assert len(dev) == 2 and (dev > 0).all() and (dev <= r).all()
    t = blended.times(1e-3)
    P = robot.positions(blended.evaluate(t))
    corners = np.array([c for c, _, _ in blended.corners])
    for c in corners:  # moving where it passes the corner
        i = int(np.argmin(np.linalg.norm(P - c, axis=1)))
        assert np.linalg.norm(blended.evaluate(t[i], 1)) > 0.05
    ref = robot.positions(stopped.evaluate(stopped.times(1e-4)))
    away = (np.linalg.norm(P[:, None, :] - corners[None], axis=2) > r).all(axis=1)
    gap = np.array([np.linalg.norm(ref - p, axis=1).min() for p in P[away]])
    assert away.sum() > 100 and gap.max() < 2e-4
    assert np.allclose(blended.waypoints[-1], stopped.waypoints[-1], atol=1e-12)
    assert blended.duration < stopped.duration
    assert max(v.max() for v in blended.check_limits().values()) <= 1.0


@pytest.mark.parametrize("hair", [-1e-12, 0.0, 1e-12])
def test_blend_radius_through_a_sample_of_the_lin_still_plans(robot, hair):
    """A radius at a LIN sample's distance from the corner (the 25 mm strokes, sampled
    every ``STEP``; that distance times 1 - 1e-12, 1, 1 + 1e-12) puts a sample on the
    sphere, next to the cut: it is dropped, not kept as a near-duplicate waypoint that
    toppra's spline cannot follow.

    Mutations: either quarter-step guard removed (``end = a + 1``, ``start = b`` always)
    -> TrajectoryError, fails.
    """
    from scara_opt.motion import geometry
    from scara_opt.motion.plan import STEP

    intervals = geometry.count(0.025, STEP) - 1
    r = 0.025 * (intervals // 2) / intervals * (1 + hair)   # at a sample's distance
    traj = _up_across_down(robot, r)
    assert (traj.blend_deviations() <= r).all()
    assert max(v.max() for v in traj.check_limits().values()) <= 1.0


def test_blend_with_a_ptp_too_large_names_the_move_and_the_largest(robot):
    """A radius above half of the 25 mm LIN is refused with the move and 0.0125 m."""
    with pytest.raises(MoveError, match=r"move 0: blend radius 0.02 m .* blend <= 0.0125"):
        _up_across_down(robot, 0.02)


def test_wrist_takes_the_nearest_turn_and_fast_ik_matches_ik_path():
    """On fang (wrist ±360°) a LIN whose goal yaw is given wrapped keeps the wrist's turn.

    The vectorised closed form equals ik_path's solution point by point (1e-9).
    Mutation: the unwrap from the previous point dropped (``Q[:, revolute] = np.unwrap(...)``
    -> ``Q[:, revolute] = Q[:, revolute]`` in branch.py) -> the wrist takes the turn nearest
    0 (3.4 rad -> -2.9 rad): the fast path is refused and so is the step, fails.
    """
    from scara_opt.motion.branch import closed_form_path, tool_pose

    fang = so.load_robot("fang")
    q0 = np.array([-1.0, 1.2, 0.0, 3.4])
    p, yaw = tool_pose(fang, q0)
    wrapped = math.remainder(yaw + 0.3, 2 * math.pi)  # 3.9 rad given as -2.38 rad
    traj = plan(fang, [LIN(so.Target(p + [0, 0.1, 0], yaw=wrapped))], start=q0)
    wrist = traj.evaluate(traj.times(0.01))[:, 3]
    assert np.abs(np.diff(wrist)).max() < 0.05 and wrist.min() > 3.0
    P = p + np.linspace(0, 1, 20)[1:, None] * [0, 0.1, 0]
    yaws = yaw + np.linspace(0, 0.3, 20)[1:]
    fast = closed_form_path(fang, P, yaws, q0)
    targets = [so.Target(pt, float(y)) for pt, y in zip(P, yaws, strict=True)]
    slow = so.ik_path(fang, targets, q_start=q0).q
    assert fast is not None and np.abs(fast - slow).max() < 1e-9


def test_blended_run_keeps_each_moves_own_speed():
    """A 0.1 m/s LIN blended into a 0.3 m/s LIN cruises at each speed on its own stretch.

    Mutation: the profile takes the run's smallest limit everywhere (``np.minimum(v[:-1],
    v[1:])`` -> ``np.full(len(v) - 1, v.min())`` in tool_limits.py) -> the second LIN
    crawls at 0.1 m/s, fails.
    """
    robot = so.load_robot("zavar2024")
    moves = [LIN(P0 + [0, 0.1, 0], speed=0.1, blend=0.01), LIN(P0 + [-0.1, 0.1, 0], speed=0.3)]
    traj = plan(robot, moves, ToolLimits(acceleration=3.0), start=Q0)
    t = traj.times(1e-3)
    P = robot.positions(traj.evaluate(t))
    v = np.linalg.norm(np.diff(P, axis=0), axis=1) / 1e-3
    mid = (P[1:] + P[:-1]) / 2
    first = np.abs(mid[:, 1] - (P0[1] + 0.05)) < 0.01  # around the middle of each LIN
    second = np.abs(mid[:, 0] - (P0[0] - 0.05)) < 0.01
    assert np.abs(v[first] / 0.1 - 1).max() < 0.01
    assert np.abs(v[second] / 0.3 - 1).max() < 0.01
    assert traj.check_limits()["tool_speed"].max() <= 1.0


def test_jerk_limited_variant_matches_ruckig_on_one_joint_and_keeps_limits(robot):
    """method='ruckig': on a one-joint PTP it equals joint-space Ruckig (same v, a, j);
    on a blended program every ratio is <= 1 and it is no faster than toppra.

    Mutation: the path jerk 10/s x U -> 5/s x U (``JERK_PER_ACCELERATION * U`` ->
    ``5 * U`` in jerk.py) -> slower than joint-space Ruckig, fails.
    """
    q1 = Q0 + [1.5, 0.0, 0.0, 0.0]
    ours = plan(robot, [PTP(q1)], start=Q0, method="ruckig")
    ref = so.time_parameterize([Q0, q1], robot, method="ruckig")
    assert abs(ours.duration - ref.duration) < 1e-5 * ref.duration
    moves = [LIN(P0 + [0, 0.1, 0], blend=0.01), CIRC(P0 + [-0.05, 0.15, 0], P0 + [0, 0.2, 0])]
    tool = ToolLimits(speed=0.3, acceleration=2.0)
    jerk = plan(robot, moves, tool, start=Q0, method="ruckig")
    fast = plan(robot, moves, tool, start=Q0)
    assert max(v.max() for v in jerk.check_limits().values()) <= 1.0
    assert jerk.duration >= fast.duration
    with pytest.raises(InputError, match="method must be one of"):
        plan(robot, moves, start=Q0, method="quintic")


def test_lin_that_needs_the_other_branch_is_refused_with_the_point(robot):
    """A righty LIN whose end the righty arm cannot reach (θ1 beyond -120°) but the lefty arm
    can is refused as leaving the branch, with the point; the arc to -70° is fine.

    Reference (zavar2024, r = 0.3 m): at -80° the righty shoulder angle is
    -80° - γ/2 = -121.4° with γ = arccos(0.125) = 82.8°, beyond the -120° limit.
    Mutation: the branch check of the solved path dropped (``off = np.flatnonzero(...)`` ->
    ``off = np.flatnonzero(signs != signs)`` in branch.py) -> reported as a joint jump, fails.
    """
    def at(deg: float) -> so.Target:
        a = math.radians(deg)
        return so.Target([0.3 * math.cos(a), 0.3 * math.sin(a), -0.06], yaw=-1.0)

    from scara_opt.motion.branch import elbow_signs

    start = PTP(at(0), elbow="righty")
    plan(robot, [start, LIN(at(-70))])
    with pytest.raises(MoveError, match=r"move 1: LIN leaves the righty branch at point \d+"):
        plan(robot, [start, LIN(at(-80))])
    split = plan(robot, [start, LIN(at(-80))], allow_flip=True)  # stop, flip, go on
    P = robot.positions(split.waypoints)
    assert list(elbow_signs(robot, split.waypoints)) == [1, 1, -1, -1]
    assert np.allclose(P[1], P[2], atol=1e-9) and np.allclose(P[3], at(-80).position, atol=1e-9)
    line = np.cross(P[1] - P[0], at(-80).position - P[0])  # the cut is on the line
    assert np.linalg.norm(line) < 1e-9


def test_each_paper_report_times_the_standard_cycle(tmp_path):
    """reproduce carries a beyond-the-paper row with the standard cycle's three times, equal
    to cycle_time's for that robot (computed, not written down).

    Mutation caught: ``add_cycle_finding`` not called from inverted5's ``run`` (no row).
    """
    from scara_opt.motion.cycle import cycle_time
    from scara_opt.reports import run_paper

    rep = run_paper("inverted5", tmp_path)
    rows = [f for f in rep.findings if f.item.startswith("standard pick-and-place cycle")]
    assert len(rows) == 1 and rows[0].verdict == "beyond the paper"
    times = cycle_time(so.load_robot("inverted5")).durations
    assert f"toppra {times['toppra']:.3f} s" in rows[0].ours
    assert f"quintic {times['quintic']:.3f} s" in rows[0].ours


def test_a_motion_program_keeps_torque_limits_and_a_payload_only_slows_it(tmp_path, capsys):
    """plan(torque_limits=, payload=) adds toppra's torque constraint (RNEA, gravity) to the
    joint and tool limits: with fang's arm torques cut to 3 % the cycle is slower than the
    rate-limited one, every sampled torque ratio stays <= 1, and 1 and 2 kg at the tool are
    each slower still; ruckig refuses torque limits; ``cycle --payload`` reports the time.

    Mutations caught: the torque constraint not given to toppra (a > 5 % stretch, refused);
    plan() not passing its dynamics to the sections (no torque in check_limits).
    """
    from scara_opt.cli import main
    from scara_opt.motion.cycle import cycle_with_payload

    robot = so.load_robot("fang")
    res = so.cycle_time(robot)
    weak = robot.torque_limit * np.array([0.03, 0.03, 1.0, 0.03])  # d3 still holds gravity
    times = []
    for kg in (0.0, 1.0, 2.0):
        traj = so.plan(robot, res.trajectory.moves, start=res.corners[0], torque_limits=weak,
                       payload=kg)
        assert float(traj.check_limits()["torque"].max()) <= 1.0 + 1e-9
        times.append(traj.duration)
    assert res.durations["toppra"] < times[0] < times[1] < times[2]
    with pytest.raises(so.InputError, match="toppra"):
        so.plan(robot, res.trajectory.moves, start=res.corners[0], method="ruckig", payload=1.0)
    loaded = cycle_with_payload(robot, res, 2.0)
    assert loaded.duration >= res.durations["toppra"] - 1e-12
    assert main(["cycle", "fang", "--payload", "2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["payload_kg"] == 2.0 and data["payload_toppra_s"] == pytest.approx(
        loaded.duration)


def test_a_motion_trajectory_without_its_robot_refuses_the_fk_checks(robot):
    """A MotionTrajectory stripped of its robot says so (InputError) instead of crashing.

    Mutation caught: ``_robot()`` returning ``self.robot`` unchecked -> AttributeError
    ('NoneType' object has no attribute ...) from check_limits and blend_deviations.
    """
    from dataclasses import replace

    p0 = robot.position(Q0)
    traj = plan(robot, [LIN(p0 + [0.0, 0.1, 0.0], blend=0.02), LIN(p0 + [-0.1, 0.1, 0.0])],
                ToolLimits(speed=0.25, acceleration=3.0), start=Q0)
    assert traj.corners and traj.blend_deviations().shape == (1,)
    bare = replace(traj, robot=None)
    with pytest.raises(InputError, match="no robot"):
        bare.check_limits()
    with pytest.raises(InputError, match="no robot"):
        bare.blend_deviations()


@pytest.mark.parametrize("kind", ["LIN", "PTP"])
def test_a_move_down_blended_into_the_same_move_back_up_plans(robot, kind):
    """A 30 mm move straight down blended (r = 5 mm) into the move back up plans: the tip
    turns back r/2 above the bottom (the Bézier of a reversal passes (A + 2C + B)/4, A = B),
    every sample finite, all ratios <= 1, ends at the top.

    Issue 38's run: toppra's "x must be strictly increasing" for LIN; for PTP a plan whose
    limit ratios are NaN (a zero step of toppra's grid). Mutation caught:
    ``geometry.corner_count`` returning ``count(2 * radius, step, least=5)`` (even: 6
    samples at r = 5 mm, step 2 mm, the middle two equal) -> LIN raises ValueError, PTP's
    ratios NaN, fails.
    """
    move = {"LIN": LIN, "PTP": lambda p, **kw: PTP(so.Target(p), **kw)}[kind]
    r, top = 0.005, P0 + [0.05, 0.0, 0.0]
    bottom = top - [0.0, 0.0, 0.03]
    traj = plan(robot, [LIN(top), move(bottom, blend=r), move(top)],
                ToolLimits(speed=0.3, acceleration=2.0), start=Q0)
    Q = traj.evaluate(traj.times(1e-3))
    assert np.isfinite(Q).all() and np.isfinite(traj.evaluate(traj.times(1e-3), 1)).all()
    dev = traj.blend_deviations()
    assert len(dev) == 1 and abs(dev[0] - r / 2) < 1e-4
    assert np.allclose(robot.position(traj.waypoints[-1]), top, atol=1e-9)
    assert max(v.max() for v in traj.check_limits().values()) <= 1.0
