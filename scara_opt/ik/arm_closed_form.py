r"""Every branch of a 6R arm's closed form (IK-Geo's subproblems), compiled once per machine.

For an arm of :mod:`~scara_opt.ik.arm_geometry`'s cases, one casadi SX Function maps a
full pose :math:`T^*`, the held joint's value ``s`` (7R arms), ``q0`` and the limits to the
closed form's 8 branches (Elias and Wen 2022, Algorithms 6–8, with SP1–SP4 of
:mod:`~scara_opt.ik.subproblems`):

* three parallel axes and two meeting (UR): :math:`q_1` by SP4
  (:math:`h_2^T R_{01}^T p_{16} = h_2^T (p_{12} + p_{23} + p_{34} + p_{45})`),
  :math:`q_5` by SP4, :math:`q_2 + q_3 + q_4` and :math:`q_6` by SP1, :math:`q_3` by SP3,
  :math:`q_2` by SP1;
* a spherical wrist: the wrist centre from :math:`q_1, q_2, q_3` (SP3 then SP2 where
  :math:`h_1` meets :math:`h_2`; SP4, SP3, SP1 where :math:`h_2 ∥ h_3`), then
  :math:`q_5` by SP4 and :math:`q_4, q_6` by SP1.

Each branch's angles are then turned, joint by joint, to the whole turn nearest ``q0``
within the limits (a branch no turn brings within a joint's limits is marked out), and
its residual is computed by the robot's own FK in the same Function (position [m] and
rotation angle [rad], the verdict's measure), so the caller keeps only the branches the
FK confirms. Compiled to C once per machine and kept (:mod:`scara_opt.model.compiled`;
casadi's virtual machine where no compiler works).
"""

from __future__ import annotations

import math
import threading
from pathlib import Path

import casadi as ca
import numpy as np

from scara_opt.ik import arm_geometry, subproblems
from scara_opt.ik.arm_geometry import ArmCase, ArmModel
from scara_opt.ik.subproblems import rot, sp1, sp2, sp3, sp4
from scara_opt.ik.task import LIMIT_SLACK
from scara_opt.model import symbolic
from scara_opt.model.batch_fk import kinematic_key
from scara_opt.model.buffers import FunctionArrays
from scara_opt.model.compiled import compiled, source_hash
from scara_opt.model.robot import Array, Robot

#: branches of every closed form here (2 × 2 × 2)
BRANCHES = 8
#: the distance reported for a branch no whole turn brings within the limits
OUT = 1e300
_CODE = source_hash(arm_geometry.__file__, subproblems.__file__, symbolic.__file__,
                    str(Path(__file__)))


def _three_parallel(H: Array, P: Array, R: ca.SX, p: ca.SX) -> list[list[ca.SX]]:
    """The 8 branches of ``three_parallel_two_intersecting`` for the pose ``(R, p)``."""
    h1, h2, h3, _, h5, h6 = H
    p16 = p - P[0] - R @ P[6]
    out = []
    for q1 in sp4(h2, p16, -h1, float(h2 @ (P[1] + P[2] + P[3] + P[4]))):
        R1t = rot(h1, q1).T
        for q5 in sp4(h2, h6, h5, ca.dot(ca.SX(h2), R1t @ R @ h6)):
            R45 = rot(h5, q5)
            t14 = sp1(R45 @ h6, R1t @ R @ h6, h2)
            R14 = rot(h2, t14)
            q6 = sp1(h5, R45.T @ R14.T @ R1t @ R @ h5, h6)
            inner = R1t @ p16 - P[1] - R14 @ (P[4] + P[5])
            for q3 in sp3(P[3], -P[2], h3, ca.norm_2(inner)):
                q2 = sp1(P[2] + rot(h3, q3) @ P[3], inner, h2)
                out.append([q1, q2, q3, t14 - q2 - q3, q5, q6])
    return out


