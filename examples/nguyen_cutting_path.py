# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""nguyen cutting path: IK of the 5-DoF rail SCARA along a closed contour, SFLA and IPOPT.

Reproduces the path study of Nguyen, "Inverse Kinematics of SCARA Manipulator based on
SFLA" (shared/seeds/002_e63e44ba374820ad.txt), Sec. 4-5:

* Figs. 6, 7, 9 — the cutting path, a nearly closed contour with the tool tangent to it.
  The paper gives it only as a figure, so a representative contour stands in for it
  (:func:`scara_opt.paths.nguyen_contour`: a rounded rectangle 0.20 m x 0.30 m in the arm's
  x-z plane, tool angle A = θ2 + θ3 + θ5 along the direction of travel), inside the
  workspace of the joint limits assumed in robots/nguyen.toml (the paper gives none).
* Figs. 10-11 — position errors along the path; here the largest position and angle error
  of SFLA (the paper's Table 2 settings, the ``sfla`` defaults) and of IPOPT, side by side.
* Figs. 12-13 — the joints along the path: the rail d1, and θ2, θ3, θ5.
* Beyond the paper: the IPOPT joint path timed by TOPP-RA within the assumed limits.

Each point is solved from the previous solution (``ik_path``), so the redundant degree of
freedom moves as little as possible. Prints the comparison table; saves
``examples/out/nguyen_fig9_path.png``, ``nguyen_fig10_11_errors.png``,
``nguyen_fig12_13_joints.png`` and ``nguyen_toppra.png``. ``--quick``: fewer points.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt import paths
from scara_opt.trajectory import JointPath, ik_path, time_parameterize
from scara_opt.trajectory.plot import new_figure

ROBOT = "nguyen"
N_POINTS = 120  # points along the contour (one more closes it)
QUICK_POINTS = 24
#: start of the path: rail 0.3 m, elbow bent, wrist 0 (the first point is solved from here)
Q_START = (0.3, 0.0, 1.5, 0.05, 0.0)
#: IK tolerance [m, rad]: the solver default
IK_TOL = 1e-9
SEED = 0
OUT = Path(__file__).resolve().parent / "out"


def solve_paths(robot: so.Robot, targets: list[so.Target]) -> dict[str, JointPath]:
    """IK along the contour with IPOPT and, once it is registered, SFLA."""
    try:
        import scara_opt.metaheuristics  # noqa: F401  (registers sfla)
    except ImportError:
        pass
    methods = ["ipopt"] + (["sfla"] if "sfla" in so.solvers() else [])
    if "sfla" not in methods:
        print("(SFLA is not registered in this version: IPOPT only)")
    return {m: ik_path(robot, targets, method=m, q_start=Q_START, seed=SEED, tol=IK_TOL)
            for m in methods}


def print_table(results: dict[str, JointPath]) -> None:
    """Largest errors, statuses, jumps and time per method."""
    print(f"{'method':<8}{'solved':>9}{'max |dp| [m]':>14}{'max |dA| [rad]':>16}"
          f"{'jumps':>7}{'time [s]':>10}  statuses")
    for name, jp in results.items():
        counts = {s.value: jp.status.count(s) for s in dict.fromkeys(jp.status)}
        print(f"{name:<8}{int(jp.solved.sum()):>5}/{len(jp):<3}"
              f"{np.linalg.norm(jp.position_error, axis=1).max():>14.3g}"
              f"{np.abs(jp.angle_error).max():>16.3g}{len(jp.jumps):>7}{jp.time_s:>10.2f}  "
              f"{counts}")


def plot_path(robot: so.Robot, results: dict[str, JointPath], path: Path) -> Path:
    """Fig. 9: the contour in the x-z plane, the tips reached, tool directions."""
    fig = new_figure(1, 1, size=(7.0, 6.0))
    ax = fig.subplots()
    first = next(iter(results.values()))
    P = np.array([t.position for t in first.targets])
    A = np.array([t.yaw for t in first.targets])
    ax.plot(P[:, 0], P[:, 2], "k-", lw=2, alpha=0.3, label="cutting contour (targets)")
    step = max(len(P) // 24, 1)
    ax.quiver(P[::step, 0], P[::step, 2], np.cos(A[::step]), np.sin(A[::step]), width=0.003,
              scale=25, label="tool angle A (tangent)")
    for name, jp in results.items():
        tip = robot.positions(jp.q)
        ax.plot(tip[:, 0], tip[:, 2], ".", ms=4, label=f"tip, {name}")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title("nguyen Fig. 9 (representative contour): end-effector path")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.savefig(path, dpi=110)
    return path


def plot_errors(results: dict[str, JointPath], path: Path) -> Path:
    """Figs. 10-11: |x| and |z| position errors and the angle error per point (log scale)."""
    fig = new_figure(1, 3, size=(4.0, 3.0))
    axes = fig.subplots(1, 3)
    for name, jp in results.items():
        for ax, values in zip(axes, (jp.position_error[:, 0], jp.position_error[:, 2],
                                     jp.angle_error), strict=True):
            ax.semilogy(np.abs(values) + 1e-18, ".-", ms=3, lw=0.6, label=name)
    for ax, title in zip(axes, ("|x error| [m] (Fig. 10)", "|z error| [m] (Fig. 11)",
                                "|tool angle error| [rad]"), strict=True):
        ax.set_title(title)
        ax.set_xlabel("point")
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize="small")
    fig.savefig(path, dpi=110)
    return path


def plot_joints(robot: so.Robot, results: dict[str, JointPath], path: Path) -> Path:
    """Figs. 12-13: rail position, then θ2, θ3, θ5 (and d4) along the path."""
    fig = new_figure(1, robot.nq, size=(3.2, 3.0))
    axes = fig.subplots(1, robot.nq)
    for name, jp in results.items():
        for k, ax in enumerate(axes):
            scale = np.degrees(1.0) if robot.joint_types[k] == "revolute" else 1000.0
            ax.plot(jp.q[:, k] * scale, ".-", ms=3, lw=0.6, label=name)
    for k, ax in enumerate(axes):
        unit = "deg" if robot.joint_types[k] == "revolute" else "mm"
        ax.set_title(f"{robot.joint_names[k]} [{unit}]")
        ax.set_xlabel("point")
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize="small")
    fig.suptitle("nguyen Figs. 12-13: joints along the cutting path")
    fig.savefig(path, dpi=110)
    return path


