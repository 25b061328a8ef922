r"""The timed joint trajectory: one piecewise polynomial per joint, sampled and checked exactly.

Every backend (toppra's cubic spline, ruckig's constant-jerk phases, the quintic) yields
piecewise polynomials in time, so a :class:`Trajectory` keeps one
:class:`scipy.interpolate.PPoly` per joint. Its limit check is exact, not sampled: the
largest :math:`|\dot q|` and :math:`|\ddot q|` of a polynomial piece lie at the piece's ends
or where the next derivative vanishes, and those points are all evaluated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PPoly

from scara_opt.checks import check_memory, check_path, check_real, describe, float_array
from scara_opt.errors import InputError
from scara_opt.trajectory.bernstein import coefficients, piece_bounds
from scara_opt.trajectory.limits import Limits

if TYPE_CHECKING:
    from scara_opt.collision.continuous import CollisionReport
    from scara_opt.model.robot import Robot
    from scara_opt.trajectory.dynamics import RobotDynamics

Array = NDArray[np.float64]

#: times may leave [0, duration] by this much (relative to the duration) through round-off
_T_SLACK = 1e-9


def _end_values(c: Array, x: Array) -> Array:
    """Values of every piece at both of its ends, (2 m, ...): left limits included.

    ``c`` (d + 1, m, ...) in PPoly's layout, ``x`` (m + 1,) the breakpoints.
    """
    h = np.diff(x).reshape((-1,) + (1,) * (c.ndim - 2))
    right = c[0].copy()
    for row in c[1:]:
        right = right * h + row
    return np.concatenate([c[-1], right])


def _may_leave(pp: PPoly, lo: float, hi: float) -> NDArray[np.intp]:
    """Pieces (indices) whose values may leave [lo, hi]: the others provably do not.

    A polynomial on a piece lies within the range of its Bernstein coefficients (convex
    hull property), so a piece whose coefficients all lie in [lo, hi] stays inside.
    """
    b = coefficients(pp.c, pp.x)
    return np.flatnonzero((b.max(axis=0) > hi) | (b.min(axis=0) < lo))


def extrema(pp: PPoly) -> tuple[float, float]:
    """Smallest and largest value of a 1-D piecewise polynomial over its domain (exact).

    Candidates are the ends of every piece and the real roots of ``f'`` inside the pieces
    that may reach beyond the ends' range (:func:`_may_leave`); the other pieces cannot.
    """
    vals = _end_values(pp.c, pp.x)
    if pp.c.shape[0] > 2:
        idx = _may_leave(pp, float(vals.min()), float(vals.max()))
        if idx.size:  # those pieces laid end to end: same local polynomials, same values
            h = np.diff(pp.x)[idx]
            sub = PPoly(pp.c[:, idx], np.concatenate([[0.0], np.cumsum(h)]), extrapolate=False)
            roots = sub.derivative().roots(discontinuity=False, extrapolate=False)
            roots = roots[np.isfinite(roots)]
            if roots.size:
                vals = np.concatenate([vals, sub(roots)])
    return float(vals.min()), float(vals.max())


def cubic_range(pp: PPoly) -> tuple[Array, Array]:
    """Smallest and largest value (nq,) each of a piecewise cubic with values in (nq,), exact.

    ``pp.c`` is (4, N, nq) (a spline through joint waypoints). Candidates are the ends of
    every piece and the roots of its quadratic derivative inside the piece, all at once
    (the numerically stable quadratic formula, which also gives the root of a linear one).
    """
    c, h = pp.c, np.diff(pp.x)[:, None]
    a, b, d = 3.0 * c[0], 2.0 * c[1], c[2]                # q'(t) = a t² + b t + d
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = b * b - 4.0 * a * d
        q = -0.5 * (b + np.copysign(np.sqrt(np.where(disc >= 0, disc, np.nan)), b))
        roots = np.stack([q / a, d / q])                  # (2, N, nq); NaN or inf when none
    roots = np.where((roots > 0) & (roots < h), roots, np.nan)
    inner = ((c[0] * roots + c[1]) * roots + c[2]) * roots + c[3]
    right = ((c[0] * h + c[1]) * h + c[2]) * h + c[3]
    values = np.concatenate([inner.reshape(-1, c.shape[2]), c[3], right])
    return np.nanmin(values, axis=0), np.nanmax(values, axis=0)


def sup_abs_columns(c: Array, x: Array) -> Array:
    """Largest ``|f|`` (n,) of n piecewise polynomials sharing their breakpoints, exact.

    ``c`` (d + 1, m, n): coefficients in PPoly's layout (highest power first), ``x`` (m + 1,)
    the breakpoints. As :func:`extrema`, all columns at once: the pieces' ends, then the
    real roots of ``f'`` inside the pieces whose Bernstein coefficients leave the ends'
    range (the only ones that can reach beyond it).
    """
    ends = _end_values(c, x)
    lo, hi = ends.min(axis=0), ends.max(axis=0)
    best = np.maximum(np.abs(lo), np.abs(hi))
    if c.shape[0] < 3:
        return best
    b = coefficients(c, x)
    i, j = np.nonzero((b.max(axis=0) > hi) | (b.min(axis=0) < lo))
    if i.size:  # those pieces laid end to end (as in extrema): one root search for all
        x_sub = np.concatenate([[0.0], np.cumsum(np.diff(x)[i])])
        sub = PPoly(c[:, i, j], x_sub, extrapolate=False)
        roots = sub.derivative().roots(discontinuity=False, extrapolate=False)
        roots = roots[np.isfinite(roots)]
        if roots.size:
            values = np.abs(sub(roots))
            col = j[np.clip(np.searchsorted(x_sub, roots, side="right") - 1, 0, i.size - 1)]
            np.maximum.at(best, col, values)
    return best


def sup_abs(pp: PPoly) -> float:
    """Largest ``|f(t)|`` of a 1-D piecewise polynomial over its whole domain (exact)."""
    lo, hi = extrema(pp)
    return max(abs(lo), abs(hi))


def stretch(pp: PPoly, factor: float) -> PPoly:
    """``t ↦ f(t / factor)``: the same path ``factor`` times slower (velocities / factor)."""
    deg = pp.c.shape[0] - 1
    scale = factor ** -(deg - np.arange(deg + 1.0))
    return PPoly(pp.c * scale[:, None], pp.x * factor, extrapolate=False)


def concatenate(pieces: list[PPoly]) -> PPoly:
    """One PPoly from consecutive ones, each starting at time 0, laid end to end in time."""
    if len(pieces) == 1 and pieces[0].x[0] == 0.0:  # one already starts at 0: nothing to lay
        return pieces[0]
    deg = max(p.c.shape[0] for p in pieces)
    xs, cs, t0 = [np.zeros(1)], [], 0.0
    for p in pieces:
        c = np.vstack([np.zeros((deg - p.c.shape[0], p.c.shape[1])), p.c])
        xs.append(p.x[1:] - p.x[0] + t0)
        cs.append(c)
        t0 = xs[-1][-1]
    return PPoly(np.hstack(cs), np.concatenate(xs), extrapolate=False)


@dataclass(frozen=True, repr=False, eq=False)
class Trajectory:
    """A timed joint trajectory from rest to rest.

    Attributes:
        pieces: one 1-D :class:`~scipy.interpolate.PPoly` per joint, time [s] → q [rad or m].
        limits: the limits it was timed for (velocity, acceleration, jerk, position).
        method: registry name of the timing method (``"toppra"``, ``"ruckig"``, ``"quintic"``).
        waypoints: (n, nq) the joint waypoints it passes [rad or m].
        waypoint_times: (n,) when it passes them [s].
        compute_time_s: wall-clock time of the computation [s].
        notes: what the backend did beyond the obvious (safety margin, stretch factor, ...).
        dynamics: the inverse dynamics and torque limits it was timed for (with any
            payload), or ``None`` when it was not torque-limited.
    """

    pieces: tuple[PPoly, ...]
    limits: Limits
    method: str
    waypoints: Array
    waypoint_times: Array
    compute_time_s: float = 0.0
    notes: str = ""
    dynamics: RobotDynamics | None = None
    _derivs: dict = field(default_factory=dict, init=False)

    @property
    def nq(self) -> int:
        """Number of joints."""
        return len(self.pieces)

    @property
    def duration(self) -> float:
        """Total duration [s]."""
        return float(self.pieces[0].x[-1])

    def _derivative(self, k: int, order: int) -> PPoly:
        key = (k, order)
        if key not in self._derivs:
            self._derivs[key] = self.pieces[k].derivative(order) if order else self.pieces[k]
        return self._derivs[key]

    def _times(self, t: ArrayLike) -> Array:
        try:
            ts = float_array(t, "t")
        except InputError:
            raise InputError(f"t must be a time or an array of times [s]; got "
                             f"{describe(t)}") from None
        T = self.duration
        slack = _T_SLACK * max(T, 1.0)
        if not np.isfinite(ts).all():
            raise InputError("times must be finite numbers [s]; got NaN or inf")
        if ts.size and (ts.min() < -slack or ts.max() > T + slack):
            raise InputError(f"times must lie within [0, {T:.6g}] s (the duration); got values "
                             f"in [{ts.min():.6g}, {ts.max():.6g}] s")
        return np.clip(ts, 0.0, T)

    def evaluate(self, t: ArrayLike, order: int = 0) -> Array:
        """``order``-th time derivative of ``q`` at ``t``: (nq,) for a scalar, (m, nq) for (m,).

        Raises:
            InputError: a time outside [0, duration] or not finite; ``order`` not an
                integer >= 0.
        """
        if not (isinstance(order, (int, np.integer)) and not isinstance(order, bool)
                and order >= 0):
            raise InputError(f"order must be an integer >= 0 (0: q, 1: qd, 2: qdd, ...); "
                             f"got {order!r}")
        ts = self._times(t)
        flat = ts.reshape(-1)
        out = np.stack([self._derivative(k, order)(flat) for k in range(self.nq)], axis=-1)
        return out.reshape(ts.shape + (self.nq,))

    def sample(self, t: ArrayLike) -> tuple[Array, Array, Array]:
        """Positions, velocities and accelerations at ``t`` [s].

        Args:
            t: a time [s] or an array of times (m,), within [0, duration].

        Returns:
            ``(q, qd, qdd)``, each (nq,) for a scalar ``t`` or (m, nq) for an array
            [rad or m, per s, per s²].

        Raises:
            InputError: a time outside [0, duration] or not finite.
        """
        return self.evaluate(t, 0), self.evaluate(t, 1), self.evaluate(t, 2)

    def times(self, dt: float = 0.01) -> Array:
        """A grid 0, dt, 2 dt, ... ending exactly at the duration, (m,) [s].

        Raises:
            InputError: ``dt`` not a positive finite number, or so small that the grid (and
                the samples taken on it) would exceed :data:`scara_opt.checks.MAX_BYTES`.
        """
        dt = check_real("dt", dt, 0.0, low_open=True, unit="s")
        T = self.duration
        steps = T / dt
        count = math.ceil(steps) + 1 if math.isfinite(steps) else 2**64
        # the grid, and q, qd, qdd sampled on it (to_csv, plot)
        check_memory(f"times(dt={dt:g}) over {T:.6g} s", count, 8 * (2 + 4 * self.nq),
                     "raise dt")
        grid = np.arange(0.0, T, dt)
        if grid.size and T - grid[-1] < 1e-9 * dt:
            grid = grid[:-1]
        return np.append(grid, T)

    def positions(self, dt: float = 0.01) -> Array:
        """Positions (m, nq) [rad or m] on :meth:`times` ``(dt)``."""
        return self.evaluate(self.times(dt))

    def peaks(self) -> dict[str, Array]:
        """Largest |qd|, |qdd| (and |qddd| when jerk-limited) per joint, exact, (nq,) each."""
        shared = self._shared_derivatives()
        if shared is not None:  # all joints at once
            x, derivatives = shared
            return {name: sup_abs_columns(c, x) for name, c in derivatives.items()}
        return {name: np.array([sup_abs(self._derivative(k, order)) for k in range(self.nq)])
                for name, order in self._orders().items()}

    def peak_bounds(self) -> dict[str, Array]:
        """Upper bounds on :meth:`peaks` (nq,) each, never below them; cheaper.

        The largest Bernstein coefficient of each derivative's pieces in absolute value
        (:func:`~scara_opt.trajectory.bernstein.piece_bounds`: convex hull property).
        """
        shared = self._shared_derivatives()
        if shared is not None:
            x, derivatives = shared
            return {name: np.abs(coefficients(c, x)).max(axis=(0, 1))
                    for name, c in derivatives.items()}
        return {name: np.array([piece_bounds(self._derivative(k, order)).max()
                                for k in range(self.nq)])
                for name, order in self._orders().items()}

    def _orders(self) -> dict[str, int]:
        """The derivatives the limits bound: velocity, acceleration (and jerk), by order."""
        orders = {"velocity": 1, "acceleration": 2}
        if self.limits.jmax is not None:
            orders["jerk"] = 3
        return orders

    def _shared_derivatives(self) -> tuple[Array, dict[str, Array]] | None:
        """Breakpoints and each bounded derivative's coefficients (d + 1 - r, m, nq).

        All joints at once, or ``None`` where the joints' pieces do not share breakpoints.
        """
        x = self.pieces[0].x
        if not all(p.x is x or np.array_equal(p.x, x) for p in self.pieces):
            return None
        c = np.stack([p.c for p in self.pieces], axis=-1)  # (d + 1, m, nq)
        power = np.arange(c.shape[0] - 1, -1, -1.0)  # of each coefficient's τ
        out = {}
        for name, order in self._orders().items():  # d^r/dτ^r τ^p = p (p-1) ... (p-r+1) τ^(p-r)
            factor = np.prod(power[None, :] - np.arange(order)[:, None], axis=0)
            keep = len(power) - order
            out[name] = c[:keep] * factor[:keep, None, None]
        return x, out

    def speed_bounds(self) -> list[tuple[Array, Array]]:
        """Per joint: breakpoints (m + 1,) [s] and a bound (m,) on ``|q̇|`` on each piece.

        Bounds in [rad/s or m/s] (:func:`piece_bounds`): what a collision proof needs.
        """
        return [(np.asarray(p.x, float), piece_bounds(self._derivative(k, 1)))
                for k, p in enumerate(self.pieces)]

    def check_collisions(self, cell: object, robot: Robot | None = None, *,
                         margin: float | None = None) -> CollisionReport:
        """Prove the trajectory clear of a cell, or report its first contact.

        Not sampled: between checked instants, a bound on how far any point of the robot
        can move (from the joint speeds' bounds and the link geometry) must stay below the
        clearance measured at them, or the interval is split
        (:mod:`scara_opt.collision.continuous`).

        Args:
            cell: a :class:`~scara_opt.Cell` (with ``robot``) or a
                :class:`~scara_opt.CollisionChecker`.
            robot: the robot the trajectory moves (not needed with a checker).
            margin: clearance to keep [m]; default a checker's own (0 with a Cell); given
                with a checker, it is used (``checker.with_margin(margin)``).

        Returns:
            A :class:`~scara_opt.collision.continuous.CollisionReport`: ``clear`` with the
            least clearance along the whole trajectory (``least``, to 0.1 mm) and the
            proven lower bound (``clearance``), or the first contact's ``time`` [s],
            ``bodies`` and ``depth`` [m].

        Raises:
            InputError: neither a Cell nor a checker, no robot, or a robot of another size.
        """
        from scara_opt.collision.continuous import collision_report, make_checker

        return collision_report(make_checker(cell, robot, margin, self.nq), self)

    def position_range(self) -> tuple[Array, Array]:
        """Smallest and largest value of each joint over the trajectory, exact, (nq,) each.

        Between waypoints a spline can overshoot them; compare with the joint limits.
        """
        lo, hi = zip(*(extrema(p) for p in self.pieces), strict=True)
        return np.array(lo), np.array(hi)

    def check_limits(self) -> dict[str, Array]:
        """Largest ``|qd| / vmax`` and ``|qdd| / amax`` per joint (and jerk for ruckig).

        The maxima are exact over the whole trajectory (see the module docstring), so any
        sample of it is at or below them; a ratio <= 1 means the limit holds. A
        torque-limited trajectory adds ``"torque"``: the largest ``|τ| / τ_max`` per joint
        with τ from Pinocchio's RNEA sampled at 1 kHz (and the end), payload included.

        Returns:
            ``{"velocity": (nq,), "acceleration": (nq,)}``, plus ``"jerk"`` when the
            trajectory was timed with a jerk limit and ``"torque"`` when with torque limits.
        """
        lim = {"velocity": self.limits.vmax, "acceleration": self.limits.amax}
        if self.limits.jmax is not None:
            lim["jerk"] = self.limits.jmax
        out = {name: peak / lim[name] for name, peak in self.peaks().items()}
        if self.dynamics is not None:
            if "torque" not in self._derivs:
                self._derivs["torque"] = self.dynamics.ratios(self)
            out["torque"] = self._derivs["torque"].copy()
        return out

    def check_torque(self, robot: Robot, torque_limits: object = None, payload: object = None,
                     payload_frame: str | None = None) -> Array:
        """Largest ``|τ| / τ_max`` per joint (nq,), τ by Pinocchio's RNEA sampled at 1 kHz.

        For any trajectory, torque-limited or not; the arguments are those of
        :class:`~scara_opt.trajectory.dynamics.RobotDynamics` (default: the robot's own
        torque limits, no payload).

        Raises:
            DynamicsError: the robot has no inertial data or no torque limits.
            InputError: ``robot`` not a Robot with nq joints; bad ``torque_limits`` or
                ``payload``.
            FrameNotFoundError: ``payload_frame`` is not a frame of the robot.
        """
        from scara_opt.model.robot import check_robot
        from scara_opt.trajectory.dynamics import RobotDynamics

        check_robot(robot)
        if robot.nq != self.nq:
            raise InputError(f"robot {robot.name!r} has {robot.nq} joints, the trajectory "
                             f"{self.nq}; pass the robot it was timed for")
        return RobotDynamics(robot, torque_limits, payload, payload_frame).ratios(self)

    def to_csv(self, path: str | Path, dt: float = 0.01) -> Path:
        """Write t, q, qd, qdd on the grid ``dt`` to a CSV file; units in the column names.

        Columns in that order, each block over the joints: ``t_s``, every ``<joint>_rad``
        (or ``_m``), every ``<joint>_rad_per_s``, every ``<joint>_rad_per_s2`` (the order
        of ``to_json``'s ``t_s``, ``q``, ``qd``, ``qdd``). A torque-limited trajectory adds
        each joint's torque ``<joint>_torque_Nm`` (or ``_N`` for a prismatic joint),
        Pinocchio's RNEA with the payload it was timed for.

        Returns:
            The path written.
        """
        t = self.times(dt)
        q, qd, qdd = self.sample(t)
        units = [{"rad": "rad", "m": "m"}.get(self.limits.unit(k), "unit")
                 for k in range(self.nq)]
        cols, header = [t, q, qd, qdd], ["t_s"]
        for suffix in ("", "_per_s", "_per_s2"):
            header += [f"{name}_{u}{suffix}"
                       for name, u in zip(self.limits.joint_names, units, strict=True)]
        if self.dynamics is not None:
            tau = self.dynamics.torques(q, qd, qdd)
            for k, name in enumerate(self.limits.joint_names):
                cols.append(tau[:, k])
                header.append(f"{name}_torque_{'N' if self.limits.unit(k) == 'm' else 'Nm'}")
        path = check_path("path", path)
        np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header),
                   comments="", fmt="%.10g")
        return path

    def plot(self, path: str | Path, dt: float | None = None, title: str | None = None) -> Path:
        """Save a PNG of q, qd, qdd per joint with the limit lines (matplotlib, Agg).

        Args:
            path: the PNG file to write.
            dt: sampling step [s]; default: 1/500 of the duration.
            title: figure title; default: method and duration.

        Returns:
            The path written.
        """
        from scara_opt.trajectory.plot import plot_trajectory

        return plot_trajectory(self, path, dt=dt, title=title)

    def __repr__(self) -> str:
        return (f"Trajectory(method={self.method!r}, duration={self.duration:.4f} s, "
                f"nq={self.nq}, waypoints={len(self.waypoints)})")

    __str__ = __repr__
