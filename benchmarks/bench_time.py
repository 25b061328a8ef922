"""Time-optimal motion in a cell: the duration of our planned PTPs against the MoveIt pipeline.

On the robots, cells and pairs of benchmarks/bench_plan.py (benchmarks/plan_cells.py; pairs
whose straight joint segment collides), per pair:

* **ours, time**: ``so.plan(robot, [PTP(goal)], start=, cell=checker, objective="time")``;
* **ours, length**: the same with ``objective="length"`` (the path short in joint space,
  then toppra);
* **MoveIt's pipeline**: OMPL RRTConnect + PathSimplifier (bench_plan.py's
  ``ompl_baseline``: a Python validity callback, edge resolution 0.01), then toppra along
  the simplified path (``so.time_parameterize``, the same joint limits; where toppra's
  spline through the waypoints leaves the joint limits, through points added near the
  corners, ``scara_opt.motion.clearance.hugging``, as our own timing does).

Printed per robot: solved; the median duration of each, and ours over the pipeline's
(median over pairs of the ratio); ``duration / lower_bound`` of ours (median and
quartiles, max), the bound being the slowest joint's own time-optimal move
(:mod:`scara_opt.trajectory.bound`); median time to plan (ours: the call; the pipeline:
plan + simplify + toppra); and colliding outputs by bench_plan.py's independent dense
check (Pinocchio + coal every 1e-3 rad or m along the timed trajectory).

Run: ``python benchmarks/bench_time.py`` (``--pairs N`` per cell, default 10;
``--robots zavar2024,ur5_dh``; default the three SCARAs and the 6R arm of capsules).
"""

from __future__ import annotations

import argparse
import math
import time

import bench_plan
import numpy as np
from bench_plan import deepest, dense_trajectory, make_pairs, ompl_baseline
from plan_cells import Bench, benches

import scara_opt as so
from scara_opt.errors import NoPathFoundError, TrajectoryError
from scara_opt.motion.clearance import RETRIES, hugging

TIME_LIMIT = bench_plan.TIME_LIMIT
ROBOTS = "zavar2024,irb910sc_like,large_scara,ur5_dh"
#: issue 39's aim: the median per pair of our duration over the pipeline's, per robot
TARGET = 0.80

#: the polyline of bench_plan's last OMPL run (ompl_baseline hands it to path_length)
PIPELINE: list[np.ndarray] = []
_length = bench_plan.path_length


def _recorded_length(Q: np.ndarray) -> float:
    PIPELINE.append(Q)
    return _length(Q)


bench_plan.path_length = _recorded_length


def ours(bench: Bench, checker: so.CollisionChecker, a: np.ndarray, b: np.ndarray,
         seed: int, objective: str) -> dict:
    t = time.perf_counter()
    try:
        traj = so.plan(bench.robot, [so.PTP(b)], start=a, cell=checker, time_limit=TIME_LIMIT,
                       seed=seed, objective=objective, **bench.plan)
    except (NoPathFoundError, TrajectoryError):
        return {"solved": False, "time": time.perf_counter() - t}
    return {"solved": True, "time": time.perf_counter() - t, "duration": traj.duration,
            "bound": traj.lower_bound, "depth": deepest(checker, dense_trajectory(traj))}


def pipeline(bench: Bench, checker: so.CollisionChecker, a: np.ndarray, b: np.ndarray,
             seed: int) -> dict:
    PIPELINE.clear()
    row = ompl_baseline(bench, checker, a, b, seed)
    if not row["solved"]:
        return row
    t = time.perf_counter()
    for level in range(RETRIES + 1):  # a spline that leaves the joint limits: closer points
        try:
            traj = so.time_parameterize(hugging(PIPELINE[-1], level), bench.robot,
                                        **bench.plan)
            break
        except TrajectoryError:
            if level == RETRIES:
                return {"solved": False, "time": row["time"] + time.perf_counter() - t}
    row["time"] += time.perf_counter() - t
    row.update(duration=traj.duration, depth=deepest(checker, dense_trajectory(traj)))
    return row


def _q(x: list[float], p: float) -> float:
    return float(np.percentile(x, p)) if x else math.nan


