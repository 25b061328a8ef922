# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""Your own robot: a general 6-joint arm from a URDF, IK by IPOPT and PSO, a timed path.

Needs: the base install only (``pip install scara-opt``).

Nothing in scara_opt is SCARA-only except the closed form. This script loads
``examples/arm6.urdf`` (rotated joint origins, an unaligned elbow axis, a short slide), solves
a full pose with IPOPT and a position target with PSO, follows a straight line with
``ik_path``, times it with TOPP-RA within the URDF's velocity limits and assumed acceleration
limits, and saves a pose drawing and the timed joint trajectory into ``examples/out/``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.plots import draw_robot

URDF = Path(__file__).resolve().parent / "arm6.urdf"
OUT = Path(__file__).resolve().parent / "out"
Q_GOAL = np.array([0.4, -0.6, 0.8, 0.05, 0.3, -0.2])  # the pose to reach [rad, m]
AMAX = 5.0  # assumed acceleration limit of every joint [rad/s², m/s²]: the URDF has none
LINE_POINTS = 30


def main() -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.Robot.from_urdf(URDF, tip="tool0")
    print(robot)
    T = robot.fk(Q_GOAL)
    pose = so.Target(T[:3, 3], rotation=T[:3, :3])
    res_ipopt = so.solve_ik(robot, pose, method="ipopt", restarts=40)
    res_pso = so.solve_ik(robot, T[:3, 3], method="pso", population=60, iterations=200,
                          seed=0, tol=1e-6)
    print(f"{'method':<8}{'target':<10}{'status':<13}{'error':>10}{'time [ms]':>11}")
    for name, kind, res in (("ipopt", "pose", res_ipopt), ("pso", "position", res_pso)):
        print(f"{name:<8}{kind:<10}{res.status.value:<13}{res.error:>10.2e}"
              f"{res.time_s * 1e3:>11.1f}")
    start = robot.position(res_ipopt.q)
    path = so.ik_path(robot, so.paths.line(start, start + [0.0, 0.10, -0.05], LINE_POINTS),
                      q_start=res_ipopt.q)
    print(path)
    traj = so.time_parameterize(path, robot, method="toppra", amax=AMAX)
    worst = max(float(r.max()) for r in traj.check_limits().values())
    print(f"toppra: {traj.duration:.3f} s along an 11.2 cm line, largest limit ratio "
          f"{worst:.4f}")
    draw_robot(robot, res_ipopt.q, path=OUT / "own_urdf_pose.png")
    written = [OUT / "own_urdf_pose.png",
               traj.plot(OUT / "own_urdf_toppra.png", title="arm6 straight line, toppra")]
    for p in written:
        print(f"wrote {p}")


if __name__ == "__main__":
    main()
