"""Seeded metaheuristic runs give the numbers they gave before the speed work (issue 18).

The speed work may change how a generation is computed, never what it computes: the
configurations below were recorded at commit 90dda97 (before it) on zavar2024, population
20, 20 generations, seed 5. A change of the random draws' order, of the bounds rule or of
the cost gives different numbers. Compared to 1e-9 relative, not bit for bit, so that the
FK compiled to C and casadi's virtual machine (machines without a compiler) both pass.
"""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so
import scara_opt.metaheuristics  # noqa: F401  (registers the solvers)
from scara_opt.metaheuristics.base import Problem

EASY = (-0.23, 0.20, -0.07)
BUDGET = {"population": 20, "iterations": 20, "seed": 5, "tol": 1e-9}
POSITION = [  # method, options, evaluations, q
    ("ca", {}, 420, [1.7224122569437434, 1.4075213392492436, 0.020036429840503352,
                     -0.9889416220441722]),
    ("gwo", {}, 420, [1.7114638437255447, 1.4183360809171368, 0.016939246142244995,
                      0.16534928824943357]),
    ("gwo", {"greedy": True}, 420, [1.7345074495057844, 1.3850751972900888,
                                    0.02012098009863931, 1.7271676072272282]),
    ("pso", {}, 420, [1.7285115791978507, 1.388798899595112, 0.021267210217721363,
                      -0.9406900536482765]),
    ("ga", {}, 420, [1.7199452547407301, 1.4130164503490825, 0.024863368458147503,
                     0.37435987701691437]),
    ("gha", {}, 420, [1.7199452547407301, 1.4130164503490825, 0.024863368458147503,
                      0.37435987701691437]),
    ("fa", {}, 420, [1.7218479690220565, 1.408205089096671, 0.02757520201810692,
                     -0.3449485765744525]),
    ("fa", {"sweep": "nearest"}, 420, [1.7144404602538534, 1.4173657910831612,
                                       0.022317126776278996, -0.5879155145061491]),
    ("aco", {}, 420, [1.7217630080030881, 1.4080731788550311, 0.020053148315681606,
                      1.2249828489570755]),
    ("sfla", {}, 226, [1.9341568003046652, 1.0905693054316412, 0.03813222685179596,
                       -1.410587281634104]),
]
YAW = [  # a yaw target: the cost goes through task.cost_batch, not the position fast path
    ("pso", 420, [1.6582644199176797, 1.580611319008845, 0.0465342071213365,
                  -0.6294753589357568]),
    ("fa", 420, [0.07243465841781807, 1.824172387315356, 0.03016276123059016,
                 0.7756615997072582]),
]


@pytest.fixture(scope="module")
def zavar(robots) -> so.Robot:
    return robots["zavar2024"]


@pytest.mark.parametrize(("method", "options", "evaluations", "q"), POSITION,
                         ids=[f"{m}{'+' + '+'.join(map(str, o.values())) if o else ''}"
                              for m, o, _, _ in POSITION])
def test_seeded_position_runs_unchanged(zavar, method, options, evaluations, q):
    """Same seed, same numbers as before the speed work, position target.

    Mutations: pso drawing ``r2, r1`` instead of ``r1, r2`` fails the pso row; fa drawing
    ``v, u`` instead of ``u, v`` fails the fa row; repair without the final clip fails rows.
    """
    res = so.solve_ik(zavar, EASY, method=method, **options, **BUDGET)
    assert res.evaluations == evaluations
    np.testing.assert_allclose(res.q, q, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(("method", "evaluations", "q"), YAW, ids=[m for m, _, _ in YAW])
def test_seeded_yaw_runs_unchanged(zavar, method, evaluations, q):
    """Same seed, same numbers as before the speed work, yaw target (mutations as above)."""
    res = so.solve_ik(zavar, so.Target(EASY, yaw=np.radians(150)), method=method, **BUDGET)
    assert res.evaluations == evaluations
    np.testing.assert_allclose(res.q, q, rtol=1e-9, atol=1e-12)


def test_repair_is_reflect_then_clip_bit_for_bit(zavar):
    """``Problem.repair`` equals the documented rule (reflect once at the crossed limit, then
    clip) exactly, on moves inside, just outside and far outside the box.

    Mutations: ``np.maximum(X, mirror - X)`` -> ``np.minimum`` fails; dropping the clip to
    ``lower`` fails (a move beyond a whole range would stay outside).
    """
    problem = Problem(zavar, so.Target(EASY), 1e-9)
    lo, hi = problem.lower, problem.upper
    X = np.random.default_rng(0).uniform(lo - 3 * problem.span, hi + 3 * problem.span,
                                         (2000, zavar.nq))
    X[:4] = [lo, hi, lo - 1e-17, hi + problem.span]
    Y = np.where(X < lo, 2.0 * lo - X, X)
    expected = np.clip(np.where(Y > hi, 2.0 * hi - Y, Y), lo, hi)
    assert np.array_equal(problem.repair(X), expected)
    assert np.all((problem.repair(X) >= lo) & (problem.repair(X) <= hi))


def test_position_cost_equals_task_cost_batch(zavar):
    """``Problem.cost``'s position fast path gives exactly ``task.cost_batch``'s numbers,
    and counts its rows.

    Mutations: dropping the weight (``wp**2``) in the fast path fails with the non-unit
    weight; not counting the rows fails the evaluation count.
    """
    from scara_opt.ik.task import cost_batch

    X = np.random.default_rng(1).uniform(zavar.lower, zavar.upper, (100, zavar.nq))
    for target in (so.Target(EASY), so.Target(EASY, weights=(3.0, 1.0))):
        problem = Problem(zavar, target, 1e-9)
        assert np.array_equal(problem.cost(X), cost_batch(zavar, target, X))
        assert problem.evaluations == 100


def test_batch_fk_one_chunk_path_matches_the_chunked_path_and_owns_its_rows(zavar):
    """The one-chunk fast path of ``batch_fk.evaluate`` gives the chunked path's rows, and
    returns its own array (the next call reuses the buffers).

    Mutation: returning ``f.res["rows"][:n]`` without ``.copy()`` fails (the first result
    changes when the second batch is evaluated).
    """
    from scara_opt.model import batch_fk

    rng = np.random.default_rng(2)
    Q = rng.uniform(zavar.lower, zavar.upper, (batch_fk.CHUNK + 100, zavar.nq))
    chunked = batch_fk.evaluate(zavar, "pose", Q)          # two chunks: the loop
    first = batch_fk.evaluate(zavar, "pose", Q[:100])      # one chunk: the fast path
    assert np.array_equal(first, chunked[:100])
    batch_fk.evaluate(zavar, "pose", Q[100:200])
    assert np.array_equal(first, chunked[:100])
