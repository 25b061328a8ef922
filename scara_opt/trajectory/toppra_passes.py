"""TOPP-RA's two passes over toppra's stage LPs, without its per-stage Python overhead.

toppra's ``TOPPRA.compute_parameterization`` runs, for each of the N grid stages, a few
lines of Python around two calls of its Cython ``seidelWrapper.solve_stagewise_optim``
(the 2-D LP of one stage): the backward pass (the controllable sets ``K``) and the forward
pass (the greatest controllable path velocity). Those lines, and the solver-availability
probe each instance makes (three failed imports), cost about three times the solver itself.

:func:`reachability_passes` takes the stage rows toppra's constraints give
(``compute_constraint_params``, assembled as ``seidelWrapper`` assembles them) and runs both
passes in C (toppra_passes.c, compiled once per machine by
:func:`~scara_opt.model.compiled.c_function`): each backward LP exactly, by eliminating the
path acceleration ``u`` (Fourier-Motzkin: two variables, a few dozen rows), the forward
pass as toppra's own 1-D LP with toppra's round-off safeguards (``SMALL``, ``TINY``,
``MAX_TRIES``). Its velocities agree with toppra's ``TOPPRA`` to round-off
(``tests/test_toppra_passes.py``). Where nothing compiles (or ``SCARA_OPT_NO_COMPILE=1``)
:func:`seidel_passes` runs: toppra's own Cython LP, called with the same arguments in the
same order as ``TOPPRA``, so the same velocities to the bit.
"""

from __future__ import annotations

import ctypes
import functools
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.model.compiled import c_function

Array = NDArray[np.float64]

__all__ = ["reachability_passes", "seidel_passes", "stage_rows"]

#: seidelWrapper's box on a variable without one (its ``VAR_MIN`` / ``VAR_MAX``)
UNBOUNDED = 1e8


def reachability_passes(constraints: list, path: Any, grid: Array) -> tuple[Array | None, str]:
    """Rest-to-rest TOPP-RA on ``grid`` (N+1,): toppra's ``TOPPRA``, in C where it compiles.

    Arguments and return as :func:`seidel_passes`; the velocities agree with it to round-off.
    """
    kernel = _kernel()
    if kernel is None:
        return seidel_passes(constraints, path, grid)
    from toppra.algorithm import ParameterizationReturnCode as Code
    from toppra.constants import MAX_TRIES, SMALL, TINY

    a, b, c, ubox, xbox = stage_rows(constraints, path, grid)
    n, m = len(grid) - 1, a.shape[1]
    ulo, uhi, xlo, xhi = (np.ascontiguousarray(v) for v in (*ubox.T, *xbox.T))
    delta = np.ascontiguousarray(np.diff(grid), dtype=float)
    out = np.zeros((3, n + 1))
    code = kernel(n, m, *(v.ctypes.data for v in (a, b, c, ulo, uhi, xlo, xhi, delta)),
                  SMALL, TINY, MAX_TRIES, *(out[k].ctypes.data for k in range(3)))
    if code:
        return None, Code.FailUncontrollable if code == 1 else Code.ErrUnknown
    return np.sqrt(out[2]), Code.Ok


def stage_rows(constraints: list, path: Any, grid: Array) -> tuple[Array, ...]:
    """Every stage's LP as toppra's ``seidelWrapper`` assembles it.

    Returns:
        ``(a, b, c, ubox, xbox)``: rows ``a u + b x + c <= 0`` (N+1, m) each, rows 0 and 1
        left zero (the next controllable set's, filled per stage), and the boxes
        ``[low, high]`` (N+1, 2) of the path acceleration ``u`` and of ``x`` (the squared
        path velocity).

    Raises:
        NotImplementedError: a constraint that is not canonical linear (as seidelWrapper).
    """
    from toppra.constraint import ConstraintType

    n1 = len(grid)
    a_rows, b_rows, c_rows = [np.zeros((n1, 2))], [np.zeros((n1, 2))], [np.zeros((n1, 2))]
    ubox = np.tile([-UNBOUNDED, UNBOUNDED], (n1, 1))
    xbox = ubox.copy()
    for con in constraints:
        if con.get_constraint_type() != ConstraintType.CanonicalLinear:
            raise NotImplementedError(f"{con!r} is not canonical linear")
        a, b, c, F, h, ubound, xbound = con.compute_constraint_params(path, grid)
        if a is not None:
            if con.identical:
                a_rows.append(a @ F.T)
                b_rows.append(b @ F.T)
                c_rows.append(c @ F.T - h)
            else:
                a_rows.append(np.einsum("ikj,ij->ik", F, a))
                b_rows.append(np.einsum("ikj,ij->ik", F, b))
                c_rows.append(np.einsum("ikj,ij->ik", F, c) - h)
        for box, bound in ((ubox, ubound), (xbox, xbound)):
            if bound is not None:
                box[:, 0] = np.maximum(box[:, 0], bound[:, 0])
                box[:, 1] = np.minimum(box[:, 1], bound[:, 1])
    return (*(np.ascontiguousarray(np.hstack(r), dtype=float)
              for r in (a_rows, b_rows, c_rows)), ubox, xbox)


