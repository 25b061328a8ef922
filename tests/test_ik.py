"""Exact IK: IPOPT reference and closed form, one registry, one result type, the papers' cases."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import scara_opt as so
from scara_opt.comparison import takes_budget
from scara_opt.ik.analytic import NotScaraError, solve_batch
from scara_opt.ik.ipopt import cached_nlp
from scara_opt.reports.fang import paper_ik
from tests.conftest import BUNDLED, random_q

FOUR_JOINT = ["fang", "peng2025", "zavar2024"]


def reachable_targets(robot: so.Robot, n: int, seed: int) -> np.ndarray:
    """Positions (n, 3) of random in-limit configurations: reachable by construction."""
    return robot.positions(random_q(robot, n, seed))


def assert_invariants(robot: so.Robot, res: so.IKResult) -> None:
    assert robot.within_limits(res.q)
    assert res.success == (res.status == "solved")
    if res.success:
        assert res.error <= res.tol
    assert res.message and np.isfinite(res.error) and res.position_error.shape == (3,)


# ------------------------------------------------------------------ IPOPT reference
@pytest.mark.parametrize("method", ["ipopt", "lm"])
@pytest.mark.parametrize("name", BUNDLED)
def test_exact_solvers_reach_1000_reachable_targets(robots, name, method):
    """IPOPT, and the fast solver alone, reach 1000 reachable targets of each robot to 1e-9 m."""
    robot = robots[name]
    P = reachable_targets(robot, 1000, seed=7)
    results = [so.solve_ik(robot, p, method=method, tol=1e-9) for p in P]
    for res in results:
        assert_invariants(robot, res)
    failed = [r for r in results if not r.success]
    assert not failed, f"{len(failed)} failures, e.g. {failed[:2]}"
    assert max(r.error for r in results) <= 1e-9


@pytest.mark.parametrize("name", FOUR_JOINT)
def test_ipopt_answer_is_one_of_the_closed_form_branches(robots, name):
    """For the 4-joint robots IPOPT's q (position target) equals one branch of ik_all (1000)."""
    robot = robots[name]
    for p in reachable_targets(robot, 1000, seed=8):
        res = so.solve_ik(robot, p, method="ipopt")
        branches = so.ik_all(robot, p)
        assert branches, "reachable target without closed-form branch"
        gap = min(np.abs(b.q - res.q).max() for b in branches)
        assert gap < 1e-6, (res, branches)


@pytest.mark.parametrize(("name", "method"), [(n, "ipopt") for n in FOUR_JOINT]
                         + [(n, "auto") for n in BUNDLED])
def test_exact_solvers_with_yaw(robots, name, method):
    """Position and tool angle together (nguyen eq. 10 task) on 200 targets, to 1e-9."""
    robot = robots[name]
    Q = random_q(robot, 200, seed=9)
    for q, p in zip(Q, robot.positions(Q), strict=True):
        res = so.solve_ik(robot, so.Target(p, yaw=robot.yaw(q)), method=method)
        assert res.success, res
        assert abs(res.yaw_error) <= 1e-9
        assert_invariants(robot, res)


def test_ipopt_with_a_full_rotation_on_a_general_arm(arm6):
    """A 6-joint arm with full pose targets is solved to 1e-9 (nothing SCARA-only).

    This test arm (unaligned elbow, a short unaligned slide) has narrow basins: measured
    19/20 solved with restarts=40 (seed 10), so at least 18 are asserted; every answer,
    solved or not, keeps the invariants.
    """
    results = []
    for q in random_q(arm6, 20, seed=10):
        T = arm6.fk(q)
        results.append(so.solve_ik(arm6, so.Target(T[:3, 3], rotation=T[:3, :3]),
                                   method="ipopt", restarts=40))
    for res in results:
        assert_invariants(arm6, res)
    assert sum(r.success for r in results) >= 18, results


