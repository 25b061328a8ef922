"""Genetic-hybrid algorithm (G-HA): the GA of ``ga``, then a Nelder–Mead polish."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, cast

import numpy as np
from scipy.optimize import Bounds, OptimizeResult, minimize

from scara_opt.ik.registry import register_solver
from scara_opt.metaheuristics.base import Population, Problem, check_number
from scara_opt.metaheuristics.ga import GeneticSolver


@dataclass
class Generation(Population):
    """A population sorted by cost, and the cost reached by the last polish.

    Attributes:
        polished_f: cost of the last Nelder–Mead result (``inf`` before the first).
    """

    polished_f: float = math.inf


@register_solver("gha")
class GeneticHybridSolver(GeneticSolver):
    r"""Genetic-hybrid algorithm G-HA, zavar2024 Algorithm 4 (GA + "hybrid function").

    Every generation is one generation of the plain GA, :class:`GeneticSolver` (``ga``;
    selection, BLX-γ crossover, annealed mutation, elitist survival, with the same
    options and defaults). Then the **hybrid function**: once the best cost falls below
    ``polish_below`` (the paper: :math:`10^{-3}` in Sec. 6, Fig. 4(d); its Sec. 5 says
    :math:`10^{-4}`), the best individual is polished by
    ``scipy.optimize.minimize(method="Nelder-Mead", bounds=limits)`` (the paper's
    "Nelder–Mead Simplex"), at most ``polish_maxfev`` evaluations, stopping as soon as
    the cost meets the tolerance, and the result replaces the worst individual. Every
    Nelder–Mead evaluation is counted in ``evaluations``. The first simplex spans the
    population's spread along each joint (at most a tenth of its range), so the polish
    starts at the scale the GA has reached.

    Where it departs from the paper, beyond the GA's own choices (see
    :class:`GeneticSolver`): the paper's Algorithm 4 applies the hybrid function inside
    the generation loop and its text once the cost reaches the threshold, without saying
    how often or with what budget. Here a polish runs in the loop whenever the best cost
    is below ``polish_below`` and the GA has found a better point than the last polish
    gave (so not twice from the same point); each polish has a capped budget, and its
    result rejoins the population instead of ending the run.

    Options:
        population, iterations, tournament, crossover, blend, mutation, mutation_scale,
        mutation_scale_end: as for :class:`GeneticSolver`, same defaults.
        polish_below: cost [m, rad] below which Nelder–Mead polishes (default 1e-3).
        polish_maxfev: evaluations allowed to one polish (default 400, at least 1; for
            no polish at all use the plain GA, ``method="ga"``).
    """

    name = "gha"
    label = "G-HA"
    defaults: ClassVar[dict[str, Any]] = {
        **GeneticSolver.defaults, "polish_below": 1e-3, "polish_maxfev": 400,
    }

    def check_options(self) -> None:
        """Validate the GA's options, then the polish settings."""
        super().check_options()
        check_number("polish_below", self.options["polish_below"], 0.0)
        check_number("polish_maxfev", self.options["polish_maxfev"], 1, integer=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Generation:
        """The first population, sorted by cost; no polish yet."""
        pop = super().initialize(problem, population, rng)
        return Generation(pop.X, pop.f)

    def advance(self, problem: Problem, state: Population, rng: np.random.Generator,
                t: int) -> Generation:
        """One GA generation; then polish the best once it is below ``polish_below``."""
        last = cast(Generation, state)  # initialize and advance only ever return Generations
        pop = self.breed(problem, last, rng, t)
        new = Generation(pop.X, pop.f, polished_f=last.polished_f)
        if problem.stop_cost < new.f[0] < min(self.options["polish_below"], new.polished_f):
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
