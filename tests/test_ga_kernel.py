"""The GA's C kernel (ga_breed.c) and its numpy form give the same bits (issue 18).

The golden seeded runs (test_meta_reproducible, test_meta_speed) pin whole solves; here the
two forms of one generation meet on populations the solves rarely make: many equal costs,
a NaN cost, tournaments of 1-3, sizes 1-100, children far outside the box (the repair's
three branches), a continuous joint (the kernel leaves the repair to numpy).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import scara_opt as so
from scara_opt.metaheuristics import base, ga_breed
from scara_opt.metaheuristics.ga_breed import Draws, offspring, offspring_numpy
from scara_opt.metaheuristics.problem import Problem

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def problems(robots) -> dict[str, Problem]:
    wrist = so.Robot.from_urdf(DATA / "scara_continuous_wrist.urdf", tip="tool")
    target = so.Target((-0.2, 0.2, -0.05))
    return {"zavar2024": Problem(robots["zavar2024"], target, 1e-6),
            "wrist": Problem(wrist, target, 1e-6)}


def population(problem: Problem, n: int, rng: np.random.Generator, nan: bool,
               zeros: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``n`` rows in the box with costs from {0, 1, 2} (ties everywhere), one NaN if asked;
    with ``zeros``, every coordinate +0.0 or -0.0."""
    X = rng.choice([-0.0, 0.0], (n, problem.nq)) if zeros else problem.uniform(rng, n)
    f = rng.integers(0, 3, n).astype(float)
    if nan:
        f[rng.integers(n)] = np.nan
    return X, f


def bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).view(np.uint64)


@pytest.mark.parametrize("robot", ["zavar2024", "wrist"])
@pytest.mark.parametrize("t", [1, 2, 3])
@pytest.mark.parametrize("n", [1, 7, 100])
@pytest.mark.parametrize("nan", [False, True])
def test_c_and_numpy_children_same_bits(problems, robot, t, n, nan):
    """C and numpy children agree bit for bit (crossing and mutation rates 0 to 1; σ up to
    2 joint ranges, so children land below, above and far beyond the box).

    Mutations (each fails here): the winner the last of equals (``<`` -> ``<=`` in
    ``winner``); a NaN cost not winning (``|| f[e[k]] != f[e[k]]`` dropped); the blend
    where not crossed (``crossed ?`` -> ``1 ?``); the mutation mask dropped (``(double)(...)``
    -> ``1.0``); ``step * (sigma * span)`` reassociated as ``(step * sigma) * span``; the
    upper reflection dropped (``np_min(c, 2.0 * a->hi[j] - c)`` -> ``c``); the blend weight
    without its map to U(-γ, 1 + γ) (``w = u_low + u_range * u`` -> ``w = u``; the golden
    runs of test_meta_reproducible fail too).
    """
    if ga_breed._kernel() is None:
        pytest.skip("no C compiler here: only the numpy form runs")
    problem = problems[robot]
    rng = np.random.default_rng([n, t, nan])
    for crossover, mutation, sigma in [(0.8, 0.2, 0.1), (0.0, 1.0, 2.0), (1.0, 0.0, 1e-4),
                                       (0.5, 0.5, 0.7)]:
        X, f = population(problem, n, rng, nan)
        d = Draws(problem, n, t)
        d.draw(rng, 0.4)
        expect = offspring_numpy(problem, X, f, d, sigma, crossover, mutation)
        got = offspring(problem, X, f, d, sigma, crossover, mutation)
        assert got is d.out
        np.testing.assert_array_equal(bits(got), bits(expect))
        assert np.all((got >= problem.lower) & (got <= problem.upper))


