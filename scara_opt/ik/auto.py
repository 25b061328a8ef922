"""The default route: Levenberg–Marquardt first, closed-form starts, then IPOPT's multi-start.

``method="auto"`` tries, in order, until a start reaches the target:

0. on a 6R or 7R arm whose closed form :mod:`~scara_opt.ik.arm_route` serves, for a full
   pose: the closed-form solution nearest ``q0`` (every branch and turn within the
   limits; a 7R arm's held joint at ``q0``'s value, then slid to the solution nearest
   ``q0``), the route named in :attr:`~scara_opt.IKResult.route`;
1. the fast solver (:mod:`scara_opt.ik.lm`) from ``q0`` (or the default start): the
   solution nearest to ``q0`` on the branch reached from it, the rule of IPOPT;
2. for SCARA-type robots (position or yaw targets), the fast solver from each
   closed-form branch (:func:`scara_opt.ik.analytic.solve_all`), nearest to ``q0`` first:
   each is already a solution, polished and slid toward ``q0`` in a few iterations;
3. ``restarts`` seeded random starts of the fast solver;
4. IPOPT's multi-start (:class:`~scara_opt.ik.ipopt.IpoptSolver`, ``ipopt_restarts``);
   ``q`` is then the closer of the two solvers' answers, judged by the verdict
   (:mod:`scara_opt.ik.verdict`: ``unreachable`` only with a certificate).

**Complete where IPOPT is.** Step 4 is the ``ipopt`` method's own run: the same options
(``ipopt_restarts`` defaults to its ``restarts``), ``q0`` and a generator seeded anew with
the caller's ``seed`` (the draws of steps 1–3 do not shift its starts). So whenever
``solve_ik(..., method="ipopt", seed=s)`` reaches a target, ``method="auto"`` with the same
``seed`` and ``q0`` does too: its answer is at least as close.

On reachable targets step 1 decides almost always (see ``benchmarks/bench_ik_peers.py``),
so the cost is that of the fast solver; IPOPT runs only for the rare misses and for
targets out of reach.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from itertools import chain
from typing import Any, ClassVar

import numpy as np

from scara_opt.ik.arm_route import solve_nearest
from scara_opt.ik.base import (
    MAX_RESTARTS,
    LazyGenerator,
    Solver,
    SolverOutput,
    check_flag,
    check_number,
)
from scara_opt.ik.closed_form import solve_all
from scara_opt.ik.geometry import NotScaraError
from scara_opt.ik.ipopt import IpoptSolver
from scara_opt.ik.lm import LevenbergMarquardtSolver
from scara_opt.ik.lm_functions import limits
from scara_opt.ik.lm_search import Search, check_budget, lm_search, random_starts, search_output
from scara_opt.ik.registry import register_solver
from scara_opt.ik.task import config_errors, error_from
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target


def closed_form_starts(robot: Robot, target: Target, q_ref: Array) -> Iterator[Array]:
    """Closed-form branches within the limits, nearest to ``q_ref`` first (lazily).

    A full rotation on a robot whose tool only turns about one axis starts from the
    branches of its yaw (:func:`as_yaw`). Nothing for robots that are not SCARA-type.
    """
    if target.rotation is not None:
        yaw_target = as_yaw(robot, target)
        if yaw_target is None:
            return
        target = yaw_target
    try:
        branches = solve_all(robot, target, q_ref)
    except NotScaraError:
        return
    yield from sorted(branches, key=lambda q: float(np.linalg.norm(q - q_ref)))


def as_yaw(robot: Robot, target: Target) -> Target | None:
    """The yaw target of a full rotation, for a robot whose revolute axes are all parallel.

    The yaw of ``target.rotation``'s x axis about :attr:`~scara_opt.Robot.yaw_axis`: the
    same target where the rotation does not tilt that axis (else a start, not a solution).
    ``None`` without a yaw axis or a rotation, or where the x axis lies along it.
    """
    if robot.yaw_axis is None or target.rotation is None:
        return None
    e1, e2 = robot.yaw_basis()
    x = target.rotation[:, 0]
    u, v = float(x @ e1), float(x @ e2)
    if math.hypot(u, v) < 1e-6:
        return None
    return Target(target.position, yaw=math.atan2(v, u), weights=target.weights)


@register_solver("auto")
class AutoSolver(Solver):
    """Fast exact IK, IPOPT as the last resort (see the module docstring for the order).

    Options:
        restarts: random starts of the fast solver after ``q0`` and the closed-form
            branches (default 50: a start costs ~0.1 ms; hard poses near joint limits of a
            7-joint arm took up to 40).
        max_iter: fast-solver iterations per start (default 100).
        ipopt_restarts: IPOPT's further random starts when the fast solver misses
            (default: the ``ipopt`` method's ``restarts``, 50, so that ``auto`` reaches
            every target ``ipopt`` reaches with the same seed).
        jit: the fast solver's iterations compiled to C, cached per machine (default True;
            see :class:`~scara_opt.ik.lm.LevenbergMarquardtSolver`).
        analytic: a 6R or 7R arm's closed form first, for full poses (default True; see
            :class:`~scara_opt.ik.lm.LevenbergMarquardtSolver`).
    """

    name = "auto"
    label = "auto (LM + IPOPT)"
    defaults: ClassVar[dict[str, Any]] = {
        "restarts": 50, "max_iter": 100, "jit": True, "analytic": True,
        "ipopt_restarts": IpoptSolver.defaults["restarts"]}

    def check_options(self) -> None:
        """restarts, ipopt_restarts >= 0 and max_iter >= 1 (integers); jit, analytic bools."""
        check_budget(self.options)
        check_flag("analytic", self.options["analytic"])
        check_number("ipopt_restarts", self.options["ipopt_restarts"], 0, MAX_RESTARTS,
                     integer=True)

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        opts = self.options
        box, q_default = limits(robot)
        q_ref = q_default if q0 is None else q0
        if opts["analytic"] and target.rotation is not None:  # a 6R/7R arm's closed form
            out = solve_nearest(robot, target, q_ref, tol, bool(opts["jit"]))
            if out is not None:
                return out
        starts = chain([q_ref], closed_form_starts(robot, target, q_ref),
                       random_starts(robot, rng, int(opts["restarts"])))
        found = lm_search(robot, target, q_ref, starts, tol=tol, max_iter=int(opts["max_iter"]),
                          jit=bool(opts["jit"]), box=box)
        if found.converged or (found.within and _error(robot, target, found.q) <= tol):
            return search_output(found)  # within tol: judged by the FK, as the base will
        return self._fallback(robot, target, q0, rng, tol, found)

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build (or load) the fast solver's iterations of this task kind.

        IPOPT's NLPs are built only when a target first needs them (their build time is
        then reported as setup, not search time).
        """
        LevenbergMarquardtSolver(jit=self.options["jit"],
                                 analytic=self.options["analytic"]).prepare(robot, kind)

    def _fallback(self, robot: Robot, target: Target, q0: Array | None,
                 rng: np.random.Generator, tol: float, found: Search) -> SolverOutput:
        """IPOPT's multi-start after the fast solver missed; the closer answer is kept.

        The ``ipopt`` method's run with this call's seed (a generator seeded anew: see the
        module docstring), not the draws left over from the fast solver's starts.
        """
        ipopt = IpoptSolver(restarts=int(self.options["ipopt_restarts"]))
        setup = ipopt.timed_prepare(robot, target.kind)
        fresh = rng.fresh() if isinstance(rng, LazyGenerator) else rng
        out = ipopt._solve(robot, target, q0, fresh, tol)  # the template's hook: no re-judging
        fast = search_output(found)
        closer = out if _error(robot, target, out.q) <= _error(robot, target, found.q) else fast
        message = f"fast solver missed from {found.starts} starts"
        if out.message:
            message += f"; then {out.message}"
        return SolverOutput(q=closer.q, iterations=fast.iterations + out.iterations,
                            evaluations=fast.evaluations + out.evaluations,
                            history=np.concatenate([fast.history, out.history]),
                            message=message, setup_s=setup)


def _error(robot: Robot, target: Target, q: Array) -> float:
    """The honest residual of ``q`` [m, rad], as the base will judge it."""
    return error_from(*config_errors(robot, target, np.clip(q, robot.lower, robot.upper)))
