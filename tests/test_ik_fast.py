"""Fast exact IK: the Levenberg–Marquardt solver, the "auto" route, warm starts and batches."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik.geometry import scara_geometry
from scara_opt.ik.lm import cached_step
from scara_opt.ik.lm_batch import solve_many
from tests.conftest import BUNDLED, random_q
from tests.test_ik import FOUR_JOINT, assert_invariants, reachable_targets

UNREACHABLE = [-0.23, 0.20, -0.20]  # zavar2024's paper target: 0.102 m below the stroke


# ------------------------------------------------------------------ the fast solver
@pytest.mark.parametrize("name", FOUR_JOINT)
def test_lm_answer_is_a_closed_form_branch_with_the_wrist_at_q0(robots, name):
    """4-joint robots: the answer is one of ik_all's branches, the free wrist left at q0."""
    robot = robots[name]
    q0 = random_q(robot, 1, seed=3)[0]
    for p in reachable_targets(robot, 200, seed=8):
        res = so.solve_ik(robot, p, method="lm", q0=q0)
        branches = so.ik_all(robot, p, q0=q0)
        gap = min(np.abs(b.q - res.q).max() for b in branches)
        assert gap < 1e-9, (res, branches)


@pytest.mark.parametrize("name", FOUR_JOINT)
def test_lm_agrees_with_ipopt_from_a_nearby_q0(robots, name):
    """Same problem, same rule: from a q0 near a solution both exact solvers return it.

    Where the arm is nearly stretched (elbow within 0.01 rad of the singular pose) the two
    elbow branches nearly coincide and "nearest to q0, on the branch reached" may pick
    either: there both must be solutions equally near q0 (to 1e-5 in range units).
    IPOPT runs both as the default (polished by the fast solver's phases) and on its own
    (``polish=False``). Mutations caught: IPOPT without its nearest NLP (the regulariser's
    offset stays in q); the nearest NLP pulling toward zero instead of q0; the fast solver
    skipping its slide toward q0 -> q differs by > 1e-7.
    """
    robot = robots[name]
    geom = scara_geometry(robot)
    span = robot.upper - robot.lower
    rng = np.random.default_rng(12)
    Q = random_q(robot, 100, seed=12)
    for q in Q:
        q0 = np.clip(q + rng.normal(0, 0.02, robot.nq), robot.lower, robot.upper)
        p = robot.position(q)
        fast, ref = (so.solve_ik(robot, p, q0=q0, method=m) for m in ("lm", "ipopt"))
        alone = so.solve_ik(robot, p, q0=q0, method="ipopt", polish=False)
        for other in (ref, alone):
            assert fast.success and other.success
            gamma = geom.phi2 - geom.phi1 + geom.s[geom.elbow] * other.q[geom.elbow]
            if abs(np.sin(gamma)) > 0.01:
                np.testing.assert_allclose(fast.q, other.q, atol=1e-7)
            else:
                d = [np.linalg.norm((r.q - q0) / span) for r in (fast, other)]
                assert abs(d[0] - d[1]) < 1e-5


def test_redundant_robots_keep_the_nearest_rule(robots):
    """inverted5 splits a stroke evenly from an even q0; nguyen does not move when q0 reaches."""
    robot = robots["inverted5"]
    q0 = np.array([0.02, 0.5, 1.0, 0.0, 0.02])
    res = so.solve_ik(robot, robot.position(q0) + [0, 0, -0.02], q0=q0, method="lm")
    np.testing.assert_allclose(res.q, [0.03, 0.5, 1.0, 0.0, 0.03], atol=1e-9)
    robot = robots["nguyen"]
    q0 = np.array([0.3, 0.4, -0.6, 0.05, 0.2])
    res = so.solve_ik(robot, so.Target(robot.position(q0), yaw=robot.yaw(q0)), q0=q0,
                      method="lm")
    np.testing.assert_allclose(res.q, q0, atol=1e-12)


def test_curved_self_motion_ends_nearer_to_q0_than_ipopt(robots):
    """nguyen's rail + 2R solution set is curved: the slide ends at least as near to q0."""
    robot = robots["nguyen"]
    span = robot.upper - robot.lower
    for p in reachable_targets(robot, 20, seed=8):
        fast, ref = (so.solve_ik(robot, p, method=m) for m in ("lm", "ipopt"))
        d_fast, d_ref = (np.linalg.norm(r.q / span) for r in (fast, ref))  # q0 = 0
        assert fast.success and d_fast <= d_ref + 1e-6


def test_full_rotation_targets_on_a_general_arm(arm6):
    """A 6-joint arm with full pose targets: nothing SCARA-only (measured 40/40, restarts=40)."""
    results = []
    for q in random_q(arm6, 20, seed=10):
        T = arm6.fk(q)
        target = so.Target(T[:3, 3], rotation=T[:3, :3])
        results.append(so.solve_ik(arm6, target, method="lm", restarts=40))
    for res in results:
        assert_invariants(arm6, res)
    assert sum(r.success for r in results) >= 19, results


