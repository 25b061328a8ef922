"""One target's start loop in Python: the three phases on the compiled iterations.

:class:`Run` calls the Functions of :mod:`scara_opt.ik.lm_functions` on one target's
arrays, phase by phase (see :mod:`scara_opt.ik.lm`), and counts iterations, FK
evaluations and the history. :mod:`scara_opt.ik.lm_driver` runs the same loop in C with
the constants below, bit for bit; this one runs where the phases are not compiled.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TypeVar

from scara_opt.ik.lm_functions import PhaseArrays
from scara_opt.ik.lm_steps import EVALS, ITERATIONS, LAMBDA0, LAMBDA_MAX
from scara_opt.model.robot import Array

_Tol = TypeVar("_Tol", float, Array)

#: a start has converged when ‖r‖ <= TOL_FACTOR * tol * min(weights) and the step <= STEP_TOL
TOL_FACTOR, STEP_TOL = 1e-2, 1e-12
#: the slide has converged when its step falls below this [joint ranges]
SLIDE_TOL = 1e-9
#: a start has stalled after this many calls in a row that lower ‖r‖² by less than a
#: fraction STALL_DECREASE (converging to a solution, LM gains far more a call; sliding
#: into a local minimum it gains less: the UR5-class arm's stalled starts went on for up
#: to 22 calls at 1e-6; 300 poses from mid-range q0: mean calls a solve 15.0 -> 11.6)
STALL_CALLS, STALL_DECREASE = 2, 1e-2


def residual_tol(weights: Sequence[float], tol: float) -> float:
    """‖r‖² [weighted m², rad²] at which a start has converged, for the caller's ``tol``."""
    return (TOL_FACTOR * tol * float(min(weights))) ** 2


def within_tol(e_tol: _Tol) -> _Tol:
    """‖r‖² at which the residual is within the caller's ``tol``, per ``e_tol`` (float or array).

    ``e_tol``: the convergence threshold, :func:`residual_tol`.

    Each row of r is a weighted error (position [m], the wrapped yaw or the rotation
    angle [rad]), so ‖r‖ <= tol·min(weights) bounds each error by ``tol``. A search
    stops at a start that ends there, converged or not: the answer is a solution.
    """
    return e_tol / TOL_FACTOR**2


@dataclass
class Run:
    """State of the iterations on one target (the three phases share it).

    ``f``: this thread's one-target arrays holding the target and limits; ``e_tol``: the
    convergence threshold on ‖r‖² (:func:`residual_tol`); ``nearest``: phases 2 and 3
    after phase 1; ``budget``: iterations left to the current start.
    """

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

