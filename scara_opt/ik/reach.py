"""Is a target inside the workspace? Decided by the exact solvers, for the others' verdicts."""

from __future__ import annotations

from scara_opt.robot import Robot
from scara_opt.target import Target


def is_reachable(robot: Robot, target: Target, tol: float = 1e-9) -> bool:
    """True when an exact solver reaches ``target`` within ``tol``.

    The closed form decides for SCARA-type robots; otherwise IPOPT with its seeded
    multi-start does (its failure to find a solution counts as unreachable).
    """
    from scara_opt.ik.analytic import analytic_reachable
    from scara_opt.ik.ipopt import IpoptSolver

    verdict = analytic_reachable(robot, target, tol)
    if verdict is not None:
        return verdict
    return IpoptSolver().solve(robot, target, seed=0, tol=tol).success
