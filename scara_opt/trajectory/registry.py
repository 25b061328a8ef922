"""One registry of timing methods: ``time_parameterize(path, robot, method=...)`` looks them up.

Same pattern as the IK registry (:mod:`scara_opt.ik.registry`): a decorator that refuses
duplicate names, a listing, and :class:`~scara_opt.errors.UnknownSolverError` for an unknown
name. Backends import their heavy library (toppra, ruckig) inside the call, not here.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from scara_opt import checks
from scara_opt.checks import check_real, describe
from scara_opt.errors import InputError, SolverOptionError, UnknownSolverError
from scara_opt.model.robot import Robot, check_robot
from scara_opt.trajectory import quintic, ruckig_backend, toppra_backend
from scara_opt.trajectory.dynamics import RobotDynamics
from scara_opt.trajectory.limits import Limits, resolve_limits
from scara_opt.trajectory.methods import Backend, TimingMethod
from scara_opt.trajectory.trajectory import Trajectory
from scara_opt.trajectory.waypoints import prepare_waypoints

log = logging.getLogger(__name__)

#: the registered methods: the built-in backends' entries, then any register_timing adds
_REGISTRY: dict[str, TimingMethod] = {m.name: m for m in (quintic.METHOD, toppra_backend.METHOD,
                                                          ruckig_backend.METHOD)}

#: longest fixed duration [s] (about 32 years): the quintic's coefficients divide by
#: duration**5, which must stay far from overflow
MAX_DURATION = 1e9


def register_timing(name: str, *, options: dict[str, Any] | None = None,
                    uses_jerk: bool = False, takes_duration: bool = False,
                    replace: bool = False) -> Callable[[Backend], Backend]:
    """Decorator registering a timing backend under ``name``.

    Raises:
        InputError: the name is not a short lowercase tag, or is taken (unless ``replace``).
    """
    if not name or name != name.lower() or not name.replace("_", "").isalnum():
        raise InputError(f"timing method name must be a short lowercase tag; got {name!r}")

    def add(fn: Backend) -> Backend:
        if name in _REGISTRY and not replace:
            raise InputError(f"a timing method named {name!r} is already registered; pick "
                             "another name or pass replace=True")
        _REGISTRY[name] = TimingMethod(name, fn, dict(options or {}), uses_jerk, takes_duration)
        return fn

    return add


def timing_methods() -> list[str]:
    """Names of the registered timing methods, sorted."""
    return sorted(_REGISTRY)


def get_timing(method: str) -> TimingMethod:
    """The :class:`TimingMethod` registered as ``method``.

    Raises:
        UnknownSolverError: not registered (the message lists the names).
    """
    if not isinstance(method, str):
        raise InputError(f"method must be one timing method name (a str) from "
                         f"{sorted(_REGISTRY)}; got {describe(method)}")
    if method not in _REGISTRY:
        raise UnknownSolverError(method, _REGISTRY, kind="time-parameterisation method")
    return _REGISTRY[method]


def _check_duration(duration: object, entry: TimingMethod) -> float | None:
    if duration is None:
        return None
    if not entry.takes_duration:
        raise InputError(f"method {entry.name!r} computes the shortest duration within the "
                         "limits and takes no duration=; use method='quintic' for a fixed "
                         "duration")
    return check_real("duration", duration, 0.0, MAX_DURATION, low_open=True, unit="s")


def time_parameterize(path: object, robot: Robot | None = None, method: str = "toppra",
                      vmax: object | None = None, amax: object | None = None,
                      jmax: object | None = None, duration: float | None = None, *,
                      allow_jumps: bool = False, drop_duplicates: bool = False,
                      torque_limits: object | None = None, payload: object | None = None,
                      payload_frame: str | None = None, **options: Any) -> Trajectory:
    """Time a joint path within joint velocity/acceleration (and jerk, torque) limits.

    Args:
        path: a :class:`~scara_opt.trajectory.path.JointPath` or an (n, nq) array of joint
            waypoints [rad or m], n >= 2.
        robot: the robot; its limits are the defaults and its position limits are checked.
            May be ``None`` when ``vmax`` and ``amax`` are given.
        method: a name from :func:`timing_methods`: ``"toppra"`` (time-optimal through the
            waypoints), ``"ruckig"`` (jerk-limited, moving through the interior waypoints:
            :mod:`~scara_opt.trajectory.passing`), ``"quintic"``
            (rest-to-rest quintic per segment).
        vmax: velocity limits [rad/s or m/s], scalar or (nq,); default the robot's.
        amax: acceleration limits [rad/s² or m/s²], scalar or (nq,); default the robot's.
        jmax: jerk limits [rad/s³ or m/s³] for jerk-limited methods; default
            ``JERK_PER_ACCELERATION × amax`` (10/s × amax).
        duration: fixed total duration [s] (``"quintic"`` only), at most
            :data:`MAX_DURATION`; ``None`` = the shortest within the limits. A shorter one
            than that is refused unless the option ``enforce_limits=False`` is passed too.
        allow_jumps: time a JointPath even if it reports joint jumps (logged as a warning);
            True or False only.
        drop_duplicates: remove consecutive duplicate waypoints (logged) instead of refusing;
            True or False only.
        torque_limits: joint torque limits [N·m revolute, N prismatic] (``"toppra"`` only,
            needs a robot with inertial data): ``True`` for the robot's own
            (``robot.torque_limit``), a scalar or (nq,); ``None`` = not torque-limited,
            unless ``payload`` is given (then the robot's own); ``False`` = not limited.
            τ = Pinocchio's RNEA, gravity included; checked at 1 kHz in
            ``check_limits()["torque"]``.
        payload: a load at ``payload_frame``: mass [kg], ``(mass, com (3,) [m])`` or
            ``(mass, com, inertia (3, 3) [kg·m²] about the com)``, com in that frame.
        payload_frame: the frame (link) carrying the payload; default the robot's tip.
        **options: method-specific options (an unknown one raises SolverOptionError):
            toppra ``margin``, ``grid_per_segment``, ``min_grid``, ``max_refine``; quintic
            ``enforce_limits``; ruckig none.

    Returns:
        Trajectory: rest to rest, through every waypoint.

    Raises:
        UnknownSolverError: unknown ``method``.
        SolverOptionError: an option the method does not accept.
        InputError: malformed path or duration; ``robot`` not a Robot (a robot name: load it
            with ``so.load_robot``); a flag that is not True/False; a zero, negative,
            infinite, NaN or misshaped limit, or one outside
            :data:`~scara_opt.trajectory.limits.LIMIT_RANGES`; an option value out of
            range; ``jmax`` for a method without jerk; bad ``torque_limits`` or ``payload``
            (negative or NaN mass, a limit <= 0), or either for a method without torque.
        DynamicsError: torque-limited timing of a robot without inertial data or torque
            limits, or a path where gravity alone exceeds a torque limit.
        FrameNotFoundError: ``payload_frame`` is not a frame of the robot.
        JointLimitError: a waypoint outside the joint limits.
        TrajectoryError: fewer than two waypoints, consecutive duplicates, a JointPath with
            unreachable points or jumps, a fixed quintic duration below the shortest within
            the limits (without ``enforce_limits=False``), or a backend failure.
    """
    if robot is not None:
        check_robot(robot)
    checks.check_flag("allow_jumps", allow_jumps)
    checks.check_flag("drop_duplicates", drop_duplicates)
    entry = get_timing(method)
    unknown = set(options) - set(entry.options)
    if unknown:
        raise SolverOptionError(method, unknown, entry.options)
    if jmax is not None and not entry.uses_jerk:
        raise InputError(f"method {method!r} does not limit jerk; drop jmax= or use "
                         "method='ruckig'")
    fixed = _check_duration(duration, entry)
    Q = prepare_waypoints(path, robot, allow_jumps=allow_jumps, drop_duplicates=drop_duplicates)
    limits: Limits = resolve_limits(robot, Q.shape[1], vmax, amax, jmax, entry.uses_jerk)
    extra = {}
    if payload_frame is not None and payload is None:
        raise InputError(f"payload_frame={payload_frame!r} without payload=: pass the payload "
                         "(mass [kg], or (mass, com[, inertia])) or drop payload_frame=")
    if not (torque_limits is None or torque_limits is False) or payload is not None:
        extra["dynamics"] = _dynamics(entry, robot, torque_limits, payload, payload_frame)
    start = time.perf_counter()
    traj = entry.backend(Q, limits, fixed, **{**entry.options, **options}, **extra)
    elapsed = time.perf_counter() - start
    if log.isEnabledFor(logging.DEBUG):  # traj.duration costs ~1 µs even when not logged
        log.debug("%s: %d waypoints timed to %.4f s in %.2f ms", method, len(Q), traj.duration,
                  elapsed * 1e3)
    return replace(traj, compute_time_s=elapsed)


def _dynamics(entry: TimingMethod, robot: Robot | None, torque_limits: object,
              payload: object, payload_frame: str | None) -> RobotDynamics:
    """The inverse dynamics for a torque-limited timing, checked (see time_parameterize)."""
    if not entry.uses_torque:
        with_torque = [m.name for m in _REGISTRY.values() if m.uses_torque]
        raise InputError(f"method {entry.name!r} does not limit joint torque; drop "
                         f"torque_limits=/payload= or use method={with_torque[0]!r}")
    if robot is None:
        raise InputError("torque_limits= and payload= need the robot (its inertial data): pass "
                         "robot=")
    if torque_limits is False:
        raise InputError("torque_limits=False with a payload: a payload only matters under "
                         "torque limits; pass torque_limits=True (the robot's own) or values")
    return RobotDynamics(robot, torque_limits, payload, payload_frame)


def ruckig_point_to_point(q_start: object, q_goal: object, robot: Robot | None = None,
                          vmax: object | None = None, amax: object | None = None,
                          jmax: object | None = None) -> Trajectory:
    """Jerk-limited, time-optimal rest-to-rest move from ``q_start`` to ``q_goal``.

    Args:
        q_start: (nq,) start configuration [rad or m].
        q_goal: (nq,) goal configuration [rad or m].
        robot: the robot (default limits, joint names, position-limit check), or ``None``.
        vmax: velocity limits, scalar or (nq,) [rad/s or m/s]; default the robot's.
        amax: acceleration limits, scalar or (nq,) [rad/s² or m/s²]; default the robot's.
        jmax: jerk limits, scalar or (nq,) [rad/s³ or m/s³]; default 10/s × amax.

    Raises:
        InputError, JointLimitError, TrajectoryError: as for
        :func:`~scara_opt.trajectory.time_parameterize`; TrajectoryError also when
        ``q_goal`` equals ``q_start`` (there is no move to time).
    """
    return time_parameterize(_pair(q_start, q_goal), robot, method="ruckig", vmax=vmax,
                             amax=amax, jmax=jmax)


def _pair(q_start: object, q_goal: object) -> object:
    """``[q_start, q_goal]``; as one (2, nq) array when both are float64 ndarrays (nq,).

    The array is what :func:`~scara_opt.trajectory.waypoints.prepare_waypoints` makes of
    such a list, made directly, so that its fast path takes it (~10 µs less); anything else
    stays the list, for the full checks and their messages.
    """
    if (type(q_start) is np.ndarray and type(q_goal) is np.ndarray and q_start.ndim == 1
            and q_start.shape == q_goal.shape and q_start.dtype == q_goal.dtype == np.float64):
        return np.array([q_start, q_goal])
    return [q_start, q_goal]
