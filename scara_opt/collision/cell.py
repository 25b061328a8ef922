"""A robot cell: the obstacles around the robot, from Python or a TOML cell file.

In Python::

    cell = so.Cell([so.Box("table", (0.6, 0.8, 0.02), xyz=(0.3, 0, -0.12)),
                    so.Cylinder("post", radius=0.03, length=0.4, xyz=(0.25, 0.15, 0))])

A cell file states its units, like a robot file, and lists its obstacles::

    name = "rack cell"
    length_unit = "mm"          # m, cm, mm, in
    angle_unit = "deg"          # rad, deg
    allowed = [["link4", "part"]]   # contacts that are not collisions (optional)

    [[obstacles]]
    name = "post"
    type = "cylinder"           # box (size), cylinder / capsule (radius, length),
    radius = 30                 # sphere (radius), mesh (file, scale)
    length = 400
    xyz = [250, 150, 0]         # centre of the shape
    rpy = [0, 0, 0]             # optional

A mesh's ``file`` is relative to the cell file, its coordinates in ``length_unit`` times
``scale`` (one number, or one per axis). Unknown or misspelt keys, a missing size, a size
<= 0 (quoted in the file's unit) and duplicate names are refused with
:class:`~scara_opt.errors.CellError` naming the obstacle and the key.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from scara_opt.checks import check_path, check_text, describe
from scara_opt.collision.geometry import name_pairs
from scara_opt.collision.obstacles import Box, Capsule, Cylinder, Mesh, Obstacle, Sphere
from scara_opt.errors import CellError, InputError
from scara_opt.model.dh import ANGLE_UNITS, LENGTH_UNITS
from scara_opt.model.dh_file import check_keys, read_toml

__all__ = ["CELL_KEYS", "Cell", "OBSTACLE_KEYS", "load_cell"]

#: the keys a cell file may hold at its top level
CELL_KEYS = ("name", "title", "source", "notes", "length_unit", "angle_unit", "allowed",
             "obstacles")

#: the keys of an ``[[obstacles]]`` entry, by type (``name``, ``type``, ``xyz``, ``rpy`` always)
OBSTACLE_KEYS = {"box": ("size",), "cylinder": ("radius", "length"),
                 "capsule": ("radius", "length"), "sphere": ("radius",),
                 "mesh": ("file", "scale")}


class Cell:
    """The obstacles of a cell, and the contacts that are allowed.

    Attributes:
        obstacles: the obstacles, in order (names unique).
        allowed: ``(a, b)`` pairs of bodies whose contact is not a collision: a robot
            link or body with an obstacle (a gripper in its nest, the base on its column).
            Checked against the robot's bodies when a checker is built.
        name: a name for reports.
        source: where the cell comes from (a file path, or ``"python"``).
    """

    def __init__(self, obstacles: Iterable[Obstacle] = (), *, allowed: Iterable = (),
                 name: str = "cell", source: str = "python") -> None:
        try:
            items = tuple(obstacles)
        except TypeError:
            raise CellError(f"obstacles must be a list of Box, Cylinder, Capsule, Sphere or "
                            f"Mesh; got {describe(obstacles)}") from None
        seen: set[str] = set()
        for ob in items:
            if not isinstance(ob, Obstacle) or type(ob) is Obstacle:
                raise CellError(f"obstacles must be Box, Cylinder, Capsule, Sphere or Mesh; "
                                f"got {describe(ob)}")
            if ob.name in seen:
                raise CellError(f"two obstacles are named {ob.name!r}; give each its own name "
                                "(contacts are reported by name)")
            seen.add(ob.name)
        try:
            pairs = tuple(name_pairs(allowed, "allowed"))
        except CellError:
            raise
        except InputError as exc:
            raise CellError(str(exc)) from None
        for a, b in pairs:
            if a in seen and b in seen:
                raise CellError(f"allowed pair ({a!r}, {b!r}) names two obstacles: obstacles "
                                "are never checked against each other; an allowed pair is a "
                                "robot link or body and an obstacle")
        check_text("the cell's name", name, CellError)
        self.obstacles: tuple[Obstacle, ...] = items
        self.allowed: tuple[tuple[str, str], ...] = pairs
        self.name = name
        self.source = source

    @property
    def names(self) -> list[str]:
        """The obstacles' names, in order."""
        return [ob.name for ob in self.obstacles]

    def __getitem__(self, name: str) -> Obstacle:
        for ob in self.obstacles:
            if ob.name == name:
                return ob
        raise KeyError(f"no obstacle named {name!r}; obstacles: {', '.join(self.names)}")

    def __len__(self) -> int:
        return len(self.obstacles)

    def __repr__(self) -> str:
        listed = ", ".join(self.names[:6]) + (", ..." if len(self) > 6 else "")
        count = f"{len(self)} obstacle{'' if len(self) == 1 else 's'}"
        return f"Cell({self.name!r}: {count} [{listed}])"

    @classmethod
    def from_toml(cls, path: str | Path) -> Cell:
        """Read a cell file (see the module docstring); same as :func:`load_cell`."""
        return load_cell(path)


def _number(entry: dict, key: str, where: str) -> float:
    value = entry.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CellError(f"{where}: {key} must be a number; got {describe(value)}")
    return _float(value, key, where)


