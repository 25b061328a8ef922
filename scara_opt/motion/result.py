"""What :func:`~scara_opt.motion.plan` returns: a Trajectory that knows its moves and limits."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

from scara_opt.errors import InputError
from scara_opt.model.robot import Robot
from scara_opt.motion import export
from scara_opt.motion.moves import Move
from scara_opt.motion.timing import CHECK_DT, tool_ratios
from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
from scara_opt.trajectory.trajectory import Trajectory

if TYPE_CHECKING:
    from scara_opt.collision.checker import CollisionChecker
    from scara_opt.collision.continuous import CollisionReport

Array = NDArray[np.float64]


@dataclass(frozen=True, repr=False, eq=False)
class MotionTrajectory(Trajectory):
    """A :class:`~scara_opt.Trajectory` planned from moves; it also knows its tool limits.

    Attributes (beyond Trajectory's; ``waypoints`` are where each move ends, ``waypoint_times``
    the start then the end of each move [s]: a stop at its goal, or, for a blended move, the
    configuration and time at which the tip passes closest to its corner):
        robot: the robot it was planned for.
        moves: the program.
        tool_limits: the tool limits of each move, in program order: its own ``speed`` /
            ``acceleration``, else the program's (a PTP: its own only).
        profiles: per run, the waypoint times [s] from the run's start and the tool limits
            per waypoint interval (:class:`~scara_opt.motion.tool_limits.ToolProfile`).
        corners: ``(C (3,), r, run)`` of each blended corner [m], ``run`` the index of the
            stop-to-stop run it belongs to.
        checker: the :class:`~scara_opt.CollisionChecker` of the cell it was planned in
            (``None``: planned without a cell).
        stops: (n_runs + 1,) the start then the end of each stop-to-stop run [s], where the
            robot is at rest.
        run_bounds: (n_runs,) the lower bound of each stop-to-stop run [s]: its slowest
            joint's own time-optimal rest-to-rest move under the joint velocity and
            acceleration limits (:mod:`scara_opt.trajectory.bound`); no trajectory between
            those rests is faster.
        objective: what :func:`~scara_opt.plan` minimised, ``"length"`` or ``"time"``.
    """

    robot: Robot | None = None
    moves: tuple[Move, ...] = ()
    tool_limits: tuple[ToolLimits, ...] = ()
    corners: tuple[tuple[Array, float, int], ...] = ()
    profiles: tuple[tuple[Array, ToolProfile], ...] = ()
    checker: CollisionChecker | None = None
    stops: Array = field(default_factory=lambda: np.zeros(0))
    run_bounds: Array = field(default_factory=lambda: np.zeros(0))
    objective: str = "length"

    @property
    def lower_bound(self) -> float:
        """The least duration any trajectory through these stops could take [s].

        The sum of :attr:`run_bounds` (``nan`` when built without them).
        """
        return float(self.run_bounds.sum()) if len(self.run_bounds) else math.nan

    @property
    def bound_ratio(self) -> float:
        """``duration / lower_bound`` (>= 1; 1: as fast as the joint limits allow)."""
        bound = self.lower_bound
        return self.duration / bound if bound > 0 else math.nan

    def __repr__(self) -> str:
        bound = (f", lower bound {self.lower_bound:.4f} s (x{self.bound_ratio:.3f})"
                 if len(self.run_bounds) else "")
        return (f"MotionTrajectory(method={self.method!r}, objective={self.objective!r}, "
                f"duration={self.duration:.4f} s{bound}, nq={self.nq}, "
                f"waypoints={len(self.waypoints)})")

    __str__ = __repr__

    def _robot(self) -> Robot:
        """:attr:`robot`; a trajectory built by hand without one cannot be checked by FK.

        Raises:
            InputError: no robot attached.
        """
        if self.robot is None:
            raise InputError("this MotionTrajectory has no robot: build it with "
                             "scara_opt.plan(robot, moves), which attaches it")
        return self.robot

    def _stops(self) -> Array:
        """:attr:`stops`, or the waypoint times of a trajectory built without them."""
        return self.stops if len(self.stops) else self.waypoint_times

    def _passages(self, dt: float) -> tuple[Array, Array]:
        """Per blended corner: closest approach of the tip [m] and its time [s], FK at ``dt``.

        The time is refined between the samples next to the closest one (bounded scalar
        minimisation of the distance, FK by Pinocchio).
        """
        from scipy.optimize import minimize_scalar

        robot = self._robot()
        t = self.times(dt)
        P = robot.positions(self.evaluate(t))
        stops = self._stops()
        dist, when = [], []
        for c, _, run in self.corners:  # only while that run is under way
            inside = np.flatnonzero((t >= stops[run]) & (t <= stops[run + 1]))
            k = inside[int(np.argmin(np.linalg.norm(P[inside] - c, axis=1)))]
            lo, hi = t[max(k - 1, 0)], t[min(k + 1, len(t) - 1)]
            best = minimize_scalar(lambda x, c=c: float(np.linalg.norm(
                robot.position(self.evaluate(np.array([x]))[0]) - c)),
                bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
            d0 = float(np.linalg.norm(P[k] - c))
            dist.append(min(d0, float(best.fun)))
            when.append(float(best.x) if best.fun <= d0 else float(t[k]))
        return np.array(dist), np.array(when)

    def with_corner_passages(self) -> MotionTrajectory:
        """This trajectory with each blended corner's passage among its waypoints.

        A blended move ends where the tip passes closest to its corner: that time and the
        configuration there join :attr:`waypoints` and :attr:`waypoint_times`, in order.
        """
        stops = self._stops()
        if not self.corners or len(self.waypoint_times) != len(stops):  # none, or done
            return self
        when = self._passages(CHECK_DT)[1]
        times = np.concatenate([stops, when])
        order = np.argsort(times, kind="stable")
        rows = np.concatenate([self.waypoints[:len(stops)], self.evaluate(when)])
        return replace(self, waypoints=rows[order], waypoint_times=times[order],
                       stops=stops)

    def blend_deviations(self, dt: float = CHECK_DT) -> Array:
        """Closest approach of the tip to each blended corner (n_corners,) [m], FK at ``dt``.

        Each is at most that corner's radius (``corners[i][1]``), and above 0: the corner is
        cut, not stopped at.
        """
        return self._passages(dt)[0]

    def tool_limit_ratios(self, dt: float = CHECK_DT) -> dict[str, Array]:
        """Worst tip speed / acceleration / yaw-rate ratio per run (n_runs,), by FK at ``dt``.

        Each sample is judged against the limit in force where it is (a blended run crosses
        moves with different limits). 0 where a run has no such limit; <= 1 means the limit
        holds at every sample.
        """
        rows: dict[str, list[float]] = {"speed": [], "acceleration": [], "yaw_rate": []}
        for i, (knots, profile) in enumerate(self.profiles):
            t0, t1 = self._stops()[i], self._stops()[i + 1]
            part = _window(self, t0, t1)
            for name, value in tool_ratios(self._robot(), part, profile, knots, dt).items():
                rows[name].append(value)
        return {f"tool_{k}": np.array(v) for k, v in rows.items()}

    def to_json(self, path: str | Path, dt: float = 0.01) -> Path:
        """Samples every ``dt`` [s] as JSON (:func:`scara_opt.motion.export.to_json`)."""
        return export.to_json(self, path, dt)

    def to_ros(self, dt: float = 0.01) -> dict:
        """A ROS ``JointTrajectory``-shaped dict (:func:`scara_opt.motion.export.to_ros`)."""
        return export.to_ros(self, dt)

    def to_ros_yaml(self, path: str | Path, dt: float = 0.01) -> Path:
        """The ROS form as YAML (:func:`scara_opt.motion.export.to_ros_yaml`)."""
        return export.to_ros_yaml(self, path, dt)

    def check_limits(self) -> dict[str, Array]:
        """Joint ratios (exact, per joint) and tool ratios (1 kHz FK, per move).

        Planned in a cell, also ``"clearance"``: (1,) the required clearance (the margin)
        over the clearance proven along the whole trajectory; <= 1 means proven clear with
        the margin (0 with no margin), ``inf`` a contact (:meth:`check_collisions`).
        """
        out = {**super().check_limits(), **self.tool_limit_ratios()}
        if self.checker is not None:
            out["clearance"] = np.array([self.check_collisions().ratio])
        return out

    def move_spans(self) -> Array:
        """(n, 2) when each move starts and ends [s], from :attr:`waypoint_times`.

        One row per move of :attr:`moves` (a blended move ends where the tip passes
        closest to its corner); a program split by ``allow_flip`` has a row for each flip
        PTP too.
        """
        t = self.waypoint_times
        return np.column_stack([t[:-1], t[1:]])

    def move_clearances(self) -> Array:
        """(n,) the least clearance of each move of :meth:`move_spans` to the cell [m].

        Over every pair, found to 0.1 mm (:class:`~scara_opt.collision.continuous.
        LeastClearance`, of the trajectory's pieces that cover the move: their knots may
        reach a little beyond it), in the cell it was planned in; ``inf`` for a move that
        does not move.

        Raises:
            InputError: planned without a cell.
        """
        from scara_opt.collision.continuous import collision_report

        if self.checker is None:
            raise InputError("this trajectory was planned without a cell: it has no "
                             "clearances; plan it with cell=")
        out = []
        for t0, t1 in self.move_spans():
            report = None if t1 - t0 <= 0 else collision_report(self.checker,
                                                                _window(self, t0, t1))
            out.append(math.inf if report is None or report.least is None
                       else report.least.distance)
        return np.array(out)

    def check_collisions(self, cell: object = None, robot: Robot | None = None, *,
                         margin: float | None = None) -> CollisionReport:
        """:meth:`Trajectory.check_collisions` in the cell it was planned in by default.

        With no ``cell``, the checker it was planned with (``margin=``: that checker asking
        for another margin).

        Raises:
            InputError: no cell given and none attached.
        """
        if cell is None:
            if self.checker is None:
                raise InputError("this trajectory was planned without a cell: pass one, "
                                 "check_collisions(cell)")
            if margin is not None:
                return super().check_collisions(self.checker, margin=margin)
            if "collisions" not in self._derivs:
                self._derivs["collisions"] = super().check_collisions(self.checker)
            return self._derivs["collisions"]
        return super().check_collisions(cell, robot or self.robot, margin=margin)


def _window(traj: Trajectory, t0: float, t1: float) -> Trajectory:
    """The part of ``traj`` between ``t0`` and ``t1``, as a Trajectory starting at 0."""
    pieces = []
    for p in traj.pieces:
        i0 = int(np.searchsorted(p.x, t0 + 1e-12, side="right")) - 1
        i1 = int(np.searchsorted(p.x, t1 - 1e-12, side="left"))
        pieces.append(PPoly(p.c[:, i0:i1], p.x[i0:i1 + 1] - p.x[i0], extrapolate=False))
    return Trajectory(tuple(pieces), traj.limits, traj.method, traj.waypoints[:2],
                      np.array([0.0, t1 - t0]))
