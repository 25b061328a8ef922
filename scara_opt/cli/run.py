"""``scara-opt run PROGRAM.toml``: a program file of PTP / LIN / CIRC moves, planned and timed.

The file (:mod:`scara_opt.motion.program_file`) names the robot, the cell, the units, the
start and the moves; the options below replace the file's robot, cell, margin, time limit
and seed, and add the robot options of the API (``--tip``, ``--vmax``, ``--amax``,
``--radius``, ``--payload``). Prints each move's duration and, in a cell, its least
clearance (proven); writes what ``plan`` writes (:mod:`scara_opt.cli.exports`). Exit 1
when no path was found within the time limit.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from scara_opt.cli.args import (
    add_cell_arguments,
    add_limit_options,
    add_objective,
    joint_limits,
    make_checker,
    nonnegative,
)
from scara_opt.cli.exports import add_export_options, asked, write_exports

#: the stem of the files ``run`` writes
STEM = "program"


def _checker(args: argparse.Namespace, program: Any) -> Any:
    """The checker of ``--cell`` or the file's cell (``None``: no cell), with the overrides.

    Raises:
        InputError: a cell option without a cell.
    """
    from scara_opt.errors import InputError

    cell = program.cell
    if args.cell is not None:
        from scara_opt.collision.cell import load_cell

        cell = load_cell(args.cell)
    if cell is None:
        given = [o for o, v in (("--margin", args.margin), ("--radius", args.radius),
                                ("--seed", args.seed), ("--time-limit", args.time_limit))
                 if v is not None]
        if given:
            raise InputError(f"{' and '.join(given)} set(s) how to plan in a cell, and "
                             f"{program.source!r} names none: give --cell FILE, or drop them")
        return None
    margin = program.margin if args.margin is None else args.margin / 1e3
    return make_checker(program.robot, cell, args, margin)


def _moves(program: Any, traj: Any) -> list[dict[str, Any]]:
    """Each move: index, type, label, duration [s], lower bound [s], least clearance [m].

    The lower bound where each move is a stop-to-stop run of its own (no blends), else
    ``None``; the least clearance in a cell, else ``None``.
    """
    spans = traj.move_spans()
    clearances = traj.move_clearances() if traj.checker is not None else None
    offset = len(program.moves) - len(traj.moves)  # a first PTP without start: the start
    rows = [{"index": i, "type": program.moves[i].kind, "label": program.labels[i],
             "duration_s": 0.0, "lower_bound_s": None, "least_clearance_m": None,
             "start": True}
            for i in range(offset)]
    if len(spans) != len(traj.moves):  # allow_flip split a move: no move-by-move account
        return rows
    own = len(traj.run_bounds) == len(spans)  # each move between two stops
    for k, (t0, t1) in enumerate(spans):
        i = k + offset
        clear = None if clearances is None else float(clearances[k])
        rows.append({"index": i, "type": program.moves[i].kind, "label": program.labels[i],
                     "duration_s": float(t1 - t0),
                     "lower_bound_s": float(traj.run_bounds[k]) if own else None,
                     "least_clearance_m": None if clear is None or math.isinf(clear) else clear,
                     "start": False})
    return rows


def cmd_run(args: argparse.Namespace) -> int:
    """Read the program file, plan it, print each move, write the files asked for."""
    from scara_opt.cli.plan import no_path
    from scara_opt.errors import NoPathFoundError
    from scara_opt.motion.program_file import load_program

    asked(args, STEM)  # --out given if a file is asked for: before any work
    program = load_program(args.program, robot=args.robot, tip=args.tip)
    joint = joint_limits(args, program.robot, need_jerk=False)
    checker = _checker(args, program)
    kw: dict[str, Any] = {"vmax": joint.vmax, "amax": joint.amax, "payload": args.payload}
    for key in ("time_limit", "seed", "objective"):
        if getattr(args, key) is not None:
            kw[key] = getattr(args, key)
    if args.time is not None:
        kw["method"] = args.time
    try:
        traj = program.plan(cell=checker, **kw)
    except NoPathFoundError as exc:
        return no_path(program.robot.name, exc, args.json)
    rows = _moves(program, traj)
    cell = None if traj.checker is None else traj.checker.cell.name
    report = None if traj.checker is None else traj.check_collisions()
    written = write_exports(args, STEM, program.robot, traj,
                            f"{program.name}: {program.robot.name}, {len(program.moves)} "
                            f"moves{f' in {cell}' if cell else ''}")
    if args.json:
        print(json.dumps({
            "program": program.name, "robot": program.robot.name, "status": "solved",
            "duration_s": traj.duration, "compute_time_s": traj.compute_time_s,
            "objective": traj.objective, "lower_bound_s": traj.lower_bound,
            "bound_ratio": traj.bound_ratio,
            "cell": cell, "least_clearance_m": None if report is None or report.least is None
            else report.least.distance,
            "proven_clearance_m": None if report is None else report.clearance,
            "moves": rows, "notes": traj.notes, "files": [str(f) for f in written]}))
        return 0
    where = (f"; proven clear of {cell!r}: {report.clearance_text()}"
             if report is not None else "")
    print(f"solved: {program.name!r} on {program.robot.name}, {len(program.moves)} moves in "
          f"{traj.duration:.4f} s{where} (planned in {traj.compute_time_s * 1e3:.0f} ms)")
    print(f"  objective {traj.objective}: lower bound {traj.lower_bound:.4f} s (each stop's "
          f"slowest joint alone), duration / bound {traj.bound_ratio:.3f} "
          f"({traj.duration - traj.lower_bound:+.4f} s)")
    for row in rows:
        name = f"move {row['index']} ({row['type']}{', ' + row['label'] if row['label'] else ''})"
        if row["start"]:
            print(f"  {name:28s} the start (its goal is where the program begins)")
            continue
        clear = ("" if row["least_clearance_m"] is None
                 else f"  least clearance {row['least_clearance_m'] * 1e3:.3f} mm")
        bound = ("" if row["lower_bound_s"] is None
                 else f"  (bound {row['lower_bound_s']:.4f} s)")
        print(f"  {name:28s} {row['duration_s']:8.4f} s{bound}{clear}")
    if len(rows) < len(program.moves):
        print(f"  (a move was split by allow_flip: {traj.notes})")
    if written:
        print("wrote " + ", ".join(str(f) for f in written))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``run`` to the subparsers ``sub``."""
    p = sub.add_parser("run", parents=parents,
                       help="plan and time a program file (TOML: PTP, LIN, CIRC moves)")
    p.add_argument("program", metavar="PROGRAM", help="program file (.toml)")
    p.add_argument("--robot", metavar="ROBOT",
                   help="run it on this robot (bundled name or .urdf/.toml path) instead of "
                        "the file's")
    p.add_argument("--tip", metavar="LINK", help="the tip frame of --robot")
    p.add_argument("--time", choices=["toppra", "ruckig"],
                   help="timing: toppra (time-optimal) or ruckig (jerk-limited); default the "
                        "file's method, else toppra")
    add_limit_options(p)
    p.add_argument("--payload", type=nonnegative, metavar="KG",
                   help="time it with KG at the tool under the robot's torque limits (needs "
                        "its inertias)")
    add_cell_arguments(p, from_file=True)
    add_objective(p, from_file=True)
    add_export_options(p, STEM)
    p.add_argument("--json", action="store_true", help="print JSON for scripts")
    p.set_defaults(func=cmd_run)
