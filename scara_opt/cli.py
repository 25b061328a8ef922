"""The ``scara-opt`` command line. Exit codes: 0 success, 2 bad usage or bad input."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from scara_opt.errors import ScaraOptError


def _fmt_limit(kind: str, lo: float, hi: float) -> str:
    if kind == "revolute":
        return f"[{math.degrees(lo):.1f}, {math.degrees(hi):.1f}] deg"
    return f"[{lo * 1000:.1f}, {hi * 1000:.1f}] mm"


def cmd_robots(args: argparse.Namespace) -> int:
    """List the bundled robots with joints, limits and source."""
    from scara_opt.robot import list_robots, load_robot

    for name in list_robots():
        robot = load_robot(name)
        print(f"{name}  ({robot.nq} joints, tip {robot.tip!r})")
        for jname, kind, lo, hi in zip(robot.joint_names, robot.joint_types, robot.lower,
                                       robot.upper, strict=True):
            print(f"  {jname:<8} {kind:<9} {_fmt_limit(kind, lo, hi)}")
        print(f"  source: {robot.source}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="scara-opt",
        description="Kinematics, IK and trajectories of SCARA robots and serial URDF chains.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    p = sub.add_parser("robots", help="list the bundled robots with joints, limits and source")
    p.set_defaults(func=cmd_robots)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except ScaraOptError as exc:
        print(f"scara-opt: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
