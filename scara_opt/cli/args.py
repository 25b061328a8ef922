"""Arguments several commands share, checked in the units the user typed them in.

The robot (:func:`add_robot`: ``ROBOT`` and ``--tip``), the units (:func:`add_units`), the
joint limits (:func:`add_limit_options`) and planning in a cell (:func:`add_cell_arguments`:
``--cell``, ``--margin``, ``--radius``, ``--time-limit``, ``--seed``): every subcommand that
needs one of the API's robot options takes it under the same name.

SI inside, ``--deg`` and ``--mm`` outside: :func:`joint_scale`, :func:`joint_units`.
Number types: :func:`positive`, :func:`nonnegative`; ``degrees``: an angle option in degrees
(``--yaw``). ``--vmax/--amax/--jmax`` of the commands that time a motion (``path``,
``cycle``, ``plan``, ``run``): one value for every joint or one per joint, in SI (rad/s or
m/s and their derivatives, whatever ``--deg``/``--mm`` say about positions); a joint
without a limit of its own (a URDF carries no acceleration limit) needs the option. The
limits are resolved before any IK runs, so a missing or bad one is refused at once, naming
the option.
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


def add_robot(p: argparse.ArgumentParser) -> None:
    """``ROBOT`` (a bundled name or a .urdf/.toml path) and ``--tip LINK``."""
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--tip", metavar="LINK",
                   help="the tip frame (default: the bundled robot's tool, a URDF's end link)")


def load_robot(args: argparse.Namespace) -> Any:
    """The robot of ``ROBOT`` and ``--tip`` (:func:`scara_opt.load_robot`)."""
    from scara_opt.model.catalogue import load_robot as load

    return load(args.robot, tip=args.tip)


def add_units(p: argparse.ArgumentParser, json: bool = True) -> None:
    """``--mm`` and ``--deg`` (and ``--json``)."""
    p.add_argument("--mm", action="store_true",
                   help="lengths (positions, prismatic joints) in mm instead of m")
    p.add_argument("--deg", action="store_true",
                   help="revolute joint values in degrees instead of radians")
    if json:
        p.add_argument("--json", action="store_true", help="print JSON for scripts")


def add_out(p: argparse.ArgumentParser, required: bool = False, what: str = "") -> None:
    """``--out DIR`` and ``--force``."""
    from scara_opt.cli.outputs import FORCE_HELP

    p.add_argument("--out", required=required, metavar="DIR",
                   help=f"output folder{what}" if required else "folder for the files below")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)


def files_asked(args: argparse.Namespace, files: dict[str, str]) -> list[str]:
    """The options of ``files`` (``{"csv": "plan.csv", ...}``) given, checked against --out.

    Raises:
        InputError: a file asked for without ``--out``.
    """
    asked = [k for k in files if getattr(args, k)]
    if asked and args.out is None:
        raise InputError(f"--{' --'.join(asked)}: the files go into a folder; give it with "
                         "--out DIR")
    return asked


#: the shortest ``--time-limit`` [s]: setting up one search takes milliseconds by itself,
#: so a shorter limit could not be kept
MIN_TIME_LIMIT = 0.01


def time_limit(text: str) -> float:
    """An argparse type: ``--time-limit`` in seconds, at least :data:`MIN_TIME_LIMIT`."""
    value = positive(text)
    if value < MIN_TIME_LIMIT:
        raise argparse.ArgumentTypeError(
            f"{text} s is shorter than setting up one search takes; pass at least "
            f"{MIN_TIME_LIMIT:g} s")
    return value


def radius_entries(text: str) -> tuple[str | None, float]:
    """An argparse type: ``--radius`` entry ``MM`` (every link) or ``JOINT=MM`` [mm]."""
    name, sep, number = text.rpartition("=")
    value = positive(number)
    if sep and not name:
        raise argparse.ArgumentTypeError(f"expected MM or JOINT=MM, got {text!r}")
    return (name or None), value


def add_cell_arguments(p: argparse.ArgumentParser, from_file: bool = False) -> None:
    """``--cell``, ``--margin``, ``--radius``, ``--time-limit`` and ``--seed``.

    ``from_file``: the values default to a program file's (``None`` here), not to 0, 1 s
    and 0.
    """
    where = "; default the program file's" if from_file else ""
    p.add_argument("--cell", metavar="FILE",
                   help="cell file (TOML: obstacles in stated units); moves are planned "
                        f"around its obstacles and proven clear of them{where}")
    p.add_argument("--margin", type=nonnegative, default=None if from_file else 0.0,
                   metavar="MM", help=f"clearance to keep from the cell [mm] ({where or '0'})")
    p.add_argument("--radius", type=radius_entries, nargs="+", metavar="MM|JOINT=MM",
                   help="capsule radius of a robot without <collision> geometry [mm]: one "
                        "for every link, or JOINT=MM for the link each joint moves (default "
                        "the robot file's radius keys)")
    p.add_argument("--time-limit", type=time_limit, default=None if from_file else 1.0,
                   metavar="S", help="planning limit of each PTP around obstacles [s] "
                   f"({where or '1'}; at least {MIN_TIME_LIMIT:g})")
    p.add_argument("--seed", type=int_at_least(0), default=None if from_file else 0,
                   help=f"the planner's seed ({where or '0'})")


def add_objective(p: argparse.ArgumentParser, from_file: bool = False) -> None:
    """``--objective length|time`` (:func:`scara_opt.plan`'s ``objective=``)."""
    where = "the program file's, else length" if from_file else "length"
    p.add_argument("--objective", choices=["length", "time"], default=None if from_file
                   else "length",
                   help="what a PTP minimises: length (the path short in joint space, then "
                        "timed) or time (the least duration found: Ruckig's synchronized "
                        f"move where it is proven clear, at the lower bound); default {where}")


def make_checker(robot: Any, cell: Any, args: argparse.Namespace, margin: float) -> Any:
    """The :class:`~scara_opt.CollisionChecker` of ``cell`` with ``--radius`` and ``margin`` [m]."""
    from scara_opt.collision.checker import CollisionChecker

    return CollisionChecker(robot, cell, margin=margin, radius=_radius(args.radius))


def _radius(entries: list[tuple[str | None, float]] | None) -> object:
    """``radius=`` of :class:`~scara_opt.CollisionChecker` from ``--radius`` [mm] (SI)."""
    if entries is None:
        return None
    names = [n for n, _ in entries]
    if None in names:
        if len(entries) > 1:
            raise InputError("--radius takes one MM for every link, or JOINT=MM entries; "
                             f"got {len(entries)} entries with a bare number among them")
        return entries[0][1] / 1e3
    return {n: r / 1e3 for n, r in entries}


def cell_keywords(args: argparse.Namespace, robot: Any) -> dict:
    """The ``cell=`` (a checker), ``time_limit=`` and ``seed=`` of :func:`scara_opt.plan`.

    Raises:
        InputError: ``--margin``, ``--radius`` or ``--seed`` without ``--cell``.
        CellError, UnknownBodyError, MeshNotFoundError: a bad cell file or robot geometry.
    """
    if args.cell is None:
        given = [o for o, v in (("--margin", args.margin), ("--radius", args.radius),
                                ("--seed", args.seed)) if v]
        if given:
            raise InputError(f"{' and '.join(given)} set(s) how to plan in a cell: give "
                             "--cell FILE, or drop them")
        return {}
    from scara_opt.collision.cell import load_cell

    checker = make_checker(robot, load_cell(args.cell), args, args.margin / 1e3)
    return {"cell": checker, "time_limit": args.time_limit, "seed": args.seed}