def test_same_seed_same_answer(robots):
    """Restarts come from the seed alone: the same seed gives the same q."""
    robot = robots["zavar2024"]
    a, b = (so.solve_ik(robot, UNREACHABLE, method="lm", seed=3, restarts=3) for _ in range(2))
    np.testing.assert_array_equal(a.q, b.q)


def test_history_and_counters(robots):
    """iterations, evaluations and history are filled; history never increases."""
    robot = robots["zavar2024"]
    res = so.solve_ik(robot, reachable_targets(robot, 1, seed=2)[0], method="lm")
    assert res.evaluations >= res.iterations >= len(res.history) > 0
    assert np.all(np.diff(res.history) <= 0)


# ------------------------------------------------------------------ verdicts
def test_auto_reports_unreachable_with_the_true_residual(robots):
    """zavar2024's (-0.23, 0.20, -0.20) via 'auto': unreachable by 0.102 m along z."""
    robot = robots["zavar2024"]
    res = so.solve_ik(robot, UNREACHABLE, method="auto")
    assert res.status == "unreachable" and not res.success
    assert res.error == pytest.approx(0.102, abs=1e-3)
    assert "along z" in res.message
    assert_invariants(robot, res)


def test_lm_alone_never_claims_a_solution_it_has_not_got(robots):
    """The fast solver on an unreachable target: not solved, q within limits, true residual."""
    robot = robots["zavar2024"]
    res = so.solve_ik(robot, UNREACHABLE, method="lm", restarts=2)
    assert not res.success and res.error == pytest.approx(0.102, abs=1e-3)
    assert_invariants(robot, res)


def test_widened_limits_use_their_own_box(robots):
    """A robot copy with other limits solves with those limits (cached Functions are shared)."""
    robot = robots["peng2025"]
    target = so.Target(np.array([400.0, -120.0, 170.0]) / 1000, yaw=0.0)  # needs z0 = -2 mm
    assert not so.solve_ik(robot, target, method="lm", restarts=2).success
    widened = robot.with_limits(z0=(-0.005, 0.040))
    res = so.solve_ik(widened, target, method="auto")
    assert res.success and res.q[0] == pytest.approx(-0.002, abs=1e-9)


# ------------------------------------------------------------------ warm starts
@pytest.mark.parametrize("name", BUNDLED)
def test_warm_start_from_a_neighbour_converges_on_its_branch(robots, name):
    """Along a path, each point solved from the previous q: few iterations, no jump."""
    robot = robots[name]
    lo, hi = robot.lower, robot.upper
    start = lo + (hi - lo) * np.random.default_rng(4).uniform(0.2, 0.8, robot.nq)
    path = robot.positions(start + np.outer(np.arange(1, 30), 0.002 * (hi - lo)))
    q = start
    for p in path:
        res = so.solve_ik(robot, p, q0=q, method="lm")
        assert res.success and res.iterations <= 12, res
        assert np.abs(res.q - q).max() < 0.05
        q = res.q


# ------------------------------------------------------------------ batches
@pytest.mark.parametrize("name", BUNDLED)
def test_solve_many_agrees_with_single_solves(robots, name):
    """The batch entry point returns the single solver's q for every target, bit for bit."""
    robot = robots[name]
    P = reachable_targets(robot, 200, seed=13)
    batch = solve_many(robot, P)
    assert batch.success.all() and batch.error.max() <= 1e-9
    single = np.array([so.solve_ik(robot, p, method="lm").q for p in P])
    np.testing.assert_array_equal(batch.q, single)


def test_solve_many_with_yaw_rows_q0s_and_targets(robots):
    """(n, 4) rows [x, y, z, yaw], per-target q0s and a list of Target give the same q."""
    robot = robots["fang"]
    Q = random_q(robot, 50, seed=14)
    P = robot.positions(Q)
    Y = np.array([robot.yaw(q) for q in Q])
    q0s = np.clip(Q + 0.05, robot.lower, robot.upper)
    rows = solve_many(robot, np.column_stack([P, Y]), q0s)
    listed = solve_many(robot, [so.Target(p, yaw=y) for p, y in zip(P, Y, strict=True)], q0s)
    assert rows.success.all()
    np.testing.assert_array_equal(rows.q, listed.q)
    single = [so.solve_ik(robot, so.Target(p, yaw=y), q0=q0, method="lm").q
              for p, y, q0 in zip(P, Y, q0s, strict=True)]
    np.testing.assert_array_equal(rows.q, np.array(single))


def test_solve_many_with_rotation_targets(arm6):
    """Full-pose targets batch like single solves (the rotation error broadcasts too)."""
    Q = random_q(arm6, 6, seed=17)
    targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in arm6.fk_batch(Q)]
    batch = solve_many(arm6, targets, restarts=40)
    single = [so.solve_ik(arm6, t, method="lm", restarts=40) for t in targets]
    np.testing.assert_array_equal(batch.q, np.array([r.q for r in single]))
    np.testing.assert_allclose(batch.error, [r.error for r in single], atol=1e-15)
    assert batch.success.tolist() == [r.success for r in single]


