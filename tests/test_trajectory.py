"""Joint paths and their timing: fang's tables, the backends against their libraries, limits."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import scara_opt as so
from scara_opt import paths
from scara_opt.errors import (
    InputError,
    JointLimitError,
    SolverOptionError,
    TrajectoryError,
    UnknownSolverError,
)
from scara_opt.reports import reference_data
from scara_opt.trajectory import (
    JointPath,
    Trajectory,
    ik_path,
    quintic_blend,
    register_timing,
    resolve_limits,
    ruckig_point_to_point,
    shortest_duration,
    time_parameterize,
    timing_methods,
)
from scara_opt.trajectory.ruckig_backend import ruckig_segment
from scara_opt.trajectory.toppra_backend import chord_parameter, timed_pieces

REFERENCE = reference_data("fang")  # the paper's printed rows, shipped with the reports
#: paper units (deg, deg, mm, deg) -> SI
TO_SI = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])
METHODS = ("toppra", "ruckig", "quintic")
RATIO_TOL = 1e-6


def fang_move(table: dict) -> np.ndarray:
    return np.array([table["start"], table["end"]]) * TO_SI


def worst_ratio(traj: Trajectory) -> float:
    return max(float(r.max()) for r in traj.check_limits().values())


@pytest.fixture(scope="module")
def fang(robots) -> so.Robot:
    return robots["fang"]


@pytest.fixture(scope="module")
def zavar(robots) -> so.Robot:
    return robots["zavar2024"]


@pytest.fixture(scope="module")
def circle_path(zavar) -> JointPath:
    return ik_path(zavar, paths.zavar2024_circle(reachable=True))


# ---------------------------------------------------------------- fang, Tables 2 and 3
@pytest.mark.parametrize("table", REFERENCE["tables"], ids=lambda t: f"table{t['table']}")
def test_quintic_reproduces_fang_tables(fang, table):
    """Every printed row of Tables 2-3 within the tolerance, at tau = k/35, in deg and mm."""
    n = REFERENCE["samples"]
    rows = np.array(table["rows"])
    for duration in (1.0, None):  # positions at tau = k/35 do not depend on the duration
        # the paper's 1 s breaks the (assumed) limits of robots/fang.toml: opt in explicitly
        traj = time_parameterize(fang_move(table), fang, method="quintic", duration=duration,
                                 enforce_limits=False)
        ours = traj.sample(traj.duration * np.arange(n) / (n - 1))[0] / TO_SI
        assert np.abs(ours[:len(rows)] - rows).max() <= REFERENCE["tolerance"]
        assert np.allclose(ours[-1], table["end"], atol=1e-12)
    start, end = np.array(table["start"]), np.array(table["end"])
    blend = quintic_blend(np.arange(len(rows)) / (n - 1))[:, None]
    assert np.abs(start + (end - start) * blend - rows).max() <= REFERENCE["tolerance"]


@pytest.mark.parametrize("table", REFERENCE["tables"], ids=lambda t: f"table{t['table']}")
def test_toppra_and_ruckig_beat_the_shortest_quintic_on_fang(fang, table):
    """Both are shorter than the shortest quintic under the same limits, and within them."""
    Q = fang_move(table)
    d = {m: time_parameterize(Q, fang, method=m) for m in METHODS}
    assert math.isclose(d["quintic"].duration,
                        shortest_duration(Q[1] - Q[0], fang.velocity_limit,
                                          fang.acceleration_limit))
    assert d["toppra"].duration < d["ruckig"].duration < d["quintic"].duration
    for traj in d.values():
        assert worst_ratio(traj) <= 1 + RATIO_TOL
    assert max(float(r.max()) for r in d["quintic"].check_limits().values()) > 1 - 1e-9


def test_toppra_on_a_straight_move_is_bang_coast_bang(fang):
    """A two-waypoint move is a line: T = D/v + v/a of the slowest joint, limits x (1 - margin)."""
    Q = fang_move(REFERENCE["tables"][0])
    traj = time_parameterize(Q, fang, method="toppra")
    k = int(np.argmax(np.abs(Q[1] - Q[0]) / fang.velocity_limit))
    v, a = 0.995 * fang.velocity_limit[k], 0.995 * fang.acceleration_limit[k]
    D = abs(Q[1, k] - Q[0, k])
    assert math.isclose(traj.duration, D / v + v / a, rel_tol=1e-3)


# ---------------------------------------------------------------- backends vs libraries
def test_toppra_pieces_equal_toppras_const_accel_output(zavar, circle_path):
    """The degree-6 pieces reproduce toppra's own ParametrizeConstAccel to round-off.

    Mutation caught: the powers of ``s - knot`` built with the wrong term of the quadratic
    (``w[j + 1]`` for ``w[j]``) -> fails.
    """
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    Q = circle_path.q
    s = chord_parameter(Q, zavar.velocity_limit)
    path = toppra.SplineInterpolator(s, Q)
    grid = np.linspace(0, 1, 201)
    grid = np.unique(np.concatenate([grid, s]))
    inst = algo.TOPPRA([constraint.JointVelocityConstraint(zavar.velocity_limit),
                        constraint.JointAccelerationConstraint(zavar.acceleration_limit)],
                       path, gridpoints=grid, solver_wrapper="seidel")
    inst.compute_parameterization(0, 0)
    sd = inst.problem_data.sd_vec
    t, c = timed_pieces(path.cspl, grid, sd)
    ref = toppra.ParametrizeConstAccel(path, grid, sd)
    ts = np.random.default_rng(0).uniform(0, t[-1], 300)
    from scipy.interpolate import PPoly

    for order in (0, 1, 2):
        ours = np.stack([PPoly(c[:, :, k], t).derivative(order)(ts) if order else
                         PPoly(c[:, :, k], t)(ts) for k in range(Q.shape[1])], axis=1)
        assert np.allclose(ours, ref(ts, order), atol=1e-9, rtol=1e-9)
    assert math.isclose(t[-1], ref.duration, rel_tol=1e-12)


def test_ruckig_pieces_equal_ruckigs_own_trajectory(fang):
    """The constant-jerk pieces read from Ruckig's profiles match Trajectory.at_time."""
    import ruckig

    Q = fang_move(REFERENCE["tables"][1])
    limits = resolve_limits(fang, 4, need_jerk=True)
    pieces, T = ruckig_segment(Q[0], Q[1], limits)
    otg, inp, out = ruckig.Ruckig(4), ruckig.InputParameter(4), ruckig.Trajectory(4)
    inp.current_position, inp.target_position = list(Q[0]), list(Q[1])
    inp.max_velocity, inp.max_acceleration = list(limits.vmax), list(limits.amax)
    inp.max_jerk = list(limits.jmax)
    otg.calculate(inp, out)
    assert math.isclose(T, out.duration)
    for t in np.linspace(0, T, 97):
        p, v, a = out.at_time(t)
        for k, pp in enumerate(pieces):
            assert np.allclose([pp(t), pp.derivative()(t), pp.derivative(2)(t)],
                               [p[k], v[k], a[k]], atol=1e-9)


