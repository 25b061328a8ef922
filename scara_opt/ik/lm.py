r"""Fast exact IK: bounded Levenberg–Marquardt in casadi, on the IPOPT reference's problem.

The problem is the one of :mod:`scara_opt.ik.ipopt` with a vanishing regulariser, which
is what IPOPT and its polish aim at: the weighted task residual :math:`r(q)` (the
position error; plus the NLP's rotation-matrix error, or for a yaw the wrapped angle,
which vanishes where the NLP's chord does) driven to round-off within the joint bounds,
and among the configurations that reach the target the one nearest to ``q0`` in
range-scaled joint coordinates, locally (on the branch reached from the start).

Each start runs three phases, in range-scaled coordinates :math:`u = q / s` (``s``: the
joint ranges), over the joints that a bound does not hold:

1. **Levenberg–Marquardt** on :math:`\tfrac12\|r\|^2`: :math:`Δu = -J^+_μ r`,
   :math:`J^+_μ = J^T (J J^T + μ I)^{-1}` (minimum norm: the redundant joints stay put),
   :math:`μ = λ \|r\|^2` (Yamashita and Fukushima, 2001: quadratic convergence also where
   the solutions are not isolated); a step is kept when it lowers the residual (then
   :math:`λ` shrinks tenfold), else refused (:math:`λ` grows tenfold). Joints at a bound
   whose gradient points outward are held; every candidate is clipped onto the box.
2. **Slide** along the solution set toward ``q0``: candidates are the Newton (SQP) step
   of :math:`\min \tfrac12\|u - u_0\|^2` subject to :math:`r = 0` with the Lagrangian's
   Hessian (quadratic convergence at the end: :func:`_newton`), and the tangent step
   :math:`(I - J^+ J)(u_0 - u)` (or a fraction of it, or as far as the first bound: these
   carry the slide where the Newton step is refused). Each is followed by Gauss–Newton
   steps back onto the solution set (a retraction, so curved solution sets such as
   nguyen's rail + 2R are followed: two, four after the Newton step); the candidate
   nearest to ``q0`` among those nearer than the current point with a residual below
   1e-6 is kept. The Newton candidate is tried alone first (a third of the
   instructions), the full set only where it was refused.
   Skipped in effect (one evaluation) where there is no redundancy.
3. **Polish**: phase 1 again, to round-off, if the slide moved.

With the option ``nearest=False`` a start ends after phase 1: a solution, the one the
minimum-norm steps reach from the start, not the nearest to ``q0``.

Each phase's iteration is one casadi SX :class:`casadi.Function` per robot and task kind
(FK, Jacobian, active set, damped pseudo-inverse by Cholesky, candidates and the choice:
:mod:`~scara_opt.ik.lm_steps`), compiled to C once per machine and kept
(:mod:`~scara_opt.ik.lm_functions`, :mod:`scara_opt.model.compiled`; casadi's virtual
machine where no compiler works). Where they are compiled, each start's loop of calls runs
in C too (:mod:`~scara_opt.ik.lm_driver`, the same numbers as
:class:`~scara_opt.ik.lm_run.Run`, its Python form). :func:`~scara_opt.ik.lm_batch.solve_many`
runs that loop target by target, or maps the same Functions over the batch where nothing
is compiled.

A start that stalls (a local minimum of the residual, or a joint limit: less than
``STALL_DECREASE`` progress for ``STALL_CALLS`` calls) is followed by up to ``restarts``
starts drawn uniformly within the limits from the seeded generator; the best
configuration is kept (:mod:`~scara_opt.ik.lm_search`).
A miss is judged by :mod:`scara_opt.ik.verdict` (``unreachable`` only with a certificate);
``method="auto"`` (:mod:`scara_opt.ik.auto`) adds the IPOPT multi-start itself.
"""

from __future__ import annotations

from itertools import chain
from typing import Any, ClassVar

import numpy as np

from scara_opt.ik.arm_route import prepare_arm, solve_nearest
from scara_opt.ik.base import Solver, SolverOutput, check_flag
from scara_opt.ik.lm_functions import limits, phase_arrays
from scara_opt.ik.lm_search import check_budget, lm_search, random_starts, search_output
from scara_opt.ik.registry import register_solver
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target


@register_solver("lm")
class LevenbergMarquardtSolver(Solver):
    r"""Fast exact IK: bounded Levenberg–Marquardt in casadi (see the module docstring).

    Solves the IPOPT reference's problem (:mod:`scara_opt.ik.ipopt`) to round-off,
    nearest to ``q0`` on the branch reached from it, typically in 5–15 iterations of a
    few µs each (``method="auto"`` adds closed-form starts and IPOPT).

    Options:
        restarts: further seeded random starts after a start stalls (default 50: a start
            costs ~0.1 ms; hard poses near the joint limits of a 7-joint arm took up to 40).
        max_iter: iterations per start, all phases (default 100).
        jit: run the iterations compiled to C, once per machine and cached (default True;
            casadi's virtual machine where no C compiler works; False: the virtual machine
            always).
        nearest: slide along the solution set to the configuration nearest ``q0``, as
            IPOPT's reference does (default True). ``False`` stops at the first solution the
            descent reaches from a start (Levenberg–Marquardt's minimum-norm steps from
            ``q0``, as ``ik_LM`` and TRAC-IK return): the same where the solutions are
            isolated (non-redundant tasks); on the 7-joint test arm's full poses less than
            half the time (median 0.107 -> 0.049 ms, benchmarks/bench_ik_arms.py).
        analytic: on the 6R and 7R arms whose closed form :mod:`~scara_opt.ik.arm_route`
            serves, full poses go there first (default True): the solution nearest ``q0``
            of every branch and turn within the limits (a 7R arm's held joint at ``q0``'s
            value, then the slide with ``nearest``); the descent runs only where it finds
            none. ``False``: the descent alone.
    """

    name = "lm"
    label = "LM"
    defaults: ClassVar[dict[str, Any]] = {"restarts": 50, "max_iter": 100, "jit": True,
                                          "nearest": True, "analytic": True}

    def check_options(self) -> None:
        """restarts >= 0 and max_iter >= 1 (integers); jit, nearest and analytic bools."""
        check_budget(self.options)
        check_flag("nearest", self.options["nearest"])
        check_flag("analytic", self.options["analytic"])

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build the phases' Functions and this thread's arrays (cached on the robot).

        And the arm route's closed form where it serves
        (:func:`~scara_opt.ik.arm_route.prepare_arm`).
        """
        phase_arrays(robot, kind, 1, bool(self.options["jit"]))
        if self.options["analytic"]:
            prepare_arm(robot, kind, bool(self.options["jit"]), bool(self.options["nearest"]))

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        box, q_default = limits(robot)
        q_ref = q_default if q0 is None else q0
        opts = self.options
        if opts["analytic"] and target.rotation is not None:  # a 6R/7R arm's closed form
            out = solve_nearest(robot, target, q_ref, tol, bool(opts["jit"]),
                                bool(opts["nearest"]))
            if out is not None:
                return out
        starts = chain([q_ref], random_starts(robot, rng, int(self.options["restarts"])))
        return search_output(lm_search(robot, target, q_ref, starts, tol=tol,
                                       max_iter=int(opts["max_iter"]), jit=bool(opts["jit"]),
                                       box=box, nearest=bool(opts["nearest"])))
