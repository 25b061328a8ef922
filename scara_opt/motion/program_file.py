"""Program files: a cell program of PTP / LIN / CIRC moves in TOML, in the units it states.

A program file names its robot and cell (optional), states its units like a robot or cell
file, and lists its moves in order::

    name = "pick and place"
    robot = "zavar2024"            # a bundled name, or a .urdf / .toml path (from this file)
    cell = "scara_cell.toml"       # optional: planned around its obstacles, proven clear
    length_unit = "mm"             # m, cm, mm, in: positions, prismatic joints, blends
    angle_unit = "deg"             # rad, deg: revolute joints, yaw, rpy
    margin = 2                     # clearance to keep from the cell (length_unit)
    start = [30, 60, 40, 0]        # optional joints; default: the first move's goal (a PTP)

    [limits]                       # the program's tool limits (each optional)
    speed = 500                    # length_unit/s
    acceleration = 3000            # length_unit/s²
    yaw_rate = 180                 # angle_unit/s

    [[moves]]
    type = "PTP"                   # PTP, LIN or CIRC
    xyz = [300, -120, -60]         # a Cartesian goal: position, and yaw, rpy or quat
    yaw = 0
    elbow = "righty"               # optional: lefty, righty

    [[moves]]
    type = "LIN"
    xyz = [300, -120, -80]
    yaw = 0
    speed = 100                    # this move's own tool speed (length_unit/s)

    [[moves]]
    type = "PTP"
    joints = [-40, 70, 40, 0]      # a joint goal: one value per joint
    blend = 10                     # round the corner within 10 length units

    [[moves]]
    type = "CIRC"
    via = [340, 50, -60]           # a point on the arc
    xyz = [250, 200, -60]

Other top-level keys: ``title``, ``notes``, ``method`` (``"toppra"`` or ``"ruckig"``),
``objective`` (``"length"`` or ``"time"``, :func:`scara_opt.plan`'s), ``time_limit`` [s]
and ``seed`` (the planner's, in a cell), ``allow_flip``. A move may
carry a ``label`` (shown beside its index). Unknown or misspelt keys and values are
refused with :class:`~scara_opt.errors.ProgramError`, naming the file, the move and the
key, with a close match when there is one; every number is checked in the file's own units.
:func:`load_program` gives a :class:`Program`; :meth:`Program.plan` plans it
(:func:`scara_opt.plan`).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import describe
from scara_opt.errors import ProgramError, ScaraOptError
from scara_opt.model.dh import ANGLE_UNITS, LENGTH_UNITS
from scara_opt.model.dh_file import check_keys, read_toml
from scara_opt.motion.fastest import OBJECTIVES
from scara_opt.motion.moves import CIRC, ELBOWS, LIN, PTP, Move
from scara_opt.motion.tool_limits import ToolLimits
from scara_opt.pose import quat_to_matrix, rpy_to_matrix
from scara_opt.target import Target

if TYPE_CHECKING:
    from scara_opt.collision.cell import Cell
    from scara_opt.collision.checker import CollisionChecker
    from scara_opt.model.robot import Robot
    from scara_opt.motion.result import MotionTrajectory

Array = NDArray[np.float64]

__all__ = ["FILE_KEYS", "MOVE_KEYS", "Program", "load_program"]

#: the keys a program file may hold at its top level
FILE_KEYS = ("name", "title", "notes", "robot", "cell", "length_unit", "angle_unit", "start",
             "margin", "method", "objective", "time_limit", "seed", "allow_flip", "limits",
             "moves")
#: the keys of a ``[[moves]]`` entry
MOVE_KEYS = ("type", "label", "xyz", "yaw", "rpy", "quat", "joints", "via", "speed",
             "acceleration", "blend", "elbow")
#: the keys of ``[limits]``
LIMIT_KEYS = ("speed", "acceleration", "yaw_rate")
#: the move types, by their name in a file
TYPES: dict[str, type[Move]] = {"PTP": PTP, "LIN": LIN, "CIRC": CIRC}
#: the timing methods a program may ask for
METHODS = ("toppra", "ruckig")


@dataclass(frozen=True)
class Program:
    """A program read from a file, in SI units, with its robot and cell.

    Attributes:
        name: the program's name (the file's ``name``, else its stem).
        robot: the robot it runs on.
        moves: the moves, in order (goals as :class:`~scara_opt.Target` or joints [rad, m]).
        labels: each move's label ("" where none is given).
        start: (nq,) start joints [rad, m], or ``None``: the first move's goal.
        limits: the program's :class:`~scara_opt.ToolLimits` (``None``: none given).
        cell: the cell it is planned in (``None``: no cell).
        margin: clearance to keep from the cell [m].
        method: ``"toppra"`` or ``"ruckig"``.
        time_limit: planning limit of each PTP around obstacles [s].
        seed: the planner's seed.
        allow_flip: a LIN / CIRC may be split by a stop-and-flip PTP.
        source: the file it was read from.
        objective: ``"length"`` or ``"time"`` (:func:`scara_opt.plan`'s).
    """

    name: str
    robot: Robot
    moves: tuple[Move, ...]
    labels: tuple[str, ...]
    start: Array | None = None
    limits: ToolLimits | None = None
    cell: Cell | None = None
    margin: float = 0.0
    method: str = "toppra"
    time_limit: float = 1.0
    seed: int = 0
    allow_flip: bool = False
    source: str = ""
    notes: str = field(default="", repr=False)
    objective: str = "length"

    def plan(self, cell: Cell | CollisionChecker | None = None, **options: Any
             ) -> MotionTrajectory:
        """Plan the program (:func:`scara_opt.plan`) with its robot, start, limits and cell.

        Args:
            cell: another cell, or a :class:`~scara_opt.CollisionChecker` (built with
                ``radius=`` for a robot without collision geometry); default the file's.
            **options: more keywords of :func:`scara_opt.plan` (``vmax``, ``amax``,
                ``payload``, ...), or ones that replace the file's (``margin``,
                ``time_limit``, ``seed``, ``method``, ``allow_flip``, ``objective``).

        Raises:
            MoveError, MoveCollisionError, NoPathFoundError, CollisionError, InputError:
                as :func:`scara_opt.plan`.
        """
        from scara_opt.motion.plan import plan

        kw: dict[str, Any] = {"start": self.start, "method": self.method,
                              "allow_flip": self.allow_flip, "objective": self.objective}
        where = self.cell if cell is None else cell
        if where is not None:
            kw.update(cell=where, margin=self.margin, time_limit=self.time_limit,
                      seed=self.seed)
        kw.update(options)
        return plan(self.robot, list(self.moves), self.limits, **kw)

    def move_names(self, offset: int = 0) -> list[str]:
        """``"move 2 (LIN, down)"`` for each move from ``offset`` on."""
        return [f"move {i} ({m.kind}{', ' + label if label else ''})" for i, (m, label)
                in enumerate(zip(self.moves, self.labels, strict=True)) if i >= offset]


class _Reader:
    """One program file's values, checked and converted to SI (its messages name the file)."""

    def __init__(self, path: Path, data: dict) -> None:
        self.where = f"program file {str(path)!r}"
        self.path = path
        lu, au = data.get("length_unit"), data.get("angle_unit", "rad")
        if lu not in LENGTH_UNITS or au not in ANGLE_UNITS:
            raise ProgramError(f"{self.where}: length_unit must be one of "
                               f"{sorted(LENGTH_UNITS)} and angle_unit one of "
                               f"{sorted(ANGLE_UNITS)}; got {lu!r} and {au!r}")
        self.lu, self.au = str(lu), str(au)
        self.L, self.A = LENGTH_UNITS[self.lu], ANGLE_UNITS[self.au]

    def number(self, table: dict, key: str, at: str, unit: str, *, positive: bool = False,
               at_least: float | None = None) -> float | None:
        """``table[key]`` (or None) as a finite number, checked in the file's ``unit``."""
        if key not in table:
            return None
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(float(value)):
            raise ProgramError(f"{at}: {key} must be a finite number [{unit}]; got "
                               f"{describe(value)}")
        if positive and not value > 0:
            raise ProgramError(f"{at}: {key} = {value} {unit}: it must be > 0")
        if at_least is not None and value < at_least:
            raise ProgramError(f"{at}: {key} = {value} {unit}: it must be >= {at_least:g}")
        return float(value)

    def numbers(self, table: dict, key: str, at: str, n: int | None, unit: str) -> list[float]:
        """``table[key]`` as a list of ``n`` finite numbers (any length if ``n`` is None)."""
        value = table[key]
        if (not isinstance(value, list) or (n is not None and len(value) != n) or not value
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                           and math.isfinite(float(v)) for v in value)):
            count = f"{n} " if n is not None else ""
            raise ProgramError(f"{at}: {key} must be a list of {count}finite numbers [{unit}]; "
                               f"got {describe(value)}")
        return [float(v) for v in value]

    def joints(self, table: dict, key: str, at: str, robot: Robot) -> Array:
        """Joint values in the file's units (angle_unit revolute, length_unit prismatic)."""
        units = [self.au if t == "revolute" else self.lu for t in robot.joint_types]
        values = self.numbers(table, key, at, robot.nq, "/".join(dict.fromkeys(units)))
        scale = [self.A if t == "revolute" else self.L for t in robot.joint_types]
        return np.array(values) * np.array(scale)

    def target(self, entry: dict, at: str) -> Target:
        """``xyz`` and one of ``yaw``, ``rpy``, ``quat`` as a Target in SI."""
        given = [k for k in ("yaw", "rpy", "quat") if k in entry]
        if len(given) > 1:
            raise ProgramError(f"{at}: give one orientation, yaw, rpy or quat; got "
                               f"{' and '.join(given)}")
        xyz = np.array(self.numbers(entry, "xyz", at, 3, self.lu)) * self.L
        try:
            if "yaw" in entry:
                yaw = self.number(entry, "yaw", at, self.au)
                assert yaw is not None  # "yaw" is in entry
                return Target(xyz, yaw=yaw * self.A)
            if "rpy" in entry:
                rpy = np.array(self.numbers(entry, "rpy", at, 3, self.au)) * self.A
                return Target(xyz, rotation=rpy_to_matrix(rpy))
            if "quat" in entry:
                return Target(xyz, rotation=quat_to_matrix(self.numbers(entry, "quat", at, 4,
                                                                        "1")))
            return Target(xyz)
        except ScaraOptError as exc:
            raise ProgramError(f"{at}: {exc}") from None

    def move(self, entry: object, i: int, robot: Robot) -> tuple[Move, str]:
        """One ``[[moves]]`` entry as a move in SI, and its label."""
        at = f"{self.where}: moves entry {i + 1} (move {i})"
        if not isinstance(entry, dict):
            raise ProgramError(f"{at} must be a table (key = value lines); got "
                               f"{describe(entry)}")
        check_keys(entry, MOVE_KEYS, at, ProgramError)
        kind = entry.get("type")
        if not isinstance(kind, str) or kind.upper() not in TYPES:
            close = difflib.get_close_matches(str(kind).upper(), list(TYPES), 1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ProgramError(f"{at}: type must be one of {', '.join(TYPES)}; got "
                               f"{describe(kind)}{hint}")
        kind = kind.upper()
        label = entry.get("label", "")
        if not isinstance(label, str):
            raise ProgramError(f"{at}: label must be a string; got {describe(label)}")
        if label:
            at = f"{at}, {label!r}"
        if ("joints" in entry) == ("xyz" in entry):
            raise ProgramError(f"{at}: give the goal as xyz = [x, y, z] (with yaw, rpy or "
                               "quat) or as joints = [...], one of them")
        if "joints" in entry:
            extra = [k for k in ("yaw", "rpy", "quat") if k in entry]
            if extra:
                raise ProgramError(f"{at}: {' and '.join(extra)} orient an xyz goal; a "
                                   "joints goal has its own: drop them")
            goal: Target | Array = self.joints(entry, "joints", at, robot)
        else:
            goal = self.target(entry, at)
        if (kind == "CIRC") != ("via" in entry):
            raise ProgramError(f"{at}: " + ("a CIRC needs via = [x, y, z], a point on the arc"
                                            if kind == "CIRC" else f"a {kind} takes no via"))
        elbow = entry.get("elbow")
        if elbow is not None and elbow not in ELBOWS:
            raise ProgramError(f"{at}: elbow must be one of {', '.join(ELBOWS)}; got "
                               f"{describe(elbow)}")
        speed = self.number(entry, "speed", at, f"{self.lu}/s", positive=True)
        accel = self.number(entry, "acceleration", at, f"{self.lu}/s²", positive=True)
        blend = self.number(entry, "blend", at, self.lu, at_least=0.0) or 0.0
        kw: dict[str, Any] = {"speed": None if speed is None else speed * self.L,
                              "acceleration": None if accel is None else accel * self.L,
                              "blend": blend * self.L, "elbow": elbow}
        if kind == "CIRC":
            via = np.array(self.numbers(entry, "via", at, 3, self.lu)) * self.L
            return CIRC(via, goal, **kw), label
        return TYPES[kind](goal, **kw), label

    def limits(self, table: object) -> ToolLimits:
        """``[limits]`` as ToolLimits in SI."""
        at = f"{self.where}: [limits]"
        if not isinstance(table, dict):
            raise ProgramError(f"{at} must be a table; got {describe(table)}")
        check_keys(table, LIMIT_KEYS, at, ProgramError)
        units = {"speed": (f"{self.lu}/s", self.L), "acceleration": (f"{self.lu}/s²", self.L),
                 "yaw_rate": (f"{self.au}/s", self.A)}
        values = {}
        for key, (unit, scale) in units.items():
            value = self.number(table, key, at, unit, positive=True)
            values[key] = None if value is None else value * scale
        return ToolLimits(**values)


def _robot(value: object, path: Path, robot: object, tip: str | None) -> Robot:
    """The robot given, else the file's ``robot`` (a name, or a path from the file)."""
    from scara_opt.model.catalogue import list_robots, load_robot
    from scara_opt.model.robot import Robot

    where = f"program file {str(path)!r}"
    if isinstance(robot, Robot):
        if tip is not None:
            raise ProgramError(f"tip={tip!r} chooses the tip of a robot loaded here; a Robot "
                               "has its own: drop tip= or pass the robot by name or path")
        return robot
    if robot is not None:
        if not isinstance(robot, (str, Path)):
            raise ProgramError(f"robot must be a Robot, a bundled name or a path; got "
                               f"{describe(robot)}")
        return load_robot(robot, tip=tip)
    if value is None:
        raise ProgramError(f"{where} names no robot: add robot = \"zavar2024\" (a bundled "
                           "name, or a .urdf / .toml path from the file), or pass robot=")
    if not isinstance(value, str) or not value:
        raise ProgramError(f"{where}: robot must be a bundled name or a path (a string); "
                           f"got {describe(value)}")
    return load_robot(value if value in list_robots() else path.parent / value, tip=tip)


def load_program(path: str | Path, robot: Robot | str | Path | None = None,
                 tip: str | None = None) -> Program:
    """Read a program file (TOML; see the module docstring) into a :class:`Program` in SI.

    Args:
        path: the program file.
        robot: the robot to run it on (a :class:`~scara_opt.Robot`, a bundled name or a
            path); default the file's ``robot``.
        tip: the tip frame of the robot loaded here (see :func:`scara_opt.load_robot`).

    Raises:
        ProgramError: a missing or unreadable file, TOML syntax, an unknown key, unit or
            move type (with a close match), a bad or missing value (named with the move and
            its unit), no robot.
        CellError, MeshNotFoundError: the file's cell cannot be read.
        RobotNotFoundError, URDFError: the robot cannot be loaded.
    """
    if not isinstance(path, (str, Path)):
        raise ProgramError(f"a program file path must be a str or Path; got {describe(path)}")
    path = Path(path)
    data = read_toml(path, f"program file {str(path)!r}", "a TOML program file", ProgramError)
    reader = _Reader(path, data)
    where = reader.where
    check_keys(data, FILE_KEYS, where, ProgramError)
    bot = _robot(data.get("robot"), path, robot, tip)
    entries = data.get("moves")
    if not isinstance(entries, list) or not entries:
        raise ProgramError(f"{where} has no moves: add [[moves]] tables (type = \"PTP\", "
                           "\"LIN\" or \"CIRC\", and a goal)")
    pairs = [reader.move(e, i, bot) for i, e in enumerate(entries)]
    start = None if "start" not in data else reader.joints(data, "start", where, bot)
    limits = None if "limits" not in data else reader.limits(data["limits"])
    cell = None
    if "cell" in data:
        from scara_opt.collision.cell import load_cell

        if not isinstance(data["cell"], str) or not data["cell"]:
            raise ProgramError(f"{where}: cell must be a cell file's path (a string); got "
                               f"{describe(data['cell'])}")
        cell = load_cell(path.parent / data["cell"])
    margin = reader.number(data, "margin", where, reader.lu, at_least=0.0) or 0.0
    if margin and cell is None:
        raise ProgramError(f"{where}: margin is the clearance to keep from a cell; add "
                           "cell = \"...\" or drop margin")
    method = data.get("method", "toppra")
    if method not in METHODS:
        raise ProgramError(f"{where}: method must be one of {', '.join(METHODS)}; got "
                           f"{describe(method)}")
    objective = data.get("objective", "length")
    if objective not in OBJECTIVES:
        raise ProgramError(f"{where}: objective must be one of {', '.join(OBJECTIVES)}; got "
                           f"{describe(objective)}")
    time_limit = reader.number(data, "time_limit", where, "s", positive=True)
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ProgramError(f"{where}: seed must be a whole number >= 0; got {describe(seed)}")
    flip = data.get("allow_flip", False)
    if not isinstance(flip, bool):
        raise ProgramError(f"{where}: allow_flip must be true or false; got {describe(flip)}")
    name = data.get("name", path.stem)
    if not isinstance(name, str):
        raise ProgramError(f"{where}: name must be a string; got {describe(name)}")
    return Program(name, bot, tuple(m for m, _ in pairs), tuple(lb for _, lb in pairs),
                   start, limits, cell, margin * reader.L, str(method),
                   1.0 if time_limit is None else time_limit, seed, flip, str(path),
                   str(data.get("notes", "")), str(objective))
