"""The solver contract (template method): the base checks, seeds and times; the verdict judges.

The base checks input, seeds, builds the solver's one-off pieces (:meth:`Solver.prepare`,
timed apart as ``setup_s``), times the search and hands the answer to
:func:`scara_opt.ik.verdict.judge`; a subclass implements :meth:`Solver._solve` (and, if it
builds something once, :meth:`Solver.prepare`).

Where ``q0`` is given, the answer is first turned to the whole turn of each revolute joint
nearest ``q0`` (:func:`scara_opt.ik.turns.nearest_turn`: the same pose, no joint wound
round where it need not be), for every method alike.

Every solver's answer is judged by the verdict, the same way: the final ``q`` goes through
the robot's FK, the residual is recomputed, ``solved`` is granted only within ``tol`` and
``unreachable`` only with a certificate (see :mod:`scara_opt.ik.verdict`).
"""

from __future__ import annotations

import math
import numbers
import sys
import time
from abc import ABC, abstractmethod
from dataclasses import replace
from typing import Any, ClassVar, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import short_repr
from scara_opt.errors import InputError, JointLimitError, SolverOptionError
from scara_opt.ik.result import IKResult, SolverOutput
from scara_opt.ik.task import LIMIT_SLACK, check_task, default_q0
from scara_opt.ik.turns import nearest_turn
from scara_opt.ik.verdict import judge
from scara_opt.model.robot import Robot
from scara_opt.target import Target, as_target

Array = NDArray[np.float64]

#: the smallest tol [m, rad] a residual can be certified against: round-off of the FK of a
#: metre-scale arm is ~1e-16 m, so a tol below this floor could refuse an exact solution
TOL_FLOOR = 1e-15
#: the largest tol [m, rad]: above it any configuration of a metre-scale arm is "solved"
TOL_CEILING = 1.0
#: the most restarts and iterations per start an exact solver takes (a budget above them
#: would not return in any useful time: 10,000 IPOPT starts already take tens of seconds)
MAX_RESTARTS, MAX_ITER = 10_000, 100_000
#: ints up to this size are exact as floats (beyond ~1.8e308, ``math.isnan`` overflows)
_EXACT_INT = 2**53

__all__ = ["LIMIT_SLACK", "MAX_ITER", "MAX_RESTARTS", "TOL_CEILING", "TOL_FLOOR",
           "LazyGenerator", "Solver", "SolverOutput", "check_flag", "check_number",
           "check_q0", "check_seed", "check_tol", "default_q0"]


def check_q0(robot: Robot, q0: ArrayLike | None) -> Array | None:
    """``q0`` as an in-limit (nq,) array, or ``None``.

    Raises:
        InputError: wrong shape or non-finite values.
        JointLimitError: a joint outside its limits (names it, its value and range).
    """
    if q0 is None:
        return None
    if robot.fits_limits(q0):  # the common case, a float (nq,) array within the limits:
        return q0  # check_q would hand back the same object
    return _check_q0_full(robot, q0)


def _check_q0_full(robot: Robot, q0: ArrayLike) -> Array:
    """:func:`check_q0` of a ``q0`` that is not None, without its fast path."""
    q = robot.check_q(q0, "q0")
    lower, upper = robot.lower, robot.upper
    if ((q >= lower) & (q <= upper)).all():  # the array method: np.all costs ~2 µs a call
        return q
    for name, kind, v, lo, hi in zip(robot.joint_names, robot.joint_types, q, lower, upper,
                                     strict=True):
        if not lo - LIMIT_SLACK <= v <= hi + LIMIT_SLACK:
            unit = "rad" if kind == "revolute" else "m"
            raise JointLimitError(
                f"q0: joint {name!r} = {v:.4g} {unit} is outside [{lo:.4g}, {hi:.4g}] {unit}; "
                "pass q0 inside the limits or q0=None", joint=name)
    return np.clip(q, lower, upper)


def check_number(name: str, value: Any, low: float, high: float = math.inf, *,
                 integer: bool = False, low_open: bool = False, high_open: bool = False) -> None:
    """Refuse an option value outside ``[low, high]`` (ends opened by ``*_open``).

    Bools and NaN are refused too.

    Raises:
        InputError: wrong type or out of range; the message names the option and range.
    """
    t = type(value)  # a plain int (exact as a float) or float in range: ~0.2 µs less per check
    if (t is int and -_EXACT_INT <= value <= _EXACT_INT) or (t is float and not integer):
        if ((value > low if low_open else value >= low)  # NaN fails: the full check says why
                and (value < high if high_open else value <= high)):
            return
    _check_number_full(name, value, low, high, integer=integer, low_open=low_open,
                       high_open=high_open)


def _check_number_full(name: str, value: Any, low: float, high: float, *, integer: bool,
                       low_open: bool, high_open: bool) -> None:
    """:func:`check_number` without its fast path for plain ints and floats in range."""
    ok_type = isinstance(value, (int, np.integer)) if integer else isinstance(
        value, (int, float, np.integer, np.floating))
    # an int compares exactly with the float bounds, at any size (math.isnan(10**400) would
    # raise OverflowError)
    ok = ok_type and not isinstance(value, bool) and not (
        isinstance(value, (float, np.floating)) and math.isnan(value))
    if ok and not integer and isinstance(value, int) and abs(value) > sys.float_info.max:
        ok = False  # an int no float holds (a float option is used as a float)
    if ok:
        ok = ((value > low if low_open else value >= low)
              and (value < high if high_open else value <= high))
    if not ok:
        kind = "an integer" if integer else "a number"
        if math.isinf(high):
            span = f"{'>' if low_open else '>='} {low:g}"
        else:
            span = f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
        raise InputError(f"option {name}={short_repr(value)} must be {kind} {span}")


