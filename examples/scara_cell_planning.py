# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""Planning in a SCARA cell: a post to swing around, a rack to clear by lifting the quill.

Needs: the base install only (OMPL's wheel is a dependency).

zavar2024 (robots/zavar2024.toml, capsules from its ``radius`` keys) in the cell of
``examples/scara_cell.toml``. The script shows, with its numbers:

1. the straight PTP from the pick to the place hits the cell (first contact: time,
   bodies, depth, by ``Trajectory.check_collisions``);
2. the same move planned around it (``so.planning.plan_path``: OMPL RRTConnect and
   PathSimplifier, every edge proven clear), then a pick-and-place program planned with
   ``so.plan(..., cell=)``: timed by toppra, the timed trajectory proven clear again;
3. a PTP from the pick to beyond the rack, the tool low at both ends: the planner lifts
   the quill over the rack's bar;
4. a LIN through the rack refused, naming the move, the time and the bodies;
5. the pick-and-place cycle time in the cell (``so.cycle_time(..., cell=)``).

Saves ``examples/out/scara_cell_planning.png``: the cell seen from above with the tool
paths (straight and planned), and the tool's height crossing the rack.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import scara_opt as so  # noqa: E402
from scara_opt.planning import plan_path  # noqa: E402

ROBOT = "zavar2024"
CELL = Path(__file__).parent / "scara_cell.toml"
PICK = [0.32, -0.05, -0.09]    # tool position at the pick [m]
PLACE = [0.03, 0.30, -0.075]   # into the tray [m]
DROP = [0.12, -0.22, -0.09]    # beyond the rack, tool low [m]
LIFT = 0.02                    # up before moving across [m]
SEED = 0
OUT = Path(__file__).parent / "out"


def outline(ax, cell: so.Cell) -> None:
    """Each obstacle's footprint (z projection) in grey."""
    for ob in cell.obstacles:
        R = ob.placement.rotation
        c = np.array(ob.xyz[:2])
        if ob.kind in ("cylinder", "capsule", "sphere"):
            ax.add_patch(plt.Circle(c, ob.radius, color="0.6", alpha=0.6))
        elif ob.kind == "box":
            sx, sy = ob.size[0] / 2, ob.size[1] / 2
            corners = np.array([[-sx, -sy, 0], [sx, -sy, 0], [sx, sy, 0], [-sx, sy, 0]]) @ R.T
            ax.add_patch(plt.Polygon(corners[:, :2] + c, color="0.6", alpha=0.4))
        ax.annotate(ob.name, c, fontsize=7, ha="center")


def main() -> None:
    robot = so.load_robot(ROBOT)
    cell = so.load_cell(CELL)
    checker = so.CollisionChecker(robot, cell)
    print(f"{robot.name} in {cell!r}: {checker.npairs} pairs checked, "
          f"{sum(why.startswith('never') for why in checker.skipped.values())} pairs out of reach")

    up = np.array([0, 0, LIFT])
    a = so.ik_all(robot, so.Target(np.add(PICK, up)))[0].q
    b = [s.q for s in so.ik_all(robot, so.Target(np.add(PLACE, up)), q0=a)
         if not checker.collides(s.q)][0]
    straight = so.time_parameterize(np.array([a, b]), robot)
    hit = straight.check_collisions(checker)
    print(f"\nstraight PTP above pick -> above place: {hit}")

    res = plan_path(checker, a, b, seed=SEED)
    print(f"planned around the cell:  {res}")

    program = [so.LIN(so.Target(np.add(PICK, up))),
               so.PTP(b),
               so.LIN(so.Target(PLACE), speed=0.1),
               so.LIN(so.Target(np.add(PLACE, up))),
               so.PTP(a)]
    start = so.ik_all(robot, so.Target(PICK), q0=a)[0].q
    traj = so.plan(robot, program, start=start, cell=cell, margin=0.002, seed=SEED)
    report = traj.check_collisions()
    print(f"\n{'move':<6}{'kind':<6}{'start s':>9}{'end s':>9}")
    for k, m in enumerate(program):
        print(f"{k:<6}{m.kind:<6}{traj.waypoint_times[k]:>9.3f}{traj.waypoint_times[k + 1]:>9.3f}")
    ratios = traj.check_limits()
    print(f"program: {traj.duration:.3f} s, computed in {traj.compute_time_s * 1e3:.0f} ms; "
          f"{report}; worst joint ratio "
          f"{max(ratios['velocity'].max(), ratios['acceleration'].max()):.3f}, "
          f"clearance ratio {ratios['clearance'][0]:.3f} (<= 1: the 2 mm margin is kept)")

    low = so.ik_all(robot, so.Target(DROP), q0=start)
    drop = [s.q for s in low if not checker.collides(s.q)][0]
    over = so.plan(robot, [so.PTP(drop)], start=start, cell=cell, seed=SEED)
    t_over = over.times(0.005)
    Po = robot.positions(over.evaluate(t_over))
    z_over = Po[:, 2]
    print(f"\nPTP pick -> beyond the rack, tool at {PICK[2] * 1e3:g} mm at both ends: "
          f"{over.duration:.3f} s, the tool lifted to {z_over.max() * 1e3:.1f} mm on the way "
          f"({over.check_collisions()})")

    through = [so.LIN(so.Target([0.26, -0.24, -0.09]))]
    try:
        so.plan(robot, through, start=start, cell=cell)
    except so.MoveCollisionError as exc:
        print(f"\nrefused: {exc}")

    cycle = so.cycle_time(robot, across=0.2, cell=cell)
    print(f"\ncycle in the cell: {cycle}")

    OUT.mkdir(exist_ok=True)
    fig, (ax, az) = plt.subplots(1, 2, figsize=(11, 4.8))
    outline(ax, cell)
    ts = straight.times(0.005)
    ax.plot(*robot.positions(straight.evaluate(ts))[:, :2].T, "r--", label="straight PTP")
    tp = traj.times(0.005)
    P = robot.positions(traj.evaluate(tp))
    ax.plot(P[:, 0], P[:, 1], "b-", label="planned program")
    ax.plot(0, 0, "k+", ms=12)
    ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot.name} in {cell.name}: top view")
    ax.set_aspect("equal")
    ax.plot(Po[:, 0], Po[:, 1], "g-", label="PTP over the rack")
    ax.legend(fontsize=8)
    az.plot(t_over, z_over * 1e3, "g-")
    rack = cell["rack"]
    az.axhline((rack.xyz[2] + rack.size[2] / 2) * 1e3, color="0.5", ls=":",
               label="rack top")
    az.legend(fontsize=8)
    az.set(xlabel="t [s]", ylabel="tool tip z [mm]",
           title="PTP over the rack: the quill lifts the tool")
    fig.tight_layout()
    path = OUT / "scara_cell_planning.png"
    fig.savefig(path, dpi=110)
    print(f"\nwrote {path}")


if __name__ == "__main__":
    main()
