"""Display names of the IK methods: the paper's name where the registry tag is terse."""

from __future__ import annotations

from scara_opt.ik.registry import get_solver


def method_label(name: str) -> str:
    """The display label of the solver registered as ``name``, e.g. ``"gha"`` → ``"G-HA"``.

    The solver class's ``label`` (every metaheuristic has one, e.g. ``"ACO (ACO_R)"``), or
    ``name.upper()`` for a solver without one (``"ipopt"`` → ``"IPOPT"``).

    Args:
        name: a registered solver name (see :func:`scara_opt.solvers`).

    Raises:
        UnknownSolverError: ``name`` is not registered (the message lists the names).
    """
    return getattr(get_solver(name), "label", "") or name.upper()
