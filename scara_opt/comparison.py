"""Fair comparison of IK methods: same robot, same targets, same seeds, one table.

:func:`compare` runs every (method, population, seed, target) combination through the one
registry and returns a pandas DataFrame, one row per solve. Population methods (the
metaheuristics) are swept over ``populations`` and ``seeds``; exact methods (``ipopt``,
``analytic``) run once per target as the reference. Any ``concurrent.futures.Executor``
spreads the jobs (a process pool, or a ``dask.distributed`` client's ``get_executor()``), a
few batches of solves per worker (:func:`batches`: one future per ~6 ms solve would cost
more than the solve); every job carries its own seed, so the numbers equal a serial run's
(except the times).

Times are fair: ``time_s`` is each solve's search alone; the one-off setup a method pays the
first time it meets a robot and task kind in a process (casadi builds, compilation) is its
own column, ``setup_s`` (0 once cached), never inside ``time_s``.
"""

from __future__ import annotations

import itertools
import math
import os
from collections import Counter
from collections.abc import Iterable, Sequence
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from scara_opt import checks
from scara_opt.checks import (
    check_flag,
    check_int,
    check_memory,
    check_options_dict,
    count_text,
    describe,
)
from scara_opt.errors import InputError
from scara_opt.ik.base import check_seed, check_tol
from scara_opt.ik.registry import get_solver, solve_ik, solvers
from scara_opt.ik.result import IKResult
from scara_opt.model.robot import Robot, check_robot
from scara_opt.target import Target, as_target

#: the exact reference methods added to every comparison (``reference=True``)
EXACT_METHODS = ("analytic", "ipopt")

#: batches per worker of an executor (``compare(chunksize=None)``): enough to balance them
BATCHES_PER_WORKER = 4
#: most solves in one batch (``chunksize=None``): ~0.3 s of 6 ms solves
MAX_BATCH = 50

#: estimated memory of one job [bytes]: the job, its IKResult and its table row (measured:
#: 2.4 to 2.8 kB at the peak), plus 8 B per history entry for the population methods
BYTES_PER_JOB = 3000

COLUMNS = ["method", "population", "budget_iterations", "seed", "target", "x", "y", "z",
           "reached_x", "reached_y", "reached_z", "abs_err_x", "abs_err_y", "abs_err_z",
           "yaw_error", "error", "cost", "status",
           "success", "reason", "time_s", "setup_s", "evaluations", "iterations",
           "history_len", "history"]


@dataclass(frozen=True)
class _Job:
    index: int
    method: str
    population: int | None
    iterations: int | None
    seed: int | None
    target_index: int
    target: Target
    options: tuple[tuple[str, Any], ...]


def _run(robot: Robot, job: _Job, tol: float) -> tuple[int, IKResult]:
    """One solve (module-level so that process pools can pickle it)."""
    opts = dict(job.options)
    if job.population is not None:
        opts.update(population=job.population, iterations=job.iterations)
    return job.index, solve_ik(robot, job.target, method=job.method, seed=job.seed, tol=tol,
                               **opts)


def _run_batch(robot: Robot, jobs: list[_Job], tol: float) -> list[tuple[int, IKResult]]:
    """A batch of solves, one after the other (one executor job; module-level to pickle)."""
    return [_run(robot, job, tol) for job in jobs]


def executor_workers(executor: Executor) -> int:
    """How many jobs ``executor`` runs at once: a dask client's threads, a pool's workers.

    Any other executor counts as this machine's cores.
    """
    client = getattr(executor, "_client", None)  # distributed's ClientExecutor
    if client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except (OSError, RuntimeError, ValueError, TimeoutError):
            pass
    workers = getattr(executor, "_max_workers", None)  # concurrent.futures' pools
    return workers if isinstance(workers, int) and workers > 0 else os.cpu_count() or 1


