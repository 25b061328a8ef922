"""compare() on 1,000+ solves: serially, on a dask cluster of 2 worker processes, in a pool.

The sweep: PSO and GWO at populations 20 and 40, 40 iterations, 250 seeds, one reachable
target of zavar2024 (1,002 solves with the two exact reference rows; each ~5-7 ms). Run
serially, then on a ``dask.distributed.LocalCluster`` of 2 worker processes (1 thread each)
through ``client.get_executor()``, once as ``compare`` batches the jobs (the default) and
once with ``chunksize=1`` (one future per solve, as before the batching), and in a
``ProcessPoolExecutor(2)``. The workers are warmed first; then the four runs go in
interleaved rounds, each run's best time counted (a busy spell of the shared machine
falls on all of them). Every table must equal the serial one, bit for bit (times aside).
Ratios: serial time / executor time (above 1: the executor pays).

Wall clock on a shared 2-core machine: compare the ratios within one run.

Usage: ``python benchmarks/bench_dask.py [--seeds 250] [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any

import pandas as pd

import scara_opt as so
from scara_opt.comparison import COLUMNS, compare

TARGET = (0.3, 0.1, -0.07)
SAME = [c for c in COLUMNS if c not in ("time_s", "setup_s", "history")]


def _sweep(seeds: int) -> dict[str, Any]:
    return {"methods": ["pso", "gwo"], "populations": [20, 40], "iterations": 40,
            "seeds": range(seeds), "progress": False}


def _time(robot: so.Robot, executor: Executor | None, sweep: dict[str, Any],
          chunksize: int | None = None) -> tuple[float, pd.DataFrame]:
    t = time.perf_counter()
    table = compare(robot, [TARGET], executor=executor, chunksize=chunksize, **sweep)
    return time.perf_counter() - t, table


def main() -> None:
    """Print the table of times and ratios; fail if any executor's numbers differ."""
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=250)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    robot = so.load_robot("zavar2024")
    sweep = _sweep(args.seeds)
    compare(robot, [TARGET], **{**sweep, "seeds": range(2)})  # build and load once here
    names = ["serial", "dask, 2 workers, batched", "dask, 2 workers, 1 solve a future",
             "process pool of 2, batched"]
    best = dict.fromkeys(names, float("inf"))
    tables: dict[str, pd.DataFrame] = {}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client, \
            ProcessPoolExecutor(2) as pool:
        ex = client.get_executor()
        runs = {names[0]: (None, None), names[1]: (ex, None), names[2]: (ex, 1),
                names[3]: (pool, None)}
        compare(robot, [TARGET], executor=ex, **{**sweep, "seeds": range(8)})  # warm workers
        compare(robot, [TARGET], executor=pool, **{**sweep, "seeds": range(8)})
        for _ in range(args.rounds):  # interleaved: a busy spell of the machine hits all
            for name, (executor, chunksize) in runs.items():
                seconds, tables[name] = _time(robot, executor, sweep, chunksize)
                best[name] = min(best[name], seconds)
    serial = tables[names[0]]
    print(f"{len(serial)} solves (PSO and GWO, populations 20 and 40, 40 iterations, "
          f"{args.seeds} seeds, + 2 exact); best of {args.rounds} interleaved rounds")
    print(f"{'run':<36}{'time [s]':>10}{'serial / run':>14}  same numbers")
    for name in names:
        same = tables[name][SAME].equals(serial[SAME])
        print(f"{name:<36}{best[name]:>10.2f}{best[names[0]] / best[name]:>14.2f}  {same}")
        assert same, name


if __name__ == "__main__":
    main()
