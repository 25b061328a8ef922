"""compare(): one table for every method, identical numbers serially, in a pool, on dask."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

import scara_opt as so
from scara_opt.comparison import COLUMNS, compare, convergence, rank_methods, summarize
from tests.conftest import run_cli

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


@pytest.fixture(scope="module")
def cluster():
    """A real dask scheduler with two worker processes on 127.0.0.1 (closed after the module)."""
    distributed = pytest.importorskip("distributed", reason="pip install 'scara-opt[dask]'")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0",
                                  timeout=120) as local:
        yield local


def test_dask_local_cluster_gives_the_serial_numbers(robots, serial, cluster):
    """A dask.distributed LocalCluster's executor reproduces the serial table exactly.

    Mutation caught: as for the process pool (a job that ignores its seed).
    """
    from distributed import Client

    with Client(cluster, timeout=120) as client:
        par = compare(robots["zavar2024"], TARGETS, executor=client.get_executor(), **SWEEP)
    assert par[SAME].equals(serial[SAME])


def test_the_cli_finishes_on_a_real_dask_cluster_with_the_serial_numbers(cluster, tmp_path):
    """``scara-opt compare --dask tcp://ADDRESS`` against a scheduler and two workers: exit 0,
    the files written, runs.csv equal to a serial run's but for the times (it crashed with
    ``ClientExecutor.shutdown() got an unexpected keyword argument 'cancel_futures'``, exit
    1, --out empty).

    Mutation caught: ``shutdown(cancel_futures=True)`` on the dask executor again -> exit 1.
    """
    base = ["compare", "zavar2024", "--target", "0.3", "0.1", "-0.07", "--methods", "pso",
            "--populations", "8", "--iterations", "10", "--seeds", "6"]
    runs = {}
    for name, extra in (("dask", ["--dask", cluster.scheduler_address]), ("serial", [])):
        out = run_cli(*base, *extra, "--out", str(tmp_path / name), timeout=600)
        assert out.returncode == 0, out.stderr
        assert "Traceback" not in out.stderr
        runs[name] = pd.read_csv(tmp_path / name / "runs.csv")
    keep = [c for c in runs["serial"].columns if not c.startswith(("time_s", "setup_s"))]
    assert len(runs["dask"]) == 8 and runs["dask"][keep].equals(runs["serial"][keep])


def test_the_cli_closes_its_dask_client(cluster):
    """The command line's dask client is closed when compare ends, even by an error.

    Mutation caught: ``client.close()`` removed from ``cli.compare._executor`` -> status "running".
    """
    import argparse

    from scara_opt.cli.compare import _executor

    args = argparse.Namespace(dask=cluster.scheduler_address, workers=1)
    with pytest.raises(ZeroDivisionError), _executor(args) as executor:
        client = executor._client
        assert client.status == "running"
        raise ZeroDivisionError
    assert client.status == "closed"


class _CountingPool(ThreadPoolExecutor):
    """A thread pool that counts the futures submitted to it."""

    def __init__(self, workers: int) -> None:
        super().__init__(workers)
        self.submitted = 0

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        self.submitted += 1
        return super().submit(fn, *args, **kwargs)


def test_jobs_go_to_an_executor_in_batches_with_the_serial_numbers(robots):
    """40 solves on 2 workers go out as 8 batches (4 per worker; one future per ~6 ms solve
    made dask slower than serial), dealt in turn; ``chunksize=1`` sends one per solve;
    the numbers equal the serial ones either way.

    Mutation caught: one future per job again (``chunksize`` ignored) -> 40 futures; fails.
    """
    args = dict(methods=["pso"], populations=[6], iterations=4, seeds=range(40),
                progress=False, reference=False)
    serial = compare(robots["zavar2024"], TARGETS[:1], **args)
    for chunksize, futures in ((None, 8), (1, 40), (15, 3)):
        with _CountingPool(2) as pool:
            table = compare(robots["zavar2024"], TARGETS[:1], executor=pool,
                            chunksize=chunksize, **args)
        assert pool.submitted == futures
        assert table[SAME].equals(serial[SAME])
    with pytest.raises(so.InputError, match="chunksize must be a positive integer"):
        compare(robots["zavar2024"], TARGETS[:1], chunksize=0, **args)


def test_batches_are_dealt_in_turn_and_capped():
    """Batches hold every job once, in turn (k mod n); at most MAX_BATCH jobs each."""
    from scara_opt.comparison import MAX_BATCH, batches

    jobs = list(range(1000))
    dealt = batches(jobs, 2)  # type: ignore[arg-type]
    assert sorted(j for b in dealt for j in b) == jobs
    assert dealt[0][:3] == [0, len(dealt), 2 * len(dealt)]
    assert max(len(b) for b in dealt) <= MAX_BATCH and len(dealt) == 1000 // MAX_BATCH
    assert len(batches(jobs[:5], 4)) == 5  # never an empty batch


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


# ---------------------------------------------------------------------- argument types
@pytest.mark.parametrize("kwargs, match", [
    (dict(targets=None), "targets must be a list"),
    (dict(targets=5), "targets must be a list"),
    (dict(methods=None), "methods must be 'all', a method name or a list"),
    (dict(methods=[1]), "methods must be"),
    (dict(methods=["pso", "pso"]), r"methods lists \['pso'\] more than once"),
    (dict(populations=["a"]), r"each population must be a positive integer; got 'a' \(str\)"),
    (dict(populations=[10, 10]), r"populations lists \[10\] more than once"),
    (dict(populations=10), "populations must be a list"),
    (dict(seeds="0"), "seeds must be a list"),
    (dict(seeds=[1, 1]), r"seeds lists \[1\] more than once"),
    (dict(iterations="5"), "iterations must be a positive integer"),
    (dict(progress="yes"), "progress must be True or False"),
    (dict(reference="no"), "reference must be True or False"),
    (dict(options="ipopt"), "options must be a dict"),
    (dict(options={"ipotp": {"restarts": 2}}), r"options are given for \['ipotp'\]"),
    (dict(executor="pool"), r"executor must be a concurrent.futures.Executor .*'pool' \(str\)"),
])
def test_compare_type_checks_every_argument(robots, kwargs, match):
    """Wrong types raised AttributeError/TypeError; a misspelt options key and a repeated
    method, population or seed were silently ignored or repeated.

    Mutation: compare without the executor check ('str' has no attribute 'submit') and
    with options for unknown methods ignored -> fails.
    """
    args = dict(targets=TARGETS[:1], methods=["pso"], populations=[5], iterations=2,
                seeds=[0], progress=False, reference=False)
    with pytest.raises(so.InputError, match=match):
        compare(robots["zavar2024"], **{**args, **kwargs})


@pytest.mark.parametrize("name", ["seeds", "populations"])
def test_a_0d_array_of_seeds_or_populations_is_an_input_error(robots, name):
    """``seeds=np.array(5)`` raised a bare TypeError ("iteration over a 0-d array").

    Mutation caught: _listed without its ``ndim == 0`` refusal -> TypeError, not InputError.
    """
    with pytest.raises(so.InputError, match=f"{name} must be a list"):
        compare(robots["zavar2024"], TARGETS[:1], methods=["pso"], iterations=2,
                progress=False, reference=False, **{name: np.array(5)})


def test_compare_refuses_a_robot_name(robots):
    """A robot name is answered with the call that loads it."""
    with pytest.raises(so.InputError, match=r"so.load_robot\('zavar2024'\)"):
        compare("zavar2024", TARGETS, progress=False)


def test_an_explicit_method_that_does_not_apply_raises(arm6):
    """compare(arm6, methods=["analytic"]) silently dropped the method; now it says why.

    The reference rows (and methods="all") still skip the closed form quietly.
    Mutation: the explicit list filtered silently as before -> fails.
    """
    with pytest.raises(so.InputError, match="'analytic' was asked for.*SCARA-type"):
        compare(arm6, [[0.3, 0.0, 0.3]], methods=["analytic", "lm"], progress=False)
    table = compare(arm6, [[0.3, 0.0, 0.3]], methods=["lm"], progress=False)
    assert sorted(table["method"].unique()) == ["ipopt", "lm"]


def test_a_shut_down_executor_is_an_input_error(robots):
    """submit() on a shut-down pool raised RuntimeError; now the message says what to do.

    Mutation: _submit without its RuntimeError branch -> fails.
    """
    from concurrent.futures import ThreadPoolExecutor

    pool = ThreadPoolExecutor(1)
    pool.shutdown()
    with pytest.raises(so.InputError, match="shut down or broken; pass a running executor"):
        compare(robots["zavar2024"], TARGETS[:1], methods=["lm"], executor=pool,
                progress=False)


@pytest.mark.parametrize("kwargs, match", [
    (dict(seeds=range(10**30)), r"seeds has more than .* entries"),
    (dict(populations=range(1, 10**12)), r"populations has more than .* entries"),
    (dict(iterations=10**30), r"would need about .* history of iterations \+ 1 costs"),
])
def test_absurd_job_lists_are_refused_before_they_are_built(robots, kwargs, match):
    """range(10**30) seeds raised OverflowError/MemoryError while being listed.

    Mutation: _listed reads the whole iterable with list() -> fails.
    """
    with pytest.raises(so.InputError, match=match):
        compare(robots["zavar2024"], TARGETS, methods=["pso"], progress=False, **kwargs)


def test_the_job_memory_estimate_counts_every_solve(robots, monkeypatch):
    """targets x (exact methods + population methods x populations x seeds) solves.

    3 x (2 + 2 x 2) = 18 solves of 3000 + 8 x (2 + 1) B each: 53.2 KiB.
    Mutation: compare without _check_memory (the table is built whatever its size) -> fails.
    """
    from scara_opt import checks

    monkeypatch.setattr(checks, "MAX_BYTES", 50_000)
    with pytest.raises(so.InputError, match=r"compare \(18 solves\) would need about 53.2 KiB"):
        compare(robots["zavar2024"], TARGETS, methods=["pso"], populations=[5, 6],
                seeds=[0, 1], iterations=2, progress=False)
