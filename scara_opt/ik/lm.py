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
(FK, Jacobian, active set, damped pseudo-inverse by Cholesky, candidates and the choice),
compiled to C once per machine and kept (:mod:`scara_opt.model.compiled`; casadi's
virtual machine where no compiler works). Where they are compiled, each start's loop of
calls runs in C too (:mod:`scara_opt.ik.lm_driver`, the same numbers as :class:`_Run`,
its Python form). :func:`solve_many` runs that loop target by target, or maps the same
Functions over the batch where nothing is compiled.

A start that stalls (a local minimum of the residual, or a joint limit: less than
``STALL_DECREASE`` progress for ``STALL_CALLS`` calls) is followed by up to ``restarts``
starts drawn uniformly within the limits from the seeded generator; the best
configuration is kept.
A miss is judged by :mod:`scara_opt.ik.verdict` (``unreachable`` only with a certificate);
``method="auto"`` (:mod:`scara_opt.ik.auto`) adds the IPOPT multi-start itself.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from itertools import chain
from pathlib import Path
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from scara_opt.ik import lm_driver, problem
from scara_opt.ik.base import (
    MAX_ITER,
    MAX_RESTARTS,
    Solver,
    SolverOutput,
    check_flag,
    check_number,
    default_q0,
)
from scara_opt.ik.problem import ANGLE_SIZE, fill_params, n_params, task_residual
from scara_opt.ik.registry import register_solver
from scara_opt.model import symbolic
from scara_opt.model.batch_fk import kinematic_key
from scara_opt.model.buffers import FunctionArrays
from scara_opt.model.compiled import compiled, source_hash
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

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
#: a start has converged when ‖r‖ <= TOL_FACTOR * tol * min(weights) and the step <= STEP_TOL
TOL_FACTOR, STEP_TOL = 1e-2, 1e-12
#: the slide has converged when its step falls below this [joint ranges]
SLIDE_TOL = 1e-9
#: a start has stalled after this many calls in a row that lower ‖r‖² by less than a
#: fraction STALL_DECREASE (converging to a solution, LM gains far more a call; sliding
#: into a local minimum it gains less: the UR5-class arm's stalled starts went on for up
#: to 22 calls at 1e-6; 300 poses from mid-range q0: mean calls a solve 15.0 -> 11.6)
STALL_CALLS, STALL_DECREASE = 2, 1e-2
#: Levenberg–Marquardt iterations per Function call
UNROLL = 3
#: iterations and FK evaluations per Function call (residual and Jacobian, the candidates)
ITERATIONS = {"lm": UNROLL, "slide": 1, "newton": 1}
#: (the slide: the residual, Jacobian and Lagrangian Hessian at q, then per candidate the
#: step, the retraction and the check)
EVALS = {"lm": 2 * UNROLL, "newton": 2 + (2 + NEWTON_RETRACTION),
         "slide": 2 + (2 + NEWTON_RETRACTION) + (2 + RETRACTION_STEPS) * (len(SLIDES) + 1)}