def _spherical(H: Array, P: Array, R: ca.SX, p: ca.SX, case: str) -> list[list[ca.SX]]:
    """The 8 branches of a spherical-wrist case for the pose ``(R, p)``."""
    h1, h2, h3, h4, h5, h6 = H
    p16 = p - P[0] - R @ P[6]  # the wrist centre, from the shoulder's first point
    arms: list[tuple[ca.SX, ca.SX, ca.SX]] = []
    if case == "spherical_two_intersecting":  # |p16| fixes q3; then (q1, q2) by SP2
        for q3 in sp3(P[3], -P[2], h3, ca.norm_2(p16)):
            v = P[2] + rot(h3, q3) @ P[3]
            for q1, q2 in sp2(p16, v, -h1, h2):
                arms.append((q1, q2, q3))
    else:  # h2 ∥ h3: q1 keeps the wrist centre's height along h2
        for q1 in sp4(h2, p16, -h1, float(h2 @ (P[1] + P[2] + P[3]))):
            u = rot(h1, q1).T @ p16 - P[1]
            for q3 in sp3(P[3], -P[2], h3, ca.norm_2(u)):
                arms.append((q1, sp1(P[2] + rot(h3, q3) @ P[3], u, h2), q3))
    out = []
    for q1, q2, q3 in arms:
        R36 = (rot(h1, q1) @ rot(h2, q2) @ rot(h3, q3)).T @ R
        for q5 in sp4(h4, h6, h5, ca.dot(ca.SX(h4), R36 @ h6)):
            q4 = sp1(rot(h5, q5) @ h6, R36 @ h6, h4)
            q6 = sp1(rot(-h5, q5) @ h4, R36.T @ h4, -h6)
            out.append([q1, q2, q3, q4, q5, q6])
    return out


def solve_case(arm: ArmCase, R: ca.SX, p: ca.SX) -> list[ca.SX]:
    """The 8 branches (6,) each of the chain ``arm`` for :math:`G = (R, p)`.

    In the chain's own joint order and signs (``arm.sign`` undone, ``arm.reversed`` read
    back).
    """
    if arm.reversed:
        R, p = R.T, -R.T @ p
    rows = (_three_parallel(arm.H, arm.P, R, p) if arm.case == arm_geometry.CASES[0]
            else _spherical(arm.H, arm.P, R, p, arm.case))
    out = []
    for row in rows:
        q = ca.vertcat(*[float(s) * v for s, v in zip(arm.sign, row, strict=True)])
        out.append(q[::-1] if arm.reversed else q)
    return out


def _pose_to_chain(model: ArmModel, R: ca.SX, p: ca.SX, s: ca.SX) -> tuple[ca.SX, ca.SX]:
    """:math:`G` of the 6R chain for the robot's target ``(R, p)`` and held value ``s``."""
    M = model.home
    RG = R @ M[:3, :3].T
    pG = p - RG @ M[:3, 3]
    if model.held is None:
        return RG, pG
    E = rot(model.held_axis, -s)  # e^{-ξ s} = (E, (I - E) o)
    e = (ca.SX.eye(3) - E) @ model.held_point
    if model.held == 0:  # G = e^{-ξ1 s} T* M^-1
        return E @ RG, E @ pG + e
    return RG @ E, RG @ e + pG  # G = T* M^-1 e^{-ξ7 s}


def _turned(v: ca.SX, ref: ca.SX, lo: ca.SX, hi: ca.SX) -> tuple[ca.SX, ca.SX]:
    """``v + 2πm`` nearest ``ref`` within ``[lo, hi]``, and 1 where some ``m`` fits, else 0.

    A value beyond a limit by at most ``LIMIT_SLACK`` (round-off of a configuration at the
    limit) fits, and is put on the limit.
    """
    turn = 2 * math.pi
    first = ca.ceil((lo - LIMIT_SLACK - v) / turn)
    last = ca.floor((hi + LIMIT_SLACK - v) / turn)
    m = ca.fmin(ca.fmax(ca.floor((ref - v) / turn + 0.5), first), last)
    return ca.fmin(ca.fmax(v + turn * m, lo), hi), first <= last


def _branches(robot: Robot, model: ArmModel, R: ca.SX, p: ca.SX, s: ca.SX, q0: ca.SX,
              lo: ca.SX, hi: ca.SX) -> list[tuple[ca.SX, ca.SX, ca.SX]]:
    """Per branch: ``q`` (nq,) turned nearest ``q0``, its FK residual, and whether it fits.

    ``fits`` is 1 where some whole turn of every joint fits the limits, else 0.
    """
    RG, pG = _pose_to_chain(model, R, p, s)
    out = []
    for chain_q in solve_case(model.arm, RG, pG):
        q, fits = ca.SX.zeros(robot.nq), ca.SX(1)
        for k in range(robot.nq):
            v = s if k == model.held else chain_q[model.joints.index(k)]
            turned, ok = _turned(v, q0[k], lo[k], hi[k])
            q[k] = turned
            fits = fits * ok
        _, pq, Rq = symbolic.chain_walk(robot.chain, robot.tip_placement, q)
        frob = ca.norm_fro(Rq - R)
        angle = 2 * ca.asin(ca.fmin(frob / (2 * math.sqrt(2)), 1.0))
        out.append((q, ca.fmax(ca.norm_2(pq - p), angle), fits))
    return out


