r"""The IK problem in casadi, shared by the exact solvers (IPOPT and Levenberg–Marquardt).

One parameter vector ``par`` describes a target (see :func:`nlp_params`): position (3),
angle target (2 for a yaw: cos, sin; 9 for a rotation, column-major), ``q0`` (nq),
weights (2) and the regularisation (1). From it:

* :func:`ik_objective`: IPOPT's least-squares NLP,
  :math:`\tfrac12 w_p^2 \|p(q) - p^*\|^2 + \tfrac12 w_a^2 \|e_a(q)\|^2
  + \tfrac12 λ \|(q - q_0)/s\|^2` (``s``: the joint ranges), with the smooth chord
  :func:`angle_error_expr` as the angle error;
* :func:`task_residual`: the weighted residual whose zeros are the solutions, with a
  Jacobian of full row rank wherever the task has as many independent numbers as rows
  (position: 3 rows; yaw: +1 wrapped angle; rotation: +3, the rotation vector
  :math:`θ\,u` of :math:`R^{*T} R`), for Levenberg–Marquardt and IPOPT's equality
  constraints.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

#: rows of the angle target in ``par`` per task kind
ANGLE_SIZE = {"position": 0, "yaw": 2, "rotation": 9}
#: rows of :func:`task_residual` per task kind
RESIDUAL_SIZE = {"position": 3, "yaw": 4, "rotation": 6}


def n_params(robot: Robot, kind: str) -> int:
    """Length of the parameter vector of a task kind."""
    return 3 + ANGLE_SIZE[kind] + robot.nq + 3


def split_params(robot: Robot, kind: str, par: ca.SX) -> dict[str, ca.SX]:
    """The named pieces of ``par``: p_star, angle, q0, wp, wa, lam."""
    nq, n_ang = robot.nq, ANGLE_SIZE[kind]
    return {"p_star": par[:3], "angle": par[3:3 + n_ang], "q0": par[3 + n_ang:3 + n_ang + nq],
            "wp": par[3 + n_ang + nq], "wa": par[4 + n_ang + nq], "lam": par[5 + n_ang + nq]}


def angle_error_expr(robot: Robot, kind: str, R: ca.SX, param: ca.SX) -> ca.SX:
    """Smooth angle-error vector: its norm ~ the angle [rad] for small errors."""
    if kind == "yaw":
        e1, e2 = robot.yaw_basis()
        x = R[:, 0]
        heading = ca.vertcat(ca.dot(ca.DM(e1), x), ca.dot(ca.DM(e2), x))
        return heading - param  # param = (cos yaw*, sin yaw*): |.| = 2 sin(|Δ|/2)
    return ca.reshape(R - ca.reshape(param, 3, 3), 9, 1) / 2.0  # |.| = √2 sin(θ/2)


def ranges(robot: Robot) -> Array:
    """Joint ranges (nq,) used as scales [rad or m]; 1 where a joint has no limits."""
    span = robot.upper - robot.lower
    return np.where(np.isfinite(span), span, 1.0)


def ik_objective(robot: Robot, kind: str) -> dict[str, ca.SX]:
    """IPOPT's least-squares NLP ``{"x": q, "p": par, "f": f}`` of a task kind."""
    q = ca.SX.sym("q", robot.nq)
    par = ca.SX.sym("par", n_params(robot, kind))
    P = split_params(robot, kind, par)
    p, R = robot.symbolic_fk(q)
    f = 0.5 * P["wp"] ** 2 * ca.sumsqr(p - P["p_star"])
    if kind != "position":
        f += 0.5 * P["wa"] ** 2 * ca.sumsqr(angle_error_expr(robot, kind, R, P["angle"]))
    f += 0.5 * P["lam"] * ca.sumsqr((q - P["q0"]) / ca.DM(ranges(robot)))
    return {"x": q, "p": par, "f": f}


def rotation_vector(R_err: ca.SX) -> ca.SX:
    r"""The rotation vector :math:`θ u` (3,) of a rotation matrix: its norm is the angle θ.

    :math:`v = \operatorname{vee}(R - R^T)/2 = \sin θ\, u` and :math:`c = (\operatorname{tr}
    R - 1)/2 = \cos θ`; :math:`θ u = \operatorname{atan2}(|v|, c)\, v / |v|`, with the series
    :math:`1 + |v|^2/6` for the factor near :math:`θ = 0` only (no 0/0). Near :math:`θ = π`
    ``v`` is small too, but its direction is still ``u``'s: the factor θ/|v| keeps the norm
    θ, so a half-turn error is never taken for a solution. Where ``v`` is exactly zero at a
    half turn (a symmetric ``R``, no direction left in it) the residual is θ along x: its
    norm is right, and the first step leaves that point.
    """
    v = 0.5 * ca.vertcat(R_err[2, 1] - R_err[1, 2], R_err[0, 2] - R_err[2, 0],
                         R_err[1, 0] - R_err[0, 1])
    c = 0.5 * (R_err[0, 0] + R_err[1, 1] + R_err[2, 2] - 1.0)
    s2 = ca.sumsqr(v)
    s = ca.sqrt(ca.fmax(s2, 1e-300))
    theta = ca.atan2(s, c)
    series = ca.logic_and(s2 <= 1e-12, c > 0)
    rv = ca.if_else(series, 1.0 + s2 / 6.0, theta / s) * v
    return ca.if_else(ca.logic_and(s2 == 0, c < 0), ca.vertcat(theta, 0.0, 0.0), rv)


def task_residual(robot: Robot, kind: str, q: ca.SX, par: ca.SX) -> ca.SX:
    """Weighted task residual r(q) (:data:`RESIDUAL_SIZE` rows), zero exactly at solutions.

    Position rows ``w_p (p - p*)``; a yaw adds the wrapped angle ``w_a Δ`` (the chord of the
    NLP vanishes at the same places, but its two rows have rank one); a rotation adds
    ``w_a θu`` of :math:`R^{*T} R` (:func:`rotation_vector`).
    """
    P = split_params(robot, kind, par)
    p, R = robot.symbolic_fk(q)
    r = P["wp"] * (p - P["p_star"])
    if kind == "position":
        return r
    if kind == "yaw":  # heading h = chord + (c, s): angle from (c, s) to h
        chord = angle_error_expr(robot, kind, R, P["angle"])
        c, s = P["angle"][0], P["angle"][1]
        h1, h2 = chord[0] + c, chord[1] + s
        return ca.vertcat(r, P["wa"] * ca.atan2(c * h2 - s * h1, c * h1 + s * h2))
    R_star = ca.reshape(P["angle"], 3, 3)
    return ca.vertcat(r, P["wa"] * rotation_vector(R_star.T @ R))


def nlp_params(target: Target, q0: Array, lam: float) -> np.ndarray:
    """The parameter vector of one target (order of :func:`split_params`)."""
    out = np.empty(3 + ANGLE_SIZE[target.kind] + len(q0) + 3)
    fill_params(out, target, q0, lam)
    return out


def fill_params(out: np.ndarray, target: Target, q0: Array, lam: float) -> None:
    """:func:`nlp_params` written into ``out`` (its length), without a new array per solve."""
    out[:3] = target.position
    k = 3 + ANGLE_SIZE[target.kind]
    if target.rotation is not None:  # (a Target has a yaw or a rotation, never both)
        out[3:k] = np.asarray(target.rotation).ravel(order="F")  # casadi: column-major
    elif target.yaw is not None:
        out[3], out[4] = math.cos(target.yaw), math.sin(target.yaw)
    out[k:-3] = q0
    out[-3], out[-2] = target.weights
    out[-1] = lam
