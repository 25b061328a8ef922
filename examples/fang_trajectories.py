# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""fang joint trajectories: Tables 2 and 3 by the quintic, then time-optimal and jerk-limited.

Reproduces Fang & Li, "Four degrees of freedom SCARA robot kinematics modeling and simulation
analysis" (shared/seeds/004_bf70fd1cc4e521c8.txt), Sec. 4:

* Tables 2 and 3 — the joint trajectories A → B and B → C printed by the Robotics Toolbox's
  ``jtraj``: a quintic with zero velocity and acceleration at both ends, 36 samples at
  τ = k/35 (angles in degrees, labelled "rad" in the paper; joint 3 in mm). Our quintic
  is compared with every printed row (tests/reference/fang.toml).
* The same two moves timed within the robot's joint limits (robots/fang.toml; the paper
  gives none, so they are assumptions: 180 deg/s and 720 deg/s² for joints 1-2, 0.5 m/s and
  2 m/s² for joint 3, 360 deg/s and 1440 deg/s² for joint 4) three ways: the shortest
  quintic, TOPP-RA (time-optimal, toppra) and Ruckig (jerk-limited, jerk = 10/s × amax).

Prints the table check, the durations and the ratios to the shortest quintic; saves
``examples/out/fang_table2_move.png`` and ``fang_table3_move.png`` (q, qd, qdd per joint
of the three timings, with the limit lines).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.trajectory import time_parameterize
from scara_opt.trajectory.plot import plot_trajectories

ROBOT = "fang"
#: the moves of Tables 2 and 3 as printed (deg, deg, mm, deg)
MOVES = {
    2: ((0.0, 0.0, 0.0, -15.0), (-64.4042, 128.8085, 15.1500, -61.4099)),
    3: ((64.4042, 128.8085, 15.1500, 61.4099), (-52.6250, -106.8207, 0.0300, -52.7509)),
}
SAMPLES = 36  # jtraj samples, tau = k / 35
METHODS = ("quintic", "toppra", "ruckig")
ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "tests" / "reference" / "fang.toml"
OUT = Path(__file__).resolve().parent / "out"
#: paper units (deg, deg, mm, deg) -> SI (rad, rad, m, rad)
TO_SI = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])


def fmt(row: np.ndarray) -> str:
    """A row as the paper prints it: four decimals."""
    return "(" + ", ".join(f"{v:.4f}" for v in row) + ")"


def check_tables(robot: so.Robot) -> None:
    """Print our quintic against every row the paper prints (if the reference file is here)."""
    if not REFERENCE.is_file():
        print(f"(no {REFERENCE}: table check skipped)")
        return
    ref = tomllib.loads(REFERENCE.read_text())
    tau = np.arange(SAMPLES) / (SAMPLES - 1)
    for table in ref["tables"]:
        Q = np.array([table["start"], table["end"]]) * TO_SI
        traj = time_parameterize(Q, robot, method="quintic", duration=1.0)
        ours = traj.sample(tau)[0] / TO_SI
        rows = np.array(table["rows"])
        dev = np.abs(ours[:len(rows)] - rows).max()
        print(f"Table {table['table']} ({table['title']}): {len(rows)} printed rows of "
              f"{SAMPLES}, largest deviation {dev:.1e} (deg / mm; tolerance "
              f"{ref['tolerance']:g}) -> {'matched' if dev <= ref['tolerance'] else 'DIFFERS'}")
        for k in (1, len(rows) - 1):
            print(f"    row {k + 1:>2} (tau = {k}/35): ours {fmt(ours[k])}  paper {fmt(rows[k])}")


def time_moves(robot: so.Robot) -> None:
    """Time both moves three ways, print durations and ratios, save one figure per move."""
    print(f"\nlimits of {ROBOT} (assumed, robots/fang.toml): vmax {robot.velocity_limit.round(3)}"
          f", amax {robot.acceleration_limit.round(3)} [rad, m, s]; ruckig jerk = 10/s x amax")
    print(f"{'move':<8}{'quintic [s]':>12}{'toppra [s]':>12}{'ruckig [s]':>12}"
          f"{'toppra/quintic':>16}{'ruckig/quintic':>16}{'max ratio':>11}")
    for table, (start, end) in MOVES.items():
        Q = np.array([start, end]) * TO_SI
        trajs = [time_parameterize(Q, robot, method=m) for m in METHODS]
        durations = [tr.duration for tr in trajs]
        worst = max(float(r.max()) for tr in trajs for r in tr.check_limits().values())
        print(f"Table {table}{durations[0]:>12.4f}{durations[1]:>12.4f}{durations[2]:>12.4f}"
              f"{durations[1] / durations[0]:>16.3f}{durations[2] / durations[0]:>16.3f}"
              f"{worst:>11.6f}")
        path = plot_trajectories(
            trajs, OUT / f"fang_table{table}_move.png",
            labels=["shortest quintic", "toppra", "ruckig"],
            title=f"fang Table {table} move: shortest quintic vs TOPP-RA vs Ruckig")
        print(f"    wrote {path}")


def main() -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.load_robot(ROBOT)
    check_tables(robot)
    time_moves(robot)


if __name__ == "__main__":
    main()
