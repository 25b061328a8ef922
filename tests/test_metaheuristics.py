"""Metaheuristic IK: one contract for all seven, measured success rates, SFLA with a yaw target."""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so
import scara_opt.metaheuristics  # noqa: F401  (registers the seven solvers)
from scara_opt.errors import InputError, SolverOptionError
from scara_opt.metaheuristics import PopulationSolver

METHODS = ["aco", "ca", "fa", "ga", "gwo", "pso", "sfla"]
EASY = (-0.23, 0.20, -0.07)        # zavar2024's target with z moved into reach
OUT_OF_REACH = (-0.23, 0.20, -0.20)  # zavar2024's own target: z outside [-0.098, -0.05] m
SMALL = {"population": 20, "iterations": 30}


@pytest.fixture(scope="module")
def zavar(robots) -> so.Robot:
    return robots["zavar2024"]


def test_importing_the_package_registers_all_seven():
    """Importing scara_opt.metaheuristics registers every metaheuristic under its short name."""
    assert set(METHODS) <= set(so.solvers())
    for name in METHODS:
        assert isinstance(so.get_solver(name), PopulationSolver)


def test_defaults_are_the_papers_settings():
    """SFLA: nguyen Table 2 (N = 20 frogs in m = 10 memeplexes, iter = 10 leaps between G = 20
    shuffles, C = 2, Dmax = inf); G-HA: zavar2024 switches to Nelder-Mead below cost 1e-3."""
    sfla = so.get_solver("sfla").options
    assert sfla == {"population": 200, "iterations": 200, "memeplexes": 10, "local_steps": 10,
                    "leap": 2.0, "max_leap": np.inf}
    assert so.get_solver("ga").options["polish_below"] == 1e-3
    gwo = so.get_solver("gwo").options
    assert gwo["a_start"] == 2.0 and gwo["greedy"] is False  # zavar2024 Algorithm 2: a 2 -> 0


@pytest.mark.parametrize("method", METHODS)
def test_contract(zavar, method):
    """Same seed gives the same answer, seeds differ, history never rises, q stays in limits."""
    a = so.solve_ik(zavar, EASY, method=method, seed=3, tol=1e-6, **SMALL)
    b = so.solve_ik(zavar, EASY, method=method, seed=3, tol=1e-6, **SMALL)
    c = so.solve_ik(zavar, EASY, method=method, seed=4, tol=1e-6, **SMALL)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.history, b.history)
    assert a.evaluations == b.evaluations and a.iterations == b.iterations
    assert not np.array_equal(a.q, c.q)
    for res in (a, c):
        assert res.method == method
        assert zavar.within_limits(res.q)
        assert res.success == (res.status == "solved")
        if res.success:
            assert res.error <= res.tol
        assert len(res.history) == res.iterations + 1 <= SMALL["iterations"] + 1
        assert np.all(np.diff(res.history) <= 0)
        assert res.history[-1] == pytest.approx(res.cost, rel=1e-9, abs=1e-15)
        assert res.evaluations >= SMALL["population"]


@pytest.mark.parametrize("method", METHODS)
def test_out_of_reach_target_is_unreachable_never_solved(zavar, method):
    """zavar2024's own target (z out of reach) is reported unreachable with its 0.102 m residual."""
    res = so.solve_ik(zavar, OUT_OF_REACH, method=method, seed=0, tol=1e-6, **SMALL)
    assert not res.success
    assert res.status == "unreachable"
    assert res.error >= 0.102 - 1e-9
    assert zavar.within_limits(res.q)


@pytest.mark.parametrize("method", METHODS)
def test_unknown_option_raises(zavar, method):
    """A misspelt option raises SolverOptionError naming the accepted options."""
    with pytest.raises(SolverOptionError, match="population"):
        so.solve_ik(zavar, EASY, method=method, populaton=20)


@pytest.mark.parametrize(("method", "options"), [
    ("pso", {"population": 1}), ("gwo", {"population": 2}), ("aco", {"iterations": 0}),
    ("ca", {"accept": 0.0}), ("fa", {"alpha_end": 0.5}), ("ga", {"mutation": 1.5}),
    ("sfla", {"population": 15, "memeplexes": 10}), ("pso", {"population": 20.5}),
    ("gwo", {"greedy": "yes"}),
])
def test_bad_option_value_raises(method, options):
    """An option value out of its documented range raises InputError at construction."""
    with pytest.raises(InputError):
        so.get_solver(method, **options)


@pytest.mark.parametrize("method", METHODS)
def test_q0_seeds_one_individual(zavar, method):
    """A q0 that already solves the target is kept as an individual: solved at generation 0."""
    q0 = so.solve_ik(zavar, EASY, method="analytic").q
    res = so.solve_ik(zavar, EASY, method=method, q0=q0, seed=0, tol=1e-6, **SMALL)
    assert res.success and res.iterations == 0 and len(res.history) == 1
    assert np.array_equal(res.q, q0)


