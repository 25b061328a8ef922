# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""inverted5: the redundant inverted SCARA with two vertical strokes (P1 and P5).

Needs: the base install only (``pip install scara-opt``).

Reproduces the FK check of the inverted 5-DoF SCARA (robots/inverted5.toml [citation],
Fig. 3: q = (0, 0, 0, 0, 3.94 in) puts the tip at (7.87, 0, -3.94) in), then shows what the
redundancy means for IK: one target, reached with the z move split differently between the
two strokes, chosen by ``q0`` (IPOPT's rule: the solution nearest to ``q0``) or held with the
closed form's ``fixed=``. Prints the table (inches and degrees at this edge); saves the poses
into ``examples/out/inverted5_redundancy.png``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import scara_opt as so
from scara_opt.plots import draw_robot

IN = 0.0254  # m per inch: the paper's unit
OUT = Path(__file__).resolve().parent / "out"
TARGET = np.array([9.0, 5.0, -3.0]) * IN


def main() -> None:
    robot = so.load_robot("inverted5")
    tip = robot.position([0, 0, 0, 0, 3.94 * IN]) / IN
    print(f"Fig. 3 pose q = (0, 0, 0, 0, 3.94 in): tip at {np.round(tip, 6).tolist()} in "
          "(paper: (7.87, 0, -3.94) in)")
    answers = {f"ipopt, q0: P1 = {p1:g}, P5 = 0 in": so.solve_ik(
        robot, TARGET, method="ipopt", q0=[p1 * IN, 0.5, 1.0, 0.0, 0.0]) for p1 in (0.0, 1.0)}
    for p1 in (0.5, 1.5):
        answers[f"closed form, P1 held at {p1:g} in"] = so.solve_ik(
            robot, TARGET, method="analytic", fixed={"P1": p1 * IN})
    table = pd.DataFrame([{
        "route": route, "status": res.status.value, "error_m": res.error,
        "P1_in": res.q[0] / IN, "theta1_deg": np.degrees(res.q[1]),
        "theta2_deg": np.degrees(res.q[2]), "theta3_deg": np.degrees(res.q[3]),
        "P5_in": res.q[4] / IN, "P1+P5_in": (res.q[0] + res.q[4]) / IN}
        for route, res in answers.items()])
    reached = sum(res.success for res in answers.values())
    totals = table["P1+P5_in"].to_numpy()
    split = ("only the split of the z move between the strokes differs" if
             np.ptp(totals) <= 1e-9 / IN else "the strokes' totals differ")
    print(f"IK of {np.round(TARGET / IN, 3).tolist()} in: {reached} of {len(answers)} answers "
          f"reach it; {split} (IPOPT: nearest to q0, joint ranges as the scale)")
    print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    ax = None
    for k, (route, res) in enumerate(answers.items()):
        ax = draw_robot(robot, res.q, ax=ax, color=f"C{k}", label=route)
    OUT.mkdir(exist_ok=True)
    path = OUT / "inverted5_redundancy.png"
    ax.figure.savefig(path, dpi=120, bbox_inches="tight")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