def main(quick: bool = False) -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.load_robot(ROBOT)
    n = QUICK_POINTS if quick else N_POINTS
    targets = paths.nguyen_contour(n)
    print(f"{ROBOT}: representative closed contour, {len(targets)} points (the paper's path is "
          f"a figure only); IK tolerance {IK_TOL:g}, q_start {Q_START}")
    results = solve_paths(robot, targets)
    print_table(results)
    written = [plot_path(robot, results, OUT / "nguyen_fig9_path.png"),
               plot_errors(results, OUT / "nguyen_fig10_11_errors.png"),
               plot_joints(robot, results, OUT / "nguyen_fig12_13_joints.png")]
    jp = results["ipopt"]
    for jump in jp.jumps:
        print(f"  IPOPT path jump at {jump} (sample more finely: N_POINTS)")
    if jp.unsolved:
        print("IPOPT joint path not timed: " + "; ".join(jp.problems()[:3]))
    else:
        traj = time_parameterize(jp, robot, method="toppra", allow_jumps=bool(jp.jumps))
        ratios = traj.check_limits()
        print(f"IPOPT joint path timed by toppra: {traj.duration:.3f} s (largest limit ratio "
              f"{max(float(r.max()) for r in ratios.values()):.6f}; {traj.notes})")
        written.append(traj.plot(OUT / "nguyen_toppra.png",
                                 title=f"nguyen cutting path, toppra: {traj.duration:.3f} s"))
    for p in written:
        print(f"  wrote {p}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv[1:])
