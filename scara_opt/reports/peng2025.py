"""peng2025: FK at zero, the validation pose of eq. 21 (Figs. 8-10), the workspace (Figs. 3-6).

Paper: ``shared/seeds/001_b35f9d7865ac69db.txt``. Lengths in mm in the paper.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import scara_opt as so
from scara_opt.plots import draw_robot, root_figure
from scara_opt.reports import Finding, PaperReport
from scara_opt.reports import verdicts as rules
from scara_opt.reports.cycle import add_cycle_finding

#: eq. 21, rotated back into the paper's base frame (180° about x): position [mm], yaw 0
VALIDATION_MM = np.array([400.0, -120.0, 170.0])


def run(out: Path, quick: bool = False) -> PaperReport:
    """Checks of the FK, the validation pose and its two branches, and the workspace."""
    robot = so.load_robot("peng2025")
    rep = PaperReport("peng2025", "compact 4-DoF SCARA, prismatic joint first")
    p0 = robot.position(np.zeros(4)) * 1000
    verdict, rule = rules.within(float(p0[2]), 172.0, 1e-9)
    rep.findings.append(Finding("eq. 4.6 at zero joints: z = z0 + 172", "z = 172 mm",
                                f"z = {p0[2]:.3f} mm (x = {p0[0]:.1f} mm)", verdict,
                                rule=rule + " mm", basis="fk"))
    _validation(robot, rep, out)
    _workspace(robot, rep, out, quick)
    add_cycle_finding(robot, rep)
    return rep


def _validation(robot: so.Robot, rep: PaperReport, out: Path) -> None:
    target = so.Target(VALIDATION_MM / 1000, yaw=0.0)
    res = so.solve_ik(robot, target)
    verdict, rule = rules.claim_of_reach([res])
    rep.findings.append(Finding(
        "eq. 21 validation pose (400, -120, 170) mm, yaw 0", "two solution sets (Figs. 9-10)",
        f"{res.status.value} ({res.reason.value}), residual {res.error * 1000:.3f} mm",
        verdict, rules.proof_of(res) + " (z = 170 mm needs z0 = -2 mm: the paper's 'marginal J0 "
        "discrepancy' against ikunc)", rule, "ik"))
    widened = robot.with_limits(z0=(-0.005, 0.040))
    branches = so.ik_all(widened, target)
    rows = [{"branch": k + 1, "z0_mm": b.q[0] * 1000, "theta1_deg": np.degrees(b.q[1]),
             "theta2_deg": np.degrees(b.q[2]), "theta3_deg": np.degrees(b.q[3]),
             "error_m": b.error} for k, b in enumerate(branches)]
    rep.add_table("validation_branches", pd.DataFrame(rows), out)
    elbows = sorted({round(float(np.degrees(b.q[2])), 4) for b in branches})
    verdict, rule = rules.within(len(elbows), 2, 0)
    rep.findings.append(Finding(
        "same pose with the stroke widened to [-5, 40] mm", "two solution sets",
        f"{len(elbows)} elbow branches (theta2 = {', '.join(f'{e:g}' for e in elbows)} deg), "
        f"{len(branches)} solutions counting the +-360 deg wrist turns", verdict,
        "the wrist's +-360 deg range doubles each branch",
        "matched if the closed form finds exactly 2 elbow branches, each solved", "ik"))
    title = ("peng2025 Figs. 9-10: closed-form branches of the validation pose, "
             "stroke widened to [-5, 40] mm")
    ax = (draw_robot(widened, widened.lower, label="(no branch)", title=title)
          if not branches else None)
    for k, b in enumerate(branches[:2]):
        ax = draw_robot(widened, b.q, ax=ax, color=f"C{k}", title=title,
                        label=f"branch {k + 1}: theta2 = {np.degrees(b.q[2]):.4g} deg")
    if branches:
        rep.animation = (widened, np.array([b.q for b in branches[:2]]), title)
    path = out / "peng2025_fig9_fig10_branches.png"
    assert ax is not None  # drawn: the pose without a branch, or each branch
    root_figure(ax).savefig(path, dpi=120, bbox_inches="tight")
    rep.figures.append(path)


def _workspace(robot: so.Robot, rep: PaperReport, out: Path, quick: bool) -> None:
    try:
        from scara_opt.workspace_analysis import workspace
    except ImportError:  # pragma: no cover - the workspace module ships with the package
        rep.notes.append("workspace module not available")
        return
    n = 20_000 if quick else 60_000
    free = workspace(robot, n=n, seed=0, footprint=False)
    calibrated = workspace(robot, n=n, seed=0, footprint=True)
    rep.add_table("workspace", pd.DataFrame([
        {"model": "joint limits only (Figs. 3, 4)", "samples": len(free.points),
         "xy_area_m2": free.xy_area},
        {"model": "with base footprint (Fig. 6)", "samples": len(calibrated.points),
         "xy_area_m2": calibrated.xy_area}]), out)
    # the paper: Fig. 3 the XY projection, Fig. 4 the Monte Carlo cloud, Fig. 6 calibrated
    for name, ws in (("fig3_workspace", free), ("fig6_calibrated", calibrated)):
        rep.figures.append(ws.plot_xy(out / f"peng2025_{name}_xy.png"))
    rep.figures.append(free.plot_3d(out / "peng2025_fig4_monte_carlo_3d.png"))
    rep.findings.append(Finding(
        f"Monte Carlo workspace, N = {n:,}", "N = 60,000 (Fig. 4); calibrated (Fig. 6)",
        f"XY area {free.xy_area:.4f} m2, with the base zone {calibrated.xy_area:.4f} m2",
        rules.FIGURE_ONLY, "the paper gives figures, no numbers: compare the PNGs with its "
        "figures", "nothing to compare: no number in the paper", "workspace"))
