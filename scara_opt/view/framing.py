"""What the page frames, where its floor grid lies and where the camera looks from.

The camera frames the robot's reach (its joint origins and tip over seeded samples of its
joint ranges and at up to :data:`FRAMED` frames of the motion) and the cell's obstacles
within it: each obstacle's box is clipped to the cube around the reach grown by
:data:`GROW` on each side, so a table wider than the cell does not shrink the robot, and an
obstacle out of reach is neither framed nor labelled. It looks
from above and in front, as a cell engineer stands: from the side the arm points to at its
zero pose (the joint ranges' middle when zero is outside them), turned :data:`AZIMUTH` to
the side and raised :data:`ELEVATION`. The page fits the distance to the window
(``page.js``).

The floor grid lies under the cell: on the table, the widest obstacle below the robot's base
that reaches under it, else under the base, the motion and the obstacles (the reach framed
stops there). It spans what is framed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import coal
import numpy as np
from numpy.typing import NDArray

from scara_opt.model.robot import Robot

if TYPE_CHECKING:
    from scara_opt.collision.cell import Cell

__all__ = ["AZIMUTH", "ELEVATION", "FRAMED", "GROW", "Layout", "layout"]

Array = NDArray[np.float64]

#: the view's turn from straight in front [rad] (to the robot's left)
AZIMUTH = np.radians(35.0)
#: the view's height above the horizontal [rad]
ELEVATION = np.radians(35.0)
#: obstacles are framed within the reach's bounding cube grown by this fraction
GROW = 0.1
#: seeded samples of the joint ranges for the robot's reach
REACH_SAMPLES = 400
#: at most this many frames of the motion are framed (evenly spread, both ends)
FRAMED = 200
_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Layout:
    """Where the page looks and what it draws under the cell.

    Attributes:
        points: (m, 3) points the camera keeps in view [m]: the reach (joint origins and
            tip over the samples and the frames), the clipped obstacle boxes' corners.
        eye: (3,) unit vector from the scene toward the camera.
        floor: height of the floor grid [m].
        lo: (2,) lower x, y corner of the grid [m].
        hi: (2,) upper x, y corner of the grid [m].
        spacing: the grid's pitch [m].
        labels: ``(name, anchor (3,))`` per obstacle framed: where its label points [m].
        table: the obstacle the grid lies on (``None``: under everything framed).
    """

    points: Array
    eye: Array
    floor: float
    lo: Array
    hi: Array
    spacing: float
    labels: tuple[tuple[str, Array], ...]
    table: str | None

    def grid_segments(self) -> Array:
        """The grid's lines as (3, 2 k) segment end points [m] (meshcat's ``LineSegments``)."""
        p = self.spacing
        xs = np.arange(self.lo[0], self.hi[0] + p / 2, p)
        ys = np.arange(self.lo[1], self.hi[1] + p / 2, p)
        ends = [((x, self.lo[1]), (x, self.hi[1])) for x in xs]
        ends += [((self.lo[0], y), (self.hi[0], y)) for y in ys]
        xy = np.array(ends).reshape(-1, 2)
        return np.column_stack([xy, np.full(len(xy), self.floor)]).T


def _reach(robot: Robot) -> Array:
    """Joint origins and tips (m, 3) [m] over seeded samples of the joint ranges."""
    rng = np.random.default_rng(0)
    lo, hi = robot.sampling_lower, robot.sampling_upper
    samples = lo + (hi - lo) * rng.random((REACH_SAMPLES, robot.nq))
    return robot.joint_origins(samples).reshape(-1, 3)


def _boxes(cell: Cell | None) -> list[tuple[str, Array, Array]]:
    """Each obstacle's name and world axis-aligned box ``(lo (3,), hi (3,))`` [m] (coal)."""
    out = []
    for ob in cell.obstacles if cell is not None else ():
        obj = coal.CollisionObject(ob.shape(), coal.Transform3s(ob.placement.rotation,
                                                                ob.placement.translation))
        obj.computeAABB()
        box = obj.getAABB()
        out.append((ob.name, np.array(box.min_), np.array(box.max_)))
    return out


