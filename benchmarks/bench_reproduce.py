"""Wall time of ``scara-opt reproduce all --quick`` (issue 18: <= 15 s), and of the full run.

Runs the CLI in a fresh process into a temporary folder and prints its wall time, each
paper's own time (from the CLI's per-paper lines) and, as the baseline measured in the same
run, a fresh process that only imports scara_opt (what every command pays before working).
Each run twice: with the CLI's default ``--jobs`` (the papers in two processes on two cores
or more; a paper's time is then its worker's) and with ``--jobs 1`` (one after the other).
``--full`` also times ``reproduce all`` without ``--quick``.

Usage: python benchmarks/bench_reproduce.py [--full]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

GOAL_QUICK_S = 15.0
PAPER_LINE = re.compile(r"^(\w+): .*\(([\d.]+) s\)$")


def timed(cmd: list[str]) -> tuple[float, str]:
    """Wall time [s] and stdout of one fresh process."""
    env = dict(os.environ, MPLBACKEND="Agg")
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return time.perf_counter() - start, proc.stdout


def reproduce(quick: bool, jobs: list[str]) -> tuple[float, dict[str, float]]:
    """Wall time [s] of ``reproduce all`` (``jobs``: extra CLI arguments) and each paper's [s]."""
    with tempfile.TemporaryDirectory(prefix="scara_opt_reproduce_") as out:
        cmd = [sys.executable, "-m", "scara_opt.cli", "reproduce", "all", "--out", out, *jobs]
        wall, stdout = timed(cmd + (["--quick"] if quick else []))
    papers = {m[1]: float(m[2]) for line in stdout.splitlines()
              if (m := PAPER_LINE.match(line.strip()))}
    return wall, papers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="also time the full run")
    args = parser.parse_args()
    base = min(timed([sys.executable, "-c", "import scara_opt"])[0] for _ in range(3))
    print(f"baseline: a fresh process importing scara_opt: {base:.2f} s")
    runs = [("--quick", True)] + ([("full", False)] if args.full else [])
    for (label, quick), jobs in ((run, jobs) for run in runs for jobs in ([], ["--jobs", "1"])):
        wall, papers = reproduce(quick, jobs)
        goal = (f"  goal <= {GOAL_QUICK_S:g} s: {'met' if wall <= GOAL_QUICK_S else 'NOT met'}"
                if quick else "")
        print(f"reproduce all {label} {' '.join(jobs) or '(default --jobs)'}: {wall:.1f} s wall "
              f"({wall / base:.0f}x the import){goal}")
        for paper, seconds in papers.items():
            print(f"  {paper:<10} {seconds:8.1f} s")


if __name__ == "__main__":
    main()
