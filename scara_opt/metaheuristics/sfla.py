"""Shuffled frog leaping algorithm (SFLA): memeplexes, leaps of the worst frog, shuffling."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import short_repr
from scara_opt.errors import InputError
from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import (
    Array,
    Population,
    PopulationSolver,
    Problem,
    check_number,
)


@dataclass
class Frogs(Population):
    """All frogs and their current partition into memeplexes.

    Attributes:
        memeplexes: (m, n_m) row indices into ``X``: frog ``memeplexes[k, i]`` belongs to
            memeplex ``k``.
    """

    memeplexes: NDArray[np.intp]


@register_solver("sfla")
class ShuffledFrogSolver(PopulationSolver[Frogs]):
    r"""Shuffled frog leaping, nguyen eq. 8-9 (Eusuff & Lansey 2003; Eusuff et al. 2006).

    **Memeplexes.** At every shuffle the frogs are sorted by cost and dealt like cards
    into ``memeplexes`` groups (rank 1 to memeplex 1, rank 2 to memeplex 2, …, rank
    m + 1 to memeplex 1 again), so each memeplex gets a share of good and bad frogs.
    With a population that is not a multiple of ``memeplexes`` the worst
    ``population mod memeplexes`` frogs sit out until the next shuffle.

    **One generation (iteration) = one leap in every memeplex**, all memeplexes at once.
    In each, the worst frog :math:`X_w` leaps toward the memeplex's best :math:`X_b`
    (eq. 8-9), with one :math:`r \sim U(0, 1)` per leap:

    .. math::
        D = r\,C\,(X_b - X_w), \quad |D_j| \le D_{max}, \qquad X_w \leftarrow X_w + D

    The leap is kept if it lowers the frog's cost; otherwise it is retried toward the
    global best :math:`X_g`; if that fails too, the frog is replaced by a random one
    drawn uniformly within the limits. So a generation costs at most ``3 * memeplexes``
    evaluations, in at most three batches (a memeplex whose frogs all cost the same
    sits the round out).

    **Shuffling.** Every ``local_steps`` generations the memeplexes are merged and dealt
    again (global exchange of information).

    **The paper's Table 2** (N = 20, G = 20, C = 2, m = 10, iter = 10, Dmax = ∞) read
    as: m = 10 memeplexes of N = 20 frogs (``population`` = 200), iter = 10 leaps per
    memeplex between two shuffles (``local_steps``), G = 20 shuffles, so
    ``iterations`` = G · iter = 200 leaps per memeplex, C = 2 (``leap``) and
    Dmax = ∞ (``max_leap``). The paper does not define its symbols; reading N = 20 as
    the whole population (memeplexes of 2 frogs) changes only the first sample and the
    pool the leaps draw on, not the number of leaps. Those are the defaults.

    Options:
        population: frogs (default 200 = m · N).
        iterations: leap rounds (default 200 = G · iter).
        memeplexes: m, number of memeplexes (default 10).
        local_steps: iter, leap rounds between two shuffles (default 10).
        leap: C, leap scale, between 1 and 2 in the paper (default 2).
        max_leap: Dmax, cap on each coordinate of a leap [rad or m] (default ∞).
    """

    name = "sfla"
    label = "SFLA"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 200, "iterations": 200, "memeplexes": 10, "local_steps": 10,
        "leap": 2.0, "max_leap": math.inf,
    }

    def check_options(self) -> None:
        """Validate the memeplex layout and the leap settings.

        Raises:
            InputError: fewer than 2 frogs per memeplex, or an option out of range.
        """
        o = self.options
        check_number("memeplexes", o["memeplexes"], 1, integer=True)
        check_number("local_steps", o["local_steps"], 1, integer=True)
        check_number("leap", o["leap"], 0.0, 4.0, low_open=True)
        check_number("max_leap", o["max_leap"], 0.0, low_open=True)
        if o["population"] < 2 * o["memeplexes"]:
            raise InputError(
                f"sfla needs at least 2 frogs per memeplex: population="
                f"{short_repr(o['population'])} with memeplexes={short_repr(o['memeplexes'])}; "
                f"raise population to {short_repr(2 * o['memeplexes'])} or lower memeplexes")

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Frogs:
        """The first frogs, dealt into memeplexes."""
        return self._shuffle(Frogs(population.X, population.f, np.zeros((0, 0), np.intp)))

    def advance(self, problem: Problem, state: Frogs, rng: np.random.Generator,
                t: int) -> Frogs:
        """One leap of the worst frog in every memeplex; shuffle every ``local_steps``."""
        if t > 0 and t % self.options["local_steps"] == 0:
            state = self._shuffle(state)
        X, f, M = state.X, state.f, state.memeplexes
        rows = np.arange(M.shape[0])
        fM = f.take(M)                # (m, n_m) the memeplexes' costs
        best = M[rows, fM.argmin(axis=1)]
        worst = M[rows, fM.argmax(axis=1)]
        learns = worst != best        # a memeplex of equal frogs has nothing to learn
        global_best = X[f.argmin()].copy()    # fixed before any frog leaps
        w = worst[learns]
        if w.size:
            w = self._leap(problem, state, w, X.take(best[learns], axis=0), rng)
        if w.size:
            w = self._leap(problem, state, w, global_best, rng)
        if w.size:
            X[w] = problem.uniform(rng, w.size)
            f[w] = problem.cost(X[w])
        return state

    def _leap(self, problem: Problem, state: Frogs, w: NDArray[np.intp], leader: Array,
              rng: np.random.Generator) -> NDArray[np.intp]:
        """Leap the frogs ``w`` toward ``leader`` (eq. 8-9); keep improvements.

        Args:
            problem: bounds, repair rule and counted cost.
            state: the frogs, updated in place.
            w: (k,) the leaping frogs' rows in ``state.X``.
            leader: (k, nq) each one's leader, or (nq,) one leader for all.
            rng: the solve's random generator (one draw per leap).

        Returns:
            The frogs whose leap failed, in the order of ``w``.
        """
        r = rng.random((w.shape[0], 1))
        cap = self.options["max_leap"]
        Xw = state.X.take(w, axis=0)
        D = r * self.options["leap"] * (leader - Xw)
        if cap != math.inf:           # max(D, -inf) and min(D, inf) would leave D as it is
            D = np.minimum(np.maximum(D, -cap), cap)
        cand = problem.repair(Xw + D)
        fc = problem.cost(cand)
        better = fc < state.f.take(w)
        kept = w[better]
        state.X[kept], state.f[kept] = cand[better], fc[better]
        return w[~better]

    def _shuffle(self, state: Frogs) -> Frogs:
        """Sort all frogs by cost and deal them into the memeplexes."""
        m = self.options["memeplexes"]
        order = np.argsort(state.f, kind="stable")
        per = order.shape[0] // m
        state.memeplexes = order[: m * per].reshape(per, m).T.copy()
        return state