def test_ipopt_counts_are_honest_where_the_task_overdetermines_the_joints(robots):
    """A full pose for a 4-joint SCARA (6 residual rows, 4 joints): IPOPT's nearest NLP would
    have no degrees of freedom, so it is not run; the answer comes from the closest NLP.
    The iterations reported are IPOPT's, at most max_iter per call (before: 3e10 to 6e10,
    casadi's unset counter of the refused calls summed), and an IPOPT call that stopped
    before evaluating the objective counts no iterations.

    Mutations caught: the nearest NLP run anyway (Not_Enough_Degrees_Of_Freedom in the
    message); the count taken from a call that never evaluated f (an unset counter, ~1e9).
    """
    from scara_opt.ik.ipopt import _Run, build_nearest_nlp

    robot = robots["zavar2024"]
    q = random_q(robot, 1, seed=3)[0]
    T = robot.fk(q)
    target = so.Target(T[:3, 3], rotation=T[:3, :3])
    res = so.solve_ik(robot, target, method="ipopt", restarts=3)
    assert res.success, res
    assert "Not_Enough_Degrees_Of_Freedom" not in res.message
    assert 0 < res.iterations <= 4 * 100, res.iterations
    run = _Run(robot, target, {**so.get_solver("ipopt").options}, q, robot.lower,
               robot.upper, 1e-9, nearest=False)
    run._call(build_nearest_nlp(robot, "rotation"), q, lbg=0.0, ubg=0.0)  # refused by IPOPT
    assert run.statuses == ["Not_Enough_Degrees_Of_Freedom"]
    assert run.iterations == 0 and run.evaluations <= 1  # IPOPT's one gradient at the start


def test_nlp_is_built_once_per_robot_and_task_kind(robots):
    """A second solve reuses the cached casadi NLP instead of rebuilding it."""
    robot = robots["zavar2024"]
    so.solve_ik(robot, [0.2, 0.1, -0.06], method="ipopt")
    first = cached_nlp(robot, "position")
    so.solve_ik(robot, [0.25, -0.1, -0.07], method="ipopt")
    assert cached_nlp(robot, "position") is first


def test_redundant_inverted5_splits_the_stroke_closest_to_q0(robots):
    """inverted5's two z strokes (P1, P5) share a move evenly from an even q0 (nearest rule)."""
    robot = robots["inverted5"]
    q0 = np.array([0.02, 0.5, 1.0, 0.0, 0.02])
    p = robot.position(q0) + [0, 0, -0.02]  # 2 cm lower: P1 + P5 must grow by 0.02 m
    res = so.solve_ik(robot, p, q0=q0, method="ipopt")
    assert res.success
    np.testing.assert_allclose(res.q[[0, 4]], [0.03, 0.03], atol=1e-6)
    np.testing.assert_allclose(res.q[1:4], q0[1:4], atol=1e-6)


def test_redundant_nguyen_moves_least_from_q0(robots):
    """nguyen: a target reached from q0 itself returns q0 (zero motion is the nearest)."""
    robot = robots["nguyen"]
    q0 = np.array([0.3, 0.4, -0.6, 0.05, 0.2])
    res = so.solve_ik(robot, so.Target(robot.position(q0), yaw=robot.yaw(q0)), q0=q0,
                      method="ipopt")
    assert res.success
    np.testing.assert_allclose(res.q, q0, atol=1e-9)


# ------------------------------------------------------------------ the papers' cases
def test_zavar2024_paper_target_is_unreachable_by_0102_m(robots):
    """zavar2024's target (-0.23, 0.20, -0.20) is out of reach: residual 0.102 m along z."""
    robot = robots["zavar2024"]
    for method in ("ipopt", "analytic", "auto"):
        res = so.solve_ik(robot, [-0.23, 0.20, -0.20], method=method)
        assert res.status == "unreachable" and not res.success
        assert res.error == pytest.approx(0.102, abs=1e-3)
        assert "along z" in res.message and "along z" in repr(res)
        assert_invariants(robot, res)


def test_zavar2024_reachable_variant_is_solved(robots):
    """The same x, y at z = -0.07 m (inside the stroke) is solved by both exact methods."""
    robot = robots["zavar2024"]
    for method in ("ipopt", "analytic", "auto"):
        res = so.solve_ik(robot, [-0.23, 0.20, -0.07], method=method)
        assert res.status == "solved" and res.error <= 1e-9


def test_peng2025_validation_pose_is_2mm_out_of_stroke(robots):
    """peng2025 eq. 21: (400, -120, 170) mm, yaw 0 needs z0 = -2 mm: unreachable by 2 mm."""
    robot = robots["peng2025"]
    target = so.Target(np.array([400.0, -120.0, 170.0]) / 1000, yaw=0.0)
    res = so.solve_ik(robot, target)
    assert res.status == "unreachable"
    assert res.error == pytest.approx(0.002, abs=1e-6)
    assert so.ik_all(robot, target) == []
    widened = robot.with_limits(z0=(-0.005, 0.040))
    branches = so.ik_all(widened, target)
    elbows = {round(float(b.q[2]), 9) for b in branches}
    assert len(elbows) == 2, branches  # the paper's two solution sets (Figs. 9-10)
    for b in branches:
        assert b.q[0] == pytest.approx(-0.002, abs=1e-12)


