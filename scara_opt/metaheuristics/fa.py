"""Firefly algorithm (FA): attraction that decays with distance, plus a random walk."""

from __future__ import annotations

import ctypes
import functools
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, ClassVar, Protocol

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
    greedy,
)
from scara_opt.model.compiled import c_function

#: the values of the ``sweep`` option: every brighter firefly in turn, or the nearest one
SWEEPS = ("all", "nearest")

#: most random numbers the compiled all-pairs sweep draws at once (512 KiB)
BLOCK = 65536


class UniformSource(Protocol):
    """What the sweeps draw from: ``random(shape)``, uniform on [0, 1) (a numpy Generator)."""

    def random(self, size: tuple[int, ...]) -> Array:
        """Uniform draws of shape ``size``."""
        ...


@register_solver("fa")
class FireflySolver(PopulationSolver[Population]):
    r"""Firefly algorithm, zavar2024 Algorithm 5 (Yang 2008, ch. 10, eq. 10.4).

    Reference: X.-S. Yang, *Nature-Inspired Metaheuristic Algorithms*, Luniver Press 2008.

    Firefly :math:`i` is attracted by a brighter (cheaper) firefly :math:`j` with an
    attractiveness that decays with their distance :math:`r_{ij}` (measured in units of
    each joint's range, so revolute and prismatic joints weigh alike), and walks at
    random; one **move** of :math:`i` toward :math:`j` is, with
    :math:`u, v \sim U(0, 1)^{nq}`:

    .. math::
        β_{ij} = β_0 e^{-γ r_{ij}^2}, \qquad
        x_i \leftarrow x_i + β_{ij}\, u \odot (x_j - x_i)
            + α_t\,(v - \tfrac12) \odot (\text{upper} - \text{lower})

    **Sweep** (option ``sweep``):

    * ``"all"`` (default; the paper's Algorithm 5 and Yang's own 2008 code,
      ``firefly_simple.m`` / ``ffa_move``): every firefly :math:`i` moves toward **every**
      brighter :math:`j` in turn, from the dimmest of them to the brightest (Yang sorts
      the fireflies by brightness first), :math:`r_{ij}` measured from :math:`i`'s
      current (already moved) position to :math:`j`'s position at the start of the
      generation, each move with its own random step (as in both of Yang's codes).
      Vectorised as in :func:`sweep_all`: one
      Python step per attracting firefly, moving all the fireflies dimmer than it at
      once (numpy), so a generation is about ``population`` small numpy steps, not
      ``population²`` scalar ones.
    * ``"nearest"``: every firefly makes one move, toward the brighter firefly that
      attracts it most (:math:`\max_j β_{ij}`, its nearest brighter neighbour), all at
      once (:func:`sweep_nearest`: an n × n distance matrix, one broadcast). Cheaper per
      generation; the sweep this class ran before the all-pairs one became the default.

    The brightest firefly (no one attracts it) makes one random step, in both sweeps.
    Brightness is the cost at the start of the generation, and the moved fireflies are
    costed once per generation, in one batch, after the sweep, as in Yang's 2008 code
    (the paper's Algorithm 5, and Yang's 2010 ``fa_ndim``, evaluate after each move: n²
    evaluations a generation instead of n). The walk cools geometrically over
    the budget, :math:`α_t = α_0 (α_{end}/α_0)^{t/T}` (Yang's code cools the same way, to
    a fixed fraction at the last generation :math:`T`), so it ends below the tolerance.

    Where it departs from Yang's code: the per-coordinate weight :math:`u` and keeping
    a firefly's old position when its new one is not brighter (greedy) are those of the
    common implementations (Yarpiz, mealpy); Yang scales by :math:`β` alone and always
    moves; the brightest firefly walks (in Yang's 2008 code it stays); a move that leaves the
    joint limits is brought back once, after the sweep (reflect, then clip; Yang clips).

    Options:
        population: fireflies (default 60).
        iterations: generations :math:`T` (default 200); also sets the cooling.
        beta0: attractiveness at distance 0, :math:`β_0` (default 1).
        gamma: light absorption :math:`γ` (default 1; distances in joint ranges).
        alpha: random step :math:`α_0` at the first generation, as a fraction of each
            joint's range (default 0.2).
        alpha_end: random step :math:`α_{end}` at the last generation, same units
            (default 2e-7: below a micrometre on a 0.4 m arm).
        sweep: ``"all"`` (default) or ``"nearest"``, see above.
    """

    name = "fa"
    label = "FA"
    defaults: ClassVar[dict[str, Any]] = {
        "population": 60, "iterations": 200, "beta0": 1.0, "gamma": 1.0, "alpha": 0.2,
        "alpha_end": 2e-7, "sweep": "all",
    }

    def check_options(self) -> None:
        """Validate β0 in [0, 2], γ >= 0, 0 < α_end <= α0 <= 1 and the sweep's name."""
        o = self.options
        check_number("beta0", o["beta0"], 0.0, 2.0)
        check_number("gamma", o["gamma"], 0.0)
        check_number("alpha", o["alpha"], 0.0, 1.0, low_open=True)
        check_number("alpha_end", o["alpha_end"], 0.0, o["alpha"], low_open=True)
        if not isinstance(o["sweep"], str) or o["sweep"] not in SWEEPS:
            raise InputError(f"option sweep={short_repr(o['sweep'])} must be one of "
                             f"{', '.join(map(repr, SWEEPS))}")

    def memory_estimate(self, nq: int) -> int:
        """The base estimate; the nearest sweep adds its n × n distance arrays (5 floats a pair)."""
        n = int(self.options["population"])
        extra = 5 * 8 * n * n if self.options["sweep"] == "nearest" else 0
        return super().memory_estimate(nq) + extra

    def initialize(self, problem: Problem, population: Population,
                   rng: np.random.Generator) -> Population:
        """The first population as it is."""
        return population

    def advance(self, problem: Problem, state: Population, rng: np.random.Generator,
                t: int) -> Population:
        """One sweep of moves, one batch of costs; each firefly keeps its gain, if any."""
        o = self.options
        step = self.cooled(o["alpha"], o["alpha_end"], t) * problem.span
        sweep = sweep_all if o["sweep"] == "all" else sweep_nearest
        moved = problem.repair(sweep(state.X, state.f, problem.span, float(o["beta0"]),
                                     float(o["gamma"]), step, rng))
        greedy(state, moved, problem.cost(moved))
        return state