def _symbols(nq: int) -> tuple[ca.SX, ...]:
    """The inputs ``R`` (9,), ``p``, ``s``, ``q0``, ``lo``, ``hi``, ``tol``."""
    return (ca.SX.sym("R", 9), ca.SX.sym("p", 3), ca.SX.sym("s"),
            *(ca.SX.sym(n, nq) for n in ("q0", "lo", "hi")), ca.SX.sym("tol"))


_IN = ["R", "p", "s", "q0", "lo", "hi", "tol"]


def build_function(robot: Robot, model: ArmModel, name: str) -> ca.Function:
    """The closed form of ``model`` as one Function, every branch checked by the FK.

    ``(R (9,), p (3,), s, q0 (nq,), lo (nq,), hi (nq,), tol) -> (Q (8 nq,), err (8,),
    dist (8,), best)``: every branch turned nearest ``q0``, its FK residual and its
    distance to ``q0`` (:data:`OUT` where no turn fits the limits), ``Q`` branch after
    branch; ``best``: the nearest branch within ``tol`` and the limits, -1 if none.
    ``R`` column after column (numpy: ``R.ravel(order="F")``).
    """
    ins = _symbols(robot.nq)
    Rv, p, s, q0, lo, hi, tol = ins
    rows = _branches(robot, model, ca.reshape(Rv, 3, 3), p, s, q0, lo, hi)
    Qs = [q for q, _, _ in rows]
    errs = [e for _, e, _ in rows]
    dists = [ca.if_else(fits, ca.norm_2(q - q0), OUT) for q, _, fits in rows]
    best, score = ca.SX(-1), ca.SX(OUT)
    for k, (e, d) in enumerate(zip(errs, dists, strict=True)):
        better = (e <= tol) * (d < score)
        best, score = ca.if_else(better, k, best), ca.if_else(better, d, score)
    outputs = [ca.vertcat(*Qs), ca.vertcat(*errs), ca.vertcat(*dists), best]
    if hasattr(ca, "cse"):
        outputs = ca.cse(outputs)
    return ca.Function(name, list(ins), outputs, _IN, ["Q", "err", "dist", "best"])


#: Gauss–Newton steps of :func:`build_slide` over the held joint
SLIDE_STEPS = 6
#: the largest step of the held joint in one of them [rad]
SLIDE_STEP = 0.5


