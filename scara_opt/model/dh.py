r"""Denavit–Hartenberg tables to URDF: the bundled robots are written this way.

A robot file (``robots/<name>.toml``) holds the paper's DH table in the paper's
own units. :func:`scara_opt.model.dh_file.load_dh` reads it into a :class:`DHRobot` (SI
inside) and :func:`dh_to_urdf` writes the URDF that :class:`scara_opt.Robot` loads, through
yourdfpy's data classes (``Robot``, ``Link``, ``Joint``, ``Inertial``) and its XML writer.

Conventions, per row ``i``:

* standard DH: :math:`T_i = R_z(\theta_i) T_z(d_i) T_x(a_i) R_x(\alpha_i)`;
* modified DH (Craig): :math:`T_i = R_x(\alpha_{i-1}) T_x(a_{i-1}) R_z(\theta_i) T_z(d_i)`,
  with the row's own ``alpha`` and ``a`` standing for :math:`\alpha_{i-1}, a_{i-1}`.

A joint variable ``q`` enters its row as ``offset + sign * q``: ``theta`` is the
offset of a revolute row, ``d`` of a prismatic row, and ``sign = -1`` models a
"−d3" entry. ``python -m scara_opt.model.dh_file`` regenerates every bundled URDF.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from scara_opt.errors import JointLimitError, URDFError
from scara_opt.model.inertial import check_inertial, inertia_matrix

if TYPE_CHECKING:
    import yourdfpy

__all__ = ["ANGLE_UNITS", "CONVENTIONS", "DHJoint", "DHRobot", "JOINT_TYPES", "LENGTH_UNITS",
           "dh_to_urdf", "joint_frames"]

LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
JOINT_TYPES = ("revolute", "prismatic", "fixed")
CONVENTIONS = ("standard", "modified")
#: the keys a robot file may hold: top level (``footprint`` is read by
#: scara_opt.workspace_analysis), each ``[[joints]]`` row and the ``[tool]`` table
FILE_KEYS = ("name", "title", "source", "notes", "convention", "length_unit", "angle_unit",
             "joints", "tool", "footprint", "dynamics_source", "citation")
JOINT_KEYS = ("name", "type", "a", "alpha", "d", "theta", "sign", "lower", "upper", "velocity",
              "acceleration", "mass", "com", "inertia", "effort", "radius")
TOOL_KEYS = ("xyz", "rpy")


@dataclass(frozen=True)
class DHJoint:
    """One DH row in SI units [m, rad]; limits are those of the joint variable ``q``.

    Inertial data (optional, for torque-limited timing) describe the link the joint moves
    (URDF ``link{k}``), in the joint's moving frame: ``mass`` [kg] (0: no body), ``com`` (3,)
    [m], ``inertia`` ``(ixx, ixy, ixz, iyy, iyz, izz)`` about the centre of mass [kg·m²];
    ``effort`` is the torque [N·m] (revolute) or force [N] (prismatic) limit, 0 for none.
    """

    name: str
    type: str
    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    sign: float = 1.0
    lower: float = 0.0
    upper: float = 0.0
    velocity: float = 1.0
    acceleration: float = 1.0
    mass: float = 0.0
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[float, ...] = (0.0,) * 6
    effort: float = 0.0

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise URDFError(
                f"joint {self.name!r}: type {self.type!r} is not one of {JOINT_TYPES}"
            )
        if self.sign not in (1.0, -1.0):
            raise URDFError(f"joint {self.name!r}: sign must be +1 or -1, got {self.sign}")
        values = (self.a, self.alpha, self.d, self.theta, self.lower, self.upper,
                  self.velocity, self.acceleration)
        if not all(math.isfinite(v) for v in values):
            raise URDFError(f"joint {self.name!r}: every DH entry and limit must be finite")
        if len(self.com) != 3 or len(self.inertia) != 6:
            raise URDFError(f"joint {self.name!r}: com needs 3 numbers and inertia 6 (ixx, ixy, "
                            f"ixz, iyy, iyz, izz); got {self.com!r} and {self.inertia!r}")
        check_inertial(f"joint {self.name!r}", self.mass, np.array(self.com, float),
                       inertia_matrix(self.inertia), self.effort)
        if self.type == "fixed" and (self.mass or self.effort):
            raise URDFError(f"joint {self.name!r}: a fixed row moves no link of its own; put its "
                            "mass on the movable row before it and drop effort")
        if self.type != "fixed":
            if not self.lower < self.upper:
                raise JointLimitError(
                    f"joint {self.name!r}: lower limit {self.lower} is not below upper "
                    f"limit {self.upper}; swap them or fix the robot file",
                    joint=self.name,
                )
            if self.velocity <= 0 or self.acceleration <= 0:
                raise JointLimitError(
                    f"joint {self.name!r}: velocity and acceleration limits must be > 0, "
                    f"got {self.velocity} and {self.acceleration}",
                    joint=self.name,
                )


@dataclass(frozen=True)
class DHRobot:
    """A robot described by a DH table (SI units) plus its tool transform and provenance."""

    name: str
    joints: tuple[DHJoint, ...]
    convention: str = "standard"
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    source: str = ""
    notes: str = ""

    def __post_init__(self) -> None:
        if self.convention not in CONVENTIONS:
            raise URDFError(
                f"robot {self.name!r}: convention {self.convention!r} is not one of {CONVENTIONS}"
            )
        if not any(j.type != "fixed" for j in self.joints):
            raise URDFError(f"robot {self.name!r} has no movable joint; add a DH row that moves")


def _rz(angle: float) -> np.ndarray:
    T = np.eye(4)
    T[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    return T


def _rx(angle: float) -> np.ndarray:
    T = np.eye(4)
    T[1:3, 1:3] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    return T


def _tz(dist: float) -> np.ndarray:
    T = np.eye(4)
    T[2, 3] = dist
    return T


def _tx(dist: float) -> np.ndarray:
    T = np.eye(4)
    T[0, 3] = dist
    return T


def joint_frames(robot: DHRobot) -> tuple[list[tuple[DHJoint, np.ndarray]], np.ndarray]:
    """Split the table into joint origins and the flange placement.

    Returns:
        ``(joints, flange)``: for each movable row, ``(joint, origin)`` with ``origin``
        the 4×4 placement of the joint frame (before its motion about/along its z
        axis) in the previous joint's moving frame; ``flange`` is the 4×4 placement
        of the last DH frame in the last joint's moving frame. Fixed rows are folded
        into the next placement.
    """
    out: list[tuple[DHJoint, np.ndarray]] = []
    carry = np.eye(4)
    for j in robot.joints:
        if robot.convention == "standard":
            whole = _rz(j.theta) @ _tz(j.d) @ _tx(j.a) @ _rx(j.alpha)
        else:
            whole = _rx(j.alpha) @ _tx(j.a) @ _rz(j.theta) @ _tz(j.d)
        if j.type == "fixed":
            carry = carry @ whole
            continue
        if robot.convention == "standard":
            # the variable sits at the front: _rz(theta) for revolute, _tz(d) after Rz for prismatic
            before = _rz(j.theta) if j.type == "revolute" else _rz(j.theta) @ _tz(j.d)
            after = _tx(j.a) @ _rx(j.alpha)
            if j.type == "revolute":
                after = _tz(j.d) @ after
        else:
            # Rz and Tz commute, so the whole row can precede the motion
            before, after = whole, np.eye(4)
        out.append((j, carry @ before))
        carry = after
    return out, carry


def _snapped(T: np.ndarray) -> np.ndarray:
    """``T`` with round-off below 1e-15 (from the rotation matrices) set to 0."""
    return np.where(np.abs(T) < 1e-15, 0.0, T)


def _inertial(j: DHJoint) -> yourdfpy.Inertial | None:
    """Row ``j``'s ``<inertial>`` (``None`` for a massless row)."""
    import yourdfpy

    if j.mass == 0:
        return None
    com = np.eye(4)
    com[:3, 3] = j.com
    return yourdfpy.Inertial(origin=com, mass=float(j.mass), inertia=inertia_matrix(j.inertia))


