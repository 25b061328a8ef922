"""Workspace speed: 60,000 Monte Carlo samples with FK and the occupancy grid, vs numpy.

Times :func:`scara_opt.workspace_analysis.workspace` (sampling, batch FK, the footprint
check where a robot file declares one, automatic grid, area, ranges) on every bundled robot,
and a plain
numpy baseline measured in the same run: zavar2024's closed-form FK (eq. 5) on the same
number of uniform samples plus ``np.histogram2d`` for the occupied cells. Prints the time
and its ratio to the baseline.
Goals: <= 0.5 s for 60,000 samples on the 4-joint robots (issue 6); every robot <= 1.5x
the baseline of the same run (issue 18).
"""

from __future__ import annotations

import math

import numpy as np
from timing import best_time

import scara_opt as so
from scara_opt.workspace_analysis import workspace

N = 60_000
REPEATS = 11  # the least of these counts (a shared machine: pauses land in single runs)
GOAL_S = 0.5
CELL = 0.01  # baseline grid cell [m]


def baseline_zavar(n: int, seed: int = 0) -> float:
    """zavar2024 by hand: uniform samples, eq. 5 FK, occupied cells by np.histogram2d [m²]."""
    rng = np.random.default_rng(seed)
    lim = math.radians(120)
    t1 = rng.uniform(-lim, lim, n)
    t2 = rng.uniform(-lim, lim, n)
    d3 = rng.uniform(0.0, 0.048, n)
    t12 = t1 + t2
    x = 0.2 * np.cos(t1) + 0.2 * np.cos(t12)
    y = 0.2 * np.sin(t1) + 0.2 * np.sin(t12)
    z = -d3 - 0.05
    bins = (np.arange(x.min(), x.max() + CELL, CELL), np.arange(y.min(), y.max() + CELL, CELL))
    counts, _, _ = np.histogram2d(x, y, bins=bins)
    _ = z.min(), z.max(), np.hypot(x, y).max()
    return float((counts > 0).sum()) * CELL**2


def main() -> None:
    times = {}
    for name in so.list_robots():
        robot = so.load_robot(name)
        times[name] = (robot, best_time(workspace, robot, n=N, seed=0, repeats=REPEATS))
    # after the robots: the first large arrays of a process come slower (the allocator's
    # state), which put 9.4 or 12.5 ms on the same baseline depending on what ran before
    base = best_time(baseline_zavar, N, repeats=REPEATS)
    print(f"baseline: numpy eq. 5 FK + np.histogram2d (zavar2024), N={N}: {base * 1e3:.1f} ms "
          f"(area {baseline_zavar(N):.4f} m^2, plain cell count; timed after the robots)")
    print(f"{'robot':<10} {'nq':>3} {'footprint':>9} {'time [ms]':>10} {'x baseline':>11} "
          f"{'area [m^2]':>11}")
    worst_4, worst_ratio = 0.0, 0.0
    for name, (robot, t) in times.items():
        ws = workspace(robot, n=N, seed=0)
        if robot.nq == 4:
            worst_4 = max(worst_4, t)
        worst_ratio = max(worst_ratio, t / base)
        print(f"{name:<10} {robot.nq:>3} {'yes' if ws.footprint else 'no':>9} {t * 1e3:>10.1f} "
              f"{t / base:>11.2f} {ws.xy_area:>11.4f}")
    verdict = "met" if worst_4 <= GOAL_S else "NOT met"
    print(f"goal <= {GOAL_S} s for {N} samples on the 4-joint robots: slowest "
          f"{worst_4:.3f} s -> {verdict}")
    print(f"goal <= 1.5x the baseline on every robot: worst {worst_ratio:.2f}x -> "
          f"{'met' if worst_ratio <= 1.5 else 'NOT met'}")


if __name__ == "__main__":
    main()