def sweep_all(X: Array, f: Array, span: Array, beta0: float, gamma: float, step: Array,
              rng: UniformSource) -> Array:
    r"""Every firefly moved toward every brighter one in turn (Yang's ``ffa_move``).

    For each firefly :math:`j` from the dimmest to the brightest, every firefly strictly
    dimmer than :math:`j` (cost above :math:`f_j`) moves toward :math:`j` at once:
    :math:`x_i \leftarrow x_i + β_0 e^{-γ r^2} u \odot (x_j - x_i) + (v - ½) \odot`
    ``step``, with :math:`r` from :math:`i`'s current position to :math:`j`'s (which has
    not moved yet: :math:`j` moves only toward brighter fireflies, later in the sweep).
    So each firefly meets its brighter ones in the same order as in Yang's double loop.
    The fireflies that nothing is brighter than make one random step. No box rule here.

    Args:
        X: (n, nq) positions at the start of the generation [rad or m].
        f: (n,) their costs (lower is brighter).
        span: (nq,) joint ranges; distances are measured in them.
        beta0: :math:`β_0`.
        gamma: :math:`γ`.
        step: (nq,) random step :math:`α_t \cdot` span [rad or m].
        rng: draws :math:`u, v` (a numpy Generator).

    Returns:
        (n, nq) moved positions, in the row order of ``X``.
    """
    n, nq = X.shape
    order = f.argsort(kind="stable")                      # brightest first
    Xs, fs = X.take(order, axis=0), f.take(order)
    new = Xs.copy()
    first_dimmer = fs.searchsorted(fs, side="right")      # rows >= this are dimmer than row k
    w = span**-2.0                                        # r² in joint ranges
    kernel = _kernel()
    if kernel is not None:
        _sweep_compiled(kernel, Xs, new, first_dimmer, w, beta0, gamma, step, rng)
    else:
        for k in range(n - 1, -1, -1):                    # attractor: dimmest to brightest
            s = first_dimmer[k]
            if s == n:
                continue
            D = Xs[k] - new[s:]                           # (m, nq), m = fireflies dimmer than k
            r2 = np.zeros(n - s)
            for j in range(nq):                           # fa_sweep.c's sum, in its order
                r2 = r2 + D[:, j] * D[:, j] * w[j]
            beta = beta0 * _exp(-gamma * r2)
            u, v = rng.random((2, n - s, nq))
            new[s:] += beta[:, None] * u * D + (v - 0.5) * step
    top = first_dimmer[0]                                 # the brightest: a random step only
    new[:top] += (rng.random((top, nq)) - 0.5) * step
    out = np.empty_like(new)
    out[order] = new
    return out


