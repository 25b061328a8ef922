r"""Tool limits: translational speed and acceleration of the tip, and its yaw rate.

Along a geometric path :math:`q(s)` the tip moves as :math:`p(s) = \mathrm{FK}(q(s))`, so
with the path speed :math:`\dot s` (:math:`x = \dot s^2`) and acceleration :math:`u = \ddot s`

.. math::  \dot p = p'\dot s, \qquad \ddot p = p' u + p'' x, \qquad \dot ψ = ψ' \dot s.

Speed and yaw rate are first-order constraints, :math:`x \le (v_{max}/\|p'\|)^2` and
:math:`x \le (ω_{max}/|ψ'|)^2` (toppra's ``xbound``). The acceleration bound
:math:`\|\ddot p\| \le a_{max}` is a disc in the plane of :math:`p'` and :math:`p''`;
:class:`acceleration_constraint` gives toppra the inscribed regular polygon of
:data:`POLYGON` sides (radius :math:`a_{max}\cos(π/K)`, 0.5 % inside), a linear constraint
in :math:`(u, x)`. :math:`p'` and :math:`p''` come from the FK of the joint spline by central
differences in :math:`s`; :math:`ψ' = s^\top q'` exactly for a SCARA (the yaw is
:math:`ψ_0 + s^\top q`).

:func:`tool_peaks` checks a timed result independently: it samples the trajectory at
``dt`` (1 ms), takes the tip positions by FK and differentiates them by finite differences.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import describe, is_real
from scara_opt.errors import InputError
from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

#: sides of the polygon inscribed in the tool-acceleration disc
POLYGON = 32

#: step in the path parameter (normalised to [0, 1]) of the central differences of p(s)
DS = 1e-4

#: the names of the tool limits, their units
UNITS = {"speed": "m/s", "acceleration": "m/s²", "yaw_rate": "rad/s"}


@dataclass(frozen=True)
class ToolLimits:
    """Limits on the tip: ``speed`` [m/s], ``acceleration`` [m/s²], ``yaw_rate`` [rad/s].

    ``None`` leaves a quantity unlimited (only the joint limits bound it).

    Raises:
        InputError: a zero, negative, NaN or infinite limit (the message names it).
    """

    speed: float | None = None
    acceleration: float | None = None
    yaw_rate: float | None = None

    def __post_init__(self) -> None:
        for name in UNITS:
            value = getattr(self, name)
            if value is None:
                continue
            if not is_real(value) or not (math.isfinite(float(value)) and float(value) > 0):
                raise InputError(f"tool {name} limit is {describe(value)}; it must be a finite "
                                 f"number > 0 [{UNITS[name]}], or None for no limit")
            object.__setattr__(self, name, float(value))

    def merged(self, speed: float | None, acceleration: float | None) -> ToolLimits:
        """These limits with a move's own ``speed`` / ``acceleration`` where given."""
        return ToolLimits(self.speed if speed is None else speed,
                          self.acceleration if acceleration is None else acceleration,
                          self.yaw_rate)

    @property
    def empty(self) -> bool:
        """Whether no tool limit is set."""
        return self.speed is None and self.acceleration is None and self.yaw_rate is None


#: stands for "no limit" where toppra needs a finite bound
UNLIMITED = 1e12


@dataclass(frozen=True)
class ToolProfile:
    """Tool limits per interval between the waypoints of a joint path, (n-1,) each.

    A blended run crosses moves with different limits: interval ``i`` (waypoints ``i`` to
    ``i+1``) takes the smaller of its two points' limits. ``inf`` where none (toppra's
    constraints take :data:`UNLIMITED` there).
    """

    speed: Array
    acceleration: Array
    yaw_rate: Array

    @classmethod
    def per_point(cls, tools: list[ToolLimits]) -> ToolProfile:
        """From one :class:`ToolLimits` per waypoint (n >= 2)."""
        def row(name: str) -> Array:
            v = np.array([math.inf if getattr(t, name) is None else getattr(t, name)
                          for t in tools])
            return np.minimum(v[:-1], v[1:])
        return cls(row("speed"), row("acceleration"), row("yaw_rate"))

    def at(self, name: str, x: Array, knots: Array) -> Array:
        """Limit in force at ``x`` (m,) on a path with waypoints at ``knots`` (n,).

        At a waypoint itself, the smaller of the two intervals meeting there.
        """
        v = getattr(self, name)
        i = np.clip(np.searchsorted(knots, x, side="right") - 1, 0, len(v) - 1)
        out = v[i]
        on = (i > 0) & np.isclose(x, knots[i], rtol=0.0, atol=1e-12)
        out[on] = np.minimum(out[on], v[i[on] - 1])
        return out

    def __repr__(self) -> str:
        """Each limit's distinct values and on how many intervals, ``none`` where unlimited."""
        def show(name: str) -> str:
            values, counts = np.unique(getattr(self, name), return_counts=True)
            labels = [f"{v:g} {UNITS[name]}" if np.isfinite(v) else "none" for v in values]
            if len(values) > 1:
                labels = [f"{label} on {c}" for label, c in zip(labels, counts, strict=True)]
            return ", ".join(labels)

        return (f"ToolProfile({len(self.speed)} intervals; speed {show('speed')}; acceleration "
                f"{show('acceleration')}; yaw_rate {show('yaw_rate')})")

    def limited(self, name: str) -> bool:
        """Whether some interval limits ``name``."""
        return bool(np.isfinite(getattr(self, name)).any())

    def scaled(self, factor: float) -> ToolProfile:
        """Every finite limit times ``factor``."""
        def sc(v: Array) -> Array:
            return v * factor  # inf stays inf
        return ToolProfile(sc(self.speed), sc(self.acceleration), sc(self.yaw_rate))


