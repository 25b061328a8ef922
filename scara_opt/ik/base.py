"""The solver contract (template method): the base checks, seeds, times and judges.

The base checks input, seeds, times and assembles the :class:`IKResult`; a subclass
implements :meth:`Solver._solve` only.

Every solver's answer is judged here, the same way: the final ``q`` goes through the robot's
FK, the residual is recomputed, and ``solved`` is granted only when it is within ``tol``.
A solver that cannot prove a target unreachable (a metaheuristic) has its failures checked
by an exact solver, so ``"unreachable"`` always means outside the workspace and
``"max_iter"`` means the budget ran out on a reachable target.
"""

from __future__ import annotations

import math
import numbers
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar, cast

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import InputError, JointLimitError, SolverOptionError
from scara_opt.ik.result import STATUS_MESSAGES, IKResult, Status
from scara_opt.ik.task import check_task, config_errors, cost_of, error_from
from scara_opt.robot import Robot
from scara_opt.target import Target, as_target

Array = NDArray[np.float64]

#: joint values may leave the limits by this much through floating-point round-off [rad or m]
LIMIT_SLACK = 1e-10


@dataclass
class SolverOutput:
    """What a solver's ``_solve`` hands back to the base.

    Attributes:
        q: (nq,) the best configuration found.
        iterations: iterations (generations) run.
        evaluations: FK evaluations used.
        history: best cost per iteration.
        status: the solver's own verdict when the residual is above ``tol``
            (``UNREACHABLE`` only from solvers that can certify it).
        message: specifics to append to the standard message.
    """

    q: Array
    iterations: int = 0
    evaluations: int = 0
    history: Array = field(default_factory=lambda: np.zeros(0))
    status: Status = Status.MAX_ITER
    message: str = ""


def check_q0(robot: Robot, q0: object | None) -> Array | None:
    """``q0`` as an in-limit (nq,) array, or ``None``.

    Raises:
        InputError: wrong shape or non-finite values.
        JointLimitError: a joint outside its limits (names it, its value and range).
    """
    if q0 is None:
        return None
    q = robot.check_q(q0, "q0")
    for name, kind, v, lo, hi in zip(robot.joint_names, robot.joint_types, q, robot.lower,
                                     robot.upper, strict=True):
        if not lo - LIMIT_SLACK <= v <= hi + LIMIT_SLACK:
            unit = "rad" if kind == "revolute" else "m"
            raise JointLimitError(
                f"q0: joint {name!r} = {v:.4g} {unit} is outside [{lo:.4g}, {hi:.4g}] {unit}; "
                "pass q0 inside the limits or q0=None", joint=name)
    return np.clip(q, robot.lower, robot.upper)


def default_q0(robot: Robot) -> Array:
    """The start used when ``q0`` is None: zero where within the limits, else mid-range."""
    mid = 0.5 * (robot.sampling_lower + robot.sampling_upper)
    zero_ok = (robot.lower <= 0) & (robot.upper >= 0)
    return np.where(zero_ok, 0.0, mid)


def _describe_miss(dp: Array, dang: float | None, tol: float) -> str:
    """Which coordinates miss, e.g. "misses along z (dz = +0.102 m)"."""
    axes = [axis for axis, v in zip("xyz", dp, strict=True) if abs(v) > tol]
    parts = [f"d{axis} = {dp['xyz'.index(axis)]:+.4g} m" for axis in axes]
    if dang is not None and abs(dang) > tol:
        axes.append("the tool angle")
        parts.append(f"dangle = {dang:+.4g} rad")
    if not axes:
        return "no single coordinate above tol"
    return f"misses along {', '.join(axes)} ({', '.join(parts)})"


def make_result(robot: Robot, target: Target, out: SolverOutput, *, tol: float, method: str,
                seed: int | None, time_s: float, certified: bool) -> IKResult:
    """Judge a solver's output and build the :class:`IKResult` (see module docstring)."""
    lower, upper = robot.lower, robot.upper
    q_out = np.asarray(out.q, dtype=float)
    q = np.clip(q_out, lower, upper)
    over = float(np.max(np.abs(q - q_out)))  # NaN if q_out has NaN
    status_if_miss, extra = out.status, out.message
    if not over <= LIMIT_SLACK:
        # a solver bug must not leak: report failure at the closest in-limit point
        status_if_miss = Status.FAILED
        extra = f"solver returned q outside the limits by {over:.3g}; " + extra
        q = np.clip(np.nan_to_num(q_out), lower, upper)
        certified = True  # nothing to certify: this is a failure, not a verdict on the target
    dp, dang = config_errors(robot, target, q)
    error = error_from(dp, dang)
    if error <= tol:
        status = Status.SOLVED
    elif status_if_miss == Status.FAILED or certified:
        status = status_if_miss
    else:
        from scara_opt.ik.reach import is_reachable

        status = Status.MAX_ITER if is_reachable(robot, target, tol) else Status.UNREACHABLE
    message = STATUS_MESSAGES[status]
    if status != Status.SOLVED:
        message += f"; residual {error:.4g} ({_describe_miss(dp, dang, tol)}), tol {tol:g}"
    if extra:
        message += f"; {extra}"
    return IKResult(q=q, success=status == Status.SOLVED, status=status, message=message,
                    position_error=dp, yaw_error=dang, error=error,
                    cost=cost_of(target, dp, dang), iterations=int(out.iterations),
                    evaluations=int(out.evaluations), time_s=time_s,
                    history=np.asarray(out.history, dtype=float), method=method, seed=seed,
                    tol=tol)


