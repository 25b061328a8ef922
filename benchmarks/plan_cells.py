"""The robots and cells of benchmarks/bench_plan.py: which robot, which cell, on each row.

Robots (each with the options a user passes to plan it):

* ``zavar2024``: the bundled SCARA (0.2 + 0.2 m arms, capsules from its robot file);
* ``irb910sc_like``: a SCARA of another size and base placement: 0.30 + 0.25 m arms, a
  180 mm quill, its base 0.12 m above the floor and off the origin at (0.15, -0.10) m,
  turned 30 degrees (a fixed first DH row); capsules 35/30/10/15 mm;
* ``large_scara``: 0.55 + 0.45 m arms, a 400 mm quill, its base at (-0.3, 0.2, 0.25) m;
* ``ur5_dh``: a UR5-class 6R arm of 45 mm capsules (tests/data), joints within ±π;
* ``ur5``: example-robot-data's UR5 from its published URDF with its own collision meshes
  (7 links, 446-1,176 triangles each; joint limits as published, ±2π but the elbow ±π);
  no acceleration limits in the URDF: ``amax=4`` rad/s²;
* ``panda``: example-robot-data's Panda, 7 joints, its own collision meshes (the hand
  locked), ``amax=5`` rad/s².

Cells: built here, in SI units; ``fixture`` cells hold an STL mesh written by trimesh into
a temporary folder (a CAD fixture as users have them), the others primitives.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import scara_opt as so

DATA = Path(__file__).resolve().parent.parent / "tests" / "data"


@dataclass
class Bench:
    """One row's robot and cell, and how the robot is planned."""

    robot_name: str
    cell_name: str
    robot: so.Robot
    cell: so.Cell
    checker: dict = field(default_factory=dict)   # CollisionChecker keyword arguments
    plan: dict = field(default_factory=dict)      # so.plan keyword arguments (amax=)


def _scara_toml(name: str, base: tuple[float, float, float, float], a1: float, a2: float,
                stroke: float, radii: tuple[float, float, float, float]) -> Path:
    """A SCARA robot file (mm, deg) with a fixed first row placing its base: (x, y, z, yaw)."""
    x, y, z, yaw = base
    r1, r2, r3, r4 = radii
    text = f'''name = "{name}"
title = "{name}, a benchmark SCARA (assumed geometry)"
source = "benchmarks/plan_cells.py (assumed)"
convention = "standard"
length_unit = "mm"
angle_unit = "deg"

[[joints]]
name = "mount"
type = "fixed"
a = {math.hypot(x, y) * 1e3:.6f}
theta = {math.degrees(math.atan2(y, x)):.6f}
d = {z * 1e3:.6f}

[[joints]]
name = "j1"
type = "revolute"
theta = {yaw - math.degrees(math.atan2(y, x)):.6f}
a = {a1 * 1e3:.6f}
lower = -140
upper = 140
velocity = 300
acceleration = 1200
radius = {r1 * 1e3:.6f}

[[joints]]
name = "j2"
type = "revolute"
a = {a2 * 1e3:.6f}
lower = -145
upper = 145
velocity = 400
acceleration = 1600
radius = {r2 * 1e3:.6f}

[[joints]]
name = "j3"
type = "prismatic"
sign = -1
lower = 0
upper = {stroke * 1e3:.6f}
velocity = 1000
acceleration = 4000
radius = {r3 * 1e3:.6f}

[[joints]]
name = "j4"
type = "revolute"
lower = -360
upper = 360
velocity = 1500
acceleration = 6000
radius = {r4 * 1e3:.6f}
'''
    path = Path(tempfile.mkdtemp(prefix="bench_plan_")) / f"{name}.toml"
    path.write_text(text)
    return path


def _bracket_stl(folder: Path) -> Path:
    """A closed U-shaped fixture (three boxes, mm) as an STL, as CAD exports them."""
    import trimesh

    parts = [trimesh.creation.box((240, 20, 160)), trimesh.creation.box((240, 20, 160)),
             trimesh.creation.box((20, 220, 160))]
    parts[0].apply_translation((0, -100, 0))
    parts[1].apply_translation((0, 100, 0))
    parts[2].apply_translation((-110, 0, 0))
    path = folder / "bracket.stl"
    trimesh.util.concatenate(parts).export(path)
    return path


