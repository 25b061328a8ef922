r"""The deterministic reference: IK as a casadi NLP solved by IPOPT, with seeded multi-start.

Problem (built once per robot and task kind, then cached on the robot):

.. math::

    \min_q \; \tfrac12 w_p^2 \|p(q) - p^*\|^2 + \tfrac12 w_a^2 e_a(q)^2
          + \tfrac12 \lambda \|(q - q_0) / s\|^2 \quad \text{s.t.} \quad q_{lo} \le q \le q_{hi}

with :math:`e_a` the tool-angle error (yaw: the chord between the tool's heading and the
target heading; rotation: :math:`\|R - R^*\|_F / 2`), ``s`` the joint ranges and a small
``regularization`` :math:`\lambda`. The minimiser is then polished by Gauss–Newton
minimum-norm steps on the Pinocchio Jacobian, so the residual reaches round-off instead of
the :math:`O(\lambda)` offset the regulariser leaves.

Redundancy rule (``nguyen``, ``inverted5``, and the free wrist of a position-only target):
among the configurations that reach the target, the regulariser and the minimum-norm
polish pick the one nearest to ``q0`` (locally: on the branch IPOPT converges to).

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
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.ik.base import Solver, SolverOutput, default_q0
from scara_opt.ik.registry import register_solver
from scara_opt.ik.result import Status
from scara_opt.ik.task import config_errors, error_from, errors_from_poses
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


def build_ik_nlp(robot: Robot, kind: str, max_iter: int = 100, verbose: bool = False) -> _NLP:
    """The casadi NLP of a task kind (``position``, ``yaw``, ``rotation``) for ``robot``.

    Parameters of the NLP, in order: target position (3), angle target (2 for yaw: cos, sin;
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
    ipopt = {**IPOPT_OPTIONS, "max_iter": int(max_iter), "print_level": 5 if verbose else 0}
    solver = ca.nlpsol(f"ik_{robot.name}_{kind}", "ipopt", {"x": q, "p": par, "f": f},
                       {"ipopt": ipopt, "print_time": bool(verbose), "error_on_fail": False})
    return _NLP(solver, int(par.shape[0]))


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



def _residual_and_jacobian(robot: Robot, target: Target, q: Array) -> tuple[Array, Array, float]:
    """Weighted task residual r (m,), its Jacobian (m, nq), and the error, at ``q``."""
    wp, wa = target.weights
    T = robot.fk(q)
    J = robot.jacobian(q)
    dp, dang = errors_from_poses(robot, target, T[None])
    r, Jr = [wp * dp[0]], [wp * J[:3]]
    if target.kind == "yaw":
        r.append(wa * dang)
        Jr.append(wa * (robot.yaw_axis @ J[3:])[None, :])
    elif target.kind == "rotation":
        r.append(wa * pin.log3(T[:3, :3] @ np.asarray(target.rotation).T))
        Jr.append(wa * J[3:])
    err = error_from(dp[0], None if dang is None else float(dang[0]))
    return np.concatenate(r), np.vstack(Jr), err


def polish(robot: Robot, target: Target, q: Array, q_ref: Array,
           steps: int = 30) -> tuple[Array, float]:
    """Refine an NLP answer: Gauss–Newton to round-off, plus null-space moves toward ``q_ref``.

    Each step is :math:`Δ = -J^+ r + (I - J^+ J)(q_{ref} - q)` in range-scaled joint
    coordinates, over the joints not held at a limit: the first term removes the task
    residual (minimum-norm), the second slides along the solution set toward ``q_ref``, so
    a redundant robot ends at the solution locally nearest to ``q_ref``. A joint a step
    would push past a limit is held at that limit from then on. Steps are kept only while
    the residual does not grow above max(its value, 1e-13), shortening the slide if needed.

    Returns:
        The refined ``q`` (within the limits) and its error [m, rad].
    """
    lo, hi = robot.lower, robot.upper
    scale = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
    free = (q > lo + 1e-12) & (q < hi - 1e-12)
    r, J, err = _residual_and_jacobian(robot, target, q)
    for _ in range(steps):
        if not free.any():
            break
        Js = J[:, free] * scale[free]
        pinv = np.linalg.pinv(Js, rcond=1e-10)
        toward = (q_ref - q)[free] / scale[free]
        fix = -pinv @ r
        slide = toward - pinv @ (Js @ toward)
        for alpha in (1.0, 0.25, 1 / 16, 0.0):  # shorten the slide until the residual holds
            cand = q.copy()
            cand[free] += (fix + alpha * slide) * scale[free]
            held = free & ((cand < lo) | (cand > hi))
            cand = np.clip(cand, lo, hi)
            r_c, J_c, err_c = _residual_and_jacobian(robot, target, cand)
            if err_c <= max(err, 1e-13):
                break
        else:
            break
        free &= ~held
        moved = float(np.abs(cand - q).max())
        q, r, J, err = cand, r_c, J_c, err_c
        if moved < 1e-13:
            break
    return _gauss_newton(robot, target, q, free, r, J, err)


def _gauss_newton(robot: Robot, target: Target, q: Array, free: NDArray[np.bool_], r: Array,
                  J: Array, err: float, steps: int = 5) -> tuple[Array, float]:
    """Pure minimum-norm Gauss–Newton steps (no slide) while the residual keeps falling."""
    for _ in range(steps):
        if err == 0.0 or not free.any():
            break
        cand = q.copy()
        cand[free] -= np.linalg.lstsq(J[:, free], r, rcond=1e-10)[0]
        cand = np.clip(cand, robot.lower, robot.upper)
        r_c, J_c, err_c = _residual_and_jacobian(robot, target, cand)
        if not err_c < err:
            break
        q, r, J, err = cand, r_c, J_c, err_c
    return q, err


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

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        opts = self.options
        nlp = cached_nlp(robot, target.kind, opts["max_iter"], opts["verbose"])
        q_ref = default_q0(robot) if q0 is None else q0
        lam = float(opts["regularization"])
        lbx, ubx = robot.lower, robot.upper
        starts = [q_ref]
        best_q, best_err, iters, evals, history = q_ref, math.inf, 0, 0, []
        statuses = []
        for k in range(int(opts["restarts"]) + 1):
            if k > 0:
                starts.append(rng.uniform(robot.sampling_lower, robot.sampling_upper))
            x0 = starts[-1]
            sol = nlp.solver(x0=x0, p=nlp_params(target, q_ref, lam), lbx=lbx, ubx=ubx)
            stats = nlp.solver.stats()
            statuses.append(stats["return_status"])
            iters += int(stats.get("iter_count", 0))
            evals += int(stats.get("n_call_nlp_f", 0)) + int(stats.get("n_call_nlp_grad_f", 0))
            q = np.clip(np.asarray(sol["x"]).ravel(), lbx, ubx)
            if opts["polish"]:
                q, err = polish(robot, target, q, q_ref)
            else:
                err = error_from(*config_errors(robot, target, q))
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
