r"""The fast solver's iterations as casadi Functions: phase 1 (and 3) and phase 2.

The phases of :mod:`scara_opt.ik.lm` (see there), each one casadi SX
:class:`casadi.Function` per robot and task kind: FK, Jacobian, active set, damped
pseudo-inverse by Cholesky, the candidates and the choice, all symbolic. Built here,
compiled and cached by :mod:`scara_opt.ik.lm_functions`; every constant below shapes the
generated code (the compiled cache's key hashes this file).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from scara_opt.ik.problem import ANGLE_SIZE, n_params, task_residual
from scara_opt.model.robot import Robot

#: damping factor λ of μ = λ‖r‖²: start, floor, ceiling (a start has stalled at the ceiling)
LAMBDA0, LAMBDA_MIN, LAMBDA_MAX = 1.0, 1e-6, 1e8
#: μ never falls below this multiple of ‖J‖²_F (a hundred machine epsilons): the damped
#: pseudo-inverse stays regular at exact solutions, and on a rank-deficient J its step in
#: the null directions stays bounded instead of amplifying round-off
MU_REL = 100 * float(np.finfo(float).eps)
#: and never below this [weighted m²] (a J of zeros)
MU_FLOOR = 1e-300
#: slide lengths tried, as fractions of the full tangent step toward q0 (and one to a bound)
SLIDES = (1.0, 0.5, 0.25, 0.125)
#: Gauss–Newton steps that bring a slid configuration back onto the solution set
RETRACTION_STEPS = 2
#: and after the Newton step, which is longer far from the end (Panda: 4 steps let it carry
#: the slide where 2 left a residual above SLIDE_SLACK: 76 instead of 168 full slides on
#: 100 poses)
NEWTON_RETRACTION = 4
#: residual [weighted m, rad] a slide may leave; the polish removes it
SLIDE_SLACK = 1e-6
#: Levenberg–Marquardt iterations per Function call
UNROLL = 3
#: iterations and FK evaluations per Function call (residual and Jacobian, the candidates)
ITERATIONS = {"lm": UNROLL, "slide": 1, "newton": 1}
#: (the slide: the residual, Jacobian and Lagrangian Hessian at q, then per candidate the
#: step, the retraction and the check)
EVALS = {"lm": 2 * UNROLL, "newton": 2 + (2 + NEWTON_RETRACTION),
         "slide": 2 + (2 + NEWTON_RETRACTION) + (2 + RETRACTION_STEPS) * (len(SLIDES) + 1)}


@dataclass
class _Symbols:
    """The symbolic inputs shared by both iterations, and the NLP's pieces of them."""

    q: ca.SX
    par: ca.SX
    box: ca.SX
    lo: ca.SX
    hi: ca.SX
    s: ca.SX
    q_ref: ca.SX

    @classmethod
    def make(cls, robot: Robot, kind: str) -> _Symbols:
        nq, n_ang = robot.nq, ANGLE_SIZE[kind]
        q, box = ca.SX.sym("q", nq), ca.SX.sym("box", 3 * nq)
        par = ca.SX.sym("par", n_params(robot, kind))
        return cls(q, par, box, box[:nq], box[nq:2 * nq], box[2 * nq:],
                   par[3 + n_ang:3 + n_ang + nq])

    def clip(self, q: ca.SX) -> ca.SX:
        """``q`` clipped onto the joint box."""
        return ca.fmin(ca.fmax(q, self.lo), self.hi)

    def distance(self, q: ca.SX) -> ca.SX:
        """Squared range-scaled distance to ``q0``."""
        return ca.sumsqr((q - self.q_ref) / self.s)


def _floored(J: ca.SX, mu: ca.SX | float) -> ca.SX:
    r"""The damping with its floor: :math:`μ' = μ + ` ``MU_REL`` :math:`\|J\|_F^2 +` ``MU_FLOOR``.

    The floor scales with ``J``; ``μ = 0`` gives the floor alone.
    """
    return mu + MU_REL * ca.sumsqr(J) + MU_FLOOR


def _damped_pinv(J: ca.SX, mu: ca.SX | float, v: ca.SX) -> ca.SX:
    r""":math:`J^T (J J^T + μ'I)^{-1} v` (nq,): the damped pseudo-inverse applied to ``v`` (m,).

    Solved in the smaller of its two forms, with ``v`` (one right-hand side, not the m
    columns of the pseudo-inverse). :math:`μ'`: :func:`_floored`; the floor keeps the step
    sound on rank-deficient Jacobians too (more residual rows than joints, singular poses).
    """
    m, nq = J.shape
    mu = _floored(J, mu)
    if m <= nq:
        return J.T @ _spd_solve(J @ J.T + mu * ca.SX.eye(m), v)
    return _spd_solve(J.T @ J + mu * ca.SX.eye(nq), J.T @ v)


