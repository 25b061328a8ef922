"""A program planned in a cell: goals clear of it, PTPs around it, every section proven clear.

:func:`~scara_opt.motion.plan` with ``cell=`` hands each move here:

* **Start and goals.** The start, and every PTP goal, must be clear of the cell:
  :class:`~scara_opt.errors.CollisionError` / :class:`~scara_opt.errors.MoveCollisionError`
  name the bodies and the depth. A PTP to a :class:`~scara_opt.Target` without ``elbow``
  takes the nearest IK solution that is clear (a SCARA's other elbow branch or wrist turn).
* **PTP.** The straight joint segment when the conservative rule proves it clear, else a
  path around the obstacles by :func:`scara_opt.planning.plan_path` (OMPL's RRTConnect and
  PathSimplifier, every edge proven); "no path found within the time limit" is a
  :class:`~scara_opt.errors.NoPathFoundError` with what was tried.
* **Timing, then the proof again.** Each stop-to-stop section is timed by toppra as without
  a cell, and proven clear (:mod:`scara_opt.collision.continuous`): toppra's spline through
  a planned path's waypoints is not the polyline that was proven. A planned section is
  first tried through its waypoints alone; while its spline is not proven clear, or leaves
  the joint limits, extra points are added near its corners (:func:`hugging`, up to
  :data:`RETRIES` times) so the spline follows the polyline more closely. With toppra the
  spline is proven before it is timed (the timing runs along it and visits nothing else);
  with ruckig the timed trajectory is proven.
* **LIN / CIRC** keep their tool path: one that hits the cell is refused
  (:class:`~scara_opt.errors.MoveCollisionError`, naming the move, the time and the bodies).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import check_int, check_real
from scara_opt.collision.checker import CollisionChecker
from scara_opt.collision.continuous import (
    CollisionReport,
    Proof,
    check_path,
    collision_report,
    make_checker,
)
from scara_opt.errors import (
    CollisionError,
    InputError,
    MoveCollisionError,
    MoveError,
    NoPathFoundError,
    TrajectoryError,
)
from scara_opt.ik.analytic import ik_all
from scara_opt.model.robot import Robot
from scara_opt.motion import branch
from scara_opt.motion.moves import PTP, Move, goal_point
from scara_opt.motion.timing import section_spline
from scara_opt.motion.tool_limits import ToolProfile
from scara_opt.planning.planner import SEED_MAX, PathPlan, check_clear, plan_path
from scara_opt.target import Target
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.trajectory import Trajectory, concatenate, cubic_range
from scara_opt.trajectory.waypoints import LIMIT_SLACK

Array = NDArray[np.float64]

__all__ = ["CellPlanning", "hugging", "in_cell"]

#: joint-space points added near each inner corner of a planned path, per attempt after the
#: first (which adds none: its spline was proven clear for 70 of 75 paths planned in
#: benchmarks/bench_plan.py's cells, and times 9 % faster than through the midpoints alone)
#: (fractions of the adjoining segments, from the corner): fewer points time faster and
#: shorter, more keep the spline on the proven polyline
NEAR = ((), (0.2,), (0.25, 0.08), (0.25, 0.1, 0.03), (0.12, 0.05, 0.015))

#: times a planned section is tried again, with the next set of :data:`NEAR` points
RETRIES = len(NEAR) - 1


def hugging(Q: Array, level: int = 0) -> Array:
    """The polyline ``Q`` (n, nq) with points added so a spline through them follows it.

    Each segment gets its middle and points at the fractions ``NEAR[level]`` from each of
    its inner ends; the spline's bulge at a corner then spans only the short pieces beside
    it.
    """
    if len(Q) < 3:
        return Q
    near = np.array(NEAR[level], dtype=float)
    rows = [Q[:1]]
    for k in range(len(Q) - 1):
        a, b = Q[k], Q[k + 1]
        f = [0.5]
        if k > 0:
            f += list(near)
        if k < len(Q) - 2:
            f += list(1 - near)
        at = np.unique(np.array(f))
        rows += [a + at[:, None] * (b - a), b[None, :]]
    return np.vstack(rows)


class CellPlanning:
    """The cell-aware steps of :func:`~scara_opt.motion.plan` (see the module docstring).

    Args:
        checker: the robot in its cell.
        time_limit: the limit of the whole program's planning [s], from :meth:`start_clock`:
            each PTP plans within what is left; past it, a section is timed the one way
            proven by construction (stopping at its waypoints) and proven once more.
        seed: the planner's seed (move ``i`` plans with ``seed + i``, modulo
            :data:`~scara_opt.planning.planner.SEED_MAX` + 1).
    """

    def __init__(self, checker: CollisionChecker, time_limit: float, seed: int) -> None:
        self.checker = checker
        self.time_limit = time_limit
        self.seed = seed
        self.deadline = math.inf
        self.plans: dict[int, PathPlan] = {}

    def start_clock(self) -> None:
        """Start the time limit, once the compiled kernel is built and the libraries loaded.

        One-off costs of a first call do not count: the kernel's compilation, and importing
        toppra (it imports matplotlib: 1-2 s) and OMPL. Counted, they left a 1 s program
        no time for its planned PTP on a busy machine, and made its result depend on them.
        """
        import ompl.geometric  # noqa: F401 (loaded now, not on the clock)
        import toppra  # noqa: F401
        from toppra.solverwrapper import cy_seidel_solverwrapper  # noqa: F401

        self.checker._kernel()
        self.deadline = time.perf_counter() + self.time_limit

    def left(self) -> float:
        """What is left of the time limit [s], at least 1 µs.

        With none left, a straight PTP is still proven, and the planner reports no path
        found within the limit.
        """
        return max(self.deadline - time.perf_counter(), 1e-6)

    def check_start(self, q: Array) -> None:
        """Refuse a start in collision (bodies and depth named)."""
        check_clear(self.checker, q, "start")

    def goal(self, index: int, move: PTP, robot: Robot, q_prev: Array) -> Array:
        """The PTP's joint goal, clear of the cell (another IK solution if need be).

        Raises:
            MoveCollisionError: the goal (every IK solution of a Target) in collision.
            MoveError: as without a cell (unreachable, off-branch, outside the limits).
        """
        goal = goal_point(index, move.goal, robot.nq, "goal")
        q = branch.ptp_goal(index, robot, goal, q_prev, move.elbow)
        if not self.checker.collides(q):
            return q
        if isinstance(goal, Target) and branch.geometry(robot) is not None:
            for res in ik_all(robot, goal, q0=q_prev):
                signs = branch.elbow_signs(robot, res.q)
                if (move.elbow is not None and signs is not None
                        and signs[0] != branch.SIGN[move.elbow]):
                    continue
                if not self.checker.collides(res.q):
                    return res.q
        try:
            check_clear(self.checker, q, "goal")
        except CollisionError as exc:
            other = " (and so is every other IK solution)" if isinstance(goal, Target) else ""
            a, b = exc.bodies
            raise MoveCollisionError(index, f"PTP: {exc}{other}", (a, b), exc.depth) from None
        return q  # pragma: no cover - collides() and check_clear agree

    def joints(self, index: int, move: Move, robot: Robot, q_prev: Array, step: float,
               straight: Callable[..., Array]) -> Array:
        """The move's joint path: a PTP planned around the cell, a LIN/CIRC as without one.

        ``straight``: :func:`~scara_opt.motion.plan.move_joints`, for LIN and CIRC.

        Raises:
            MoveCollisionError: a PTP goal in collision. NoPathFoundError: nothing found
                in time. MoveError: as without a cell.
        """
        if not isinstance(move, PTP):
            return straight(index, move, robot, q_prev, step)
        q1 = self.goal(index, move, robot, q_prev)
        if np.abs(q1 - q_prev).max() <= 1e-9:
            raise MoveError(index, "PTP goal is where the robot already is: drop the move")
        result = plan_path(self.checker, q_prev, q1, time_limit=min(self.left(),
                                                                      self.time_limit),
                           seed=(self.seed + index) % (SEED_MAX + 1))
        self.plans[index] = result
        if result.path is None:  # not solved
            raise NoPathFoundError(index, f"PTP: {result.message}", result.time_s,
                                   self.time_limit, result.tree_states, result.checks)
        return result.path

    def planned(self, index: int) -> bool:
        """Whether move ``index`` is a PTP planned around obstacles (more than one edge)."""
        plan = self.plans.get(index)
        return plan is not None and plan.path is not None and len(plan.path) > 2

    def prove(self, traj: Trajectory) -> CollisionReport:
        """The timed section proven clear, or its first contact.

        No least clearance: the whole trajectory's is found on demand,
        ``check_collisions()``.
        """
        return collision_report(self.checker, traj, least=False)

    def refuse(self, index: int, kind: str, report: CollisionReport, at: float,
               bodies: tuple[str, str], t0: float) -> None:
        """Raise the MoveCollisionError of a section that hits the cell.

        ``at`` and ``bodies``: the report's first contact (time in the section [s], pair).

        Raises:
            MoveCollisionError: always; the move, the time from the program's start, the
                bodies, the depth.
        """
        a, b = bodies
        t = t0 + at
        how = (f"{report.depth * 1e3:.3f} mm deep" if report.touching else
               "not proven clear (they graze)")
        raise MoveCollisionError(
            index, f"{kind} hits the cell at t = {t:.4f} s: {a} and {b}, {how}; a "
                   f"{kind} keeps its path: move its points away from {b}, or reach the "
                   "goal with a PTP (planned around the cell)", (a, b), report.depth, t)

    def timed_clear(self, run: list[tuple[int, Move]], Q: Array, owner: list[int],
                    timed: Callable, limits: Limits, method: str, t0: float) -> tuple:
        """``timed(Q, owner)`` of a section, proven clear (and a planned one within limits).

        A planned PTP is timed through its waypoints, then through :func:`hugging` points,
        more of them up to :data:`RETRIES` times (while the time limit lasts), until the
        timing is proven clear and within the joint limits; as a last resort, straight
        from waypoint to waypoint, stopping at each (exactly the polyline that was proven,
        slower). With toppra the
        spline a try would follow (:func:`~scara_opt.motion.timing.section_spline`) is
        proven before it is timed (:func:`~scara_opt.collision.continuous.check_path`, its
        exact range against the limits): the timing runs along it, so it visits nothing
        else, and a spline that is not proven costs no timing. Any other section is timed,
        then its trajectory proven; one that is not clear is refused.

        Returns:
            What ``timed`` returns, the note saying the proof.

        Raises:
            MoveCollisionError: a LIN/CIRC (or a blended run) that hits the cell.
            TrajectoryError: a planned path whose timing is not proven even stopping at
                every waypoint (not expected: each of its segments was proven).
        """
        index = run[0][0]
        if not (len(run) == 1 and self.planned(index)):
            part, note, knots, profile = timed(Q, owner)
            report = self.prove(Trajectory(part, limits, method, Q, knots))
            if report.time is not None and report.bodies is not None:  # not clear
                k = int(np.clip(np.searchsorted(knots, report.time, side="right") - 1, 0,
                                len(owner) - 1))
                self.refuse(owner[k], "+".join(m.kind for _, m in run), report, report.time,
                            report.bodies, t0)
            return part, note + _proven(report.evaluations), knots, profile
        return self._planned_timing(index, Q, timed, limits, method)

    def _planned_timing(self, index: int, Q: Array, timed: Callable, limits: Limits,
                        method: str) -> tuple:
        """``timed`` of the planned path ``Q`` of PTP ``index``, proven (see timed_clear)."""
        plan = self.plans[index]
        late = False
        for level in range(-1, RETRIES + 2):
            last = level > RETRIES
            if 0 <= level <= RETRIES and time.perf_counter() > self.deadline:
                late = True
                continue  # out of time: no more tries, the timing proven by construction
            rows = Q if level < 0 or last else hugging(Q, level)
            owner = [index] * len(rows)
            if method == "toppra" and not last:  # the spline proven before it is timed
                proof = self._spline_clear(rows, limits)
                if proof is None:
                    continue
                part, note, knots, profile = timed(rows, owner)
                proven = _proven(proof.evaluations, "the spline it follows")
            else:
                part, note, knots, profile = (_stopping(rows, owner, timed) if last
                                              else timed(rows, owner))
                traj = Trajectory(part, limits, method, rows, knots)
                report = self.prove(traj)
                if not (report.clear and self._inside(traj)):
                    continue
                proven = _proven(report.evaluations)
            why = ("the time limit was reached" if late else
                   "no spline through them was proven clear")
            how = (f"stopping at each waypoint ({why})"
                   if last else f"timed through {len(rows)} points (attempt {level + 2})")
            note += (f"{proven}; planned around the cell: {len(Q)} waypoints "
                     f"({plan.time_s * 1e3:.1f} ms, {plan.states} states), {how}")
            return part, note, knots, profile
        raise TrajectoryError(  # pragma: no cover - every segment of the path was proven
            f"move {index} (PTP): the path planned around the cell is proven clear, but its "
            f"timing is not, even stopping at every waypoint ({report!r}); raise margin=")

    def _spline_clear(self, rows: Array, limits: Limits) -> Proof | None:
        """The spline timed through ``rows`` proven clear and within the limits, or None.

        The limits by the spline's exact range (:func:`~scara_opt.trajectory.trajectory.
        cubic_range`), the cell by :func:`~scara_opt.collision.continuous.check_path`.
        """
        spline = section_spline(rows, limits).cspl
        if not _within_limits(self.checker.robot, *cubic_range(spline)):
            return None
        proof = check_path(self.checker, spline)
        return proof if proof.clear else None

    def _inside(self, traj: Trajectory) -> bool:
        """Whether the trajectory stays within the joint limits (exact extrema)."""
        return _within_limits(self.checker.robot, *traj.position_range())


def _within_limits(robot: Robot, lo: Array, hi: Array) -> bool:
    """Whether the range [lo, hi] (nq,) each of a motion lies within the joint limits."""
    return bool((lo >= robot.lower - LIMIT_SLACK).all()
                and (hi <= robot.upper + LIMIT_SLACK).all())


def _proven(checks: int, what: str = "") -> str:
    """The note's words for a proof (its lower bound is no clearance: check_collisions())."""
    of = f" ({what})" if what else ""
    return f", proven clear{of} ({checks} checks)"


def _stopping(Q: Array, owner: list[int], timed: Callable) -> tuple:
    """``timed`` of each segment of ``Q`` alone, laid end to end: rest at every waypoint."""
    parts, knots, profiles = [], [0.0], []
    for k in range(len(Q) - 1):
        part, note, seg_knots, profile = timed(Q[k:k + 2], owner[k:k + 2])
        parts.append(part)
        profiles.append(profile)
        knots.append(knots[-1] + float(seg_knots[-1]))
    joined = tuple(concatenate([p[j] for p in parts]) for j in range(Q.shape[1]))
    profile = ToolProfile(*(np.concatenate([getattr(p, name) for p in profiles])
                            for name in ("speed", "acceleration", "yaw_rate")))
    return joined, f"{len(Q) - 1} straight segments, {note}", np.array(knots), profile


def in_cell(robot: Robot, cell: object, margin: float | None, time_limit: float, seed: int
            ) -> CellPlanning | None:
    """The :class:`CellPlanning` of :func:`~scara_opt.motion.plan`'s ``cell=`` (None: none).

    ``margin`` [m]: ``None`` keeps a checker's own (0 for a Cell); any other value is used,
    with a checker too.

    Raises:
        InputError: a checker of another robot, a bad margin, time limit or seed; a
            margin without a cell.
    """
    time_limit = check_real("time_limit", time_limit, 0.0, 3600.0, low_open=True, unit="s")
    seed = check_int("seed", seed, 0, SEED_MAX)
    if cell is None:
        if margin is not None:
            check_real("margin", margin, 0.0, 1.0, unit="m")
            raise InputError(f"margin={margin!r} is the clearance to keep from a cell, and no "
                             "cell was given: pass cell= (a Cell or a CollisionChecker), or "
                             "drop margin=")
        return None
    if isinstance(cell, CollisionChecker):
        if cell.robot is not robot and cell.robot.joint_names != robot.joint_names:
            raise InputError(f"the checker is for robot {cell.robot.name!r}, not "
                             f"{robot.name!r}: build CollisionChecker(robot, cell)")
    checker = make_checker(cell, robot, margin, robot.nq)
    return CellPlanning(checker, time_limit, seed)