def test_fang_arccos_forms_fail_for_negative_y_where_atan2_is_right(robots):
    """fang eq. 10 loses the sign of py (arccos): its answer misses; the atan2 closed form hits."""
    robot = robots["fang"]
    q_true = np.array([-0.9, 1.2, 0.01, 0.3])
    p = robot.position(q_true)
    assert p[1] < 0
    t1, t2 = paper_ik(p[0], p[1])
    paper = robot.position([t1, t2, q_true[2], 0.0])
    assert np.linalg.norm(paper[:2] - p[:2]) > 0.05  # the paper's formula lands elsewhere
    q_up = np.array([0.9, -1.2, 0.01, 0.3])  # the mirror image, py > 0: there eq. 10 works
    p_up = robot.position(q_up)
    t1, t2 = paper_ik(p_up[0], p_up[1])
    np.testing.assert_allclose(robot.position([t1, t2, q_up[2], 0.0]), p_up, atol=1e-12)
    branches = so.ik_all(robot, p)
    assert branches and all(b.error <= 1e-12 for b in branches)


# ------------------------------------------------------------------ closed form
@pytest.mark.parametrize("name", BUNDLED)
def test_every_analytic_branch_maps_back(robots, name):
    """Every closed-form branch of 1000 reachable targets is within limits and within 1e-12 m."""
    robot = robots[name]
    Q = random_q(robot, 1000, seed=11)
    for q, p in zip(Q, robot.positions(Q), strict=True):
        branches = so.ik_all(robot, so.Target(p, yaw=robot.yaw(q)), q0=q)
        assert branches, f"no branch for a reachable target of {name}"
        for b in branches:
            assert b.success and b.error <= 1e-12 and robot.within_limits(b.q)
        # nearest first: from q0 = the generating q, the first branch is q itself
        np.testing.assert_allclose(branches[0].q, q, atol=1e-9)


def test_analytic_holds_the_redundant_joint(robots):
    """inverted5: with P1 held by fixed=, the closed form solves the rest exactly."""
    robot = robots["inverted5"]
    q = np.array([0.01, 0.7, 1.4, -0.2, 0.03])
    p = robot.position(q)
    res = so.solve_ik(robot, p, method="analytic", fixed={"P1": 0.025})
    assert res.success and res.q[0] == 0.025 and res.q[4] == pytest.approx(0.015, abs=1e-12)
    with pytest.raises(so.InputError, match="redundant joints"):
        so.solve_ik(robot, p, method="analytic", fixed={"theta1": 0.1})
    # infeasible with P1 held at 0, reachable with P1 free: "failed" for the held joint,
    # never "unreachable"; the closest configuration holds P1 too
    far = robot.position(np.array([0.07, 0.7, 1.4, -0.2, 0.08]))
    miss = so.solve_ik(robot, far, method="analytic", fixed={"P1": 0.0})
    assert miss.status == "failed" and miss.reason == "held_joints"
    assert miss.q[0] == 0.0 and "P1 = 0 held" in miss.message
    assert so.solve_ik(robot, far, method="analytic").success  # P1 free: reachable


def test_analytic_refuses_a_non_scara_chain(arm6):
    """The SCARA closed form says plainly that a 6-joint arm is not SCARA-type; ``ik_all``
    on it (a prismatic joint: no arm closed form) falls back to the multi-start and says so.

    Mutation caught: ``multi_start_solutions``' route text emptied -> fails.
    """
    with pytest.raises(NotScaraError, match="SCARA-type"):
        solve_batch(arm6, np.array([[0.3, 0.1, 0.4]]))
    q = np.array([0.3, -0.4, 0.5, 0.05, 0.2, 0.1])
    found = so.ik_all(arm6, arm6.position(q))
    assert found and all(r.success and r.route.startswith("multi-start") for r in found)