def check_flag(name: str, value: Any) -> None:
    """Refuse an option that must be True or False.

    Raises:
        InputError: the message names the option and the value given.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"option {name}={short_repr(value)} must be True or False")


def check_tol(tol: Any) -> float:
    """``tol`` as a float in [:data:`TOL_FLOOR`, :data:`TOL_CEILING`] [m, rad] (numpy too).

    Raises:
        InputError: not a number, not finite, or below the floor (the message says why).
    """
    if type(tol) is float and TOL_FLOOR <= tol <= TOL_CEILING:  # the common case, ~0.4 µs less
        return tol
    ok = isinstance(tol, numbers.Real) and not isinstance(tol, (bool, np.bool_))
    # an int is finite at any size, and compares exactly (math.isfinite(10**400) overflows)
    if not (ok and (isinstance(tol, numbers.Integral) or math.isfinite(tol)) and tol > 0):
        raise InputError(f"tol must be a positive number [m, rad]; got {short_repr(tol)}")
    if tol < TOL_FLOOR:
        raise InputError(f"tol={tol:g} is below {TOL_FLOOR:g} [m, rad], the round-off of the "
                         "forward kinematics: an exact solution could not be told from a miss; "
                         f"pass tol >= {TOL_FLOOR:g}")
    if tol > TOL_CEILING:
        raise InputError(f"tol={short_repr(tol)} is above {TOL_CEILING:g} [m, rad]: every "
                         f"configuration of a metre-scale arm would count as solved; pass "
                         f"tol <= {TOL_CEILING:g}")
    return float(tol)


def check_seed(seed: Any) -> int | None:
    """``seed`` as given, if ``None`` or a non-negative integer (numpy's seeds).

    Raises:
        InputError: anything else.
    """
    if seed is None or (type(seed) is int and seed >= 0):  # the common cases
        return seed
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

    def generator(self) -> np.random.Generator:
        """The generator itself, created now if not yet.

        For loops that draw at every step: going through this proxy costs ~0.5 µs a draw.
        """
        if self._rng is None:
            self._rng = np.random.default_rng(self._seed)
        return self._rng

    def fresh(self) -> np.random.Generator:
        """A new generator for the same seed, at its first draw (as a new solve has)."""
        return cast(np.random.Generator, LazyGenerator(self._seed))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        if self._rng is None:
            self._rng = np.random.default_rng(self._seed)
        return getattr(self._rng, name)


class Solver(ABC):
    """Base of every IK solver.

    Subclasses set ``name``, ``defaults`` (every accepted option with its default) and
    optionally ``label`` (the name tables and figures show), and implement :meth:`_solve`.
    """

    name: ClassVar[str] = ""
    label: ClassVar[str] = ""
    defaults: ClassVar[dict[str, Any]] = {}

    def __init__(self, **options: Any) -> None:
        if options and not options.keys() <= self.defaults.keys():
            raise SolverOptionError(self.name, set(options) - set(self.defaults), self.defaults)
        self.options: dict[str, Any] = {**self.defaults, **options}
        self.check_options()

    def check_options(self) -> None:
        """Validate the option values (override; called at construction).

        Raises:
            InputError: an option value of the wrong type or outside its range.
        """
        return None  # a solver without numeric options accepts any value

    def solve(self, robot: Robot, target: Target | ArrayLike, q0: ArrayLike | None = None,
              seed: int | None = 0, tol: float = 1e-9) -> IKResult:
        """Solve IK for ``target``.

        Args:
            robot: the robot.
            target: a :class:`Target` or a bare (3,) position [m].
            q0: (nq,) start / preferred configuration within the limits, or ``None``; of
                the answers equal up to whole turns of the revolute joints, the one
                nearest ``q0`` is returned.
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
        setup = self.timed_prepare(robot, target.kind)
        start = time.perf_counter()
        out = self._solve(robot, target, q0a, rng, tol)
        if q0a is not None and not out.turned:  # of the equivalent turns, the nearest q0
            turned = nearest_turn(robot, out.q, q0a)
            if turned is not out.q:
                out = replace(out, q=turned)
        elapsed = time.perf_counter() - start - out.setup_s
        return judge(robot, target, out, tol=tol, method=self.name, seed=seed, time_s=elapsed,
                     setup_s=setup + out.setup_s,
                     search=lambda: self.witness(robot, target, q0a, seed, tol))

    def timed_prepare(self, robot: Robot, kind: str) -> float:
        """:meth:`prepare`, and the time it took [s]: the setup, apart from the search."""
        start = time.perf_counter()
        self.prepare(robot, kind)
        return time.perf_counter() - start

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build what the solver builds once per robot and task kind (cached on the robot).

        Called before the timed search, so ``time_s`` never includes it (``setup_s`` does).
        The default builds nothing.
        """
        return None

    def witness(self, robot: Robot, target: Target, q0: Array | None, seed: int | None,
                tol: float) -> Array | None:
        """A configuration reaching a target this solver missed, or ``None``.

        The verdict asks for one (after the closed form) before it reports a miss as
        ``max_iter`` rather than ``failed``. The exact solvers return ``None`` (their own
        search was the search); the metaheuristics run the exact ``auto`` method with the
        caller's ``seed`` and ``q0``.
        """
        return None

    @abstractmethod
    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        """Search for ``q``; never raise for an unreachable target (return the best found)."""
