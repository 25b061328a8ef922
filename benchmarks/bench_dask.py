"""compare() on 1,000+ solves: serially, on a dask cluster of 2 worker processes, in a pool.

The sweep: PSO and GWO at populations 20 and 40, 40 iterations, 250 seeds, one reachable
target of zavar2024 (1,002 solves with the two exact reference rows; each ~5-7 ms). Run
serially, then on a ``dask.distributed.LocalCluster`` of 2 worker processes (1 thread each)
through ``client.get_executor()``, once as ``compare`` batches the jobs (the default) and
once with ``chunksize=1`` (one future per solve, as before the batching), then in a
``ProcessPoolExecutor(2)``. Each executor run is timed twice, the better one counted (the
first warms the workers' caches). Every table must equal the serial one, bit for bit
(times aside). Ratios: serial time / executor time (above 1: the executor pays).

Wall clock on a shared 2-core machine: compare the ratios within one run.

Usage: ``python benchmarks/bench_dask.py [--seeds 250]``.
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


def _timed(robot: so.Robot, executor: Executor | None, sweep: dict[str, Any],
           chunksize: int | None = None, runs: int = 2) -> tuple[float, pd.DataFrame]:
    best, table = float("inf"), None
    for _ in range(runs):
        t = time.perf_counter()
        table = compare(robot, [TARGET], executor=executor, chunksize=chunksize, **sweep)
        best = min(best, time.perf_counter() - t)
    assert table is not None
    return best, table


def main() -> None:
    """Print the table of times and ratios; fail if any executor's numbers differ."""
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=250)
    args = parser.parse_args()
    robot = so.load_robot("zavar2024")
    sweep = _sweep(args.seeds)
    compare(robot, [TARGET], **{**sweep, "seeds": range(2)})  # build and load once here
    serial_s, serial = _timed(robot, None, sweep, runs=1)
    rows = [("serial", serial_s, serial)]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        ex = client.get_executor()
        rows.append(("dask, 2 workers, batched", *_timed(robot, ex, sweep)))
        rows.append(("dask, 2 workers, 1 solve a future", *_timed(robot, ex, sweep, 1)))
    with ProcessPoolExecutor(2) as pool:
        rows.append(("process pool of 2, batched", *_timed(robot, pool, sweep)))
    print(f"{len(serial)} solves (PSO and GWO, populations 20 and 40, 40 iterations, "
          f"{args.seeds} seeds, + 2 exact)")
    print(f"{'run':<36}{'time [s]':>10}{'serial / run':>14}  same numbers")
    for name, seconds, table in rows:
        same = table[SAME].equals(serial[SAME])
        print(f"{name:<36}{seconds:>10.2f}{serial_s / seconds:>14.2f}  {same}")
        assert same, name


if __name__ == "__main__":
    main()
