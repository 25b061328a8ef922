"""From a checked URDF tree to the Pinocchio model of one chain, the path to its tip.

* **Trees.** Only the joints on the path from the root link to the tip are kept; every
  other movable joint (gripper fingers, a second arm, …) is locked at its *reference*
  with ``pinocchio.buildReducedModel``. The reference is zero, or the middle of the
  joint's range when zero is outside it; a locked mimic joint follows its leader's
  reference (``multiplier * reference + offset``).
* **Continuous joints** are one angle each in ``q`` (Pinocchio's cos/sin pair never
  shows): they are loaded as revolute joints with limits ``±inf``.
* **Mimic joints** follow their leader, ``q_mimic = multiplier * q_leader + offset``. Off
  the path they are locked with the rest; on the path (leader on the path too) they are
  not a coordinate of ``q``: Pinocchio's mimic joints carry the relation through FK and
  the Jacobian, and :class:`ChainJoint` records it for the casadi expression.
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.errors import FrameNotFoundError, URDFError
from scara_opt.model.urdf_checks import MOVABLE

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}

#: URDF limits written for continuous joints before Pinocchio parses them (then set to ±inf)
_UNBOUNDED = 1e300

@dataclass(frozen=True)
class ChainJoint:
    """One movable joint of the chain, as Pinocchio stores it.

    Attributes:
        name: joint name.
        kind: ``"revolute"`` or ``"prismatic"`` (continuous joints are revolute).
        axis: unit axis (3,) in the joint frame.
        placement: 4×4 placement of the joint frame in the parent joint's frame [m].
        index: the entry of ``q`` that drives the joint.
        mimic: whether the joint follows ``q[index]`` (a mimic joint, not a coordinate).
        scaling: joint value = ``scaling * q[index] + offset`` (1 and 0 unless ``mimic``).
        offset: see ``scaling`` [rad or m].
    """

    name: str
    kind: str
    axis: Array
    placement: Array
    index: int
    mimic: bool = False
    scaling: float = 1.0
    offset: float = 0.0

def _joint_kind(jmodel: pin.JointModel) -> tuple[str, Array]:
    short = jmodel.shortname()
    concrete = jmodel.extract()
    for prefix, kind in (("JointModelR", "revolute"), ("JointModelP", "prismatic")):
        if short in (prefix + "X", prefix + "Y", prefix + "Z"):
            return kind, np.array(_AXES[short[-1]])
    if short == "JointModelRevoluteUnaligned":
        return "revolute", np.asarray(concrete.axis, float).copy()
    if short == "JointModelPrismaticUnaligned":
        return "prismatic", np.asarray(concrete.axis, float).copy()
    raise URDFError(f"Pinocchio joint kind {short} is not supported (revolute or prismatic only)")

def path_to(by_child: dict[str, Any], root: str, link: str) -> list[Any]:
    """The URDF joints from ``root`` down to ``link``, in order."""
    out = []
    while link != root:
        out.append(by_child[link])
        link = out[-1].parent
    return out[::-1]

def _dof(path: list[Any]) -> int:
    """Joint coordinates along a path: its movable joints that are not mimic joints."""
    return sum(j.type in MOVABLE and j.mimic is None for j in path)

def pick_tip(urdf: Any, by_child: dict[str, Any], root: str, tip: str | None,
              where: str) -> str:
    """``tip`` checked, or, for ``None``, the end link of the longest chain (logged)."""
    links = [lk.name for lk in urdf.robot.links]
    if tip is not None:
        if tip not in links:
            raise FrameNotFoundError(tip, links)
        return tip
    parents = {j.parent for j in urdf.robot.joints}
    ends = [name for name in links if name not in parents]
    paths = {name: path_to(by_child, root, name) for name in ends}
    best = max(ends, key=lambda name: (_dof(paths[name]), len(paths[name])))
    if len(ends) > 1:
        log.warning("%s: tip=None picks %r, the end of the longest chain (%d joint coordinates) "
                    "among the end links %s; pass tip= to choose another", where, best,
                    _dof(paths[best]), ends)
    return best

def _reference(j: Any, joints: dict[str, Any]) -> float:
    """Where a locked joint is held [rad or m]: zero, or mid-range when zero is outside.

    A mimic joint follows its leader's reference: ``multiplier * reference + offset``.
    """
    if j.mimic is not None:
        m = j.mimic
        scale = 1.0 if m.multiplier is None else m.multiplier
        return scale * _reference(joints[m.joint], joints) + (m.offset or 0.0)
    if j.type == "continuous" or j.limit.lower <= 0.0 <= j.limit.upper:
        return 0.0
    return 0.5 * (j.limit.lower + j.limit.upper)

def _split(urdf: Any, path: list[Any], where: str) -> tuple[list[Any], dict[str, float]]:
    """The movable joints kept (on the path, leader kept too) and the locked ones' references.

    Pinocchio needs a kept mimic joint's leader before it on the path.
    """
    order = {j.name: k for k, j in enumerate(path)}
    joints = {j.name: j for j in urdf.robot.joints}
    kept = [j for j in path if j.type in MOVABLE
            and (j.mimic is None or j.mimic.joint in order)]
    for j in kept:
        if j.mimic is not None and order[j.mimic.joint] > order[j.name]:
            raise URDFError(
                f"{where}: mimic joint {j.name!r} follows {j.mimic.joint!r}, which comes after "
                f"it on the path from the root to {path[-1].child!r}; Pinocchio needs the "
                f"leader joint before its mimic joint: swap their roles (put the <mimic> on "
                f"{j.mimic.joint!r}, multiplier 1/m, offset -offset/m) or pick another tip=")
    kept_names = {j.name for j in kept}
    locked = {j.name: _reference(j, joints) for j in urdf.robot.joints
              if j.type in MOVABLE and j.name not in kept_names}
    return kept, locked

def _pinocchio_text(text: str, drop_mimic: set[str]) -> str:
    """The URDF as Pinocchio gets it: continuous joints as revolute, some ``<mimic>`` dropped.

    A continuous joint becomes a revolute joint with limits ``±_UNBOUNDED`` (its effort
    and velocity limits kept), so ``q`` holds its angle, not Pinocchio's (cos, sin) pair.
    Locked mimic joints lose their ``<mimic>`` (they are held at their reference anyway),
    which frees Pinocchio from its rule that a leader precede its mimic joints.
    """
    root = ET.fromstring(text)
    joints = [j for j in root.iter("joint") if j.get("type") == "continuous"
              or (j.get("name") in drop_mimic and j.find("mimic") is not None)]
    if not joints:
        return text
    for joint in joints:
        if joint.get("type") == "continuous":
            joint.set("type", "revolute")
            limit = joint.find("limit")
            if limit is None:
                limit = ET.SubElement(joint, "limit", effort="0", velocity="0")
            limit.set("lower", repr(-_UNBOUNDED))
            limit.set("upper", repr(_UNBOUNDED))
        mimic = joint.find("mimic")
        if mimic is not None and joint.get("name") in drop_mimic:
            joint.remove(mimic)
    return ET.tostring(root, encoding="unicode")

@contextmanager
def urdfdom_messages(said: list[str]) -> Iterator[None]:
    """Keep urdfdom's messages (C++ ``Error:`` lines on the process's stderr) out of stderr.

    The block's output to file descriptor 2 goes to a temporary file; its messages, each
    once and without urdfdom's source locations, are appended to ``said`` (for the error
    that follows, or the log). Pinocchio's parse holds the GIL, so no Python thread writes
    meanwhile. Where descriptor 2 cannot be redirected the block runs as it is.
    """
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError, AttributeError):  # no fd 2, or no sys.stderr
        yield
        return
    try:
        with tempfile.TemporaryFile() as tmp:
            os.dup2(tmp.fileno(), 2)
            try:
                yield
            finally:
                os.dup2(saved, 2)
                tmp.seek(0)
                for line in tmp.read().decode(errors="replace").splitlines():
                    line = line.strip().removeprefix("Error:").strip()
                    if line and not line.startswith("at line ") and line not in said:
                        said.append(line)
    finally:
        os.close(saved)


def build_model(text: str, urdf: Any, path: list[Any],
                 where: str) -> tuple[pin.Model, dict[str, float]]:
    """The Pinocchio model of the path's joints, the others locked; and the locked values."""
    kept, locked = _split(urdf, path, where)
    on_path_mimic = any(j.mimic is not None for j in kept)
    xml = _pinocchio_text(text, drop_mimic=set(locked))
    said: list[str] = []
    try:  # the mimic flag only when needed: Pinocchio < 3.4 lacks it
        with urdfdom_messages(said):
            full = pin.buildModelFromXML(xml, True) if on_path_mimic else \
                pin.buildModelFromXML(xml)
    except TypeError:
        raise URDFError(f"{where}: mimic joints on the path to {path[-1].child!r} need "
                        f"Pinocchio >= 3.4 (installed: {pin.__version__}); pip install -U pin"
                        ) from None
    except (RuntimeError, ValueError) as exc:
        why = f" (urdfdom: {'; '.join(said)})" if said else ""
        raise URDFError(f"Pinocchio could not build {where}: {exc}{why}") from None
    if said:
        log.info("%s: urdfdom said: %s", where, "; ".join(said))
    if not locked:
        return full, locked
    q_ref = pin.neutral(full)
    for name, value in locked.items():
        q_ref[full.joints[full.getJointId(name)].idx_q] = value
    ids = [full.getJointId(name) for name in locked]
    return pin.buildReducedModel(full, ids, q_ref), locked

