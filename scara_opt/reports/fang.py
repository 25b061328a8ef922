"""fang: the quintic joint trajectories of Tables 2 and 3, then time-optimal and jerk-limited.

Paper: ``shared/seeds/004_bf70fd1cc4e521c8.txt``, Sec. 4. The tables are the Robotics
Toolbox's ``jtraj``: a quintic with zero velocity and acceleration at both ends, 36 samples at
τ = k/35 (angles in degrees, labelled "rad"; joint 3 in mm). The same two moves are then timed
within the robot's (assumed) joint limits three ways: the shortest quintic, TOPP-RA and Ruckig.
The paper's closed-form IK (eq. 10, arccos forms) is checked where it breaks (py < 0).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

import scara_opt as so
from scara_opt.reports import Finding, PaperReport, reference_data
from scara_opt.reports import verdicts as rules
from scara_opt.reports.cycle import add_cycle_finding
from scara_opt.trajectory.plot import plot_trajectories

METHODS = ("quintic", "toppra", "ruckig")
#: paper units (deg, deg, mm, deg) -> SI (rad, rad, m, rad)
TO_SI = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])
#: column suffixes of the paper's units, per joint
PAPER_UNITS = ("deg", "deg", "mm", "deg")


def table_check(robot: so.Robot) -> pd.DataFrame:
    """Our quintic at τ = k/35 against every row the paper prints, per table."""
    ref = reference_data("fang")
    tau = np.arange(ref["samples"]) / (ref["samples"] - 1)
    rows = []
    for table in ref["tables"]:
        Q = np.array([table["start"], table["end"]]) * TO_SI
        # the paper's normalised time (T = 1 s) exceeds our assumed limits: positions only
        ours = so.time_parameterize(Q, robot, method="quintic", duration=1.0,
                                    enforce_limits=False).sample(tau)[0]
        ours = ours / TO_SI
        printed = np.array(table["rows"])
        for k, row in enumerate(printed):
            rows.append({"table": table["table"], "row": k + 1, "tau": f"{k}/35",
                         **{f"paper_j{j + 1}_{u}": row[j] for j, u in enumerate(PAPER_UNITS)},
                         **{f"ours_j{j + 1}_{u}": ours[k, j] for j, u in enumerate(PAPER_UNITS)},
                         "max_abs_diff_deg_or_mm": float(np.abs(ours[k] - row).max())})
    return pd.DataFrame(rows)


def timing(robot: so.Robot, out: Path) -> tuple[pd.DataFrame, list[Path]]:
    """Durations of the two moves by the shortest quintic, toppra and ruckig, and figures."""
    rows, figures = [], []
    for table in reference_data("fang")["tables"]:
        Q = np.array([table["start"], table["end"]]) * TO_SI
        trajs = [so.time_parameterize(Q, robot, method=m) for m in METHODS]
        d = [tr.duration for tr in trajs]
        worst = max(float(r.max()) for tr in trajs for r in tr.check_limits().values())
        rows.append({"move": f"Table {table['table']}", "quintic_s": d[0], "toppra_s": d[1],
                     "ruckig_s": d[2], "toppra/quintic": d[1] / d[0],
                     "ruckig/quintic": d[2] / d[0], "largest_limit_ratio": worst})
        figures.append(plot_trajectories(
            trajs, out / f"fang_table{table['table']}_move.png",
            labels=["shortest quintic", "toppra", "ruckig"],
            title=f"fang Table {table['table']} move: shortest quintic vs TOPP-RA vs Ruckig"))
    return pd.DataFrame(rows), figures


#: payloads of the beyond-the-paper timing [kg], and rate limits lifted to let torque bind
PAYLOADS = (0.0, 1.0, 2.0)
LIFTED = 1e3


def payload_timing(robot: so.Robot) -> pd.DataFrame:
    """The Table 2 move, toppra with torque limits, a point payload at the tool (0, 1, 2 kg).

    Twice: within the assumed velocity/acceleration limits plus the (estimated) torque
    limits, and with the rate limits lifted (``LIFTED``) so that only torque limits the move.
    """
    table = reference_data("fang")["tables"][0]
    Q = np.array([table["start"], table["end"]]) * TO_SI
    rows = []
    for mass in PAYLOADS:
        row: dict = {"payload_kg": mass}
        for key, rate in (("assumed_limits", None), ("torque_only", LIFTED)):
            # None: the robot's own (assumed) limits
            traj = so.time_parameterize(Q, robot, payload=mass, vmax=rate, amax=rate)
            row[f"{key}_s"] = traj.duration
            row[f"{key}_max_torque_ratio"] = float(traj.check_limits()["torque"].max())
        rows.append(row)
    return pd.DataFrame(rows)


def paper_ik(px: float, py: float, L1: float = 0.2, L2: float = 0.2) -> tuple[float, float]:
    """fang eq. 10 read charitably: θ1 by its arccos forms, θ2 = ±arccos(...) [rad].

    Printed, θ2 = arccos(...) >= 0 always; here the sign that fits θ1 best is taken, so the
    only error left is the one ROBOTS.md names: arccos(px / r) cannot be negative, so every
    target with py < 0 is mirrored.
    """
    r = math.hypot(px, py)
    t1 = math.acos((r * r + L1 * L1 - L2 * L2) / (2 * L1 * r)) + math.acos(px / r)
    t2 = math.acos(max(-1.0, min(1.0, (math.cos(t1) * px + math.sin(t1) * py - L1) / L2)))

    def miss(t: float) -> float:
        return math.hypot(L1 * math.cos(t1) + L2 * math.cos(t1 + t) - px,
                          L1 * math.sin(t1) + L2 * math.sin(t1 + t) - py)

    return t1, min((t2, -t2), key=miss)


def run(out: Path, quick: bool = False) -> PaperReport:
    """Tables 2-3 check, timing comparison, eq. 10 check."""
    robot = so.load_robot("fang")
    rep = PaperReport("fang", "Adept-like 4-DoF SCARA: closed form and quintic trajectories")
    check = table_check(robot)
    rep.add_table("tables2_3_check", check, out)
    tol = reference_data("fang")["tolerance"]
    for table, grp in check.groupby("table"):
        dev = float(grp["max_abs_diff_deg_or_mm"].max())
        verdict, rule = rules.within(dev, 0.0, tol)
        rep.findings.append(Finding(
            f"Table {table}: {len(grp)} printed rows (deg, mm)", "jtraj quintic, 4 decimals",
            f"largest deviation {dev:.1e}", verdict,
            f"tolerance {tol:g} (the paper's rounding)", rule + " (deg or mm), every row",
            "timing"))
    times, figures = timing(robot, out)
    move = reference_data("fang")["tables"][0]
    toppra = so.time_parameterize(np.array([move["start"], move["end"]]) * TO_SI, robot)
    rep.animation = (robot, toppra, f"fang Table {move['table']} move, toppra: "
                                    f"{toppra.duration:.3f} s")
    rep.add_table("timing", times, out)
    rep.figures += figures
    for _, row in times.iterrows():
        rep.findings.append(Finding(
            f"{row['move']} move, timed within the limits", "quintic of the paper's duration",
            f"toppra {row['toppra_s']:.3f} s, ruckig {row['ruckig_s']:.3f} s vs shortest quintic "
            f"{row['quintic_s']:.3f} s ({row['toppra/quintic']:.2f}x, "
            f"{row['ruckig/quintic']:.2f}x)",
            rules.BEYOND, "time-optimal and jerk-limited timings within the same (assumed) "
            f"limits; largest ratio to a limit {row['largest_limit_ratio']:.3f}",
            "nothing to compare: the paper times the moves only as quintics", "timing"))
    pay = payload_timing(robot)
    rep.add_table("payload_timing", pay, out)
    rep.findings.append(Finding(
        "Table 2 move with a payload at the tool, " + ", ".join(f"{m:g}" for m in PAYLOADS)
        + " kg", "not in the paper (no dynamics)",
        "within the assumed limits plus torque: " + ", ".join(
            f"{d:.3f}" for d in pay["assumed_limits_s"]) + " s (largest torque ratio "
        f"{pay['assumed_limits_max_torque_ratio'].max():.2f}); torque only (rate limits "
        f"lifted): " + ", ".join(f"{d:.3f}" for d in pay["torque_only_s"]) + " s",
        rules.BEYOND, "torque-limited TOPP-RA with Pinocchio's RNEA, gravity included; masses, "
        "inertias and torque limits are estimates (robots/fang.toml), checked at 1 kHz",
        "nothing to compare: the paper has no masses or torques", "timing"))
    q = np.array([-0.9, 1.2, 0.01, 0.3])
    p = robot.position(q)
    t1, t2 = paper_ik(p[0], p[1])
    miss = float(np.linalg.norm(robot.position([t1, t2, q[2], 0.0])[:2] - p[:2]))
    ours = so.ik_all(robot, p)
    ours_error = max((b.error for b in ours), default=float("inf"))
    # the paper's formula is wrong where it misses and ours, checked by FK, reaches
    wrong = miss > 1e-6 and bool(ours) and ours_error <= 1e-9
    verdict = rules.INCONSISTENT if wrong else rules.MATCHED if miss <= 1e-6 else rules.DIFFERS
    rep.findings.append(Finding(
        f"eq. 10 closed form at ({p[0]:.3f}, {p[1]:.3f}) m (py < 0)", "arccos forms",
        f"eq. 10 misses by {miss * 1000:.1f} mm; atan2 forms: {len(ours)} branches, error "
        f"{ours_error:.1e} m", verdict,
        "arccos(px/r) and arccos(...) lose the sign for py < 0 / negative angles",
        "paper inconsistent if eq. 10 misses by > 1e-6 m where our closed form reaches the "
        "point to 1e-9 m (checked by FK); matched if eq. 10 reaches it", "ik"))
    rep.notes.append("Table 3 starts at (+64.4042, 128.8085, 15.15, +61.4099), not at the end "
                     "of Table 2 (-64.4042, ..., -61.4099): kept as printed.")
    rep.notes.append("Velocity and acceleration limits are assumptions (robots/fang.toml); "
                     "ruckig's jerk limit is 10/s x amax.")
    add_cycle_finding(robot, rep)
    return rep
