"""nguyen: IK of the 5-DoF rail SCARA along a closed cutting contour, SFLA against IPOPT.

Paper: ``shared/seeds/002_e63e44ba374820ad.txt``, Sec. 4-5. The cutting path is given only
as a figure, so a representative contour stands in for it (:func:`scara_opt.paths.nguyen_contour`:
a rounded rectangle 0.20 m x 0.30 m in the arm's x-z plane, tool angle A = θ2 + θ3 + θ5 along
the direction of travel), inside the workspace of the joint limits assumed in
robots/nguyen.toml (the paper gives none). Each point is solved from the previous solution
(``ik_path``), so the redundant degree of freedom moves as little as possible. Figures:
Fig. 9 (path), Figs. 10-11 (errors), Figs. 12-13 (joints), Figs. 14-15 (postures), and the
IPOPT joint path timed by TOPP-RA (beyond the paper).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import scara_opt as so
from scara_opt import paths
from scara_opt.errors import TrajectoryError
from scara_opt.ik.registry import method_label
from scara_opt.plots import draw_robot, root_figure
from scara_opt.reports import Finding, PaperReport
from scara_opt.reports import verdicts as rules
from scara_opt.reports.cycle import add_cycle_finding
from scara_opt.trajectory import JointPath, ik_path, time_parameterize
from scara_opt.trajectory.plot import new_figure

N_POINTS = 120  # points along the contour (one more closes it)
QUICK_POINTS = 40
#: start of the path: rail 0.3 m, elbow bent, wrist 0 (the first point is solved from here)
Q_START = (0.3, 0.0, 1.5, 0.05, 0.0)
SEED = 0


def solve_paths(robot: so.Robot, targets: list[so.Target]) -> dict[str, JointPath]:
    """IK along the contour with IPOPT and SFLA (the paper's Table 2 settings)."""
    methods = ["ipopt"] + (["sfla"] if "sfla" in so.solvers() else [])
    return {m: ik_path(robot, targets, method=m, q_start=Q_START, seed=SEED,
                       objective="fewest_jumps") for m in methods}


def path_table(results: dict[str, JointPath]) -> pd.DataFrame:
    """Largest errors, solved points, jumps and time per method."""
    return pd.DataFrame([{
        "method": name, "solved": int(jp.solved.sum()), "points": len(jp),
        "max_position_error_m": float(np.linalg.norm(jp.position_error, axis=1).max()),
        "max_angle_error_rad": float(np.abs(jp.angle_error).max()), "jumps": len(jp.jumps),
        "time_s": jp.time_s} for name, jp in results.items()])


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
        ax.plot(tip[:, 0], tip[:, 2], ".", ms=4, label=f"tip, {method_label(name)}")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"nguyen Fig. 9 (representative contour): end-effector path, {len(P)} points")
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
            ax.semilogy(np.maximum(np.abs(values), 1e-18), ".-", ms=3, lw=0.6,
                        label=method_label(name))
    for ax, title in zip(axes, ("|x error| [m] (Fig. 10)", "|z error| [m] (Fig. 11)",
                                "|tool angle error| [rad]"), strict=True):
        ax.set_title(title)
        ax.set_xlabel("point")
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize="small")
    n = len(next(iter(results.values())))
    fig.suptitle(f"nguyen Figs. 10-11: errors along the cutting contour ({n} points), "
                 "log scale, exact zeros drawn at 1e-18")
    fig.savefig(path, dpi=110)
    return path


def plot_joints(robot: so.Robot, results: dict[str, JointPath], path: Path) -> Path:
    """Figs. 12-13: rail position, then θ2, θ3, θ5 (and d4) along the path."""
    fig = new_figure(1, robot.nq, size=(3.2, 3.0))
    axes = fig.subplots(1, robot.nq)
    for name, jp in results.items():
        for k, ax in enumerate(axes):
            scale = np.degrees(1.0) if robot.joint_types[k] == "revolute" else 1000.0
            ax.plot(jp.q[:, k] * scale, ".-", ms=3, lw=0.6, label=method_label(name))
    for k, ax in enumerate(axes):
        unit = "deg" if robot.joint_types[k] == "revolute" else "mm"
        ax.set_title(f"{robot.joint_names[k]} [{unit}]")
        ax.set_xlabel("point")
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize="small")
    fig.suptitle("nguyen Figs. 12-13: joints along the cutting path")
    fig.savefig(path, dpi=110)
    return path


