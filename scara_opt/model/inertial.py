"""Inertial data of a robot: link masses, centres of mass, inertias and joint torque limits.

A URDF's ``<inertial>`` elements reach the Pinocchio model as they are; links behind fixed
joints are merged into their parent body by Pinocchio's URDF parser, and the bodies of
joints locked off the chain (:mod:`~scara_opt.model.urdf_tree`) are merged into the body of
the joint they hang from, at the locked pose, by ``pinocchio.buildReducedModel``. A robot
file (TOML) states them per joint (:func:`check_inertial`), see ``robots/README.md``.

Torque limits are the URDF's ``<limit effort=>``: [N·m] for a revolute joint, [N] for a
prismatic one; ``effort="0"`` (URDF's "not given") means no limit (``inf``).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.errors import URDFError

Array = NDArray[np.float64]

#: eigenvalues of an inertia matrix may be this far below zero (round-off) [kg·m²]
INERTIA_SLACK = 1e-12


def inertia_matrix(six: tuple[float, ...] | Array) -> Array:
    """The symmetric 3×3 matrix of ``(ixx, ixy, ixz, iyy, iyz, izz)`` (URDF's order) [kg·m²]."""
    ixx, ixy, ixz, iyy, iyz, izz = (float(v) for v in six)
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def check_inertial(where: str, mass: float, com: Array, inertia: Array, effort: float) -> None:
    """Refuse inertial data no body can have.

    Args:
        where: what to name in the message (``"robot 'fang': joint 'theta1'"``).
        mass: link mass [kg], finite and > 0 (0 only with a zero inertia: no body).
        com: (3,) centre of mass [m], finite.
        inertia: (3, 3) inertia about the centre of mass [kg·m²]: finite, symmetric,
            positive semi-definite and obeying the triangle inequalities
            (``ixx + iyy >= izz`` and the two others, which every real body does).
        effort: torque [N·m] or force [N] limit, finite and >= 0 (0: none stated).

    Raises:
        URDFError: naming ``where``, the quantity and the value.
    """
    values = [mass, effort, *np.ravel(com), *np.ravel(inertia)]
    if not all(math.isfinite(v) for v in values):
        raise URDFError(f"{where}: mass, com, inertia and effort must be finite numbers; got "
                        f"mass {mass!r}, com {list(np.ravel(com))}, inertia "
                        f"{np.ravel(inertia).tolist()}, effort {effort!r}")
    if mass < 0 or (mass == 0 and np.any(inertia != 0)):
        raise URDFError(f"{where}: mass must be > 0 [kg], got {mass!r}; give the link's mass "
                        "or leave out mass, com and inertia")
    if effort < 0:
        raise URDFError(f"{where}: effort (torque limit) must be > 0 [N·m or N], got "
                        f"{effort!r}; give the joint's peak torque or leave effort out")
    check_inertia_matrix(where, inertia)


def check_inertia_matrix(where: str, inertia: Array) -> None:
    """Refuse a finite (3, 3) inertia [kg·m²] that no body has.

    A body's inertia about its centre of mass is positive semi-definite (zero only along
    the axis of a rod or for a point mass) and its principal moments obey the triangle
    inequalities: ``ixx + iyy >= izz``, ``iyy + izz >= ixx``, ``ixx + izz >= iyy`` (for
    the diagonal of any frame, as of the principal one).

    Raises:
        URDFError: naming ``where``, the matrix, its eigenvalues and the rules.
    """
    eig = np.linalg.eigvalsh(inertia)
    d = np.diag(inertia)
    triangle = min(d[0] + d[1] - d[2], d[1] + d[2] - d[0], d[0] + d[2] - d[1])
    if eig.min() < -INERTIA_SLACK or triangle < -INERTIA_SLACK:
        raise URDFError(
            f"{where}: inertia {np.ravel(inertia).tolist()} [kg·m²] is not a body's inertia "
            f"(eigenvalues {eig.tolist()}, each must be >= 0, and ixx + iyy >= izz, "
            "iyy + izz >= ixx, ixx + izz >= iyy); give (ixx, ixy, ixz, iyy, iyz, izz) about "
            "the centre of mass")


def _numbers(text: str | None, count: int, default: str) -> list[float] | None:
    """``count`` finite numbers parsed from an attribute (``default`` when absent), or None."""
    try:
        values = [float(v) for v in (default if text is None else text).split()]
    except ValueError:
        return None
    return values if len(values) == count and all(map(math.isfinite, values)) else None


def check_urdf_inertials(text: str, where: str) -> None:
    """Refuse ``<inertial>`` elements the URDF parser would silently drop or misread.

    urdfdom skips an ``<inertial>`` it cannot parse (a ``nan``, a missing value) with a
    message on stderr, and the link then weighs nothing: refused here instead. An inertia
    no body has (``iyy="-1"``, a triangle inequality broken) is refused as in a robot file
    (:func:`check_inertia_matrix`).

    Raises:
        URDFError: naming the link, the element and the value.
    """
    for link in ET.fromstring(text).iter("link"):
        for inertial in link.findall("inertial"):
            at = f"{where}: link {link.get('name')!r}"
            mass = inertial.find("mass")
            raw = None if mass is None else mass.get("value")
            value = _numbers(raw, 1, "")
            if value is None or value[0] < 0:
                raise URDFError(f"{at} has <mass value={raw!r}>; give a finite mass >= 0 [kg]")
            origin = inertial.find("origin")
            for key in ("xyz", "rpy"):
                raw = None if origin is None else origin.get(key)
                if _numbers(raw, 3, "0 0 0") is None:
                    raise URDFError(f"{at} has <inertial><origin {key}={raw!r}>; give 3 finite "
                                    "numbers [m or rad]")
            inertia = inertial.find("inertia")
            six = []
            for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
                raw = None if inertia is None else inertia.get(key)
                if (number := _numbers(raw, 1, "")) is None:
                    raise URDFError(f"{at} has <inertia {key}={raw!r}>; every <inertial> needs "
                                    "<inertia> with 6 finite numbers [kg·m²]")
                six += number
            check_inertia_matrix(f"{at}: <inertia>", inertia_matrix(tuple(six)))


def check_model_inertias(model: pin.Model, where: str) -> None:
    """Refuse a model whose (URDF) inertias are not finite or have a negative mass.

    Raises:
        URDFError: naming the joint whose body is wrong.
    """
    for k in range(1, model.njoints):
        Y = model.inertias[k]
        values = [Y.mass, *Y.lever, *np.ravel(Y.inertia)]
        if not all(math.isfinite(v) for v in values) or Y.mass < 0:
            raise URDFError(f"{where}: the body moved by joint {model.names[k]!r} has mass "
                            f"{Y.mass!r} kg, centre of mass {list(Y.lever)}; every "
                            "<inertial> needs a finite mass >= 0 and finite origin and inertia")


class InertialData:
    """Mixin of :class:`~scara_opt.model.robot.Robot`: masses and torque limits from ``model``."""

    model: pin.Model

    @property
    def has_inertia(self) -> bool:
        """Whether the chain's bodies carry mass (torque-limited timing needs it)."""
        return self.total_mass > 0.0

    @property
    def total_mass(self) -> float:
        """Mass of everything the joints move [kg] (locked and fixed links included)."""
        return float(sum(self.model.inertias[k].mass for k in range(1, self.model.njoints)))

    @property
    def torque_limit(self) -> Array:
        """Joint torque limits (nq,): [N·m] revolute, [N] prismatic; ``inf`` where none given."""
        effort = np.array(self.model.effortLimit, float)
        return np.where(effort > 0, effort, np.inf)