def _float(value: int | float, key: str, where: str) -> float:
    """``value`` as a float, or CellError for an integer beyond any float."""
    try:
        return float(value)
    except OverflowError:
        raise CellError(f"{where}: {key} {describe(value)} is too large for any size or "
                        "position; give its real value") from None


def _triple(entry: dict, key: str, where: str, unit: float,
            default: list | None = None) -> tuple[float, float, float]:
    """``entry[key]``: a list of 3 numbers, each times ``unit`` (to SI)."""
    value = entry.get(key, default)
    if (not isinstance(value, list) or len(value) != 3
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
        raise CellError(f"{where}: {key} must be a list of 3 numbers; got {describe(value)}")
    x, y, z = (_float(v, key, where) * unit for v in value)
    return x, y, z


def _obstacle(entry: object, i: int, L: float, A: float, folder: Path, where: str,
              unit: str = "m") -> Obstacle:
    """One ``[[obstacles]]`` entry, in SI units."""
    at = f"{where}: obstacles entry {i + 1}"
    if not isinstance(entry, dict):
        raise CellError(f"{at} must be a table (key = value lines); got {describe(entry)}")
    name = entry.get("name")
    if not isinstance(name, str) or not name:
        raise CellError(f"{at} needs a name = \"...\" (a non-empty string)")
    at = f"{where}: obstacle {name!r}"
    kind = entry.get("type")
    if kind not in OBSTACLE_KEYS:  # a misspelt "type" key first gets its "did you mean"
        check_keys(entry, ("name", "type", "xyz", "rpy",
                           *dict.fromkeys(k for keys in OBSTACLE_KEYS.values() for k in keys)),
                   at, CellError)
        raise CellError(f"{at}: type must be one of {', '.join(OBSTACLE_KEYS)}; got "
                        f"{describe(kind)}")
    check_keys(entry, ("name", "type", "xyz", "rpy", *OBSTACLE_KEYS[kind]), at, CellError)
    missing = [k for k in OBSTACLE_KEYS[kind] if k not in entry and k != "scale"]
    if missing:
        raise CellError(f"{at}: a {kind} needs {', '.join(missing)}")
    for key in ("size", "radius", "length"):  # checked in the file's own units
        values = entry.get(key)
        for v in values if isinstance(values, list) else [values]:
            if isinstance(v, (int, float)) and not isinstance(v, bool) and not v > 0:
                raise CellError(f"{at}: {key} {values} {unit}: a size must be > 0; give its "
                                "real size (a flat plate is a thin box)")
    xyz = _triple(entry, "xyz", at, L, [0, 0, 0])
    rpy = _triple(entry, "rpy", at, A, [0, 0, 0])
    if kind == "box":
        return Box(name, _triple(entry, "size", at, L), xyz=xyz, rpy=rpy)
    if kind in ("cylinder", "capsule"):
        shape = Capsule if kind == "capsule" else Cylinder
        return shape(name, _number(entry, "radius", at) * L, _number(entry, "length", at) * L,
                     xyz=xyz, rpy=rpy)
    if kind == "sphere":
        return Sphere(name, _number(entry, "radius", at) * L, xyz=xyz, rpy=rpy)
    file = entry["file"]
    if not isinstance(file, str):
        raise CellError(f"{at}: file must be a path (a string); got {describe(file)}")
    scale = entry.get("scale", 1.0)
    if isinstance(scale, (int, float)) and not isinstance(scale, bool):  # one for all axes
        scale = [scale] * 3
    return Mesh(name, folder / file, _triple({"scale": scale}, "scale", at, L), xyz=xyz,
                rpy=rpy)


def load_cell(path: str | Path) -> Cell:
    """Read a cell file (TOML; see the module docstring) into a :class:`Cell` in SI units.

    Raises:
        CellError: a missing or unreadable file, TOML syntax, an unknown key or unit, a
            missing size, a size <= 0, duplicate names, a bad ``allowed`` entry.
        MeshNotFoundError: a mesh file that cannot be found.
    """
    path = check_path("a cell file path", path, CellError)
    where = f"cell file {str(path)!r}"
    data = read_toml(path, where, "a TOML cell file", CellError)
    check_keys(data, CELL_KEYS, where, CellError)
    lu, au = data.get("length_unit"), data.get("angle_unit", "rad")
    if lu not in LENGTH_UNITS or au not in ANGLE_UNITS:
        raise CellError(f"{where}: length_unit must be one of {sorted(LENGTH_UNITS)} and "
                        f"angle_unit one of {sorted(ANGLE_UNITS)}; got {lu!r} and {au!r}")
    entries = data.get("obstacles", [])
    if not isinstance(entries, list):
        raise CellError(f"{where}: obstacles must be [[obstacles]] tables")
    obstacles = [_obstacle(e, i, LENGTH_UNITS[lu], ANGLE_UNITS[au], path.parent, where, lu)
                 for i, e in enumerate(entries)]
    allowed = data.get("allowed", [])
    if not isinstance(allowed, list):
        raise CellError(f"{where}: allowed must be a list of [body, body] pairs")
    name = data.get("name", path.stem)
    if not isinstance(name, str):
        raise CellError(f"{where}: name must be a string; got {describe(name)}")
    try:
        return Cell(obstacles, allowed=allowed, name=name, source=str(path))
    except CellError as exc:
        raise CellError(f"{where}: {exc}") from None