def test_solve_many_reports_misses_honestly(robots):
    """An unreachable row is not a success; its error is the true residual from FK."""
    robot = robots["zavar2024"]
    P = np.vstack([reachable_targets(robot, 3, seed=1), UNREACHABLE])
    batch = solve_many(robot, P, restarts=2)
    assert batch.success.tolist() == [True, True, True, False]
    assert batch.error[3] == pytest.approx(0.102, abs=1e-3)
    assert robot.within_limits(batch.q).all()


@pytest.mark.parametrize("targets", [np.array([["0.3", "0.1", "-0.07"]]),
                                     [["0.3", "0.1", "-0.07"]], [[True, False, True]],
                                     np.array([[0.3, 0.1, None]], dtype=object)])
def test_solve_many_refuses_what_target_refuses(robots, targets):
    """Arrays of strings or bools were parsed as numbers by solve_many (``Target`` refuses
    them): now an InputError naming the argument.

    Mutation caught: ``np.asarray(targets, dtype=float)`` again -> the strings solved; fails.
    """
    with pytest.raises(so.InputError, match="targets, an .* must be numeric"):
        solve_many(robots["zavar2024"], targets)


def test_threads_get_their_own_buffers(robots):
    """Solves from several threads at once give the serial answers."""
    robot = robots["inverted5"]
    P = reachable_targets(robot, 40, seed=15)
    serial = [so.solve_ik(robot, p, method="lm").q for p in P]
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(lambda p: so.solve_ik(robot, p, method="lm").q, P))
    np.testing.assert_array_equal(np.array(threaded), np.array(serial))


def test_jit_gives_the_same_answers(robots):
    """The C-compiled iterations agree with the virtual machine's (skipped without a compiler)."""
    robot = robots["zavar2024"]
    try:
        cached_step(robot, "lm", "position", 1, jit=True)
    except so.InputError as exc:
        pytest.skip(f"no C compiler: {exc}")
    P = reachable_targets(robot, 20, seed=16)
    for p in P:
        a, b = (so.solve_ik(robot, p, method="lm", jit=j) for j in (False, True))
        assert b.success
        np.testing.assert_allclose(a.q, b.q, atol=1e-12)


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("method", ["lm", "auto"])
def test_bad_input_raises_the_base_errors(robots, arm6, method):
    """NaN targets, bad q0, q0 outside limits, bad tol, unknown options, yaw without axis."""
    robot = robots["zavar2024"]
    with pytest.raises(so.TargetError):
        so.solve_ik(robot, [np.nan, 0.1, -0.06], method=method)
    with pytest.raises(so.InputError):
        so.solve_ik(robot, [0.2, 0.1, -0.06], q0=[0.0, 0.0], method=method)
    with pytest.raises(so.JointLimitError, match="theta1"):
        so.solve_ik(robot, [0.2, 0.1, -0.06], q0=[3.0, 0.0, 0.01, 0.0], method=method)
    with pytest.raises(so.InputError, match="tol"):
        so.solve_ik(robot, [0.2, 0.1, -0.06], tol=-1.0, method=method)
    with pytest.raises(so.SolverOptionError, match="restarts"):
        so.solve_ik(robot, [0.2, 0.1, -0.06], method=method, restart=3)
    with pytest.raises(so.TargetError, match="yaw"):
        so.solve_ik(arm6, so.Target([0.3, 0.1, 0.4], yaw=0.1), method=method)


def test_solve_many_bad_input(robots, arm6):
    """solve_many refuses malformed targets, mixed kinds, bad q0s and a yaw without an axis."""
    robot = robots["zavar2024"]
    P = reachable_targets(robot, 3, seed=1)
    with pytest.raises(so.InputError):
        solve_many(robot, np.ones((3, 2)))
    with pytest.raises(so.InputError):
        solve_many(robot, [[np.nan, 0.1, -0.06]])
    with pytest.raises(so.InputError, match="one kind"):
        solve_many(robot, [so.Target(P[0]), so.Target(P[1], yaw=0.1)])
    with pytest.raises(so.InputError, match="rows"):
        solve_many(robot, P, np.zeros((2, 4)))
    with pytest.raises(so.JointLimitError):
        solve_many(robot, P, np.tile([3.0, 0.0, 0.01, 0.0], (3, 1)))
    with pytest.raises(so.TargetError):
        solve_many(arm6, [[0.3, 0.1, 0.4, 0.1]])
    with pytest.raises(so.InputError, match="max_iter=-1"):
        solve_many(robot, P, max_iter=-1)
    for seed in (-1, 1.5):
        with pytest.raises(so.InputError, match="seed"):
            solve_many(robot, P, seed=seed)
    with pytest.raises(so.InputError, match="tol"):
        solve_many(robot, P, tol=np.inf)
