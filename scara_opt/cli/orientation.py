"""Orientations at the CLI's edge: ``--yaw``/``--rpy``/``--quat`` in, RPY and quaternion out.

Conventions of :mod:`scara_opt.pose`: RPY is ``Rz(yaw) Ry(pitch) Rx(roll)`` about fixed
axes; quaternions are ``(w, x, y, z)``, printed with ``w >= 0``.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from scara_opt.cli.args import degrees
from scara_opt.errors import InputError
from scara_opt.pose import matrix_to_quat, matrix_to_rpy, quat_to_matrix, rpy_to_matrix
from scara_opt.target import Target


def add_orientation_arguments(p: argparse.ArgumentParser) -> None:
    """``--yaw`` | ``--rpy R P Y`` | ``--quat W X Y Z`` (one of them), and ``--rpy-unit``."""
    group = p.add_mutually_exclusive_group()
    group.add_argument("--yaw", type=degrees, metavar="DEG",
                       help="tool angle [deg] about the robot's yaw axis (SCARA-type robots)")
    group.add_argument("--rpy", type=float, nargs=3, metavar=("ROLL", "PITCH", "YAW"),
                       help="full orientation as roll, pitch, yaw about fixed x, y, z "
                            "(R = Rz Ry Rx), in --rpy-unit")
    group.add_argument("--quat", type=float, nargs=4, metavar=("W", "X", "Y", "Z"),
                       help="full orientation as a unit quaternion, scalar first")
    p.add_argument("--rpy-unit", choices=["deg", "rad"], default=None,
                   help="unit of --rpy (default deg)")


def target_from_args(args: argparse.Namespace, position: np.ndarray) -> Target:
    """The IK target of ``--xyz`` (already in metres) and the orientation options."""
    if args.rpy_unit is not None and args.rpy is None:
        raise InputError("--rpy-unit sets the unit of --rpy only; give --rpy ROLL PITCH YAW "
                         "with it, or drop it")
    if args.yaw is not None:
        return Target(position, yaw=math.radians(args.yaw))
    if args.rpy is not None:
        rpy = np.asarray(args.rpy, float)
        if (args.rpy_unit or "deg") == "deg":
            rpy = np.radians(rpy)
        return Target(position, rotation=rpy_to_matrix(rpy))
    if args.quat is not None:
        return Target(position, rotation=quat_to_matrix(args.quat))
    return Target(position)


def orientation(R: Any) -> dict[str, list[float]]:
    """``{"rpy_deg": [roll, pitch, yaw], "quaternion_wxyz": [w, x, y, z]}`` of a rotation."""
    return {"rpy_deg": (np.degrees(matrix_to_rpy(R)) + 0.0).tolist(),  # + 0.0: no "-0"
            "quaternion_wxyz": matrix_to_quat(R).tolist()}


def orientation_text(o: dict[str, list[float]]) -> str:
    """One line: RPY [deg] and the quaternion (w, x, y, z)."""
    rpy = ", ".join(f"{v:.6g}" for v in o["rpy_deg"])
    quat = ", ".join(f"{v:.6g}" for v in o["quaternion_wxyz"])
    return f"rpy ({rpy}) deg, quaternion (w, x, y, z) ({quat})"
