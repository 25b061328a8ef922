"""Firefly algorithm (FA): attraction that decays with distance, plus a random walk."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import (
    Population,
    PopulationSolver,
    Problem,
    check_number,
    greedy,
)


@register_solver("fa")
class FireflySolver(PopulationSolver[Population]):
    r"""Firefly algorithm, zavar2024 Algorithm 5 (Yang 2008, ch. 10, eq. 10.4).

    Reference: X.-S. Yang, *Nature-Inspired Metaheuristic Algorithms*, Luniver Press 2008.

    Firefly :math:`i` is attracted by a brighter (cheaper) firefly :math:`j` with an
    attractiveness that decays with their distance :math:`r_{ij}` (measured in units of
    each joint's range, so revolute and prismatic joints weigh alike), and walks at
    random, with :math:`u, v \sim U(0, 1)^{nq}`:

    .. math::
        β_{ij} = β_0 e^{-γ r_{ij}^2}, \qquad
        x_i \leftarrow x_i + β_{ij}\, u \odot (x_j - x_i)
            + α_t\,(v - \tfrac12) \odot (\text{upper} - \text{lower})

    Yang sweeps :math:`i` toward every brighter :math:`j` in turn; with :math:`β_0 = 1`
    a move toward a near firefly is nearly a jump onto it, so the sweep ends close to
    the brightest fireflies near :math:`i`. Here every firefly makes one move, toward
    the brighter firefly that attracts it most (:math:`\max_j β_{ij}`, i.e. its nearest
    brighter neighbour), all fireflies at once: the pairwise distances are one numpy
    broadcast (n × n, from the Gram matrix) and the generation one batch of costs. The
    per-coordinate weight :math:`u` is that of the common implementations (Yarpiz,
    mealpy); so is keeping the old position when the new one is not brighter.
    The brightest firefly only walks. The walk cools geometrically over the budget,
    :math:`α_t = α_0 (α_{end}/α_0)^{t/T}` (Yang's own code cools the same way, to a
    fixed fraction at the last generation :math:`T`), so it ends below the tolerance.

    Options:
        population: fireflies (default 60).
        iterations: generations :math:`T` (default 200); also sets the cooling.
        beta0: attractiveness at distance 0, :math:`β_0` (default 1).
        gamma: light absorption :math:`γ` (default 1; distances in joint ranges).
        alpha: random step :math:`α_0` at the first generation, as a fraction of each
            joint's range (default 0.2).
        alpha_end: random step :math:`α_{end}` at the last generation, same units
            (default 2e-7: below a micrometre on a 0.4 m arm).
    """

    name = "fa"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 60, "iterations": 200, "beta0": 1.0, "gamma": 1.0, "alpha": 0.2,
        "alpha_end": 2e-7,
    }

    def check_options(self) -> None:
        """Validate β0 in [0, 2], γ >= 0 and 0 < α_end <= α0 <= 1."""
        o = self.options
        check_number("beta0", o["beta0"], 0.0, 2.0)
        check_number("gamma", o["gamma"], 0.0)
        check_number("alpha", o["alpha"], 0.0, 1.0, low_open=True)
        check_number("alpha_end", o["alpha_end"], 0.0, o["alpha"], low_open=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Population:
        """The first population as it is."""
        return population

    def advance(self, problem: Problem, state: Population, rng: np.random.Generator,
                t: int) -> Population:
        """Every firefly moves toward its most attractive brighter one; keep the gains."""
        o = self.options
        X, f = state.X, state.f
        Y = X / problem.span                                   # distances in joint ranges
        sq = np.einsum("ij,ij->i", Y, Y)
        r2 = np.maximum(sq[:, None] + sq[None, :] - 2.0 * (Y @ Y.T), 0.0)   # (n, n)
        brighter = f[None, :] < f[:, None]                     # [i, j]: j brighter than i
        j = np.argmin(np.where(brighter, r2, np.inf), axis=1)  # nearest brighter = max β_ij
        rows = np.arange(f.shape[0])
        beta = np.where(brighter[rows, j], o["beta0"] * np.exp(-o["gamma"] * r2[rows, j]), 0.0)
        pull = beta[:, None] * rng.random(X.shape) * (X[j] - X)
        alpha = self.cooled(o["alpha"], o["alpha_end"], t)
        walk = alpha * (rng.random(X.shape) - 0.5) * problem.span
        moved = problem.repair(X + pull + walk)
        greedy(state, moved, problem.cost(moved))
        return state
