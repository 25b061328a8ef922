r"""Moving through waypoints with the community Ruckig, which has no intermediate waypoints.

Ruckig passes intermediate waypoints at speed only in Ruckig Pro (or through its cloud
API, which needs the network). With the community version installed from PyPI, the
``"ruckig"`` timing goes through the waypoints in one of two ways, both moving, both
chosen from the path, each within the joint velocity, acceleration and jerk limits:

* **joined segments** (:func:`passing_velocities`): one Ruckig move per segment, in joint
  space, joined at the waypoints at non-zero velocities taken from the path: the tangent
  :math:`q'(s_i)` of the spline through the waypoints (toppra's, on the chord parameter)
  times a path speed :math:`\dot s_i` within the joint velocity limits, the centripetal
  bound :math:`|q''| \dot s^2 \le a_{max}/2` and a forward-backward pass
  :math:`\dot s_{i+1}^2 \le \dot s_i^2 + 2 U_i Δs_i` (:math:`U_i`: half the joint
  acceleration over the largest :math:`|q'|` of the segment), starting and ending at rest.
  Accelerations are 0 at the joins, so the acceleration stays continuous. Good on sparse
  waypoints, where each segment is long against the time the jerk limit needs to build up
  an acceleration (``amax / jmax``, 0.1 s by default).
* **along the path** (:func:`along_path`): Ruckig times the path parameter
  :math:`s: 0 \to 1` of that spline rest to rest under constant bounds on
  :math:`\dot s`, :math:`\ddot s` (:func:`path_bounds`) and the path jerk,
  :math:`10/s \times \ddot s_{max}`, and :math:`q(s(t))` is written exactly as degree-9 polynomials
  (:func:`compose`); any joint ratio still above 1 (the jerk's curvature terms) is removed
  by a uniform time stretch. Good on dense waypoints (an arc, a contour), which the first
  way would cross in jerk-limited bumps.

:func:`scara_opt.trajectory.ruckig_backend.ruckig_trajectory` times both and keeps the
shorter (said in ``Trajectory.notes``). A joined segment that would leave the position
limits between its waypoints has its end velocities set to 0 (rest to rest there, on the
straight joint line).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline, PPoly

from scara_opt.errors import TrajectoryError
from scara_opt.trajectory.limits import Limits
from scara_opt.trajectory.spline import not_a_knot
from scara_opt.trajectory.toppra_backend import chord_parameter

Array = NDArray[np.float64]

#: share of the joint acceleration the centripetal term and the path acceleration may
#: each take at a join
SHARE = 0.5
#: a waypoint velocity below this share of vmax is 0 (round-off of a joint that rests:
#: Ruckig cannot synchronise a still joint to a tiny velocity in a short time)
STILL = 1e-9
#: grid points per waypoint interval at which :func:`path_bounds` evaluates (>= 200 in all)
SAMPLES = 4


def spline(Q: Array, limits: Limits) -> tuple[CubicSpline, Array]:
    """toppra's spline through ``Q`` (n, nq) on the chord parameter, and that parameter (n,)."""
    s = chord_parameter(Q, limits.vmax)
    return not_a_knot(s, Q), s


def passing_velocities(Q: Array, limits: Limits) -> Array:
    """Joint velocities (n, nq) [rad/s or m/s] at the waypoints: 0 at both ends, moving between.

    See the module docstring (joined segments).
    """
    cs, s = spline(Q, limits)
    d1 = cs(s, 1)
    a1, a2 = np.abs(d1), np.abs(cs(s, 2))
    with np.errstate(divide="ignore"):
        bound = np.minimum(np.min(limits.vmax / a1, axis=1),
                           np.min(np.sqrt(SHARE * limits.amax / a2), axis=1))
        U = np.min(SHARE * limits.amax / np.maximum(a1[:-1], a1[1:]), axis=1)
    ds = np.diff(s)
    sd = bound.copy()
    sd[0] = sd[-1] = 0.0
    for i in range(len(s) - 1):
        sd[i + 1] = min(sd[i + 1], math.sqrt(sd[i] ** 2 + 2.0 * U[i] * ds[i]))
    for i in range(len(s) - 2, -1, -1):
        sd[i] = min(sd[i], math.sqrt(sd[i + 1] ** 2 + 2.0 * U[i] * ds[i]))
    V = d1 * sd[:, None]
    V[np.abs(V) < STILL * limits.vmax] = 0.0
    return np.clip(V, -limits.vmax, limits.vmax)