def test_ruckig_point_to_point_respects_jerk(fang):
    """The helper times one move within velocity, acceleration and jerk limits."""
    Q = fang_move(REFERENCE["tables"][0])
    traj = ruckig_point_to_point(Q[0], Q[1], fang, jmax=50.0)
    ratios = traj.check_limits()
    assert set(ratios) == {"velocity", "acceleration", "jerk"}
    assert np.isclose(ratios["jerk"].max(), 1.0) and worst_ratio(traj) <= 1 + RATIO_TOL
    assert np.allclose(traj.limits.jmax, 50.0)
    with pytest.raises(TrajectoryError, match="no move to time"):
        ruckig_point_to_point(Q[0], Q[0], fang)


def test_evaluate_refuses_a_bad_derivative_order(fang):
    """order is a derivative count: -1 (an antiderivative) or 1.5 is refused, not computed."""
    traj = time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="quintic")
    np.testing.assert_allclose(traj.evaluate(0.1, order=1), traj.sample(0.1)[1])
    for order in (-1, 1.5, True):
        with pytest.raises(InputError, match="order must be an integer >= 0"):
            traj.evaluate(0.1, order=order)


# ---------------------------------------------------------------- the Trajectory object
def test_trajectory_sampling_grid_csv_and_plot(fang, tmp_path):
    """Scalar and array sampling, a dt grid ending at the duration, CSV and PNG files."""
    traj = time_parameterize(fang_move(REFERENCE["tables"][1]), fang, method="ruckig")
    q, qd, qdd = traj.sample(0.3)
    assert q.shape == qd.shape == qdd.shape == (4,)
    Q, QD, QDD = traj.sample([0.0, traj.duration])
    assert Q.shape == (2, 4) and np.allclose(QD, 0, atol=1e-12) and np.allclose(QDD, 0, atol=1e-9)
    t = traj.times(0.1)
    assert t[0] == 0 and t[-1] == traj.duration and np.all(np.diff(t) <= 0.1 + 1e-12)
    assert traj.positions(0.1).shape == (len(t), 4)
    csv = traj.to_csv(tmp_path / "traj.csv", dt=0.05)
    header = csv.read_text().splitlines()[0].split(",")
    assert header[:5] == ["t_s", "theta1_rad", "theta2_rad", "d3_m", "theta4_rad"]
    assert np.loadtxt(csv, delimiter=",", skiprows=1).shape == (len(traj.times(0.05)), 13)
    png = traj.plot(tmp_path / "traj.png")
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert "ruckig" in repr(traj)


def test_check_limits_is_exact(zavar, circle_path):
    """Dense samples never exceed check_limits' ratios and come within 1e-3 of them."""
    traj = time_parameterize(circle_path, zavar, method="toppra", allow_jumps=True)
    t = np.linspace(0, traj.duration, 40001)
    _, qd, qdd = traj.sample(t)
    exact = traj.check_limits()
    for name, values in (("velocity", qd / traj.limits.vmax), ("acceleration",
                                                                 qdd / traj.limits.amax)):
        sampled = np.abs(values).max(axis=0)
        assert np.all(sampled <= exact[name] + 1e-12)
        assert np.all(sampled >= exact[name] - 1e-3)


