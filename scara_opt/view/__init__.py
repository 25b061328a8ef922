"""A 3-D viewer that needs no server: one self-contained HTML file any browser opens.

Built on meshcat (the viewer behind Pinocchio's ``MeshcatVisualizer``) and its static HTML
export: the page inlines meshcat's JavaScript and the recorded scene, so it works offline,
from disk or as a CI artefact. The robot is loaded by Pinocchio's ``MeshcatVisualizer``:
the URDF's meshes and primitives when it has ``<visual>`` elements, a stick figure
otherwise (:mod:`scara_opt.view.geometry`), and a cell's obstacles, each labelled with its
name (a motion planned in a cell brings its own). The tool path is drawn as a line, a floor
grid under the cell (:mod:`scara_opt.view.framing`: also where the camera looks from), and
a motion is one meshcat animation. A bar along the bottom of the page, with no menu to open,
has play / pause, the clock and a time slider marked with each move's start and duration
and the instant of least clearance (:mod:`scara_opt.view.timeline`).

    import scara_opt as so
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize([[0, 0, 0, 0], [1.0, -1.2, 0.04, 0.5]], robot)
    so.view.write_html(robot, traj, "move.html")       # open it in any browser

Needs ``meshcat`` (the ``view`` extra: ``pip install "scara-opt[view]"``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.errors import InputError
from scara_opt.model.robot import Robot, check_robot
from scara_opt.view import timeline
from scara_opt.view.framing import Layout, layout

if TYPE_CHECKING:
    import meshcat

    from scara_opt.collision.cell import Cell
    from scara_opt.trajectory import JointPath, Trajectory

__all__ = ["Frames", "frames", "html", "write_html"]

Array = NDArray[np.float64]

#: frames per second of an animation (a Trajectory is sampled at this rate)
FPS = 30
#: the camera's vertical field of view [deg]
FOV = 40
_PATH_RGB = 0xD62728
_GRID_RGB = 0x7D8A97
_BACKGROUND = ([0.97, 0.975, 0.98], [0.72, 0.76, 0.8])  # top, bottom (RGB 0-1)


@dataclass(frozen=True)
class Frames:
    """The configurations an animation shows.

    Attributes:
        q: (n, nq) joint values, one row per frame [rad or m].
        t: (n,) the time of each frame [s], increasing.
        fps: frames per second of the animation (between frames at most ``1 / fps`` apart).
    """

    q: Array
    t: Array
    fps: float

    @property
    def count(self) -> int:
        """Number of frames ``n``."""
        return int(self.q.shape[0])


def frames(robot: Robot, motion: Trajectory | JointPath | ArrayLike, fps: float = FPS,
           at: ArrayLike = ()) -> Frames:
    """The configurations an animation of ``motion`` shows, one per frame.

    A Trajectory is sampled at ``fps`` over its duration, both ends included, and at the
    instants ``at`` [s] (shown exactly there: each move's start, the least clearance); a
    JointPath gives one frame per point, an (n, nq) array one per row, an (nq,) pose one
    frame, ``1 / fps`` apart.

    Raises:
        InputError: ``fps`` not positive, ``at`` outside the trajectory (or given with a
            motion that is not a Trajectory), or joint values of
            the wrong shape or not finite (values outside the joint limits are shown as they
            are).
    """
    from scara_opt.trajectory import JointPath, Trajectory

    if not (isinstance(fps, (int, float)) and not isinstance(fps, bool) and 0 < fps <= 1000):
        raise InputError(f"fps must be a number in (0, 1000]; got {fps!r}")
    extra = np.asarray(at, float).ravel()
    if isinstance(motion, Trajectory):
        if not np.all((extra >= 0) & (extra <= motion.duration)):
            raise InputError(f"at: instants must lie in [0, {motion.duration:.6g}] s; got {extra}")
        t = np.unique(np.concatenate([motion.times(1.0 / fps), extra]))
        return Frames(robot.check_q_batch(motion.evaluate(t)), t, float(fps))
    if extra.size:
        raise InputError("at: only a Trajectory has times; pass a Trajectory or no instants")
    Q = motion.q if isinstance(motion, JointPath) else np.asarray(motion, float)
    Q = robot.check_q_batch(Q[None, :] if Q.ndim == 1 else Q)
    return Frames(Q, np.arange(len(Q)) / float(fps), float(fps))


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
        cell: a :class:`~scara_opt.Cell` whose obstacles are drawn and labelled (and, for a
            Trajectory, its least clearance marked); default the cell a
            :class:`~scara_opt.MotionTrajectory` was planned in, if any.

    Raises:
        InputError: ``cell`` not a Cell.
    """
    from scara_opt.collision.cell import Cell
    from scara_opt.motion import MotionTrajectory
    from scara_opt.view.geometry import add_obstacles, visual_model

    try:
        from scara_opt.view.scene import MeshcatVisualizer, recording_visualizer, static_html
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError(f"scara_opt.view needs meshcat ({exc}); install it with "
                                  "pip install \"scara-opt[view]\"", name=exc.name) from None

    check_robot(robot)
    checker = None
    if cell is None and isinstance(motion, MotionTrajectory) and motion.checker is not None:
        cell, checker = motion.checker.cell, motion.checker
    if cell is not None and not isinstance(cell, Cell):
        raise InputError(f"cell must be a scara_opt.Cell or None; got {type(cell).__name__}")
    marks = timeline.marks(robot, motion, cell, checker)
    fr = frames(robot, motion, fps, marks.times)
    lay = layout(robot, fr.q, cell)
    geom = visual_model(robot)
    if cell is not None:
        geom = add_obstacles(geom, cell, lay.table)
    viz = MeshcatVisualizer(robot.model, None, geom)
    vis = recording_visualizer()
    viz.initViewer(viewer=vis)
    viz.loadViewerModel(rootNodeName=robot.name)
    viz.display(fr.q[0])  # the first pose, with any mesh scale
    _draw_floor(vis, lay, robot.joint_origins(fr.q[:1])[0, 0])
    if tool_path and fr.count > 1:
        _draw_path(vis, robot.positions(fr.q))
    if fr.count > 1:
        _animate(vis, viz, robot, geom, fr)
    sub = [f"in {cell.name}"] if cell is not None else []
    if marks.moves:
        sub.append(f"{len(marks.moves)} move{'s' * (len(marks.moves) > 1)}")
    if fr.count > 1:
        sub.append(f"{fr.t[-1]:.3f} s")
    sub.append(f"grid {lay.spacing * 1e3:g} mm")
    view = {"title": title or robot.name, "subtitle": " \u00b7 ".join(sub), "fps": fr.fps,
            "duration": float(fr.t[-1]) if fr.count > 1 else 0.0, "fov": FOV,
            "points": lay.points.round(5).tolist(), "eye": lay.eye.tolist(),
            "labels": [{"name": n, "at": a.round(5).tolist()} for n, a in lay.labels],
            "note": "drag: turn \u00b7 right-drag: pan \u00b7 scroll: zoom", **marks.to_json()}
    return static_html(vis, title or f"scara_opt: {robot.name}", view)


def _draw_floor(vis: meshcat.Visualizer, lay: Layout, base: Array) -> None:
    """The floor grid of ``lay``, a light background, meshcat's axes on the floor.

    meshcat's own grid (20 m wide, at z = 0) is hidden; its axes go under ``base`` (3,),
    two grid cells long.
    """
    from scara_opt.view.scene import g

    vis["/Grid"].set_property("visible", False)
    vis["floor_grid"].set_object(g.LineSegments(g.PointsGeometry(lay.grid_segments()),
                                                g.LineBasicMaterial(color=_GRID_RGB)))
    axes = np.diag([4 * lay.spacing] * 3 + [1.0])  # meshcat's axes are 0.5 m long
    axes[:3, 3] = [base[0], base[1], lay.floor]
    vis["/Axes"].set_transform(axes)
    vis["/Background"].set_property("top_color", _BACKGROUND[0])
    vis["/Background"].set_property("bottom_color", _BACKGROUND[1])


def _draw_path(vis: meshcat.Visualizer, tips: Array) -> None:
    """The tip's path (n, 3) [m] as a line."""
    from scara_opt.view.scene import g

    vis["tool_path"].set_object(g.Line(g.PointsGeometry(tips.T),
                                       g.LineBasicMaterial(color=_PATH_RGB, linewidth=2)))


def _animate(vis: meshcat.Visualizer, viz: Any, robot: Robot, geom: pin.GeometryModel,
             fr: Frames) -> None:
    """One meshcat animation: each moving body's placement at each frame's time."""
    from scara_opt.view.scene import Animation

    anim = Animation(default_framerate=fr.fps)
    data, gdata = robot.model.createData(), pin.GeometryData(geom)
    moving = [(k, viz.getViewerNodeName(obj, pin.GeometryType.VISUAL))
              for k, obj in enumerate(geom.geometryObjects) if obj.parentJoint != 0]
    for q, t in zip(fr.q, fr.t, strict=True):
        pin.forwardKinematics(robot.model, data, q)
        pin.updateGeometryPlacements(robot.model, data, geom, gdata)
        with anim.at_frame(vis, float(t * fr.fps)) as frame:
            for k, name in moving:
                frame[name].set_transform(gdata.oMg[k].homogeneous)
    vis.set_animation(anim, play=False)


def write_html(robot: Robot, motion: Trajectory | JointPath | ArrayLike, path: str | Path,
               fps: float = FPS, title: str | None = None, tool_path: bool = True,
               cell: Cell | None = None) -> Path:
    """Write :func:`html` to ``path`` (parent folders created); returns the path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(html(robot, motion, fps, title, tool_path, cell), encoding="utf-8")
    return out
