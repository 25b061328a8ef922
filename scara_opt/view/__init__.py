"""A 3-D viewer that needs no server: one self-contained HTML file any browser opens.

Built on meshcat (the viewer behind Pinocchio's ``MeshcatVisualizer``) and its static HTML
export: the page inlines meshcat's JavaScript and the recorded scene, so it works offline,
from disk or as a CI artefact. The robot is loaded by Pinocchio's ``MeshcatVisualizer``:
the URDF's meshes and primitives when it has ``<visual>`` elements, a stick figure
otherwise (:mod:`scara_opt.view.geometry`), and a cell's obstacles in grey (a motion
planned in a cell brings its own). The tool path is drawn as a line; a motion is
one meshcat animation with play / pause and a time slider (the "Animations" folder of the
page's controls).

    import scara_opt as so
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize([[0, 0, 0, 0], [1.0, -1.2, 0.04, 0.5]], robot)
    so.view.write_html(robot, traj, "move.html")       # open it in any browser

Needs ``meshcat`` (the ``view`` extra: ``pip install "scara-opt[view]"``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.errors import InputError
from scara_opt.model.robot import Robot, check_robot

if TYPE_CHECKING:
    import meshcat

    from scara_opt.collision.cell import Cell
    from scara_opt.trajectory import JointPath, Trajectory

__all__ = ["Frames", "frames", "html", "write_html"]

Array = NDArray[np.float64]

#: frames per second of an animation (a Trajectory is sampled at this rate)
FPS = 30
_PATH_RGB = 0xD62728


@dataclass(frozen=True)
class Frames:
    """The configurations an animation shows.

    Attributes:
        q: (n, nq) joint values, one row per frame [rad or m].
        fps: frames per second of the animation.
    """

    q: Array
    fps: float

    @property
    def count(self) -> int:
        """Number of frames ``n``."""
        return int(self.q.shape[0])


def frames(robot: Robot, motion: Trajectory | JointPath | ArrayLike, fps: float = FPS) -> Frames:
    """The configurations an animation of ``motion`` shows, one per frame.

    A Trajectory is sampled at ``fps`` over its duration, both ends included; a JointPath
    gives one frame per point, an (n, nq) array one per row, an (nq,) pose one frame.

    Raises:
        InputError: ``fps`` not positive, or joint values of the wrong shape or not finite
            (values outside the joint limits are shown as they are).
    """
    from scara_opt.trajectory import JointPath, Trajectory

    if not (isinstance(fps, (int, float)) and not isinstance(fps, bool) and 0 < fps <= 1000):
        raise InputError(f"fps must be a number in (0, 1000]; got {fps!r}")
    if isinstance(motion, Trajectory):
        Q = motion.evaluate(motion.times(1.0 / fps))
    elif isinstance(motion, JointPath):
        Q = motion.q
    else:
        Q = np.asarray(motion, float)
        Q = Q[None, :] if Q.ndim == 1 else Q
    return Frames(robot.check_q_batch(Q), float(fps))


def html(robot: Robot, motion: Trajectory | JointPath | ArrayLike, fps: float = FPS,
         title: str | None = None, tool_path: bool = True, cell: Cell | None = None) -> str:
    """The self-contained HTML page animating ``motion`` (see :func:`frames`).

    Args:
        robot: the robot.
        motion: a Trajectory, a JointPath, (n, nq) joint values or one (nq,) pose.
        fps: frames per second (a Trajectory is sampled at this rate).
        title: the page title (default: the robot's name).
        tool_path: draw the tip's path as a line (a motion planned in a cell: the path
            planned around its obstacles).
        cell: a :class:`~scara_opt.Cell` whose obstacles are drawn; default the cell a
            :class:`~scara_opt.MotionTrajectory` was planned in, if any.

    Raises:
        InputError: ``cell`` not a Cell.
    """
    from scara_opt.collision.cell import Cell
    from scara_opt.motion import MotionTrajectory
    from scara_opt.view.geometry import add_obstacles, visual_model

    try:
        from scara_opt.view.scene import (
            Animation,
            MeshcatVisualizer,
            g,
            recording_visualizer,
            static_html,
        )
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError(f"scara_opt.view needs meshcat ({exc}); install it with "
                                  "pip install \"scara-opt[view]\"", name=exc.name) from None

    check_robot(robot)
    fr = frames(robot, motion, fps)
    if cell is None and isinstance(motion, MotionTrajectory) and motion.checker is not None:
        cell = motion.checker.cell
    if cell is not None and not isinstance(cell, Cell):
        raise InputError(f"cell must be a scara_opt.Cell or None; got {type(cell).__name__}")
    geom = visual_model(robot)
    if cell is not None:
        geom = add_obstacles(geom, cell)
    viz = MeshcatVisualizer(robot.model, None, geom)
    vis = recording_visualizer()
    viz.initViewer(viewer=vis)
    viz.loadViewerModel(rootNodeName=robot.name)
    viz.display(fr.q[0])  # the first pose, with any mesh scale
    if tool_path and fr.count > 1:
        tips = robot.positions(fr.q)
        vis["tool_path"].set_object(g.Line(g.PointsGeometry(tips.T),
                                           g.LineBasicMaterial(color=_PATH_RGB, linewidth=2)))
    _aim_camera(vis, robot, fr.q)
    if fr.count > 1:
        anim = Animation(default_framerate=fr.fps)
        data, gdata = robot.model.createData(), pin.GeometryData(geom)
        for i, q in enumerate(fr.q):
            pin.forwardKinematics(robot.model, data, q)
            pin.updateGeometryPlacements(robot.model, data, geom, gdata)
            with anim.at_frame(vis, i) as frame:
                for k, obj in enumerate(geom.geometryObjects):
                    name = viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)
                    frame[name].set_transform(gdata.oMg[k].homogeneous)
        vis.set_animation(anim, play=False)
    return static_html(vis, title or f"scara_opt: {robot.name}")


def _aim_camera(vis: meshcat.Visualizer, robot: Robot, Q: Array) -> None:
    """Pivot the camera on the motion's centre and back it off to show the whole arm.

    meshcat's camera node is y-up below ``rotated``; the view looks down at about 30°.
    """
    pts = robot.joint_origins(Q).reshape(-1, 3)
    centre = (pts.min(axis=0) + pts.max(axis=0)) / 2
    size = max(float(np.linalg.norm(pts - centre, axis=1).max()), 0.05)
    pivot = np.eye(4)
    pivot[:3, 3] = centre
    vis["/Cameras/default"].set_transform(pivot)
    d = 2.6 * size
    vis["/Cameras/default/rotated/<object>"].set_property("position", [0.8 * d, 0.6 * d, 0.5 * d])


def write_html(robot: Robot, motion: Trajectory | JointPath | ArrayLike, path: str | Path,
               fps: float = FPS, title: str | None = None, tool_path: bool = True,
               cell: Cell | None = None) -> Path:
    """Write :func:`html` to ``path`` (parent folders created); returns the path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(html(robot, motion, fps, title, tool_path, cell), encoding="utf-8")
    return out