def _extrema_by_every_root(pp):
    """Reference: ends of every piece and the roots of f' in every piece (no pruning)."""
    h = np.diff(pp.x)
    right = sum(row * h ** (len(pp.c) - 1 - m) for m, row in enumerate(pp.c))
    vals = [pp.c[-1], right]
    roots = pp.derivative().roots(discontinuity=False, extrapolate=False)
    roots = roots[np.isfinite(roots)]
    vals = np.concatenate([*vals, pp(roots)])
    return vals.min(), vals.max()


@pytest.mark.parametrize("degree", [2, 3, 4, 5, 6])
def test_pruned_extrema_equal_every_root_extrema(degree):
    """``extrema`` skips pieces whose Bernstein coefficients lie within the ends' range; on
    300 random piecewise polynomials (wiggly pieces, flat pieces, steps) it finds the same
    smallest and largest values as the root of every piece; ``cubic_range`` (all joints at
    once) equals it on cubic splines.

    Mutations: ``_may_leave`` returning no piece -> interior extrema missed, fails; the
    Bernstein matrix transposed -> wrong bounds, fails; ``cubic_range`` keeping one root of
    the two (``d / q`` -> ``q / a``) -> fails.
    """
    from scipy.interpolate import CubicSpline, PPoly

    from scara_opt.trajectory.trajectory import cubic_range, extrema

    rng = np.random.default_rng(degree)
    for _ in range(300):
        n = int(rng.integers(1, 40))
        c = rng.normal(size=(degree + 1, n)) * rng.choice([1e-6, 1.0, 1e3], size=n)
        x = np.concatenate([[0.0], np.cumsum(rng.random(n) + 1e-3)])
        pp = PPoly(c, x, extrapolate=False)
        lo, hi = extrema(pp)
        ref = _extrema_by_every_root(pp)
        np.testing.assert_allclose([lo, hi], ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    for _ in range(100):
        n = int(rng.integers(2, 30))
        s = np.concatenate([[0.0], np.cumsum(rng.random(n - 1) + 0.01)])
        spline = CubicSpline(s, rng.normal(size=(n, 3)), bc_type="clamped")
        lo, hi = cubic_range(spline)
        ref = np.array([extrema(PPoly(spline.c[:, :, k], spline.x)) for k in range(3)])
        np.testing.assert_allclose(np.c_[lo, hi], ref, rtol=0, atol=1e-12)


@pytest.mark.parametrize("t", [-0.1, 1e9, math.nan, "x"])
def test_sampling_outside_the_trajectory_is_refused(fang, t):
    """Times outside [0, duration] or not numbers: InputError."""
    traj = time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="quintic")
    with pytest.raises(InputError):
        traj.sample(t)


@pytest.mark.parametrize("dt", [0, -0.1, math.inf])
def test_bad_grid_step_is_refused(fang, dt):
    """A grid step that is not a positive finite number: InputError."""
    traj = time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="quintic")
    with pytest.raises(InputError, match="dt"):
        traj.times(dt)


# ---------------------------------------------------------------- properties
@st.composite
def waypoint_sets(draw) -> tuple[np.ndarray, float]:
    """2-5 fang waypoints within 90 % of the joint ranges, and a scale for the limits."""
    n = draw(st.integers(2, 5))
    u = np.array(draw(st.lists(st.lists(st.floats(0.05, 0.95), min_size=4, max_size=4),
                               min_size=n, max_size=n)))
    scale = draw(st.floats(0.2, 5.0))
    return u, scale


@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=40, deadline=None, derandomize=True,  # the same examples every run
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(case=waypoint_sets())
def test_timing_properties_on_random_waypoints(fang, method, case):
    """No NaN, positive duration, through every waypoint, rest at the ends, ratios <= 1 + 1e-6.

    The robot's position limits are left out (robot=None): a spline through arbitrary
    waypoints may leave them, which toppra refuses (tested below), and so may ruckig's
    moving timings (they keep within the robot's limits when given, tested below); the
    quintic, rest to rest, never leaves the box of its waypoints.
    """
    u, scale = case
    Q = fang.lower + u * (fang.upper - fang.lower)
    assume(np.all(np.abs(np.diff(Q, axis=0)).max(axis=1) > 1e-3))
    traj = time_parameterize(Q, None, method=method, vmax=scale * fang.velocity_limit,
                             amax=scale**2 * fang.acceleration_limit)
    assert traj.duration > 0 and np.isfinite(traj.duration)
    q, qd, qdd = traj.sample(np.linspace(0, traj.duration, 501))
    assert np.isfinite(q).all() and np.isfinite(qd).all() and np.isfinite(qdd).all()
    assert np.allclose(traj.evaluate(traj.waypoint_times), Q, atol=1e-9)
    assert np.allclose(qd[[0, -1]], 0, atol=1e-9)
    assert worst_ratio(traj) <= 1 + RATIO_TOL
    if method == "quintic":
        lo, hi = traj.position_range()
        assert np.all(lo >= Q.min(axis=0) - 1e-9) and np.all(hi <= Q.max(axis=0) + 1e-9)