def _exp(x: Array) -> Array:
    """``exp`` of each element by the C library's ``exp`` (what fa_sweep.c calls).

    numpy's own ``np.exp`` is vectorised where the CPU allows (AVX-512: it differs from
    the C library's in the last bit, 4,639 of 100,000 values on one machine); the numpy
    form of the sweep must give the kernel's numbers bit for bit on any machine.
    """
    return np.array([math.exp(v) for v in x.tolist()])


def _sweep_compiled(kernel: Callable[..., None], Xs: Array, new: Array,
                    first_dimmer: NDArray[np.intp],
                    w: Array, beta0: float, gamma: float, step: Array,
                    rng: UniformSource) -> None:
    """The attractor loop of :func:`sweep_all` in C (fa_sweep.c), ``new`` moved in place.

    The draws are taken in blocks of attractors of at most :data:`BLOCK` numbers each, in
    the numpy loop's order (one ``random`` call per block instead of one per attractor).
    """
    n, nq = Xs.shape
    first = np.ascontiguousarray(first_dimmer, dtype=np.int64)
    need = 2 * nq * (n - first)                           # draws of attractor k
    Xs, w, step = (np.ascontiguousarray(a, dtype=float) for a in (Xs, w, step))
    k_hi = n - 1
    while k_hi >= 0:
        k_lo, total = k_hi, int(need[k_hi])
        while k_lo > 0 and total + need[k_lo - 1] <= BLOCK:
            k_lo -= 1
            total += int(need[k_lo])
        draws = np.ascontiguousarray(rng.random((total,)), dtype=float)
        kernel(n, nq, k_hi, k_lo, Xs.ctypes.data, new.ctypes.data, first.ctypes.data,
               w.ctypes.data, beta0, gamma, step.ctypes.data, draws.ctypes.data)
        k_hi = k_lo - 1


@functools.cache
def _kernel() -> Callable[..., None] | None:
    """``fa_sweep`` of fa_sweep.c compiled once per machine, or ``None`` (numpy form)."""
    ptr, i64, dbl = ctypes.c_void_p, ctypes.c_int64, ctypes.c_double
    return c_function(Path(__file__).with_name("fa_sweep.c"), "fa_sweep",
                      [i64, i64, i64, i64, ptr, ptr, ptr, ptr, dbl, dbl, ptr, ptr])


def sweep_nearest(X: Array, f: Array, span: Array, beta0: float, gamma: float, step: Array,
                  rng: UniformSource) -> Array:
    """Every firefly moved once, toward its nearest brighter neighbour (max β), all at once.

    Pairwise distances (in joint ranges) are one n × n broadcast from the Gram matrix.
    The brightest firefly only takes its random step. Arguments and return as for
    :func:`sweep_all`.
    """
    Y = X / span
    sq = np.einsum("ij,ij->i", Y, Y)
    r2 = np.maximum(sq[:, None] + sq[None, :] - 2.0 * (Y @ Y.T), 0.0)   # (n, n)
    brighter = f[None, :] < f[:, None]                     # [i, j]: j brighter than i
    j = np.argmin(np.where(brighter, r2, np.inf), axis=1)  # nearest brighter = max β_ij
    rows = np.arange(f.shape[0])
    beta = np.where(brighter[rows, j], beta0 * np.exp(-gamma * r2[rows, j]), 0.0)
    pull = beta[:, None] * rng.random(X.shape) * (X[j] - X)
    return X + pull + (rng.random(X.shape) - 0.5) * step