@pytest.mark.parametrize("name", FOUR_JOINT)
def test_solve_batch_matches_ik_all(robots, name):
    """The vectorised closed form returns valid branches that reach every target exactly."""
    robot = robots[name]
    Q = random_q(robot, 2000, seed=12)
    P = robot.positions(Q)
    yaws = np.array([robot.yaw(q) for q in Q])
    sols, valid = solve_batch(robot, P, yaws)
    assert sols.shape == (2000, 2, robot.nq) and valid.any(axis=1).all()
    reach = robot.positions(sols[valid])
    np.testing.assert_allclose(reach, np.repeat(P[:, None], 2, axis=1)[valid], atol=1e-12)
    assert robot.within_limits(sols[valid]).all()


def test_solve_batch_flags_unreachable_rows(robots):
    """Rows out of reach are marked invalid, not returned as NaN."""
    robot = robots["zavar2024"]
    sols, valid = solve_batch(robot, [[-0.23, 0.20, -0.20], [-0.23, 0.20, -0.07], [1, 0, -0.07]])
    assert valid.any(axis=1).tolist() == [False, True, False]
    assert np.isfinite(sols).all()


# ------------------------------------------------------------------ property-based
@settings(max_examples=40, deadline=None, derandomize=True)  # the same examples every run
@given(st.sampled_from(BUNDLED), st.integers(0, 2**31 - 1), st.sampled_from(["ipopt", "auto"]))
def test_fk_ik_fk_round_trip(name, seed, method):
    """For any in-limit q, IPOPT (and the default, auto) find q' with fk(q') = fk(q) to 1e-9 m."""
    robot = so.load_robot(name)
    q = random_q(robot, 1, seed)[0]
    res = so.solve_ik(robot, robot.position(q), method=method)
    assert res.success
    np.testing.assert_allclose(robot.position(res.q), robot.position(q), atol=1e-9)


# ------------------------------------------------------------------ registry and bad input
REGISTERED = ["aco", "analytic", "auto", "ca", "fa", "ga", "gha", "gwo", "ipopt", "lm", "pso",
              "sfla"]


@pytest.mark.parametrize("method", REGISTERED)
def test_every_registered_solver_keeps_the_result_contract(robots, method):
    """Every solver of the registry: same seed, same answer; q in limits; success iff solved
    within tol; zavar2024's out-of-reach target (z) never solved, with its 0.102 m residual."""
    robot = robots["zavar2024"]
    budget = {"population": 20, "iterations": 30} if takes_budget(method) else {}
    runs = [so.solve_ik(robot, target, method=method, seed=3, tol=1e-6, **budget)
            for target in ([-0.23, 0.20, -0.07], [-0.23, 0.20, -0.07], [-0.23, 0.20, -0.20])]
    assert np.array_equal(runs[0].q, runs[1].q) and runs[0].error == runs[1].error
    for res in runs:
        assert res.method == method
        assert_invariants(robot, res)
    assert runs[2].status == "unreachable" and runs[2].error >= 0.102 - 1e-9


def test_registry_lists_and_refuses(robots):
    """solvers() lists every method; an unknown name lists the registered ones."""
    assert so.solvers() == REGISTERED
    with pytest.raises(so.UnknownSolverError, match="registered: .*ipopt"):
        so.solve_ik(robots["zavar2024"], [0.2, 0.1, -0.06], method="newton")
    with pytest.raises(so.SolverOptionError, match="restart.*accepted: .*restarts"):
        so.solve_ik(robots["zavar2024"], [0.2, 0.1, -0.06], restart=3)


def test_register_solver_plugs_in_and_refuses_duplicates(robots):
    """A user's solver plugs into solve_ik; a second registration under a taken name fails."""
    from scara_opt.ik import registry
    from scara_opt.ik.base import Solver, SolverOutput

    class Lazy(Solver):
        name = "lazy"
        defaults = {}

        def _solve(self, robot, target, q0, rng, tol):
            return SolverOutput(q=np.clip(np.zeros(robot.nq), robot.lower, robot.upper))

    so.register_solver("lazy", Lazy)
    try:
        assert "lazy" in so.solvers()
        res = so.solve_ik(robots["zavar2024"], [-0.23, 0.20, -0.07], method="lazy")
        assert res.status == "max_iter"  # reachable, but this solver did not get there
        with pytest.raises(so.InputError, match="already registered"):
            so.register_solver("lazy", Lazy)
    finally:
        registry._REGISTRY.pop("lazy")