def test_toppra_refuses_a_spline_that_leaves_the_joint_limits(zavar):
    """Waypoints at the limit on both sides of a turn: the spline overshoots, toppra refuses;
    ruckig, moving through them, keeps within.

    Mutation caught: a joined segment that leaves the limits kept (``if solver.leaves(
    limits) and ...`` -> ``if False and ...`` in ruckig_backend) -> theta1 at 2.121 rad.
    """
    Q = np.zeros((4, 4))
    Q[:, 0], Q[:, 1], Q[:, 2] = [1.5, 2.09, 2.09, 1.5], [0.0, 0.3, 0.6, 0.9], 0.02
    with pytest.raises(TrajectoryError, match="theta1.*between waypoints 1 and 2.*ruckig"):
        time_parameterize(Q, zavar, method="toppra")
    traj = time_parameterize(Q, zavar, method="ruckig")
    assert traj.position_range()[1][0] <= 2.09 + 1e-12


# ---------------------------------------------------------------- ik_path
def test_ik_path_reports_the_elbow_flip_on_the_reachable_circle(zavar, circle_path):
    """All ten points solved; the one jump is the elbow flip, forced by point 8.

    The righty branch reaches points 0-7 and the lefty 7-9 (θ1 within ±120°): the global
    walk flips once, where it costs least (step 6→7), and names point 8 as the one forcing
    it; the greedy walk flips where its branch ends (7→8). Mutation caught: the forcing
    point searched from the candidate after the jump (``int(choice[j - 1])`` ->
    ``int(choice[j])`` in branches._forcing_points) -> no forcing point, fails.
    """
    jp = circle_path
    assert jp.solved.all() and jp.error.max() < 1e-12 and not jp.ok
    assert jp.branches == "global" and [j.index for j in jp.jumps] == [7]
    jump = jp.jumps[0]
    assert jump.joints == ("theta2",) and jump.forced_by == 8 and jp.forced == [8]
    assert np.sign(jp.q[6, 1]) != np.sign(jp.q[7, 1]) and abs(jump.delta[1]) > math.radians(160)
    assert "jumps at steps 7 (forced by points 8)" in jp.summary()
    assert str(jump).startswith("step 6→7") and "does not reach point 8" in str(jump)
    greedy = ik_path(zavar, paths.zavar2024_circle(reachable=True), branches="greedy")
    assert [j.index for j in greedy.jumps] == [8] and greedy.jumps[0].forced_by is None
    assert (jp.travel / zavar.velocity_limit).sum() <= (greedy.travel
                                                        / zavar.velocity_limit).sum()
    analytic = ik_path(zavar, paths.zavar2024_circle(reachable=True), method="analytic")
    assert [j.index for j in analytic.jumps] == [7]
    assert np.allclose(analytic.q, jp.q, atol=1e-9)


def test_ik_path_reports_the_papers_circle_unreachable(zavar):
    """Each Table 3 point is out of reach by 4 cm: status unreachable, residual reported."""
    jp = ik_path(zavar, paths.zavar2024_circle())
    assert len(jp) == 10 and jp.unsolved == list(range(10))
    assert all(s == "unreachable" for s in jp.status)
    assert np.allclose(jp.error, 0.04, atol=1e-3)
    with pytest.raises(TrajectoryError, match="not reached"):
        jp.raise_if_invalid()
    with pytest.raises(TrajectoryError, match="not reached"):
        time_parameterize(jp, zavar)
    with pytest.raises(TrajectoryError, match="at least two"):
        time_parameterize(jp.subset(jp.solved), zavar)


def test_jumps_must_be_allowed_explicitly(zavar, circle_path, caplog):
    """A path with a jump is refused unless allow_jumps=True, which logs a warning."""
    with pytest.raises(TrajectoryError, match="allow_jumps"):
        time_parameterize(circle_path, zavar, method="toppra")
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        traj = time_parameterize(circle_path, zavar, method="ruckig", allow_jumps=True)
    assert "jump" in caplog.text and worst_ratio(traj) <= 1 + RATIO_TOL
    part = circle_path.subset(slice(0, 7))
    assert part.ok and len(part) == 7
    assert time_parameterize(part, zavar).duration > 0


def test_ik_path_keeps_the_wrist_continuous_across_pi(fang):
    """Yaw targets crossing ±π: the wrist moves by the small angle, not by 2π."""
    yaws = [3.0, 3.1, -3.1, -3.0]
    ts = [so.Target((0.25, 0.05 * k, -0.02), yaw=a) for k, a in enumerate(yaws)]
    for method in ("ipopt", "analytic"):
        jp = ik_path(fang, ts, method=method, q_start=[0.0, 1.0, 0.0, 1.0])
        assert jp.ok, jp.problems()
        wrist_yaw = jp.q[:, 0] + jp.q[:, 1] + jp.q[:, 3]
        assert np.abs(np.diff(wrist_yaw)).max() < 0.2


def test_ik_path_on_the_nguyen_contour_is_continuous(robots):
    """The redundant rail robot follows the closed contour with no jump, tool angle included."""
    robot = robots["nguyen"]
    jp = ik_path(robot, paths.nguyen_contour(120), q_start=(0.3, 0.0, 1.5, 0.05, 0.0))
    assert jp.ok, jp.problems()[:3]
    assert np.abs(jp.position_error).max() < 1e-9 and np.abs(jp.angle_error).max() < 1e-9
    assert np.abs(np.diff(jp.q, axis=0)).max(axis=0)[0] < 0.06  # the rail moves smoothly
    traj = time_parameterize(jp, robot, method="toppra")
    assert worst_ratio(traj) <= 1 + RATIO_TOL