@functools.cache
def _kernel() -> Callable[..., int] | None:
    """``toppra_passes`` of toppra_passes.c compiled once per machine, or ``None``."""
    ptr, i32, dbl = ctypes.c_void_p, ctypes.c_int, ctypes.c_double
    return c_function(Path(__file__).with_name("toppra_passes.c"), "toppra_passes",
                      [i32, i32] + [ptr] * 8 + [dbl, dbl, i32] + [ptr] * 3, ctypes.c_int)


def seidel_passes(constraints: list, path: Any, grid: Array) -> tuple[Array | None, str]:
    """Rest-to-rest TOPP-RA on ``grid`` (N+1,), as toppra's ``TOPPRA`` computes it, to the bit.

    What ``TOPPRA(..., solver_wrapper="seidel").compute_parameterization(0, 0)`` computes.

    Args:
        constraints: toppra constraints (velocity, acceleration, ...: no conic ones).
        path: the toppra interpolator (its ``path_interval`` is the grid's ends).
        grid: increasing path parameters, the path's ends included.

    Returns:
        ``(sd, code)``: the path velocities (N+1,) [1/s] and toppra's
        ``ParameterizationReturnCode`` (``sd`` is ``None`` unless the code is ``Ok``).
    """
    from toppra.algorithm import ParameterizationReturnCode as Code
    from toppra.constants import MAX_TRIES, SMALL, TINY
    from toppra.solverwrapper.cy_seidel_solverwrapper import seidelWrapper

    solver = seidelWrapper(constraints, path, grid, solve_lp1d=True)
    solve = solver.solve_stagewise_optim
    n = len(grid) - 1
    nan = math.nan
    g = np.zeros(solver.get_no_vars())
    g[0], g[1] = 1e-9, -1.0
    g_low = -g
    lower = [0.0] * (n + 1)  # the controllable sets K[i] = [lower[i], upper[i]] (squared)
    upper = [0.0] * (n + 1)
    for i in range(n - 1, -1, -1):
        lo, hi = lower[i + 1], upper[i + 1]
        x_hi = float(solve(i, None, g, nan, nan, lo, hi)[1])
        x_lo = float(solve(i, None, g_low, nan, nan, lo, hi)[1])
        if math.isnan(x_hi) or math.isnan(x_lo):
            return None, Code.FailUncontrollable
        upper[i], lower[i] = x_hi, max(x_lo, 0.0)
    if SMALL < lower[0] or upper[0] + SMALL < 0.0:  # the start at rest is not controllable
        return None, Code.FailUncontrollable
    deltas = solver.get_deltas()
    xs = [0.0] * (n + 1)
    tries, i = 0, 0
    while i < n:
        g[0], g[1] = -2.0 * deltas[i], -1.0
        u = float(solve(i, None, g, xs[i], xs[i], lower[i + 1], upper[i + 1])[0])
        if math.isnan(u):  # just infeasible by round-off: lower x[i] slightly, as toppra
            if tries < MAX_TRIES:
                xs[i] = max(xs[i] - TINY, 0.999 * xs[i])
                tries += 1
                continue
            return None, Code.ErrUnknown
        tries = 0
        x_next = xs[i] + 2.0 * deltas[i] * u
        x_next = max(x_next - TINY, 0.9999 * x_next)
        xs[i + 1] = min(upper[i + 1], max(lower[i + 1], x_next))
        i += 1
    return np.sqrt(np.array(xs)), Code.Ok
