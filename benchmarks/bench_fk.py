"""FK speed: Pinocchio per call, numpy fk_batch, casadi symbolic_fk.map, vs a numpy closed form.

Prints the time per configuration of each route and its ratio to a plain numpy
closed-form FK of zavar2024 (eq. 5 of the paper) measured in the same run.
Goal (issue: foundation): fk_batch <= 1 µs per configuration on the 4-joint robots.
"""

from __future__ import annotations

import time

import numpy as np

import scara_opt as so

N = 100_000
REPEATS = 5


def best_time(fn, *args) -> float:
    """Best of REPEATS wall-clock times [s] (machines are shared: take the least disturbed)."""
    times = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        fn(*args)
        times.append(time.perf_counter() - t)
    return min(times)


def closed_form_zavar(Q: np.ndarray) -> np.ndarray:
    """zavar2024 eq. 5: tip positions (n, 3) [m], a1 = a2 = 0.2 m, z = -d3 - 0.05 m."""
    t1, t12 = Q[:, 0], Q[:, 0] + Q[:, 1]
    return np.column_stack([0.2 * np.cos(t1) + 0.2 * np.cos(t12),
                            0.2 * np.sin(t1) + 0.2 * np.sin(t12), -Q[:, 2] - 0.05])


def fk_loop(robot: so.Robot, Q: np.ndarray) -> list[np.ndarray]:
    """One Pinocchio call per configuration."""
    return [robot.fk(q) for q in Q]


def per_call(fn, Q: np.ndarray, calls: int) -> float:
    """Best time of one ``fn(Q)`` call [s], over ``calls`` calls in a row."""
    return best_time(lambda: [fn(Q) for _ in range(calls)]) / calls


def small_batches(robot: so.Robot, Q: np.ndarray, calls: int = 2000) -> None:
    """Per-call cost at a metaheuristic's population sizes.

    fk_batch and positions (the casadi route up to SMALL_BATCH / SMALL_BATCH_POSITIONS)
    against the numpy chain walk they replace there, and the closed form.
    """
    print(f"small batches on {robot.name} (a population per call), us per call:")
    print(f"  {'n':>5} {'fk_batch':>9} {'positions':>10} {'numpy walk':>11} "
          f"{'closed form':>12} {'walk/positions':>15}")
    for n in (20, 60, 100, 200, 400):
        fast = per_call(robot.fk_batch, Q[:n], calls)
        pos = per_call(robot.positions, Q[:n], calls)
        walk = per_call(robot._fk_batch_rp, Q[:n], calls)
        base = per_call(closed_form_zavar, Q[:n], calls)
        print(f"  {n:>5} {fast * 1e6:>9.1f} {pos * 1e6:>10.1f} {walk * 1e6:>11.1f} "
              f"{base * 1e6:>12.1f} {walk / pos:>15.2f}")


def main() -> None:
    rng = np.random.default_rng(0)
    zavar = so.load_robot("zavar2024")
    Qz = rng.uniform(zavar.lower, zavar.upper, (N, zavar.nq))
    base = best_time(closed_form_zavar, Qz) / N
    print(f"baseline: numpy closed-form FK of zavar2024: {base * 1e9:.0f} ns/config (N={N})")
    print(f"{'robot':<10} {'route':<22} {'ns/config':>10} {'x baseline':>11}")
    for name in so.list_robots():
        robot = so.load_robot(name)
        Q = rng.uniform(robot.lower, robot.upper, (N, robot.nq))
        fmap = robot.symbolic_fk.map(N)
        Qt = Q.T.copy()
        rows = [
            ("fk (pinocchio, loop)", best_time(fk_loop, robot, Q[:2000]) / 2000),
            ("fk_batch (numpy)", best_time(robot.fk_batch, Q) / N),
            ("positions (numpy)", best_time(robot.positions, Q) / N),
            ("symbolic_fk.map", best_time(fmap, Qt) / N),
        ]
        for route, t in rows:
            print(f"{name:<10} {route:<22} {t * 1e9:>10.0f} {t / base:>11.1f}")
    small_batches(zavar, Qz)
    t = best_time(zavar.fk_batch, Qz) / N
    verdict = "met" if t <= 1e-6 else "NOT met"
    print(f"goal fk_batch <= 1 us/config on zavar2024: {t * 1e6:.2f} us -> {verdict}")


if __name__ == "__main__":
    main()
