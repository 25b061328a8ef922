"""``plan(robot, moves, limits)``: one rest-to-rest :class:`~scara_opt.Trajectory` of a program.

Each move becomes a joint path: a PTP the straight joint line to its goal (IK on the asked
elbow branch for a Target), a LIN or CIRC the IK of its Cartesian points every ``step``
metres, on the branch it starts on (:mod:`scara_opt.motion.branch`). Each path is timed
time-optimally under the joint limits and the move's tool limits
(:mod:`scara_opt.motion.timing`); without blends the robot stops exactly at every goal.
Moves with a ``blend`` radius run on into the next move through a rounded corner, the
whole run timed at once: a Bézier of the tool path between LIN/CIRC moves
(:mod:`scara_opt.motion.blend`), a Bézier in joint space in a run with a PTP
(:mod:`scara_opt.motion.blend_joint`).
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Iterable
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PPoly

from scara_opt.checks import check_flag, check_real
from scara_opt.errors import BranchError, InputError, MoveError
from scara_opt.model.joint_checks import check_within_limits
from scara_opt.model.robot import Robot, check_robot
from scara_opt.motion import branch, geometry
from scara_opt.motion.blend import blended_joints
from scara_opt.motion.blend_joint import joint_blended
from scara_opt.motion.clearance import in_cell
from scara_opt.motion.fastest import check_objective, restarts, synchronized
from scara_opt.motion.jerk import jerk_limited_section
from scara_opt.motion.moves import CIRC, LIN, PTP, Move, as_moves, goal_point
from scara_opt.motion.result import MotionTrajectory
from scara_opt.motion.timing import time_section
from scara_opt.motion.tool_limits import ToolLimits, ToolProfile
from scara_opt.target import Target
from scara_opt.trajectory.bound import lower_bound
from scara_opt.trajectory.dynamics import PayloadLike, RobotDynamics
from scara_opt.trajectory.limits import resolve_limits
from scara_opt.trajectory.trajectory import concatenate

if TYPE_CHECKING:
    from scara_opt.collision import Cell, CollisionChecker

Array = NDArray[np.float64]

#: how each stop-to-stop run is timed, by ``method``
SECTION_TIMERS = {"toppra": time_section, "ruckig": jerk_limited_section}

#: default spacing of the Cartesian points of a LIN or CIRC [m]
STEP = 0.002

#: a move whose goal is this close to its start (joints [rad or m]) does not move
STILL = 1e-9


def _goal_pose(index: int, robot: Robot, goal: Target | Array, yaw0: float | None
               ) -> tuple[Array, float | None]:
    """Goal position (3,) and yaw (nearest turn to ``yaw0``; ``yaw0`` if the goal has none)."""
    if isinstance(goal, Target):
        if goal.rotation is not None:
            raise MoveError(index, "LIN/CIRC goals take a position and optional yaw, not a "
                                   "rotation; pass Target(position, yaw=)")
        p, yaw = goal.position, goal.yaw
    else:
        p, yaw = branch.tool_pose(robot, robot.check_q(goal, "goal"))
    if yaw0 is None or yaw is None:
        return np.asarray(p, float), yaw0
    return np.asarray(p, float), geometry.nearest_turn(yaw, yaw0)


def move_curve(index: int, move: Move, robot: Robot, p0: Array, yaw0: float | None
               ) -> tuple[geometry.Curve, float | None]:
    """Tool path of a LIN or CIRC from ``p0`` and its goal yaw (nearest turn to ``yaw0``).

    Raises:
        MoveError: a rotation goal; CIRC points collinear or coincident.
    """
    goal = goal_point(index, move.goal, robot.nq, "goal")
    p1, yaw1 = _goal_pose(index, robot, goal, yaw0)
    if not isinstance(move, CIRC):
        return geometry.Curve(p0, p1), yaw1  # a LIN
    via = goal_point(index, move.via, robot.nq, "via", joints=False).position
    c = geometry.circle(p0, np.asarray(via, float), p1)
    if c is None:
        raise MoveError(index, f"CIRC start {np.round(p0, 6).tolist()}, via "
                               f"{np.round(via, 6).tolist()} and goal "
                               f"{np.round(p1, 6).tolist()} m are collinear (or two coincide): "
                               "no circle passes them; move the via point off the line, or "
                               "use LIN")
    return geometry.Curve(p0, p1, c), yaw1


def move_joints(index: int, move: Move, robot: Robot, q_prev: Array, step: float) -> Array:
    """Joint path (n, nq) of one move from ``q_prev`` (its first row).

    Raises:
        MoveError: unreachable or off-branch goals and paths, collinear CIRC points, a move
            that does not move.
    """
    goal = goal_point(index, move.goal, robot.nq, "goal")
    if isinstance(move, PTP):
        q1 = branch.ptp_goal(index, robot, goal, q_prev, move.elbow)
        Q = np.array([q_prev, q1])
    else:
        p0, yaw0 = branch.tool_pose(robot, q_prev)
        curve, yaw1 = move_curve(index, move, robot, p0, yaw0)
        f = np.linspace(0.0, 1.0, geometry.count(curve.length, step))
        P = curve.at(f)
        yaws = None if yaw0 is None or yaw1 is None else yaw0 + f * (yaw1 - yaw0)
        # (yaw1 is None only where yaw0 is: _goal_pose)
        Q = np.vstack([q_prev, branch.path_joints(index, move.kind, robot, P[1:],
                                                  None if yaws is None else yaws[1:],
                                                  q_prev, move.elbow)])
        if not isinstance(goal, Target) and np.abs(Q[-1] - goal).max() > 1e-6:
            raise MoveError(index, f"{move.kind} ends at joints {np.round(Q[-1], 6).tolist()}, "
                                   f"not the joint goal {np.round(goal, 6).tolist()} (another "
                                   "elbow branch or wrist turn): a LIN/CIRC keeps its branch; "
                                   "reach that goal with a PTP")
    if np.abs(Q[-1] - Q[0]).max() <= STILL:
        raise MoveError(index, f"{move.kind} goal is where the robot already is: drop the move")
    return Q


def _sections(program: list[Move], offset: int) -> list[list[tuple[int, Move]]]:
    """The program cut into stop-to-stop runs: a move with a blend joins the next one.

    Raises:
        MoveError: a blend on the last move.
    """
    last = len(program) - 1
    if program[last].blend:
        raise MoveError(last + offset, "the last move has a blend radius but nothing to blend "
                                       "into; pass blend=0")
    runs, run = [], []
    for k, m in enumerate(program):
        run.append((k + offset, m))
        if not m.blend:
            runs.append(run)
            run = []
    return runs


def _flip(index: int, move: Move, robot: Robot, q: Array, exc: BranchError,
          step: float) -> list[list[tuple[int, Move]]]:
    """A LIN/CIRC that leaves its branch, split where it leaves it.

    Up to the last point on the branch, a PTP flipping the elbow at that pose (a stop),
    then the rest on the other branch.
    """
    p0, yaw0 = branch.tool_pose(robot, q)
    curve, yaw1 = move_curve(index, move, robot, p0, yaw0)
    f = np.linspace(0.0, 1.0, geometry.count(curve.length, step))[exc.point]

    def pose(x: float) -> Target:
        return Target(curve.at(np.array([x]))[0], None if yaw0 is None or yaw1 is None else
                      yaw0 + x * (yaw1 - yaw0))

    def part(a: float, b: float, goal: Target | ArrayLike) -> Move:
        if isinstance(move, LIN):
            return LIN(goal, speed=move.speed, acceleration=move.acceleration)
        return CIRC(curve.at(np.array([(a + b) / 2]))[0], goal, speed=move.speed,
                    acceleration=move.acceleration)

    other = "lefty" if exc.side == "righty" else "righty"
    runs = [[(index, part(0.0, f, pose(f)))]] if f > 0 else []
    return runs + [[(index, PTP(pose(f), elbow=other))], [(index, part(f, 1.0, move.goal))]]


def plan(robot: Robot, moves: Move | Iterable[Move], limits: ToolLimits | None = None, *,
         start: ArrayLike | None = None, vmax: ArrayLike | None = None,
         amax: ArrayLike | None = None,
         step: float = STEP, method: str = "toppra", allow_flip: bool = False,
         torque_limits: bool | ArrayLike | None = None, payload: PayloadLike | None = None,
         payload_frame: str | None = None, cell: Cell | CollisionChecker | None = None,
         margin: float | None = None, time_limit: float = 1.0, seed: int = 0,
         objective: str = "length") -> MotionTrajectory:
    """Plan a program of PTP / LIN / CIRC moves into one timed trajectory.

    Args:
        robot: the robot (its joint limits are the defaults).
        moves: a sequence of :class:`~scara_opt.motion.PTP`, ``LIN``, ``CIRC``.
        limits: program-wide :class:`ToolLimits` (speed, acceleration, yaw rate) for LIN
            and CIRC moves; a move's own ``speed`` / ``acceleration`` overrides them, and
            a PTP honours only its own.
        start: (nq,) start configuration; default the first move's goal when the first
            move is a PTP (it is then the start and takes no time).
        vmax: joint velocity limits, scalar or (nq,) [rad/s or m/s]; default the robot's.
        amax: joint acceleration limits, scalar or (nq,) [rad/s² or m/s²]; default the robot's.
        step: spacing of the Cartesian points of LIN/CIRC moves [m].
        method: ``"toppra"`` (time-optimal) or ``"ruckig"`` (jerk-limited along the path,
            under constant bounds on the path speed: :mod:`scara_opt.motion.jerk`).
        allow_flip: a LIN/CIRC (not blended) that cannot stay on its elbow branch is split
            where it leaves it: a stop, a PTP flipping the elbow at that pose, then the rest
            on the other branch (said in the notes). Default: refused with BranchError.
        torque_limits: ``True`` (the robot's own), a scalar or (nq,) [N·m or N]: toppra
            also keeps the joint torques (Pinocchio's RNEA, gravity included) within them,
            checked at 1 kHz (``check_limits()["torque"]``); needs the robot's inertias.
        payload: a load at the tool (``mass`` [kg] or ``(mass, com[, inertia])``, see
            :func:`scara_opt.time_parameterize`); implies ``torque_limits=True``.
        payload_frame: the frame carrying the payload (default the tip).
        cell: a :class:`~scara_opt.Cell` (or a :class:`~scara_opt.CollisionChecker`) to
            plan in: PTPs go around its obstacles, every section is proven clear, a LIN or
            CIRC that hits it is refused (:mod:`scara_opt.motion.clearance`). A Cell is
            made into a checker at each call: pass a checker to plan many programs.
        margin: clearance to keep from the cell [m]; default a checker's own margin (0
            with a Cell); a margin given with a checker is used (``checker.with_margin``),
            and one given without a cell is refused.
        time_limit: limit of the whole call in a cell [s] (> 0): the PTPs plan within what
            is left, the simplifier stops at it with the shortest path proven by then, and
            past it a planned section is timed stopping at its waypoints (proven by
            construction) and proven once more: the call ends within the limit plus that
            last timing and proof. The kernel's one-off compilation does not count.
        seed: the planner's seed (the same seed, the same path).
        objective: ``"length"`` (a PTP is the straight joint segment, or in a cell the
            path planned short in joint space, then timed by toppra) or ``"time"`` (the
            least duration found: a PTP alone between stops is Ruckig's time-synchronized
            move where that is proven clear, at the lower bound, else the fastest proven
            timing of up to 6 planned paths (other seeds), shortcut by time; never slower than
            ``"length"``: :mod:`scara_opt.motion.fastest`). With ``method="toppra"``,
            without torque limits, for PTPs without tool limits of their own; other
            moves are timed as under ``"length"``.

    Returns:
        MotionTrajectory: rest to rest, stopping at every goal not blended;
        ``lower_bound`` the least duration any trajectory through its stops could take
        under the joint limits, ``bound_ratio`` its duration over it;
        ``check_limits()`` has the joint ratios and the tool ratios per stop-to-stop run
        (and ``"clearance"`` in a cell).

    Raises:
        MoveError: a bad move, named by index, with what to change (see the module).
        MoveCollisionError: in a cell, a LIN/CIRC (or blended run) that hits it, or a goal
            in collision: the move, the time, the bodies, the depth.
        NoPathFoundError: in a cell, no path found for a PTP within ``time_limit``.
        CollisionError: the start in collision.
        JointLimitError: the start outside the joint limits.
        InputError: bad limits, start or step; torque limits with ``method="ruckig"``.
        DynamicsError: torque limits for a robot without inertias, or a load gravity alone
            makes too heavy.
    """
    robot = check_robot(robot)
    program = as_moves(moves, robot.nq)
    tool = ToolLimits() if limits is None else limits
    if not isinstance(tool, ToolLimits):
        raise InputError("limits must be a ToolLimits(speed=, acceleration=, yaw_rate=) or None")
    step = check_real("step", step, 0.0, 0.1, low_open=True, unit="m")
    check_flag("allow_flip", allow_flip)
    if method not in SECTION_TIMERS:
        raise InputError(f"method must be one of {sorted(SECTION_TIMERS)}; got {method!r}")
    joint_limits = resolve_limits(robot, robot.nq, vmax, amax)
    objective = check_objective(objective)
    dynamics = None
    if torque_limits is not None or payload is not None:
        if method != "toppra":
            raise InputError("torque_limits= and payload= are kept by method='toppra' only; "
                             "drop them or use toppra")
        dynamics = RobotDynamics(robot, True if torque_limits is None else torque_limits,
                                 payload, payload_frame)
    cellp = in_cell(robot, cell, margin, time_limit, seed)
    if cellp is not None:
        cellp.start_clock()
    begin = time.perf_counter()
    if start is None:
        if not isinstance(program[0], PTP):
            raise InputError("give start= (nq,) or begin the program with a PTP (its goal is "
                             "then the start)")
        q0 = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
        q = (branch.ptp_goal(0, robot, goal_point(0, program[0].goal, robot.nq, "goal"), q0,
                             program[0].elbow) if cellp is None
             else cellp.goal(0, program[0], robot, q0))
        program, offset = program[1:], 1
        if not program:
            raise InputError("a program of a single PTP without start= does not move")
    else:
        q, offset = check_within_limits(robot, start, "start"), 0
    if cellp is not None:
        cellp.check_start(q)
    pieces: list[tuple[PPoly, ...]] = []
    goals, notes, corners, profiles, bounds = [q], [], [], [], []
    tools: dict[int, ToolLimits] = {}  # each move's own tool limits, by index
    queue = deque(_sections(program, offset))
    while queue:
        run = queue.popleft()
        fast, eligible = None, False
        if len(run) == 1:
            index, m = run[0]
            eligible = (objective == "time" and isinstance(m, PTP) and method == "toppra"
                        and dynamics is None and m.speed is None and m.acceleration is None)
            if eligible and isinstance(m, PTP):  # (isinstance: for mypy)
                q1 = (branch.ptp_goal(index, robot, goal_point(index, m.goal, robot.nq,
                                                               "goal"), q, m.elbow)
                      if cellp is None else cellp.goal(index, m, robot, q))
                if np.abs(q1 - q).max() <= STILL:
                    raise MoveError(index, "PTP goal is where the robot already is: drop "
                                           "the move")
                fast = synchronized(np.array([q, q1]), joint_limits, cellp)
        if fast is not None:
            Q, owner = np.array([q, q1]), [index] * 2
        elif len(run) == 1:
            try:
                Q = (move_joints(index, m, robot, q, step) if cellp is None
                     else cellp.joints(index, m, robot, q, step, move_joints))
            except BranchError as exc:
                if not allow_flip:
                    raise
                queue.extendleft(reversed(_flip(index, m, robot, q, exc, step)))
                continue
            owner = [index] * len(Q)
        else:
            Q, found, owner = (joint_blended(run, robot, q, step, move_joints)
                               if any(isinstance(m, PTP) for _, m in run)
                               else blended_joints(run, robot, q, step, move_curve))
            corners += [(c, r, len(pieces)) for c, r in found]
        by_index = {i: (ToolLimits(m.speed, m.acceleration) if isinstance(m, PTP)
                        else tool.merged(m.speed, m.acceleration)) for i, m in run}
        for i, own in by_index.items():
            tools.setdefault(i, own)

        def timed(Q: Array, owner: list[int], by_index: dict = by_index) -> tuple:
            profile = ToolProfile.per_point([by_index[i] for i in owner])
            part, note, knots = (time_section(robot, Q, joint_limits, profile, dynamics)
                                 if dynamics is not None
                                 else SECTION_TIMERS[method](robot, Q, joint_limits, profile))
            return part, note, knots, profile

        if fast is not None:
            part, note, knots = fast
            profile = ToolProfile.per_point([by_index[i] for i in owner])
        elif cellp is None:
            part, note, knots, profile = timed(Q, owner)
        elif eligible:  # in a cell, the synchronized move not proven clear
            t0 = sum(p[0].x[-1] for p in pieces)
            Q, (part, note, knots, profile) = restarts(cellp, run, Q, timed, joint_limits,
                                                       method, t0)
        else:
            t0 = sum(p[0].x[-1] for p in pieces)
            part, note, knots, profile = cellp.timed_clear(run, Q, owner, timed,
                                                           joint_limits, method, t0)
        bounds.append((Q[0], Q[-1]))  # the bounds after the loop: not on the clock
        profiles.append((knots, profile))
        pieces.append(part)
        goals.append(Q[-1])
        kinds = "+".join(m.kind for _, m in run)
        notes.append(f"move {run[0][0]}" + (f"-{run[-1][0]}" if len(run) > 1 else "")
                     + f" ({kinds}): {note}")
        q = Q[-1]
    run_bounds = np.array([lower_bound(a, b, joint_limits) for a, b in bounds])
    joined = tuple(concatenate([p[j] for p in pieces]) for j in range(robot.nq))
    ends = np.concatenate([[0.0], np.cumsum([p[0].x[-1] for p in pieces])])
    traj = MotionTrajectory(joined, joint_limits, method, np.array(goals), ends,
                            notes="; ".join(notes), robot=robot, moves=tuple(program),
                            tool_limits=tuple(tools[i] for i in sorted(tools)),
                            corners=tuple(corners), profiles=tuple(profiles),
                            dynamics=dynamics, stops=ends,
                            checker=None if cellp is None else cellp.checker,
                            run_bounds=run_bounds, objective=objective)
    return replace(traj.with_corner_passages(), compute_time_s=time.perf_counter() - begin)
