"""Bernstein coefficients of polynomial pieces: bounds that hold over each whole piece.

Here, not in :mod:`scara_opt.trajectory.trajectory`, so the collision proofs
(:mod:`scara_opt.collision.continuous`) use them without importing the trajectory, which
imports them.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PPoly

Array = NDArray[np.float64]

__all__ = ["coefficients", "piece_bounds", "to_bernstein"]


@functools.cache
def to_bernstein(degree: int) -> Array:
    """Matrix M (d+1, d+1): Bernstein coefficients ``M @ α`` of ``Σ α_k u^k`` on [0, 1]."""
    d = degree
    return np.array([[math.comb(j, k) / math.comb(d, k) if k <= j else 0.0
                      for k in range(d + 1)] for j in range(d + 1)])


def coefficients(c: Array, x: Array) -> Array:
    """Bernstein coefficients of every piece, shaped as ``c``.

    ``c`` (d + 1, m, ...): coefficients in PPoly's layout (highest power first), ``x``
    (m + 1,) the breakpoints. Each piece's values lie within the range of its coefficients
    (convex hull property).
    """
    d = c.shape[0] - 1
    alpha = c[::-1] * (np.diff(x) ** np.arange(d + 1.0)[:, None]).reshape(
        (d + 1, -1) + (1,) * (c.ndim - 2))  # α_k = a_k h^k, lowest power first
    return (to_bernstein(d) @ alpha.reshape(d + 1, -1)).reshape(c.shape)


def piece_bounds(pp: PPoly) -> Array:
    """A bound on ``|f|`` over each piece of a piecewise polynomial.

    (n_pieces,), or (n_pieces, nq) for values in (nq,). The largest Bernstein coefficient
    in absolute value (convex hull property): never below the true largest ``|f|`` on the
    piece.
    """
    return np.abs(coefficients(pp.c, pp.x)).max(axis=0)
