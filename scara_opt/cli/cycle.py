"""``scara-opt cycle ROBOT``: time the standard pick-and-place cycle (kept out of cli.py).

Wired into :func:`scara_opt.cli.build_parser` by ``cli_motion.add_parser(sub)``. Its files go
into ``--out`` as every command's do (never overwritten unasked: ``--force``).
"""

from __future__ import annotations

import argparse
import json

from scara_opt.cli_args import add_limit_options, joint_limits
from scara_opt.cli_args import nonnegative as _nonnegative
from scara_opt.cli_args import positive as _positive
from scara_opt.cli_plan import add_cell_arguments, cell_keywords
from scara_opt.outputs import FORCE_HELP

#: the files ``cycle`` writes into ``--out`` when asked, by option
FILES = {"csv": "cycle.csv", "ros": "cycle_ros.yaml", "plot": "cycle.png", "html": "cycle.html"}


def cmd_cycle(args: argparse.Namespace) -> int:
    """Place and time the cycle; print the times; write CSV / ROS YAML / figure / 3-D view."""
    import scara_opt as so
    from scara_opt.errors import InputError
    from scara_opt.motion.cycle import check_cycle_blend, cycle_time, cycle_with_payload
    from scara_opt.motion.plot import plot_motion
    from scara_opt.outputs import OutputDir, write_animation

    asked = [k for k in FILES if getattr(args, k)]
    if asked and args.out is None:
        raise InputError(f"--{' --'.join(asked)}: the files go into a folder; give it with "
                         "--out DIR")
    robot = so.load_robot(args.robot)
    joint = joint_limits(args, robot, need_jerk=False)  # before any IK
    check_cycle_blend(args.blend, args.up, args.across, args.down, "mm", 1.0, "--blend")
    limits = None
    if args.speed is not None or args.acceleration is not None:
        limits = so.ToolLimits(speed=args.speed, acceleration=args.acceleration)
    res = cycle_time(robot, args.up / 1e3, args.across / 1e3, args.down / 1e3, limits,
                     args.blend / 1e3, vmax=joint.vmax, amax=joint.amax,
                     **cell_keywords(args))
    traj = res.trajectory
    loaded = (None if args.payload is None
              else cycle_with_payload(robot, res, args.payload, limits))
    written = []
    if asked:
        with OutputDir(args.out, [FILES[k] for k in asked], args.force) as out:
            if args.csv:
                traj.to_csv(out / FILES["csv"], dt=args.dt)
            if args.ros:
                traj.to_ros_yaml(out / FILES["ros"], dt=args.dt)
            if args.plot:
                plot_motion(robot, traj, out / FILES["plot"], title=res.title)
            if args.html:
                write_animation(robot, traj, out / FILES["html"], res.title.replace("\n", "; "))
        written = [str(out.final / FILES[k]) for k in asked]
    if args.json:
        print(json.dumps({"robot": robot.name, "up_mm": args.up, "across_mm": args.across,
                          "down_mm": args.down, "blend_mm": args.blend,
                          "pick_m": res.pick.tolist(),
                          "place_m": res.place.tolist(), "cycle_s": res.durations,
                          "payload_kg": args.payload,
                          "payload_toppra_s": None if loaded is None else loaded.duration,
                          "files": written}))
        return 0
    blend = f", toppra_blended: upper corners within {args.blend:g} mm" if args.blend else ""
    print(f"{robot.name}: pick-and-place cycle {args.up:g}/{args.across:g}/{args.down:g} mm"
          f"{blend}, pick at {[round(float(v), 4) for v in res.pick]} m, place at "
          f"{[round(float(v), 4) for v in res.place]} m")
    for method, seconds in res.durations.items():
        print(f"  {method:14s} {seconds:8.4f} s")
    ratios = traj.check_limits()
    which = "toppra_blended" if args.blend else "toppra"
    ratios.pop("clearance", None)  # (planned in a cell: said below)
    print(f"  worst limit ratio ({which}, joints exact, tool at 1 kHz): "
          f"{max(float(v.max()) for v in ratios.values()):.4f}")
    checker = traj.checker
    if checker is not None:
        print(f"  proven clear of {checker.cell.name!r} ({which}): clearance >= "
              f"{traj.check_collisions().clearance * 1e3:.3f} mm all along")
    if loaded is not None:
        torque = float(loaded.check_limits()["torque"].max())
        print(f"  {which} with {args.payload:g} kg at the tool, torque-limited: "
              f"{loaded.duration:8.4f} s (worst torque ratio {torque:.3f})")
    if written:
        print("wrote " + ", ".join(written))
    return 0


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Add the ``cycle`` subcommand to the subparsers ``sub``; returns its parser."""
    p = sub.add_parser("cycle", help="time the standard pick-and-place cycle (25/305/25 mm)")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--up", type=_positive, default=25.0, help="lift at the pick [mm] (25)")
    p.add_argument("--across", type=_positive, default=305.0,
                   help="horizontal stroke [mm] (305; shorter for small robots)")
    p.add_argument("--down", type=_positive, default=25.0, help="descent at the place [mm] (25)")
    p.add_argument("--blend", type=_nonnegative, default=0.0, metavar="MM",
                   help="also time toppra rounding the upper corners within this radius [mm] "
                        "instead of stopping there (at most half a vertical stroke; 0: no)")
    p.add_argument("--speed", type=_positive, help="tool speed limit on the LIN strokes [m/s]")
    p.add_argument("--acceleration", type=_positive,
                   help="tool acceleration limit on the LIN strokes [m/s²]")
    add_limit_options(p)
    p.add_argument("--payload", type=_nonnegative, metavar="KG",
                   help="also time it by toppra with KG at the tool under the robot's torque "
                        "limits (needs its inertias)")
    add_cell_arguments(p)
    p.add_argument("--out", help="folder for the files below")
    p.add_argument("--csv", action="store_true",
                   help=f"write the toppra trajectory as {FILES['csv']} (t, q, qd, qdd)")
    p.add_argument("--ros", action="store_true",
                   help=f"write it as ROS JointTrajectory-shaped YAML, {FILES['ros']}")
    p.add_argument("--dt", type=_positive, default=0.001, help="export sampling step [s] (0.001)")
    p.add_argument("--plot", action="store_true",
                   help=f"save {FILES['plot']}: tool speed and joint profiles")
    p.add_argument("--html", action="store_true",
                   help=f"save {FILES['html']}: a 3-D animation (needs the view extra)")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    p.add_argument("--json", action="store_true", help="print JSON for scripts")
    p.set_defaults(func=cmd_cycle)
    return p