def report(name: str, rows: dict[str, list[dict]]) -> None:
    t, ln, mv = rows["time"], rows["length"], rows["moveit"]
    every = [k for k in range(len(t)) if t[k]["solved"] and ln[k]["solved"]
             and mv[k]["solved"]]

    def med(r: list[dict], key: str) -> float:
        return _q([r[k][key] for k in every], 50)

    def per_pair(r: list[dict], key: str) -> float:
        return _q([r[k][key] / mv[k]["duration"] for k in every], 50)

    ratio = [t[k]["duration"] / t[k]["bound"] for k in range(len(t)) if t[k]["solved"]]
    lratio = [ln[k]["duration"] / ln[k]["bound"] for k in range(len(ln)) if ln[k]["solved"]]
    slower = sum(t[k]["duration"] > ln[k]["duration"] * (1 + 1e-9) for k in every)
    longest = "/".join(f"{max((x['time'] for x in r), default=math.nan):.2f}"
                       for r in (t, ln, mv))
    print(f"{name:<15}{sum(r['solved'] for r in t):>3}/{sum(r['solved'] for r in ln):>3}/"
          f"{sum(r['solved'] for r in mv):>3} of {len(t):<4}"
          f"{med(t, 'duration'):>7.3f}{med(ln, 'duration'):>7.3f}{med(mv, 'duration'):>7.3f}"
          f"{per_pair(t, 'duration'):>7.3f}{per_pair(ln, 'duration'):>7.3f}"
          f"{per_pair(t, 'bound'):>7.3f}   {_q(ratio, 50):.3f} [{_q(ratio, 25):.2f}, "
          f"{_q(ratio, 75):.2f}, max {max(ratio, default=math.nan):.2f}] {_q(lratio, 50):>6.3f}"
          f"{med(t, 'time') * 1e3:>8.1f}{med(ln, 'time') * 1e3:>8.1f}"
          f"{med(mv, 'time') * 1e3:>8.1f}  {longest:<15}"
          f"{sum(r['solved'] and r['depth'] > 0 for r in t)}/"
          f"{sum(r['solved'] and r['depth'] > 0 for r in ln)}/"
          f"{sum(r['solved'] and r['depth'] > 0 for r in mv)}{slower:>4}")


def verdict(name: str, rows: dict[str, list[dict]]) -> None:
    """Whether the robot meets :data:`TARGET`, and whether any planner could on these pairs.

    Every answer lasts at least its pair's lower bound, so each pair's duration over the
    pipeline's is at least the bound over it, and so is their median (the median is
    monotone): where the median of bound / pipeline exceeds the target, no planner meets it.
    """
    t, mv = rows["time"], rows["moveit"]
    every = [k for k in range(len(t)) if t[k]["solved"] and mv[k]["solved"]]
    ours = _q([t[k]["duration"] / mv[k]["duration"] for k in every], 50)
    floor = [t[k]["bound"] / mv[k]["duration"] for k in every]
    least, below = _q(floor, 50), sum(f <= TARGET for f in floor)
    print(f"{name:<15}time / pipeline {ours:.3f}: {'meets' if ours <= TARGET else 'misses'} "
          f"{TARGET:g}; the bound within {TARGET:g} x the pipeline on {below} of "
          f"{len(floor)} pairs, bound / pipeline {least:.3f}: "
          + ("no planner can meet it on these pairs" if least > TARGET else
             "not ruled out by the bound"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=10, help="pairs per cell (10)")
    parser.add_argument("--robots", default=ROBOTS, help=f"robots to run ({ROBOTS})")
    parser.add_argument("--cells", default="", help="cells to run (default: all)")
    args = parser.parse_args()
    chosen = set(filter(None, args.robots.split(",")))
    cells = set(filter(None, args.cells.split(",")))
    by_robot: dict[str, dict[str, list[dict]]] = {}
    print(f"{args.pairs} pairs per cell, {TIME_LIMIT:g} s limit. Columns: solved (time / "
          "length / MoveIt pipeline); median duration [s] of each on the pairs all three "
          "solve; the median per pair of ours over the pipeline's (time, length) and of the "
          "lower bound over the pipeline's (the best any planner could do); duration / lower "
          "bound of ours, time: median [quartiles, max], and length: median; median time to "
          "a timed trajectory [ms] on those pairs (time, length, pipeline: plan + simplify + "
          "toppra); longest call [s] (time/length/pipeline); colliding outputs "
          "(time/length/pipeline); pairs where time is slower than length")
    for bench in benches():
        if bench.robot_name not in chosen or (cells and bench.cell_name not in cells):
            continue
        checker = so.CollisionChecker(bench.robot, bench.cell, **bench.checker)
        pairs = make_pairs(bench.robot, checker, args.pairs, seed=7)
        rows = by_robot.setdefault(bench.robot_name, {"time": [], "length": [], "moveit": []})
        mine: dict[str, list[dict]] = {"time": [], "length": [], "moveit": []}
        for seed, (a, b) in enumerate(pairs):
            for objective in ("time", "length"):
                mine[objective].append(ours(bench, checker, a, b, seed, objective))
            mine["moveit"].append(pipeline(bench, checker, a, b, seed))
        for key, value in mine.items():
            rows[key].extend(value)
        report(f"{bench.robot_name[:6]}/{bench.cell_name}", mine)
    print("\nper robot")
    for name, rows in by_robot.items():
        report(name, rows)
    print(f"\nthe target, {TARGET:g} x the pipeline's duration (median per pair)")
    for name, rows in by_robot.items():
        verdict(name, rows)
    every = [r for rows in by_robot.values() for r in rows["time"] if r["solved"]]
    ratio = [r["duration"] / r["bound"] for r in every]
    print(f"all pairs: duration / lower bound (time) median {_q(ratio, 50):.3f}, deciles "
          + ", ".join(f"{_q(ratio, p):.2f}" for p in range(10, 100, 10))
          + f", max {max(ratio, default=math.nan):.2f}; at the bound (<= 1 + 1e-6): "
          f"{sum(x <= 1 + 1e-6 for x in ratio)} of {len(ratio)}")


if __name__ == "__main__":
    main()
