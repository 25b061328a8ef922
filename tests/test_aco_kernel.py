"""aco's C kernel (aco_ants.c) against its numpy form: the same ants, bit for bit (issue 18)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import scara_opt as so
from scara_opt.metaheuristics import aco
from scara_opt.metaheuristics.base import Problem

CODE = ("import numpy as np, scara_opt as so; from scara_opt.metaheuristics import aco; "
        "r = so.solve_ik(so.load_robot('zavar2024'), (-0.23, 0.2, -0.07), method='aco', "
        "population=30, iterations=30, seed=2, tol=1e-12); "
        "print(aco._kernel() is None, r.q.tobytes().hex(), r.evaluations)")


def box(lower: list[float], upper: list[float], periodic: list[bool]) -> Problem:
    """A :class:`Problem` with only a search box (enough for ``repair``; no robot, no cost)."""
    problem = Problem.__new__(Problem)
    problem.lower, problem.upper = np.array(lower), np.array(upper)
    problem.periodic = np.array(periodic)
    problem._any_periodic, problem._position, problem._sized = any(periodic), False, {}
    return problem


def archive(rng: np.random.Generator, problem: Problem, k: int) -> np.ndarray:
    """k rows in the box: odd joints continuous values, even joints from 5 values (ties),
    the limits among them; one row repeated (equal rows)."""
    lo, hi = problem.lower, problem.upper
    S = rng.uniform(lo, hi, (k, lo.shape[0]))
    grid = lo + (hi - lo) * np.array([0.0, 0.25, 0.5, 0.625, 1.0])[:, None]
    for j in range(0, lo.shape[0], 2):
        S[:, j] = grid[rng.integers(0, 5, k), j]
    S[k // 2] = S[0]
    return S


@pytest.mark.parametrize("k", [2, 3, 17, 100, 257])
@pytest.mark.parametrize("q", [0.1, 0.7])
def test_kernel_gives_the_numpy_forms_ants_bit_for_bit(monkeypatch, k, q):
    """C and numpy: the same ants, to the bit, on archives with ties, the limits, a repeated
    row, draws that hit the cumulative weights exactly (and u = 0, 1), wide kernels (reflected
    and clipped) and continuous joints (wrapped).

    Mutations, each fails: searchsorted side='left' (``base[n / 2] <= x`` -> ``<``);
    σ without the ``/ (k - 1)``; the running sum off by one (``C[r - 1] + v[r]`` ->
    ``C[r - 1] + v[r - 1]``); ties merged right first (``before(key[j], key[i])`` ->
    ``!before(key[i], key[j])``); σ as ``xi * (dev / (k - 1))``; the deviation formula
    regrouped (``+ v[r] + C[k - 1]`` -> ``+ (v[r] + C[k - 1])``); wrap as a plain ``fmod``.
    """
    if aco._kernel() is None:
        pytest.skip("no C compiler: only the numpy form runs")
    rng = np.random.default_rng(k)
    problem = box([-1.0, -2.0, 0.0, -np.pi, -0.5], [1.0, 2.0, 0.05, np.pi, 3.0],
                  [False, False, False, True, True])
    for _ in range(5):
        S = archive(rng, problem, k)
        draws = aco.Draws(problem, k, q)
        cum = draws.cum
        hits = cum / cum[-1]
        hits = hits[cum[-1] * hits == cum]                # u with cum[-1] u == some cum[l]
        draws.u[:] = rng.random(k)
        draws.u[: min(k, hits.shape[0])] = hits[:k]
        draws.u[-2:] = 0.0, 1.0
        draws.normal[:] = 4.0 * rng.standard_normal((k, 5))
        ants_c = aco.sample_ants(problem, S, 0.85, draws).copy()
        with monkeypatch.context() as m:
            m.setattr(aco, "_kernel", lambda: None)
            ants_np = aco.sample_ants(problem, S, 0.85, draws)
        assert ants_c.tobytes() == ants_np.tobytes()


def test_no_compile_runs_the_numpy_form_with_the_same_numbers():
    """Under SCARA_OPT_NO_COMPILE=1 no kernel is loaded and a seeded solve gives the same
    answer, to the bit, as with the kernel.

    Mutation: ``if kernel is None`` -> ``if False`` (the C path taken without a kernel) fails.
    """
    env = {**os.environ, "SCARA_OPT_NO_COMPILE": "1"}
    out = subprocess.run([sys.executable, "-c", CODE], env=env, capture_output=True,
                         text=True, check=True).stdout.split()
    assert out[0] == "True"
    res = so.solve_ik(so.load_robot("zavar2024"), (-0.23, 0.2, -0.07), method="aco",
                      population=30, iterations=30, seed=2, tol=1e-12)
    assert out[1:] == [res.q.tobytes().hex(), str(res.evaluations)]


def test_signed_zeros_repair_as_numpy(monkeypatch):
    """At a limit of 0, an ant of -0.0 (archive -0.0 plus a -0.0 kernel step) is reflected and
    clipped to numpy's zero, sign included (np.maximum/minimum give the second of equals).

    Mutation caught: max/min returning the first of equals (``a > b`` -> ``a >= b``).
    """
    if aco._kernel() is None:
        pytest.skip("no C compiler: only the numpy form runs")
    problem = box([0.0, -1.0], [1.0, 0.0], [False, False])
    k = 4
    S = np.array([[-0.0, -0.0], [0.0, 0.0], [-0.0, 0.0], [0.0, -0.0]])
    draws = aco.Draws(problem, k, 0.5)
    draws.u[:] = [0.1, 0.4, 0.6, 0.9]
    draws.normal[:] = -0.0
    ants_c = aco.sample_ants(problem, S, 0.85, draws).copy()
    monkeypatch.setattr(aco, "_kernel", lambda: None)
    assert ants_c.tobytes() == aco.sample_ants(problem, S, 0.85, draws).tobytes()
