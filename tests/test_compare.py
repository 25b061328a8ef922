"""compare(): one table for every method, identical numbers serially, in a pool, on dask."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd
import pytest

import scara_opt as so
from scara_opt.compare import COLUMNS, compare, convergence, rank_methods, summarize

TARGETS = [[-0.23, 0.20, -0.07], [-0.23, 0.20, -0.20], [0.30, 0.10, -0.06]]
SAME = [c for c in COLUMNS if c not in ("time_s", "setup_s", "history")]
#: a stochastic method in every sweep: one seed for all jobs would show
SWEEP = {"methods": ["ipopt", "pso"], "populations": [8], "iterations": 15, "seeds": range(3),
         "progress": False}


@pytest.fixture(scope="module")
def serial(robots):
    return compare(robots["zavar2024"], TARGETS, **SWEEP)


def test_table_has_one_row_per_solve_with_reference_rows(serial):
    """Exact methods give one row per target; the closed form comes along as reference.

    Population methods give one row per (population, seed, target).
    """
    assert list(serial.columns) == COLUMNS
    assert sorted(serial["method"].unique()) == ["analytic", "ipopt", "pso"]
    assert len(serial) == 2 * len(TARGETS) + 3 * len(TARGETS)
    unreachable = serial[serial["target"] == 1]
    assert (unreachable["status"] == "unreachable").all()
    assert (unreachable["reason"] == "height_out_of_stroke").all()
    exact = unreachable[unreachable["method"] != "pso"]
    assert np.allclose(exact["abs_err_z"], 0.102, atol=1e-3)


def test_process_pool_gives_the_serial_numbers(robots, serial):
    """A process pool reproduces the serial table exactly (times aside), PSO's seeds included.

    Mutation caught: a pool job that ignores its seed (every job seeded 0) -> the PSO rows
    of seeds 1 and 2 differ from the serial run's.
    """
    assert serial[serial["method"] == "pso"]["seed"].nunique() == 3
    pso = serial[serial["method"] == "pso"]
    assert pso.groupby("target")["error"].nunique().max() > 1  # the seeds do change results
    with ProcessPoolExecutor(2) as pool:
        par = compare(robots["zavar2024"], TARGETS, executor=pool, **SWEEP)
    assert par[SAME].equals(serial[SAME])


def test_dask_local_cluster_gives_the_serial_numbers(robots, serial):
    """A dask.distributed LocalCluster's executor reproduces the serial table exactly.

    Mutation caught: as for the process pool (a job that ignores its seed).
    """
    distributed = pytest.importorskip("distributed", reason="pip install 'scara-opt[dask]'")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        par = compare(robots["zavar2024"], TARGETS, executor=client.get_executor(), **SWEEP)
    assert par[SAME].equals(serial[SAME])


def test_summary_and_convergence(serial):
    """summarize gives medians and the share within tol; convergence one curve per method."""
    summary = summarize(serial, tol=1e-6)
    row = summary[summary["method"] == "ipopt"].iloc[0]
    assert row["within_tol"] == pytest.approx(2 / 3) and row["solves"] == 3
    curves = convergence(serial)
    assert ("ipopt", None) in curves and np.all(np.diff(curves[("ipopt", None)]) <= 0)


def test_rank_methods_lets_time_break_ties_only():
    """Share within tol first, then (reproducible) evaluations; time only on an exact tie."""
    summary = pd.DataFrame({
        "method": ["ca", "ca", "ga", "pso", "gwo"], "population": [20, 40, 20, 20, 20],
        "within_tol": [1.0, 1.0, 1.0, 1.0, 0.5], "evaluations": [900, 1100, 800, 1000, 10],
        "time_s": [0.001, 0.001, 0.009, 0.002, 0.0001]})
    ranked = rank_methods(summary)
    assert list(ranked.index) == ["ga", "ca", "pso", "gwo"]
    assert ranked.loc["ca", "evals"] == 1000 and ranked.loc["ca", "rate"] == 1.0
    tie = summary.assign(evaluations=1000)
    assert list(rank_methods(tie).index) == ["ca", "pso", "ga", "gwo"]


def test_compare_refuses_bad_input(robots):
    """No targets, unknown methods, bad options or budgets raise specific errors."""
    robot = robots["zavar2024"]
    with pytest.raises(so.InputError, match="at least one target"):
        compare(robot, [], progress=False)
    with pytest.raises(so.UnknownSolverError):
        compare(robot, TARGETS, methods=["nope"], progress=False)
    with pytest.raises(so.SolverOptionError):
        compare(robot, TARGETS, methods=["ipopt"], options={"ipopt": {"bogus": 1}},
                progress=False)
    with pytest.raises(so.InputError, match="positive"):
        compare(robot, TARGETS, methods=["ipopt"], iterations=0, progress=False)
    with pytest.raises(so.InputError, match="at least one method"):
        compare(robot, TARGETS, methods=[], reference=False, progress=False)
    with pytest.raises(so.InputError, match="seed must be a non-negative integer"):
        compare(robot, TARGETS, methods="pso", seeds=[-1], progress=False)
    with pytest.raises(so.InputError, match="memeplex"):  # before any solve, not halfway
        compare(robot, TARGETS, methods=["pso", "sfla"], populations=[10, 2], progress=False)


def test_a_single_method_name_is_one_method(robots):
    """methods="pso" is the PSO method (plus the references), not the letters p, s, o."""
    table = compare(robots["zavar2024"], TARGETS[:1], methods="pso", populations=[10],
                    iterations=5, seeds=[0], progress=False)
    assert sorted(table["method"].unique()) == ["analytic", "ipopt", "pso"]


def test_all_methods_budgets_only_the_population_methods(robots):
    """methods="all": exact and fast methods run once per target, metaheuristics per seed."""
    table = so.compare(robots["zavar2024"], TARGETS[:1], methods="all", populations=[20],
                       iterations=3, seeds=[0, 1], progress=False)
    counts = table.groupby("method").size().to_dict()
    assert set(counts) == set(so.solvers())
    for method in ("analytic", "auto", "ipopt", "lm"):
        assert counts[method] == 1 and table[table["method"] == method]["success"].all()
    assert all(counts[m] == 2 for m in counts if m not in ("analytic", "auto", "ipopt", "lm"))
