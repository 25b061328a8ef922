"""One GA generation from its random draws: the children in C (numpy as fallback), survivors.

:func:`offspring` runs ga_breed.c where it compiles (:func:`~scara_opt.model.compiled.c_function`)
and :func:`offspring_numpy` otherwise (or under ``SCARA_OPT_NO_COMPILE=1``): the same
operations in the same order, so the same bits (tests/test_ga_kernel.py). The draws stay
in numpy (:meth:`Draws.draw`), the same numbers in the order the GA always took them, into
buffers made once a solve: the kernel's arguments are their addresses, taken once (a
``.ctypes.data`` costs ~1 µs, more than the kernel's arithmetic; issue 18).
:meth:`Draws.survivors` keeps :func:`~scara_opt.metaheuristics.base.survivors`' rows.
"""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.metaheuristics.base import Population, survivors
from scara_opt.metaheuristics.problem import Array, Problem
from scara_opt.model.compiled import c_function


class Draws:
    """A generation's random draws and the kernel's buffers, for ``n`` rows and tournament ``t``.

    Attributes:
        entrants: (2, n, t) int64 rows: tournaments ``i`` and ``n + i`` give child ``i``'s
            parents ``p1`` and ``p2``.
        u: (n, nq) uniform draws in [0, 1): the blend weights are
            ``u_low + u_range * u``, :math:`U(-γ, 1 + γ)`, as numpy's ``uniform`` makes them
            from the same draws (bit for bit).
        u_low, u_range: :math:`-γ` and :math:`(1 + γ) - (-γ)`, set by :meth:`draw`.
        rc: (n, 1) uniform draws: child ``i`` is crossed where ``rc < crossover``.
        rm: (n, nq) uniform draws: a gene mutates where ``rm < mutation``.
        step: (n, nq) standard normal mutation steps.
        cur, other: two :class:`_Pool` used in turn: the kernel reads the parents and
            writes the children into ``cur``; the survivors are taken from it into
            ``other``'s parent rows, which become ``cur`` (no copy back). So a population
            :meth:`survivors` returns lives there until the generation after next.
    """

    def __init__(self, problem: Problem, n: int, t: int) -> None:
        nq = problem.nq
        self.shape = (n, t)
        self.entrants = np.empty((2, n, t), dtype=np.int64)
        self.u, self.step = np.empty((n, nq)), np.empty((n, nq))
        self.u_low, self.u_range = 0.0, 1.0
        self.uniform = np.empty(n * (1 + nq))           # rc then rm: one call, one stream
        self.rc, self.rm = self.uniform[:n].reshape(n, 1), self.uniform[n:].reshape(n, nq)
        self.span, self.lo, self.hi = (a.copy() for a in (problem.span, problem.lower,
                                                          problem.upper))
        self.repair = not problem._any_periodic   # else Problem.repair wraps, after
        self.cur, self.other = _Pool(self, n, nq, t), _Pool(self, n, nq, t)

    @property
    def out(self) -> Array:
        """The current pool's children (n, nq): the C form's output."""
        return self.cur.out

    @staticmethod
    def of(problem: Problem, n: int, t: int) -> Draws:
        """The buffers of ``problem``'s solve, made at its first generation.

        Kept on the problem, which lives for one solve (as its per-size buffers do).
        """
        draws: Draws | None = problem.__dict__.get("_ga_draws")
        if draws is None or draws.shape != (n, t):
            draws = problem.__dict__["_ga_draws"] = Draws(problem, n, t)
        return draws

    def draw(self, rng: np.random.Generator, blend: float) -> None:
        """Take the draws, in the GA's order: entrants, u, rc, rm, step.

        ``out=`` where the generator has it: the same numbers as a fresh array; ``rc`` and
        ``rm`` in one call (the generator fills them from one stream, in the same order).
        """
        n, t = self.shape
        np.copyto(self.entrants, rng.integers(n, size=(2, n, t)))
        rng.random(out=self.u)   # the weights' draws: uniform(-γ, 1 + γ) is low + range * u
        self.u_low = -blend
        self.u_range = (1.0 + blend) - self.u_low
        rng.random(out=self.uniform)
        rng.standard_normal(out=self.step)

    def survivors(self, X: Array, f: Array, children: Array, fc: Array) -> Population:
        """:func:`~scara_opt.metaheuristics.base.survivors` of the parents and the children.

        The same rows: where ``children`` is :attr:`out` (the C form), the stable sort of
        the pool's costs (parents first, so ties keep the old) picks them from the pool,
        without stacking the two again, into the other pool.
        """
        n, p, q = self.shape[0], self.cur, self.other
        if children is not p.out:
            return survivors(X, f, children, fc, n)
        np.copyto(p.fc, fc)
        order = p.pool_f.argsort(kind="stable")[:n]
        p.pool.take(order, axis=0, out=q.X, mode="clip")   # "clip": no index is out of
        p.pool_f.take(order, out=q.f, mode="clip")         # range; "raise" copies twice
        self.cur, self.other = q, p
        return Population(q.X, q.f)