def build_slide(robot: Robot, model: ArmModel, branch: int, name: str) -> ca.Function:
    r"""Along one branch of a 7R arm, the held joint moved to the solution nearest ``q0``.

    The branch's solutions as the held joint :math:`s` varies form a curve :math:`q(s)`;
    :data:`SLIDE_STEPS` safeguarded Gauss–Newton steps on
    :math:`\tfrac12 \|W (q(s) - q_0)\|^2` (``W``: the inverse joint ranges, the fast
    solver's scaling), :math:`Δs = -g / h` with :math:`g = (W^2 (q - q_0)) · q'`,
    :math:`h = \|W q'\|^2`, at most :data:`SLIDE_STEP`, within the held joint's limits; a
    step is kept only where the new point is a solution within ``tol`` and the limits
    and nearer, else the next tries a quarter of it.

    ``(R, p, s, q0, lo, hi, tol, w (nq,)) -> (q (nq,), err, held)``: the point reached (its
    residual; ``held`` its held joint's value).
    """
    ins = _symbols(robot.nq)
    Rv, p, s, q0, lo, hi, tol = ins
    w = ca.SX.sym("w", robot.nq)
    R = ca.reshape(Rv, 3, 3)
    sym = ca.SX.sym("t")
    q_t, e_t, fits_t = _branches(robot, model, R, p, sym, q0, lo, hi)[branch]
    at = ca.Function("at", [sym, Rv, p, q0, lo, hi],
                     [q_t, ca.jacobian(q_t, sym), e_t, fits_t])
    held = model.held
    if held is None:
        raise ValueError("build_slide serves a 7R arm with a held joint")
    h_lo, h_hi = lo[held], hi[held]
    q, dq, e, _ = at(s, Rv, p, q0, lo, hi)
    f = 0.5 * ca.sumsqr(w * (q - q0))
    scale = ca.SX(1.0)
    for _ in range(SLIDE_STEPS):
        g = ca.dot(w * w * (q - q0), dq)
        h = ca.sumsqr(w * dq) + 1e-12
        step = ca.fmin(ca.fmax(-scale * g / h, -SLIDE_STEP), SLIDE_STEP)
        s_new = ca.fmin(ca.fmax(s + step, h_lo), h_hi)
        q_new, dq_new, e_new, fits_new = at(s_new, Rv, p, q0, lo, hi)
        f_new = 0.5 * ca.sumsqr(w * (q_new - q0))
        ok = (e_new <= tol) * fits_new * (f_new < f)
        s, e, f = (ca.if_else(ok, a, b) for a, b in ((s_new, s), (e_new, e), (f_new, f)))
        q = ca.if_else(ok, q_new, q)
        dq = ca.if_else(ok, dq_new, dq)
        scale = ca.if_else(ok, 1.0, 0.25 * scale)
    outputs = [q, e, s]
    if hasattr(ca, "cse"):
        outputs = ca.cse(outputs)
    return ca.Function(name, [*ins, w], outputs, [*_IN, "w"], ["q", "err", "held"])


def slide_arrays(robot: Robot, model: ArmModel, branch: int,
                 jit: bool = True) -> FunctionArrays:
    """This thread's arrays for :func:`build_slide` of ``branch`` (limits, weights filled in).

    Compiled once per machine and kept, as :func:`arm_function`.
    """
    cache: dict[tuple, FunctionArrays] = robot.__dict__.setdefault("_arm_slides", {})
    key = (branch, jit, threading.get_ident())
    f = cache.get(key)
    if f is None:
        funcs: dict[tuple, ca.Function] = robot.__dict__.setdefault("_arm_slide_functions", {})
        if (branch, jit) not in funcs:
            key_k = kinematic_key(robot)
            name = f"scara_opt_arm_slide{branch}_{key_k[:12]}"

            def build() -> ca.Function:
                return build_slide(robot, model, branch, name)

            funcs[(branch, jit)] = compiled(name, f"{key_k} slide {branch} {_CODE}", build) \
                if jit else build()
        f = cache[key] = FunctionArrays(funcs[(branch, jit)], 1)
        f.arg["lo"][:] = robot.lower
        f.arg["hi"][:] = robot.upper
        span = robot.upper - robot.lower
        f.arg["w"][:] = 1.0 / np.where(np.isfinite(span), span, 1.0)
    return f


def arm_function(robot: Robot, model: ArmModel, n: int = 1, jit: bool = True) -> ca.Function:
    """:func:`build_function` compiled once per machine (mapped over ``n`` poses), cached."""
    cache: dict[tuple, ca.Function] = robot.__dict__.setdefault("_arm_functions", {})
    if (n, jit) not in cache:
        if (1, jit) not in cache:
            key = kinematic_key(robot)
            name = f"scara_opt_arm_{key[:12]}"

            def build() -> ca.Function:
                return build_function(robot, model, name)

            cache[(1, jit)] = compiled(name, f"{key} arm {_CODE}", build) if jit else build()
        cache[(n, jit)] = cache[(1, jit)] if n == 1 else cache[(1, jit)].map(n)
    return cache[(n, jit)]


def arm_arrays(robot: Robot, model: ArmModel, n: int = 1, jit: bool = True) -> FunctionArrays:
    """This thread's arrays for :func:`arm_function` over ``n`` poses (limits filled in)."""
    cache: dict[tuple, FunctionArrays] = robot.__dict__.setdefault("_arm_arrays", {})
    key = (n, jit, threading.get_ident())
    f = cache.get(key)
    if f is None:
        f = cache[key] = FunctionArrays(arm_function(robot, model, n, jit), n)
        f.arg["lo"][:] = robot.lower
        f.arg["hi"][:] = robot.upper
    return f