def check_number(name: str, value: Any, low: float, high: float = math.inf, *,
                 integer: bool = False, low_open: bool = False, high_open: bool = False) -> None:
    """Refuse an option value outside ``[low, high]`` (ends opened by ``*_open``).

    Bools and NaN are refused too.

    Raises:
        InputError: wrong type or out of range; the message names the option and range.
    """
    ok_type = isinstance(value, (int, np.integer)) if integer else isinstance(
        value, (int, float, np.integer, np.floating))
    ok = ok_type and not isinstance(value, bool) and not math.isnan(value)
    if ok:
        ok = ((value > low if low_open else value >= low)
              and (value < high if high_open else value <= high))
    if not ok:
        kind = "an integer" if integer else "a number"
        if math.isinf(high):
            span = f"{'>' if low_open else '>='} {low:g}"
        else:
            span = f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
        raise InputError(f"option {name}={value!r} must be {kind} {span}")


def check_flag(name: str, value: Any) -> None:
    """Refuse an option that must be True or False.

    Raises:
        InputError: the message names the option and the value given.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"option {name}={value!r} must be True or False")


def check_tol(tol: Any) -> float:
    """``tol`` as a float: a finite positive number [m, rad] (numpy scalars included).

    Raises:
        InputError: not a number, not finite, or not positive.
    """
    ok = isinstance(tol, numbers.Real) and not isinstance(tol, (bool, np.bool_))
    if not (ok and math.isfinite(tol) and tol > 0):
        raise InputError(f"tol must be a positive number [m, rad]; got {tol!r}")
    return float(tol)


def check_seed(seed: Any) -> int | None:
    """``seed`` as given, if ``None`` or a non-negative integer (numpy's seeds).

    Raises:
        InputError: anything else.
    """
    ok = seed is None or (isinstance(seed, (int, np.integer))
                          and not isinstance(seed, (bool, np.bool_)) and seed >= 0)
    if not ok:
        raise InputError(f"seed must be a non-negative integer or None; got {seed!r}")
    return seed


class LazyGenerator:
    """A ``numpy.random.Generator`` for ``seed``, created at its first use.

    Seeding costs ~10–20 µs, as much as a fast solve; solvers that converge from their
    first start never draw. Same seed, same numbers: the draws are those of
    ``np.random.default_rng(seed)``.
    """

    __slots__ = ("_rng", "_seed")

    def __init__(self, seed: int | None) -> None:
        self._seed = seed
        self._rng: np.random.Generator | None = None

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        if self._rng is None:
            self._rng = np.random.default_rng(self._seed)
        return getattr(self._rng, name)


class Solver(ABC):
    """Base of every IK solver.

    Subclasses set ``name``, ``defaults`` (every accepted option with its default) and
    ``certifies_unreachable`` (True for exact solvers whose failure proves unreachability),
    and implement :meth:`_solve`.
    """

    name: ClassVar[str] = ""
    defaults: ClassVar[dict[str, Any]] = {}
    certifies_unreachable: ClassVar[bool] = False

    def __init__(self, **options: Any) -> None:
        unknown = set(options) - set(self.defaults)
        if unknown:
            raise SolverOptionError(self.name, unknown, self.defaults)
        self.options: dict[str, Any] = {**self.defaults, **options}
        self.check_options()

    def check_options(self) -> None:
        """Validate the option values (override; called at construction).

        Raises:
            InputError: an option value of the wrong type or outside its range.
        """
        return None  # a solver without numeric options accepts any value

    def solve(self, robot: Robot, target: Target | object, q0: object | None = None,
              seed: int | None = 0, tol: float = 1e-9) -> IKResult:
        """Solve IK for ``target``.

        Args:
            robot: the robot.
            target: a :class:`Target` or a bare (3,) position [m].
            q0: (nq,) start / preferred configuration within the limits, or ``None``.
            seed: seed of the solver's ``numpy.random.Generator`` (same seed, same result).
            tol: residual [m and rad] below which the target counts as reached.

        Raises:
            TargetError: malformed target, or a yaw for a robot whose tool cannot turn.
            InputError: malformed ``q0``, ``tol`` or ``seed``.
            JointLimitError: ``q0`` outside the joint limits.
        """
        if not isinstance(robot, Robot):
            raise InputError(f"robot must be a scara_opt.Robot (so.load_robot(name) or "
                             f"Robot.from_urdf(path)); got {type(robot).__name__}")
        target = as_target(target)
        check_task(robot, target)
        q0a = check_q0(robot, q0)
        tol = check_tol(tol)
        check_seed(seed)
        rng = cast(np.random.Generator, LazyGenerator(seed))
        start = time.perf_counter()
        out = self._solve(robot, target, q0a, rng, tol)
        elapsed = time.perf_counter() - start
        return make_result(robot, target, out, tol=tol, method=self.name, seed=seed,
                           time_s=elapsed, certified=self.certifies_unreachable)

    @abstractmethod
    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        """Search for ``q``; never raise for an unreachable target (return the best found)."""
