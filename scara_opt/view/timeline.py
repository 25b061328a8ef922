"""What the page's time slider marks: each move's start and duration, the least clearance.

A motion planned from moves (a :class:`~scara_opt.MotionTrajectory`) gives one block per
move on the slider, from its start to its end (``waypoint_times``). In a cell, the instant
of least clearance is marked: the smallest signed distance of any pair along the whole
trajectory, found to 0.1 mm by branch and bound on the proofs' motion bound
(:func:`scara_opt.collision.continuous.least_clearance`), and the pair there. The checker
is the one the trajectory was planned with, else one made for the cell; a robot without
collision geometry gets a note saying why there is none.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from scara_opt.errors import CellError

if TYPE_CHECKING:
    from scara_opt.collision.cell import Cell
    from scara_opt.collision.checker import CollisionChecker
    from scara_opt.model.robot import Robot
    from scara_opt.trajectory import JointPath, Trajectory

__all__ = ["Least", "Marks", "Move", "least_clearance", "marks", "moves"]


@dataclass(frozen=True)
class Move:
    """One block on the time slider.

    Attributes:
        label: its number and kind (``"2 PTP"``).
        start: when it starts [s].
        duration: how long it lasts [s].
    """

    label: str
    start: float
    duration: float


@dataclass(frozen=True)
class Least:
    """The instant of least clearance.

    Attributes:
        time: when [s].
        distance: the smallest signed distance of a checked pair there [m].
        bodies: that pair's names.
    """

    time: float
    distance: float
    bodies: tuple[str, str]


def moves(traj: Trajectory) -> tuple[Move, ...]:
    """One :class:`Move` per move of a MotionTrajectory; none for another motion."""
    from scara_opt.motion import MotionTrajectory

    if not isinstance(traj, MotionTrajectory) or not traj.moves:
        return ()
    t = np.asarray(traj.waypoint_times, float)
    if len(t) != len(traj.moves) + 1:  # blended corners' passages among them: by stops
        return ()
    return tuple(Move(f"{k + 1} {m.kind}", float(t[k]), float(t[k + 1] - t[k]))
                 for k, m in enumerate(traj.moves))


def least_clearance(checker: CollisionChecker, traj: Trajectory) -> Least | None:
    """The instant of least clearance of ``traj`` over every pair, found to 0.1 mm.

    ``None`` when the checker has no pair to check.
    """
    from scara_opt.collision.continuous import least_clearance as search

    found = search(checker, traj)
    return None if found is None else Least(found.at, found.distance, found.bodies)


@dataclass(frozen=True)
class Marks:
    """All the time slider marks of one motion.

    Attributes:
        moves: one block per move (none for a motion not planned from moves).
        least: the instant of least clearance (``None``: no cell, or none computed).
        note: why there is no least clearance in a cell (``None`` otherwise).
    """

    moves: tuple[Move, ...] = ()
    least: Least | None = None
    note: str | None = None

    @property
    def times(self) -> list[float]:
        """The marked instants [s]: the animation shows each exactly."""
        return [m.start for m in self.moves] + ([self.least.time] if self.least else [])

    def to_json(self) -> dict:
        """The marks as ``page.js`` reads them (``least.text``: mm, bodies, time)."""
        least = None
        if self.least is not None:
            a, b = self.least.bodies
            least = {"time": self.least.time, "distance": self.least.distance,
                     "bodies": [a, b], "text": f"{self.least.distance * 1e3:.2f} mm "
                     f"({a}\u2013{b}) at {self.least.time:.3f} s"}
        return {"moves": [vars(m) for m in self.moves], "least": least, "least_note": self.note}


def marks(robot: Robot, motion: Trajectory | JointPath | object, cell: Cell | None,
          checker: CollisionChecker | None = None) -> Marks:
    """The slider marks of ``motion`` in ``cell``, by ``checker`` if given (see the module).

    Only a Trajectory has them (a JointPath or array of joint values has no times).
    """
    from scara_opt.collision.checker import CollisionChecker
    from scara_opt.trajectory import Trajectory

    if not isinstance(motion, Trajectory):
        return Marks()
    if cell is None:
        return Marks(moves(motion))
    try:
        least = least_clearance(checker or CollisionChecker(robot, cell), motion)
    except CellError as exc:
        return Marks(moves(motion), None, f"no least clearance: {exc}")
    return Marks(moves(motion), least, None if least else "no least clearance: no pair to check")