@pytest.mark.parametrize("threshold", [-1.0, 0.0, math.nan, [1.0, 2.0], "x"])
def test_bad_jump_threshold_is_refused(zavar, threshold):
    """A threshold that is not positive (per joint): InputError."""
    with pytest.raises(InputError, match="jump_threshold"):
        ik_path(zavar, paths.zavar2024_circle(reachable=True)[:2], jump_threshold=threshold)


def test_ik_path_rejects_empty_targets_and_unknown_methods(zavar):
    """No targets: InputError; an unknown IK method: UnknownSolverError."""
    with pytest.raises(InputError):
        ik_path(zavar, [])
    with pytest.raises(UnknownSolverError):
        ik_path(zavar, paths.zavar2024_circle(), method="nope")


# ---------------------------------------------------------------- bad input
def test_unknown_method_and_option(fang):
    """Unknown timing method lists the registered ones; unknown option lists the accepted."""
    Q = fang_move(REFERENCE["tables"][0])
    assert timing_methods() == ["quintic", "ruckig", "toppra"]
    with pytest.raises(UnknownSolverError, match="time-parameterisation method.*quintic"):
        time_parameterize(Q, fang, method="trapezoid")
    with pytest.raises(SolverOptionError, match="margin"):
        time_parameterize(Q, fang, method="toppra", margn=0.01)
    with pytest.raises(InputError, match="margin"):
        time_parameterize(Q, fang, method="toppra", margin=0.7)
    with pytest.raises(InputError, match="already registered"):
        register_timing("toppra")(lambda *a: None)


@pytest.mark.parametrize("kwargs, error, match", [
    ({"vmax": 0.0}, InputError, "vmax for joint 'theta1' is 0 "),
    ({"vmax": [1, 1, -1, 1]}, InputError, "vmax for joint 'd3' is -1 "),
    ({"amax": math.inf}, InputError, "amax for joint 'theta1' is inf .*finite and > 0"),
    ({"amax": -math.inf}, InputError, "amax for joint 'theta1' is -inf "),
    ({"vmax": [1, math.nan, 1, 1]}, InputError, "NaN"),
    ({"amax": [1.0, 2.0]}, InputError, "shape"),
    ({"vmax": "fast"}, InputError, "vmax"),
    ({"method": "ruckig", "jmax": [1, 1, 0, 1]}, InputError, "jmax for joint 'd3' is 0 "),
    ({"method": "ruckig", "jmax": math.inf}, InputError, "jmax for joint 'theta1' is inf "),
    ({"method": "toppra", "jmax": 10.0}, InputError, "jerk"),
    ({"method": "toppra", "duration": 2.0}, InputError, "quintic"),
    ({"method": "quintic", "duration": -1.0}, InputError, "duration"),
    ({"method": "quintic", "duration": True}, InputError, "duration"),
])
def test_bad_limits_and_options(fang, kwargs, error, match):
    """Zero, negative, infinite, NaN or misshaped limits; options a method does not take."""
    Q = fang_move(REFERENCE["tables"][0])
    with pytest.raises(error, match=match) as info:
        time_parameterize(Q, fang, **{"method": "toppra", **kwargs})
    assert type(info.value) is error  # not a subclass such as JointLimitError


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("limits", [{"vmax": 0.0}, {"amax": -2.0}, {"vmax": math.inf},
                                    {"amax": [1.0, math.nan, 1.0, 1.0]}, {"vmax": [1.0, 2.0]}])
def test_every_bad_limit_is_a_trajectory_or_input_error(fang, method, limits):
    """The issue's contract: one ``except (TrajectoryError, InputError)`` catches them all."""
    try:
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method=method, **limits)
    except (TrajectoryError, InputError) as exc:
        assert "vmax" in str(exc) or "amax" in str(exc)
    else:
        pytest.fail(f"{limits} was accepted by {method}")


@pytest.mark.parametrize("method, options, match", [
    ("toppra", {"max_refine": -1}, r"'toppra': option max_refine=-1 must be an integer in \[0, "),
    ("toppra", {"max_refine": 11}, r"max_refine=11 must be an integer in \[0, 10\]"),
    ("toppra", {"max_refine": 1.5}, r"max_refine=1.5 must be an integer"),
    ("toppra", {"grid_per_segment": 0, "min_grid": 0}, r"grid_per_segment=0 must be .* >= 1"),
    ("toppra", {"min_grid": 1}, r"min_grid=1 must be an integer >= 2; .*default 100"),
    ("toppra", {"min_grid": 2.0}, r"min_grid=2.0 must be an integer"),
    ("toppra", {"grid_per_segment": True}, r"grid_per_segment=True must be an integer"),
    ("toppra", {"margin": 0.5}, r"margin=0.5 must be a number in \[0, 0.5\)"),
    ("toppra", {"margin": -0.1}, r"margin=-0.1 must be a number in \[0, 0.5\)"),
    ("toppra", {"margin": math.nan}, r"margin=nan must be a number"),
    ("toppra", {"margin": "small"}, r"margin='small' must be a number"),
    ("quintic", {"enforce_limits": "no"}, r"'quintic': option enforce_limits='no' must be True"),
])
def test_bad_backend_options_name_the_option_and_range(fang, method, options, match):
    """Out-of-range, non-integer, NaN or bool options: InputError naming option and range."""
    with pytest.raises(InputError, match=match):
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method=method, **options)


