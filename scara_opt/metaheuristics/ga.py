"""Genetic-hybrid algorithm (G-HA): a real-coded GA, then a Nelder–Mead polish."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from scipy.optimize import Bounds, OptimizeResult, minimize

from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import (
    Population,
    PopulationSolver,
    Problem,
    check_number,
    truncate,
)


@dataclass
class Generation(Population):
    """A population sorted by cost, and the cost reached by the last polish.

    Attributes:
        polished_f: cost of the last Nelder–Mead result (``inf`` before the first).
    """

    polished_f: float = math.inf


@register_solver("ga")
class GeneticHybridSolver(PopulationSolver[Generation]):
    r"""Genetic-hybrid algorithm, zavar2024 Algorithm 4 (GA + hybrid function).

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

    **Hybrid function**: once the best cost falls below ``polish_below`` (the paper:
    :math:`10^{-3}` in Sec. 6; its Sec. 5 says :math:`10^{-4}`), the best individual is
    polished by ``scipy.optimize.minimize(method="Nelder-Mead", bounds=limits)``
    (at most ``polish_maxfev`` evaluations, stopping as soon as the cost meets the
    tolerance), and the result replaces the worst individual. A polish runs again only
    when the GA has since found a better point than the last polish gave. Every
    Nelder–Mead evaluation is counted in ``evaluations``. The first simplex spans the
    population's spread along each joint (at most a tenth of its range), so the polish
    starts at the scale the GA has reached.

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
        polish_below: cost [m, rad] below which Nelder–Mead polishes (default 1e-3).
        polish_maxfev: evaluations allowed to one polish (default 400; 0: no polish,
            a plain GA).
    """

    name = "ga"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 60, "iterations": 200, "tournament": 2, "crossover": 0.8, "blend": 0.4,
        "mutation": 0.2, "mutation_scale": 0.1, "mutation_scale_end": 1e-4, "polish_below": 1e-3,
        "polish_maxfev": 400,
    }

    def check_options(self) -> None:
        """Validate the GA rates, sizes and the polish settings."""
        o = self.options
        check_number("tournament", o["tournament"], 1, o["population"], integer=True)
        check_number("crossover", o["crossover"], 0.0, 1.0)
        check_number("blend", o["blend"], 0.0, 1.0)
        check_number("mutation", o["mutation"], 0.0, 1.0)
        check_number("mutation_scale", o["mutation_scale"], 0.0, 1.0, low_open=True)
        check_number("mutation_scale_end", o["mutation_scale_end"], 0.0, o["mutation_scale"],
                     low_open=True)
        check_number("polish_below", o["polish_below"], 0.0)
        check_number("polish_maxfev", o["polish_maxfev"], 0, integer=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Generation:
        """The first population, sorted by cost."""
        pop = truncate(population.X, population.f, population.f.shape[0])
        return Generation(pop.X, pop.f)

    def advance(self, problem: Problem, state: Generation, rng: np.random.Generator,
                t: int) -> Generation:
        """Select, cross, mutate, keep the best; polish the best once it is good enough."""
        o = self.options
        X, f = state.X, state.f
        n, nq = X.shape
        entrants = rng.integers(n, size=(2, n, o["tournament"]))
        parents = np.take_along_axis(entrants, np.argmin(f[entrants], axis=2)[..., None],
                                     axis=2)[..., 0]                   # (2, n) indices
        p1, p2 = X[parents[0]], X[parents[1]]
        u = rng.uniform(-o["blend"], 1.0 + o["blend"], (n, nq))
        crossed = rng.random((n, 1)) < o["crossover"]
        children = np.where(crossed, p1 + u * (p2 - p1), p1)
        mutate = rng.random((n, nq)) < o["mutation"]
        sigma = self.cooled(o["mutation_scale"], o["mutation_scale_end"], t)
        step = sigma * problem.span * rng.standard_normal((n, nq))
        children = problem.repair(children + mutate * step)
        fc = problem.cost(children)
        pop = truncate(np.vstack([X, children]), np.concatenate([f, fc]), n)
        new = Generation(pop.X, pop.f, polished_f=state.polished_f)
        if (o["polish_maxfev"] > 0 and problem.stop_cost < new.f[0]
                < min(o["polish_below"], new.polished_f)):
            self._polish(problem, new)
        return new

    def _polish(self, problem: Problem, gen: Generation) -> None:
        """Nelder–Mead from the best individual; the result replaces the worst one."""
        x0 = gen.X[0]
        h = np.clip(gen.X.std(axis=0), 1e-9 * problem.span, 0.1 * problem.span)
        h = np.where(x0 + h > problem.upper, -h, h)     # keep the first simplex in the box
        simplex = np.vstack([x0, x0 + np.diag(h)])

        def stop_at_tol(intermediate_result: OptimizeResult) -> None:
            if intermediate_result.fun <= problem.stop_cost:
                raise StopIteration

        res = minimize(problem.cost_one, x0, method="Nelder-Mead",
                       bounds=Bounds(problem.lower, problem.upper), callback=stop_at_tol,
                       options={"initial_simplex": simplex, "maxfev": self.options[
                           "polish_maxfev"], "xatol": 1e-14, "fatol": 0.0})
        gen.polished_f = float(res.fun)
        if res.fun < gen.f[-1]:
            gen.X[-1], gen.f[-1] = np.clip(res.x, problem.lower, problem.upper), res.fun
            order = np.argsort(gen.f, kind="stable")
            gen.X, gen.f = gen.X[order], gen.f[order]
