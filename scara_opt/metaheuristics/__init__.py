r"""Population metaheuristics for IK, behind the same solver interface as the exact solvers.

All eight solve the same problem, zavar2024 eq. 6-8 with the joint limits as a box:

.. math::
    \min_{q \in [\text{lower}, \text{upper}]} c(q), \qquad
    c(q) = \sqrt{w_p^2 \lVert p(q) - p^* \rVert^2 + w_a^2 Δ_A(q)^2}

(eq. 8 of zavar2024 for a position target; with a tool angle, eq. 10 of the SFLA paper),
evaluated by :func:`scara_opt.ik.task.cost_batch` for a whole population in one
vectorised FK call. They differ only in how one generation moves the population; the
rest lives once in :class:`~scara_opt.metaheuristics.base.PopulationSolver`:

* the first population is uniform within the joint limits (``q0``, if given, replaces
  one individual);
* a move that leaves the limits is reflected at the limit, then clipped;
* the loop stops after ``iterations`` generations or once the best cost implies
  ``error <= tol``; ``history[k]`` is the best cost after generation ``k``;
* ``evaluations`` counts every configuration costed (Nelder–Mead's too, for ``gha``);
* randomness comes only from the seeded ``numpy.random.Generator``: same seed, same result.

Importing this package registers, for :func:`scara_opt.solve_ik`:

* ``ca``: :class:`CulturalSolver`, belief space (situational + normative knowledge);
* ``gwo``: :class:`GreyWolfSolver`, alpha/beta/delta leaders, ``a`` from 2 to 0;
* ``pso``: :class:`ParticleSwarmSolver`, inertia + cognitive + social pulls;
* ``ga``: :class:`GeneticSolver`, the plain GA: selection/crossover/mutation/survival;
* ``gha``: :class:`GeneticHybridSolver`, zavar2024's G-HA: the same GA, then Nelder–Mead;
* ``fa``: :class:`FireflySolver`, distance-decaying attraction + cooling random walk
  (every firefly toward every brighter one, or ``sweep="nearest"``);
* ``aco``: :class:`AntColonySolver`, ACO_R archive of Gaussian kernels;
* ``sfla``: :class:`ShuffledFrogSolver`, memeplexes, leaps of the worst frog, shuffling.

Each class has a display ``label`` for tables and plots, the paper's name where there is
one (``"G-HA"``, ``"GWO"``, …); :func:`method_label` looks it up by registry name.

**ACO is ACO_R, not the paper's Algorithm 6.** zavar2024's Algorithm 6 is the pheromone
method of combinatorial ACO (evaporation ρ, weights α, β on pheromone and heuristic,
ants stepping through discrete choices). Its text gives no discretisation of the joint
space and no heuristic for IK, and a joint grid would cap the accuracy at the grid's
step. ``aco`` is the standard continuous-domain ACO instead (ACO_R, Socha & Dorigo 2008:
the pheromone is an archive of good solutions sampled through Gaussian kernels), hence
its label ``"ACO (ACO_R)"``; it takes no ρ, α, β.

These solvers cannot prove a target unreachable: when one misses, the base asks an exact
solver, and the status is ``"max_iter"`` (reachable, budget used up) or ``"unreachable"``.
"""

from scara_opt.ik.registry import method_label
from scara_opt.metaheuristics.aco import AntColonySolver
from scara_opt.metaheuristics.base import Population, PopulationSolver, Problem
from scara_opt.metaheuristics.ca import CulturalSolver
from scara_opt.metaheuristics.fa import FireflySolver
from scara_opt.metaheuristics.ga import GeneticSolver
from scara_opt.metaheuristics.gha import GeneticHybridSolver
from scara_opt.metaheuristics.gwo import GreyWolfSolver
from scara_opt.metaheuristics.pso import ParticleSwarmSolver
from scara_opt.metaheuristics.sfla import ShuffledFrogSolver

__all__ = [
    "AntColonySolver",
    "CulturalSolver",
    "FireflySolver",
    "GeneticHybridSolver",
    "GeneticSolver",
    "GreyWolfSolver",
    "ParticleSwarmSolver",
    "Population",
    "PopulationSolver",
    "Problem",
    "ShuffledFrogSolver",
    "method_label",
]
