"""``scara-opt fk ROBOT q...``: the tip of one configuration, its RPY and quaternion."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from scara_opt.cli.args import add_robot, add_units, joint_scale, joint_units, load_robot


def cmd_fk(args: argparse.Namespace) -> int:
    """Forward kinematics of one configuration: position, RPY [deg] and quaternion (w, x, y, z)."""
    from scara_opt.cli.orientation import orientation, orientation_text

    robot = load_robot(args)
    q = robot.check_q(args.q) / joint_scale(robot, args.deg, args.mm)
    T = robot.fk(q)
    L = 1000.0 if args.mm else 1.0
    out: dict[str, Any] = {
        "robot": robot.name, "q": q.tolist(), "q_units": joint_units(robot, False, False),
        "position": (T[:3, 3] * L).tolist(), "position_unit": "mm" if args.mm else "m",
        "rotation": T[:3, :3].tolist(), "within_limits": bool(robot.within_limits(q)),
    }
    out.update(orientation(T[:3, :3]))
    if robot.yaw_axis is not None:
        out["yaw_deg"] = math.degrees(robot.yaw(q))
    if args.json:
        print(json.dumps(out))
        return 0
    unit = out["position_unit"]
    print(f"{robot.name}: tip at ({', '.join(f'{v:.6g}' for v in out['position'])}) {unit}"
          + (f", yaw {out['yaw_deg']:.6g} deg" if "yaw_deg" in out else ""))
    print(f"  orientation: {orientation_text(out)}")
    if not out["within_limits"]:
        print("note: q is outside the joint limits")
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``fk`` to the subparsers ``sub``."""
    p = sub.add_parser("fk", parents=parents, help="forward kinematics of one configuration")
    add_robot(p)
    p.add_argument("q", metavar="q", type=float, nargs="+", help="joint values, one per joint")
    add_units(p)
    p.set_defaults(func=cmd_fk)
