r"""The deterministic reference: IK as a casadi NLP solved by IPOPT, with seeded multi-start.

Problem (built once per robot and task kind, then cached on the robot):

.. math::

    \min_q \; \tfrac12 w_p^2 \|p(q) - p^*\|^2 + \tfrac12 w_a^2 e_a(q)^2
          + \tfrac12 \lambda \|(q - q_0) / s\|^2 \quad \text{s.t.} \quad q_{lo} \le q \le q_{hi}

with :math:`e_a` the tool-angle error (yaw: the chord between the tool's heading and the
target heading; rotation: :math:`\|R - R^*\|_F / 2`), ``s`` the joint ranges and a small
``regularization`` :math:`\lambda`. The minimiser is then polished by the phases of the
fast solver (:mod:`scara_opt.ik.lm`: damped Gauss–Newton on the same residual, a slide
toward ``q0``, Gauss–Newton again), so the residual reaches round-off instead of the
:math:`O(\lambda)` offset the regulariser leaves.

Redundancy rule (``nguyen``, ``inverted5``, and the free wrist of a position-only target):
among the configurations that reach the target, the regulariser and the polish's slide
pick the one nearest to ``q0`` in range-scaled joint coordinates (locally: on the branch
IPOPT converges to).

If the first start misses, up to ``restarts`` further starts are drawn uniformly within the
limits from the seeded generator; the best is kept. A best residual above ``tol`` after all
starts is reported as ``"unreachable"``: ``q`` is the closest configuration found and
``error`` the true residual. Where the closed form applies and finds a solution IPOPT
missed, the status is ``"failed"`` instead, never ``"unreachable"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from scara_opt.ik.base import Solver, SolverOutput, check_flag, check_number, default_q0
from scara_opt.ik.registry import register_solver
from scara_opt.ik.result import Status
from scara_opt.ik.task import config_errors, error_from
from scara_opt.robot import Array, Robot
from scara_opt.target import Target

#: IPOPT options, in one place (pinocchio's casadi examples read the return status; so do we)
IPOPT_OPTIONS: dict[str, Any] = {
    "tol": 1e-9,
    "acceptable_tol": 1e-5,  # the polish finishes the last digits and the redundancy
    "acceptable_iter": 1,
    "hessian_approximation": "exact",
    "honor_original_bounds": "yes",
    "mu_strategy": "monotone",
    "mu_init": 1e-8,
    "bound_push": 1e-8,
    "bound_frac": 1e-8,
    "print_level": 0,
    "sb": "yes",
}


@dataclass
class _NLP:
    solver: ca.Function
    n_param: int


def angle_error_expr(robot: Robot, kind: str, R: ca.SX, param: ca.SX) -> ca.SX:
    """Smooth angle-error vector: its norm ~ the angle [rad] for small errors."""
    if kind == "yaw":
        e1, e2 = robot.yaw_basis()
        x = R[:, 0]
        heading = ca.vertcat(ca.dot(ca.DM(e1), x), ca.dot(ca.DM(e2), x))
        return heading - param  # param = (cos yaw*, sin yaw*): |.| = 2 sin(|Δ|/2)
    return ca.reshape(R - ca.reshape(param, 3, 3), 9, 1) / 2.0  # |.| = √2 sin(θ/2)


def ik_objective(robot: Robot, kind: str) -> dict[str, ca.SX]:
    """The NLP ``{"x": q, "p": par, "f": f}`` of a task kind, for any casadi ``nlpsol``.

    Parameters ``par``, in order: target position (3), angle target (2 for yaw: cos, sin;
    9 for rotation), ``q0`` (nq), weights (2), regularisation (1).
    """
    nq = robot.nq
    q = ca.SX.sym("q", nq)
    n_ang = {"position": 0, "yaw": 2, "rotation": 9}[kind]
    par = ca.SX.sym("par", 3 + n_ang + nq + 3)
    p_star, ang = par[:3], par[3:3 + n_ang]
    q0 = par[3 + n_ang:3 + n_ang + nq]
    wp, wa, lam = par[3 + n_ang + nq], par[4 + n_ang + nq], par[5 + n_ang + nq]
    p, R = robot.symbolic_fk(q)
    f = 0.5 * wp**2 * ca.sumsqr(p - p_star)
    if kind != "position":
        f += 0.5 * wa**2 * ca.sumsqr(angle_error_expr(robot, kind, R, ang))
    scale = ca.DM(np.where(np.isfinite(robot.upper - robot.lower), robot.upper - robot.lower, 1.0))
    f += 0.5 * lam * ca.sumsqr((q - q0) / scale)
    return {"x": q, "p": par, "f": f}


def build_ik_nlp(robot: Robot, kind: str, max_iter: int = 100, verbose: bool = False) -> _NLP:
    """The IPOPT solver of :func:`ik_objective` (kind: ``position``, ``yaw``, ``rotation``)."""
    nlp = ik_objective(robot, kind)
    ipopt = {**IPOPT_OPTIONS, "max_iter": int(max_iter), "print_level": 5 if verbose else 0}
    solver = ca.nlpsol(f"ik_{robot.name}_{kind}", "ipopt", nlp,
                       {"ipopt": ipopt, "print_time": bool(verbose), "error_on_fail": False})
    return _NLP(solver, int(nlp["p"].shape[0]))


def cached_nlp(robot: Robot, kind: str, max_iter: int = 100, verbose: bool = False) -> _NLP:
    """:func:`build_ik_nlp`, built once per robot, task kind and settings (kept on the robot)."""
    cache: dict[tuple, _NLP] = robot.__dict__.setdefault("_ik_nlp_cache", {})
    key = (kind, int(max_iter), bool(verbose))
    if key not in cache:
        cache[key] = build_ik_nlp(robot, kind, max_iter, verbose)
    return cache[key]


def nlp_params(target: Target, q0: Array, lam: float) -> np.ndarray:
    """The NLP parameter vector of one target (order of :func:`build_ik_nlp`)."""
    if target.kind == "yaw":
        ang = [math.cos(target.yaw), math.sin(target.yaw)]
    elif target.kind == "rotation":
        ang = np.asarray(target.rotation).reshape(-1, order="F").tolist()  # casadi: column-major
    else:
        ang = []
    return np.concatenate([target.position, ang, q0, target.weights, [lam]])


def polish(robot: Robot, target: Target, q: Array, err: float, q_ref: Array,
           tol: float) -> tuple[Array, float]:
    """Refine an NLP answer ``q`` (error ``err``) to round-off, nearest to ``q_ref``.

    The fast solver's phases (:func:`scara_opt.ik.lm.lm_search`) from ``q``: Levenberg–
    Marquardt on the residual, a slide along the solution set toward ``q_ref`` (a
    redundant robot ends at the solution locally nearest to it), and Gauss–Newton to
    round-off. The refined ``q`` is kept only if its error is not larger.

    Returns:
        ``q`` (within the limits) and its error [m, rad].
    """
    from scara_opt.ik.lm import lm_search  # lm builds on this module's NLP pieces

    found = lm_search(robot, target, q_ref, [q], tol=tol, max_iter=100)
    q_new = np.clip(found.q, robot.lower, robot.upper)
    err_new = error_from(*config_errors(robot, target, q_new))
    return (q_new, err_new) if err_new <= err else (q, err)


@register_solver("ipopt")
class IpoptSolver(Solver):
    r"""IK by IPOPT on the casadi NLP (see the module docstring for the problem and rules).

    Options:
        restarts: further seeded random starts after the first misses (default 10).
        max_iter: IPOPT iterations per start (default 100).
        regularization: weight :math:`\lambda` of the pull toward ``q0`` (default 1e-8).
        polish: run the Gauss–Newton polish (default True).
        verbose: let IPOPT print (default False).
    """

    name = "ipopt"
    defaults = {"restarts": 10, "max_iter": 100, "regularization": 1e-8, "polish": True,
                "verbose": False}
    certifies_unreachable = True

    def check_options(self) -> None:
        """restarts >= 0 and max_iter >= 1 (integers), regularization >= 0, flags bool."""
        check_number("restarts", self.options["restarts"], 0, integer=True)
        check_number("max_iter", self.options["max_iter"], 1, integer=True)
        check_number("regularization", self.options["regularization"], 0.0, 1.0)
        check_flag("polish", self.options["polish"])
        check_flag("verbose", self.options["verbose"])

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float, held: dict[int, float] | None = None
               ) -> SolverOutput:
        """The multi-start; ``held`` (joint index -> value) holds joints by equal bounds.

        With joints held (the closed form's fallback) the polish, which moves every joint,
        is skipped.
        """
        opts = self.options
        nlp = cached_nlp(robot, target.kind, opts["max_iter"], opts["verbose"])
        q_ref = default_q0(robot) if q0 is None else q0
        lam = float(opts["regularization"])
        lbx, ubx = robot.lower.copy(), robot.upper.copy()
        held = held or {}
        idx, vals = list(held), np.array(list(held.values()), dtype=float)
        lbx[idx] = ubx[idx] = vals
        q_ref = q_ref.copy()
        q_ref[idx] = vals
        do_polish = bool(opts["polish"]) and not held
        starts = [q_ref]
        best_q, best_err, iters, evals, history = q_ref, math.inf, 0, 0, []
        statuses = []
        for k in range(int(opts["restarts"]) + 1):
            if k > 0:
                starts.append(rng.uniform(robot.sampling_lower, robot.sampling_upper))
                starts[-1][idx] = vals
            x0 = starts[-1]
            sol = nlp.solver(x0=x0, p=nlp_params(target, q_ref, lam), lbx=lbx, ubx=ubx)
            stats = nlp.solver.stats()
            statuses.append(stats["return_status"])
            iters += int(stats.get("iter_count", 0))
            evals += int(stats.get("n_call_nlp_f", 0)) + int(stats.get("n_call_nlp_grad_f", 0))
            q = np.clip(np.asarray(sol["x"]).ravel(), lbx, ubx)
            err = error_from(*config_errors(robot, target, q))
            if do_polish:
                q, err = polish(robot, target, q, err, q_ref, tol)
            if err < best_err:
                best_q, best_err = q, err
            history.append(best_err)
            if best_err <= tol:
                break
        out = SolverOutput(q=best_q, iterations=iters, evaluations=evals,
                           history=np.asarray(history))
        if best_err > tol:
            out.status, out.message = self._verdict(robot, target, tol, len(starts), statuses)
        return out

    @staticmethod
    def _verdict(robot: Robot, target: Target, tol: float, n_starts: int,
                 statuses: list[str]) -> tuple[Status, str]:
        from scara_opt.ik.analytic import analytic_reachable

        if analytic_reachable(robot, target, tol) is True:
            return Status.FAILED, (f"IPOPT missed from {n_starts} starts ({statuses[-1]}) but "
                                   "the closed form reaches the target: try more restarts")
        return Status.UNREACHABLE, (f"best of {n_starts} IPOPT starts; more restarts= can "
                                    "only help if the target is in fact reachable")
