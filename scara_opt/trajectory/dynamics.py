r"""Joint torques of a timed trajectory: Pinocchio's inverse dynamics (RNEA), with a payload.

:class:`RobotDynamics` holds a copy of the robot's Pinocchio model with the payload appended
as a rigid body at its frame (by default the robot's tip), and the joint torque limits.
:math:`τ = \mathrm{RNEA}(q, \dot q, \ddot q) = M(q)\ddot q + C(q, \dot q)\dot q + g(q)` [N·m
for revolute joints, N for prismatic ones], gravity :math:`9.81\,\mathrm{m/s^2}` along
:math:`-z` of the robot's base frame (Pinocchio's default), so it loads the joints whose axis
sees it (a vertical stroke, an arm swinging in a vertical plane) and not a SCARA's vertical
revolute axes. No friction, no motor inertia: the limits stated are joint-side torques.

Checked, not assumed: :meth:`RobotDynamics.ratios` samples a trajectory at
:data:`CHECK_RATE` (1 kHz, and its end) and returns the largest :math:`|τ_k| / τ_{max,k}`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeAlias

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import DynamicsError, FrameNotFoundError, InputError
from scara_opt.model.inertial import INERTIA_SLACK

if TYPE_CHECKING:
    from scara_opt.model.robot import Robot
    from scara_opt.trajectory.trajectory import Trajectory

Array = NDArray[np.float64]

#: sampling rate of the torque check [Hz]
CHECK_RATE = 1000.0

#: relative extra time stretch beyond the sampled excess (the samples move with the stretch)
STRETCH_SLACK = 1e-6


@dataclass(frozen=True)
class Payload:
    """A rigid load carried at a frame of the robot.

    Attributes:
        mass: [kg], >= 0.
        com: (3,) centre of mass in the frame [m].
        inertia: (3, 3) inertia about the centre of mass [kg·m²] (zero: a point mass).
        frame: the frame (link) it is fixed to.
    """

    mass: float
    com: Array
    inertia: Array
    frame: str


#: a payload as given (:func:`as_payload`): a Payload, a mass [kg], or (mass, com[, inertia])
PayloadLike: TypeAlias = "Payload | float | Sequence[ArrayLike]"


#: the heaviest payload [kg], farthest centre of mass [m] and largest inertia entry [kg·m²]
#: taken: far beyond any robot's, and small enough that the torques stay finite numbers
#: (a payload of 1e308 kg gave NaN torques)
MAX_PAYLOAD, MAX_COM, MAX_INERTIA = 1e6, 1e3, 1e9


def _bad(what: str, value: object) -> InputError:
    return InputError(f"payload {what}; got {describe(value)}: pass payload=mass [kg], "
                      "(mass, com (3,) [m]) or (mass, com, inertia (3, 3) [kg·m²]), the centre "
                      "of mass in the payload frame (default: the tip)")


def as_payload(value: object, robot: Robot, frame: str | None = None) -> Payload | None:
    """``payload=`` of :func:`~scara_opt.trajectory.time_parameterize`, checked.

    Args:
        value: ``None``; a mass [kg] (a point mass at the frame's origin); ``(mass, com)``
            with com (3,) [m] in the frame; ``(mass, com, inertia)`` with inertia (3, 3)
            about the centre of mass [kg·m²]; or a :class:`Payload`.
        robot: the robot carrying it.
        frame: the frame it is fixed to; default ``robot.tip``.

    Raises:
        InputError: a negative, NaN or infinite mass or one above :data:`MAX_PAYLOAD`, a
            misshaped, non-finite or huge com or inertia, an inertia no body has (not
            symmetric positive semi-definite).
        FrameNotFoundError: ``frame`` is not a frame of the robot's model.
    """
    if value is None:
        return None
    if isinstance(value, Payload):
        frame = value.frame
        value = (value.mass, value.com, value.inertia)
    frame = robot.tip if frame is None else frame
    if not isinstance(frame, str) or not robot.model.existFrame(frame):
        raise FrameNotFoundError(str(frame), [f.name for f in robot.model.frames])
    parts = tuple(value) if isinstance(value, (tuple, list)) else (value,)
    if not 1 <= len(parts) <= 3:
        raise _bad("must have 1 to 3 entries", value)
    try:
        mass = float(float_array(parts[0], "payload mass"))
        com = float_array(parts[1] if len(parts) > 1 else np.zeros(3), "payload com")
        inertia = float_array(parts[2] if len(parts) > 2 else np.zeros((3, 3)), "payload inertia")
    except (InputError, TypeError):
        raise _bad("entries must be numbers", value) from None
    if not (math.isfinite(mass) and 0 <= mass <= MAX_PAYLOAD):
        raise _bad(f"mass must be a number in [0, {MAX_PAYLOAD:g}] kg, not {mass!r}", value)
    if com.shape != (3,) or inertia.shape != (3, 3):
        raise _bad(f"com must have shape (3,) and inertia (3, 3), not {com.shape} and "
                   f"{inertia.shape}", value)
    if not (np.abs(com).max() <= MAX_COM and np.abs(inertia).max() <= MAX_INERTIA):
        raise _bad(f"com must be finite, within ±{MAX_COM:g} m, and inertia within "
                   f"±{MAX_INERTIA:g} kg·m²", value)
    if (not np.allclose(inertia, inertia.T, atol=INERTIA_SLACK)
            or np.linalg.eigvalsh(inertia).min() < -INERTIA_SLACK):
        raise _bad("inertia must be symmetric positive semi-definite", value)
    return Payload(mass, com, inertia, frame)


def resolve_torque_limits(robot: Robot, torque_limits: object) -> Array:
    """The torque limits (nq,) [N·m or N]: the robot's for ``None``/``True``, else checked.

    Raises:
        InputError: not a positive finite scalar or (nq,) array (the joint is named).
        DynamicsError: the robot's own limits are missing for some joint.
    """
    names = robot.joint_names
    if torque_limits is None or torque_limits is True:
        tau = robot.torque_limit
        missing = [names[k] for k in np.flatnonzero(~np.isfinite(tau))]
        if missing:
            raise DynamicsError(f"robot {robot.name!r} states no torque limit (URDF <limit "
                                f"effort=>) for joints {missing}; pass torque_limits= (scalar "
                                "or one per joint) [N·m or N]")
        return tau
    try:
        tau = float_array(torque_limits, "torque_limits")
    except InputError:
        raise InputError(f"torque_limits must be True (the robot's own), a number or one number "
                         f"per joint {names} [N·m or N]; got {describe(torque_limits)}") from None
    tau = np.full(robot.nq, float(tau)) if tau.ndim == 0 else tau
    if tau.shape != (robot.nq,):
        raise InputError(f"torque_limits must be a scalar or have shape ({robot.nq},), one per "
                         f"joint {names}; got shape {tau.shape}")
    for k, v in enumerate(tau):
        if not (v > 0 and math.isfinite(v)):
            raise InputError(f"torque_limits for joint {names[k]!r} is {v:g}; each must be "
                             "finite and > 0 [N·m for revolute, N for prismatic joints]")
    return tau


class RobotDynamics:
    """Inverse dynamics of a robot with an optional payload, and its joint torque limits.

    Args:
        robot: a robot with inertial data (``robot.has_inertia``).
        torque_limits: ``None``/``True`` for ``robot.torque_limit``, or a scalar or (nq,)
            [N·m or N].
        payload: see :func:`as_payload`.
        payload_frame: the frame carrying the payload; default the tip.

    Raises:
        DynamicsError: the robot has no inertial data or no torque limits of its own, or
            its model has mimic joints (nv != nq).
        InputError, FrameNotFoundError: see :func:`as_payload`, :func:`resolve_torque_limits`.
    """

    def __init__(self, robot: Robot, torque_limits: object = None, payload: object = None,
                 payload_frame: str | None = None) -> None:
        if not robot.has_inertia:
            raise DynamicsError(
                f"robot {robot.name!r} has no inertial data (no link mass), so torques cannot "
                "be computed: give its links <inertial> elements in the URDF, or mass, com "
                "and inertia rows in its robot file (robots/README.md); or time it without "
                "torque_limits= and payload=")
        if robot.model.nv != robot.nq:
            raise DynamicsError(f"robot {robot.name!r} has mimic joints on its chain; torque "
                                "limits are not supported for them")
        self.joint_names = tuple(robot.joint_names)
        self.tau_max = resolve_torque_limits(robot, torque_limits)
        self.payload = as_payload(payload, robot, payload_frame)
        self.model = pin.Model(robot.model)
        if self.payload is not None and self.payload.mass > 0:
            p = self.payload
            frame = self.model.frames[self.model.getFrameId(p.frame)]
            self.model.appendBodyToJoint(frame.parentJoint, pin.Inertia(p.mass, p.com, p.inertia),
                                         frame.placement)
        self.data = self.model.createData()

    def rnea(self, q: Array, v: Array, a: Array) -> Array:
        """Joint torques (nq,) [N·m or N] at ``q``, ``v``, ``a`` (nq,) each, gravity included."""
        return pin.rnea(self.model, self.data, q, v, a).copy()

    def torques(self, Q: Array, V: Array, A: Array) -> Array:
        """Joint torques (m, nq) for samples (m, nq) of q, qd, qdd."""
        return np.array([pin.rnea(self.model, self.data, q, v, a)
                         for q, v, a in zip(Q, V, A, strict=True)]).reshape(len(Q), -1)

    def samples(self, traj: Trajectory, rate: float = CHECK_RATE) -> tuple[Array, Array]:
        """Torque without and with gravity (m, nq) each, at ``rate`` [Hz] and the end.

        ``τ - g(q)`` scales with ``1 / f²`` when time is stretched by ``f``; ``g`` does not.
        """
        t = traj.times(1.0 / rate)
        Q, V, A = traj.sample(t)
        zero = np.zeros(Q.shape[1])
        g = np.array([pin.rnea(self.model, self.data, q, zero, zero) for q in Q]).reshape(Q.shape)
        return self.torques(Q, V, A) - g, g

    def ratios(self, traj: Trajectory, rate: float = CHECK_RATE) -> Array:
        """Largest ``|τ_k| / τ_max,k`` per joint (nq,), sampled at ``rate`` [Hz] and the end."""
        t = traj.times(1.0 / rate)
        tau = self.torques(*traj.sample(t))
        return np.abs(tau).max(axis=0) / self.tau_max

    def check_static(self, Q: Array) -> None:
        """Refuse a path (m, nq) on which gravity alone exceeds a torque limit.

        Raises:
            DynamicsError: naming the joint, the torque needed and the limit.
        """
        zero = np.zeros(Q.shape[1])
        self._check_static(np.array([pin.rnea(self.model, self.data, q, zero, zero)
                                     for q in Q]).reshape(Q.shape))

    def _check_static(self, g: Array) -> None:
        with np.errstate(over="ignore", invalid="ignore"):
            static = np.where(np.isfinite(g), np.abs(g) / self.tau_max, np.inf)
        if static.max() > 1.0:
            k = int(np.unravel_index(np.argmax(static), static.shape)[1])
            need = np.abs(g[:, k]).max()
            text = f"{need:.4g}" if np.isfinite(need) else "an overflowing torque"
            raise DynamicsError(
                f"gravity alone needs {text} at joint "
                f"{self.joint_names[k]!r}, above its torque limit {self.tau_max[k]:.4g} "
                "[N·m or N]: no timing holds the load; lighten the payload or raise "
                "torque_limits=")

    def stretch_factor(self, traj: Trajectory, rate: float = CHECK_RATE) -> float:
        """Smallest time stretch ``f >= 1`` that brings every sampled torque ratio to <= 1.

        With ``x = 1/f²`` each sample needs ``|g + x d| <= τ_max`` (``d = τ - g``).

        Raises:
            DynamicsError: gravity alone exceeds a joint's limit (no timing can hold it).
        """
        d, g = self.samples(traj, rate)
        self._check_static(g)
        lim = self.tau_max
        room = np.where(d > 0, lim - g, lim + g)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            x = np.where(np.abs(d) > 0, room / np.abs(d), np.inf)
        x_min = float(x.min())
        # slack: the stretched trajectory is sampled at other points of the path
        return 1.0 if x_min >= 1.0 else (1.0 + STRETCH_SLACK) / math.sqrt(x_min)

    def toppra_constraint(self, scale: float = 1.0) -> object:
        """toppra's ``JointTorqueConstraint`` for limits ``scale × τ_max`` (interpolation)."""
        import toppra.constraint as constraint

        lim = self.tau_max * scale
        return constraint.JointTorqueConstraint(
            self.rnea, np.column_stack([-lim, lim]), np.zeros(len(lim)),
            discretization_scheme=constraint.DiscretizationType.Interpolation)
