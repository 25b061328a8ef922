"""``scara-opt solvers``: the registered IK methods, one a line."""

from __future__ import annotations

import argparse


def cmd_solvers(args: argparse.Namespace) -> int:
    """List the registered IK methods."""
    from scara_opt.ik import solvers

    print("\n".join(solvers()))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``solvers`` to the subparsers ``sub``."""
    p = sub.add_parser("solvers", parents=parents, help="list the registered IK methods")
    p.set_defaults(func=cmd_solvers)
