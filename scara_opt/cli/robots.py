"""``scara-opt robots``: the bundled robots with their joints, limits, source and paper."""

from __future__ import annotations

import argparse
import math


def _fmt_limit(kind: str, lo: float, hi: float) -> str:
    if kind == "revolute":
        return f"[{math.degrees(lo):.1f}, {math.degrees(hi):.1f}] deg"
    return f"[{lo * 1000:.1f}, {hi * 1000:.1f}] mm"


def cmd_robots(args: argparse.Namespace) -> int:
    """List the bundled robots with joints, limits, source and the paper's full reference."""
    from scara_opt.model.catalogue import list_robots, load_robot
    from scara_opt.model.citation import format_citation

    for name in list_robots():
        robot = load_robot(name)
        print(f"{name}  ({robot.nq} joints, tip {robot.tip!r})")
        for jname, kind, lo, hi in zip(robot.joint_names, robot.joint_types, robot.lower,
                                       robot.upper, strict=True):
            print(f"  {jname:<8} {kind:<9} {_fmt_limit(kind, lo, hi)}")
        print(f"  source: {robot.source}")
        citation = robot.metadata.get("citation")
        if citation:
            print(f"  paper:  {format_citation(citation)}")
            if "note" in citation:
                print(f"          ({citation['note']})")
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``robots`` to the subparsers ``sub``."""
    p = sub.add_parser("robots", parents=parents,
                       help="list the bundled robots with joints, limits and source")
    p.set_defaults(func=cmd_robots)
