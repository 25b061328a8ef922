"""Inverse kinematics: one registry, one result type, exact and metaheuristic solvers.

Every solver subclasses :class:`~scara_opt.ik.base.Solver` and is registered under a short
name; :func:`solve_ik` dispatches by name and always returns an :class:`IKResult` whose
residual was recomputed by the base from the robot's FK. The exact solvers live here:
``ipopt`` (casadi NLP, the deterministic reference) and ``analytic`` (closed-form SCARA).
"""

from scara_opt.ik import analytic, auto, ipopt, lm  # noqa: F401  (registers the solvers)
from scara_opt.ik.analytic import ik_all
from scara_opt.ik.base import Solver, SolverOutput
from scara_opt.ik.registry import get_solver, register_solver, solve_ik, solvers
from scara_opt.ik.result import IKResult, Status

__all__ = [
    "IKResult",
    "Solver",
    "SolverOutput",
    "Status",
    "get_solver",
    "ik_all",
    "register_solver",
    "solve_ik",
    "solvers",
]
