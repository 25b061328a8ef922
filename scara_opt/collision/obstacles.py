"""The obstacles of a cell: box, cylinder, sphere, capsule and mesh, each at a pose.

Sizes and positions in metres, angles in radians (a cell file may use other units:
:mod:`scara_opt.collision.cell`). A pose is ``xyz`` (the shape's centre) and ``rpy``
(roll, pitch, yaw about the fixed x, y, z axes, as URDF's ``<origin rpy=>``). Cylinders
and capsules stand along their frame's z axis, centred on ``xyz``. Every size is checked
at construction: zero, negative or non-finite sizes raise :class:`~scara_opt.errors.CellError`.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import coal
import numpy as np
import pinocchio as pin

from scara_opt.checks import check_path, check_text, describe, is_real
from scara_opt.errors import CellError, MeshNotFoundError

log = logging.getLogger(__name__)

__all__ = ["Box", "Capsule", "Cylinder", "Mesh", "Obstacle", "Sphere"]


#: the largest position or size of an obstacle [m]: a cell spans metres, and coal's
#: distances lose their micrometres far beyond this (a box at 1e300 m was "0.000 mm deep")
MAX_EXTENT = 1e4

#: the widest a mesh obstacle may be [m] (wider: a file in mm read as metres)
MESH_EXTENT = 50.0

#: the smallest size of an obstacle [m] (a 1e-300 m box inside a link gave -inf mm)
MIN_SIZE = 1e-6


def _finite(value: object) -> float | None:
    """``value`` as a finite float, or None (not a real number, inf, NaN, or too large)."""
    if not is_real(value):
        return None
    try:
        v = float(value)
    except OverflowError:  # an int beyond any float
        return None
    return v if math.isfinite(v) else None


def _vector(owner: str, name: str, value: object, n: int = 3,
            limit: float = MAX_EXTENT) -> tuple[float, ...]:
    """``value`` as ``n`` finite floats within ±``limit``, or CellError naming the field."""
    try:
        items = list(value)  # type: ignore[call-overload]
    except TypeError:
        items = None
    floats = None if items is None else [_finite(v) for v in items]
    if floats is None or len(floats) != n or any(v is None for v in floats):
        raise CellError(f"obstacle {owner!r}: {name} must be {n} finite numbers; got "
                        f"{describe(value)}")
    out = tuple(float(v) for v in floats if v is not None)
    if max(abs(v) for v in out) > limit:
        raise CellError(f"obstacle {owner!r}: {name} {list(out)} lies beyond {limit:g} m "
                        "(no cell is that large: check the units)")
    return out


def _size(owner: str, name: str, value: object, unit: str = "m") -> float:
    v = _finite(value)
    if v is None or v <= 0:
        raise CellError(f"obstacle {owner!r}: {name} must be a finite number > 0 [{unit}]; got "
                        f"{describe(value)}; give its real size (a flat plate is a thin box)")
    if unit == "m" and not MIN_SIZE <= v <= MAX_EXTENT:
        raise CellError(f"obstacle {owner!r}: {name} {v:g} m is outside [{MIN_SIZE:g}, "
                        f"{MAX_EXTENT:g}] m; give its real size (check the units)")
    return v


@dataclass(frozen=True)
class Obstacle:
    """What every obstacle has: a name and a pose.

    Attributes:
        name: unique within its cell (contacts and errors name it).
        xyz: position of the shape's centre (3,) [m].
        rpy: orientation, roll-pitch-yaw (3,) [rad].
    """

    name: str
    xyz: tuple[float, float, float] = field(default=(0.0, 0.0, 0.0), kw_only=True)
    rpy: tuple[float, float, float] = field(default=(0.0, 0.0, 0.0), kw_only=True)

    kind: ClassVar[str] = "obstacle"

    def __post_init__(self) -> None:
        check_text("an obstacle's name", self.name, CellError)
        object.__setattr__(self, "xyz", _vector(self.name, "xyz", self.xyz))
        object.__setattr__(self, "rpy", _vector(self.name, "rpy", self.rpy))
        self._check()

    def _check(self) -> None:
        raise NotImplementedError

    @property
    def placement(self) -> pin.SE3:
        """The pose as a ``pinocchio.SE3``."""
        return pin.SE3(pin.rpy.rpyToMatrix(*self.rpy), np.array(self.xyz))

    def shape(self) -> coal.CollisionGeometry:
        """The coal shape, in the obstacle's own frame."""
        raise NotImplementedError

    def size_text(self) -> str:
        """The size for messages and reprs, in mm."""
        raise NotImplementedError

    def __repr__(self) -> str:
        xyz = ", ".join(f"{v * 1e3:g}" for v in self.xyz)
        return f"{type(self).__name__}({self.name!r}, {self.size_text()}, at ({xyz}) mm)"


@dataclass(frozen=True, repr=False)
class Box(Obstacle):
    """A box of edge lengths ``size`` (3,) [m] along its frame's x, y, z."""

    size: tuple[float, float, float] = (0.0, 0.0, 0.0)
    kind: ClassVar[str] = "box"

    def _check(self) -> None:
        size = _vector(self.name, "size", self.size)
        object.__setattr__(self, "size", tuple(_size(self.name, f"size[{i}]", v)
                                               for i, v in enumerate(size)))

    def shape(self) -> coal.CollisionGeometry:
        """A ``coal.Box``."""
        return coal.Box(*self.size)

    def size_text(self) -> str:
        """Edge lengths [mm]."""
        return "x".join(f"{v * 1e3:g}" for v in self.size) + " mm"


