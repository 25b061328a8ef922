"""Torque-limited toppra against velocity/acceleration-only toppra on the same path, same run.

The path is bench_traj's: zavar2024, a 100-waypoint arc of the reachable circle on one elbow
branch. Per case, the best of REPEATS compute times through ``time_parameterize`` (each
including the 1 kHz RNEA check and any stretch) and the ratio to the vel/acc-only timing
(goal, issue 19: <= 3x), the duration, and the worst torque ratio of ``check_limits()``.

Cases: the robot's own (assumed) limits with torque added at 0 and 2 kg payload, and the
same with the rate limits lifted (vmax = amax = 1e3) so that the torques bind. The inertial
data and torque limits of zavar2024 are estimates (robots/zavar2024.toml).
"""

from __future__ import annotations

import math

from timing import best_time

import scara_opt as so
from scara_opt import paths
from scara_opt.trajectory import ik_path, time_parameterize

REPEATS = 7


def best_ms(fn, *args, **kwargs) -> float:
    """:func:`timing.best_time` of REPEATS runs [ms]."""
    return best_time(fn, *args, repeats=REPEATS, **kwargs) * 1e3
N_WAYPOINTS = 100
GOAL = 3.0


def main() -> None:
    robot = so.load_robot("zavar2024")
    arc = paths.circle((0.0, 0.0), 0.30, -0.07, N_WAYPOINTS, start=math.radians(151),
                       sweep=-math.radians(210))
    path = ik_path(robot, arc)
    cases = {
        "vel/acc only": {},
        "+ torque, 0 kg": {"torque_limits": True},
        "+ torque, 2 kg": {"payload": 2.0},
        "torque-bound, 0 kg": {"vmax": 1e3, "amax": 1e3, "torque_limits": True},
        "torque-bound, 2 kg": {"vmax": 1e3, "amax": 1e3, "payload": 2.0},
    }
    for kwargs in cases.values():  # warm-up (imports, caches)
        time_parameterize(path, robot, **kwargs)
    base = best_ms(time_parameterize, path, robot)
    print(f"zavar2024, {N_WAYPOINTS}-waypoint arc, toppra; compute time best of {REPEATS}")
    print(f"{'case':<22}{'compute [ms]':>14}{'/ vel-acc':>11}{'duration [s]':>14}"
          f"{'max torque ratio':>18}")
    worst = 0.0
    for name, kwargs in cases.items():
        ms = base if not kwargs else best_ms(time_parameterize, path, robot, **kwargs)
        traj = time_parameterize(path, robot, **kwargs)
        ratios = traj.check_limits()
        tau = ratios["torque"].max() if "torque" in ratios else float("nan")
        if "torque_limits" in kwargs or "payload" in kwargs:
            worst = max(worst, ms / base)
        print(f"{name:<22}{ms:>14.1f}{ms / base:>11.2f}{traj.duration:>14.4f}{tau:>18.4f}")
    print(f"worst torque-limited / vel-acc-only compute time: {worst:.2f}x (goal <= {GOAL:g}x: "
          f"{'met' if worst <= GOAL else 'NOT met'})")


if __name__ == "__main__":
    main()