def test_option_ranges_are_inclusive_where_documented(fang):
    """The smallest valid toppra options still time within the limits; ruckig takes none."""
    Q = fang_move(REFERENCE["tables"][0])
    traj = time_parameterize(Q, fang, method="toppra", margin=0, grid_per_segment=1,
                             min_grid=2, max_refine=0)
    assert worst_ratio(traj) <= 1 + RATIO_TOL and "2 grid intervals" in traj.notes
    with pytest.raises(SolverOptionError, match="enforce_limits"):
        time_parameterize(Q, fang, method="ruckig", enforce_limits=False)


@pytest.mark.parametrize("path, error, match", [
    (np.zeros((1, 4)), TrajectoryError, "at least two"),
    (np.zeros((3, 3)), InputError, "joints"),
    (np.zeros(4), InputError, "shape"),
    ([[0, 0, 0, 0], [0, 0, math.nan, 0]], InputError, "NaN"),
    ([[0, 0, 0, 0], [3.0, 0, 0, 0]], JointLimitError, "theta1"),
    ([[0, 0, 0, 0], [0.1, 0, 0, 0], [0.1, 0, 0, 0]], TrajectoryError, "duplicate"),
    ("abc", InputError, "JointPath"),
])
def test_bad_paths(fang, path, error, match):
    """Fewer than two points, wrong shapes, NaN, out of limits, consecutive duplicates."""
    with pytest.raises(error, match=match):
        time_parameterize(path, fang, method="toppra")


def test_drop_duplicates_removes_them_and_says_so(fang, caplog):
    """drop_duplicates=True removes the repeated waypoint and logs it."""
    Q = [[0, 0, 0, 0], [0.1, 0, 0, 0], [0.1, 0, 0, 0], [0.2, 0.1, 0, 0]]
    with caplog.at_level(logging.INFO, logger="scara_opt"):
        traj = time_parameterize(Q, fang, method="toppra", drop_duplicates=True)
    assert len(traj.waypoints) == 3 and "duplicate" in caplog.text
    with pytest.raises(TrajectoryError, match="fewer than two"):
        time_parameterize([[0.1, 0, 0, 0]] * 3, fang, drop_duplicates=True)


def test_limits_without_a_robot():
    """Without a robot vmax and amax are required; with them any joint count works."""
    Q = [[0.0, 0.0], [1.0, -2.0]]
    with pytest.raises(InputError, match="vmax"):
        time_parameterize(Q, None, method="quintic")
    traj = time_parameterize(Q, None, method="quintic", vmax=1.0, amax=2.0)
    assert traj.limits.joint_names == ("joint0", "joint1") and worst_ratio(traj) <= 1 + 1e-9


def test_too_short_fixed_quintic_duration_is_refused(fang):
    """Below the shortest duration: TrajectoryError giving it; that duration then works."""
    Q = fang_move(REFERENCE["tables"][0])
    shortest = time_parameterize(Q, fang, method="quintic").duration
    with pytest.raises(TrajectoryError, match="below .* the shortest that respects") as info:
        time_parameterize(Q, fang, method="quintic", duration=0.01)
    assert f"{shortest:.6g} s" in str(info.value) and "enforce_limits=False" in str(info.value)
    suggested = float(str(info.value).split("pass duration >= ")[1].split()[0])
    assert shortest <= suggested <= shortest + 1e-6
    for duration in (suggested, shortest):
        traj = time_parameterize(Q, fang, method="quintic", duration=duration)
        assert worst_ratio(traj) <= 1 + RATIO_TOL and traj.duration == pytest.approx(duration)


def test_too_short_fixed_quintic_duration_when_opted_in(fang, caplog):
    """enforce_limits=False: timed anyway, logged, written in notes, visible in the ratios."""
    Q = fang_move(REFERENCE["tables"][0])
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        traj = time_parameterize(Q, fang, method="quintic", duration=0.5, enforce_limits=False)
    assert "below the shortest" in caplog.text and worst_ratio(traj) > 1
    assert "limits exceeded" in traj.notes and "enforce_limits=False" in traj.notes
    assert f"largest ratio {worst_ratio(traj):.4g}" in traj.notes
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="scara_opt"):
        slow = time_parameterize(Q, fang, method="quintic", duration=5.0, enforce_limits=False)
    assert not caplog.text and "exceeded" not in slow.notes and worst_ratio(slow) < 1


def test_toppra_refuses_a_grid_with_a_stalled_interval(fang):
    """One grid interval from rest to rest would take forever: TrajectoryError, no inf."""
    import toppra

    from scara_opt.trajectory.toppra_backend import _solve

    Q = fang_move(REFERENCE["tables"][0])
    s = chord_parameter(Q, fang.velocity_limit)
    limits = resolve_limits(fang, 4)
    with pytest.raises(TrajectoryError, match="zero at both ends of grid interval 0 of 1"):
        _solve(toppra.SplineInterpolator(s, Q), s, 1, limits, 1.0)


