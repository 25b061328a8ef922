"""IK along a path: the global branch choice against the greedy walk, in the same run.

Prints, for each SCARA with a wrist (zavar2024, fang, peng2025): ``ik_path`` on a
1,000-point arc with ``branches="global"`` (every closed-form solution per point, then
SciPy's Dijkstra over them) and ``branches="greedy"`` (each point from the previous one
by ``auto``), best of REPEATS each, their ratio, and each result's jumps. The arc: 1,000
points, radius 0.30 m (0.25 m for peng2025), 160° about the shoulder axis from -50°, the
tool held at 0.3 rad (position only on zavar2024, whose ±120° wrist cannot hold it all
along); the height in the middle of the robot's stroke.

Goal (issue 31): the global choice on 1,000 points in <= 20 ms.
Also the UR5-class arm of tests/data through its 5 full poses (seed 2, the issue's case):
the global multi-start against greedy, travel and jumps.

Usage: ``python benchmarks/bench_paths.py``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from timing import best_time_and_result

import scara_opt as so
from scara_opt.ik.geometry import scara_geometry

REPEATS = 5
N = 1000
DATA = Path(__file__).resolve().parent.parent / "tests" / "data"


def arc(robot: so.Robot, radius: float, yaw: float | None) -> list[so.Target]:
    """The benchmark's arc about the shoulder axis, at mid-stroke, tool at ``yaw``."""
    g = scara_geometry(robot)
    q_mid = 0.5 * (robot.sampling_lower + robot.sampling_upper)
    z = robot.position(q_mid)[2]
    c = g.base[0] * g.e1 + g.base[1] * g.e2
    return so.paths.circle(c[:2], radius, z, N, start=math.radians(-50),
                           sweep=math.radians(160), yaw=yaw)


def main() -> None:
    print(f"{'robot':<11}{'global [ms]':>13}{'greedy [ms]':>13}{'ratio':>8}  jumps "
          "(global | greedy)")
    worst = 0.0
    for name, radius, yaw in (("zavar2024", 0.30, None), ("fang", 0.30, 0.3),
                              ("peng2025", 0.25, 0.3)):
        robot = so.load_robot(name)
        ts = arc(robot, radius, yaw)
        so.ik_path(robot, ts[:3])  # compiled pieces loaded once, outside the timing
        t_glob, glob = best_time_and_result(so.ik_path, robot, ts, repeats=REPEATS)
        t_greedy, greedy = best_time_and_result(so.ik_path, robot, ts, branches="greedy",
                                                repeats=REPEATS)
        worst = max(worst, t_glob)
        print(f"{name:<11}{t_glob * 1e3:>13.2f}{t_greedy * 1e3:>13.2f}"
              f"{t_glob / t_greedy:>8.3f}  {[j.index for j in glob.jumps]} | "
              f"{[j.index for j in greedy.jumps]} ({int(glob.solved.sum())}/{len(glob)} "
              "solved)")
    print(f"goal: the global choice on {N} points <= 20 ms: worst {worst * 1e3:.2f} ms "
          f"({'met' if worst <= 0.020 else 'NOT met'})")

    arm = so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")
    Q = np.random.default_rng(2).uniform(arm.lower, arm.upper, (5, 6))
    poses = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in map(arm.fk, Q)]
    for branches in ("global", "greedy"):
        t, jp = best_time_and_result(so.ik_path, arm, poses, branches=branches, repeats=3)
        print(f"UR5-class, 5 full poses, {branches:<6}: {t * 1e3:7.1f} ms, travel "
              f"{jp.travel.sum():.2f} rad, {len(jp.jumps)} jumps")


if __name__ == "__main__":
    main()