def plot_postures(robot: so.Robot, jp: JointPath, path: Path) -> Path:
    """Figs. 14-15: a few postures of the arm along the path."""
    ax = None
    for k, idx in enumerate(np.linspace(0, len(jp) - 1, 4).astype(int)):
        ax = draw_robot(robot, jp.q[idx], ax=ax, color=f"C{k}", label=f"point {idx + 1}",
                        title=f"nguyen Figs. 14-15: postures along the cutting contour "
                              f"({len(jp)} points, IPOPT)")
    assert ax is not None, "four postures drawn"
    root_figure(ax).savefig(path, dpi=110, bbox_inches="tight")
    return path


def _sfla_why(row: pd.Series) -> str:
    """The SFLA row's explanation, from its settings and its outcome."""
    o = so.get_solver("sfla").options
    settings = (f"the paper's Table 2 read as m = {o['memeplexes']} memeplexes, population "
                f"{o['population']}, {o['iterations']} leaps per memeplex, C = {o['leap']}")
    if row["solved"] == row["points"]:
        return f"{settings}: every point within 1e-9"
    return (f"{settings}: {row['points'] - row['solved']} of {row['points']} points stop "
            f"above 1e-9 (largest |dp| {row['max_position_error_m']:.1e} m)")


def run(out: Path, quick: bool = False) -> PaperReport:
    """The contour by IPOPT and SFLA, errors, joints, postures, timing; findings."""
    robot = so.load_robot("nguyen")
    rep = PaperReport("nguyen", "5-DoF SCARA on a rail: SFLA along a cutting path")
    out.mkdir(parents=True, exist_ok=True)
    targets = paths.nguyen_contour(QUICK_POINTS if quick else N_POINTS)
    results = solve_paths(robot, targets)
    table = path_table(results)
    rep.add_table("cutting_path", table, out)
    rep.figures += [plot_path(robot, results, out / "nguyen_fig9_path.png"),
                    plot_errors(results, out / "nguyen_fig10_11_errors.png"),
                    plot_joints(robot, results, out / "nguyen_fig12_13_joints.png"),
                    plot_postures(robot, results["ipopt"], out / "nguyen_fig14_15_postures.png")]
    for _, row in table.iterrows():
        rep.findings.append(Finding(
            f"Figs. 10-11, {method_label(row['method'])} along {row['points']} contour points",
            "'very small' errors (figures only)",
            f"{row['solved']}/{row['points']} within 1e-9; largest |dp| "
            f"{row['max_position_error_m']:.2e} m, |dA| {row['max_angle_error_rad']:.2e} rad, "
            f"{row['jumps']} joint jumps", rules.FIGURE_ONLY,
            _sfla_why(row) if row["method"] == "sfla" else "the exact reference",
            "nothing to compare: the paper shows the errors only as figures", "ik"))
    jp = results["ipopt"]
    rep.animation = (robot, jp, f"nguyen: IPOPT along the cutting contour ({len(jp)} points)")
    try:
        traj = time_parameterize(jp, robot, method="toppra", allow_jumps=bool(jp.jumps))
    except TrajectoryError as exc:
        rep.notes.append(f"IPOPT joint path not timed by toppra: {exc}")
    else:
        rep.figures.append(traj.plot(out / "nguyen_toppra.png",
                                     title=f"nguyen cutting path, toppra: {traj.duration:.3f} s"))
        rep.notes.append(f"IPOPT joint path timed by toppra within the assumed limits: "
                         f"{traj.duration:.3f} s")
        rep.animation = (robot, traj, f"nguyen: the cutting contour, toppra, "
                                      f"{traj.duration:.3f} s")
    rep.notes.append("The contour is representative (the paper shows it only as a figure); the "
                     "joint limits are assumptions (robots/nguyen.toml).")
    add_cycle_finding(robot, rep)
    return rep