# ---------------------------------------------------------------- argument types and ranges
def test_a_robot_name_instead_of_a_robot_says_to_load_it(fang):
    """time_parameterize(P, "zavar2024") raised AttributeError: 'str' has no attribute 'nq'.

    Mutation: time_parameterize without check_robot -> fails.
    """
    Q = fang_move(REFERENCE["tables"][0])
    with pytest.raises(InputError, match=r"robot = so.load_robot\('fang'\)"):
        time_parameterize(Q, "fang")
    with pytest.raises(InputError, match=r"scara_opt.Robot .*got 5 \(int\)"):
        time_parameterize(Q, 5)


@pytest.mark.parametrize("flag", ["allow_jumps", "drop_duplicates"])
@pytest.mark.parametrize("value", ["no", 0, 1.0, None])
def test_flags_must_be_true_or_false(fang, flag, value):
    """allow_jumps="no" was taken as true.

    Mutation: time_parameterize without the flag checks -> fails.
    """
    with pytest.raises(InputError, match=f"{flag} must be True or False"):
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, **{flag: value})


@pytest.mark.parametrize("method", [["toppra"], None, 3])
def test_timing_method_must_be_one_name(fang, method):
    """A list of names raised TypeError: unhashable."""
    with pytest.raises(InputError, match="method must be one timing method name"):
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method=method)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("kwargs, match", [
    ({"vmax": 1e-300}, r"vmax for joint 'theta1' is 1e-300 .*so small that the timing "
                       r"overflows.*\[1e-06, 1e\+06\]"),
    ({"amax": 1e-7}, r"amax .* so small"),
    ({"vmax": 1e300}, r"vmax .* lose precision; for an effectively unlimited joint pass 1e\+06"),
    ({"amax": 1e9}, r"amax for joint 'theta1' is 1e\+09 .*lose precision"),
])
def test_limits_outside_their_range_are_refused_with_the_reason(fang, method, kwargs, match):
    """toppra with vmax = 1e-300 raised ValueError (its chord parameter overflowed to inf),
    ruckig with amax = 1e9 a RuckigError, quintic with amax = 1e-300 OverflowError.

    Mutation: LIMIT_RANGES without floor and ceiling (0, inf) -> fails.
    """
    with pytest.raises(InputError, match=match):
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method=method, **kwargs)


def test_the_robots_own_limits_are_range_checked_too(fang):
    """A robot whose file gives a tiny acceleration limit is named as the source."""
    text = fang._init_args[0].replace('acceleration="12.566370614359172"',
                                      'acceleration="1e-9"', 1)
    slow = so.Robot(text, "tool", name="slow")
    with pytest.raises(InputError, match=r"robot 'slow''s own limit: amax .* \(or fix the robot"):
        time_parameterize(fang_move(REFERENCE["tables"][0]), slow)


def test_jerk_far_above_acceleration_is_refused(fang):
    """jmax / amax = 1e11 /s let ruckig exceed the acceleration limit by 4e-4, silently.

    Mutation: MAX_JERK_RATIO = inf -> fails (a trajectory above its limits comes back).
    """
    Q = fang_move(REFERENCE["tables"][0])
    with pytest.raises(InputError, match=r"jmax / amax for joint 'theta1' is 1e\+11 /s"):
        time_parameterize(Q, fang, method="ruckig", amax=1e-3, jmax=1e8)
    ok = time_parameterize(Q, fang, method="ruckig", amax=1e-3, jmax=1e2)
    assert worst_ratio(ok) <= 1 + RATIO_TOL


@pytest.mark.parametrize("duration", [1e308, 10**30, 1e10])
def test_a_fixed_duration_beyond_the_ceiling_is_refused(fang, duration):
    """A quintic over 1e308 s had duration**5 = inf: every coefficient 0, a path that never
    moved. Up to MAX_DURATION it still reaches its goal.

    Mutation: MAX_DURATION = inf -> fails.
    """
    Q = fang_move(REFERENCE["tables"][0])
    with pytest.raises(InputError, match=r"duration must be a number in \(0, 1e\+09\]"):
        time_parameterize(Q, fang, method="quintic", duration=duration)
    slow = time_parameterize(Q, fang, method="quintic", duration=1e9)
    np.testing.assert_allclose(slow.evaluate(slow.duration), Q[-1], atol=1e-12)


def test_ruckigs_unknown_result_codes_become_trajectory_errors(fang):
    """At vmax = 1e-6 Ruckig returns -101 (duration beyond its range), which its binding
    raised as ValueError: "-101 is not a valid Result".

    Mutation: ruckig_segment without its ValueError branch -> fails.
    """
    with pytest.raises(TrajectoryError, match="-101 means the duration exceeds"):
        time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="ruckig", vmax=1e-6)


@pytest.mark.parametrize("dt, match", [(1e-300, r"times\(dt=1e-300\) .* would need about"),
                                       (True, r"dt must be a finite number > 0"),
                                       ("0.1", "dt must be")])
def test_a_sampling_grid_too_fine_or_mistyped_is_refused(fang, dt, match):
    """times(1e-300) raised numpy's "Maximum allowed size exceeded"; dt=True was 1 s.

    Mutation: times without check_memory -> fails.
    """
    traj = time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="quintic")
    with pytest.raises(InputError, match=match):
        traj.times(dt)


