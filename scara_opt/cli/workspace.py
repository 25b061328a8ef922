"""``scara-opt workspace ROBOT --out DIR``: the Monte Carlo workspace, its areas and figures."""

from __future__ import annotations

import argparse

from scara_opt.cli.args import add_out, add_robot, int_at_least, load_robot
from scara_opt.cli.outputs import OutputDir


def cmd_workspace(args: argparse.Namespace) -> int:
    """Monte Carlo workspace: areas, ranges and the XY/3-D figures."""
    from scara_opt.workspace_analysis import workspace

    robot = load_robot(args)
    names = [f"{robot.name}_workspace_xy.png", f"{robot.name}_workspace_3d.png"]
    with OutputDir(args.out, names, args.force) as out:
        ws = workspace(robot, n=args.n, seed=args.seed, footprint=not args.no_footprint)
        ws.plot_xy(out / names[0])
        ws.plot_3d(out / names[1])
    print(repr(ws))
    print(f"XY area: {ws.xy_area:.6f} m^2")
    print("wrote " + ", ".join(str(out.final / n) for n in names))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``workspace`` to the subparsers ``sub``."""
    p = sub.add_parser("workspace", parents=parents, help="Monte Carlo workspace with figures")
    add_robot(p)
    p.add_argument("-n", type=int, default=60_000, help="samples (default 60000)")
    p.add_argument("--seed", type=int_at_least(0), default=0, help="random seed (default 0)")
    p.add_argument("--no-footprint", action="store_true", help="ignore the base exclusion zone")
    add_out(p, required=True)
    p.set_defaults(func=cmd_workspace)
