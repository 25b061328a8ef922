"""What the viewer draws of a robot: the URDF's visual geometry, or simple shapes.

A URDF with ``<visual>`` elements gives its meshes and primitives (Pinocchio's
``buildGeomFromUrdfString``, meshes found through the robot's ``mesh_dir``). A URDF
without any (the bundled DH robots) gets a stick figure: a cylinder from each joint frame
to the next joint's placement (rigid in that frame; a prismatic joint's slide shows as the
gap it opens), a sphere at each joint and a small one at the tip. A cell's obstacles are
added fixed in the world (:func:`add_obstacles`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import coal
import numpy as np
import pinocchio as pin

from scara_opt.collision.obstacles import Mesh
from scara_opt.model.robot import Robot

if TYPE_CHECKING:
    from scara_opt.collision.cell import Cell

__all__ = ["LINK_RADIUS", "add_obstacles", "has_visuals", "visual_model"]

#: stick-figure link radius, as a fraction of the chain's length
LINK_RADIUS = 0.025
_LINK_RGBA = np.array([0.35, 0.45, 0.6, 1.0])
_JOINT_RGBA = np.array([0.95, 0.55, 0.15, 1.0])
_TIP_RGBA = np.array([0.85, 0.1, 0.1, 1.0])
#: obstacles' colours, one after the other; the table the grid lies on is _TABLE_RGBA
_OBSTACLE_RGBA = np.array([[0.55, 0.63, 0.5, 0.85], [0.74, 0.6, 0.43, 0.85],
                           [0.45, 0.6, 0.66, 0.85], [0.58, 0.52, 0.68, 0.85],
                           [0.72, 0.52, 0.52, 0.85]])
_TABLE_RGBA = np.array([0.8, 0.79, 0.76, 0.9])


def has_visuals(robot: Robot) -> bool:
    """True if the robot's URDF has at least one ``<visual>`` element."""
    return "<visual" in robot._init_args[0]


def visual_model(robot: Robot) -> pin.GeometryModel:
    """The geometry to draw, attached to the joints of ``robot.model``."""
    urdf_text, mesh_dir = robot._init_args[0], robot._init_args[6]
    if has_visuals(robot):
        dirs = [mesh_dir] if mesh_dir else []
        return pin.buildGeomFromUrdfString(robot.model, urdf_text, pin.GeometryType.VISUAL,
                                           package_dirs=dirs)
    return _sticks(robot)


def _cylinder(name: str, parent: int, a: np.ndarray, b: np.ndarray, r: float,
              rgba: np.ndarray) -> pin.GeometryObject | None:
    """A cylinder from ``a`` to ``b`` in joint ``parent``'s frame (coal's axis is z)."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return None
    z = d / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    R = np.column_stack([x, np.cross(z, x), z])
    obj = pin.GeometryObject(name, parent, pin.SE3(R, (a + b) / 2), coal.Cylinder(r, length))
    obj.meshColor = rgba
    return obj


def _sphere(name: str, parent: int, at: np.ndarray, r: float,
            rgba: np.ndarray) -> pin.GeometryObject:
    obj = pin.GeometryObject(name, parent, pin.SE3(np.eye(3), at), coal.Sphere(r))
    obj.meshColor = rgba
    return obj


def _sticks(robot: Robot) -> pin.GeometryModel:
    model = robot.model
    ends = [model.jointPlacements[k + 1].translation for k in range(1, model.njoints - 1)]
    ends.append(robot.tip_placement[:3, 3])
    scale = sum(float(np.linalg.norm(e)) for e in ends) + float(
        np.linalg.norm(model.jointPlacements[1].translation))
    r = LINK_RADIUS * max(scale, 0.05)
    geom = pin.GeometryModel()
    base = _cylinder("base", 0, np.zeros(3), model.jointPlacements[1].translation, r, _LINK_RGBA)
    for obj in ([base] if base else []):
        geom.addGeometryObject(obj)
    for k in range(1, model.njoints):
        geom.addGeometryObject(_sphere(f"joint{k}", k, np.zeros(3), 1.6 * r, _JOINT_RGBA))
        link = _cylinder(f"link{k}", k, np.zeros(3), ends[k - 1], r, _LINK_RGBA)
        if link is not None:
            geom.addGeometryObject(link)
    tip_joint = model.frames[robot.tip_id].parentJoint
    geom.addGeometryObject(_sphere("tip", tip_joint, robot.tip_placement[:3, 3], 1.2 * r,
                                   _TIP_RGBA))
    return geom


def add_obstacles(geom: pin.GeometryModel, cell: Cell,
                  table: str | None = None) -> pin.GeometryModel:
    """``geom`` with a cell's obstacles added, fixed in the world (meshes from their file).

    ``cell``: a :class:`~scara_opt.Cell`; ``table``: the name of the one drawn in light grey
    (the others take the colours of a palette in turn). Returns ``geom`` itself.
    """
    others = (ob for ob in cell.obstacles if ob.name != table)
    colour = {ob.name: _OBSTACLE_RGBA[k % len(_OBSTACLE_RGBA)] for k, ob in enumerate(others)}
    for ob in cell.obstacles:
        obj = pin.GeometryObject(f"obstacle_{ob.name}", 0, ob.placement, ob.shape())
        if isinstance(ob, Mesh):
            obj.meshPath = str(ob.path)
            obj.meshScale = np.array(ob.scale)
        obj.meshColor = colour.get(ob.name, _TABLE_RGBA)
        geom.addGeometryObject(obj)
    return geom