def batches(jobs: list[_Job], workers: int, chunksize: int | None = None) -> list[list[_Job]]:
    """The jobs dealt into batches: one executor job each.

    ``chunksize=None``: :data:`BATCHES_PER_WORKER` batches per worker, none above
    :data:`MAX_BATCH` jobs (a Ctrl-C waits for the batches running). Jobs are dealt in
    turn (job k to batch k mod n), so every batch holds a like mix of methods and
    populations and the workers finish together.
    """
    if chunksize is None:
        n = max(BATCHES_PER_WORKER * workers, math.ceil(len(jobs) / MAX_BATCH))
    else:
        n = math.ceil(len(jobs) / chunksize)
    n = max(1, min(n, len(jobs)))
    return [jobs[k::n] for k in range(n)]


def _row(job: _Job, res: IKResult) -> dict[str, Any]:
    err = np.abs(res.position_error)
    return {
        "method": job.method, "population": job.population, "budget_iterations": job.iterations,
        "seed": job.seed, "target": job.target_index, "x": job.target.position[0],
        "y": job.target.position[1], "z": job.target.position[2],
        **{f"reached_{a}": job.target.position[k] + res.position_error[k]
           for k, a in enumerate("xyz")}, "abs_err_x": err[0],
        "abs_err_y": err[1], "abs_err_z": err[2],
        "yaw_error": math.nan if res.yaw_error is None else res.yaw_error,
        "error": res.error, "cost": res.cost, "status": res.status.value, "success": res.success,
        "reason": res.reason.value, "time_s": res.time_s, "setup_s": res.setup_s,
        "evaluations": res.evaluations, "iterations": res.iterations,
        "history_len": len(res.history), "history": res.history,
    }


def takes_budget(method: str) -> bool:
    """Whether ``method`` is a population method (population, iterations, a seed sweep).

    The others (``ipopt``, ``analytic``, ``lm``, ``auto``, …) run once per target, seed 0.
    """
    return "population" in get_solver(method).defaults


def _jobs(targets: list[Target], methods: Sequence[str], populations: Sequence[int],
          iterations: int, seeds: Sequence[int],
          options: dict[str, dict[str, Any]]) -> list[_Job]:
    jobs: list[_Job] = []
    for method in methods:
        opts = tuple(sorted(options.get(method, {}).items()))
        exact = not takes_budget(method)
        for pop in ([None] if exact else populations):
            for seed in ([0] if exact else seeds):
                for t_idx, target in enumerate(targets):
                    jobs.append(_Job(len(jobs), method, pop, None if exact else iterations,
                                     seed, t_idx, target, opts))
    return jobs


