r"""The deterministic reference: IK as casadi NLPs solved by IPOPT, with seeded multi-start.

Two NLPs per robot and task kind (built once, cached on the robot per thread), both in
:mod:`scara_opt.ik.problem`:

* **closest** (from each start): the least-squares problem
  :math:`\min_q \tfrac12 w_p^2 \|p(q) - p^*\|^2 + \tfrac12 w_a^2 \|e_a(q)\|^2
  + \tfrac12 λ \|(q - q_0)/s\|^2` within the joint limits (``λ`` = ``regularization``,
  ``s`` the joint ranges); its minimiser is the closest configuration IPOPT finds, and the
  small pull toward ``q0`` picks the branch nearest to it where two meet (singular poses);
* **nearest** (from that answer, when it is within ``NEAREST_FROM`` of the target):
  :math:`\min_q \tfrac12 \|(q - q_0)/s\|^2` subject to the task residual being zero
  (:func:`~scara_opt.ik.problem.task_residual`) and the limits: the configuration that
  reaches the target exactly, nearest to ``q0`` in range-scaled joint coordinates (locally:
  on the branch reached). Where the task leaves joints free (redundant robots, a
  position-only target on a robot with a wrist) this is the redundancy rule; elsewhere it
  removes the offset of order λ the pull leaves. Kept only if it still reaches the target.
  Not run where the task has more residual rows than the robot joints (a full pose for a
  4-joint SCARA): no configuration is left to choose, and IPOPT refuses such a problem.

IPOPT stops at its own tolerance (``NEAREST_OPTIONS``: the task residual met to 1e-13, no
early exit at an "acceptable" level), so IPOPT alone reaches round-off on reachable
targets; the return status of every IPOPT call is reported in the result's message. If the
first start misses, up to ``restarts`` further starts are drawn uniformly within the limits
from the seeded generator (none once a start is within a relative 1e-6 of the least
residual a certificate of :mod:`scara_opt.ik.certificates` proves); the best is kept.
``polish`` then runs the fast solver's phases (:mod:`scara_opt.ik.lm`) from the answer,
kept only if not worse: the last digits.

IPOPT does not decide reachability: a miss is judged by :mod:`scara_opt.ik.verdict`
(``unreachable`` only with a certificate).
"""

from __future__ import annotations

import math
import threading
from collections import Counter
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from scara_opt import interrupt
from scara_opt.ik.base import (
    MAX_ITER,
    MAX_RESTARTS,
    Solver,
    SolverOutput,
    check_flag,
    check_number,
    default_q0,
)
from scara_opt.ik.certificates import certify
from scara_opt.ik.lm_functions import phase_arrays
from scara_opt.ik.lm_search import lm_search
from scara_opt.ik.problem import (
    RESIDUAL_SIZE,
    ik_objective,
    n_params,
    nlp_params,
    ranges,
    split_params,
    task_residual,
)
from scara_opt.ik.registry import register_solver
from scara_opt.ik.task import config_errors, error_from
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

#: IPOPT options of both NLPs (pinocchio's casadi examples read the return status; so do we)
_COMMON: dict[str, Any] = {
    "hessian_approximation": "exact",
    "honor_original_bounds": "yes",
    "mu_strategy": "monotone",
    "mu_init": 1e-8,
    "bound_push": 1e-8,
    "bound_frac": 1e-8,
    "print_level": 0,
    "sb": "yes",
}
#: IPOPT options of the nearest NLP, whose answer is final: the task residual met to 1e-13
#: [weighted m, rad], no early exit at an "acceptable" level; its objective (a distance in
#: joint ranges, ~1e-6 near the answer) scaled up so that IPOPT's tolerance reaches joints
#: that end on a bound (unscaled they stop ~3e-5 rad inside it)
NEAREST_OPTIONS: dict[str, Any] = {**_COMMON, "tol": 1e-10, "constr_viol_tol": 1e-13,
                                   "obj_scaling_factor": 1e6, "acceptable_iter": 0}
#: IPOPT options of the closest NLP: it locates the branch and the nearest NLP finishes, or,
#: where the target is out of reach, its answer is the closest configuration found. An
#: iterate at IPOPT's "acceptable" level 1e-6 ends it: along a redundant robot's solution
#: set its pull toward q0 is too weak a curvature for IPOPT to converge fast (nguyen: 48
#: iterations to 1e-8, 18 with the early end; the nearest NLP is not affected)
IPOPT_OPTIONS: dict[str, Any] = {**_COMMON, "tol": 1e-8, "acceptable_tol": 1e-6,
                                 "acceptable_iter": 1}
#: the nearest NLP runs from a closest-NLP answer at least this close to the target [m, rad]
NEAREST_FROM = 1e-3


