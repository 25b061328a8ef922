"""Grey wolf optimiser (GWO): the pack follows its alpha, beta and delta wolves."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from scara_opt.ik.base import check_flag
from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import (
    Array,
    Population,
    PopulationSolver,
    Problem,
    check_number,
    survivors,
    truncate,
)


@dataclass
class Pack(Population):
    """Wolves and their three leaders.

    Attributes:
        leaders: (3, nq) alpha, beta and delta: the three best positions found so far.
        leader_f: (3,) their costs, ascending.
    """

    leaders: Array
    leader_f: Array


@register_solver("gwo")
class GreyWolfSolver(PopulationSolver[Pack]):
    r"""Grey wolf optimiser, zavar2024 Algorithm 2 (Mirjalili et al. 2014, eqs. 3.1–3.7).

    Every wolf :math:`X` moves to the mean of three positions, one set by each leader
    :math:`X_k \in \{X_α, X_β, X_δ\}` (the three best positions found so far), with
    fresh :math:`r_1, r_2 \sim U(0, 1)` per leader, wolf and joint:

    .. math::
        A = 2 a r_1 - a, \quad C = 2 r_2, \quad D_k = |C X_k - X|, \quad
        X'_k = X_k - A D_k, \qquad X \leftarrow (X'_α + X'_β + X'_δ) / 3

    with :math:`a` falling linearly from ``a_start`` to 0 over the ``iterations``
    generations, :math:`a = a_0 (1 - (t + 1)/T)` for generation :math:`t = 0 … T-1`, so the
    last generation moves every wolf to the leaders' centroid (:math:`|A| > 1` explores,
    :math:`|A| < 1` closes in on the prey).

    Options:
        population: wolves (default 60, at least 3).
        iterations: generations (default 200); also sets the schedule of :math:`a`.
        a_start: initial value of :math:`a` (default 2, as in the paper).
        greedy: a wolf moves only if its new position costs less, and the leaders are
            the three best wolves (default False, as in the paper and Mirjalili et al.;
            True is mealpy's ``OriginalGWO``).
    """

    name = "gwo"
    label = "GWO"
    defaults: ClassVar[dict[str, Any]] = {"population": 60, "iterations": 200, "a_start": 2.0,
                                          "greedy": False}
    min_population = 3

    def check_options(self) -> None:
        """Validate ``a_start`` (a positive number, at most 4) and ``greedy`` (a bool)."""
        check_number("a_start", self.options["a_start"], 0.0, 4.0, low_open=True)
        check_flag("greedy", self.options["greedy"])

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Pack:
        """The pack with its three best wolves as leaders."""
        lead = truncate(population.X, population.f, 3)
        return Pack(population.X, population.f, leaders=lead.X, leader_f=lead.f)

    def advance(self, problem: Problem, state: Pack, rng: np.random.Generator,
                t: int) -> Pack:
        """Move every wolf toward the three leaders (eq. 3.7), then re-elect the leaders."""
        a = self.options["a_start"] * (1.0 - self.progress(t + 1))  # 0 at the last generation
        n = state.X.shape[0]
        # (3, n, nq): each leader repeated for every wolf (a (3, 1, nq) broadcast is ~4x slower)
        L = state.leaders[:, None, :].repeat(n, axis=1)
        A, C = rng.random((2, 3, n, state.X.shape[1]))     # r1, r2: (3, n, nq) each
        # eqs. 3.3-3.7 in place on the draws (no temporaries; the same operations)
        A *= 2.0 * a
        A -= a                                # A = 2 a r1 - a
        C *= 2.0                              # C = 2 r2
        D = np.multiply(C, L, out=C)
        D -= state.X
        np.abs(D, out=D)                      # D_k = |C X_k - X|
        D *= A
        np.subtract(L, D, out=D)              # X'_k = X_k - A D_k
        X = np.add.reduce(D)
        X /= 3.0                              # the mean of the three
        X = problem.repair(X)
        f = problem.cost(X)
        if self.options["greedy"]:  # every wolf keeps its best; the leaders are the 3 best wolves
            keep = f >= state.f
            np.copyto(X, state.X, where=keep[:, None])    # X[keep] = state.X[keep], no copies
            np.copyto(f, state.f, where=keep)
            lead = truncate(X, f, 3)
        else:
            lead = survivors(state.leaders, state.leader_f, X, f, 3)
        return Pack(X, f, leaders=lead.X, leader_f=lead.f)