def dh_to_urdf(robot: DHRobot) -> str:
    """Write the URDF (as a string) of a DH robot, with yourdfpy.

    Links are ``base_link``, ``link1`` … ``linkN`` (one per movable joint), ``flange``
    (the last DH frame) and ``tool`` (the flange times the tool transform). The
    acceleration limit, which URDF lacks, is kept in a ``<scara_opt acceleration=…/>``
    child of each joint [rad/s² or m/s²]; parsers that do not know it ignore it. A row's
    ``mass`` > 0 gives ``link{k}`` an ``<inertial>``; its ``effort`` is ``<limit effort=>``.
    """
    import yourdfpy  # 3 s to import (trimesh): only when a URDF is written
    from lxml import etree  # yourdfpy's XML library

    frames, flange = joint_frames(robot)
    links = [yourdfpy.Link("base_link")]
    joints = []
    parent = "base_link"
    for k, (j, origin) in enumerate(frames, start=1):
        child = f"link{k}"
        links.append(yourdfpy.Link(child, inertial=_inertial(j)))
        joints.append(yourdfpy.Joint(
            j.name, type=j.type, parent=parent, child=child, origin=_snapped(origin),
            axis=np.array([0.0, 0.0, float(j.sign)]),
            limit=yourdfpy.Limit(effort=float(j.effort), velocity=float(j.velocity),
                                 lower=float(j.lower), upper=float(j.upper))))
        parent = child
    for name, T, par in (("flange", flange, parent), ("tool", robot.tool, "flange")):
        links.append(yourdfpy.Link(name))
        joints.append(yourdfpy.Joint(f"{name}_joint", type="fixed", parent=par, child=name,
                                     origin=_snapped(T)))
    urdf = yourdfpy.URDF(yourdfpy.Robot(robot.name, links=links, joints=joints),
                         build_scene_graph=False, load_meshes=False)
    tree = urdf.write_xml()
    acceleration = {j.name: float(j.acceleration) for j, _ in frames}
    for element in tree.getroot().iterfind("joint"):  # URDF has no acceleration limit
        if element.get("name") in acceleration:
            etree.SubElement(element, "scara_opt",
                             acceleration=str(acceleration[element.get("name")]))
    tree.getroot().addprevious(etree.Comment(
        f" Generated by scara_opt.model.dh from robots/{robot.name}.toml; do not edit: edit "
        "the TOML and run python -m scara_opt.model.dh_file "))
    return etree.tostring(tree, xml_declaration=True, encoding="UTF-8",
                          pretty_print=True).decode()
