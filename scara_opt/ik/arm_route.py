"""Full-pose IK of 6R and 7R arms by their closed form: the nearest solution, or every one.

For a robot :func:`~scara_opt.ik.arm_geometry.arm_model` serves and a full-pose target
(a rotation), :mod:`~scara_opt.ik.arm_closed_form` gives 8 branches per pose (per value of
the held joint of a 7R arm); each branch the FK confirms within ``tol`` is a solution, and
one within :data:`POLISH` of the target (the closed form's round-off near a singularity,
or a geometry a hair off the case's) is polished by the fast solver
(:mod:`~scara_opt.ik.lm_search`) from it, its residual judged again.

* :func:`nearest_solution`: the solution nearest ``q0`` (the held joint at ``q0``'s value),
  for ``solve_ik``'s ``lm`` and ``auto``;
* :func:`all_solutions`: every distinct solution within the limits, every whole turn of
  each joint included (a UR's ±2π joints give up to 8 × 2⁵), for :func:`~scara_opt.ik_all`
  and :func:`~scara_opt.ik_path`. A 7R arm's held joint is sampled at ``samples`` values
  evenly over its range (both ends included), or held at a value the caller gives.

Arms it does not serve (a general 6R, a 7R whose end joints held leave no case, targets
that are not full poses) take the multi-start (:func:`multi_start_solutions`): the
distinct solutions the fast solver reaches from ``q0`` and seeded random starts, which
need not be all. Every result says which route it took (:attr:`~scara_opt.IKResult.route`).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from scara_opt.ik.arm_closed_form import (
    BRANCHES,
    OUT,
    SLIDE_STEPS,
    arm_arrays,
    slide_arrays,
)
from scara_opt.ik.arm_geometry import ArmModel, arm_model
from scara_opt.ik.lm_functions import limits
from scara_opt.ik.lm_search import lm_search, random_starts
from scara_opt.ik.result import SolverOutput
from scara_opt.ik.turns import TURN
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target

#: a branch whose residual is within this [m, rad] (and above tol) is polished by LM: the
#: closed form's round-off near a singularity reaches 1e-2 (a UR5 with the wrist 6e-7 rad
#: and the elbow 1e-4 rad from singular: 0.008 and 0.029), a branch that does not exist
#: misses by more, typically (a polish that converges is a solution all the same)
POLISH = 0.05
#: LM iterations of a polish (a branch within POLISH converges in 2-4)
POLISH_ITER = 30
#: solutions closer than this in every joint are the same [rad]
DISTINCT = 1e-6
#: values of a 7R arm's held joint that ik_all samples by default
SAMPLES = 32
#: the step [rad] of solve_ik's scan of the held joint where q0's value reaches no branch
SCAN_STEP = 0.5
#: starts of the multi-start route (q0 first, then seeded uniform ones)
MULTI_STARTS = 32
MULTI_START = "multi-start"


def served(robot: Robot, target: Target) -> ArmModel | None:
    """The arm model when the closed form serves ``target`` on ``robot``, else ``None``."""
    if target.rotation is None:
        return None
    return arm_model(robot)


def route_label(robot: Robot, model: ArmModel, sampled: Array | None = None) -> str:
    """``"analytic (<case>)"``, naming the held joint and how it was set on a 7R arm."""
    text = model.label
    if model.held is not None:
        name = robot.joint_names[model.held]
        if sampled is None:
            text += f"; {name} held at q0's value"
        elif len(sampled) == 1:
            text += f"; {name} held at {float(sampled[0]):.6g} rad"
        else:
            text += (f"; {name} sampled at {len(sampled)} values evenly over "
                     f"[{float(sampled[0]):.4g}, {float(sampled[-1]):.4g}] rad")
    return f"analytic ({text})"


def _evaluate(robot: Robot, model: ArmModel, target: Target, q_ref: Array, s: float,
              tol: float, jit: bool) -> dict[str, Array]:
    """The closed form's outputs for one pose (this thread's arrays: read them at once)."""
    f = arm_arrays(robot, model, 1, jit)
    arg = f.arg
    arg["R"][0] = target.rotation.ravel(order="F")  # type: ignore[union-attr]
    arg["p"][0] = target.position
    arg["s"][0] = s
    arg["q0"][0] = q_ref
    arg["tol"][0] = tol
    f()
    return f.res


def branches(robot: Robot, model: ArmModel, target: Target, q_ref: Array, s: float = 0.0,
             jit: bool = True) -> tuple[Array, Array, Array]:
    """The 8 branches (8, nq) turned nearest ``q_ref``, residuals (8,), distances (8,).

    The distance to ``q_ref`` is ``OUT`` where a joint's limits fit no turn; ``s``: the
    held joint's value (7R arms).
    """
    res = _evaluate(robot, model, target, q_ref, s, 0.0, jit)
    return res["Q"][0].reshape(8, robot.nq).copy(), res["err"][0].copy(), res["dist"][0].copy()


def polish(robot: Robot, target: Target, q: Array, tol: float, jit: bool = True,
           held: int | None = None) -> Array | None:
    """``q`` taken to within ``tol`` by the fast solver (minimum-norm steps), or ``None``.

    Joint ``held`` keeps its value (both its bounds set to it: the solver's box holds it).
    """
    box = limits(robot)[0]
    if held is not None:
        box = box.copy()
        box[held] = box[robot.nq + held] = q[held]
    found = lm_search(robot, target, q, [q], tol=tol, max_iter=POLISH_ITER, jit=jit,
                      box=box, nearest=False)
    return found.q if found.within else None


def nearest_solution(robot: Robot, model: ArmModel, target: Target, q_ref: Array, tol: float,
                     jit: bool = True) -> tuple[Array, int, bool] | None:
    """The closed-form solution nearest ``q_ref`` within the limits, or ``None``.

    A 7R arm's held joint keeps ``q_ref``'s value; where no branch reaches the pose
    there, it moves outward in steps of :data:`SCAN_STEP` either way (within its limits)
    to the first value where one does. Where no branch is within ``tol``, the nearest one within
    :data:`POLISH` is polished (``None`` if that fails too).

    Returns:
        ``(q, branch, scanned)``: the solution (nq,); its branch (each joint at its whole
        turn nearest ``q_ref``), or -1 where it was polished (its turns as the polish left
        them); whether the held joint came from the scan.
    """
    s = 0.0 if model.held is None else float(q_ref[model.held])
    res = _evaluate(robot, model, target, q_ref, s, tol, jit)
    best = int(res["best"][0, 0])
    nq = robot.nq
    if best >= 0:  # the compiled choice: the nearest branch within tol and the limits
        return res["Q"][0, best * nq:(best + 1) * nq].copy(), best, False
    Q, err, dist = res["Q"][0].reshape(8, nq).copy(), res["err"][0].copy(), res["dist"][0].copy()
    if model.held is not None:
        found = _scan(robot, model, target, q_ref, tol, jit)
        if found is not None:
            return (*found, True)
    near = (dist < OUT) & (err <= POLISH)
    for k in np.argsort(np.where(near, dist, np.inf))[:int(near.sum())]:
        q = polish(robot, target, Q[k], tol, jit)
        if q is not None:
            return q, -1, False
    return None


def _scan(robot: Robot, model: ArmModel, target: Target, q_ref: Array, tol: float,
          jit: bool) -> tuple[Array, int] | None:
    """The nearest solution at the first held value, outward from ``q_ref``'s, that has one.

    In steps of :data:`SCAN_STEP` either way within the held joint's limits; ``None``
    where no value reaches the pose.
    """
    k = model.held
    if k is None:  # pragma: no cover - called for 7R arms only
        return None
    lo, hi = robot.sampling_lower[k], robot.sampling_upper[k]
    s0 = float(q_ref[k])
    for m in range(1, int((hi - lo) / SCAN_STEP) + 2):
        for s in (s0 + m * SCAN_STEP, s0 - m * SCAN_STEP):
            if not lo <= s <= hi:
                continue
            res = _evaluate(robot, model, target, q_ref, s, tol, jit)
            best = int(res["best"][0, 0])
            if best >= 0:
                return res["Q"][0, best * robot.nq:(best + 1) * robot.nq].copy(), best
    return None


def held_values(robot: Robot, model: ArmModel, fixed: dict[str, float] | None,
                samples: int) -> Array:
    """The values the held joint takes: the caller's (``fixed``), else ``samples`` evenly."""
    if model.held is None:
        return np.zeros(1)
    name = robot.joint_names[model.held]
    if fixed and name in fixed:
        return np.array([float(fixed[name])])
    lo, hi = robot.sampling_lower[model.held], robot.sampling_upper[model.held]
    return np.linspace(lo, hi, samples)


def every_turn(robot: Robot, q: Array) -> list[Array]:
    """``q`` and every configuration equal to it up to whole turns within the limits.

    A joint without finite limits keeps its value (it has turns without end).
    """
    options = []
    for k, (v, lo, hi) in enumerate(zip(q, robot.lower, robot.upper, strict=True)):
        if robot.joint_types[k] != "revolute" or not math.isfinite(hi - lo):
            options.append([float(v)])
            continue
        first, last = math.ceil((lo - v) / TURN - 1e-12), math.floor((hi - v) / TURN + 1e-12)
        options.append([min(max(v + m * TURN, lo), hi) for m in range(first, last + 1)]
                       or [float(v)])
    return [np.array(c) for c in itertools.product(*options)]


def _new(found: list[Array], q: Array, periodic: Array) -> bool:
    """Whether ``q`` differs from every row of ``found`` (up to turns where ``periodic``).

    By more than :data:`DISTINCT` in some joint; revolute joints compared up to whole
    turns.
    """
    if not found:
        return True
    d = np.abs(np.asarray(found) - q)
    d = np.where(periodic, np.abs((d + math.pi) % TURN - math.pi), d)
    return bool((d.max(axis=1) > DISTINCT).all())


def all_solutions(robot: Robot, model: ArmModel, target: Target, q_ref: Array, tol: float,
                  fixed: dict[str, float] | None = None, samples: int = SAMPLES,
                  jit: bool = True) -> tuple[list[Array], str]:
    """Every distinct closed-form solution within the limits, every whole turn, and the route.

    The branches (polished where needed) are told apart up to whole turns, then each one's
    turns within the limits are listed (:func:`every_turn`).

    Returns:
        ``(solutions, route)``: configurations (nq,) each, in no particular order (the
        caller sorts), and :func:`route_label` with the sampling.
    """
    values = held_values(robot, model, fixed, samples)
    periodic = np.array([k == "revolute" for k in robot.joint_types])
    reps: list[Array] = []
    for s in values:
        Q, err, dist = branches(robot, model, target, q_ref, float(s), jit)
        for k in np.flatnonzero((dist < OUT) & (err <= POLISH)):
            q = Q[k] if err[k] <= tol else polish(robot, target, Q[k], tol, jit, model.held)
            if q is not None and _new(reps, q, periodic):
                reps.append(q)
    return [t for q in reps for t in every_turn(robot, q)], route_label(robot, model, values)


def every_solution(robot: Robot, model: ArmModel | None, target: Target, q_ref: Array,
                   tol: float, fixed: dict[str, float] | None = None, samples: int = SAMPLES,
                   seed: int | None = 0) -> tuple[list[Array], str]:
    """:func:`all_solutions` where the closed form serves, else :func:`multi_start_solutions`.

    Where the closed form finds none (a pose at a singularity, where its branches are a
    continuum and its round-off largest, or out of reach), the multi-start runs too, and
    the route says so.
    """
    if model is None:
        return multi_start_solutions(robot, target, q_ref, tol, seed)
    sols, route = all_solutions(robot, model, target, q_ref, tol, fixed, samples)
    if sols or (fixed and model.held is not None):
        return sols, route
    sols, multi = multi_start_solutions(robot, target, q_ref, tol, seed)
    return sols, f"{multi}; the closed form ({route}) found none"


def multi_start_solutions(robot: Robot, target: Target, q_ref: Array, tol: float,
                          seed: int | None = 0, starts: int = MULTI_STARTS,
                          jit: bool = True) -> tuple[list[Array], str]:
    """The distinct solutions the fast solver reaches from ``q_ref`` and seeded starts.

    Each start runs the minimum-norm descent (``nearest=False``); the solutions reached
    within ``tol``, every whole turn of each within the limits, distinct. Not a proof
    that there are no others.
    """
    rng = np.random.default_rng(seed)
    periodic = np.array([k == "revolute" for k in robot.joint_types])
    reps: list[Array] = []
    for start in itertools.chain([q_ref], random_starts(robot, rng, starts - 1)):
        res = lm_search(robot, target, q_ref, [start], tol=tol, max_iter=100, jit=jit,
                        nearest=False)
        if res.within and _new(reps, res.q, periodic):
            reps.append(res.q)
    route = f"{MULTI_START} ({starts} starts: no closed form serves this arm and target)"
    return [t for q in reps for t in every_turn(robot, q)], route


def solve_nearest(robot: Robot, target: Target, q_ref: Array, tol: float, jit: bool = True,
                  nearest: bool = True) -> SolverOutput | None:
    """``solve_ik``'s arm route: the closed-form solution nearest ``q_ref``, or ``None``.

    ``None`` where the closed form does not serve the robot and target, or finds no
    solution within the limits (the caller's multi-start goes on). On a 7R arm the held
    joint starts at ``q_ref``'s value; with ``nearest`` it then moves along the branch to
    the solution nearest ``q_ref`` (:func:`~scara_opt.ik.arm_closed_form.build_slide`:
    range-scaled distance, as the fast solver's slide).
    """
    model = served(robot, target)
    if model is None:
        return None
    found_q = nearest_solution(robot, model, target, q_ref, tol, jit)
    if found_q is None:
        return None
    q, branch, scanned = found_q
    labels = robot.__dict__.get("_arm_route_labels")
    if labels is None:
        labels = robot.__dict__["_arm_route_labels"] = (
            route_label(robot, model),
            route_label(robot, model).replace(
                "held at q0's value", f"moved from q0's value in steps of {SCAN_STEP:g} rad to "
                "the first that reaches the pose"))
    label = labels[scanned]
    if model.held is None or not nearest or branch < 0:
        return SolverOutput(q=q, evaluations=1, route=label, turned=branch >= 0)
    f = slide_arrays(robot, model, branch, jit)
    arg = f.arg
    arg["R"][0] = target.rotation.ravel(order="F")  # type: ignore[union-attr]
    arg["p"][0] = target.position
    arg["s"][0] = q[model.held]
    arg["q0"][0] = q_ref
    arg["tol"][0] = tol
    f()
    res = f.res
    if not res["err"][0, 0] <= tol:  # pragma: no cover - every step kept is within tol
        return SolverOutput(q=q, evaluations=1, route=label, turned=True)
    return SolverOutput(q=res["q"][0].copy(), evaluations=1 + SLIDE_STEPS, turned=True,
                        route=label + ", then slid along its branch to the solution nearest q0")


def prepare_arm(robot: Robot, kind: str, jit: bool = True, nearest: bool = True) -> None:
    """Build (or load) the arm route's compiled Functions before a timed solve.

    For full poses on an arm the closed form serves: the closed form, and on a 7R arm
    with ``nearest`` the slide of each branch (compiling them is a one-off of some
    seconds per machine and arm; loading them from the cache well under a millisecond).
    """
    model = arm_model(robot) if kind == "rotation" else None
    if model is None:
        return
    arm_arrays(robot, model, 1, jit)
    if model.held is not None and nearest:
        for branch in range(BRANCHES):
            slide_arrays(robot, model, branch, jit)
