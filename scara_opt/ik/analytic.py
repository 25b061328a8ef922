"""The closed form as a solver (``method="analytic"``) and :func:`ik_all`, every solution.

The mathematics lives in :mod:`scara_opt.ik.geometry` (the SCARA structure read from the
FK), :mod:`scara_opt.ik.closed_form` (every branch, over the whole range of the
redundant joints) and, for 6R and 7R arms, :mod:`scara_opt.ik.arm_route`; this module
wraps the SCARA closed form in the solver interface and lists every solution of any robot.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from scara_opt.ik.arm_route import SAMPLES, every_solution, served
from scara_opt.ik.base import (
    MAX_RESTARTS,
    Solver,
    SolverOutput,
    check_number,
    check_q0,
    check_seed,
    check_tol,
    default_q0,
)
from scara_opt.ik.closed_form import solve_all
from scara_opt.ik.geometry import (  # noqa: F401  (re-exported: the closed form's names)
    NotScaraError,
    ScaraGeometry,
    applies,
    check_fixed,
    held_values,
    scara_geometry,
    solve_batch,
)
from scara_opt.ik.ipopt import IpoptSolver
from scara_opt.ik.registry import register_solver
from scara_opt.ik.result import IKResult
from scara_opt.ik.task import check_task
from scara_opt.ik.verdict import judge
from scara_opt.model.robot import Array, Robot, check_robot
from scara_opt.target import Target, as_target

#: the route of a SCARA-type robot's results
SCARA_ROUTE = "analytic (SCARA closed form)"


def ik_all(robot: Robot, target: Target | ArrayLike, q0: ArrayLike | None = None, tol: float = 1e-9,
           fixed: dict[str, float] | None = None, samples: int = SAMPLES,
           seed: int | None = 0) -> list[IKResult]:
    """Every IK solution within the limits, nearest to ``q0`` first, its route named.

    Each result's :attr:`~scara_opt.IKResult.route` says how the solutions were found:

    * SCARA-type robots (position or yaw targets): the closed form's branches, both elbows
      and every turn of each revolute joint that fits its limits (a ±360° wrist gives
      two). Redundant joints are not enumerated (they have a continuum of values): those
      named in ``fixed`` keep that value; the others keep ``q0``'s value (or the default
      start's) when some branch exists there, else they take the nearest values at which
      one does (see :mod:`scara_opt.ik.closed_form`).
    * 6R arms of the cases of :mod:`~scara_opt.ik.arm_geometry` (UR-type, spherical
      wrists, either way round), full-pose targets: every branch of the closed form and
      every whole turn of each joint within the limits (:mod:`~scara_opt.ik.arm_route`);
      7R arms whose first or last joint held leaves such a 6R: that joint held at its
      ``fixed`` value, else sampled at ``samples`` values evenly over its range (the route
      says which).
    * Any other robot or target: the distinct solutions a seeded multi-start of the fast
      solver reaches (``"multi-start"``): not necessarily all.

    Args:
        robot: the robot.
        target: a :class:`Target` or a (3,) position [m].
        q0: (nq,) reference for sorting, held joints and the wrist of position-only targets.
        tol: residual [m, rad] each solution is checked against (>= the tol floor).
        fixed: values of redundant joints by name (e.g. ``{"P1": 0.02}``), never moved.
        samples: values of a 7R arm's sampled joint (>= 1).
        seed: seed of the multi-start's starts.

    Returns:
        One :class:`IKResult` per solution, each ``solved``; an empty list when none is
        found (with the ``fixed`` joints held).

    Raises:
        TargetError: a malformed target, or a rotation target for a SCARA-type robot.
        InputError: a malformed ``q0``, ``tol``, ``fixed``, ``samples`` or ``seed``.
    """
    robot = check_robot(robot)
    target = as_target(target)
    check_task(robot, target)
    tol = check_tol(tol)
    check_seed(seed)
    check_number("samples", samples, 1, MAX_RESTARTS, integer=True)
    q_ref = check_q0(robot, q0)
    q_ref = default_q0(robot) if q_ref is None else q_ref
    if applies(robot):
        sols, route = solve_all(robot, target, q_ref, fixed), SCARA_ROUTE
    else:
        check_fixed(fixed)
        sols, route = every_solution(robot, served(robot, target), target, q_ref, tol, fixed,
                                     int(samples), seed)
    results = []
    for q in sols:
        res = judge(robot, target, SolverOutput(q=q, evaluations=1, route=route), tol=tol,
                    method="analytic", seed=None, time_s=0.0)
        if res.success:
            results.append(res)
    results.sort(key=lambda r: float(np.linalg.norm(r.q - q_ref)))
    return results


@register_solver("analytic")
class AnalyticSolver(Solver):
    """Closed-form SCARA IK: the branch nearest to ``q0`` (see :func:`ik_all`).

    Options:
        fixed: values of the redundant joints by name [rad or m], never moved (default:
            none; the redundant joints then start at ``q0``'s values and move, over their
            whole range, only when no branch exists there).

    On a miss, ``q`` comes from IPOPT's least-squares solve (the ``fixed`` joints held):
    the closest configuration found. The verdict then certifies ``unreachable`` (the
    closed form over the whole range found nothing), or reports ``failed`` with reason
    ``held_joints`` when only the ``fixed`` values make it infeasible.
    """

    name = "analytic"
    label = "closed form"
    defaults: ClassVar[dict[str, Any]] = {"fixed": None}

    def check_options(self) -> None:
        """``fixed`` is None or a mapping of joint names to values (checked per robot later)."""
        check_fixed(self.options["fixed"])

    def prepare(self, robot: Robot, kind: str) -> None:
        """Read the robot's SCARA geometry once (IPOPT's NLPs are built at a first miss)."""
        scara_geometry(robot)

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        q_ref = default_q0(robot) if q0 is None else q0
        fixed = self.options["fixed"]
        sols = solve_all(robot, target, q_ref, fixed)
        if sols:
            best = min(sols, key=lambda q: float(np.linalg.norm(q - q_ref)))
            return SolverOutput(q=best, iterations=0, evaluations=1)
        geom = scara_geometry(robot)
        values = held_values(robot, geom, q_ref, fixed)
        held = {robot.joint_names.index(name): float(values[robot.joint_names.index(name)])
                for name in (fixed or {})}
        ipopt = IpoptSolver()
        setup = ipopt.timed_prepare(robot, target.kind)
        closest = ipopt._solve(robot, target, q_ref, rng, tol, held=held)
        names = ", ".join(f"{robot.joint_names[k]} = {v:.4g}" for k, v in held.items())
        infeasible_held = bool(held) and bool(solve_all(robot, target, q_ref))
        return SolverOutput(q=closest.q, iterations=closest.iterations,
                            evaluations=closest.evaluations, held=infeasible_held, setup_s=setup,
                            message="no closed-form branch within the limits"
                                    + (f" with {names} held" if held else "")
                                    + "; q from IPOPT's closest configuration")