def compare(robot: Robot, targets: Iterable[Target | object], methods: Sequence[str] | str = "all",
            populations: Sequence[int] = (20, 40, 60, 80, 100), iterations: int = 200,
            seeds: Iterable[int] = range(10), executor: Executor | None = None,
            progress: bool = True, tol: float = 1e-9,
            options: dict[str, dict[str, Any]] | None = None,
            reference: bool = True, chunksize: int | None = None) -> pd.DataFrame:
    """Run IK methods over targets, populations and seeds; one DataFrame row per solve.

    Args:
        robot: the robot.
        targets: :class:`Target` objects or (3,) positions [m].
        methods: registry names (a single name is one method), or ``"all"`` for every
            registered solver that applies to the robot (``analytic`` only for SCARA-type
            robots). A method named explicitly that does not apply raises.
        populations: population sizes for the population methods.
        iterations: iteration budget of the population methods.
        seeds: seeds of the population methods (the others run once, seed 0; see
            :func:`takes_budget`).
        executor: any ``concurrent.futures.Executor`` (``None``: run serially here); it must
            be running (not shut down). The jobs go to it in batches (:func:`batches`).
        progress: show a tqdm progress bar.
        tol: residual [m, rad] counted as solved.
        options: extra solver options by method name, e.g. ``{"ipopt": {"restarts": 20}}``;
            every name must be one of the methods compared.
        reference: add the exact methods (``ipopt``, and ``analytic`` where it applies) as
            reference rows even when not listed in ``methods``.
        chunksize: solves per executor job; ``None`` chooses (:func:`batches`: a few
            batches per worker, so a ~6 ms solve does not pay a job's overhead each).

    The jobs are counted before any is built: targets x (exact methods + population
    methods x populations x seeds), each about :data:`BYTES_PER_JOB` plus 8 B per history
    entry; above :data:`scara_opt.checks.MAX_BYTES` the call is refused.

    Returns:
        DataFrame with columns :data:`COLUMNS`: target and reached position [m], per-axis
        absolute error [m], the tool-angle error [rad] (a float column: NaN for a
        position-only target, which has none), error, cost,
        status, time [s], evaluations, iterations, history length and the history itself.

    Raises:
        InputError: a non-Robot, no targets, a malformed ``methods``, a method named twice
            or named explicitly where it does not apply (``analytic`` on a non-SCARA robot),
            empty, repeated or non-integer populations or seeds, a non-positive budget, a
            negative seed, a bad ``tol``, a flag that is not True/False, options for a
            method not compared, an executor without ``submit`` or shut down, a
            ``chunksize`` that is not a positive integer or None, too many jobs
            for :data:`scara_opt.checks.MAX_BYTES`, or an option value a method refuses
            (checked for every method and population before the first solve).
        UnknownSolverError: a method name that is not registered.
        SolverOptionError: an option a method does not accept.
    """
    robot = check_robot(robot)
    if not isinstance(targets, Iterable) or isinstance(targets, (str, bytes, Target)):
        raise InputError(f"targets must be a list of Target or of (3,) positions [m]; got "
                         f"{describe(targets)}")
    target_list = [as_target(t) for t in targets]
    if not target_list:
        raise InputError("compare needs at least one target")
    check_flag("progress", progress)
    check_flag("reference", reference)
    names = _method_names(robot, methods, reference)
    tol = check_tol(tol)
    iterations = check_int("iterations", iterations, 1)
    seed_list = _listed("seeds", seeds, check_seed)
    pop_list = _listed("populations", populations, lambda p: check_int("each population", p, 1))
    if any(takes_budget(m) for m in names) and (not seed_list or not pop_list):
        raise InputError("compare needs at least one seed and one population size")
    options = check_options_dict("options", options)
    stray = sorted(set(options) - set(names))
    if stray:
        raise InputError(f"options are given for {stray}, which are not compared (methods: "
                         f"{names}); fix the name or add the method")
    _check_memory(len(target_list), names, len(pop_list), len(seed_list), iterations)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise InputError(f"executor must be a concurrent.futures.Executor (e.g. "
                         f"ProcessPoolExecutor()) or None; got {describe(executor)}")
    if chunksize is not None:
        chunksize = check_int("chunksize", chunksize, 1)
    for m in names:  # fail fast on names and option values, before the first solve
        budgets = [{"population": p, "iterations": iterations} for p in pop_list] \
            if takes_budget(m) else [{}]
        for budget in budgets:
            solver = get_solver(m, **options.get(m, {}), **budget)
            if hasattr(solver, "check_memory"):  # a metaheuristic's working memory
                solver.check_memory(robot.nq)
    jobs = _jobs(target_list, names, pop_list, iterations, seed_list, options)
    results: dict[int, IKResult] = {}
    bar = _progress(len(jobs), progress)
    try:
        if executor is None:
            for job in jobs:
                idx, res = _run(robot, job, tol)
                results[idx] = res
                bar.update()
        else:
            dealt = batches(jobs, executor_workers(executor), chunksize)
            futures = [_submit(executor, robot, batch, tol) for batch in dealt]
            try:
                for fut in as_completed(futures):
                    done = fut.result()
                    results.update(done)
                    bar.update(len(done))
            except BaseException:  # Ctrl-C or a failed job: the queued jobs are not run
                for fut in futures:
                    fut.cancel()
                raise
    finally:
        bar.close()
    return pd.DataFrame([_row(job, results[job.index]) for job in jobs], columns=COLUMNS)


