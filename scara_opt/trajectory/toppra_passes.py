"""TOPP-RA's two passes over toppra's own LP solver, without its per-stage Python overhead.

toppra's ``TOPPRA.compute_parameterization`` runs, for each of the N grid stages, a few
lines of Python around two calls of its Cython ``seidelWrapper.solve_stagewise_optim``
(the 2-D LP of one stage): the backward pass (the controllable sets ``K``) and the forward
pass (the greatest controllable path velocity). Those lines, and the solver-availability
probe each instance makes (three failed imports), cost about three times the solver itself.
:func:`reachability_passes` makes the same solver calls with the same arguments, in the
same order, with toppra's numerical safeguards (``SMALL``, ``TINY``, ``MAX_TRIES``), so it
returns the same squared path velocities, to the bit (``tests/test_trajectory.py``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

__all__ = ["reachability_passes"]


def reachability_passes(constraints: list, path: Any, grid: Array) -> tuple[Array | None, str]:
    """Rest-to-rest TOPP-RA on ``grid`` (N+1,), as toppra's ``TOPPRA`` computes it.

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
