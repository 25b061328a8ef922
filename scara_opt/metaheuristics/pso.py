"""Particle swarm optimisation (PSO): inertia, cognitive and social pulls."""

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
)
from scara_opt.metaheuristics.problem import tiled


@dataclass
class Swarm(Population):
    """Particles with their velocities and personal bests.

    Attributes:
        V: (n, nq) velocities [rad or m per generation].
        P: (n, nq) best position each particle has visited.
        fP: (n,) its cost.
        vmax: (n, nq) the velocity cap of each coordinate (``max_velocity`` times the
            joint's range, one row per particle).
    """

    V: Array
    P: Array
    fP: Array
    vmax: Array


@register_solver("pso")
class ParticleSwarmSolver(PopulationSolver[Swarm]):
    r"""Particle swarm optimisation, zavar2024 Algorithm 3.

    Update (Kennedy & Eberhart 1995 with the inertia weight of Shi & Eberhart 1998; the
    defaults are Clerc & Kennedy's 2002 constriction values :math:`χ = 0.7298`,
    :math:`χ φ/2 = 1.49618`), per particle :math:`i` and joint :math:`j`, with
    :math:`r_1, r_2 \sim U(0, 1)` drawn per coordinate:

    .. math::
        v_{ij} \leftarrow w\,v_{ij} + c_1 r_1 (p_{ij} - x_{ij}) + c_2 r_2 (g_j - x_{ij}),
        \qquad x_{ij} \leftarrow x_{ij} + v_{ij}

    where :math:`p_i` is the particle's best position and :math:`g` the swarm's.
    :math:`|v_{ij}|` is capped at ``max_velocity`` times the joint's range; a coordinate
    reflected at a joint limit has its velocity reversed. Particles start at rest.

    Options:
        population: particles (default 60).
        iterations: generations (default 200).
        inertia: :math:`w` (default 0.7298).
        cognitive: :math:`c_1`, pull toward the particle's own best (default 1.49618).
        social: :math:`c_2`, pull toward the swarm's best (default 1.49618).
        max_velocity: velocity cap as a fraction of each joint's range (default 0.2).
    """

    name = "pso"
    label = "PSO"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 60, "iterations": 200, "inertia": 0.7298, "cognitive": 1.49618,
        "social": 1.49618, "max_velocity": 0.2,
    }

    def check_options(self) -> None:
        """Validate the PSO coefficients (see the class docstring for their ranges)."""
        check_number("inertia", self.options["inertia"], 0.0, 1.0)
        check_number("cognitive", self.options["cognitive"], 0.0, 4.0)
        check_number("social", self.options["social"], 0.0, 4.0)
        check_number("max_velocity", self.options["max_velocity"], 0.0, 1.0, low_open=True)

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Swarm:
        """Particles at rest, each its own best so far."""
        X, f = population.X, population.f
        vmax = tiled(self.options["max_velocity"] * problem.span, X.shape[0])
        return Swarm(X, f, V=np.zeros_like(X), P=X.copy(), fP=f.copy(), vmax=vmax)

    def advance(self, problem: Problem, state: Swarm, rng: np.random.Generator,
                t: int) -> Swarm:
        """Move every particle by its new velocity, then update the personal bests."""
        o = self.options
        X, P, vmax = state.X, state.P, state.vmax
        g = P[state.fP.argmin()]
        r1, r2 = rng.random((2, *X.shape))
        V = o["inertia"] * state.V + o["cognitive"] * r1 * (P - X) + o["social"] * r2 * (g - X)
        np.maximum(V, -vmax, out=V)                  # np.clip, without its overhead
        np.minimum(V, vmax, out=V)
        moved = X + V
        X = problem.repair(moved)
        np.negative(V, out=V, where=X != moved)      # reflected: the velocity reverses
        f = problem.cost(X)
        better = f < state.fP
        np.copyto(P, X, where=better[:, None])       # P[better] = X[better], no copies
        np.copyto(state.fP, f, where=better)
        return Swarm(X, f, V=V, P=P, fP=state.fP, vmax=vmax)