def _analytic_refusal(robot: Robot) -> str | None:
    """Why the closed form does not apply to ``robot``, or ``None`` when it does."""
    from scara_opt.ik.analytic import NotScaraError, scara_geometry

    try:
        scara_geometry(robot)
    except NotScaraError as exc:
        return str(exc)
    return None


def _method_names(robot: Robot, methods: object, reference: bool) -> list[str]:
    """The methods to run: checked names, explicit ones applicable, references added.

    ``"all"`` and the reference rows skip ``analytic`` silently where it does not apply;
    a method named explicitly must apply.
    """
    if isinstance(methods, str) and methods == "all":
        names = [m for m in solvers() if m != "analytic" or _analytic_refusal(robot) is None]
    else:
        listed = [methods] if isinstance(methods, str) else methods
        if not isinstance(listed, Iterable) or not all(isinstance(m, str) for m in listed):
            raise InputError(f"methods must be 'all', a method name or a list of names "
                             f"({', '.join(solvers())}); got {describe(methods)}")
        names = list(listed)
        twice = sorted(m for m, count in Counter(names).items() if count > 1)
        if twice:
            raise InputError(f"methods lists {twice} more than once; list each method once")
        why = _analytic_refusal(robot) if "analytic" in names else None
        if why is not None:
            raise InputError(f"method 'analytic' was asked for, but the closed form does not "
                             f"apply to robot {robot.name!r}: {why}; drop it from methods")
    if reference:
        names += [m for m in EXACT_METHODS if m not in names
                  and (m != "analytic" or _analytic_refusal(robot) is None)]
    if not names:
        raise InputError("compare needs at least one method; pass methods= or reference=True")
    return names