def bounds_grid(s: Array) -> Array:
    """Path parameters at which bounds are evaluated (:data:`SAMPLES` per interval, >= 200).

    ``s`` (n,): the waypoints' parameters.
    """
    return np.linspace(0.0, 1.0, max(SAMPLES * (len(s) - 1), 200) + 1)


def path_bounds(path: CubicSpline, s: Array, limits: Limits,
                speed_cap: float = math.inf) -> tuple[float, float, Array, Array]:
    r"""Constant bounds ``(V, U)`` on the path speed and acceleration that the joints allow.

    ``V``: the smallest of ``speed_cap``, ``vmax / |q'|`` and ``sqrt(amax / 2 / |q''|)``
    (the centripetal term takes at most half the acceleration); ``U``: the smallest
    ``(amax - |q''| V²) / |q'|``, so :math:`|q' \ddot s + q'' \dot s^2| \le a_{max}` for any
    :math:`|\ddot s| \le U`. Both over a grid of :data:`SAMPLES` points per interval (at
    least 200); also returns the grid and ``|q''|`` on it, for further bounds.
    """
    grid = bounds_grid(s)
    dq, ddq = np.abs(path(grid, 1)), np.abs(path(grid, 2))
    with np.errstate(divide="ignore"):
        V = min(speed_cap, float(np.min(limits.vmax / dq)),
                float(np.min(np.sqrt(0.5 * limits.amax / ddq))))
        U = float(np.min((limits.amax - ddq * V**2) / dq))
    return V, U, grid, ddq


def compose(path: CubicSpline, ps: PPoly, knots: Array) -> tuple[tuple[PPoly, ...], Array]:
    """``q(s(t))`` exactly, as degree-9 PPolys; and the times ``s(t)`` reaches each knot."""
    hits = [0.0] + [float(ps.solve(k, extrapolate=False)[0]) for k in knots[1:-1]]
    hits.append(float(ps.x[-1]))
    br = np.unique(np.concatenate([ps.x, hits]))
    br = br[np.concatenate([[True], np.diff(br) > 1e-12])]
    nodes = (1 - np.cos(np.pi * (np.arange(10) + 0.5) / 10)) / 2  # Chebyshev on [0, 1]
    h = np.diff(br)
    tau = h[:, None] * nodes[None, :]  # (m, 10) local times
    sv = np.clip(ps(br[:-1, None] + tau), 0.0, 1.0)
    Qv = path(sv.ravel()).reshape(len(h), 10, -1)  # (m, 10, nq)
    Vm = np.vander(nodes, 10)  # fit in the unit variable, then rescale to time
    coef = np.linalg.solve(Vm[None], Qv)  # (m, 10, nq), highest power first
    coef = coef / (h[:, None, None] ** np.arange(9, -1, -1)[None, :, None])
    pieces = tuple(PPoly(coef[:, :, k].T, br, extrapolate=False) for k in range(Qv.shape[2]))
    return pieces, np.array(hits)


def check_bounds(V: float, U: float, what: str) -> None:
    """Refuse bounds that are not finite and positive (a path the joints cannot move along).

    Raises:
        TrajectoryError: naming ``what`` timed them and what to do.
    """
    if not (math.isfinite(V) and math.isfinite(U) and V > 0 and U > 0):
        raise TrajectoryError(f"{what} found no positive bound on the path speed or "
                              "acceleration for this path; use method='toppra'")