def unbound_continuous(model: pin.Model, urdf: Any) -> None:
    """Set the position limits of the (former) continuous joints to ``±inf``."""
    lower, upper = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    for j in urdf.robot.joints:
        if j.type == "continuous" and model.existJointName(j.name):
            jm = model.joints[model.getJointId(j.name)]
            if jm.nq == 1:
                lower[jm.idx_q], upper[jm.idx_q] = -np.inf, np.inf
    model.lowerPositionLimit, model.upperPositionLimit = lower, upper

def chain_joint(model: pin.Model, k: int, urdf_joints: dict[str, Any]) -> ChainJoint:
    """The :class:`ChainJoint` of joint ``k`` of the model (a mimic one read via the URDF)."""
    jm, name = model.joints[k], model.names[k]
    placement = model.jointPlacements[k].homogeneous.copy()
    if jm.shortname() != "JointModelMimic":
        return ChainJoint(name, *_joint_kind(jm), placement, index=jm.idx_q)
    uj = urdf_joints[name]
    axis = np.asarray(uj.axis if uj.axis is not None else _AXES["X"], float)
    kind = "prismatic" if uj.type == "prismatic" else "revolute"
    mimic = jm.extract()
    return ChainJoint(name, kind, axis / np.linalg.norm(axis), placement, index=jm.idx_q,
                      mimic=True, scaling=float(mimic.scaling), offset=float(mimic.offset))