def test_ga_counts_nelder_mead_evaluations(zavar):
    """G-HA's Nelder-Mead polish is counted: more evaluations than the GA generations alone."""
    res = so.solve_ik(zavar, EASY, method="ga", seed=1, tol=1e-6)
    assert res.success
    assert res.evaluations > 60 * (res.iterations + 1)
    off = so.solve_ik(zavar, EASY, method="ga", seed=1, tol=1e-6, polish_maxfev=0)
    assert off.evaluations == 60 * (off.iterations + 1)


# Success at tol = 1e-6 m on EASY, population 60, 200 iterations, seeds 0-9: the floor
# asserted sits one below what was measured (30 seeds, 0-29, in parentheses):
# aco 10/10 (30/30), ca 10/10 (30/30), fa 10/10 (29/30), ga 10/10 (30/30),
# pso 10/10 (30/30), sfla 10/10 (30/30). GWO reaches 0/10 (0/30) at 1e-6 m: with
# a falling linearly to 0 its steps stay ~a·|x|, so it stalls near 1e-4 m (median 1.1e-4,
# worst 3.7e-4 over 30 seeds), as in the paper's Table 2; it is held to 1e-3 m instead.
SUCCESS_FLOORS = [("aco", 1e-6, 9), ("ca", 1e-6, 9), ("fa", 1e-6, 9), ("ga", 1e-6, 9),
                  ("pso", 1e-6, 9), ("sfla", 1e-6, 9), ("gwo", 1e-3, 9)]


@pytest.mark.parametrize(("method", "tol", "floor"), SUCCESS_FLOORS)
def test_success_rate_on_easy_target(zavar, method, tol, floor):
    """At population 60 / 200 iterations each method reaches tol in at least its measured share."""
    results = [so.solve_ik(zavar, EASY, method=method, population=60, iterations=200,
                           seed=seed, tol=tol) for seed in range(10)]
    solved = sum(r.success for r in results)
    assert solved >= floor, [f"{r.status}: {r.error:.2e}" for r in results]
    assert all(r.status in ("solved", "max_iter") for r in results)


def test_gwo_greedy_variant(zavar):
    """gwo greedy=True (mealpy's variant) is reproducible and stalls near 1e-4 m.

    Measured at population 60 / 200 iterations, seeds 0-29: median 1.1e-4 m, worst
    4.9e-4 m, none at 1e-6 m (the paper's GWO: median 1.1e-4 m, worst 3.7e-4 m).
    """
    runs = [so.solve_ik(zavar, EASY, method="gwo", greedy=True, seed=s, tol=1e-3)
            for s in range(5)]
    assert all(r.success for r in runs)
    again = so.solve_ik(zavar, EASY, method="gwo", greedy=True, seed=0, tol=1e-3)
    assert np.array_equal(again.q, runs[0].q)


# SFLA on nguyen, yaw targets, 12 reachable poses (seed 11), measured: at the paper's
# settings (200 leap rounds) the median residual is 1.4e-3 (5/12 below 1e-3, 11/12 below
# 1e-2, worst 1.4e-2) with ~2600 evaluations; with 1000 rounds all 12 reach 1e-6 (median
# 4600 evaluations). The test uses the first 6 of them.
def test_sfla_on_nguyen_with_yaw_at_the_paper_settings(robots):
    """SFLA at nguyen's Table 2 settings lands within millimetres, and at 1e-6 given more leaps."""
    robot = robots["nguyen"]
    qs = np.random.default_rng(11).uniform(robot.lower, robot.upper, (6, robot.nq))
    targets = [so.Target(robot.fk(q)[:3, 3], yaw=robot.yaw(q)) for q in qs]
    errors = []
    for target in targets:
        res = so.solve_ik(robot, target, method="sfla", seed=0, tol=1e-6)
        assert robot.within_limits(res.q) and res.yaw_error is not None
        assert res.success == (res.error <= 1e-6)
        errors.append(res.error)
    assert np.median(errors) < 5e-3 and max(errors) < 3e-2
    more = so.solve_ik(robot, targets[0], method="sfla", seed=0, tol=1e-6, iterations=1000)
    assert more.success


def test_aco_deviation_sums_equal_the_pairwise_definition():
    """ACO_R's O(k log k) deviation sums equal sum_e |s_e - s_l| computed pairwise (ties too)."""
    from scara_opt.metaheuristics.aco import abs_deviation_sums

    S = np.random.default_rng(4).normal(size=(40, 5))
    S[7] = S[3]  # a tie
    pairwise = np.abs(S[:, None, :] - S[None, :, :]).sum(axis=0)
    np.testing.assert_allclose(abs_deviation_sums(S), pairwise, rtol=1e-12, atol=1e-12)
