"""inverted5: FK reference pose (Fig. 3) and the redundancy of its two z strokes.

Paper: ``shared/seeds/003_923abea74416c111.txt``. Lengths in inches in the paper.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

import scara_opt as so
from scara_opt.plots import draw_robot
from scara_opt.reports import Finding, PaperReport
from scara_opt.reports import verdicts as rules
from scara_opt.reports.cycle import add_cycle_finding

IN = 0.0254  # m per inch


def run(out: Path, quick: bool = False) -> PaperReport:
    """FK check, IK of one target from two starts (two stroke splits), closed form, figure."""
    robot = so.load_robot("inverted5")
    rep = PaperReport("inverted5", "inverted 5-DoF SCARA, two prismatic joints")
    q_ref = np.array([0.0, 0.0, 0.0, 0.0, 3.94 * IN])
    p = robot.position(q_ref) / IN
    verdict, rule = rules.within(float(np.abs(p - [7.87, 0.0, -3.94]).max()), 0.0, 1e-9)
    rep.findings.append(Finding("Fig. 3 reference pose q = (0, 0, 0, 0, 3.94 in)",
                                "(7.87, 0, -3.94) in", f"({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) in",
                                verdict, rule=rule + " in, per coordinate", basis="fk"))
    # one target, two preferred configurations: the strokes P1, P5 split the z move differently
    target = so.Target(np.array([9.0, 5.0, -3.0]) * IN)
    rows, results = [], []
    for label, q0 in (("q0: P1 = 0", [0.0, 0.5, 1.0, 0.0, 0.0]),
                      ("q0: P1 = 0.5 in, P5 = 2.5 in", [0.5 * IN, 0.5, 1.0, 0.0, 2.5 * IN])):
        res = so.solve_ik(robot, target, q0=q0)
        results.append(res)
        rows.append({"start": label, "status": res.status.value, "error_m": res.error,
                     "P1_in": res.q[0] / IN, "theta1_deg": np.degrees(res.q[1]),
                     "theta2_deg": np.degrees(res.q[2]), "theta3_deg": np.degrees(res.q[3]),
                     "P5_in": res.q[4] / IN})
    held = so.solve_ik(robot, target, method="analytic", fixed={"P1": 1.0 * IN})
    results.append(held)
    rows.append({"start": "closed form, P1 held at 1 in", "status": held.status.value,
                 "error_m": held.error, "P1_in": held.q[0] / IN,
                 "theta1_deg": np.degrees(held.q[1]), "theta2_deg": np.degrees(held.q[2]),
                 "theta3_deg": np.degrees(held.q[3]), "P5_in": held.q[4] / IN})
    table = pd.DataFrame(rows)
    rep.add_table("redundancy", table, out)
    total = (table["P1_in"] + table["P5_in"]).to_numpy()
    verdict, rule = rules.claim_of_reach(results)
    same = bool(np.ptp(total) <= 1e-9 / IN)
    split = (f"P1 + P5 = {total[0]:.3f} in in every row" if same else
             "P1 + P5 = " + ", ".join(f"{v:.3f}" for v in total) + " in")
    rep.findings.append(Finding(
        "IK of (9, 5, -3) in, from two starts and with P1 held",
        "geometric (atan2) planar solution",
        f"{sum(r.success for r in results)}/{len(results)} solved, max error "
        f"{table['error_m'].max():.1e} m", verdict,
        f"{split}; the split follows the start (nearest-to-q0 rule) or the held P1", rule,
        "ik"))
    rep.notes.append("P1 and P5 both move along z: infinitely many solutions. IPOPT picks the "
                     "one nearest to q0 (range-scaled); the closed form holds P1 at a given value.")
    ax = draw_robot(robot, q_ref, label="Fig. 3 pose")
    rep.figures.append(Path(out) / "inverted5_poses.png")
    res = so.solve_ik(robot, target, q0=[1.5 * IN, 0.5, 1.0, 0.0, 1.5 * IN])
    rep.animation = (robot, np.array([q_ref, res.q]), "inverted5: the Fig. 3 pose, then the IK "
                                                      "of (9, 5, -3) in")
    draw_robot(robot, res.q, ax=ax, color="C1", label="IK of (9, 5, -3) in",
               path=rep.figures[-1], title="inverted5 Fig. 3 pose and the IK of (9, 5, -3) in "
                                           "(228.6, 127, -76.2) mm, method auto")
    add_cycle_finding(robot, rep)
    return rep
