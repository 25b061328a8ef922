"""Beyond the papers: the standard pick-and-place cycle of each bundled robot.

The 25 / 305 / 25 mm cycle (up, across, down, and back), placed where the robot reaches it
on one elbow branch, timed by toppra (time-optimal), Ruckig along the path (jerk-limited)
and a quintic baseline within the robot's (assumed) joint limits
(:func:`scara_opt.motion.cycle_time`). None of the papers times a cycle: the row's verdict
is "beyond the paper". Where the robot has inertias, the row adds the toppra time under its
torque limits with 0, 1 and 2 kg at the tool (:func:`scara_opt.motion.cycle.cycle_with_payload`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from scara_opt.errors import InputError
from scara_opt.motion.cycle import cycle_time, cycle_with_payload
from scara_opt.reports import verdicts as rules

#: payloads of the cycle rows [kg], at the tool
PAYLOADS = (0.0, 1.0, 2.0)

if TYPE_CHECKING:
    from scara_opt.model.robot import Robot
    from scara_opt.reports import PaperReport


def add_cycle_finding(robot: Robot, rep: PaperReport) -> None:
    """Append the standard cycle's times to ``rep`` (a note when the robot cannot place it)."""
    from scara_opt.reports import Finding

    try:
        res = cycle_time(robot)
    except InputError as exc:  # too small a robot for the standard strokes
        rep.notes.append(f"standard 25/305/25 mm cycle not timed: {exc}")
        return
    ratio = max(float(v.max()) for v in res.trajectory.check_limits().values())
    t = res.durations
    loads = ""
    if robot.has_inertia:
        timed = {kg: cycle_with_payload(robot, res, kg) for kg in PAYLOADS}
        loads = ("; toppra under the (estimated) torque limits with " + ", ".join(
            f"{kg:g} kg: {tr.duration:.3f} s (torque ratio "
            f"{float(tr.check_limits()['torque'].max()):.2f})" for kg, tr in timed.items()))
    rep.findings.append(Finding(
        "standard pick-and-place cycle 25/305/25 mm", "not in the paper",
        f"toppra {t['toppra']:.3f} s, ruckig {t['ruckig']:.3f} s, quintic {t['quintic']:.3f} s; "
        f"largest ratio to a limit (toppra) {ratio:.3f}{loads}", rules.BEYOND,
        "placed where the arm reaches it on one elbow branch; the robot's joint limits "
        "(assumptions where the paper gives none)",
        "nothing to compare: the paper times no cycle", "timing"))
