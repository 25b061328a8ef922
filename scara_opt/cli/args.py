"""Arguments several commands share, checked in the units the user typed them in.

SI inside, ``--deg`` and ``--mm`` outside: :func:`joint_scale`, :func:`joint_units`.
Number types: :func:`positive`, :func:`nonnegative`; ``degrees``: an angle option in degrees
(``--yaw``). ``--vmax/--amax/--jmax`` of the
commands that time a motion (``path``, ``cycle``): one value for every joint or one per
joint, in SI (rad/s or m/s and their derivatives,
whatever ``--deg``/``--mm`` say about positions); a joint without a limit of its own (a
URDF carries no acceleration limit) needs the option. The limits are resolved before any
IK runs, so a missing or bad one is refused at once, naming the option.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from scara_opt.checks import count_text
from scara_opt.errors import InputError, TrajectoryError

#: unit of each option, for the help and the messages
UNITS = {"vmax": "rad/s or m/s", "amax": "rad/s² or m/s²", "jmax": "rad/s³ or m/s³"}


def degrees(text: str) -> float:
    """An argparse type: an angle in degrees, checked in degrees (the unit the user typed).

    Raises:
        argparse.ArgumentTypeError: not a number, not finite, or beyond the largest angle a
            target takes (:data:`scara_opt.target.MAX_ANGLE` rad, in degrees).
    """
    from scara_opt.target import MAX_ANGLE

    most = math.degrees(MAX_ANGLE)
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an angle in degrees, got {text!r}") from None
    if not (math.isfinite(value) and abs(value) <= most):
        raise argparse.ArgumentTypeError(
            f"{text} deg: an angle must be finite and within ±{most:.6g} deg (beyond, a float "
            "cannot resolve it); give it within a turn, e.g. in [-180, 180]")
    return value


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def int_at_least(low: int, high: int | None = None) -> Any:
    """An argparse type: an integer >= ``low`` (and <= ``high``)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"expected an integer >= {low}, got {value}")
        if high is not None and value > high:
            raise argparse.ArgumentTypeError(
                f"expected an integer <= {high}, got {count_text(value)}")
        return value
    return parse


def positive(text: str) -> float:
    """An argparse type: a finite number > 0."""
    value = _number(text)
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0; got {text}")
    return value


def nonnegative(text: str) -> float:
    """An argparse type: a finite number >= 0."""
    value = _number(text)
    if not (value >= 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0; got {text}")
    return value


def joint_scale(robot: Any, deg: bool, mm: bool) -> np.ndarray:
    """Factor from SI joint values to the display units (``--deg``, ``--mm``), per joint."""
    rev = np.array([t == "revolute" for t in robot.joint_types])
    return np.where(rev, 180 / math.pi if deg else 1.0, 1000.0 if mm else 1.0)


def joint_units(robot: Any, deg: bool, mm: bool) -> list[str]:
    """The display unit of each joint (``rad``/``deg``, ``m``/``mm``)."""
    return [("deg" if deg else "rad") if t == "revolute" else ("mm" if mm else "m")
            for t in robot.joint_types]


def add_limit_options(p: argparse.ArgumentParser, jerk: str | None = None) -> None:
    """Add ``--vmax``, ``--amax`` (and ``--jmax`` with its help ``jerk``) to ``p``."""
    names = {"vmax": "joint velocity", "amax": "joint acceleration"}
    if jerk is not None:
        names["jmax"] = "joint jerk"
    for name, what in names.items():
        extra = f"; {jerk}" if name == "jmax" else ""
        p.add_argument(f"--{name}", type=positive, nargs="+", metavar="V",
                       help=f"{what} limit [{UNITS[name]}, SI], one value for all joints or "
                            f"one per joint (default: the robot's own){extra}")


def joint_limits(args: argparse.Namespace, robot: Any, need_jerk: bool) -> Any:
    """The :class:`~scara_opt.trajectory.Limits` of the options and the robot, checked now.

    Raises:
        InputError: a count that is neither 1 nor the robot's joint count, a value out of
            range, ``--jmax`` where no jerk limit is used, or a joint with no limit of its
            own and none given (the message names the option to pass).
    """
    from scara_opt.trajectory.limits import resolve_limits

    values = {}
    for name in ("vmax", "amax", "jmax"):
        given = getattr(args, name, None)
        if given is not None and len(given) not in (1, robot.nq):
            raise InputError(f"--{name} takes one value for all joints or {robot.nq}, one per "
                             f"joint {robot.joint_names} [{UNITS[name]}]; got {len(given)}")
        values[name] = None if given is None else np.broadcast_to(
            np.asarray(given, float), (robot.nq,)).copy()
    if values["jmax"] is not None and not need_jerk:
        raise InputError("--jmax limits the jerk of --time ruckig only; drop it or pass "
                         "--time ruckig")
    try:
        return resolve_limits(robot, robot.nq, values["vmax"], values["amax"], values["jmax"],
                              need_jerk, option="--{}")
    except TrajectoryError as exc:  # a joint without a limit of its own: bad input here
        raise InputError(str(exc)) from None
