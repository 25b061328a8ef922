"""``scara-opt ik ROBOT --xyz X Y Z``: inverse kinematics of one target by any method.

Exit code 1 when the target was not solved (the printed status and its evidence say why).
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from scara_opt.cli.args import (
    add_robot,
    add_units,
    int_at_least,
    joint_scale,
    joint_units,
    load_robot,
)
from scara_opt.errors import InputError

#: exit code of ``ik`` when the target was not solved (the printed status says why)
EXIT_NOT_SOLVED = 1


def _result_dict(robot: Any, res: Any, deg: bool, mm: bool) -> dict[str, Any]:
    L = 1000.0 if mm else 1.0
    return {
        "robot": robot.name, "method": res.method, "status": res.status.value,
        "success": res.success, "q": (res.q * joint_scale(robot, deg, mm)).tolist(),
        "q_units": joint_units(robot, deg, mm), "error": res.error,
        "error_unit": "m" if res.yaw_error is None else "m and rad",
        "position_error": (res.position_error * L).tolist(),
        "position_error_unit": "mm" if mm else "m",
        "yaw_error_deg": None if res.yaw_error is None else math.degrees(res.yaw_error),
        "iterations": res.iterations, "evaluations": res.evaluations, "time_s": res.time_s,
        "message": res.message, "route": res.route,
    }


def _error_text(row: dict[str, Any]) -> str:
    """The residual in the units the user asked for: position in m or mm, angle in deg."""
    text = (f"position error {float(np.linalg.norm(row['position_error'])):.3g} "
            f"{row['position_error_unit']}")
    for key, what in (("yaw_error_deg", "yaw"), ("rotation_error_deg", "rotation")):
        if row.get(key) is not None:
            text += f", {what} error {row[key]:.3g} deg"
    return text


def _listed(robot: Any, target: Any) -> tuple[bool, str]:
    """Whether ``--all`` runs the SCARA closed form here, and what it lists, in words."""
    from scara_opt.ik.analytic import applies
    from scara_opt.ik.arm_route import served

    if applies(robot):
        return True, "every branch of the SCARA closed form, which takes no seed"
    if served(robot, target) is not None:
        return False, ("every branch of the arm's closed form (a seeded multi-start where it "
                       "finds none)")
    return False, ("the solutions a seeded multi-start reaches (no closed form serves this "
                   "robot and target): not necessarily all")


def _none_found(robot: Any, target: Any) -> str:
    """What an empty ``--all`` list means on this robot and target (proof or not)."""
    from scara_opt.ik.analytic import applies
    from scara_opt.ik.arm_route import served

    if applies(robot):
        return "no closed-form solution within the joint limits (unreachable)"
    tried = ("neither the closed form nor a seeded multi-start found a solution"
             if served(robot, target) is not None else "a seeded multi-start (no closed form "
             "serves this robot and target) found no solution")
    return (f"failed: {tried} within the joint limits (not a proof that none exists; "
            "`scara-opt ik` without --all gives the verdict)")


def cmd_ik(args: argparse.Namespace) -> int:
    """Inverse kinematics of one target (position, and --yaw, --rpy or --quat) by any method."""
    from scara_opt.cli.orientation import orientation, target_from_args
    from scara_opt.ik import ik_all, solve_ik

    robot = load_robot(args)
    L = 1000.0 if args.mm else 1.0
    target = target_from_args(args, np.asarray(args.xyz, float) / L)
    if args.all:
        scara, listed = _listed(robot, target)
        given = [o for o, v in (("--method", args.method), ("--seed", args.seed))
                 if v is not None and (o == "--method" or scara)]
        if given:
            raise InputError(f"--all lists {listed}; it does not take "
                             f"{' or '.join(given)}; drop {' and '.join(given)} or --all")
        results = ik_all(robot, target, tol=args.tol, seed=args.seed or 0)
    else:
        results = [solve_ik(robot, target, method="auto" if args.method is None
                            else args.method, seed=args.seed or 0, tol=args.tol)]
    rows = [_result_dict(robot, r, args.deg, args.mm) for r in results]
    if target.kind == "rotation":  # the angle error is the rotation's, not a yaw's
        for row, res in zip(rows, results, strict=True):
            row["rotation_error_deg"] = row.pop("yaw_error_deg")
            row["target_orientation"] = orientation(target.rotation)
            row["reached_orientation"] = orientation(robot.fk(res.q)[:3, :3])
    code = 0 if rows and all(row["success"] for row in rows) else EXIT_NOT_SOLVED
    if args.json:
        print(json.dumps(rows if args.all else rows[0]))
        return code
    if not rows:
        print(f"{robot.name}: {_none_found(robot, target)}")
    for row in rows:
        q = ", ".join(f"{name}={v:.6g} {u}" for name, v, u in
                      zip(robot.joint_names, row["q"], row["q_units"], strict=True))
        print(f"{row['status']}: {q}  ({_error_text(row)}; {row['route'] or row['method']}, "
              f"{row['time_s'] * 1e3:.2f} ms)")
        if not row["success"]:
            print(f"  {row['message']}")
    return code


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``ik`` to the subparsers ``sub``."""
    from scara_opt.cli.orientation import add_orientation_arguments

    p = sub.add_parser("ik", parents=parents, help="inverse kinematics of one target")
    add_robot(p)
    p.add_argument("--xyz", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"),
                   help="target position (m, or mm with --mm)")
    add_orientation_arguments(p)  # --yaw | --rpy | --quat, and --rpy-unit
    p.add_argument("--method", help="IK method (see `scara-opt solvers`; default auto)")
    p.add_argument("--seed", type=int_at_least(0), help="random seed (default 0)")
    p.add_argument("--tol", type=float, default=1e-9, help="residual counted as solved [m]")
    p.add_argument("--all", action="store_true",
                   help="every solution: the closed form's branches on a SCARA (no --seed) "
                        "and on 6R arms it serves, else a seeded multi-start's (no --method)")
    add_units(p)
    p.set_defaults(func=cmd_ik)