@dataclass
class _NLP:
    """One IPOPT solver of a task kind."""

    solver: ca.Function
    n_param: int


def build_ik_nlp(robot: Robot, kind: str, max_iter: int = 100, verbose: bool = False) -> _NLP:
    """The IPOPT solver of :func:`~scara_opt.ik.problem.ik_objective` (the closest NLP)."""
    nlp = ik_objective(robot, kind)
    ipopt = {**IPOPT_OPTIONS, "max_iter": int(max_iter), "print_level": 5 if verbose else 0}
    solver = ca.nlpsol(f"ik_{robot.name}_{kind}", "ipopt", nlp,
                       {"ipopt": ipopt, "print_time": bool(verbose), "error_on_fail": False})
    return _NLP(solver, int(nlp["p"].shape[0]))


def build_nearest_nlp(robot: Robot, kind: str, max_iter: int = 100,
                      verbose: bool = False) -> _NLP:
    """The IPOPT solver of the nearest NLP: distance to ``q0`` s.t. the task residual is 0."""
    q = ca.SX.sym("q", robot.nq)
    par = ca.SX.sym("par", n_params(robot, kind))
    f = 0.5 * ca.sumsqr((q - split_params(robot, kind, par)["q0"]) / ca.DM(ranges(robot)))
    g = task_residual(robot, kind, q, par)
    ipopt = {**NEAREST_OPTIONS, "max_iter": int(max_iter), "print_level": 5 if verbose else 0}
    solver = ca.nlpsol(f"ik_nearest_{robot.name}_{kind}", "ipopt",
                       {"x": q, "p": par, "f": f, "g": g},
                       {"ipopt": ipopt, "print_time": bool(verbose), "error_on_fail": False})
    return _NLP(solver, int(par.shape[0]))


def cached_nlp(robot: Robot, kind: str, max_iter: int = 100, verbose: bool = False,
               nearest: bool = False) -> _NLP:
    """:func:`build_ik_nlp` (or the nearest NLP), built once per robot, settings and thread.

    IPOPT's solver objects are not shared between threads (a call's statistics and memory
    belong to one caller at a time).
    """
    cache: dict[tuple, _NLP] = robot.__dict__.setdefault("_ik_nlp_cache", {})
    key = (kind, int(max_iter), bool(verbose), nearest, threading.get_ident())
    if key not in cache:
        build = build_nearest_nlp if nearest else build_ik_nlp
        cache[key] = build(robot, kind, max_iter, verbose)
    return cache[key]


def polish(robot: Robot, target: Target, q: Array, err: float, q_ref: Array,
           tol: float) -> tuple[Array, float]:
    """Refine an NLP answer ``q`` (error ``err``) with the fast solver's phases from ``q``.

    Levenberg–Marquardt on the residual, a slide along the solution set toward ``q_ref``
    and Gauss–Newton to round-off (:func:`scara_opt.ik.lm_search.lm_search`). The refined ``q``
    is kept only if its error is not larger.

    Returns:
        ``q`` (within the limits) and its error [m, rad].
    """
    found = lm_search(robot, target, q_ref, [q], tol=tol, max_iter=100)
    q_new = np.clip(found.q, robot.lower, robot.upper)
    err_new = error_from(*config_errors(robot, target, q_new))
    return (q_new, err_new) if err_new <= err else (q, err)