def _listed(name: str, values: object, check: Any) -> list[Any]:
    """``values`` (any iterable) as a list of checked entries, refused before it gets absurd.

    Raises:
        InputError: not an iterable, longer than any job list that fits in
            :data:`scara_opt.checks.MAX_BYTES`, a repeated entry, or an entry ``check``
            refuses.
    """
    if not isinstance(values, Iterable) or isinstance(values, (str, bytes)):
        raise InputError(f"{name} must be a list (or range) of integers; got {describe(values)}")
    cap = max(checks.MAX_BYTES // BYTES_PER_JOB, 1)
    try:
        size = len(values)  # type: ignore[arg-type]
    except OverflowError:  # e.g. range(10**30)
        size = cap + 1
    except TypeError:  # an iterator: count while reading
        size = 0
    out = list(itertools.islice(values, cap + 1)) if size <= cap else []
    if size > cap or len(out) > cap:
        raise InputError(f"{name} has more than {cap:,} entries ({describe(values)}); every "
                         f"entry adds at least one solve per target, more than "
                         f"{checks.human_bytes(checks.MAX_BYTES)} of results: pass fewer")
    for v in out:
        check(v)
    twice = sorted(v for v, count in Counter(out).items() if count > 1)
    if twice:
        raise InputError(f"{name} lists {twice} more than once; each entry would repeat the "
                         "same solves: list each once")
    return out


def _check_memory(n_targets: int, names: list[str], n_pops: int, n_seeds: int,
                  iterations: int) -> None:
    """Refuse a job list too large for :data:`scara_opt.checks.MAX_BYTES` before building it."""
    budget = [m for m in names if takes_budget(m)]
    jobs = n_targets * (len(names) - len(budget) + len(budget) * n_pops * n_seeds)
    per_job = BYTES_PER_JOB + (8 * (iterations + 1) if budget else 0)
    check_memory(f"compare ({count_text(jobs)} solves)", jobs, per_job,
                 "pass fewer targets, methods, populations or seeds (solves = targets x (exact "
                 "methods + population methods x populations x seeds)), or fewer iterations "
                 "(each solve keeps a history of iterations + 1 costs)")


def _submit(executor: Any, robot: Robot, batch: list[_Job], tol: float) -> Future:
    """Submit one batch; a shut-down (or broken) executor is an InputError, not a RuntimeError."""
    try:
        return executor.submit(_run_batch, robot, batch, tol)
    except RuntimeError as exc:
        raise InputError(f"the executor refused the job ({type(exc).__name__}: {exc}): it is "
                         "shut down or broken; pass a running executor (create it anew, or use "
                         "it inside its with-block), or executor=None") from None


def _progress(total: int, enabled: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(total=total, desc="IK solves", unit="solve", disable=not enabled or total < 2)


def summarize(table: pd.DataFrame, tol: float | None = None) -> pd.DataFrame:
    """Median per (method, population) of per-axis error, error, cost and time.

    ``time_s`` is the median search time (setup excluded); ``setup_s`` the largest one-off
    setup any of the group's solves paid. Adds ``within_tol``, the share of solves reached:
    by default the table's own verdict (``success``, judged at the ``tol`` :func:`compare`
    was given, so one table has one success rate), or with ``tol`` [m, rad] the share
    whose error is at most it: the papers' Table 2 with the success rate they leave out.
    """
    within = table["success"].astype(bool) if tol is None else table["error"] <= check_tol(tol)
    g = table.assign(within_tol=within).groupby(
        ["method", "population"], dropna=False, sort=False)
    out = g.agg(abs_err_x=("abs_err_x", "median"), abs_err_y=("abs_err_y", "median"),
                abs_err_z=("abs_err_z", "median"), error=("error", "median"),
                cost=("cost", "median"), time_s=("time_s", "median"),
                setup_s=("setup_s", "max"),
                evaluations=("evaluations", "median"), within_tol=("within_tol", "mean"),
                solves=("error", "size"))
    return out.reset_index()


#: unit suffixes for CSV files (SI; ``error`` and ``cost`` are in m, or m and rad together
#: when the target has a tool angle)
UNIT_NAMES = {"x": "x_m", "y": "y_m", "z": "z_m", "reached_x": "reached_x_m",
              "reached_y": "reached_y_m", "reached_z": "reached_z_m", "abs_err_x": "abs_err_x_m",
              "abs_err_y": "abs_err_y_m", "abs_err_z": "abs_err_z_m",
              "yaw_error": "yaw_error_rad", "error": "error_m_rad", "cost": "cost_m_rad"}


def with_units(table: pd.DataFrame) -> pd.DataFrame:
    """``table`` (of :func:`compare` or :func:`summarize`) with units in its column names."""
    return table.rename(columns=UNIT_NAMES)


def rank_methods(summary: pd.DataFrame) -> pd.DataFrame:
    """Methods of a :func:`summarize` table, best first: one row each (index: method).

    Columns ``rate`` (mean share within tol), ``evals`` and ``time`` (medians over the
    populations' rows). Sorted by ``rate`` (higher first), then ``evals``, then ``time``:
    for seeded runs the first two are reproducible, so the machine's timing noise only
    breaks exact ties.
    """
    ranked = summary.groupby("method").agg(rate=("within_tol", "mean"),
                                           evals=("evaluations", "median"),
                                           time=("time_s", "median"))
    return ranked.sort_values(["rate", "evals", "time"], ascending=[False, True, True])


def convergence(table: pd.DataFrame) -> dict[tuple[str, Any], np.ndarray]:
    """Median best-cost history per (method, population), padded with each run's last value."""
    curves = {}
    for key, grp in table.groupby(["method", "population"], dropna=False, sort=False):
        hists = [np.asarray(h, float) for h in grp["history"] if len(h)]
        if not hists:
            continue
        n = max(len(h) for h in hists)
        padded = np.array([np.pad(h, (0, n - len(h)), mode="edge") for h in hists])
        pop = None if key[1] is None or (isinstance(key[1], float) and math.isnan(key[1])) \
            else int(key[1])
        curves[(key[0], pop)] = np.median(padded, axis=0)
    return curves
