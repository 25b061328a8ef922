"""``scara-opt plan ROBOT --start q... --goal q... | --xyz X Y Z``: one PTP, in a cell if asked.

The goal is joints (``--goal``) or a tool position (``--xyz``, with ``--yaw``, ``--rpy`` or
``--quat``); with ``--cell`` the PTP goes around the cell's obstacles and is proven clear.
A whole program (approach, LIN down, lift, around a fixture, place) is ``scara-opt run``.
Exit codes as every command's, and 1 when no path was found within the time limit (the
message says what was tried).
"""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from scara_opt.cli.args import (
    add_cell_arguments,
    add_limit_options,
    add_objective,
    add_robot,
    add_units,
    cell_keywords,
    joint_limits,
    joint_scale,
    joint_units,
    load_robot,
    nonnegative,
)
from scara_opt.cli.exports import add_export_options, asked, write_exports

if TYPE_CHECKING:
    from scara_opt.target import Target

#: the stem of the files ``plan`` writes
STEM = "plan"

#: exit code when no path was found within the time limit (as ``ik`` not solving)
EXIT_NO_PATH = 1


def no_path(robot_name: str, exc: Exception, as_json: bool) -> int:
    """Say that no path was found (text or JSON); returns :data:`EXIT_NO_PATH`."""
    if as_json:
        print(json.dumps({"robot": robot_name, "status": "no_path", "message": str(exc),
                          "time_s": getattr(exc, "time_s", None),
                          "states": getattr(exc, "states", None),
                          "checks": getattr(exc, "checks", None)}))
    else:
        print(f"no_path: {exc}")
    return EXIT_NO_PATH


def cmd_plan(args: argparse.Namespace) -> int:
    """Plan one PTP from --start to --goal (joints) or --xyz (a tool position) in the cell."""
    from scara_opt.cli.orientation import target_from_args
    from scara_opt.errors import InputError, NoPathFoundError
    from scara_opt.motion.moves import PTP
    from scara_opt.motion.plan import plan

    if (args.goal is None) == (args.xyz is None):
        raise InputError("give the goal as joints, --goal q..., or as a tool position, "
                         "--xyz X Y Z (one of them)")
    asked(args, STEM)  # --out given if a file is asked for: before any work
    robot = load_robot(args)
    joint = joint_limits(args, robot, need_jerk=False)
    scale = joint_scale(robot, args.deg, args.mm)
    start = robot.check_q(args.start, "--start") / scale
    if args.goal is not None:
        goal: Target | NDArray[np.float64] = robot.check_q(args.goal, "--goal") / scale
    else:
        goal = target_from_args(args, np.asarray(args.xyz, float) / (1e3 if args.mm else 1.0))
    kw = cell_keywords(args, robot)
    try:
        traj = plan(robot, [PTP(goal)], start=start, vmax=joint.vmax, amax=joint.amax,
                    payload=args.payload, objective=args.objective, **kw)
    except NoPathFoundError as exc:
        return no_path(robot.name, exc, args.json)
    report = traj.check_collisions() if kw else None
    cell = kw["cell"].cell.name if kw else None
    written = write_exports(args, STEM, robot, traj,
                            f"{robot.name}: PTP in {cell or 'no cell'}")
    goal_q = traj.waypoints[-1] * scale
    units = joint_units(robot, args.deg, args.mm)
    if args.json:
        print(json.dumps({
            "robot": robot.name, "status": "solved", "duration_s": traj.duration,
            "objective": traj.objective, "lower_bound_s": traj.lower_bound,
            "bound_ratio": traj.bound_ratio,
            "goal": goal_q.tolist(), "q_units": units, "cell": cell,
            "least_clearance_m": None if report is None or report.least is None
            else report.least.distance,
            "proven_clearance_m": None if report is None else report.clearance,
            "compute_time_s": traj.compute_time_s, "notes": traj.notes,
            "files": [str(f) for f in written]}))
        return 0
    print(f"solved: {robot.name} PTP to "
          + ", ".join(f"{n}={v:.6g} {u}" for n, v, u in zip(robot.joint_names, goal_q, units,
                                                            strict=True))
          + f" in {traj.duration:.4f} s (computed in {traj.compute_time_s * 1e3:.1f} ms)")
    print(f"  objective {traj.objective}: lower bound {traj.lower_bound:.4f} s (the slowest "
          f"joint's own time-optimal move), duration / bound {traj.bound_ratio:.3f} "
          f"({traj.duration - traj.lower_bound:+.4f} s)")
    if report is not None:
        print(f"  proven clear of {cell!r}: {report.clearance_text()} "
              f"({report.evaluations} checks)")
    print(f"  {traj.notes}")
    if written:
        print("wrote " + ", ".join(str(f) for f in written))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``plan`` to the subparsers ``sub``."""
    from scara_opt.cli.orientation import add_orientation_arguments

    p = sub.add_parser("plan", parents=parents,
                       help="plan one PTP around a cell's obstacles, proven clear")
    add_robot(p)
    p.add_argument("--start", type=float, nargs="+", required=True, metavar="q",
                   help="start joints, one per joint (rad and m, or --deg / --mm)")
    p.add_argument("--goal", type=float, nargs="+", metavar="q",
                   help="goal joints, one per joint (rad and m, or --deg / --mm)")
    p.add_argument("--xyz", type=float, nargs=3, metavar=("X", "Y", "Z"),
                   help="goal as a tool position (m, or mm with --mm); the nearest IK "
                        "solution clear of the cell")
    add_orientation_arguments(p)
    add_limit_options(p)
    p.add_argument("--payload", type=nonnegative, metavar="KG",
                   help="time it with KG at the tool under the robot's torque limits (needs "
                        "its inertias)")
    add_cell_arguments(p)
    add_objective(p)
    add_units(p)
    add_export_options(p, STEM)
    p.set_defaults(func=cmd_plan)
