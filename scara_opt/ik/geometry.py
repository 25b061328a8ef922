"""The geometry of a SCARA-type chain, read from its FK; and the vectorised closed form.

A chain is SCARA-type when every revolute axis is parallel to one axis ``n`` (the robot's
:attr:`~scara_opt.Robot.yaw_axis`) and exactly two revolute joints move the tip in the plane
normal to ``n`` (shoulder and elbow); later revolute joints sit on the tip's axis (wrists),
prismatic joints slide along ``n`` (heights) or, before the shoulder, in the plane (a rail).
The geometry (link lengths, zero angles, axis signs, heights) is read from the robot's FK,
not assumed, and checked against it on random configurations.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe
from scara_opt.errors import InputError, ScaraOptError
from scara_opt.ik.task import LIMIT_SLACK, default_q0
from scara_opt.model.robot import Array, Robot

#: geometric zero (axes parallel, link lengths) [m, rad]
_EPS = 1e-9
#: a cosine of the elbow angle may exceed 1 by this much through round-off
COS_SLACK = 1e-12
#: a height may differ by this much through round-off when no joint moves the tip along n [m]
HEIGHT_SLACK = 1e-12


class NotScaraError(ScaraOptError, ValueError):
    """The closed form does not apply to this robot (not a SCARA-type chain)."""


@dataclass(frozen=True)
class ScaraGeometry:
    """The planar 2R + heights + wrist structure of a SCARA-type chain, read from its FK.

    Attributes:
        n: (3,) the common revolute axis; ``e1``, ``e2`` span the plane normal to it.
        shoulder, elbow: indices of the two positioning revolute joints.
        wrist: index of the solved wrist joint (last revolute on the tip axis), or -1.
        height: index of the solved height joint (last prismatic along n), or -1.
        redundant: indices of the redundant joints (rails, other heights, other wrists).
        s: (nq,) sign of each revolute axis along n (0 for prismatic joints).
        sigma: (nq,) for prismatic joints along n, their sign along n (else 0).
        rail: (nq, 2) in-plane direction of each rail joint (else 0).
        base: (2,) shoulder axis in plane coordinates at q = 0.
        l1, l2: link lengths [m]; phi1, phi2: link angles at q = 0 [rad].
        h0: tip height along n at q = 0 [m]; yaw0: tool angle at q = 0 [rad].
        fk_error: the largest disagreement of :meth:`fk` with the robot's FK on the
            random configurations it was checked on [m, rad] (round-off: ~1e-16).
    """

    n: Array
    e1: Array
    e2: Array
    shoulder: int
    elbow: int
    wrist: int
    height: int
    redundant: tuple[int, ...]
    s: Array
    sigma: Array
    rail: Array
    base: Array
    l1: float
    l2: float
    phi1: float
    phi2: float
    h0: float
    yaw0: float
    fk_error: float = 0.0

    @property
    def heights(self) -> list[int]:
        """Indices of the prismatic joints along ``n``, in chain order."""
        return [int(k) for k in np.flatnonzero(self.sigma)]

    @property
    def wrists(self) -> list[int]:
        """Indices of the revolute joints after the elbow (on the tip axis), in chain order."""
        return [int(k) for k in np.flatnonzero(self.s) if k not in (self.shoulder, self.elbow)]

    @property
    def rails(self) -> list[int]:
        """Indices of the in-plane prismatic joints before the shoulder."""
        return [int(k) for k in np.flatnonzero(np.abs(self.rail).sum(axis=1))]

    def plane(self, v: Array) -> Array:
        """Plane coordinates (..., 2) of world vectors (..., 3)."""
        return np.stack([v @ self.e1, v @ self.e2], axis=-1)

    def fk(self, Q: Array) -> tuple[Array, Array]:
        """Tip positions (n, 3) [m] and tool angles (n,) [rad] from the planar model."""
        a1 = self.phi1 + self.s[self.shoulder] * Q[:, self.shoulder]
        a2 = self.phi2 - self.phi1 + a1 + self.s[self.elbow] * Q[:, self.elbow]
        xy = (self.base + Q @ self.rail
              + self.l1 * np.stack([np.cos(a1), np.sin(a1)], -1)
              + self.l2 * np.stack([np.cos(a2), np.sin(a2)], -1))
        h = self.h0 + Q @ self.sigma
        pos = np.outer(xy[:, 0], self.e1) + np.outer(xy[:, 1], self.e2) + np.outer(h, self.n)
        return pos, self.yaw0 + Q @ self.s


def scara_geometry(robot: Robot) -> ScaraGeometry:
    """The :class:`ScaraGeometry` of ``robot``, computed once and cached on it.

    Raises:
        NotScaraError: the chain is not SCARA-type (the message says why).
    """
    cache = robot.__dict__
    if "_scara_geometry" not in cache:
        try:
            cache["_scara_geometry"] = _extract(robot)
        except NotScaraError as exc:
            cache["_scara_geometry"] = exc
    geom = cache["_scara_geometry"]
    if isinstance(geom, NotScaraError):
        raise geom
    return geom


def applies(robot: Robot) -> bool:
    """Whether ``robot`` is SCARA-type (the closed form applies to it)."""
    try:
        scara_geometry(robot)
    except NotScaraError:
        return False
    return True


def _extract(robot: Robot) -> ScaraGeometry:
    def refuse(why: str) -> NotScaraError:
        return NotScaraError(f"closed-form IK needs a SCARA-type chain; robot {robot.name!r} "
                             f"{why}; use method='ipopt' instead")

    n = robot.yaw_axis
    if n is None:
        raise refuse("has revolute axes that are not all parallel")
    if any(j.mimic for j in robot.chain):
        raise refuse("has mimic joints on its path")
    e1, e2 = robot.yaw_basis()
    nq = robot.nq
    q_zero = np.zeros(nq)
    data = robot.model.createData()  # private workspace: safe beside other threads' FK
    pin.forwardKinematics(robot.model, data, q_zero)
    origins = [data.oMi[k + 1].translation.copy() for k in range(nq)]
    axes = [data.oMi[k + 1].rotation @ j.axis for k, j in enumerate(robot.chain)]
    tip = robot.fk(q_zero)[:3, 3]
    s, sigma, rail = np.zeros(nq), np.zeros(nq), np.zeros((nq, 2))
    revolute = [k for k, j in enumerate(robot.chain) if j.kind == "revolute"]
    verticals = []
    for k, j in enumerate(robot.chain):
        a = axes[k]
        if j.kind == "revolute":
            s[k] = float(np.sign(a @ n))
        elif np.linalg.norm(np.cross(a, n)) < _EPS:
            sigma[k] = float(np.sign(a @ n))
            verticals.append(k)
        elif abs(a @ n) < _EPS and (not revolute or k < revolute[0]):
            rail[k] = [a @ e1, a @ e2]
        else:
            raise refuse(f"has prismatic joint {j.name!r} neither along the axis nor a rail "
                         "before the shoulder")

    def plane(v: Array) -> Array:
        return np.array([v @ e1, v @ e2])

    # in-plane link vectors: each revolute axis to the next one, the last one to the tip
    stops = [plane(origins[k]) for k in revolute] + [plane(tip)]
    links = [b - a for a, b in zip(stops[:-1], stops[1:], strict=True)]
    arms = [k for k, v in zip(revolute, links, strict=True) if np.linalg.norm(v) > _EPS]
    if len(arms) != 2 or arms != revolute[:2]:
        raise refuse(f"moves the tip in the plane with {len(arms)} revolute joints (need the "
                     "first two, the rest on the tip axis)")
    sh, el = arms
    v1, v2 = links[0], stops[-1] - stops[1]
    l1, l2 = float(np.linalg.norm(v1)), float(np.linalg.norm(v2))
    wrists = revolute[2:]
    geom = ScaraGeometry(
        n=n, e1=e1, e2=e2, shoulder=sh, elbow=el, wrist=wrists[-1] if wrists else -1,
        height=verticals[-1] if verticals else -1,
        redundant=tuple(sorted([k for k in range(nq) if rail[k].any()] + verticals[:-1]
                               + wrists[:-1])),
        s=s, sigma=sigma, rail=rail, base=stops[0], l1=l1, l2=l2,
        phi1=math.atan2(v1[1], v1[0]), phi2=math.atan2(v2[1], v2[0]),
        h0=float(tip @ n), yaw0=robot.yaw(q_zero),
    )
    # the model must reproduce the robot's FK everywhere, not only at q = 0
    Q = np.random.default_rng(0).uniform(-3, 3, (64, nq))
    pos, yaw = geom.fk(Q)
    T = robot.fk_batch(Q)
    yaw_fk = np.arctan2(T[:, :3, 0] @ e2, T[:, :3, 0] @ e1)
    error = max(float(np.abs(pos - T[:, :3, 3]).max()),
                float(np.abs(np.angle(np.exp(1j * (yaw - yaw_fk)))).max()))
    if error > 1e-9:
        raise refuse("does not follow the planar SCARA model (check with method='ipopt')")
    return dataclasses.replace(geom, fk_error=error)


def check_fixed(fixed: object) -> Mapping[str, Any]:
    """``fixed`` as a mapping (``{}`` for None).

    Raises:
        InputError: anything but None or a mapping of joint names to values.
    """
    if fixed is None:
        return {}
    if not isinstance(fixed, Mapping) or not all(isinstance(k, str) for k in fixed):
        raise InputError(f"fixed must be a dict of joint names to values [rad or m], e.g. "
                         f"{{'P1': 0.02}}; got {describe(fixed)}")
    return fixed


def held_values(robot: Robot, geom: ScaraGeometry, q_ref: Array,
                fixed: dict[str, float] | None) -> Array:
    """``q_ref`` with the ``fixed`` overrides applied to redundant joints (validated).

    Raises:
        InputError: an unknown joint, a joint the closed form solves, or a value outside
            the joint's limits.
    """
    q = q_ref.copy()
    for name, value in check_fixed(fixed).items():
        if name not in robot.joint_names:
            raise InputError(f"fixed: no joint named {name!r}; joints: {robot.joint_names}")
        k = robot.joint_names.index(name)
        if k not in geom.redundant:
            redundant = [robot.joint_names[i] for i in geom.redundant]
            raise InputError(f"fixed: joint {name!r} is solved by the closed form; only the "
                             f"redundant joints {redundant} can be held")
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InputError(f"fixed: {name} = {value!r} is not a number [rad or m]") from None
        if not (math.isfinite(v) and robot.lower[k] <= v <= robot.upper[k]):
            raise InputError(f"fixed: {name} = {value!r} is not within "
                             f"[{robot.lower[k]:.4g}, {robot.upper[k]:.4g}]")
        q[k] = v
    return q


def solve_batch(robot: Robot, positions: ArrayLike, yaws: ArrayLike | None = None,
                fixed: dict[str, float] | None = None) -> tuple[Array, NDArray[np.bool_]]:
    """Closed-form IK of many targets at once, vectorised with numpy.

    Redundant joints are held (at ``fixed``, else the default start), not searched: for
    redundant robots use :func:`solve_all` per target.

    Args:
        robot: a SCARA-type robot.
        positions: (n, 3) target positions [m].
        yaws: (n,) tool angles [rad], or ``None`` (the wrist then stays at its default).
        fixed: values of redundant joints by name (default: zero, or mid-range).

    Returns:
        ``(Q, valid)``: ``Q`` (n, 2, nq) the two elbow branches (γ ≥ 0 first), each angle
        taken as the turn nearest to the middle of its range; ``valid`` (n, 2) whether that
        branch lies within the joint limits. Invalid rows hold NaN-free placeholders that
        must not be used; check ``valid``.

    Raises:
        InputError: wrong shapes or non-finite values.
        NotScaraError: the robot is not SCARA-type.
    """
    geom = scara_geometry(robot)
    P = np.asarray(positions, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3 or not np.isfinite(P).all():
        raise InputError(f"positions must be a finite (n, 3) array [m]; got shape {P.shape}")
    n = P.shape[0]
    if yaws is not None:
        Y = np.asarray(yaws, dtype=float)
        if Y.shape != (n,) or not np.isfinite(Y).all():
            raise InputError(f"yaws must be a finite ({n},) array [rad]; got shape {Y.shape}")
        if geom.wrist < 0:
            raise InputError(f"robot {robot.name!r} has no wrist joint to set a yaw")
    lo, hi = robot.lower, robot.upper
    held = held_values(robot, geom, default_q0(robot), fixed)
    h_rest = geom.h0 + sum(geom.sigma[k] * held[k] for k in geom.redundant)
    Q = np.tile(held, (n, 2, 1))
    ok = np.ones(n, dtype=bool)
    if geom.height >= 0:
        d = (P @ geom.n - h_rest) / geom.sigma[geom.height]
        ok &= (d >= lo[geom.height] - LIMIT_SLACK) & (d <= hi[geom.height] + LIMIT_SLACK)
        Q[:, :, geom.height] = np.clip(d, lo[geom.height], hi[geom.height])[:, None]
    else:
        ok &= np.abs(P @ geom.n - h_rest) <= HEIGHT_SLACK
    uv = geom.plane(P) - geom.base - held @ geom.rail
    c = (np.einsum("ij,ij->i", uv, uv) - geom.l1**2 - geom.l2**2) / (2 * geom.l1 * geom.l2)
    ok &= np.abs(c) <= 1 + COS_SLACK
    g = np.arccos(np.clip(c, -1.0, 1.0))
    gamma = np.stack([g, -g], axis=1)  # (n, 2)
    a1 = np.arctan2(uv[:, 1], uv[:, 0])[:, None] - np.arctan2(
        geom.l2 * np.sin(gamma), geom.l1 + geom.l2 * np.cos(gamma))
    Q[:, :, geom.shoulder] = geom.s[geom.shoulder] * (a1 - geom.phi1)
    Q[:, :, geom.elbow] = geom.s[geom.elbow] * (gamma - (geom.phi2 - geom.phi1))
    if yaws is not None:
        w = geom.wrist
        rest = geom.yaw0 + Q @ geom.s - geom.s[w] * Q[:, :, w]
        Q[:, :, w] = geom.s[w] * (Y[:, None] - rest)
    # each revolute angle: the 2π turn nearest the middle of its range
    for k in (geom.shoulder, geom.elbow, geom.wrist if yaws is not None else -1):
        if k >= 0:
            mid = 0.5 * (robot.sampling_lower[k] + robot.sampling_upper[k])
            Q[:, :, k] = Q[:, :, k] - 2 * np.pi * np.round((Q[:, :, k] - mid) / (2 * np.pi))
    valid = ok[:, None] & np.all((Q >= lo - LIMIT_SLACK) & (Q <= hi + LIMIT_SLACK), axis=2)
    return np.clip(Q, lo, hi), valid
