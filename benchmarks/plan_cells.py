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


def _around(robot: so.Robot, reach: float, rng: np.random.Generator, n: int,
            z: tuple[float, float]) -> list[tuple[float, float, float]]:
    """``n`` points in the annulus 0.35-0.85 of ``reach`` around the robot's base [m]."""
    base = robot.fk(np.clip(np.zeros(robot.nq), robot.lower, robot.upper))
    origin = robot.model.jointPlacements[1].translation
    out = []
    for _ in range(n):
        r, phi = reach * rng.uniform(0.35, 0.85), rng.uniform(-math.pi, math.pi)
        out.append((origin[0] + r * math.cos(phi), origin[1] + r * math.sin(phi),
                    rng.uniform(*z)))
    del base
    return out


def scara_cells(name: str, robot: so.Robot, reach: float, floor: float, top: float,
                seed: int, stl: Path) -> list[Bench]:
    """A post cell, a rack cell and an STL fixture cell scaled to a SCARA's reach.

    ``floor``/``top``: the heights [m] of the tool's lowest reach and of the arms.
    """
    rng = np.random.default_rng(seed)
    s = reach / 0.4  # zavar2024's reach: the original cells' scale
    p = _around(robot, reach, rng, 4, (floor, top))
    post = so.Cell([so.Cylinder("column", 0.03 * s, top - floor + 0.2, xyz=p[0][:2] + (
                        (top + floor) / 2,)),
                    so.Box("wall", (0.12 * s, 0.012 * s, top - floor + 0.2),
                           xyz=p[1][:2] + ((top + floor) / 2,), rpy=(0, 0, 0.4))], name="post")
    bar_z = floor + 0.35 * (top - floor)
    bars = [so.Box(f"bar{k}", (0.012 * s, 0.5 * s, 0.03 * s),
                   xyz=(p[2][0] + 0.09 * s * (k - 1), p[2][1], bar_z), rpy=(0, 0, 0.3))
            for k in range(3)]
    rack = so.Cell(bars, name="rack")
    fixture = so.Cell([so.Mesh("bracket", stl, scale=(1e-3 * s,) * 3,
                               xyz=p[3][:2] + (floor + 0.05 * s,), rpy=(0, 0, 0.7)),
                       so.Box("table", (2.5 * s, 2.5 * s, 0.02), xyz=p[3][:2] + (
                           floor - 0.04,))], name="fixture")
    return [Bench(name, c.name, robot, c) for c in (post, rack, fixture)]


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
    out += scara_cells("zavar2024", zavar, 0.4, -0.11, 0.0, 1, stl)
    irb = so.load_robot(_scara_toml("irb910sc_like", (0.15, -0.10, 0.12, 30.0), 0.30, 0.25,
                                    0.18, (0.035, 0.03, 0.01, 0.015)))
    out += scara_cells("irb910sc_like", irb, 0.55, 0.12 - 0.18 - 0.05, 0.12, 2, stl)
    big = so.load_robot(_scara_toml("large_scara", (-0.3, 0.2, 0.25, -20.0), 0.55, 0.45, 0.4,
                                    (0.05, 0.045, 0.015, 0.02)))
    out += scara_cells("large_scara", big, 1.0, 0.25 - 0.4 - 0.06, 0.25, 3, stl)
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
