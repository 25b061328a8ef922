"""Joint velocity, acceleration and jerk limits of a timing, resolved and validated once."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import InputError, TrajectoryError
from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

#: default jerk limit per joint: ``JERK_PER_ACCELERATION × amax`` [1/s × rad/s² or m/s²], i.e.
#: the acceleration limit is reached in 0.1 s (robot files carry no jerk limit)
JERK_PER_ACCELERATION = 10.0

#: the range each limit must lie in, by quantity [per s, per s², per s³]. Below the floor the
#: timing arithmetic breaks down (toppra divides the path by vmax: vmax = 1e-300 overflows to
#: inf; the quintic's duration**5 overflows) and a motion would take years; above the ceiling
#: the backends lose precision (Ruckig fails at amax = 1e9). To leave a joint effectively
#: unlimited, pass the ceiling. The jerk range is wider by the default ratio
#: :data:`JERK_PER_ACCELERATION` (and more), so the default jerk of any allowed amax fits.
LIMIT_RANGES = {"vmax": (1e-6, 1e6), "amax": (1e-6, 1e6), "jmax": (1e-6, 1e8)}

#: largest jmax / amax per joint [1/s] (the acceleration limit reached in 10 µs or more):
#: beyond, Ruckig's profiles exceed the acceleration limit measurably (measured with
#: amax = 1e-3: by 1.2e-8 at 1e7 /s, 8e-7 at 1e8 /s, 4e-4 at 1e11 /s; 3e-10 at 1e5 /s)
MAX_JERK_RATIO = 1e5

_F64 = np.dtype(np.float64)


@dataclass(frozen=True)
class Limits:
    """Per-joint limits used to time a joint path.

    Attributes:
        vmax: (nq,) velocity limits [rad/s or m/s], finite and positive.
        amax: (nq,) acceleration limits [rad/s² or m/s²], finite and positive.
        jmax: (nq,) jerk limits [rad/s³ or m/s³], or ``None`` when the method ignores jerk.
        joint_names: one name per joint.
        joint_types: ``"revolute"``, ``"prismatic"`` or ``"joint"`` (unknown) per joint.
        lower: (nq,) lower position limits [rad or m] (``-inf`` when unknown).
        upper: (nq,) upper position limits [rad or m] (``+inf`` when unknown).
    """

    vmax: Array
    amax: Array
    jmax: Array | None
    joint_names: tuple[str, ...]
    joint_types: tuple[str, ...]
    lower: Array
    upper: Array

    @property
    def nq(self) -> int:
        """Number of joints."""
        return int(self.vmax.shape[0])

    def unit(self, k: int) -> str:
        """Position unit of joint ``k``: ``"rad"``, ``"m"`` or ``"rad or m"``."""
        return {"revolute": "rad", "prismatic": "m"}.get(self.joint_types[k], "rad or m")


def _in_range(value: object, nq: int, what: str) -> Array | None:
    """The fast path of :func:`_per_joint`: its answer where it is plain, else ``None``.

    A float64 ndarray (nq,) whose entries all lie in ``LIMIT_RANGES[what]`` passes every
    check and comes back as it is; a float in range comes back as ``np.full(nq, value)``.
    Anything else (ints, a list, another dtype or shape, an ndarray subclass, NaN, ±inf, a
    value out of range) gives ``None``, never an error: the full check then runs. A Python
    loop over the entries, ~1 µs for a few joints against several µs of numpy calls.
    """
    low, high = LIMIT_RANGES[what]
    if type(value) is float:
        return np.full(nq, value) if low <= value <= high else None
    if type(value) is not np.ndarray or value.dtype is not _F64 or value.shape != (nq,):
        return None
    for v in value.tolist():
        if not low <= v <= high:  # NaN fails both
            return None
    return value


def _per_joint(value: object, nq: int, what: str, unit: str,
               names: tuple[str, ...], option: str = "{}=") -> Array:
    """``value`` (scalar or (nq,)) as a checked (nq,) array within :data:`LIMIT_RANGES`.

    ``option``: how the messages spell the option, ``"{}="`` (``vmax=``) or ``"--{}"``.

    Raises:
        InputError: not numeric, wrong shape, NaN, a zero/negative/infinite entry, or one
            outside :data:`LIMIT_RANGES` (the message names the joint, the value and why).
    """
    fast = _in_range(value, nq, what)
    if fast is not None:
        return fast
    try:
        arr = float_array(value, what)
    except InputError:
        raise InputError(f"{what} must be a number or one number per joint {list(names)} "
                         f"[{unit}]; got {describe(value)}") from None
    if arr.ndim == 0:
        arr = np.full(nq, float(arr))
    if arr.shape != (nq,):
        raise InputError(f"{what} must be a scalar or have shape ({nq},), one entry per joint "
                         f"{list(names)} [{unit}]; got shape {arr.shape}")
    if np.isnan(arr).any():
        bad = [names[k] for k in np.flatnonzero(np.isnan(arr))]
        raise InputError(f"{what} is NaN for joints {bad}; give a positive number [{unit}]")
    for k, v in enumerate(arr):
        if not (v > 0 and math.isfinite(v)):
            raise InputError(
                f"{what} for joint {names[k]!r} is {v:g} [{unit}]; each limit must be finite and "
                f"> 0: pass a positive {option.format(what)} (scalar or one per joint)")
    low, high = LIMIT_RANGES[what]
    for k, v in enumerate(arr):
        if not low <= v <= high:
            why = ("so small that the timing overflows (and the motion would take years)"
                   if v < low else "so large that the timing backends lose precision; for an "
                   f"effectively unlimited joint pass {high:g}")
            raise InputError(
                f"{what} for joint {names[k]!r} is {v:g} [{unit}], {why}: each {what} must lie "
                f"in [{low:g}, {high:g}] [{unit}]; pass {option.format(what)} within that range")
    return arr


def resolve_limits(robot: Robot | None, nq: int, vmax: object | None = None,
                   amax: object | None = None, jmax: object | None = None,
                   need_jerk: bool = False, option: str = "{}=") -> Limits:
    """The limits of a timing: overrides where given, else the robot's own.

    Args:
        robot: the robot whose limits are the defaults, or ``None`` (then ``vmax`` and
            ``amax`` are required).
        nq: number of joints of the path.
        vmax: velocity limits [rad/s or m/s]: scalar or (nq,), or ``None`` for the robot's.
        amax: acceleration limits [rad/s² or m/s²]: scalar or (nq,), or ``None``.
        jmax: jerk limits [rad/s³ or m/s³]: scalar or (nq,), or ``None`` for
            ``JERK_PER_ACCELERATION × amax`` (only used when ``need_jerk``).
        need_jerk: whether the method uses a jerk limit (then ``jmax / amax`` is at most
            :data:`MAX_JERK_RATIO` per joint).
        option: how the messages name the options: ``"{}="`` (``pass amax=``), or
            ``"--{}"`` for the command line (``pass --amax``).

    Raises:
        InputError: wrong shape, non-numeric, NaN, zero, negative or infinite limits, or
            limits (given or the robot's) outside :data:`LIMIT_RANGES` (the message names
            the joint); path and robot joint counts differ.
        TrajectoryError: no limit given and the robot has none for some joint.
    """
    if robot is not None and robot.nq != nq:
        raise InputError(f"the path has {nq} joints but robot {robot.name!r} has {robot.nq} "
                         f"({robot.joint_names}); pass a path of shape (n, {robot.nq})")
    if robot is not None:
        names = tuple(robot.joint_names)
        types = tuple(robot.joint_types)
        lower, upper = robot.lower, robot.upper
    else:
        names = tuple(f"joint{k}" for k in range(nq))
        types = ("joint",) * nq
        lower, upper = np.full(nq, -np.inf), np.full(nq, np.inf)

    def pick(value: object | None, own: str, what: str, u: str) -> Array:
        if value is not None:
            return _per_joint(value, nq, what, u, names, option)
        if robot is None:
            raise InputError(f"without a robot, {option.format(what)} is required (scalar or "
                             f"one per joint) [{u}]")
        arr = getattr(robot, own)
        if _in_range(arr, nq, what) is not None:
            return arr
        missing = [names[k] for k in np.flatnonzero(~np.isfinite(arr))]
        if missing:
            raise TrajectoryError(f"robot {robot.name!r} has no {what} for joints {missing}; "
                                  f"pass {option.format(what)} (scalar or one per joint) "
                                  f"[{u}]")
        try:
            return _per_joint(arr, nq, what, u, names)
        except InputError as exc:
            raise InputError(f"robot {robot.name!r}'s own limit: {exc} (or fix the robot "
                             "file)") from None

    v = pick(vmax, "velocity_limit", "vmax", "rad/s or m/s")
    a = pick(amax, "acceleration_limit", "amax", "rad/s² or m/s²")
    j = None
    if need_jerk:
        j = (JERK_PER_ACCELERATION * a if jmax is None
             else _per_joint(jmax, nq, "jmax", "rad/s³ or m/s³", names, option))
        over = np.flatnonzero(j > MAX_JERK_RATIO * a)
        if over.size:
            k = int(over[0])
            raise InputError(
                f"jmax / amax for joint {names[k]!r} is {j[k] / a[k]:.3g} /s (jmax {j[k]:g}, "
                f"amax {a[k]:g}): above {MAX_JERK_RATIO:g} /s the jerk phases are shorter "
                "than Ruckig resolves and the acceleration limit is exceeded (by 4e-4 at "
                f"1e11 /s); pass {option.format('jmax')} <= {MAX_JERK_RATIO:g} x amax")
    return Limits(v, a, j, names, types, np.asarray(lower, float), np.asarray(upper, float))
