"""The verdict: every solver's answer is judged here, the same way, with its evidence.

A solver returns its best configuration (:class:`SolverOutput`); :func:`judge` recomputes
the residual from the robot's FK and grants a status only with evidence:

1. ``solved`` (``reached``): the residual is within ``tol``;
2. ``max_iter`` (``budget``): the closed form's exact solution (a witness) reaches the
   target, so it is reachable; ``failed`` (``held_joints``) instead when the solver reports
   that only the joints the caller held make it infeasible;
3. ``unreachable``: a :class:`~scara_opt.ik.result.Certificate` proves that no
   configuration within the limits reaches the target within ``tol``
   (:func:`scara_opt.ik.certificates.certify`; its reason and numbers go into the result);
4. ``max_iter`` (``budget``): the solver's own ``search`` finds a witness where no closed
   form applies (the metaheuristics run the exact ``auto`` method with the caller's seed and
   ``q0``);
5. ``failed`` (``no_certificate``): neither proof exists; the best residual is reported.

A configuration outside the joint limits is a solver bug: it is reported as ``failed``
(``solver_error``) at the nearest in-limit configuration, never passed on. Everything here
is deterministic, so the same call gives the same verdict.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from scara_opt.ik.certificates import certify
from scara_opt.ik.closed_form import witness
from scara_opt.ik.result import (
    STATUS_MESSAGES,
    IKResult,
    Reason,
    SolverOutput,
    Status,
)
from scara_opt.ik.task import LIMIT_SLACK, config_errors, cost_of, error_from
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

#: a solver's search for a witness: q (nq,) reaching the target, or None
WitnessSearch = Callable[[], "Array | None"]


def _describe_miss(dp: Array, dang: float | None, tol: float) -> str:
    """Which coordinates miss, e.g. "misses along z (dz = +0.102 m)"."""
    axes = [axis for axis, v in zip("xyz", dp, strict=True) if abs(v) > tol]
    parts = [f"d{axis} = {dp['xyz'.index(axis)]:+.4g} m" for axis in axes]
    if dang is not None and abs(dang) > tol:
        axes.append("the tool angle")
        parts.append(f"dangle = {dang:+.4g} rad")
    if not axes:
        return "no single coordinate above tol"
    return f"misses along {', '.join(axes)} ({', '.join(parts)})"


def residual(robot: Robot, target: Target, q: Array) -> float:
    """The honest residual max(|Δp| [m], |Δangle| [rad]) of ``q`` by the robot's FK."""
    return error_from(*config_errors(robot, target, q))


def classify_miss(robot: Robot, target: Target, tol: float, *, held: bool = False,
                  search: WitnessSearch | None = None) -> tuple[Status, Reason, str]:
    """Status, reason and evidence for a target a solver did not reach within ``tol``.

    Args:
        robot: the robot.
        target: the checked target.
        tol: the tolerance [m, rad].
        held: the solver found the target infeasible with the caller's held joints.
        search: the solver's own witness search (see the module docstring), or ``None``.
    """
    q = witness(robot, target)  # the closed form first: a reachable target has no certificate
    if q is not None and residual(robot, target, q) <= tol:
        if held:
            return Status.FAILED, Reason.HELD_JOINTS, (
                "not reachable with the joints held by the caller; the closed form reaches it "
                "with them free (release fixed= or choose other values)")
        return Status.MAX_ITER, Reason.BUDGET, (
            "reachable: the closed form reaches it (q = "
            f"{np.array2string(q, precision=4, separator=', ')})")
    cert = certify(robot, target, tol)
    if cert is not None:
        return Status.UNREACHABLE, cert.reason, f"proof: {cert.detail}"
    if search is not None:
        q = search()
        if q is not None and (err := residual(robot, target, q)) <= tol:
            return Status.MAX_ITER, Reason.BUDGET, (
                f"reachable: the exact method 'auto' reaches it to {err:.2g} (q = "
                f"{np.array2string(q, precision=4, separator=', ')})")
    return Status.FAILED, Reason.NO_CERTIFICATE, (
        "no configuration within tol was found, and no proof that none exists (the "
        "target is within the chain's reach bound); try more restarts or another q0")


def _in_limits(robot: Robot, out: SolverOutput) -> tuple[Array, bool, str]:
    """The solver's ``q`` within the limits (a new array), whether it was a bug, the message.

    Within the limits: ``q`` as it is (a float (nq,) array the clip leaves bit for bit,
    :meth:`~scara_opt.model.robot.Robot.fits_limits`, is copied: ~1.5 µs less per solve).
    Outside by up to :data:`LIMIT_SLACK` (round-off): clipped. Farther, or NaN: a solver
    bug, reported at the nearest in-limit point of ``nan_to_num(q)``.
    """
    extra = out.message
    if robot.fits_limits(out.q):
        return out.q.copy(), False, extra
    lower, upper = robot.lower, robot.upper
    q_out = np.asarray(out.q, dtype=float)
    q = np.minimum(np.maximum(q_out, lower), upper)  # np.clip, without its overhead
    over = float(np.abs(q - q_out).max())  # NaN if q_out has NaN
    bug = not over <= LIMIT_SLACK
    if bug:  # a solver bug must not leak: report failure at the closest in-limit point
        extra = f"solver returned q outside the limits by {over:.3g}; " + extra
        q = np.clip(np.nan_to_num(q_out), lower, upper)
    return q, bug, extra


def judge(robot: Robot, target: Target, out: SolverOutput, *, tol: float, method: str,
          seed: int | None, time_s: float, setup_s: float = 0.0,
          search: WitnessSearch | None = None) -> IKResult:
    """The :class:`IKResult` of a solver's output: residual, status and evidence.

    Args:
        robot: the robot.
        target: the checked target.
        out: what the solver returned.
        tol: residual [m, rad] below which the target counts as reached.
        method: the solver's registry name.
        seed: the seed it used.
        time_s: its search time [s].
        setup_s: its one-off setup time in this call [s].
        search: its witness search for a missed target (see :func:`classify_miss`).
    """
    q, bug, extra = _in_limits(robot, out)
    dp, dang = config_errors(robot, target, q)
    error = error_from(dp, dang)
    if error <= tol:
        status, reason, evidence = Status.SOLVED, Reason.REACHED, ""
    elif bug:
        status, reason, evidence = Status.FAILED, Reason.SOLVER_ERROR, ""
    else:
        status, reason, evidence = classify_miss(robot, target, tol, held=out.held,
                                                 search=search)
    message = STATUS_MESSAGES[status]
    solved = status is Status.SOLVED
    if not solved:
        message += f"; residual {error:.4g} ({_describe_miss(dp, dang, tol)}), tol {tol:g}"
    if evidence:
        message += f"; {evidence}"
    if extra:
        message += f"; {extra}"
    return IKResult._new(q=q, success=solved, status=status, message=message,
                         position_error=dp, yaw_error=dang, error=error,
                         cost=cost_of(target, dp, dang), iterations=int(out.iterations),
                         evaluations=int(out.evaluations), time_s=time_s,
                         history=np.asarray(out.history, dtype=float), method=method,
                         seed=seed, tol=tol, reason=reason, evidence=evidence, setup_s=setup_s,
                         route=out.route)