def _spd_solve(A: ca.SX, b: ca.SX) -> ca.SX:
    r""":math:`A^{-1} b` for a symmetric positive definite ``A`` (n, n), by Cholesky.

    Then two triangular solves: half the instructions of casadi's QR ``solve``. The
    callers' ``A`` is :math:`J J^T + μ'I` (or :math:`J^T J + μ'I`) with the floor of
    :func:`_floored`, a hundred machine epsilons of :math:`\|J\|_F^2`: above the
    factorisation's round-off (a few epsilons of :math:`\|A\|`), so every pivot stays
    positive.
    """
    R = ca.chol(A)
    return ca.solve(R, ca.solve(R.T, b))


def _scaled(sym: _Symbols, robot: Robot, kind: str, q: ca.SX,
            free: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Residual r (m,) at an expression ``q`` and its Jacobian in scaled free coordinates."""
    x = ca.SX.sym("x", robot.nq)
    r = task_residual(robot, kind, x, sym.par)
    rj = ca.Function("rj", [x, sym.par], [r, ca.densify(ca.jacobian(r, x))])
    r_q, J_q = rj(q, sym.par)
    return r_q, J_q @ ca.diag(sym.s * free)


def _tangent(sym: _Symbols, J: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX]:
    r"""The slide direction at ``sym.q`` with task Jacobian ``J``: (free, Js, tangent).

    ``tangent`` :math:`= (I - J_s^+ J_s)\,t`, the part of the scaled pull
    :math:`t = (q_0 - q) / s` along the solution set, over the joints not held at a bound
    that ``q0`` lies beyond.
    """
    q, t = sym.q, (sym.q_ref - sym.q) / sym.s
    free = 1 - ca.logic_or(ca.logic_and(q <= sym.lo, t < 0), ca.logic_and(q >= sym.hi, t > 0))
    Js = J @ ca.diag(sym.s * free)
    return free, Js, free * t - _damped_pinv(Js, 0.0, Js @ (free * t))


def _lm_iteration(robot: Robot, kind: str) -> ca.Function:
    """One Levenberg–Marquardt iteration (see the module docstring and :func:`build_lm_step`)."""
    sym = _Symbols.make(robot, kind)
    q, lam = sym.q, ca.SX.sym("lam")
    r = task_residual(robot, kind, q, sym.par)
    J = ca.densify(ca.jacobian(r, q))
    g = J.T @ r
    free = 1 - ca.logic_or(ca.logic_and(q <= sym.lo, g > 0), ca.logic_and(q >= sym.hi, g < 0))
    e0 = ca.sumsqr(r)
    cand = sym.clip(q - sym.s * _damped_pinv(J @ ca.diag(sym.s * free), lam * e0, r))
    e_c = ca.sumsqr(task_residual(robot, kind, cand, sym.par))
    ok = e_c < e0
    q_next = ca.if_else(ok, cand, q)
    return ca.Function(
        "lm_iteration", [q, lam, sym.par, sym.box],
        [q_next, ca.if_else(ok, ca.fmax(lam / 10, LAMBDA_MIN), ca.fmin(lam * 10, LAMBDA_MAX)),
         ca.if_else(ok, e_c, e0), ca.mmax(ca.fabs(q_next - q) / sym.s),
         ca.mmax(ca.fabs(_tangent(sym, J)[2]))])


def build_lm_step(robot: Robot, kind: str) -> ca.Function:
    """Phase 1 and 3: ``UNROLL`` Levenberg–Marquardt iterations in one Function.

    ``lm_step(q (nq), lam (1), par, box (3 nq)) -> (q_next (nq), lam_next (1),
    e_next (1), step (1), slide (1))``: ``par`` is the IPOPT NLP's parameter vector (only
    its target and weights are used here), ``box`` the lower limits, upper limits and
    ranges ``s`` (inputs, so the Function survives :meth:`Robot.with_limits`). ``e_next``
    is ‖r‖² at ``q_next``; ``step`` the largest joint move of the last iteration in
    ranges, 0 when it was refused; ``slide`` the largest entry of the slide direction
    before it (phase 2 is skipped when that is below ``lm_run.SLIDE_TOL``: no redundancy, or
    already nearest). Unrolling saves the Python work between iterations; an iteration
    after convergence is refused and changes nothing.
    """
    one = _lm_iteration(robot, kind)
    sym = _Symbols.make(robot, kind)
    x, lam = sym.q, ca.SX.sym("lam")
    outputs: list[ca.SX] = [x, lam]
    for _ in range(UNROLL):
        outputs = list(one(outputs[0], outputs[1], sym.par, sym.box))
    return ca.Function(f"lm_step_{robot.name}_{kind}", [x, lam, sym.par, sym.box], outputs,
                       ["q", "lam", "par", "box"],
                       ["q_next", "lam_next", "e_next", "step", "slide"])


def _room(sym: _Symbols, q: ca.SX, direction: ca.SX) -> ca.SX:
    """The largest multiple of ``direction`` (scaled) that keeps ``q`` within the box, ≤ 1."""
    room = ca.if_else(direction < 0, sym.lo - q, sym.hi - q) / (sym.s * direction)
    return ca.fmin(1.0, ca.mmin(ca.if_else(ca.fabs(direction) > 1e-300, room, ca.inf)))


def _newton(sym: _Symbols, robot: Robot, kind: str, free: ca.SX, Js: ca.SX,
            r: ca.SX) -> ca.SX:
    r"""The scaled SQP (Newton–KKT) step toward the nearest point of the solution set.

    Minimises :math:`\tfrac12\|u - u_0\|^2` subject to :math:`r = 0` in scaled coordinates:
    :math:`\begin{bmatrix} H & J_s^T \\ J_s & -μI \end{bmatrix}
    \begin{bmatrix} Δu \\ ν \end{bmatrix} = -\begin{bmatrix} g \\ r \end{bmatrix}`,
    :math:`g = u - u_0` over the free joints, :math:`H = I + \sum_i λ_i ∇^2 r_i` with the
    least-squares multipliers :math:`λ = -(J_s J_s^T)^{-1} J_s g` (μ: the floor of
    :func:`_floored`). The tangent step alone takes :math:`H = I` and converges
    linearly, at the rate the solution set's curvature sets (~0.3 a step on a 7-joint
    arm far from ``q0``); with the curvature this step converges quadratically.
    """
    nq, m = robot.nq, Js.shape[0]
    g = free * (sym.q - sym.q_ref) / sym.s
    mu = _floored(Js, 0.0)
    lam = -_spd_solve(Js @ Js.T + mu * ca.SX.eye(m), Js @ g)
    x, lx = ca.SX.sym("x", nq), ca.SX.sym("l", m)
    phi = ca.dot(lx, task_residual(robot, kind, x, sym.par))
    hess = ca.Function("lagrangian_hessian", [x, lx, sym.par], [ca.hessian(phi, x)[0]])
    D = ca.diag(sym.s * free)
    H = ca.SX.eye(nq) + D @ hess(sym.q, lam, sym.par) @ D
    kkt = ca.blockcat([[H, Js.T], [Js, -mu * ca.SX.eye(m)]])
    return ca.solve(kkt, -ca.vertcat(g, r))[:nq]


def build_slide_step(robot: Robot, kind: str, newton_only: bool = False) -> ca.Function:
    """Phase 2: one slide toward ``q0`` along the solution set, with a retraction.

    ``slide_step(q (nq), par, box (3 nq)) -> (q_next (nq), e_next (1), step (1),
    pull (1))``, inputs as for :func:`build_lm_step`; ``pull`` is the largest entry of the
    slide direction at ``q`` (below ``lm_run.SLIDE_TOL``: ``q`` is the nearest point, locally).
    Joints at a bound that ``q0`` lies beyond are held, and so are joints the slide takes
    to a bound, during the retraction. Steps tried: the Newton step (:func:`_newton`), and
    unless ``newton_only`` the fractions ``SLIDES`` of the tangent step and the length that
    meets the first bound; of those that end nearer to ``q0`` with a small residual, the
    nearest.
    """
    sym = _Symbols.make(robot, kind)
    q = sym.q
    r = task_residual(robot, kind, q, sym.par)
    free, Js, tangent = _tangent(sym, ca.densify(ca.jacobian(r, q)))
    fix = -_damped_pinv(Js, 0.0, r)
    e0 = ca.sumsqr(r)
    q_next, e_next, d_next = q, e0, sym.distance(q)
    steps = [] if newton_only else [fix + alpha * tangent
                                    for alpha in (*SLIDES, _room(sym, q, tangent))]
    for k, step in enumerate([_newton(sym, robot, kind, free, Js, r), *steps]):
        c1 = sym.clip(q + sym.s * step)
        inside = ca.logic_and(c1 > sym.lo, c1 < sym.hi)
        c2 = c1
        for _ in range(NEWTON_RETRACTION if k == 0 else RETRACTION_STEPS):
            r1, Js1 = _scaled(sym, robot, kind, c2, free * inside)
            c2 = sym.clip(c2 - sym.s * _damped_pinv(Js1, 0.0, r1))
        e2, d2 = ca.sumsqr(task_residual(robot, kind, c2, sym.par)), sym.distance(c2)
        ok = ca.logic_and(e2 <= ca.fmax(e0, SLIDE_SLACK**2), d2 < d_next)
        q_next, e_next = ca.if_else(ok, c2, q_next), ca.if_else(ok, e2, e_next)
        d_next = ca.if_else(ok, d2, d_next)
    return ca.Function(f"slide_step_{robot.name}_{kind}", [q, sym.par, sym.box],
                       [q_next, e_next, ca.mmax(ca.fabs(q_next - q) / sym.s),
                        ca.mmax(ca.fabs(tangent))],
                       ["q", "par", "box"], ["q_next", "e_next", "step", "pull"])


def build_newton_step(robot: Robot, kind: str) -> ca.Function:
    """:func:`build_slide_step` with the Newton step alone (a third of its instructions).

    Tried first at each slide: near the end of a slide, where it converges quadratically,
    the other candidates are not needed.
    """
    return build_slide_step(robot, kind, newton_only=True)


#: the builder of each phase's Function, by phase name
BUILDERS = {"lm": build_lm_step, "slide": build_slide_step, "newton": build_newton_step}