@register_solver("ipopt")
class IpoptSolver(Solver):
    r"""IK by IPOPT on the casadi NLPs (see the module docstring for the problems and rules).

    Options:
        restarts: further seeded random starts after the first misses (default 50; none
            once a start is as close as a certificate proves possible).
        max_iter: IPOPT iterations per start and NLP (default 100).
        regularization: weight :math:`\lambda` of the pull toward ``q0`` in the closest NLP
            (default 1e-8: near a singular pose it picks the branch nearest ``q0``; the
            nearest NLP then removes the offset of order :math:`\lambda` it leaves).
        polish: refine IPOPT's answer with the fast solver's phases (default True).
        verbose: let IPOPT print (default False).
    """

    name = "ipopt"
    label = "IPOPT"
    defaults = {"restarts": 50, "max_iter": 100, "regularization": 1e-8, "polish": True,
                "verbose": False}

    def check_options(self) -> None:
        """restarts and max_iter (integers in range), regularization in [0, 1], flags bool."""
        check_number("restarts", self.options["restarts"], 0, MAX_RESTARTS, integer=True)
        check_number("max_iter", self.options["max_iter"], 1, MAX_ITER, integer=True)
        check_number("regularization", self.options["regularization"], 0.0, 1.0)
        check_flag("polish", self.options["polish"])
        check_flag("verbose", self.options["verbose"])

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build (or find cached) the two NLPs of this task kind, and the polish's iterations."""
        o = self.options
        cached_nlp(robot, kind, o["max_iter"], o["verbose"])
        cached_nlp(robot, kind, o["max_iter"], o["verbose"], nearest=True)
        if o["polish"]:
            phase_arrays(robot, kind)

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float, held: dict[int, float] | None = None
               ) -> SolverOutput:
        """The multi-start; ``held`` (joint index -> value) holds joints by equal bounds.

        With joints held (the closed form's fallback) only the closest NLP runs.
        """
        opts = self.options
        q_ref = default_q0(robot) if q0 is None else q0
        lbx, ubx = robot.lower.copy(), robot.upper.copy()
        held = held or {}
        idx, vals = list(held), np.array(list(held.values()), dtype=float)
        lbx[idx] = ubx[idx] = vals
        q_ref = q_ref.copy()
        q_ref[idx] = vals
        run = _Run(robot, target, opts, q_ref, lbx, ubx, tol, nearest=not held)
        start, bound = q_ref, None
        for k in range(int(opts["restarts"]) + 1):
            if k > 0:
                start = rng.uniform(robot.sampling_lower, robot.sampling_upper)
                start[idx] = vals
            if run.start(start) <= tol:
                break
            if k == 0 and not held:
                cert = certify(robot, target, tol)
                bound = None if cert is None else cert.bound
            if bound is not None and run.best_err <= bound * (1 + 1e-6) + tol:
                break  # out of reach, and no start can get more than 1e-6 of it closer
        q, err = run.best_q, run.best_err
        if opts["polish"] and not held:
            q, err = polish(robot, target, q, err, q_ref, tol)
        counts = ", ".join(f"{s} x{n}" for s, n in Counter(run.statuses).items())
        return SolverOutput(q=q, iterations=run.iterations, evaluations=run.evaluations,
                            history=np.asarray(run.history),
                            message=f"IPOPT from {run.starts} start(s): {counts}")


class _Run:
    """The state of one multi-start: the NLPs, the best answer, IPOPT's statistics."""

    def __init__(self, robot: Robot, target: Target, opts: dict[str, Any], q_ref: Array,
                 lbx: Array, ubx: Array, tol: float, nearest: bool) -> None:
        self.robot, self.target, self.tol = robot, target, tol
        self.lbx, self.ubx = lbx, ubx
        self.closest = cached_nlp(robot, target.kind, opts["max_iter"], opts["verbose"])
        # more residual rows than joints (a full pose for a 4-joint SCARA): the nearest NLP
        # has no degrees of freedom (IPOPT refuses it), the closest NLP's answer stands
        nearest = nearest and RESIDUAL_SIZE[target.kind] <= robot.nq
        self.nearest = cached_nlp(robot, target.kind, opts["max_iter"], opts["verbose"],
                                  nearest=True) if nearest else None
        self.par = nlp_params(target, q_ref, float(opts["regularization"]))
        self.best_q, self.best_err = q_ref, math.inf
        self.iterations = self.evaluations = self.starts = 0
        self.history: list[float] = []
        self.statuses: list[str] = []

    def _call(self, nlp: _NLP, x0: Array, **bounds: Any) -> Array:
        # a Ctrl-C that casadi swallowed is raised again; the answer is read inside the
        # guard too: a SIGINT landing in casadi's conversion made DM.full() return None
        # (and numpy's call of DM.__array__ a SystemError), both seen in CI
        with interrupt.guard():
            sol = nlp.solver(x0=x0, p=self.par, lbx=self.lbx, ubx=self.ubx, **bounds)
            stats = nlp.solver.stats()
            x = sol["x"].full()
        interrupt.check(stats)
        self.statuses.append(stats["return_status"])
        calls = int(stats.get("n_call_nlp_f", 0))
        if calls:  # casadi leaves iter_count unset where IPOPT stops before evaluating f
            self.iterations += int(stats.get("iter_count", 0))
        self.evaluations += calls + int(stats.get("n_call_nlp_grad_f", 0))
        return np.clip(x.ravel(), self.lbx, self.ubx)

    def _error(self, q: Array) -> float:
        return error_from(*config_errors(self.robot, self.target, q))

    def start(self, x0: Array) -> float:
        """Both NLPs from one start; returns the best error so far [m, rad]."""
        self.starts += 1
        q = self._call(self.closest, x0)
        err = self._error(q)
        if self.nearest is not None and err <= NEAREST_FROM:
            q_n = self._call(self.nearest, q, lbg=0.0, ubg=0.0)
            err_n = self._error(q_n)
            if err_n <= max(err, self.tol):
                q, err = q_n, err_n
        if err < self.best_err:
            self.best_q, self.best_err = q, err
        self.history.append(self.best_err)
        return self.best_err
