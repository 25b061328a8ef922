"""``scara-opt cycle ROBOT``: time the standard pick-and-place cycle, in a cell if asked.

Prints each method's time, the worst limit ratio and, with ``--cell``, the proven
clearance and why a method is missing or slow there (:attr:`~scara_opt.motion.cycle.
CycleResult.notes`). Its files go into ``--out`` as every command's do (never
overwritten unasked: ``--force``; :mod:`scara_opt.cli.exports`).
"""

from __future__ import annotations

import argparse
import json

from scara_opt.cli.args import (
    add_cell_arguments,
    add_limit_options,
    add_objective,
    add_robot,
    cell_keywords,
    joint_limits,
    load_robot,
    nonnegative,
    positive,
)
from scara_opt.cli.exports import add_export_options, asked, write_exports

#: the stem of the files ``cycle`` writes
STEM = "cycle"


def cmd_cycle(args: argparse.Namespace) -> int:
    """Place and time the cycle; print the times; write the files asked for."""
    from scara_opt.motion.cycle import check_cycle_blend, cycle_time, cycle_with_payload
    from scara_opt.motion.tool_limits import ToolLimits

    asked(args, STEM)  # --out given if a file is asked for: before any work
    robot = load_robot(args)
    joint = joint_limits(args, robot, need_jerk=False)  # before any IK
    check_cycle_blend(args.blend, args.up, args.across, args.down, "mm", 1.0, "--blend")
    limits = None
    if args.speed is not None or args.acceleration is not None:
        limits = ToolLimits(speed=args.speed, acceleration=args.acceleration)
    res = cycle_time(robot, args.up / 1e3, args.across / 1e3, args.down / 1e3, limits,
                     args.blend / 1e3, vmax=joint.vmax, amax=joint.amax,
                     objective=args.objective, **cell_keywords(args, robot))
    traj = res.trajectory
    loaded = (None if args.payload is None
              else cycle_with_payload(robot, res, args.payload, limits))
    written = write_exports(args, STEM, robot, traj, res.title)
    if args.json:
        print(json.dumps({"robot": robot.name, "up_mm": args.up, "across_mm": args.across,
                          "down_mm": args.down, "blend_mm": args.blend,
                          "pick_m": res.pick.tolist(), "objective": args.objective,
                          "lower_bound_s": res.lower_bound,
                          "bound_ratio": res.durations["toppra"] / res.lower_bound,
                          "place_m": res.place.tolist(), "cycle_s": res.durations,
                          "cell": res.cell, "least_clearance_m": res.clearance,
                          "proven_clearance_m": None if res.cell is None else
                          traj.check_collisions().clearance,
                          "notes": list(res.notes),
                          "payload_kg": args.payload,
                          "payload_toppra_s": None if loaded is None else loaded.duration,
                          "files": [str(f) for f in written]}))
        return 0
    blend = f", toppra_blended: upper corners within {args.blend:g} mm" if args.blend else ""
    print(f"{robot.name}: pick-and-place cycle {args.up:g}/{args.across:g}/{args.down:g} mm"
          f"{blend}, pick at {[round(float(v), 4) for v in res.pick]} m, place at "
          f"{[round(float(v), 4) for v in res.place]} m")
    for method, seconds in res.durations.items():
        print(f"  {method:14s} {seconds:8.4f} s")
    print(f"  lower bound    {res.lower_bound:8.4f} s (each stop's slowest joint alone; "
          f"toppra / bound {res.durations['toppra'] / res.lower_bound:.3f}, objective "
          f"{args.objective})")
    ratios = traj.check_limits()
    which = "toppra_blended" if args.blend else "toppra"
    ratios.pop("clearance", None)  # (planned in a cell: said below)
    print(f"  worst limit ratio ({which}, joints exact, tool at 1 kHz): "
          f"{max(float(v.max()) for v in ratios.values()):.4f}")
    if res.cell is not None and res.clearance is not None:
        print(f"  proven clear of {res.cell!r} ({which}): "
              f"{traj.check_collisions().clearance_text()}")
    for note in res.notes:
        print(f"  note: {note}")
    if loaded is not None:
        torque = float(loaded.check_limits()["torque"].max())
        print(f"  {which} with {args.payload:g} kg at the tool, torque-limited: "
              f"{loaded.duration:8.4f} s (worst torque ratio {torque:.3f})")
    if written:
        print("wrote " + ", ".join(str(f) for f in written))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``cycle`` to the subparsers ``sub``."""
    p = sub.add_parser("cycle", parents=parents,
                       help="time the standard pick-and-place cycle (25/305/25 mm)")
    add_robot(p)
    p.add_argument("--up", type=positive, default=25.0, help="lift at the pick [mm] (25)")
    p.add_argument("--across", type=positive, default=305.0,
                   help="horizontal stroke [mm] (305; shorter for small robots)")
    p.add_argument("--down", type=positive, default=25.0, help="descent at the place [mm] (25)")
    p.add_argument("--blend", type=nonnegative, default=0.0, metavar="MM",
                   help="also time toppra rounding the upper corners within this radius [mm] "
                        "instead of stopping there (at most half a vertical stroke; 0: no)")
    p.add_argument("--speed", type=positive, help="tool speed limit on the LIN strokes [m/s]")
    p.add_argument("--acceleration", type=positive,
                   help="tool acceleration limit on the LIN strokes [m/s²]")
    add_limit_options(p)
    p.add_argument("--payload", type=nonnegative, metavar="KG",
                   help="also time it by toppra with KG at the tool under the robot's torque "
                        "limits (needs its inertias)")
    add_cell_arguments(p)
    add_objective(p)
    add_export_options(p, STEM)
    p.add_argument("--json", action="store_true", help="print JSON for scripts")
    p.set_defaults(func=cmd_cycle)
