"""toppra's geometric path, the not-a-knot cubic spline, without the per-call overhead.

toppra's :class:`~toppra.SplineInterpolator` is scipy's ``CubicSpline`` (not-a-knot) and
its two derivatives. Built through them, a spline of a dozen waypoints costs 0.2-0.5 ms,
almost all of it input validation and array-API dispatch: a tenth of a planned SCARA move.
:func:`not_a_knot` computes the same spline by CubicSpline's own formulas (its not-a-knot
branch: the slopes from one tridiagonal system, here solved by LAPACK's ``dgtsv``; the
line through two points; the parabola through three) and :func:`geometric_path` gives it
toppra's interface, so toppra's constraints, our timing and the proofs use it unchanged.
Both agree with scipy's and toppra's to round-off (``tests/test_spline.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline, PPoly
from scipy.linalg import lapack

Array = NDArray[np.float64]

__all__ = ["geometric_path", "not_a_knot"]


def not_a_knot(s: Array, Q: Array) -> CubicSpline:
    """scipy's ``CubicSpline(s, Q)`` (not-a-knot ends), from its own formulas.

    ``s`` (n,) strictly increasing, ``Q`` (n, nq) finite, n >= 2 (the callers build ``s``
    from validated waypoints, :func:`~scara_opt.trajectory.toppra_backend.chord_parameter`).

    Raises:
        ValueError: ``s`` not strictly increasing (as scipy), or n < 2.
    """
    s = np.asarray(s, dtype=float)
    Q = np.asarray(Q, dtype=float)
    n = len(s)
    if n < 2 or not (np.diff(s) > 0.0).all():
        raise ValueError(f"a spline needs n >= 2 strictly increasing parameters; got {s!r}")
    if n == 3:
        return _parabola(s, Q)
    dx = np.diff(s)
    slope = np.diff(Q, axis=0) / dx[:, None]
    if n == 2:  # as scipy: both end slopes the chord's, a straight line
        d = np.vstack([slope, slope])
    else:  # the slopes d (n, nq): scipy's banded system, its rows as CubicSpline fills them
        diag = np.empty(n)
        upper, lower = np.empty(n - 1), np.empty(n - 1)
        rhs = np.empty_like(Q)
        diag[1:-1] = 2.0 * (dx[:-1] + dx[1:])
        upper[1:] = dx[:-1]
        lower[:-1] = dx[1:]
        rhs[1:-1] = 3.0 * (dx[1:, None] * slope[:-1] + dx[:-1, None] * slope[1:])
        first, last = s[2] - s[0], s[-1] - s[-3]
        diag[0], upper[0] = dx[1], first
        rhs[0] = ((dx[0] + 2.0 * first) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / first
        diag[-1], lower[-1] = dx[-2], last
        rhs[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * last + dx[-1]) * dx[-2] * slope[-1]) / last
        *_, d, info = lapack.dgtsv(lower, diag, upper, rhs)
        if info != 0:  # pragma: no cover - the system is diagonally dominant inside
            raise np.linalg.LinAlgError(f"the spline's slope system is singular (dgtsv {info})")
    t = (d[:-1] + d[1:] - 2.0 * slope) / dx[:, None]  # CubicHermiteSpline's coefficients
    c = np.stack([t / dx[:, None], (slope - d[:-1]) / dx[:, None] - t, d[:-1], Q[:-1]])
    return CubicSpline.construct_fast(c, s, extrapolate=True)


def _parabola(s: Array, Q: Array) -> CubicSpline:
    """The not-a-knot spline through three points: the parabola through them.

    Built directly: scipy solves a 3 x 3 system for it through LAPACK, ~10 ms a call where
    OpenBLAS's threads contend for the cores (0.02 ms with one thread).
    """
    h0, h1 = s[1] - s[0], s[2] - s[1]
    m0, m1 = (Q[1] - Q[0]) / h0, (Q[2] - Q[1]) / h1
    d2 = 2.0 * (m1 - m0) / (h0 + h1)  # (nq,) the second derivative, constant
    d1 = (m0 * h1 + m1 * h0) / (h0 + h1)  # at the middle point
    c = np.zeros((4, 2, Q.shape[1]))
    c[1] = d2 / 2
    c[2] = [d1 - d2 * h0, d1]
    c[3] = Q[:2]
    return CubicSpline.construct_fast(c, np.asarray(s, float), extrapolate=True)


def _derivative(pp: PPoly) -> PPoly:
    """``pp.derivative()`` of a cubic (or lower) piecewise polynomial, without its checks."""
    k = pp.c.shape[0] - 1
    return PPoly.construct_fast(pp.c[:-1] * np.arange(k, 0, -1.0).reshape(
        (k,) + (1,) * (pp.c.ndim - 1)), pp.x, extrapolate=pp.extrapolate)


def geometric_path(s: Array, Q: Array) -> Any:
    """toppra's ``SplineInterpolator(s, Q)``: :func:`not_a_knot` and its two derivatives.

    ``s`` (n,) strictly increasing path parameters, ``Q`` (n, nq) waypoints, n >= 2.
    """
    import toppra

    path = toppra.SplineInterpolator.__new__(toppra.SplineInterpolator)
    path.ss_waypoints = np.array(s, dtype=float)
    path._q_waypoints = np.array(Q, dtype=float)
    path.cspl = not_a_knot(path.ss_waypoints, path._q_waypoints)
    path.cspld = _derivative(path.cspl)
    path.cspldd = _derivative(path.cspld)
    return path
