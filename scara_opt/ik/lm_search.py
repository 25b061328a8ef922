"""The fast solver's search over starts: the phases from each start until one succeeds.

:func:`lm_search` fills one target's arrays and runs the start loop (in C where the
phases are compiled, :mod:`scara_opt.ik.lm_driver`; else :class:`~scara_opt.ik.lm_run.Run`)
from each start in turn, keeping the best; :func:`random_starts` draws the further starts
from the seeded generator. Shared by ``lm``, ``auto``, IPOPT's polish and
:func:`~scara_opt.ik.lm_batch.solve_many`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from scara_opt.ik.base import MAX_ITER, MAX_RESTARTS, SolverOutput, check_flag, check_number
from scara_opt.ik.lm_driver import phase_driver
from scara_opt.ik.lm_functions import limits, phase_arrays
from scara_opt.ik.lm_run import Run, residual_tol, within_tol
from scara_opt.ik.problem import fill_params
from scara_opt.model.robot import Array, Robot
from scara_opt.target import Target


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
    run = Run(phase_arrays(robot, kind, 1, jit), e_tol, nearest) if driver is None \
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
