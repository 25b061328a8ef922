"""The fixed Python cost of one ``solve_ik`` call, apart from the search, piece by piece.

Robots: tests/data/ur5_dh.urdf and tests/data/panda_dh.urdf (full-pose targets) and the
bundled SCARA ``zavar2024`` (position targets). Targets: the FK of 40 random in-limit
configurations (seed 0); every call starts from the same float64 ``q0`` (the default start).
Per target, each piece's time is the minimum over repeats of the mean of a short loop; the
table gives the median over the targets [µs]. Pieces: the whole ``solve_ik(..., method="lm")``
call; the LM search alone (``_solve``); ``check_q0``; ``judge`` (of the search's output);
within ``judge``: ``config_errors``, ``error_from``, ``cost_of``.

Times are wall clock on a shared machine: compare within one run.

Usage: ``python benchmarks/bench_overhead.py``.
"""

from __future__ import annotations

import timeit
from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.ik.base import check_q0
from scara_opt.ik.registry import get_solver
from scara_opt.ik.task import config_errors, cost_of, default_q0, error_from
from scara_opt.ik.verdict import judge

DATA = Path(__file__).resolve().parent.parent / "tests" / "data"
N_TARGETS, NUMBER, REPEAT = 40, 20, 7


def _targets(robot: so.Robot, position_only: bool) -> list[so.Target]:
    Q = np.random.default_rng(0).uniform(robot.sampling_lower, robot.sampling_upper,
                                         (N_TARGETS, robot.nq))
    if position_only:
        return [so.Target(robot.position(q)) for q in Q]
    return [so.Target.from_pose(robot.fk(q)) for q in Q]


def _us(f: object) -> float:
    """Min over repeats of the mean time of one call [µs]."""
    return min(timeit.repeat(f, number=NUMBER, repeat=REPEAT)) / NUMBER * 1e6


def measure(robot: so.Robot, position_only: bool) -> dict[str, float]:
    """Median over the targets of each piece's time [µs]."""
    q0 = np.array(default_q0(robot), dtype=float)
    solver = get_solver("lm")
    rng = np.random.default_rng(0)
    rows: dict[str, list[float]] = {}
    for target in _targets(robot, position_only):
        so.solve_ik(robot, target, method="lm", q0=q0)  # warm caches
        out = solver._solve(robot, target, q0, rng, 1e-9)
        dp, dang = config_errors(robot, target, np.asarray(out.q, float))
        pieces = {
            "solve_ik": lambda t=target: so.solve_ik(robot, t, method="lm", q0=q0),
            "search": lambda t=target: solver._solve(robot, t, q0, rng, 1e-9),
            "check_q0": lambda: check_q0(robot, q0),
            "judge": lambda t=target, o=out: judge(robot, t, o, tol=1e-9, method="lm", seed=0,
                                                   time_s=0.0),
            "config_errors": lambda t=target, q=out.q: config_errors(robot, t, q),
            "error_from": lambda d=dp, a=dang: error_from(d, a),
            "cost_of": lambda t=target, d=dp, a=dang: cost_of(t, d, a),
        }
        for name, f in pieces.items():
            rows.setdefault(name, []).append(_us(f))
    return {name: float(np.median(v)) for name, v in rows.items()}


def main() -> None:
    robots = [("ur5_dh pose", so.Robot.from_urdf(DATA / "ur5_dh.urdf"), False),
              ("panda_dh pose", so.Robot.from_urdf(DATA / "panda_dh.urdf"), False),
              ("zavar2024 position", so.load_robot("zavar2024"), True)]
    results = {label: measure(robot, pos) for label, robot, pos in robots}
    names = list(next(iter(results.values())))
    print(f"{'piece [µs]':16s}" + "".join(f"{label:>22s}" for label in results))
    for name in names:
        print(f"{name:16s}" + "".join(f"{r[name]:22.2f}" for r in results.values()))
    print(f"{'rest':16s}" + "".join(f"{r['solve_ik'] - r['search']:22.2f}"
                                     for r in results.values()))


if __name__ == "__main__":
    main()