def yaw_signs(robot: Robot) -> Array | None:
    """(nq,) with ψ = ψ0 + signs @ q for a SCARA-type robot, else ``None``."""
    from scara_opt.motion.branch import geometry

    g = geometry(robot)
    return None if g is None else np.asarray(g.s, dtype=float)


def path_derivatives(robot: Robot, path: Any, grid: Array) -> tuple[Array, Array, Array | None]:
    """``p'(s)``, ``p''(s)`` (N, 3) and ``ψ'(s)`` (N,) (or ``None``) on ``grid`` (N,)."""
    h = DS * (path.path_interval[1] - path.path_interval[0])
    P = [robot.positions(path(grid + d)) for d in (-h, 0.0, h)]
    dp = (P[2] - P[0]) / (2 * h)
    ddp = (P[2] - 2 * P[1] + P[0]) / h**2
    signs = yaw_signs(robot)
    dyaw = None if signs is None else path(grid, 1) @ signs
    return dp, ddp, dyaw


def _linear_constraint() -> type:
    from toppra.constraint import LinearConstraint

    return LinearConstraint


def speed_constraint(robot: Robot, tool: ToolProfile, knots: Array) -> Any:
    """toppra first-order constraint: tip speed and yaw rate (``xbound``).

    ``knots`` (n,): the path parameter at the waypoints the profile's intervals join.
    """
    base = _linear_constraint()

    class _Speed(base):  # type: ignore[misc, valid-type]
        def __init__(self) -> None:
            super().__init__()
            self.dof = robot.nq

        def compute_constraint_params(self, path: Any, gridpoints: Array,
                                      *args: Any, **kwargs: Any) -> tuple:
            dp, _, dyaw = path_derivatives(robot, path, gridpoints)
            v = tool.at("speed", gridpoints, knots)
            with np.errstate(over="ignore", divide="ignore"):  # no motion: no bound (inf)
                upper = v**2 / np.einsum("ij,ij->i", dp, dp)
                if dyaw is not None:
                    w = tool.at("yaw_rate", gridpoints, knots)
                    upper = np.minimum(upper, w**2 / dyaw**2)
            upper = np.minimum(upper, UNLIMITED)
            xbound = np.column_stack([np.zeros_like(upper), upper])
            return None, None, None, None, None, None, xbound

    return _Speed()


def acceleration_constraint(robot: Robot, tool: ToolProfile, knots: Array) -> Any:
    """toppra second-order constraint: ``‖p' u + p'' x‖ <= a`` as an inscribed polygon."""
    base = _linear_constraint()
    from toppra.constraint import DiscretizationType
    from toppra.constraint.linear_constraint import canlinear_colloc_to_interpolate

    phi = 2 * np.pi * np.arange(POLYGON) / POLYGON
    F = np.column_stack([np.cos(phi), np.sin(phi)])

    class _Acc(base):  # type: ignore[misc, valid-type]
        def __init__(self) -> None:
            super().__init__()
            self.dof = robot.nq
            self.set_discretization_type(DiscretizationType.Interpolation)

        def compute_constraint_params(self, path: Any, gridpoints: Array,
                                      *args: Any, **kwargs: Any) -> tuple:
            dp, ddp, _ = path_derivatives(robot, path, gridpoints)
            speed = np.linalg.norm(dp, axis=1)
            e1 = dp / np.maximum(speed, 1e-300)[:, None]
            along = np.einsum("ij,ij->i", ddp, e1)
            across = np.linalg.norm(ddp - along[:, None] * e1, axis=1)
            a = np.column_stack([speed, np.zeros_like(speed)])
            b = np.column_stack([along, across])
            lim = np.minimum(tool.at("acceleration", gridpoints, knots), UNLIMITED) * math.cos(
                math.pi / POLYGON)
            g = np.repeat(lim[:, None], POLYGON, axis=1)
            Fs = np.repeat(F[None], len(gridpoints), axis=0)
            return canlinear_colloc_to_interpolate(a, b, np.zeros_like(a), Fs, g, None, None,
                                                   gridpoints, identical=False)

    return _Acc()


def tool_peaks(robot: Robot, Q: Array, dt: float) -> dict[str, Array]:
    """Tip speed, acceleration and yaw rate on joint samples ``Q`` (m, nq) taken every ``dt``.

    Finite differences of the FK positions: speed ``|Δp|/dt`` between samples (m-1,),
    acceleration ``|Δ²p|/dt²`` at the inner samples (m-2,), yaw rate ``|Δψ|/dt`` (m-1,)
    (empty without a yaw axis).
    """
    P = robot.positions(Q)
    out = {"speed": np.linalg.norm(np.diff(P, axis=0), axis=1) / dt,
           "acceleration": np.linalg.norm(np.diff(P, 2, axis=0), axis=1) / dt**2}
    signs = yaw_signs(robot)
    out["yaw_rate"] = (np.abs(np.diff(Q @ signs)) / dt if signs is not None
                       else np.zeros(0))
    return out
