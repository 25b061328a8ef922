"""``scara-opt plan ROBOT --cell CELL``: one PTP around a cell's obstacles (kept out of cli.py).

Wired into :func:`scara_opt.cli.build_parser` by ``cli_plan.add_parser(sub)``; the cell
options (``--cell``, ``--margin``, ``--time-limit``, ``--seed``) are shared with ``cycle``
(:func:`add_cell_arguments`, :func:`cell_keywords`). Exit codes as every command's, and 1
when no path was found within the time limit (the message says what was tried).
"""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from scara_opt.cli_args import int_at_least, nonnegative, positive
from scara_opt.outputs import FORCE_HELP

if TYPE_CHECKING:
    from scara_opt.target import Target

#: the files ``plan`` writes into ``--out`` when asked, by option
FILES = {"csv": "plan.csv", "html": "plan.html"}

#: exit code when no path was found within the time limit (as ``ik`` not solving)
EXIT_NO_PATH = 1


def add_cell_arguments(p: argparse.ArgumentParser, required: bool = False) -> None:
    """``--cell FILE``, ``--margin MM``, ``--time-limit S`` and ``--seed N``."""
    p.add_argument("--cell", metavar="FILE", required=required,
                   help="cell file (TOML: obstacles in stated units); moves are planned "
                        "around its obstacles and proven clear of them")
    p.add_argument("--margin", type=nonnegative, default=0.0, metavar="MM",
                   help="clearance to keep from the cell [mm] (0)")
    p.add_argument("--time-limit", type=positive, default=1.0, metavar="S",
                   help="planning limit of each PTP around obstacles [s] (1)")
    p.add_argument("--seed", type=int_at_least(0), default=0, help="the planner's seed (0)")


def cell_keywords(args: argparse.Namespace) -> dict:
    """The ``cell=``, ``margin=``, ``time_limit=``, ``seed=`` of :func:`scara_opt.plan`."""
    from scara_opt.errors import InputError

    if args.cell is None:
        given = [o for o, v in (("--margin", args.margin), ("--seed", args.seed)) if v]
        if given:
            raise InputError(f"{' and '.join(given)} set(s) how to plan in a cell: give "
                             "--cell FILE, or drop them")
        return {}
    from scara_opt.collision.cell import load_cell

    return {"cell": load_cell(args.cell), "margin": args.margin / 1e3,
            "time_limit": args.time_limit, "seed": args.seed}


def cmd_plan(args: argparse.Namespace) -> int:
    """Plan one PTP from --start to --goal (joints) or --xyz (a tool position) in the cell."""
    import scara_opt as so
    from scara_opt.cli_args import joint_scale, joint_units
    from scara_opt.cli_pose import target_from_args
    from scara_opt.errors import InputError, NoPathFoundError
    from scara_opt.outputs import OutputDir, write_animation

    if (args.goal is None) == (args.xyz is None):
        raise InputError("give the goal as joints, --goal q..., or as a tool position, "
                         "--xyz X Y Z (one of them)")
    asked = [k for k in FILES if getattr(args, k)]
    if asked and args.out is None:
        raise InputError(f"--{' --'.join(asked)}: the files go into a folder; give it with "
                         "--out DIR")
    robot = so.load_robot(args.robot)
    scale = joint_scale(robot, args.deg, args.mm)
    start = robot.check_q(args.start, "--start") / scale
    if args.goal is not None:
        goal: Target | NDArray[np.float64] = robot.check_q(args.goal, "--goal") / scale
    else:
        goal = target_from_args(args, np.asarray(args.xyz, float) / (1e3 if args.mm else 1.0))
    kw = cell_keywords(args)
    try:
        traj = so.plan(robot, [so.PTP(goal)], start=start, **kw)
    except NoPathFoundError as exc:
        if args.json:
            print(json.dumps({"robot": robot.name, "status": "no_path", "message": str(exc),
                              "time_s": exc.time_s, "states": exc.states,
                              "checks": exc.checks}))
        else:
            print(f"no_path: {exc}")
        return EXIT_NO_PATH
    report = traj.check_collisions() if kw else None
    written = []
    if asked:
        with OutputDir(args.out, [FILES[k] for k in asked], args.force) as out:
            if args.csv:
                traj.to_csv(out / FILES["csv"], dt=args.dt)
            if args.html:
                write_animation(robot, traj, out / FILES["html"],
                                f"{robot.name}: PTP in {kw['cell'].name if kw else 'no cell'}")
        written = [str(out.final / FILES[k]) for k in asked]
    goal_q = traj.waypoints[-1] * scale
    if args.json:
        print(json.dumps({
            "robot": robot.name, "status": "solved", "duration_s": traj.duration,
            "goal": goal_q.tolist(), "q_units": joint_units(robot, args.deg, args.mm),
            "clearance_m": None if report is None else report.clearance,
            "compute_time_s": traj.compute_time_s, "notes": traj.notes, "files": written}))
        return 0
    units = joint_units(robot, args.deg, args.mm)
    print(f"solved: {robot.name} PTP to "
          + ", ".join(f"{n}={v:.6g} {u}" for n, v, u in zip(robot.joint_names, goal_q, units,
                                                            strict=True))
          + f" in {traj.duration:.4f} s (computed in {traj.compute_time_s * 1e3:.1f} ms)")
    if report is not None:
        print(f"  proven clear of {kw['cell'].name!r}: clearance >= "
              f"{report.clearance * 1e3:.3f} mm all along ({report.evaluations} checks)")
    print(f"  {traj.notes}")
    if written:
        print("wrote " + ", ".join(written))
    return 0


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Add the ``plan`` subcommand to the subparsers ``sub``; returns its parser."""
    from scara_opt.cli_pose import add_orientation_arguments

    p = sub.add_parser("plan", help="plan one PTP around a cell's obstacles, proven clear")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--start", type=float, nargs="+", required=True, metavar="q",
                   help="start joints, one per joint (rad and m, or --deg / --mm)")
    p.add_argument("--goal", type=float, nargs="+", metavar="q",
                   help="goal joints, one per joint (rad and m, or --deg / --mm)")
    p.add_argument("--xyz", type=float, nargs=3, metavar=("X", "Y", "Z"),
                   help="goal as a tool position (m, or mm with --mm); the nearest IK "
                        "solution clear of the cell")
    add_orientation_arguments(p)
    p.add_argument("--mm", action="store_true",
                   help="lengths (positions, prismatic joints) in mm instead of m")
    p.add_argument("--deg", action="store_true",
                   help="revolute joint values in degrees instead of radians")
    add_cell_arguments(p)
    p.add_argument("--out", help="folder for the files below")
    p.add_argument("--csv", action="store_true",
                   help=f"write the trajectory as {FILES['csv']} (t, q, qd, qdd)")
    p.add_argument("--dt", type=positive, default=0.001, help="CSV sampling step [s] (0.001)")
    p.add_argument("--html", action="store_true",
                   help=f"save {FILES['html']}: the motion and the cell in 3-D (view extra)")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    p.add_argument("--json", action="store_true", help="print JSON for scripts")
    p.set_defaults(func=cmd_plan)
    return p