@dataclass(frozen=True, repr=False)
class Cylinder(Obstacle):
    """A cylinder of ``radius`` and ``length`` [m] along its frame's z axis."""

    radius: float = 0.0
    length: float = 0.0
    kind: ClassVar[str] = "cylinder"

    def _check(self) -> None:
        object.__setattr__(self, "radius", _size(self.name, "radius", self.radius))
        object.__setattr__(self, "length", _size(self.name, "length", self.length))

    def shape(self) -> coal.CollisionGeometry:
        """A ``coal.Cylinder``."""
        return coal.Cylinder(self.radius, self.length)

    def size_text(self) -> str:
        """Radius and length [mm]."""
        return f"r {self.radius * 1e3:g} x {self.length * 1e3:g} mm"


@dataclass(frozen=True, repr=False)
class Capsule(Cylinder):
    """A capsule: a cylinder of ``radius`` and ``length`` [m] with hemispherical ends."""

    kind: ClassVar[str] = "capsule"

    def shape(self) -> coal.CollisionGeometry:
        """A ``coal.Capsule``."""
        return coal.Capsule(self.radius, self.length)


@dataclass(frozen=True, repr=False)
class Sphere(Obstacle):
    """A sphere of ``radius`` [m] centred at ``xyz``."""

    radius: float = 0.0
    kind: ClassVar[str] = "sphere"

    def _check(self) -> None:
        object.__setattr__(self, "radius", _size(self.name, "radius", self.radius))

    def shape(self) -> coal.CollisionGeometry:
        """A ``coal.Sphere``."""
        return coal.Sphere(self.radius)

    def size_text(self) -> str:
        """Radius [mm]."""
        return f"r {self.radius * 1e3:g} mm"


@dataclass(frozen=True, repr=False)
class Mesh(Obstacle):
    """A triangle mesh from a file (STL, OBJ, DAE, ... as coal's assimp loader reads).

    Attributes:
        path: the mesh file.
        scale: per-axis scale (3,) from the file's units to metres (e.g. 0.001 for mm).

    A closed mesh (watertight, consistently wound) is a solid: a body inside it is a
    contact. An open one is a surface (said once, when it is loaded). A contact with a mesh
    reports coal's depth of its triangles (at least 0).
    """

    path: str | Path = ""
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    kind: ClassVar[str] = "mesh"

    def _check(self) -> None:
        check_path(f"obstacle {self.name!r}: path", self.path, CellError)
        if not Path(self.path).is_file():
            raise MeshNotFoundError(str(self.path), f"obstacle {self.name!r}",
                                    "check the path (a cell file's paths are relative to it)")
        scale = _vector(self.name, "scale", self.scale, limit=1e6)
        object.__setattr__(self, "scale", tuple(_size(self.name, f"scale[{i}]", v, "-")
                                                for i, v in enumerate(scale)))
        self._inspect()

    def _inspect(self) -> None:
        """Load the mesh once: refuse an empty one or one metres across (a file in mm read
        as metres), and say so of an open one (a surface: inside it is no contact).

        Raises:
            CellError: unreadable, no triangles, or wider than :data:`MESH_EXTENT`.
        """
        from scara_opt.collision.mesh_bounds import is_closed, mesh_arrays

        shape = self.shape()
        V, T = mesh_arrays(shape)
        where = f"obstacle {self.name!r}: mesh {str(self.path)!r}"
        if not len(T):
            raise CellError(f"{where} has no triangles; export the part as a triangle mesh "
                            "(STL, OBJ)")
        extent = float((V.max(axis=0) - V.min(axis=0)).max())
        if extent > MESH_EXTENT:
            raise CellError(f"{where} spans {extent:.4g} m at scale {list(self.scale)}: more "
                            f"than {MESH_EXTENT:g} m, no fixture is that large; a file in mm "
                            "needs scale = 0.001 (in a cell file in m; in a cell file in mm "
                            "the file's units are taken as mm already)")
        if not is_closed(V, T):
            log.warning("%s is open (not watertight, or not consistently wound): it is taken "
                        "as a surface, so a body inside it is not a contact; close the mesh "
                        "to make it a solid", where)

    def shape(self) -> coal.CollisionGeometry:
        """A coal ``BVHModel`` read by coal's mesh loader."""
        try:
            return coal.MeshLoader().load(str(self.path), np.array(self.scale))
        except ValueError as exc:
            raise CellError(f"obstacle {self.name!r}: coal cannot read mesh {str(self.path)!r} "
                            f"({' '.join(str(exc).split())[-120:]}); convert it to STL or "
                            "OBJ") from None

    def size_text(self) -> str:
        """The file name and scale."""
        return f"mesh {Path(self.path).name} x {self.scale}"


#: obstacle classes by their cell-file ``type``
KINDS: dict[str, type[Obstacle]] = {c.kind: c for c in (Box, Cylinder, Capsule, Sphere, Mesh)}
