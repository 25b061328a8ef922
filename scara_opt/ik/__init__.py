"""Inverse kinematics: one registry, one result type, exact and metaheuristic solvers.

Every solver subclasses :class:`~scara_opt.ik.base.Solver` and is registered under a short
name; :func:`solve_ik` dispatches by name and always returns an :class:`IKResult` whose
residual and status come from :mod:`scara_opt.ik.verdict` (``unreachable`` only with a
certificate, :mod:`scara_opt.ik.certificates`). The exact solvers live here: ``ipopt``
(casadi NLP, the deterministic reference), ``lm`` (fast Levenberg–Marquardt), ``auto``
(the default) and ``analytic`` (the closed form, :mod:`~scara_opt.ik.closed_form`).

Layers (imports point down only): ``result``, ``task``, ``problem``, ``geometry`` →
``closed_form`` → ``certificates`` → ``verdict`` → ``base`` → ``registry`` → the solvers.
"""

from scara_opt.ik import analytic, auto, ipopt, lm  # noqa: F401  (registers the solvers)
from scara_opt.ik.analytic import ik_all
from scara_opt.ik.base import Solver, SolverOutput
from scara_opt.ik.registry import (
    get_solver,
    method_label,
    register_solver,
    solve_ik,
    solvers,
)
from scara_opt.ik.result import Certificate, IKResult, Reason, Status

__all__ = [
    "Certificate",
    "IKResult",
    "Reason",
    "Solver",
    "SolverOutput",
    "Status",
    "get_solver",
    "ik_all",
    "method_label",
    "register_solver",
    "solve_ik",
    "solvers",
]