@pytest.mark.parametrize("call, error, match", [
    (lambda r: so.solve_ik(r, [0, np.nan, 0]), so.TargetError, "NaN"),
    (lambda r: so.solve_ik(r, [0, 0]), so.TargetError, "shape"),
    (lambda r: so.solve_ik(r, [0.2, 0, -0.06], q0=[0, 0, 0]), so.InputError, "shape"),
    (lambda r: so.solve_ik(r, [0.2, 0, -0.06], q0=[3.4, 0, 0, 0]), so.JointLimitError,
     "'theta1' = 3.4 rad is outside"),
    (lambda r: so.solve_ik(r, [0.2, 0, -0.06], tol=-1), so.InputError, "tol"),
    (lambda r: r.with_limits(d3=(0.04, 0.01)), so.JointLimitError, "lower < upper"),
    (lambda r: r.with_limits(d7=(0.0, 0.01)), so.JointLimitError, "no joint named"),
])
def test_bad_input_raises_specific_errors(robots, call, error, match):
    """NaN/inf targets, wrong shapes, q0 outside limits, bad tol, inverted overrides."""
    with pytest.raises(error, match=match):
        call(robots["zavar2024"])


@pytest.mark.parametrize("method, options, match", [
    ("ipopt", {"restarts": -1}, r"restarts=-1 must be an integer in \[0, "),
        ("ipopt", {"max_iter": 10**12}, r"max_iter=1000000000000 must be an integer in \[1, "),
    ("ipopt", {"restarts": "x"}, "restarts='x'"),
    ("ipopt", {"max_iter": -5}, "max_iter=-5"),
    ("ipopt", {"regularization": np.nan}, "regularization=nan"),
    ("ipopt", {"polish": "yes"}, "polish='yes' must be True or False"),
    ("lm", {"max_iter": 0}, "max_iter=0"),
    ("lm", {"jit": 1}, "jit=1 must be True or False"),
    ("auto", {"ipopt_restarts": -1}, "ipopt_restarts=-1"),
    ("auto", {"restarts": 2.5}, "restarts=2.5"),
])
def test_bad_option_values_are_refused(robots, method, options, match):
    """An option value out of range is an InputError naming it, never a silent no-op.

    (ipopt with restarts=-1 used to run no start at all and call the target unreachable.)
    """
    with pytest.raises(so.InputError, match=match):
        so.solve_ik(robots["zavar2024"], [-0.23, 0.20, -0.07], method=method, **options)


def test_ik_all_and_solve_ik_refuse_bad_arguments(robots):
    """ik_all with a NaN/negative tol is an error, not an empty (\"unreachable\") list; a robot
    that is not a Robot is named."""
    robot = robots["zavar2024"]
    for tol in (np.nan, -1.0):
        with pytest.raises(so.InputError, match="tol"):
            so.ik_all(robot, [-0.23, 0.20, -0.07], tol=tol)
    with pytest.raises(so.InputError, match="robot must be a scara_opt.Robot"):
        so.solve_ik(None, [-0.23, 0.20, -0.07])


def test_tol_may_be_a_numpy_scalar(robots):
    """tol=np.float32(1e-6) is a number like any other."""
    res = so.solve_ik(robots["zavar2024"], [-0.23, 0.20, -0.07], tol=np.float32(1e-6))
    assert res.success and res.tol == pytest.approx(1e-6)


def test_yaw_for_a_robot_whose_tool_cannot_turn_is_refused(arm6):
    """A yaw target on a 6-joint arm (no single tool axis) is a TargetError."""
    with pytest.raises(so.TargetError, match="rotation="):
        so.solve_ik(arm6, so.Target([0.3, 0.1, 0.4], yaw=0.2))


def test_result_repr_is_one_line(robots):
    """repr(IKResult) is one line leading with the status and residual."""
    text = repr(so.solve_ik(robots["zavar2024"], [-0.23, 0.20, -0.07]))
    assert "\n" not in text and text.startswith("IKResult(solved, error=")


@pytest.mark.parametrize("method", [["lm"], ("lm",), {"lm": 1}, None, 3])
def test_method_must_be_one_name(robots, method):
    """solve_ik(method=["lm"]) raised TypeError: unhashable type; now the message says to
    pass one name (or use compare for several).

    Mutation: get_solver without its isinstance(method, str) check -> fails.
    """
    with pytest.raises(so.InputError, match=r"method must be one solver name .*so.compare"):
        so.solve_ik(robots["zavar2024"], [0.3, 0.0, -0.07], method=method)