@pytest.mark.parametrize("mirrored", [False, True])
@pytest.mark.parametrize(("crossover", "mutation"), [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])
def test_c_and_numpy_signed_zeros_same_bits(robots, mirrored, crossover, mutation):
    """A population of +0.0 and -0.0 (zavar2024's third joint has its lower limit at 0, and
    its upper one in the box mirrored about 0: the reflections' maximum and minimum meet
    equal operands of both signs): the same bits, signs included.

    Mutations: ``np_max`` returning the first of equals (``a > b`` -> ``a >= b``) fails;
    ``np_min`` likewise (``a < b`` -> ``a <= b``) fails the mirrored box; the mask as a
    select (``s = s * (double)(...)`` -> ``s = a->rm[ij] < p_mut ? s : 0.0``, which loses
    a masked step's -0.0) fails.
    """
    if ga_breed._kernel() is None:
        pytest.skip("no C compiler here: only the numpy form runs")
    problem = Problem(robots["zavar2024"], so.Target((-0.2, 0.2, -0.05)), 1e-6)
    if mirrored:                                  # before the first repair tiles the limits
        problem.lower, problem.upper = -problem.upper, -problem.lower
    rng = np.random.default_rng(11)
    X, f = population(problem, 100, rng, nan=False, zeros=True)
    d = Draws(problem, 100, 2)
    d.draw(rng, 0.4)
    expect = offspring_numpy(problem, X, f, d, 1e-3, crossover, mutation)
    got = offspring(problem, X, f, d, 1e-3, crossover, mutation)
    assert np.signbit(expect).any() and not np.signbit(expect).all()
    np.testing.assert_array_equal(bits(got), bits(expect))


@pytest.mark.parametrize("n", [1, 7, 100])
def test_pool_survivors_same_rows_as_base_survivors(problems, n):
    """``Draws.survivors`` (from the pool) equals ``base.survivors`` (stacked), ties included.

    Mutations: the pool sorted with the default (unstable) ``argsort`` fails (ties then
    reorder); parents and children swapped in the pool (``self.pool[:n], self.pool[n:]``
    -> ``self.pool[n:], self.pool[:n]``) fails; the pools not swapped after the survivors
    are taken (``self.cur, self.other = q, p`` dropped: right rows, copied back each
    generation) fails.
    """
    problem = problems["zavar2024"]
    rng = np.random.default_rng(n)
    X, f = population(problem, n, rng, nan=False)
    d = Draws(problem, n, 2)
    np.copyto(d.cur.X, X)
    np.copyto(d.cur.f, f)
    children = problem.uniform(rng, n)
    np.copyto(d.out, children)
    fc = rng.integers(0, 3, n).astype(float)
    got = d.survivors(X, f, d.out, fc)
    expect = base.survivors(X, f, children, fc, n)
    np.testing.assert_array_equal(bits(got.X), bits(expect.X))
    np.testing.assert_array_equal(bits(got.f), bits(expect.f))
    assert got.X is d.cur.X and got.f is d.cur.f   # the next parents: read there, no copy


def test_no_compile_runs_the_numpy_form_with_the_same_answer(robots):
    """Under ``SCARA_OPT_NO_COMPILE=1`` no kernel loads and a GA solve (tournaments of 3,
    as the kernel's form runs here) returns the same bits.

    Mutation: ``offspring`` calling the kernel even when it is ``None`` (``if kernel is
    None:`` -> ``if False:``) fails.
    """
    options = "population=30, iterations=40, seed=3, tournament=3"
    code = ("import scara_opt as so, numpy as np\n"
            "from scara_opt.metaheuristics import ga_breed\n"
            "print(ga_breed._kernel() is None)\n"
            f"r = so.solve_ik(so.load_robot('zavar2024'), (-0.2, 0.2, -0.05), method='ga', "
            f"{options})\n"
            "print(r.q.tobytes().hex())\n")
    env = {**os.environ, "SCARA_OPT_NO_COMPILE": "1"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True, timeout=300).stdout.split()
    assert out[0] == "True"
    here = so.solve_ik(robots["zavar2024"], (-0.2, 0.2, -0.05), method="ga", population=30,
                       iterations=40, seed=3, tournament=3)
    assert out[1] == here.q.tobytes().hex()
