# ruff: noqa: B023  (the timed lambdas run inside the loop that binds them)
"""FK routes by batch size: the one batch route against the alternatives, measured in one run.

Routes, per robot (the bundled ones and a 7-joint arm, tests/data/panda_dh.urdf) at batch
sizes 1, 60, 100, 1,000 and 60,000:

* ``batch route``: ``Robot.positions`` / ``fk_batch`` (the casadi expression compiled to C
  once per machine and mapped: :mod:`scara_opt.model.batch_fk`);
* ``casadi VM``: the same expression evaluated by casadi's virtual machine (the route's
  fallback where no C compiler works);
* ``numpy walk``: the chain walked with numpy over the whole batch (the route the package
  used before; kept here only as the measured alternative);
* ``pinocchio loop``: one Pinocchio call per configuration;
* baseline: the closed-form numpy FK of zavar2024 (eq. 5 of the paper), same run.

Prints µs per call and ns per configuration; the decision rule is "the batch route is never
slower than the numpy walk and wins at population sizes".
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.model import batch_fk
from scara_opt.model.buffers import FunctionArrays

SIZES = (1, 60, 100, 1000, 60_000)
ARM = Path(__file__).resolve().parent.parent / "tests" / "data" / "panda_dh.urdf"


def best(fn, reps: int) -> float:
    """Best of ``reps`` wall times [s] (shared machines: the least disturbed run)."""
    times = []
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def numpy_walk(robot: so.Robot, Q: np.ndarray) -> np.ndarray:
    """Tip positions (n, 3) by walking the chain with numpy over the batch."""
    n = len(Q)
    R = np.tile(np.eye(3), (n, 1, 1))
    p = np.zeros((n, 3))
    for j in robot.chain:
        p = p + R @ j.placement[:3, 3]
        R = R @ j.placement[:3, :3]
        q = Q[:, j.index] * j.scaling + j.offset if j.mimic else Q[:, j.index]
        if j.kind == "prismatic":
            p = p + (R @ j.axis) * q[:, None]
        else:
            a = j.axis
            K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
            c, s = np.cos(q)[:, None, None], np.sin(q)[:, None, None]
            R = R @ (np.eye(3) + s * K + (1 - c) * (K @ K))
    return p + R @ robot.tip_placement[:3, 3]


def closed_form_zavar(Q: np.ndarray) -> np.ndarray:
    """zavar2024 eq. 5: tip positions (n, 3) [m]; a1 = a2 = 0.2 m, z = -d3 - 0.05 m."""
    t1, t12 = Q[:, 0], Q[:, 0] + Q[:, 1]
    return np.column_stack([0.2 * np.cos(t1) + 0.2 * np.cos(t12),
                            0.2 * np.sin(t1) + 0.2 * np.sin(t12), -Q[:, 2] - 0.05])


def vm_route(robot: so.Robot, n: int):
    """The same positions Function, uncompiled, mapped over ``n`` and evaluated in place."""
    os.environ["SCARA_OPT_NO_COMPILE"] = "1"
    try:
        f = batch_fk._build(robot, "position", "vm_positions")
    finally:
        del os.environ["SCARA_OPT_NO_COMPILE"]
    return FunctionArrays(f.map(n), n)


def main() -> None:
    rng = np.random.default_rng(0)
    robots = [so.load_robot(name) for name in so.list_robots()]
    robots.append(so.Robot.from_urdf(ARM, tip="tool"))
    zavar = so.load_robot("zavar2024")
    Qz = rng.uniform(zavar.lower, zavar.upper, (60_000, 4))
    base = best(lambda: closed_form_zavar(Qz), 5) / len(Qz)
    print(f"baseline: numpy closed form of zavar2024, {base * 1e9:.0f} ns/config (n = 60,000)")
    print(f"{'robot':<10} {'n':>6} | {'batch route':>12} {'casadi VM':>11} {'numpy walk':>11} "
          f"{'pinocchio':>11} | route ns/config  x baseline  numpy/route")
    wins = []
    for robot in robots:
        for n in SIZES:
            Q = rng.uniform(robot.sampling_lower, robot.sampling_upper, (n, robot.nq))
            reps = 200 if n <= 100 else 20 if n <= 1000 else 3
            robot.positions(Q)  # compile or load the route outside the timing
            t_route = best(lambda: robot.positions(Q), reps)
            vm = vm_route(robot, n)
            vm.arg["q"][:] = Q
            t_vm = best(vm, reps)
            t_np = best(lambda: numpy_walk(robot, Q), reps)
            k = min(n, 1000)
            t_pin = best(lambda: [robot.fk(q) for q in Q[:k]], 2) * n / k
            wins.append(t_np / t_route)
            print(f"{robot.name:<10} {n:>6} | {t_route * 1e6:>10.1f}us {t_vm * 1e6:>9.1f}us "
                  f"{t_np * 1e6:>9.1f}us {t_pin * 1e6:>9.0f}us | {t_route / n * 1e9:>14.0f} "
                  f"{t_route / n / base:>11.1f} {t_np / t_route:>12.2f}")
    verdict = "met" if min(wins) >= 1.0 else "NOT met"
    print(f"rule: the batch route never slower than the numpy walk: worst numpy/route "
          f"{min(wins):.2f} ({verdict})")


if __name__ == "__main__":
    main()
