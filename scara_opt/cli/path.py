"""``scara-opt path ROBOT --circle ... | --line ...``: IK along a path, then its timing.

Writes ``joint_path.csv`` (kept even when the path is refused for a jump),
``trajectory.csv``, ``trajectory.png`` and, with ``--html``, ``path.html`` into ``--out``.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from scara_opt.cli.args import (
    add_limit_options,
    add_out,
    add_robot,
    add_units,
    degrees,
    int_at_least,
    joint_limits,
    joint_scale,
    load_robot,
)
from scara_opt.cli.outputs import OutputDir, write_animation

#: the 3-D animation ``--html`` writes into ``--out``
HTML = "path.html"


def _yaw_arg(text: str) -> float | str:
    """``--yaw`` of a path: degrees, or ``tangent``."""
    if text == "tangent":
        return text
    try:
        float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'tangent', got {text!r}") from None
    return math.radians(degrees(text))


def _path_targets(args: argparse.Namespace) -> list[Any]:
    """The path's targets in SI from --circle CX CY R Z or --line X0 Y0 Z0 X1 Y1 Z1."""
    from scara_opt import paths

    L = 1000.0 if args.mm else 1.0
    if args.circle:
        cx, cy, r, z = (v / L for v in args.circle)
        return paths.circle((cx, cy), r, z, n=args.n, yaw=args.yaw)
    xyz = np.asarray(args.line, float) / L
    return paths.line(xyz[:3], xyz[3:], args.n, yaw=args.yaw)


def write_joint_path(jp: Any, robot: Any, path: Path) -> None:
    """One CSV row per path point: target, status, residual and q, in SI units."""
    import pandas as pd

    units = ["rad" if t == "revolute" else "m" for t in robot.joint_types]
    rows = []
    for i, (t, res) in enumerate(zip(jp.targets, jp.results, strict=True)):
        row: dict[str, Any] = {"point": i, "x_m": t.position[0], "y_m": t.position[1],
                               "z_m": t.position[2], "status": res.status.value,
                               "error_m_rad": res.error}
        row.update({f"{n}_{u}": v for n, u, v in zip(robot.joint_names, units, res.q,
                                                     strict=True)})
        rows.append(row)
    pd.DataFrame(rows).to_csv(path, index=False)


def cmd_path(args: argparse.Namespace) -> int:
    """IK along a circle or a line, then time the joint path: CSV tables and a figure."""
    from scara_opt.trajectory import ik_path, time_parameterize

    robot = load_robot(args)
    q_start = None
    if args.q_start is not None:
        q_start = robot.check_q(args.q_start, "--q-start") / joint_scale(robot, args.deg,
                                                                          args.mm)
    targets = _path_targets(args)
    limits = joint_limits(args, robot, need_jerk=args.time == "ruckig")  # before any IK
    names = ["joint_path.csv", "trajectory.csv", "trajectory.png"] + ([HTML] if args.html
                                                                      else [])
    with OutputDir(args.out, names, args.force, last=["trajectory.csv"]) as out:
        # a circle or line to follow: the fewest jumps first, then the least travel
        jp = ik_path(robot, targets, method=args.method, q_start=q_start, seed=args.seed,
                     tol=args.tol, objective="fewest_jumps")
        write_joint_path(jp, robot, out / "joint_path.csv")
        out.commit()  # joint_path.csv is kept when the path is refused below
        if not args.json:
            print(jp.summary())
        jp.raise_if_invalid(allow_jumps=args.allow_jumps)  # exit 2
        traj = time_parameterize(jp, robot, method=args.time, vmax=limits.vmax,
                                 amax=limits.amax, jmax=limits.jmax,
                                 allow_jumps=args.allow_jumps)
        traj.to_csv(out / "trajectory.csv")
        traj.plot(out / "trajectory.png")
        if args.html:
            write_animation(robot, traj, out / HTML, f"{robot.name}: {len(jp)}-point "
                            f"path, {args.time} {traj.duration:.3f} s")
    files = [out.final / n for n in names]
    ratios = {k: float(np.max(v)) for k, v in traj.check_limits().items()}
    if args.json:
        print(json.dumps({
            "robot": robot.name, "method": jp.method, "timing": args.time, "points": len(jp),
            "solved": int(jp.solved.sum()), "max_error": float(jp.error.max()),
            "jumps": [j.index for j in jp.jumps], "duration_s": traj.duration,
            "limit_ratios": ratios, "files": [str(f) for f in files]}))
        return 0
    peaks = ", ".join(f"{k} {v:.3f}" for k, v in ratios.items())
    print(f"{args.time}: {traj.duration:.4f} s; largest ratio to the limits: {peaks}")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``path`` to the subparsers ``sub``."""
    p = sub.add_parser("path", parents=parents,
                       help="IK along a circle or line, then time it (CSV + figure)")
    add_robot(p)
    shape = p.add_mutually_exclusive_group(required=True)
    shape.add_argument("--circle", type=float, nargs=4, metavar=("CX", "CY", "R", "Z"),
                       help="horizontal circle: centre, radius, height (m, or mm with --mm)")
    shape.add_argument("--line", type=float, nargs=6,
                       metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"),
                       help="straight line from start to end (m, or mm with --mm)")
    p.add_argument("-n", type=int, default=36, help="path points (default 36)")
    p.add_argument("--yaw", type=_yaw_arg, metavar="DEG|tangent",
                   help="tool angle along the path [deg], or 'tangent' to the path")
    p.add_argument("--method", default="auto",
                   help="IK method (see `scara-opt solvers`; default auto)")
    p.add_argument("--time", default="toppra", choices=["toppra", "ruckig", "quintic"],
                   help="time parameterisation (default toppra)")
    p.add_argument("--q-start", type=float, nargs="+", metavar="q",
                   help="configuration the path starts from (units per --deg/--mm)")
    p.add_argument("--allow-jumps", action="store_true",
                   help="time the path even if the joints jump (elbow flip, wrist turn)")
    add_limit_options(p, jerk="--time ruckig only (default 10/s x amax)")
    p.add_argument("--seed", type=int_at_least(0), default=0, help="random seed (default 0)")
    p.add_argument("--tol", type=float, default=1e-9, help="residual counted as solved [m]")
    add_units(p)
    add_out(p, required=True)
    p.add_argument("--html", action="store_true",
                   help=f"also write {HTML}: the motion in 3-D (needs the view extra)")
    p.set_defaults(func=cmd_path)
