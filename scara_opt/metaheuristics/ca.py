"""Cultural algorithm (CA): a belief space of situational and normative knowledge."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

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
class Culture(Population):
    """The population space (sorted by cost) and its belief space.

    Attributes:
        best: (nq,) situational knowledge: the best individual so far (the exemplar).
        low: (nq,) normative knowledge: per joint, the lowest value among the accepted.
        high: (nq,) normative knowledge: per joint, the highest value among the accepted.
    """

    best: Array
    low: Array
    high: Array


@register_solver("ca")
class CulturalSolver(PopulationSolver[Culture]):
    r"""Cultural algorithm, zavar2024 Algorithm 1 (Reynolds 1994).

    Two spaces evolve together. The **belief space** holds *situational* knowledge, the
    best individual :math:`s`, and *normative* knowledge, the interval
    :math:`[l_j, u_j]` each joint spans over the **accepted** individuals (the best
    ``accept`` fraction of the population). The belief space **influences** the
    population: every individual :math:`x` breeds one child whose step is sized by the
    normative interval and pointed at the exemplar (the situational + normative
    influence of Chung & Reynolds), with :math:`ε \sim N(0, 1)` per coordinate:

    .. math::
        δ_j = α (u_j - l_j) |ε|, \qquad
        x'_j = x_j + \operatorname{sign}(s_j - x_j)\, δ_j

    (:math:`ε` keeps its own sign where :math:`x_j = s_j`). Parents and children
    compete; the best ``population`` survive, the accepted are re-chosen from them and
    the belief space is updated (:math:`s` = best, :math:`[l, u]` = extent of the accepted). As the
    accepted individuals agree, :math:`[l, u]` and with it the step shrink, which is
    how CA refines its answer down to the tolerance.

    Options:
        population: individuals (default 60).
        iterations: generations (default 200).
        accept: fraction of the population accepted into the belief space (default 0.35).
        step: :math:`α`, step as a fraction of the normative interval (default 0.3).
    """

    name = "ca"
    label = "CA"
    defaults: ClassVar[dict[str, Any]] = {"population": 60, "iterations": 200, "accept": 0.35,
                                          "step": 0.3}

    def check_options(self) -> None:
        """Validate ``accept`` in (0, 1] and ``step`` in (0, 2]."""
        check_number("accept", self.options["accept"], 0.0, 1.0, low_open=True)
        check_number("step", self.options["step"], 0.0, 2.0, low_open=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Culture:
        """The first population, sorted, and the belief space it implies."""
        return self._accept(truncate(population.X, population.f, population.f.shape[0]))

    def advance(self, problem: Problem, state: Culture, rng: np.random.Generator,
                t: int) -> Culture:
        """Breed one child per individual under the belief space's influence, select, accept."""
        X = state.X
        direction = rng.standard_normal(X.shape)
        gap = state.best - X
        # |ε| sign(s - x) where x != s (bit for bit |ε| · ±1), ε itself where x = s
        np.copysign(direction, gap, out=direction, where=gap != 0.0)
        children = problem.repair(X + self.options["step"] * (state.high - state.low) * direction)
        f = problem.cost(children)
        merged = survivors(X, state.f, children, f, X.shape[0])
        return self._accept(merged)

    def _accept(self, pop: Population) -> Culture:
        """Belief space of a population sorted by cost (the acceptance function)."""
        k = max(1, round(self.options["accept"] * pop.f.shape[0]))
        accepted = pop.X[:k]
        return Culture(pop.X, pop.f, best=pop.X[0].copy(), low=accepted.min(axis=0),
                       high=accepted.max(axis=0))