def offspring(problem: Problem, X: Array, f: Array, d: Draws, sigma: float,
              crossover: float, mutation: float) -> Array:
    """The children (n, nq) of population ``X`` (n, nq), costs ``f`` (n,), in the box.

    Parents ``p1``, ``p2``: the :func:`winners` of ``d.entrants``; the child is
    ``p1 + u (p2 - p1)`` where ``rc < crossover``, else ``p1``; then
    ``+ step * (sigma * span) * (rm < mutation)``; then :meth:`Problem.repair`. Where the
    kernel repairs (no continuous joint), the C form's result is ``d.out``, overwritten by
    the next call (pass it to :meth:`Draws.survivors`).
    """
    kernel = _kernel()
    if kernel is None:
        return offspring_numpy(problem, X, f, d, sigma, crossover, mutation)
    p = d.cur
    if X is not p.X:                        # else already there: the last survivors
        np.copyto(p.X, X)
    if f is not p.f:
        np.copyto(p.f, f)
    kernel(p.address, sigma, crossover, mutation, d.u_low, d.u_range)
    if not d.repair:
        np.copyto(p.out, problem.repair(p.out))
    return p.out


def offspring_numpy(problem: Problem, X: Array, f: Array, d: Draws, sigma: float,
                    crossover: float, mutation: float) -> Array:
    """:func:`offspring` in numpy (where nothing compiles); ``d`` is left as it was."""
    children, p2 = X.take(winners(d.entrants, f), axis=0)   # p1, p2: (n, nq) each, fresh
    blend = np.subtract(p2, children, out=p2)
    blend *= d.u * d.u_range + d.u_low                # U(-γ, 1 + γ), as numpy's uniform
    blend += children                                 # p1 + u (p2 - p1)
    np.copyto(children, blend, where=d.rc < crossover)   # the crossed; p1 the rest
    step = d.step * (sigma * problem.span)            # σ_t (u_j - l_j) ε
    step *= d.rm < mutation                           # 0 for the genes that keep
    children += step
    return problem.repair(children)


def winners(entrants: NDArray[np.intp], f: Array) -> NDArray[np.intp]:
    """The cheapest entrant of each tournament (the first of equals, as ``argmin``).

    Args:
        entrants: (..., t) row indices, the last axis one tournament.
        f: the rows' costs.

    Returns:
        (...) the winners' row indices (picked by flat ``take``: ~4 instead of ~8 µs for
        ``take_along_axis`` at 2 x 100 tournaments of 2).
    """
    t = entrants.shape[-1]
    pick = f.take(entrants).argmin(axis=-1)
    first = np.arange(0, entrants.size, t).reshape(pick.shape)  # each tournament's start
    return entrants.reshape(-1).take(first + pick)


@functools.cache
def _kernel() -> Callable[..., Any] | None:
    """``ga_children`` of ga_breed.c compiled once per machine, or ``None`` (numpy form)."""
    dbl = ctypes.c_double
    return c_function(Path(__file__).with_name("ga_breed.c"), "ga_children",
                      [ctypes.c_void_p, dbl, dbl, dbl, dbl, dbl])


class _Pool:
    """Parents over children, and their costs: ``pool`` (2n, nq), ``pool_f`` (2n,).

    With their views (``X``, ``out``; ``f``, ``fc``) and the kernel's struct, which points
    into them and into the draws of ``d``.
    """

    def __init__(self, d: Draws, n: int, nq: int, t: int) -> None:
        self.pool, self.pool_f = np.empty((2 * n, nq)), np.empty(2 * n)
        self.X, self.out = self.pool[:n], self.pool[n:]
        self.f, self.fc = self.pool_f[:n], self.pool_f[n:]
        arrays = {k: getattr(self if hasattr(self, k) else d, k).ctypes.data
                  for k, *_ in _Args._fields_[4:]}
        self.args = _Args(n=n, nq=nq, t=t, repair=d.repair, **arrays)
        self.address = ctypes.addressof(self.args)   # the struct lives as long as self


class _Args(ctypes.Structure):
    """ga_breed.c's ``struct ga_args``: sizes, then the buffers' addresses, in its order."""

    _fields_ = [(name, ctypes.c_int64) for name in ("n", "nq", "t", "repair")] + [
        (name, ctypes.c_void_p) for name in ("X", "f", "entrants", "u", "rc", "rm", "step",
                                             "span", "lo", "hi", "out")]
