"""One registry of IK solvers: ``solve_ik(robot, target, method=...)`` looks the name up."""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable
from typing import Any, TypeVar

from numpy.typing import ArrayLike

from scara_opt.errors import InputError, UnknownSolverError
from scara_opt.ik.base import Solver
from scara_opt.ik.result import IKResult
from scara_opt.model.robot import Robot
from scara_opt.target import Target

_REGISTRY: dict[str, Callable[..., Solver]] = {}

#: modules whose import registers the built-in solvers beyond scara_opt.ik's own: a table
#: the registry reads at its first lookup (imported by name), so the package's import stays
#: light and no backend is imported by the registry at module level
BUILTIN_MODULES = ("scara_opt.metaheuristics",)
_LOAD_LOCK = threading.RLock()
_LOAD_STATE = {"loading": False, "loaded": False}


def _registry() -> dict[str, Callable[..., Solver]]:
    """The registered solvers, with the built-in ones of :data:`BUILTIN_MODULES` loaded."""
    if not _LOAD_STATE["loaded"]:
        with _LOAD_LOCK:  # re-entrant: a module being loaded may itself look a solver up
            if not _LOAD_STATE["loading"]:
                _LOAD_STATE["loading"] = True
                for module in BUILTIN_MODULES:
                    importlib.import_module(module)
                _LOAD_STATE["loaded"] = True
    return _REGISTRY


F = TypeVar("F", bound=Callable[..., Solver])


def register_solver(name: str, factory: F | None = None, *, replace: bool = False) -> Any:
    """Register a solver factory (a :class:`Solver` subclass or a callable returning one).

    Usable directly, ``register_solver("mine", MySolver)``, or as a class decorator,
    ``@register_solver("mine")``.

    Raises:
        InputError: the name is empty, not lowercase, or taken (unless ``replace=True``).
    """
    if not isinstance(name, str) or not name or name != name.lower() \
            or not name.replace("_", "").isalnum():
        raise InputError(f"solver name must be a short lowercase tag like 'pso'; got {name!r}")

    def add(f: F) -> F:
        if name in _REGISTRY and not replace:
            raise InputError(f"a solver named {name!r} is already registered; pick another name "
                             "or pass replace=True")
        _REGISTRY[name] = f
        return f

    return add if factory is None else add(factory)


def solvers() -> list[str]:
    """Names of the registered IK solvers, sorted."""
    return sorted(_registry())


def method_label(name: str) -> str:
    """The display label of the solver registered as ``name``, e.g. ``"gha"`` → ``"G-HA"``.

    The solver class's ``label`` (the paper's name, e.g. ``"ACO (ACO_R)"``), or
    ``name.upper()`` for a solver without one.

    Raises:
        UnknownSolverError: ``name`` is not registered (the message lists the names).
    """
    registry = _registry()
    if name not in registry:
        raise UnknownSolverError(name, registry)
    return getattr(registry[name], "label", "") or name.upper()


def get_solver(method: str, **options: Any) -> Solver:
    """An instance of the solver registered as ``method`` with its ``options``.

    Raises:
        InputError: ``method`` is not a str (e.g. a list of names).
        UnknownSolverError: ``method`` is not registered (the message lists the names).
        SolverOptionError: an option the solver does not accept.
    """
    if not isinstance(method, str):
        raise InputError(f"method must be one solver name (a str) from {solvers()}; got "
                         f"{method!r} ({type(method).__name__}); to run several, use "
                         "so.compare(robot, targets, methods=[...])")
    registry = _REGISTRY if _LOAD_STATE["loaded"] else _registry()
    if method not in registry:
        raise UnknownSolverError(method, registry)
    return registry[method](**options)


def solve_ik(robot: Robot, target: Target | ArrayLike, method: str = "auto",
             q0: ArrayLike | None = None, seed: int | None = 0, tol: float = 1e-9,
             **options: Any) -> IKResult:
    """Solve inverse kinematics with any registered method.

    Args:
        robot: the robot.
        target: a :class:`Target` or a (3,) position [m].
        method: a name from :func:`solvers`. The default ``"auto"`` runs the fast
            Levenberg–Marquardt solver (``"lm"``) seeded by the closed form where it applies
            and falls back to IPOPT's multi-start before it reports ``"unreachable"``;
            ``"ipopt"`` is the deterministic reference, ``"analytic"`` the closed form,
            ``"pso"``, ``"gwo"``, … the metaheuristics.
        q0: (nq,) start / preferred configuration within the limits, or ``None``.
        seed: seed of the solver's random generator.
        tol: residual [m and rad] below which the status is ``"solved"``.
        **options: solver-specific options (an unknown one raises SolverOptionError).

    Returns:
        IKResult: the same result type for every method.
    """
    return get_solver(method, **options).solve(robot, target, q0=q0, seed=seed, tol=tol)
