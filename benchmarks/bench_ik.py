"""Exact IK speed: IPOPT (cold and warm-started), closed form (single and batch), vs SciPy.

Baseline measured in the same run on the same targets: ``scipy.optimize.least_squares``
(trust-region reflective, bounds = joint limits, Pinocchio Jacobian) from the same start.
Goals (issue: exact IK) on the 4-joint robots: IPOPT median <= 2 ms per solve, warm-started
<= 1 ms; closed-form batch >= 1,000,000 targets/s. Trust issue: IPOPT alone (``polish=False``,
no help from the fast solver) within 1e-10 on >= 99.9 % of the targets (1000 with the
default size).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.optimize import least_squares

import scara_opt as so
from scara_opt.ik.analytic import solve_batch
from scara_opt.ik.base import default_q0

N = 1000 if "--quick" not in sys.argv else 50
ROBOTS = ["zavar2024", "fang", "peng2025"]


def timed(fn, items) -> tuple[np.ndarray, list]:
    """Per-item wall times [s] and results."""
    times, out = [], []
    for item in items:
        t = time.perf_counter()
        out.append(fn(item))
        times.append(time.perf_counter() - t)
    return np.array(times), out


def scipy_solve(robot: so.Robot, p: np.ndarray, q0: np.ndarray):
    """Baseline: bounded least squares on the position residual, Pinocchio Jacobian."""
    return least_squares(lambda q: robot.position(q) - p, q0, jac=lambda q: robot.jacobian(q)[:3],
                         bounds=(robot.lower, robot.upper), xtol=1e-15, ftol=1e-15, gtol=1e-15)


def row(label: str, t: np.ndarray, ok: float, base: float) -> str:
    med = np.median(t)
    return (f"  {label:<30} median {med * 1e3:8.3f} ms  p95 {np.percentile(t, 95) * 1e3:8.3f} ms"
            f"  solved {ok:6.1%}  x scipy {med / base:6.2f}")


def main() -> None:
    rng = np.random.default_rng(0)
    for name in ROBOTS:
        bench_robot(name, rng)


def bench_robot(name: str, rng: np.random.Generator) -> None:
    """Time every route on one robot and print its rows."""
    robot = so.load_robot(name)
    Q = rng.uniform(robot.lower, robot.upper, (N, robot.nq))
    P = robot.positions(Q)
    q_start = default_q0(robot)
    so.solve_ik(robot, P[0], method="ipopt")  # build and cache the NLP outside the timing
    t_sp, res_sp = timed(lambda p: scipy_solve(robot, p, q_start), P)
    ok_sp = np.mean([np.linalg.norm(robot.position(r.x) - p) <= 1e-9
                     for r, p in zip(res_sp, P, strict=True)])
    base = float(np.median(t_sp))
    t_cold, res_cold = timed(lambda p: so.solve_ik(robot, p, method="ipopt"), P)
    # warm: start from the solution of a neighbour 1 mm away (a path's previous point)
    neigh = [so.solve_ik(robot, p + [0.001, 0, 0], method="ipopt").q for p in P]
    t_warm, res_warm = timed(lambda k: so.solve_ik(robot, P[k], q0=neigh[k], method="ipopt"),
                             range(N))
    t_alone, res_alone = timed(lambda p: so.solve_ik(robot, p, method="ipopt", polish=False), P)
    alone = np.mean([r.error <= 1e-10 for r in res_alone])
    t_an, res_an = timed(lambda p: so.solve_ik(robot, p, method="analytic"), P)
    big = np.repeat(P, max(1, 1_000_000 // N), axis=0)
    t0 = time.perf_counter()
    _, valid = solve_batch(robot, big)
    t_batch = time.perf_counter() - t0
    print(f"{name}: {N} reachable targets (FK of random in-limit q), tol 1e-9 m")
    print(row("scipy least_squares (base)", t_sp, ok_sp, base))
    print(row("ipopt cold", t_cold, np.mean([r.success for r in res_cold]), base))
    print(row("ipopt warm (neighbour q0)", t_warm, np.mean([r.success for r in res_warm]),
              base))
    print(row("ipopt alone (polish=False)", t_alone, np.mean([r.success for r in res_alone]),
              base) + f"  <= 1e-10: {alone:.1%}")
    print(row("analytic single", t_an, np.mean([r.success for r in res_an]), base))
    rate = len(big) / t_batch
    print(f"  {'analytic batch':<30} {rate:,.0f} targets/s ({len(big):,} targets, "
          f"{valid.any(axis=1).mean():.1%} with a branch)  x scipy per target "
          f"{(t_batch / len(big)) / base:.2e}")
    cold, warm = np.median(t_cold), np.median(t_warm)
    print(f"  goals: ipopt cold <= 2 ms: {cold * 1e3:.2f} ms "
          f"({'met' if cold <= 2e-3 else 'NOT met'}); warm <= 1 ms: {warm * 1e3:.2f} ms "
          f"({'met' if warm <= 1e-3 else 'NOT met'}); batch >= 1e6/s: "
          f"{'met' if rate >= 1e6 else 'NOT met'}; ipopt alone <= 1e-10 on >= 99.9 %: "
          f"{alone:.1%} ({'met' if alone >= 0.999 else 'NOT met'})")


if __name__ == "__main__":
    main()
