# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""A pick-and-place cell programmed in moves (PTP / LIN / CIRC), timed, checked and exported.

Needs: the base install only (``pip install scara-opt``).

The zavar2024 SCARA (its limits are the assumed ones of robots/zavar2024.toml) picks a part
at P, lifts it, carries it on an arc over a fixture to Q and sets it down:

* ``PTP`` to 20 mm above P (the righty arm), ``LIN`` down at 0.1 m/s, ``LIN`` up,
  ``CIRC`` through a via point over the fixture to 20 mm above Q at 0.4 m/s, ``LIN`` down
  turning the part by 90° (yaw), ``LIN`` up, ``PTP`` home; the lift, the arc and the
  descent are blended (10 mm radii: no stop above P or Q), and so is the lift into the
  joint move home (a blend next to a PTP is rounded in joint space);
* program-wide tool limits: 0.5 m/s, 3 m/s², 3 rad/s yaw rate;
* the standard 25/305/25 mm cycle of the same robot, timed three ways, and by toppra with
  its upper corners blended (10 mm).

Prints each stop-to-stop run's time and its worst tool-limit ratios (1 kHz FK), how far
the blends pass from their corners, writes the CSV a
controller reads (``examples/out/pick_and_place_cell.csv``, t, q, qd, qdd at 1 ms, units in
the header), the ROS ``JointTrajectory``-shaped YAML, and the figure
``examples/out/pick_and_place_cell.png`` (tool speed and joint profiles).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.motion.plot import plot_motion

OUT = Path(__file__).resolve().parent / "out"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.load_robot("zavar2024")
    z_up, z_down = -0.06, -0.08
    P, Q = np.array([0.30, -0.12]), np.array([0.25, 0.20])
    home = np.array([-0.3, 1.2, 0.0, 0.0])
    program = [
        so.PTP(so.Target([*P, z_up], yaw=0.0), elbow="righty"),
        so.LIN(so.Target([*P, z_down], yaw=0.0), speed=0.1),
        so.LIN(so.Target([*P, z_up], yaw=0.0), blend=0.01),
        so.CIRC([0.34, 0.05, z_up], so.Target([*Q, z_up], yaw=0.0), speed=0.4, blend=0.01),
        so.LIN(so.Target([*Q, z_down], yaw=np.pi / 2), speed=0.1),
        so.LIN(so.Target([*Q, z_up], yaw=np.pi / 2), blend=0.01),
        so.PTP(home),
    ]
    limits = so.ToolLimits(speed=0.5, acceleration=3.0, yaw_rate=3.0)
    traj = so.plan(robot, program, limits, start=home)
    ratios = traj.tool_limit_ratios()
    print(f"{'run':>3} {'moves':18} {'time [s]':>9} {'speed':>6} {'acc':>6} {'yaw':>6}")
    for i, note in enumerate(traj.notes.split("; ")):
        dt = traj.waypoint_times[i + 1] - traj.waypoint_times[i]
        own = traj.profiles[i][1]  # the run's tool limits ("-": none; a PTP has only its own)
        cells = [f"{ratios['tool_' + k][i]:6.3f}" if own.limited(k) else f"{'-':>6}"
                 for k in ("speed", "acceleration", "yaw_rate")]
        print(f"{i:3d} {note.split(':')[0]:18} {dt:9.4f} " + " ".join(cells))
    print("blended corners missed by [mm]: "
          + ", ".join(f"{d * 1e3:.2f} (radius {r * 1e3:g})"
                      for d, (_, r, _) in zip(traj.blend_deviations(), traj.corners, strict=True)))
    joint = traj.check_limits()
    print(f"cell cycle {traj.duration:.4f} s; worst joint ratios: velocity "
          f"{joint['velocity'].max():.4f}, acceleration {joint['acceleration'].max():.4f}")
    csv = traj.to_csv(OUT / "pick_and_place_cell.csv", dt=0.001)
    ros = traj.to_ros_yaml(OUT / "pick_and_place_cell.yaml", dt=0.01)
    print(f"CSV for the controller: {csv} ({len(traj.times(0.001))} rows at 1 ms); ROS: {ros}")
    res = so.cycle_time(robot, blend=0.01)
    print("standard cycle 25/305/25 mm: " + ", ".join(
        f"{k} {v:.4f} s" for k, v in res.durations.items()))
    png = plot_motion(robot, traj, OUT / "pick_and_place_cell.png",
                      title=f"zavar2024 pick-and-place cell, {traj.duration:.3f} s")
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