def test_sampling_times_must_be_numbers(fang):
    """evaluate("0.1") parsed the string.

    Mutation: _times converts with np.asarray(t, dtype=float) -> fails.
    """
    traj = time_parameterize(fang_move(REFERENCE["tables"][0]), fang, method="quintic")
    with pytest.raises(InputError, match="t must be a time"):
        traj.evaluate("0.1")
    with pytest.raises(InputError, match="path must be a JointPath or a numeric"):
        time_parameterize([["0", "0", "0", "0"], ["1", "0", "0", "0"]], fang)


@pytest.mark.parametrize("kwargs, match", [
    (dict(robot="zavar2024"), r"so.load_robot\('zavar2024'\)"),
    (dict(robot=None), r"scara_opt.Robot .*None"),
    (dict(seed="1"), "seed must be a non-negative integer"),
    (dict(seed=[1]), "seed must be a non-negative integer"),
    (dict(method=["lm"]), "method must be one solver name"),
])
def test_ik_path_type_checks_robot_seed_and_method(zavar, kwargs, match):
    """ik_path("zavar2024", ...) raised AttributeError; seed="1" a TypeError at seed + i.

    Mutation: ik_path without check_robot and check_seed -> fails.
    """
    args = dict(robot=zavar, targets=paths.zavar2024_circle(reachable=True)[:2], method="lm")
    with pytest.raises(InputError, match=match):
        ik_path(**{**args, **kwargs})


@pytest.mark.parametrize("method", ["toppra", "quintic", "ruckig"])
def test_peaks_of_all_joints_at_once_equal_each_joints_extrema(zavar, method):
    """``peaks`` (all joints at once when they share breakpoints: toppra, quintic; each
    joint alone for ruckig) equals the largest of ``|extrema|`` of each joint's derivative
    PPoly, on random waypoints; ``sup_abs_columns`` equals every-root extrema on random
    piecewise polynomials.

    Mutations caught: the derivative's factor p (p-1)... taken as p alone (acceleration
    peaks wrong); the pieces that may leave the ends' range not searched (``nonzero`` of
    nothing): interior extrema missed; every root's value given to the first column
    (``col`` of zeros): the other columns' interior extrema missed.
    """
    from scipy.interpolate import PPoly

    from scara_opt.trajectory.trajectory import extrema, sup_abs_columns

    rng = np.random.default_rng(3)
    for _ in range(5):
        mid, half = (zavar.lower + zavar.upper) / 2, (zavar.upper - zavar.lower) / 2
        Q = rng.uniform(mid - 0.3 * half, mid + 0.3 * half, (int(rng.integers(2, 8)), zavar.nq))
        traj = time_parameterize(Q, zavar, method=method)
        peaks = traj.peaks()
        for name, order in (("velocity", 1), ("acceleration", 2)):
            ref = [max(abs(v) for v in extrema(p.derivative(order))) for p in traj.pieces]
            np.testing.assert_allclose(peaks[name], ref, rtol=1e-12, atol=1e-12)
    for degree in (2, 3, 5, 6):
        for _ in range(100):
            n = int(rng.integers(1, 30))
            c = rng.normal(size=(degree + 1, n, 3)) * rng.choice([1e-6, 1.0, 1e3], size=(n, 1))
            x = np.concatenate([[0.0], np.cumsum(rng.random(n) + 1e-3)])
            ref = [np.abs(_extrema_by_every_root(PPoly(c[:, :, j], x,
                                                       extrapolate=False))).max()
                   for j in range(3)]
            np.testing.assert_allclose(sup_abs_columns(c, x), ref, rtol=1e-12,
                                       atol=1e-12 * max(ref))


@pytest.mark.parametrize("method", ["toppra", "quintic", "ruckig"])
def test_peak_bounds_are_never_below_the_exact_peaks(zavar, method):
    """``peak_bounds`` (the largest |Bernstein coefficient| of each derivative's pieces,
    all joints at once or each joint alone) is >= ``peaks`` per joint and derivative, on
    random waypoints, and within 4x of them (a one-piece quintic's: 8/3 on velocity, 2√3
    on acceleration).

    Mutation caught: the smallest coefficient taken (``min`` for ``max``): below the
    peaks; the power-basis coefficients taken for Bernstein's (``c`` for
    ``coefficients(c, x)``): below the peaks on some pieces.
    """
    rng = np.random.default_rng(11)
    for _ in range(8):
        mid, half = (zavar.lower + zavar.upper) / 2, (zavar.upper - zavar.lower) / 2
        Q = rng.uniform(mid - 0.3 * half, mid + 0.3 * half, (int(rng.integers(2, 8)), zavar.nq))
        traj = time_parameterize(Q, zavar, method=method)
        peaks, bounds = traj.peaks(), traj.peak_bounds()
        assert peaks.keys() == bounds.keys()
        for name, peak in peaks.items():
            assert (bounds[name] >= peak * (1 - 1e-12)).all(), (name, bounds[name], peak)
            assert (bounds[name] <= 4 * peak + 1e-9).all(), (name, bounds[name], peak)
