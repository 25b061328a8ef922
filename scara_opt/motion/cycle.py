"""Cycle time of the standard SCARA pick-and-place cycle: 25 mm up, 305 mm across, 25 mm down, back.

The cycle is placed where the robot reaches it (:func:`place_cycle`), up along the world z
axis (the robot files put the base's z against gravity): on a SCARA with a vertical axis
the horizontal stroke perpendicular to a ray from the shoulder axis, its ends at the same
distance, the vertical strokes centred in the height range; on an arm whose axis is
horizontal (nguyen, moving in the x-z plane) all three strokes in its plane, the across
stroke horizontal; the first placement (nearest the middle of the reach,
the ray along the first joint's zero first) whose six corners the closed-form IK reaches on one
elbow branch and whose program plans is used. The program is LIN up, PTP across, LIN down,
and the same back, stopping at each corner (as cycle-time specifications are measured).
With ``blend = r`` the toppra plan is also timed running through the two upper corners of
each pass within r of them (the arch motion of a SCARA controller; it stops only at the
pick and the place): ``durations["toppra_blended"]``.

Three timings of the same program: ``toppra`` (:func:`~scara_opt.motion.plan`, time-optimal
under the joint limits and any tool limits), ``ruckig`` (the same plan jerk-limited along
the path, :mod:`scara_opt.motion.jerk`) and ``quintic`` (rest-to-rest quintic per segment
through the same corners, the baseline; its segments are the same joint lines, since the
vertical strokes move the height joint only). The jerk-limited variant is not blended: its
path bounds are constant along a run, so a blended run would crawl at the bound the
corners' curvature sets (7.0 s against 2.9 s stopping, zavar2024, r = 10 mm).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import check_real
from scara_opt.collision.continuous import prove_segment
from scara_opt.errors import CollisionError, InputError, MoveError
from scara_opt.ik.analytic import ik_all
from scara_opt.ik.geometry import ScaraGeometry
from scara_opt.model.robot import Robot, check_robot
from scara_opt.motion import branch, geometry
from scara_opt.motion.clearance import in_cell
from scara_opt.motion.fastest import check_objective
from scara_opt.motion.moves import LIN, PTP, Move
from scara_opt.motion.plan import plan
from scara_opt.motion.result import MotionTrajectory
from scara_opt.motion.tool_limits import ToolLimits
from scara_opt.target import Target
from scara_opt.trajectory.dynamics import PayloadLike
from scara_opt.trajectory.limits import resolve_limits
from scara_opt.trajectory.registry import time_parameterize

if TYPE_CHECKING:
    from scara_opt.collision import Cell, CollisionChecker

Array = NDArray[np.float64]

#: placements tried in a cell before giving up
MAX_PLACEMENTS = 12

#: ray angles tried (about the shoulder axis, from the first link's zero) [rad]
ANGLES = np.radians([0, 30, -30, 60, -60, 90, -90, 120, -120, 150, -150, 180])


@dataclass(frozen=True, repr=False)
class CycleResult:
    """Times of one placed pick-and-place cycle.

    Attributes:
        robot: robot name.
        up, across, down: the strokes [m].
        pick, place: (3,) lower corners A and B [m].
        durations: cycle time [s] by method (``toppra``, ``ruckig``, ``quintic``: stopping
            at every corner; ``toppra_blended`` with a blend radius).
        trajectory: the toppra :class:`~scara_opt.motion.MotionTrajectory` (blended when
            a blend radius is given).
        corners: (7, nq) joint values at A, A up, B up, B, B up, A up, A.
        blend: the blend radius at the upper corners [m] (0: stops at every corner).
        cell: the name of the cell it was planned in (``None``: no cell).
        clearance: in a cell, the least clearance of :attr:`trajectory` [m], found to 0.1 mm
            (``trajectory.check_collisions()`` has it and the proven bound).
        notes: what a reader of the times needs to know: a method not timed and why, a
            method much slower and why.
        lower_bound: the least duration of any cycle through the same stops [s]: per
            stop-to-stop move, its slowest joint's own time-optimal move
            (:attr:`~scara_opt.motion.MotionTrajectory.lower_bound` of the stopping plan).
        objective: what the toppra plans minimised (``"time"``: their PTPs are Ruckig's
            synchronized moves where proven clear; ``durations["toppra"]`` is that plan's).
    """

    robot: str
    up: float
    across: float
    down: float
    pick: Array
    place: Array
    durations: dict[str, float]
    trajectory: MotionTrajectory
    corners: Array
    blend: float = 0.0
    cell: str | None = None
    clearance: float | None = None
    notes: tuple[str, ...] = ()
    lower_bound: float = math.nan
    objective: str = "length"

    @property
    def title(self) -> str:
        """Two lines for a figure: robot, strokes and blend; then each method's time."""
        blend = f", corners blended within {self.blend * 1e3:g} mm" if self.blend else ""
        times = ", ".join(f"{k} {v:.3f} s" for k, v in self.durations.items())
        return (f"{self.robot}: pick-and-place cycle {self.up * 1e3:g}/{self.across * 1e3:g}/"
                f"{self.down * 1e3:g} mm{blend}\n{times}")

    def __repr__(self) -> str:
        times = ", ".join(f"{k} {v:.4f} s" for k, v in self.durations.items())
        blend = f", blend {self.blend * 1e3:g} mm" if self.blend else ""
        where = ""
        if self.cell is not None and self.clearance is not None:
            where = (f"; planned in {self.cell!r}, proven clear of it (least clearance "
                     f"{self.clearance * 1e3:.3f} mm)")
        notes = "".join(f"; {n}" for n in self.notes)
        bound = (f", lower bound {self.lower_bound:.4f} s" if math.isfinite(self.lower_bound)
                 else "")
        if self.objective != "length":
            bound += f" (objective {self.objective})"
        return (f"CycleResult({self.robot}: {self.up * 1e3:g}/{self.across * 1e3:g}/"
                f"{self.down * 1e3:g} mm{blend}, {times}{bound}{where}{notes})")


#: world up: the robot files put the base's z axis against gravity
UP = np.array([0.0, 0.0, 1.0])


def _scara(robot: Robot) -> ScaraGeometry:
    """The robot's SCARA geometry.

    Raises:
        InputError: the robot is not SCARA-type.
    """
    g = branch.geometry(robot)
    if g is None:
        raise InputError(f"cycle_time needs a SCARA-type robot; {robot.name!r} is not")
    return g


def _candidates(robot: Robot, up: float, across: float, down: float
                ) -> Iterator[tuple[Array, Array, Array]]:
    """Placements ``(A, B, up_direction)``: lower corners [m] and world up, nearest first.

    A SCARA with a vertical axis (the usual one) strokes up and down along it, across in
    its plane; an arm whose axis is horizontal (nguyen: it moves in the x-z plane) strokes
    up and down and across in its plane, across horizontal, at mid-range of its heights.
    """
    g = _scara(robot)
    lo = g.h0 + sum(min(g.sigma[k] * robot.lower[k], g.sigma[k] * robot.upper[k])
                    for k in g.heights)
    hi = g.h0 + sum(max(g.sigma[k] * robot.lower[k], g.sigma[k] * robot.upper[k])
                    for k in g.heights)
    vertical = abs(float(g.n @ UP)) > 0.5
    stroke = max(up, down)
    if vertical and hi - lo < stroke:
        raise InputError(f"robot {robot.name!r} has a vertical stroke of {(hi - lo) * 1e3:.4g} "
                         f"mm, less than the {stroke * 1e3:g} mm asked; pass up= and down= "
                         f"<= {(hi - lo):.4g} m")
    side = math.copysign(1.0, float(g.n @ UP))  # the axis n points up (+1) or down (-1)
    mid = (lo + hi) / 2  # along n
    h_pick = mid - side * up / 2 if vertical else mid
    h_place = h_pick + side * (up - down) if vertical else mid
    level = np.cross(g.n, UP) / max(float(np.linalg.norm(np.cross(g.n, UP))), 1e-300)
    reach = g.l1 + g.l2
    base = g.base[0] * g.e1 + g.base[1] * g.e2
    phi0 = g.phi1
    for d in sorted(np.linspace(0.0, reach, 41), key=lambda d: abs(d - reach / 2)):
        if d * d + (across / 2) ** 2 > reach * reach:
            continue
        for a in ANGLES:
            u = math.cos(phi0 + a) * g.e1 + math.sin(phi0 + a) * g.e2
            w = np.cross(g.n, u) if vertical else level
            centre = base + d * u
            A = centre - across / 2 * w + h_pick * g.n
            B = centre + across / 2 * w + h_place * g.n
            yield A, B, UP


def place_cycle(robot: Robot, up: float = 0.025, across: float = 0.305,
                down: float = 0.025) -> tuple[Array, Array, Array, str]:
    """Lower corners A, B (3,) [m], the joint start at A and its branch, for a reachable cycle.

    Raises:
        InputError: no placement reaches all six corners on one branch (the message says
            which strokes to shrink).
    """
    for found in placements(robot, up, across, down):
        return found
    raise InputError(f"robot {robot.name!r} cannot reach a {up * 1e3:g}/{across * 1e3:g}/"
                     f"{down * 1e3:g} mm cycle on one elbow branch anywhere: pass a shorter "
                     "across= (and up=/down=) for a small robot")


def placements(robot: Robot, up: float, across: float, down: float
               ) -> Iterator[tuple[Array, Array, Array, str]]:
    """Every reachable placement ``(A, B, q at A, branch)``, in :func:`place_cycle`'s order.

    Raises:
        InputError: the robot is not SCARA-type.
    """
    g = _scara(robot)
    for A, B, n in _candidates(robot, up, across, down):
        corners = [A, A + up * n, B + down * n, B]
        sols = [ik_all(robot, Target(p)) for p in corners]
        if not all(sols):
            continue
        for q in (s.q for s in sols[0]):
            side = int(branch.signs_of(g, q)[0])
            if side and all(any(branch.signs_of(g, s.q)[0] == side for s in ss)
                            for ss in sols[1:]):
                yield A, B, q, branch.NAME[side]
                break


def check_cycle_blend(blend: float, up: float, across: float, down: float,
                      unit: str = "m", scale: float = 1.0, option: str = "blend") -> None:
    """Refuse a blend radius above half the shortest stroke (up to round-off).

    ``unit``, ``scale`` and ``option``: how the message quotes the values (the command
    line's are in mm and named ``--blend``, ``--up``, ...).

    Raises:
        InputError: the radius, the strokes and the largest radius allowed, in ``unit``.
    """
    most = min(up, across, down) / 2
    if blend > most * (1.0 + geometry.BLEND_SLACK):
        dash = "--" if option.startswith("--") else ""
        raise InputError(
            f"{option} {blend * scale:.10g} {unit} is more than half of the shortest stroke "
            f"({dash}up {up * scale:.10g}, {dash}across {across * scale:.10g}, {dash}down "
            f"{down * scale:.10g} {unit}): the rounded corner would pass the stroke's middle; "
            f"pass {option} <= {most * scale:.10g}")


def cycle_time(robot: Robot, up: float = 0.025, across: float = 0.305, down: float = 0.025,
               limits: ToolLimits | None = None, blend: float = 0.0, *,
               vmax: ArrayLike | None = None, amax: ArrayLike | None = None,
               cell: Cell | CollisionChecker | None = None, margin: float | None = None,
               time_limit: float = 1.0, seed: int = 0, objective: str = "length"
               ) -> CycleResult:
    """Time the pick-and-place cycle (A up, across, down to B, and back) three ways.

    Args:
        robot: a SCARA-type robot (its joint limits are used).
        up: the lift at the pick [m] (standard 0.025).
        across: the horizontal stroke [m] (standard 0.305).
        down: the descent at the place [m] (standard 0.025).
        limits: optional tool limits for the LIN strokes of the toppra plan.
        blend: radius [m] within which a second toppra plan rounds the upper corners
            (``durations["toppra_blended"]``; 0: none); at most half a vertical stroke.
        vmax: joint velocity limits, scalar or (nq,) [rad/s or m/s]; default the robot's.
        amax: joint acceleration limits, scalar or (nq,) [rad/s² or m/s²]; default the
            robot's (a URDF carries none: pass it).
        cell: a :class:`~scara_opt.Cell` (or a :class:`~scara_opt.CollisionChecker`): the
            cycle is planned in it (:func:`~scara_opt.plan` with ``cell=``): the first
            placement whose program plans clear of the cell is used, the PTPs across go
            around its obstacles, every section is proven clear. The quintic baseline is
            timed only when its straight corner-to-corner segments are proven clear too.
        margin: clearance to keep from the cell [m] (as :func:`~scara_opt.plan`'s:
            default the checker's own, 0 with a Cell; refused without a cell).
        time_limit: planning limit of each PTP around obstacles [s].
        seed: the planner's seed.
        objective: :func:`~scara_opt.plan`'s, for the toppra plans (``"time"``: each PTP
            between stops is the fastest move found, at the lower bound where Ruckig's
            synchronized move is proven clear).

    Raises:
        InputError: strokes not positive, bad limits, no reachable placement (in a cell:
            none whose program plans clear of it), or a blend radius above half of the
            shortest stroke (the largest allowed is named).
        TrajectoryError: a joint without a limit of its own and none given (checked before
            any IK).
    """
    robot = check_robot(robot)
    up = check_real("up", up, 0.0, 1.0, low_open=True, unit="m")
    down = check_real("down", down, 0.0, 1.0, low_open=True, unit="m")
    across = check_real("across", across, 0.0, 10.0, low_open=True, unit="m")
    blend = check_real("blend", blend, 0.0, 1.0, unit="m")
    check_cycle_blend(blend, up, across, down)
    joint = resolve_limits(robot, robot.nq, vmax, amax)  # before any IK
    objective = check_objective(objective)
    vmax, amax = joint.vmax, joint.amax
    ctx = in_cell(robot, cell, margin, time_limit, seed)
    checker = None if ctx is None else ctx.checker

    def timed(program: list[Move], q0: Array, method: str = "toppra") -> MotionTrajectory:
        return plan(robot, program, limits, start=q0, vmax=vmax, amax=amax, method=method,
                    cell=checker, time_limit=time_limit, seed=seed,
                    objective=objective if method == "toppra" else "length")

    stops: MotionTrajectory | None = None
    tried: list[str] = []
    for A, B, q0, elbow in (placements(robot, up, across, down) if ctx is not None
                            else [place_cycle(robot, up, across, down)]):
        Au, Bu = A + up * UP, B + down * UP

        def program(r: float, Au: Array = Au, Bu: Array = Bu, A: Array = A, B: Array = B,
                    elbow: str = elbow) -> list[Move]:
            return [LIN(Target(Au), blend=r), PTP(Target(Bu), elbow=elbow, blend=r),
                    LIN(Target(B)), LIN(Target(Bu), blend=r), PTP(Target(Au), elbow=elbow,
                                                                  blend=r), LIN(Target(A))]

        try:
            stops = timed(program(0.0), q0)
            break
        except (MoveError, CollisionError) as exc:
            if ctx is None:  # pragma: no cover - placement checked the corners
                raise InputError(f"the placed cycle does not plan: {exc}; pass shorter "
                                 "strokes") from None
            tried.append(str(exc))
            if len(tried) >= MAX_PLACEMENTS:
                break
    if stops is None:
        raise InputError(f"no placement of the {up * 1e3:g}/{across * 1e3:g}/{down * 1e3:g} mm "
                         f"cycle plans clear of the cell ({len(tried)} tried; the first: "
                         f"{tried[0] if tried else 'none reachable'}); move obstacles, or "
                         "pass other strokes")
    corners = stops.waypoints
    durations = {"toppra": stops.duration,
                 "ruckig": timed(program(0.0), q0, method="ruckig").duration}
    blocked = [] if ctx is None else [
        k for k, (a, b) in enumerate(zip(corners[:-1], corners[1:], strict=True))
        if not prove_segment(ctx.checker, a, b).clear]
    if not blocked:
        durations["quintic"] = time_parameterize(corners, robot, method="quintic", vmax=vmax,
                                                 amax=amax).duration
    traj = stops
    if blend:
        traj = timed(program(blend), q0)
        durations["toppra_blended"] = traj.duration
    notes = () if ctx is None else _cell_notes(blocked, durations, ctx.checker.cell.name)
    return CycleResult(robot.name, up, across, down, A, B, durations, traj, corners, blend,
                       None if ctx is None else ctx.checker.cell.name,
                       None if ctx is None else _least(traj), notes, stops.lower_bound,
                       objective)


def _least(traj: MotionTrajectory) -> float | None:
    """The least clearance of a trajectory planned in a cell [m] (None: not found)."""
    report = traj.check_collisions()
    return None if report.least is None else report.least.distance


#: the corners of the cycle, in order (A: the pick, B: the place)
CORNERS = ("A", "A up", "B up", "B", "B up", "A up", "A")


def _cell_notes(blocked: list[int], durations: dict[str, float], cell: str
                ) -> tuple[str, ...]:
    """Why the quintic baseline is missing in a cell, and why ruckig is slow there.

    ``blocked``: the indices of the corner-to-corner joint segments not proven clear.
    """
    if not blocked:
        return ()
    which = ", ".join(f"{CORNERS[k]} to {CORNERS[k + 1]}" for k in blocked)
    notes = [f"quintic not timed: it moves straight in joint space from corner to corner, "
             f"and those segments are not proven clear of {cell!r} ({which}); toppra and "
             f"ruckig follow the paths planned around it"]
    across = [k for k in blocked if k in (1, 4)]
    if across:
        ratio = durations["ruckig"] / durations["toppra"]
        notes.append(f"ruckig takes {ratio:.2f}x toppra's time: it runs each section under "
                     f"bounds that are constant along its path, the tightest anywhere on it "
                     f"(jerk-limited), and the PTPs planned around {cell!r} bend, which sets "
                     f"those bounds low; toppra varies its speed along the path")
    return tuple(notes)


def cycle_with_payload(robot: Robot, result: CycleResult, payload: PayloadLike,
                       limits: ToolLimits | None = None) -> MotionTrajectory:
    """The placed cycle of ``result`` timed by toppra under the robot's torque limits too.

    ``payload``: the load at the tool, ``mass`` [kg] or ``(mass, com[, inertia])``. The
    joint limits are those ``result`` was timed with.

    Raises:
        DynamicsError: the robot has no inertias or torque limits, or cannot hold the load.
    """
    joint = result.trajectory.limits
    return plan(robot, result.trajectory.moves, limits, start=result.corners[0],
                vmax=joint.vmax, amax=joint.amax, payload=payload)
