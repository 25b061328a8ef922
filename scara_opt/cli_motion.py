"""``scara-opt cycle ROBOT``: time the standard pick-and-place cycle (kept out of cli.py).

Wire it into :func:`scara_opt.cli.build_parser` with::

    from scara_opt import cli_motion
    cli_motion.add_parser(sub)
"""

from __future__ import annotations

import argparse
import json


def cmd_cycle(args: argparse.Namespace) -> int:
    """Place and time the cycle; print the times, write CSV / ROS YAML / figure if asked."""
    import scara_opt as so
    from scara_opt.motion.cycle import cycle_time
    from scara_opt.motion.plot import plot_motion

    robot = so.load_robot(args.robot)
    limits = None
    if args.speed is not None or args.acceleration is not None:
        limits = so.ToolLimits(speed=args.speed, acceleration=args.acceleration)
    res = cycle_time(robot, args.up / 1e3, args.across / 1e3, args.down / 1e3, limits)
    traj = res.trajectory
    if args.csv:
        traj.to_csv(args.csv, dt=args.dt)
    if args.ros:
        traj.to_ros_yaml(args.ros, dt=args.dt)
    if args.plot:
        plot_motion(robot, traj, args.plot, title=f"{robot.name}: {res!r}")
    if args.json:
        print(json.dumps({"robot": robot.name, "up_mm": args.up, "across_mm": args.across,
                          "down_mm": args.down, "pick_m": res.pick.tolist(),
                          "place_m": res.place.tolist(), "cycle_s": res.durations}))
        return 0
    print(f"{robot.name}: pick-and-place cycle {args.up:g}/{args.across:g}/{args.down:g} mm, "
          f"pick at {[round(float(v), 4) for v in res.pick]} m, place at "
          f"{[round(float(v), 4) for v in res.place]} m")
    for method, seconds in res.durations.items():
        print(f"  {method:8s} {seconds:8.4f} s")
    ratios = traj.check_limits()
    print(f"  worst limit ratio (toppra, joints exact, tool at 1 kHz): "
          f"{max(float(v.max()) for v in ratios.values()):.4f}")
    return 0


def _positive(text: str) -> float:
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0; got {text}")
    return value


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Add the ``cycle`` subcommand to the subparsers ``sub``; returns its parser."""
    p = sub.add_parser("cycle", help="time the standard pick-and-place cycle (25/305/25 mm)")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--up", type=_positive, default=25.0, help="lift at the pick [mm] (25)")
    p.add_argument("--across", type=_positive, default=305.0,
                   help="horizontal stroke [mm] (305; shorter for small robots)")
    p.add_argument("--down", type=_positive, default=25.0, help="descent at the place [mm] (25)")
    p.add_argument("--speed", type=_positive, help="tool speed limit on the LIN strokes [m/s]")
    p.add_argument("--acceleration", type=_positive,
                   help="tool acceleration limit on the LIN strokes [m/s²]")
    p.add_argument("--csv", help="write the toppra trajectory as CSV (t, q, qd, qdd)")
    p.add_argument("--ros", help="write it as ROS JointTrajectory-shaped YAML")
    p.add_argument("--dt", type=_positive, default=0.001, help="export sampling step [s] (0.001)")
    p.add_argument("--plot", help="save a PNG of tool speed and joint profiles")
    p.add_argument("--json", action="store_true", help="print JSON for scripts")
    p.set_defaults(func=cmd_cycle)
    return p
