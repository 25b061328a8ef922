"""Genetic algorithm (GA): tournament selection, blend crossover, mutation, elitist survival."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import (
    Population,
    PopulationSolver,
    Problem,
    check_number,
    truncate,
)
from scara_opt.metaheuristics.ga_breed import Draws, offspring, winners  # noqa: F401


@register_solver("ga")
class GeneticSolver(PopulationSolver[Population]):
    r"""Plain real-coded genetic algorithm: the GA part of zavar2024 Algorithm 4, no hybrid.

    Each generation (a real-coded GA, Holland 1975 / Eshelman & Schaffer 1993):

    * **selection**: each parent is the cheapest of ``tournament`` individuals drawn at
      random;
    * **crossover** (probability ``crossover`` per child): blend crossover BLX-γ,
      :math:`c_j = p_j + u_j (p'_j - p_j)` with :math:`u_j \sim U(-γ, 1 + γ)`;
    * **mutation** (probability ``mutation`` per gene):
      :math:`c_j \leftarrow c_j + σ_t\,(u_j - l_j)\,ε`, :math:`ε \sim N(0, 1)`, with the
      step annealed geometrically over the budget,
      :math:`σ_t = σ_0 (σ_{end}/σ_0)^{t/T}` (large steps explore first, small ones
      refine later: the intent of Michalewicz's 1992 non-uniform mutation);
    * **survival**: parents and children together, the best ``population`` survive
      (elitist, so the best is never lost).

    A generation costs exactly ``population`` evaluations, one batch, so a run of
    :math:`T` generations costs ``population * (T + 1)``. Nothing else searches: no
    local polish (that is ``gha``, :class:`~scara_opt.metaheuristics.gha.GeneticHybridSolver`).

    A generation's arithmetic between the random draws and the cost (tournaments, blend,
    mutation, box repair) runs in a small C kernel (:mod:`~scara_opt.metaheuristics.ga_breed`),
    in numpy where nothing compiles: the same numbers, bit for bit.

    Where it departs from the paper: zavar2024's Algorithm 4 names the operators only
    ("soft or hard" selection by roulette wheel, rank or top; crossover; mutation) and
    gives no rates; the operators and rates here are our choice (tournament, BLX-γ,
    annealed Gaussian mutation, elitist survival), and the paper's "hybrid function"
    (Nelder–Mead) is left out on purpose: this is the GA alone, to compare against.

    Options:
        population: individuals (default 60).
        iterations: generations (default 200).
        tournament: tournament size (default 2).
        crossover: probability that a child is a blend of two parents (default 0.8).
        blend: γ of BLX-γ (default 0.4).
        mutation: probability that a gene mutates (default 0.2).
        mutation_scale: :math:`σ_0`, first mutation step as a fraction of the joint range
            (default 0.1).
        mutation_scale_end: :math:`σ_{end}`, the step the last generation approaches,
            same units (default 1e-4).
    """

    name = "ga"
    label = "GA"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 60, "iterations": 200, "tournament": 2, "crossover": 0.8, "blend": 0.4,
        "mutation": 0.2, "mutation_scale": 0.1, "mutation_scale_end": 1e-4,
    }

    def check_options(self) -> None:
        """Validate the GA rates and sizes."""
        o = self.options
        check_number("tournament", o["tournament"], 1, o["population"], integer=True)
        check_number("crossover", o["crossover"], 0.0, 1.0)
        check_number("blend", o["blend"], 0.0, 1.0)
        check_number("mutation", o["mutation"], 0.0, 1.0)
        check_number("mutation_scale", o["mutation_scale"], 0.0, 1.0, low_open=True)
        check_number("mutation_scale_end", o["mutation_scale_end"], 0.0, o["mutation_scale"],
                     low_open=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Population:
        """The first population, sorted by cost."""
        return truncate(population.X, population.f, population.f.shape[0])

    def advance(self, problem: Problem, state: Population, rng: np.random.Generator,
                t: int) -> Population:
        """One GA generation (see :meth:`breed`)."""
        return self.breed(problem, state, rng, t)

    def breed(self, problem: Problem, state: Population, rng: np.random.Generator,
              t: int) -> Population:
        """Select, cross, mutate; the best ``population`` of parents and children, sorted.

        Args:
            problem: bounds, repair rule and counted cost.
            state: the current population, sorted by cost.
            rng: the solve's random generator.
            t: the generation index (anneals the mutation step).

        Returns:
            The next population, sorted by cost (one batch of ``population`` evaluations).
        """
        o = self.options
        X, f = state.X, state.f
        n, nq = X.shape
        draws = Draws.of(problem, n, o["tournament"])
        draws.draw(rng, o["blend"])
        sigma = self.cooled(o["mutation_scale"], o["mutation_scale_end"], t)
        children = offspring(problem, X, f, draws, sigma, o["crossover"], o["mutation"])
        fc = problem.cost(children)
        return draws.survivors(X, f, children, fc)