def _front(robot: Robot, base: Array) -> Array:
    """Unit horizontal vector from the base toward the tip at the zero pose (default +x)."""
    q = np.where((robot.lower <= 0) & (robot.upper >= 0), 0.0,
                 (robot.sampling_lower + robot.sampling_upper) / 2)
    d = robot.positions(q[None])[0] - base
    d -= (d @ _UP) * _UP
    n = float(np.linalg.norm(d))
    return d / n if n > 1e-6 else np.array([1.0, 0.0, 0.0])


def _pitch(extent: float) -> float:
    """A round grid pitch (1, 2 or 5 times a power of ten) [m] giving about 12 cells."""
    raw = max(extent, 1e-3) / 12
    power = 10.0 ** np.floor(np.log10(raw))
    return float(min((m * power for m in (1, 2, 5, 10)), key=lambda v: abs(np.log(v / raw))))


def _table(boxes: list[tuple[str, Array, Array]], base: Array) -> tuple[str, float] | None:
    """Name and top [m] of the widest obstacle below ``base`` (3,) whose box reaches under it."""
    under = [(float(np.prod(hi[:2] - lo[:2])), name, float(hi[2])) for name, lo, hi in boxes
             if np.all(lo[:2] <= base[:2]) and np.all(hi[:2] >= base[:2])
             and hi[2] <= base[2] + 1e-9]
    return max(under)[1:] if under else None


def _corners(lo: Array, hi: Array) -> Array:
    """The 8 corners (8, 3) of the box ``lo``, ``hi`` (3,)."""
    return np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                     for i in (0, 1) for j in (0, 1) for k in (0, 1)])


def layout(robot: Robot, Q: Array, cell: Cell | None = None) -> Layout:
    """The view of ``robot`` moving through ``Q`` (n, nq) in ``cell`` (see the module)."""
    Q = Q[np.unique(np.linspace(0, len(Q) - 1, min(len(Q), FRAMED)).round().astype(int))]
    moving = robot.joint_origins(Q).reshape(-1, 3)
    reach = np.vstack([moving, _reach(robot)])
    base = moving[0]
    mid, half = (reach.min(axis=0) + reach.max(axis=0)) / 2, np.ptp(reach, axis=0).max() / 2
    cube = (mid - (1 + 2 * GROW) * half - 1e-3, mid + (1 + 2 * GROW) * half + 1e-3)
    front = _front(robot, base)
    eye_h = np.cos(AZIMUTH) * front + np.sin(AZIMUTH) * np.cross(_UP, front)
    boxes = _boxes(cell)
    framed, labels = [reach], []
    for name, lo, hi in boxes:
        lo, hi = np.maximum(lo, cube[0]), np.minimum(hi, cube[1])
        if np.any(lo > hi):
            continue  # far from the robot: neither framed nor labelled
        framed.append(_corners(lo, hi))
        # the label points at the middle of the top face's edge nearest the viewer
        c, h = (lo + hi) / 2, (hi - lo) / 2
        anchor = c + np.clip(eye_h * float(h[:2].max()), -h, h)
        labels.append((name, np.array([anchor[0], anchor[1], hi[2]])))
    allpts = np.vstack(framed)
    g_lo, g_hi = allpts[:, :2].min(axis=0), allpts[:, :2].max(axis=0)
    spacing = _pitch(float((g_hi - g_lo).max()))
    g_lo, g_hi = np.floor(g_lo / spacing) * spacing, np.ceil(g_hi / spacing) * spacing
    table = _table(boxes, base)
    if table:  # a hair above its top face, which would hide half of each line
        floor = table[1] + 2e-3 * spacing
    else:  # under the base, the motion and the obstacles
        floor = float(np.vstack([moving, *framed[1:]])[:, 2].min())
        allpts[:, 2] = np.maximum(allpts[:, 2], floor)
    eye = np.cos(ELEVATION) * eye_h + np.sin(ELEVATION) * _UP
    return Layout(allpts, eye, floor, g_lo, g_hi, spacing, tuple(labels),
                  table[0] if table else None)