@dataclass(frozen=True)
class Placement:
    """Maps zavar2024's cell coordinates onto another SCARA [m, rad].

    Horizontally: scaled by the reach ratio, turned by the base's yaw about its base and moved
    to it; vertically: zavar2024's tool range (z from -0.050 to -0.098 m) onto the robot's own.
    """

    base: tuple[float, float]
    yaw: float
    scale: float
    hi: float       # the robot's tool z at the top of its stroke [m]
    lo: float       # ... at the bottom [m]

    @classmethod
    def of(cls, robot: so.Robot, base: tuple[float, float], yaw: float,
           reach: float) -> Placement:
        q = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
        prismatic = [k for k, t in enumerate(robot.joint_types) if t == "prismatic"][0]
        zs = []
        for d in (robot.lower[prismatic], robot.upper[prismatic]):
            q[prismatic] = d
            zs.append(float(robot.fk(q)[2, 3]))
        return cls(base, yaw, reach / 0.4, max(zs), min(zs))

    def z(self, z: float) -> float:
        return self.hi + (z + 0.050) * (self.hi - self.lo) / 0.048

    def height(self, h: float) -> float:
        return h * (self.hi - self.lo) / 0.048

    def xyz(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        x, y = self.scale * x, self.scale * y
        return (self.base[0] + c * x - s * y, self.base[1] + s * x + c * y, self.z(z))


def scara_cells(name: str, robot: so.Robot, at: Placement, stl: Path) -> list[Bench]:
    """zavar2024's post, rack and table cells (issue 30's benchmark), placed for ``robot``.

    ``table`` holds an STL fixture (a CAD bracket, as users have them) where the original
    had a block; each cell is zavar2024's own for zavar2024 (the identity placement).
    """
    s, h = at.scale, at.height

    def box(label: str, size: tuple, xyz: tuple, yaw: float = 0.0) -> so.Box:
        return so.Box(label, (s * size[0], s * size[1], h(size[2])), xyz=at.xyz(*xyz),
                      rpy=(0, 0, yaw + at.yaw))

    def cyl(label: str, radius: float, length: float, xyz: tuple) -> so.Cylinder:
        return so.Cylinder(label, s * radius, h(length), xyz=at.xyz(*xyz))

    post = so.Cell([cyl("column", 0.03, 0.4, (0.28, 0.12, 0.0)),
                    box("wall", (0.12, 0.012, 0.4), (0.05, -0.3, 0.0), 0.4)], name="post")
    bars = [box(f"bar{k}", (0.012, 0.5, 0.03), (0.16 + 0.09 * k, 0.0, -0.09)) for k in range(3)]
    rack = so.Cell(bars + [box("bar_y", (0.3, 0.012, 0.03), (0.25, 0.22, -0.09))], name="rack")
    bracket = so.Mesh("bracket", stl, scale=(2.5e-4 * s, 2.5e-4 * s, h(0.05) / 160),
                      xyz=at.xyz(0.32, 0.12, -0.105), rpy=(0, 0, 0.7 + at.yaw))
    table = so.Cell([box("table", (0.9, 0.9, 0.02), (0.1, 0.0, -0.14)),
                     cyl("tall1", 0.025, 0.3, (0.30, -0.12, 0.0)),
                     cyl("tall2", 0.02, 0.3, (0.12, 0.30, 0.0)), bracket,
                     box("tray", (0.12, 0.08, 0.035), (0.18, -0.28, -0.112)),
                     so.Sphere("ball", s * 0.025, xyz=at.xyz(0.22, 0.05, -0.105)),
                     so.Capsule("pipe", s * 0.012, s * 0.25, xyz=at.xyz(-0.05, 0.3, -0.09),
                                rpy=(0, 1.5708, 0.3 + at.yaw))],
                    name="table")
    return [Bench(name, c.name, robot, c) for c in (post, rack, table)]


def arm_cells(name: str, robot: so.Robot, plan: dict, stl: Path, checker: dict | None = None,
              table: float = 0.0) -> list[Bench]:
    """A table-and-box cell, a shelf cell and an STL fixture cell for a 6R/7R arm.

    ``table``: the height [m] of the table top (the base stands on it; 3 mm into it for the
    mesh robots, as a mounted robot's base mesh usually is).
    """
    top = table + 0.003
    table_box = so.Cell([so.Box("table", (1.4, 1.4, 0.04), xyz=(0.0, 0.0, top - 0.02)),
                         so.Box("box", (0.2, 0.25, 0.3), xyz=(0.45, 0.2, top + 0.15)),
                         so.Box("crate", (0.25, 0.2, 0.2), xyz=(-0.1, -0.5, top + 0.1))],
                        name="table_box")
    shelf = so.Cell([so.Box("table", (1.4, 1.4, 0.04), xyz=(0.0, 0.0, top - 0.02)),
                     so.Box("shelf_low", (0.3, 0.8, 0.02), xyz=(0.55, 0.0, top + 0.25)),
                     so.Box("shelf_high", (0.3, 0.8, 0.02), xyz=(0.55, 0.0, top + 0.55)),
                     so.Box("side_l", (0.3, 0.02, 0.7), xyz=(0.55, 0.4, top + 0.35)),
                     so.Box("side_r", (0.3, 0.02, 0.7), xyz=(0.55, -0.4, top + 0.35)),
                     so.Box("back", (0.02, 0.8, 0.7), xyz=(0.71, 0.0, top + 0.35)),
                     so.Cylinder("post", 0.04, 0.8, xyz=(-0.35, 0.35, top + 0.4))],
                    name="shelf")
    fixture = so.Cell([so.Box("table", (1.4, 1.4, 0.04), xyz=(0.0, 0.0, top - 0.02)),
                       so.Mesh("bracket", stl, scale=(1e-3,) * 3, xyz=(0.45, -0.1, top + 0.08),
                               rpy=(0, 0, 0.5))], name="fixture")
    return [Bench(name, c.name, robot, c, dict(checker or {}), dict(plan))
            for c in (table_box, shelf, fixture)]


def benches() -> list[Bench]:
    """Every robot and cell of the benchmark (the mesh robots only with example-robot-data)."""
    folder = Path(tempfile.mkdtemp(prefix="bench_plan_"))
    stl = _bracket_stl(folder)
    out: list[Bench] = []
    zavar = so.load_robot("zavar2024")
    out += scara_cells("zavar2024", zavar, Placement.of(zavar, (0.0, 0.0), 0.0, 0.4), stl)
    irb = so.load_robot(_scara_toml("irb910sc_like", (0.15, -0.10, 0.12, 30.0), 0.30, 0.25,
                                    0.18, (0.035, 0.03, 0.01, 0.015)))
    out += scara_cells("irb910sc_like", irb,
                       Placement.of(irb, (0.15, -0.10), math.radians(30.0), 0.55), stl)
    big = so.load_robot(_scara_toml("large_scara", (-0.3, 0.2, 0.25, -20.0), 0.55, 0.45, 0.4,
                                    (0.05, 0.045, 0.015, 0.02)))
    out += scara_cells("large_scara", big,
                       Placement.of(big, (-0.3, 0.2), math.radians(-20.0), 1.0), stl)
    arm = so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")
    arm = arm.with_limits(**{n: (-math.pi, math.pi) for n in arm.joint_names})
    out += arm_cells("ur5_dh", arm, {}, stl, {"radius": 0.045}, table=-0.063)
    try:
        from scara_opt.model.catalogue import example_robot_data_urdf

        ur5 = so.Robot.from_urdf(example_robot_data_urdf(
            "ur_description/urdf/ur5_robot.urdf"), tip="ee_link")
        panda = so.Robot.from_urdf(example_robot_data_urdf("panda_description/urdf/panda.urdf"),
                                   tip="panda_hand")
    except ModuleNotFoundError:
        print("example-robot-data not installed (pip install 'scara-opt[robots]'): the mesh "
              "robots' rows are left out")
        return out
    out += arm_cells("ur5", ur5, {"amax": 4.0}, stl)
    out += arm_cells("panda", panda, {"amax": 5.0}, stl)
    return out
