"""The first solve of a fresh process, per bundled robot and task kind (issue 18: <= 50 ms).

Each cell is a new Python process (``subprocess``) that imports scara_opt, loads the robot
(timed apart) and then times its first :func:`scara_opt.solve_ik` (default method) and a
second one on another target (the warm baseline, measured in the same process). Two
passes: with the machine's cache folder as it is (compiled FK and NLPs reused across
processes; a cell whose Functions were never compiled on this machine compiles them
here: run twice for the warm figures), and with an empty cache folder per cell
(``SCARA_OPT_CACHE`` set to a new temporary folder: what the very first run on a machine
pays). Ratios: first / warm.

Usage: python benchmarks/bench_first_call.py [--robots a,b] [--no-cold]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

import scara_opt as so

GOAL_MS = 50.0
KINDS = ("position", "yaw", "rotation")

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
import scara_opt as so
t1 = time.perf_counter()
robot = so.load_robot(sys.argv[1])
t2 = time.perf_counter()
kind = sys.argv[2]
mid = 0.5 * (robot.lower + robot.upper)
qs = [mid + f * (robot.upper - robot.lower) for f in (0.2, -0.15)]
targets = []
for q in qs:
    T = robot.fk(q)
    if kind == "position":
        targets.append(so.Target(T[:3, 3]))
    elif kind == "yaw":
        targets.append(so.Target(T[:3, 3], yaw=float(np.arctan2(T[1, 0], T[0, 0]))))
    else:
        targets.append(so.Target(T[:3, 3], rotation=T[:3, :3]))
out = {"import_ms": (t1 - t0) * 1e3, "load_ms": (t2 - t1) * 1e3}
try:
    t = time.perf_counter()
    r = so.solve_ik(robot, targets[0])
    out["first_ms"] = (time.perf_counter() - t) * 1e3
    t = time.perf_counter()
    so.solve_ik(robot, targets[1])
    out["warm_ms"] = (time.perf_counter() - t) * 1e3
    out["status"] = r.status
except so.errors.ScaraOptError as exc:   # e.g. a yaw target on a robot without a yaw
    out["skip"] = type(exc).__name__
print(json.dumps(out))
"""


def run(robot: str, kind: str, env: dict[str, str]) -> dict:
    """One fresh process: its timings as a dict (or ``skip``)."""
    proc = subprocess.run([sys.executable, "-c", CHILD, robot, kind], env=env,
                          capture_output=True, text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default=",".join(so.list_robots()))
    parser.add_argument("--no-cold", action="store_true", help="skip the empty-cache pass")
    args = parser.parse_args()
    passes = ["machine cache"] + ([] if args.no_cold else ["empty cache"])
    for label in passes:
        print(f"\n{label}: first solve_ik of a fresh process (default method), ms")
        head = (f"{'robot':<10} {'kind':<9} {'import':>7} {'load':>7} {'first':>8} "
                f"{'warm':>7} {'first/warm':>10} {'<=50ms':>6}")
        print(head)
        print("-" * len(head))
        for robot in args.robots.split(","):
            for kind in KINDS:
                env = dict(os.environ)
                if label == "empty cache":  # each cell pays the cold cache
                    env["SCARA_OPT_CACHE"] = tempfile.mkdtemp(prefix="scara_opt_cache_")
                r = run(robot, kind, env)
                if "skip" in r:
                    print(f"{robot:<10} {kind:<9} refused ({r['skip']})")
                    continue
                print(f"{robot:<10} {kind:<9} {r['import_ms']:>7.0f} {r['load_ms']:>7.0f} "
                      f"{r['first_ms']:>8.1f} {r['warm_ms']:>7.2f} "
                      f"{r['first_ms'] / r['warm_ms']:>10.0f} "
                      f"{'yes' if r['first_ms'] <= GOAL_MS else 'NO':>6}", flush=True)


if __name__ == "__main__":
    main()
