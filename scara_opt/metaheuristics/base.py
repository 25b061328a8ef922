"""The population loop shared by every metaheuristic (template method over :class:`Solver`).

:class:`PopulationSolver` owns everything that is not the update rule: the box of joint
limits and how a move that leaves it is brought back, the seeded random generator, the
batch cost, the evaluation count, the best-so-far bookkeeping, ``history`` and the two
stopping rules. A metaheuristic writes :meth:`PopulationSolver.initialize` (build its
state from the first, already costed population) and :meth:`PopulationSolver.advance`
(one generation). The box, the repair rule and the batch cost are
:class:`~scara_opt.metaheuristics.problem.Problem`'s (imported here too).
"""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import human_bytes, short_repr
from scara_opt.errors import InputError
from scara_opt.ik.auto import AutoSolver
from scara_opt.ik.base import LazyGenerator, Solver, SolverOutput, check_number, default_q0
from scara_opt.ik.task import cost_batch
from scara_opt.metaheuristics.problem import Problem
from scara_opt.model import batch_fk
from scara_opt.model.robot import Robot
from scara_opt.target import Target

Array = NDArray[np.float64]

#: the largest working memory a solve may need before it is refused [bytes] (2 GiB)
MEMORY_LIMIT = 2 * 1024**3
#: working arrays of ``nq`` floats per individual counted by the memory estimate
ROW_ARRAYS = 16
#: floats per individual of the batch FK (R (3, 3), p (3,), per-joint intermediates)
ROW_FK_FLOATS = 64
#: bytes per ``history`` entry (list slot, float object, array element)
HISTORY_BYTES = 40


@dataclass
class Population:
    """The current individuals and their costs; metaheuristics subclass it to add state.

    Attributes:
        X: (n, nq) joint vectors [rad or m], every row within the joint limits.
        f: (n,) their task costs (zavar2024 eq. 8 / nguyen eq. 10) [m and rad].
    """

    X: Array
    f: Array


S = TypeVar("S", bound=Population)