# ---------------------------------------------------------------------- casadi iterations
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
    before it (phase 2 is skipped when that is below ``SLIDE_TOL``: no redundancy, or
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
    slide direction at ``q`` (below ``SLIDE_TOL``: ``q`` is the nearest point, locally).
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


_BUILDERS = {"lm": build_lm_step, "slide": build_slide_step, "newton": build_newton_step}
#: the source the iterations are built from: part of the compiled cache's key
_CODE = source_hash(Path(__file__), problem.__file__, symbolic.__file__)


def _merged(f: ca.Function, name: str) -> ca.Function:
    """``f`` renamed ``name`` with its common subexpressions merged (fewer instructions)."""
    outputs = f.call(f.sx_in())
    if hasattr(ca, "cse"):  # casadi >= 3.6: ~10-30 % fewer instructions
        outputs = ca.cse(outputs)
    return ca.Function(name, f.sx_in(), outputs, f.name_in(), f.name_out())


def step_function(robot: Robot, phase: str, kind: str, jit: bool = True) -> ca.Function:
    """The ``phase`` ("lm" or "slide") Function of one target, built or loaded once.

    With ``jit`` it is the C compiled once per machine and kept in the cache folder
    (:mod:`scara_opt.model.compiled`: loaded in well under a millisecond in later processes;
    where no C compiler works, casadi's virtual machine runs it). Without, the virtual
    machine always. The cache key holds the robot's kinematics, the task kind and the
    source of the modules that build it, so a change to any compiles anew.
    """
    cache: dict[tuple, ca.Function] = robot.__dict__.setdefault("_ik_lm_cache", {})
    if (phase, kind, jit) not in cache:
        key = kinematic_key(robot)
        name = f"scara_opt_{phase}_{kind}_{key[:12]}"

        def build() -> ca.Function:
            return _merged(_BUILDERS[phase](robot, kind), name)

        cache[(phase, kind, jit)] = compiled(name, f"{key} {phase} {kind} {_CODE}", build) \
            if jit else build()
    return cache[(phase, kind, jit)]


def cached_step(robot: Robot, phase: str, kind: str, n: int = 1,
                jit: bool = True) -> ca.Function:
    """:func:`step_function` mapped over ``n`` columns (one per target), built once."""
    cache: dict[tuple, ca.Function] = robot.__dict__.setdefault("_ik_lm_maps", {})
    if (phase, kind, n, jit) not in cache:
        f = step_function(robot, phase, kind, jit)
        cache[(phase, kind, n, jit)] = f if n == 1 else f.map(n)
    return cache[(phase, kind, n, jit)]


@dataclass
class PhaseArrays:
    """The iterations' :class:`FunctionArrays` for ``n`` targets, sharing ``par``, ``box``.

    Attributes:
        lm, slide: the arrays of :func:`build_lm_step` and :func:`build_slide_step`.
        par: (n, n_par) the NLP parameters of each target; box: (n, 3 nq) the limits.
        newton: the arrays of :func:`build_newton_step`.
    """

    lm: FunctionArrays
    slide: FunctionArrays
    par: Array
    box: Array
    newton: FunctionArrays


def phase_arrays(robot: Robot, kind: str, n: int = 1, jit: bool = True) -> PhaseArrays:
    """This thread's :class:`PhaseArrays` for ``robot``, task kind and ``n`` columns."""
    cache: dict[tuple, PhaseArrays] = robot.__dict__.setdefault("_ik_lm_arrays", {})
    key = (kind, n, jit, threading.get_ident())
    if key not in cache:
        lm = FunctionArrays(cached_step(robot, "lm", kind, n, jit), n)
        shared = {"par": lm.arg["par"], "box": lm.arg["box"]}
        slide = FunctionArrays(cached_step(robot, "slide", kind, n, jit), n, shared)
        newton = FunctionArrays(cached_step(robot, "newton", kind, n, jit), n, shared)
        cache[key] = PhaseArrays(lm, slide, shared["par"], shared["box"], newton)
    return cache[key]


def phase_driver(robot: Robot, kind: str, jit: bool = True) -> lm_driver.Driver | None:
    """This thread's C start loop on the one-target :func:`phase_arrays`, or ``None``.

    :mod:`scara_opt.ik.lm_driver`; ``None`` where the phases are not compiled (``jit=False``,
    no C compiler): ``_Run``, the same loop in Python, runs.
    """
    cache: dict[tuple, lm_driver.Driver | None] = robot.__dict__.setdefault("_ik_lm_driver", {})
    key = (kind, jit, threading.get_ident())
    if key not in cache:
        cache[key] = _make_driver(robot, kind) if jit else None
    return cache[key]


def _make_driver(robot: Robot, kind: str) -> lm_driver.Driver | None:
    """:func:`lm_driver.make` on this thread's compiled phases and lm's constants."""
    f = phase_arrays(robot, kind, 1, True)
    phases = {phase: (step_function(robot, phase, kind, True), getattr(f, phase))
              for phase in ("lm", "newton", "slide")}
    counts = {phase: (ITERATIONS[phase], EVALS[phase]) for phase in phases}
    constants = {"stall_calls": STALL_CALLS, "lambda0": LAMBDA0, "lambda_max": LAMBDA_MAX,
                 "step_tol": STEP_TOL, "slide_tol": SLIDE_TOL, "stall_decrease": STALL_DECREASE}
    return lm_driver.make(phases, counts, constants, robot.nq)


def limits(robot: Robot) -> tuple[Array, Array]:
    """``box`` (3 nq,) = [lower, upper, ranges] and the default ``q0``, cached per limits."""
    lo, hi = robot.lower, robot.upper
    cache: dict[bytes, tuple[Array, Array]] = robot.__dict__.setdefault("_ik_lm_limits", {})
    key = lo.tobytes() + hi.tobytes()
    if key not in cache:
        span = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
        cache[key] = np.concatenate([lo, hi, span]), default_q0(robot)
    return cache[key]


def residual_tol(weights: Sequence[float], tol: float) -> float:
    """‖r‖² [weighted m², rad²] at which a start has converged, for the caller's ``tol``."""
    return (TOL_FACTOR * tol * float(min(weights))) ** 2


def within_tol(e_tol: float) -> float:
    """‖r‖² at which the residual is within the caller's ``tol`` (``e_tol``: :func:`residual_tol`).

    Each row of r is a weighted error (position [m], the wrapped yaw or the rotation
    angle [rad]), so ‖r‖ <= tol·min(weights) bounds each error by ``tol``. A search
    stops at a start that ends there, converged or not: the answer is a solution.
    """
    return e_tol / TOL_FACTOR**2


# ---------------------------------------------------------------------- one target
@dataclass
class _Run:
    """State of the iterations on one target (the three phases share it)."""

    f: PhaseArrays
    e_tol: float
    nearest: bool = True
    budget: int = 0
    iterations: int = 0
    evaluations: int = 0
    history: list[float] = field(default_factory=list)
    best: float = math.inf
    slide_needed: bool = True

    def _count(self, phase: str, e: float) -> None:
        self.iterations += ITERATIONS[phase]
        self.budget -= ITERATIONS[phase]
        self.evaluations += EVALS[phase]
        if e < self.best:
            self.best = e
        self.history.append(math.sqrt(self.best))

    def descend(self, q: Array) -> tuple[Array, float, bool]:
        """Phase 1 (and 3) from ``q``: (q, ‖r‖², converged); sets :attr:`slide_needed`."""
        f = self.f.lm
        q_in, lam_in = f.arg["q"][0], f.arg["lam"][0]
        q_out = f.res["q_next"][0]
        lam_out, e_out, step_out = (f.res[k].reshape(-1) for k in ("lam_next", "e_next", "step"))
        q_in[:] = q
        lam_in[0] = LAMBDA0
        prev, stall, e = math.inf, 0, math.inf
        e_tol = self.e_tol
        while self.budget > 0:  # one call: UNROLL iterations
            f()
            e, step, lam = float(e_out[0]), float(step_out[0]), float(lam_out[0])
            q_in[:] = q_out
            lam_in[0] = lam
            self._count("lm", e)
            if e <= e_tol and step <= STEP_TOL:
                self.slide_needed = f.res["slide"][0, 0] > SLIDE_TOL
                return q_in.copy(), e, True
            stall = stall + 1 if e >= (1 - STALL_DECREASE) * prev else 0
            prev = min(prev, e)
            if stall >= STALL_CALLS or lam >= LAMBDA_MAX:
                break
        return q_in.copy(), e, e <= e_tol

    def slide_toward(self, q: Array) -> tuple[Array, bool]:
        """Phase 2 from a solution ``q``: (q, whether it moved).

        Each slide tries the Newton step alone first; the full set of candidates only where
        it was refused while the pull toward ``q0`` is still there (far from the end).
        """
        newton, full = self.f.newton, self.f.slide
        moved = False
        while self.budget > 0:
            f = newton
            f.arg["q"][0] = q
            f()
            self._count("newton", f.res["e_next"][0, 0])
            if f.res["step"][0, 0] == 0 and f.res["pull"][0, 0] > SLIDE_TOL:
                f = full
                f.arg["q"][0] = q
                f()
                self._count("slide", f.res["e_next"][0, 0])
            step = f.res["step"][0, 0]
            q = f.res["q_next"][0].copy()
            moved = moved or step > 0
            if step <= SLIDE_TOL:
                break
        return q, moved

    def start(self, q: Array) -> tuple[Array, float]:
        """All three phases from one start: (q, ‖r‖²)."""
        q, e, converged = self.descend(q)
        if not (converged and self.nearest and self.slide_needed):
            return q, e
        slid, moved = self.slide_toward(q)
        if moved:
            polished, e_p, ok = self.descend(slid)
            if ok:
                return polished, e_p
        return q, e


@dataclass
class Search:
    """Outcome of :func:`lm_search` over several starts.

    Attributes:
        q: (nq,) the best configuration found; ``e`` its ‖r‖² [weighted m², rad²].
        converged: ``e`` is at the convergence threshold.
        within: ``e`` is within the caller's tol (:func:`within_tol`), converged or not.
        iterations: iterations over all starts and phases; ``evaluations`` FK evaluations.
        starts: the starts used.
        history: √‖r‖² (the task cost), best so far, after each Function call
            (``UNROLL`` iterations of phase 1 or 3, or one slide).
    """

    q: Array
    e: float
    converged: bool
    within: bool
    iterations: int
    evaluations: int
    starts: int
    history: list[float]


def lm_search(robot: Robot, target: Target, q_ref: Array, starts: Iterable[Array], *,
              tol: float, max_iter: int, jit: bool = True, box: Array | None = None,
              c_loop: bool = True, nearest: bool = True) -> Search:
    """The three phases from each start in turn, until one converges or ends within tol.

    Args:
        robot: the robot.
        target: the (checked) target.
        q_ref: (nq,) ``q0``, the configuration the slide pulls toward.
        starts: start configurations (nq,) within the limits, drawn lazily in order.
        tol: residual [m, rad] the caller judges against.
        max_iter: iterations per start.
        jit: the iterations compiled to C (see :func:`step_function`).
        box: ``limits(robot)[0]`` if the caller has it already.
        c_loop: run each start's loop in C where the phases are compiled
            (:func:`phase_driver`; the same numbers as the Python loop, ``False``).
        nearest: slide to the solution nearest ``q_ref`` (phases 2 and 3); ``False``: stop
            at the solution phase 1 reaches.

    Returns:
        Search: the best configuration over the starts tried.
    """
    f = phase_arrays(robot, target.kind, 1, jit)
    fill_params(f.par[0], target, q_ref, 0.0)
    f.box[0] = limits(robot)[0] if box is None else box
    return search_filled(robot, target.kind, residual_tol(target.weights, tol), q_ref, starts,
                         max_iter=max_iter, jit=jit, c_loop=c_loop, nearest=nearest)


def search_filled(robot: Robot, kind: str, e_tol: float, q_ref: Array,
                  starts: Iterable[Array], *, max_iter: int, jit: bool = True,
                  c_loop: bool = True, nearest: bool = True) -> Search:
    """:func:`lm_search` once this thread's one-target arrays hold the target and limits.

    The arrays: ``phase_arrays(robot, kind, 1, jit)``, its ``par[0]`` and ``box[0]``.
    ``e_tol``: the convergence threshold on ‖r‖² (:func:`residual_tol`). For
    :func:`~scara_opt.ik.lm_batch.solve_many`, which fills them from its own rows.
    """
    driver = phase_driver(robot, kind, jit) if c_loop else None
    run = _Run(phase_arrays(robot, kind, 1, jit), e_tol, nearest) if driver is None \
        else driver.reset(e_tol, max_iter, nearest)
    best_q, best_e, n = q_ref, math.inf, 0
    e_within = within_tol(e_tol)
    for start in starts:
        n += 1
        run.budget = max_iter
        q, e = run.start(np.asarray(start, dtype=float))
        if e < best_e:
            best_q, best_e = q, e
        if best_e <= e_within:
            break
    return Search(best_q, best_e, best_e <= e_tol, best_e <= e_within, run.iterations,
                  run.evaluations, n, run.history)


def random_starts(robot: Robot, rng: np.random.Generator, n: int) -> Iterator[Array]:
    """``n`` configurations drawn uniformly within the limits, lazily.

    Unbounded joints (continuous, limits ±inf) are drawn within [-π, π]
    (:attr:`~scara_opt.Robot.sampling_lower`, ``sampling_upper``).
    """
    if n <= 0:
        return
    lo, hi = robot.sampling_lower, robot.sampling_upper
    for _ in range(n):
        yield rng.uniform(lo, hi)


def search_output(found: Search, message: str = "") -> SolverOutput:
    """The :class:`SolverOutput` of a :class:`Search` (the base judges its residual)."""
    if not message and not found.within:
        message = f"Levenberg–Marquardt missed from {found.starts} starts"
    return SolverOutput(q=found.q, iterations=found.iterations, evaluations=found.evaluations,
                        history=np.asarray(found.history), message=message)


def check_budget(options: dict[str, Any]) -> None:
    """The fast solver's budget options: restarts and max_iter in range, jit a bool.

    Raises:
        InputError: the message names the option, its value and the range.
    """
    check_number("restarts", options["restarts"], 0, MAX_RESTARTS, integer=True)
    check_number("max_iter", options["max_iter"], 1, MAX_ITER, integer=True)
    check_flag("jit", options["jit"])


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
    """

    name = "lm"
    label = "LM"
    defaults: ClassVar[dict[str, Any]] = {"restarts": 50, "max_iter": 100, "jit": True,
                                          "nearest": True}

    def check_options(self) -> None:
        """restarts >= 0 and max_iter >= 1 (integers), jit and nearest bools."""
        check_budget(self.options)
        check_flag("nearest", self.options["nearest"])

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build the phases' Functions and this thread's arrays (cached on the robot)."""
        phase_arrays(robot, kind, 1, bool(self.options["jit"]))

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        box, q_default = limits(robot)
        q_ref = q_default if q0 is None else q0
        starts = chain([q_ref], random_starts(robot, rng, int(self.options["restarts"])))
        opts = self.options
        return search_output(lm_search(robot, target, q_ref, starts, tol=tol,
                                       max_iter=int(opts["max_iter"]), jit=bool(opts["jit"]),
                                       box=box, nearest=bool(opts["nearest"])))
