# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""zavar2024 circular path: IK along it with IPOPT, the paper's circle and a reachable one, timed.

Needs: the base install only (``pip install scara-opt``).

Reproduces the path study of Zavar et al. (2024), Table 3 and Fig. 7
(robots/zavar2024.toml [citation]), and says where it cannot be reproduced:

* Table 3 — ten points on a circle of radius 16 cm at z = −6 cm (point 7's sign typo
  fixed). With |θ2| <= 120° the tip cannot come closer than 0.2 m to the base axis, so
  every point is out of reach by 4 cm: :func:`~scara_opt.trajectory.ik_path` reports each
  as ``unreachable`` with its true residual (the paper reports errors near 1e-17).
* The reachable variant (shared/ROBOTS.md): the same ten angles at r = 0.30 m,
  z = −0.07 m. Every point is reachable, but no single elbow branch covers the arc within
  |θ1| <= 120°: followed as one path it needs an elbow flip, which ik_path reports as a
  jump instead of hiding it.
* That joint path timed three ways within the (assumed) limits of robots/zavar2024.toml:
  shortest quintic (stops at each point), TOPP-RA (through the points), Ruckig (through
  the points, jerk-limited), with the flip allowed explicitly (``allow_jumps=True``).

Prints the per-point table and the durations; saves ``examples/out/zavar2024_circle_xy.png``
(the circle, the workspace's inner boundary and the tip path of the timed trajectory, which
leaves the circle during the flip) and ``zavar2024_circle_timing.png``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt import paths
from scara_opt.trajectory import JointPath, Trajectory, ik_path, time_parameterize
from scara_opt.trajectory.plot import new_figure, plot_trajectories

ROBOT = "zavar2024"
METHOD = "ipopt"
TIMINGS = ("quintic", "toppra", "ruckig")
OUT = Path(__file__).resolve().parent / "out"


def ik_table(robot: so.Robot, reachable: bool) -> JointPath:
    """Solve the circle along the path and print one row per point."""
    jp = ik_path(robot, paths.zavar2024_circle(reachable=reachable), method=METHOD)
    label = "reachable variant (r = 0.30 m, z = -0.07 m)" if reachable else \
        "paper's Table 3 (r = 0.16 m, z = -0.06 m)"
    print(f"\n{label}: {jp.summary()}")
    print(f"{'pt':>3} {'x [m]':>8} {'y [m]':>8} {'status':>12} {'residual [m]':>13} "
          f"{'theta1':>8} {'theta2':>8} [deg]")
    for i, (t, q) in enumerate(zip(jp.targets, jp.q, strict=True)):
        print(f"{i:>3} {t.position[0]:>8.3f} {t.position[1]:>8.3f} "
              f"{jp.status[i].value:>12} {jp.error[i]:>13.3g} "
              f"{np.degrees(q[0]):>8.1f} {np.degrees(q[1]):>8.1f}")
    for jump in jp.jumps:
        print(f"  JUMP {jump}")
    return jp


def plot_xy(robot: so.Robot, jp: JointPath, traj: Trajectory,
            path: Path) -> Path:
    """The circle, the workspace's inner boundary and the tip path of the timed trajectory."""
    fig = new_figure(1, 1, size=(7.0, 6.0))
    ax = fig.subplots()
    th = np.linspace(0, 2 * np.pi, 361)
    for r, style, label in ((0.2, "k:", "inner reach r = 0.2 m"), (0.4, "k--", "outer reach")):
        ax.plot(r * np.cos(th), r * np.sin(th), style, lw=0.8, label=label)
    P = np.array([t.position for t in jp.targets])
    tip = robot.positions(traj.positions(traj.duration / 2000))
    ax.plot(tip[:, 0], tip[:, 1], "-", lw=1, label=f"tip path, {traj.method} timing")
    ax.plot(P[:, 0], P[:, 1], "o", label="reachable circle points")
    paper = np.array([t.position for t in paths.zavar2024_circle()])
    ax.plot(paper[:, 0], paper[:, 1], "x", label="paper's Table 3 points (out of reach)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0))
    ax.set_title("zavar2024 circle: the elbow flip leaves the circle")
    fig.savefig(path, dpi=110)
    return path


def main() -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.load_robot(ROBOT)
    ik_table(robot, reachable=False)
    jp = ik_table(robot, reachable=True)
    trajs = [time_parameterize(jp, robot, method=m, allow_jumps=True) for m in TIMINGS]
    base = trajs[0].duration
    print(f"\ntimed within the assumed limits of robots/{ROBOT}.toml (flip allowed):")
    for tr in trajs:
        worst = max(float(r.max()) for r in tr.check_limits().values())
        print(f"  {tr.method:<8} {tr.duration:8.3f} s  x{tr.duration / base:6.3f} of the "
              f"shortest quintic  (max limit ratio {worst:.6f}; {tr.notes})")
    for path in (plot_trajectories(trajs, OUT / "zavar2024_circle_timing.png",
                                   title="zavar2024 reachable circle, IPOPT joint path, timed"),
                 plot_xy(robot, jp, trajs[1], OUT / "zavar2024_circle_xy.png")):
        print(f"  wrote {path}")


if __name__ == "__main__":
    main()