class PopulationSolver(Solver, Generic[S]):
    """Base of the population metaheuristics: the generation loop (template method).

    One solve runs:

    1. the first population: ``population`` configurations drawn uniformly within the
       joint limits; if ``q0`` is given it replaces the first of them (so a good start is
       kept as one individual, never forced on the others);
    2. :meth:`initialize` builds the algorithm's state from it;
    3. up to ``iterations`` generations of :meth:`advance`, stopping early once the best
       cost is at most ``tol`` times the smallest task weight in use (the cost is a
       weighted Euclidean norm of the task errors, so that bound implies ``error <= tol``).

    Every cost goes through :meth:`Problem.cost` — one vectorised FK batch per call, no
    Python loop over individuals — which counts the evaluations; every move goes through
    :meth:`Problem.repair`, so every individual stays within the joint limits. The best
    configuration ever costed is returned, and ``history[k]`` is the best cost after
    generation ``k`` (``history[0]``: the first population), so ``history`` never
    increases and has ``iterations + 1`` entries. Randomness comes only from the
    generator seeded by :meth:`Solver.solve`: same seed, same result.

    Sizes: before anything is allocated, a budget whose working memory
    (:meth:`memory_estimate`) would exceed :data:`MEMORY_LIMIT` (2 GiB) is refused with an
    :class:`~scara_opt.errors.InputError` that names the estimate, instead of a
    ``MemoryError`` (or the system's out-of-memory killer) halfway through.

    Options (all in :attr:`defaults`):
        population: individuals per generation (default 60).
        iterations: maximum number of generations (default 200).
    """

    defaults: ClassVar[dict[str, Any]] = {"population": 60, "iterations": 200}
    #: the smallest population the algorithm's update rule works with
    min_population: ClassVar[int] = 2
    def __init__(self, **options: Any) -> None:
        check_number("population", options.get("population", self.defaults["population"]),
                     self.min_population, integer=True)
        check_number("iterations", options.get("iterations", self.defaults["iterations"]), 1,
                     integer=True)
        super().__init__(**options)  # unknown names, then the algorithm's check_options

    def prepare(self, robot: Robot, kind: str) -> None:
        """Build the batch FK of one population (cached on the robot per size and thread).

        The budget's memory is checked first (:meth:`check_memory`), before any allocation.
        """
        self.check_memory(robot.nq)
        probe = {"position": Target(np.zeros(3)), "yaw": Target(np.zeros(3), yaw=0.0),
                 "rotation": Target(np.zeros(3), rotation=np.eye(3))}[kind]
        n = int(self.options["population"])
        cost_batch(robot, probe, np.tile(default_q0(robot), (n, 1)))
        if kind == "position":  # Problem.cost's unpadded buffers of one population
            batch_fk.fk_arrays(robot, "position", n)

    def witness(self, robot: Robot, target: Target, q0: Array | None, seed: int | None,
                tol: float) -> Array | None:
        """The exact ``auto`` method's answer with the caller's ``seed`` and ``q0``.

        The verdict asks for it when this metaheuristic missed and neither a certificate
        nor the closed form decides: ``max_iter`` needs a configuration that reaches.
        """
        rng = cast(np.random.Generator, LazyGenerator(seed))
        return AutoSolver()._solve(robot, target, q0, rng, tol).q

    def _solve(self, robot: Robot, target: Target, q0: Array | None,
               rng: np.random.Generator, tol: float) -> SolverOutput:
        problem = Problem(robot, target, tol)
        self.check_memory(problem.nq)
        if isinstance(rng, LazyGenerator):  # every generation draws: no proxy in between
            rng = rng.generator()
        X = problem.uniform(rng, int(self.options["population"]))
        if q0 is not None:
            X[0] = q0
        state = self.initialize(problem, Population(X, problem.cost(X)), rng)
        i = int(state.f.argmin())   # the method, not np.argmin's wrapper (~1 µs a call)
        best_q, best_f = state.X[i].copy(), float(state.f[i])
        history = [best_f]
        generations, budget = 0, int(self.options["iterations"])
        while generations < budget and best_f > problem.stop_cost:
            state = self.advance(problem, state, rng, generations)
            generations += 1
            i = int(state.f.argmin())
            if state.f[i] < best_f:
                best_q, best_f = state.X[i].copy(), float(state.f[i])
            history.append(best_f)
        return SolverOutput(q=best_q, iterations=generations, evaluations=problem.evaluations,
                            history=np.asarray(history),
                            message=f"best cost {best_f:.3g} after {generations} generations")

    def memory_estimate(self, nq: int) -> int:
        """Bytes a solve with these options may hold at once, for ``nq`` joints (an estimate).

        Per individual: ``ROW_ARRAYS`` working arrays of ``nq`` floats (population, moves,
        random draws, parents and children) plus ``ROW_FK_FLOATS`` floats of the batch FK
        (rotations, positions and their intermediates); per generation: one entry of
        ``history`` (a Python float in a list, then the array: ``HISTORY_BYTES``).
        Algorithms with larger working arrays (an n × n distance matrix) add theirs.
        Measured with ``tracemalloc`` (zavar2024, 3 generations, population 20000; 3000 for
        ``fa`` with ``sweep="nearest"``), the
        peak of every metaheuristic is 0.2–0.7 of this estimate.
        """
        population, iterations = int(self.options["population"]), int(self.options["iterations"])
        per_row = 8 * (ROW_ARRAYS * nq + ROW_FK_FLOATS)
        return population * per_row + (iterations + 1) * HISTORY_BYTES

    def check_memory(self, nq: int) -> None:
        """Refuse a budget whose :meth:`memory_estimate` exceeds :data:`MEMORY_LIMIT`.

        Raises:
            InputError: names the estimate, the limit and the options to lower.
        """
        need = self.memory_estimate(nq)
        if need > MEMORY_LIMIT:
            o = self.options
            raise InputError(
                f"{self.name}: population={short_repr(o['population'])} x iterations="
                f"{short_repr(o['iterations'])} for {nq} joints needs about "
                f"{human_bytes(need)} of working memory, more than the "
                f"{human_bytes(MEMORY_LIMIT)} allowed; lower population "
                "(tens to a few hundred individuals are usual) or iterations")

    @abstractmethod
    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> S:
        """The algorithm's state from the first, already costed population.

        Algorithms with more state than positions and costs (velocities, an archive, a
        belief space) return a :class:`Population` subclass.

        Args:
            problem: bounds, repair rule and counted cost.
            population: the first population (X (n, nq), f (n,)).
            rng: the solve's random generator.
        """

    @abstractmethod
    def advance(self, problem: Problem, state: S, rng: np.random.Generator, t: int) -> S:
        """One generation: move the individuals, cost them in batch, return the new state.

        Args:
            problem: bounds, repair rule and counted cost.
            state: the state returned by :meth:`initialize` or the previous :meth:`advance`.
            rng: the solve's random generator (the only source of randomness).
            t: index of this generation, ``0 <= t < iterations`` (for schedules).

        Returns:
            The new state; its ``X`` rows must lie within the limits.
        """

    def progress(self, t: int) -> float:
        """Fraction of the generation budget used before generation ``t``, in [0, 1)."""
        return t / int(self.options["iterations"])

    def cooled(self, start: float, end: float, t: int) -> float:
        r"""A step size cooled geometrically over the budget: :math:`s_0 (s_1/s_0)^{t/T}`.

        Args:
            start: :math:`s_0`, the value at the first generation (> 0).
            end: :math:`s_1`, the value the last generation approaches (> 0).
            t: the generation index.
        """
        return start * (end / start) ** self.progress(t)


def greedy(old: Population, X: Array, f: Array) -> None:
    """Replace, row by row, the individuals of ``old`` whose new position ``X`` costs less.

    Args:
        old: the population, updated in place.
        X: (n, nq) candidate positions, one per individual.
        f: (n,) their costs.
    """
    better = f < old.f
    np.copyto(old.X, X, where=better[:, None])   # old.X[better] = X[better], no copies
    np.copyto(old.f, f, where=better)


def survivors(X: Array, f: Array, X_new: Array, f_new: Array, n: int) -> Population:
    """Elitist survival: the ``n`` cheapest rows of ``X`` (m, nq) and ``X_new`` (k, nq).

    :func:`truncate` of the two stacked, old rows first (so ties keep the old), sorted by cost.
    """
    return truncate(np.concatenate([X, X_new]), np.concatenate([f, f_new]), n)


def truncate(X: Array, f: Array, n: int) -> Population:
    """The ``n`` cheapest rows of ``X`` (m, nq) with costs ``f`` (m,), sorted by cost.

    A stable sort, so ties keep their order and the result is reproducible. Rows are
    gathered with ``take`` (the same rows as ``X[order]``, without fancy indexing's
    overhead: ~0.3 instead of ~1.9 µs at 100 x 4).
    """
    order = f.argsort(kind="stable")[:n]
    return Population(X.take(order, axis=0), f.take(order))
