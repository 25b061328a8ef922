"""The :class:`Robot`: the serial chain from a URDF's root to a tip, loaded into Pinocchio.

Pinocchio is the numeric source of truth (:meth:`Robot.fk`, :meth:`Robot.jacobian`).
For batches, :meth:`Robot.fk_batch` walks the same model tree with numpy, and
:attr:`Robot.symbolic_fk` builds the casadi expression from it; both are tested
against Pinocchio. Small batches (a metaheuristic's population) are evaluated by the
casadi expression instead (lower per-call cost), large ones by the numpy walk.

Real-world URDFs load without edits:

* **Trees.** Only the joints on the path from the root link to the tip are kept; every
  other movable joint (gripper fingers, a second arm, …) is locked at its *reference*
  with ``pinocchio.buildReducedModel``. The reference is zero, or the middle of the
  joint's range when zero is outside it; a locked mimic joint follows its leader's
  reference (``multiplier * reference + offset``). :attr:`Robot.locked` lists them.
* **Continuous joints** are one angle each in ``q`` (Pinocchio's cos/sin pair never
  shows): they are loaded as revolute joints with limits ``±inf``. Samplers that need a
  finite box use :attr:`Robot.sampling_lower` / :attr:`Robot.sampling_upper` (``±π``).
* **Mimic joints** follow their leader, ``q_mimic = multiplier * q_leader + offset``. Off
  the path they are locked with the rest; on the path (leader on the path too) they are
  not a coordinate of ``q``: Pinocchio's mimic joints carry the relation through FK and
  the Jacobian (chain rule), and :attr:`Robot.chain` records it for the numpy and casadi
  walks.
* **Meshes** are never loaded (kinematics do not need them); files that cannot be found
  are reported in one ``logging`` warning, never an exception.
"""

from __future__ import annotations

import io
import logging
import math
import threading
import tomllib
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass
from functools import cached_property
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.checks import check_real, describe, float_array, is_real
from scara_opt.errors import (
    FrameNotFoundError,
    InputError,
    JointLimitError,
    RobotNotFoundError,
    TargetError,
    URDFError,
)
from scara_opt.symbolic import SMALL_BATCH, SMALL_BATCH_POSITIONS, small_batch_poses

if TYPE_CHECKING:
    import casadi

    from scara_opt.dh import DHRobot

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
_MOVABLE = ("revolute", "continuous", "prismatic")
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


def _check_tip(tip: object) -> None:
    """``tip`` is a link name (str) or ``None``."""
    if tip is not None and not isinstance(tip, str):
        raise InputError(f"tip must be the name of a link (a str) or None; got {describe(tip)}")


def _check_xml(text: str, where: str) -> None:
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise URDFError(f"{where} is not well-formed XML ({exc}); fix the file") from None
    if root.tag != "robot":
        raise URDFError(f"{where}: the root element is <{root.tag}>, a URDF needs <robot>")


# ---------------------------------------------------------------------- the URDF tree
def _load_urdf(text: str, mesh_dir: str | None, where: str) -> Any:
    """Parse with yourdfpy (no meshes loaded), turning its bare exceptions into URDFError."""
    import yourdfpy

    try:
        return yourdfpy.URDF.load(
            io.BytesIO(text.encode()), build_scene_graph=False, load_meshes=False,
            build_collision_scene_graph=False, load_collision_meshes=False,
            mesh_dir=mesh_dir or "",
        )
    except Exception as exc:  # yourdfpy raises bare KeyError/ValueError on bad structure
        raise URDFError(f"{where} is not a valid URDF: {type(exc).__name__}: {exc}") from None


def _check_rates(j: Any, where: str) -> None:
    """``<limit velocity= effort=>`` are finite and >= 0 (0: not given, the URDF convention)."""
    lim = j.limit
    for key in ("velocity", "effort"):
        value = None if lim is None else getattr(lim, key)
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise URDFError(f"{where}: joint {j.name!r} has <limit {key}=\"{value}\">; it must "
                            "be a finite number >= 0 (0 or absent: not given)")


def _check_limits(j: Any, where: str) -> None:
    """A revolute or prismatic joint needs finite ``lower < upper`` (continuous: none).

    The range's width must be finite too: samplers draw from it.
    """
    _check_rates(j, where)
    if j.type == "continuous":
        return
    lim = j.limit
    if lim is None or lim.lower is None or lim.upper is None:
        raise URDFError(f"{where}: joint {j.name!r} has no <limit lower= upper=>; add its range "
                        "(or make it type continuous if it turns without limits)")
    if not (math.isfinite(lim.lower) and math.isfinite(lim.upper)):
        raise JointLimitError(f"{where}: joint {j.name!r} has non-finite limits", j.name)
    if not lim.lower < lim.upper:
        raise JointLimitError(
            f"{where}: joint {j.name!r} has lower limit {lim.lower} >= upper limit "
            f"{lim.upper}; swap them or fix the URDF",
            j.name,
        )
    if not math.isfinite(lim.upper - lim.lower):
        raise JointLimitError(
            f"{where}: joint {j.name!r} has the range [{lim.lower}, {lim.upper}], whose width "
            "overflows; give its real range (or make it type continuous if it turns without "
            "limits)", j.name)


def _check_axis(j: Any, where: str) -> None:
    """A movable joint needs three finite axis numbers, not all zero (any length: normalised)."""
    axis = np.asarray(j.axis, float)
    text = " ".join(map(str, axis.tolist()))
    if axis.shape != (3,) or not np.isfinite(axis).all():
        raise URDFError(f"{where}: joint {j.name!r} has axis xyz=\"{text}\", not three finite "
                        'numbers; give a unit axis, e.g. <axis xyz="0 0 1"/>')
    if not np.linalg.norm(axis) > 0:
        raise URDFError(f"{where}: joint {j.name!r} has a zero-length axis xyz=\"{text}\"; "
                        'give a unit axis, e.g. <axis xyz="0 0 1"/>')


def _check_mimic(j: Any, joints: dict[str, Any], where: str) -> None:
    """A mimic joint must follow an existing movable joint that is not itself a mimic."""
    leader = joints.get(j.mimic.joint)
    if leader is None or leader.type not in _MOVABLE:
        raise URDFError(f"{where}: mimic joint {j.name!r} follows {j.mimic.joint!r}, which is "
                        "not a movable joint of the URDF; fix its <mimic joint=>")
    if leader.mimic is not None:
        raise URDFError(f"{where}: mimic joint {j.name!r} follows {leader.name!r}, itself a "
                        f"mimic joint; make it follow {leader.mimic.joint!r} directly")


def _unique(names: list[str], kind: str, where: str) -> None:
    """No two links (or joints) share a name."""
    dup = sorted(n for n, count in Counter(names).items() if count > 1)
    if dup:
        raise URDFError(f"{where}: {kind} name(s) {', '.join(map(repr, dup))} are used more than "
                        f"once; give every <{kind}> its own name")


def _cycle(joints: list[Any]) -> list[Any]:
    """The joints of one cycle of the parent → child link graph, in order; ``[]`` if none."""
    left = list(joints)
    while True:  # drop joints whose parent link no remaining joint leads to
        children = {j.child for j in left}
        keep = [j for j in left if j.parent in children]
        if len(keep) == len(left):
            break
        left = keep
    if not left:
        return []
    into, j, seen = {j.child: j for j in left}, left[0], []
    while j not in seen:  # every remaining parent is a remaining child: walk back to a repeat
        seen.append(j)
        j = into[j.parent]
    return seen[seen.index(j):][::-1]


def _check_structure(urdf: Any, where: str) -> dict[str, Any]:
    """Unique names, declared links, no cycle, one parent joint per link: joints by child."""
    links = [lk.name for lk in urdf.robot.links]
    _unique(links, "link", where)
    _unique([j.name for j in urdf.robot.joints], "joint", where)
    declared = set(links)
    for j in urdf.robot.joints:
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in declared:
                raise URDFError(f"{where}: joint {j.name!r} has {role} link {link!r}, which is "
                                f"not declared; add <link name=\"{link}\"/> or fix its <{role}>")
    cycle = _cycle(urdf.robot.joints)
    if cycle:
        loop = " -> ".join([cycle[0].parent, *(j.child for j in cycle)])
        raise URDFError(f"{where}: joints {', '.join(repr(j.name) for j in cycle)} form a cycle "
                        f"({loop}); a URDF must be a tree (closed loops are not supported): "
                        "remove one of these joints or fix its <parent>/<child>")
    by_child: dict[str, Any] = {}
    for j in urdf.robot.joints:
        if j.child in by_child:
            raise URDFError(f"{where}: link {j.child!r} is the child of two joints, "
                            f"{by_child[j.child].name!r} and {j.name!r}; a URDF must be a tree: "
                            "give each link at most one parent joint")
        by_child[j.child] = j
    return by_child


def _tree(urdf: Any, where: str) -> tuple[dict[str, Any], str]:
    """Joints by child link, and the root link; checks tree, joint types, axes, limits, mimics."""
    by_child = _check_structure(urdf, where)
    joints = {j.name: j for j in urdf.robot.joints}
    for j in urdf.robot.joints:
        if j.type not in (*_MOVABLE, "fixed"):
            raise URDFError(
                f"{where}: joint {j.name!r} is {j.type!r}; only revolute, continuous, "
                "prismatic and fixed joints are supported (model a floating base or a planar "
                "joint as fixed, or as a chain of prismatic and revolute joints)"
            )
        if j.type != "fixed":
            _check_axis(j, where)
            _check_limits(j, where)
        if j.mimic is not None and j.type != "fixed":
            _check_mimic(j, joints, where)
    roots = [lk.name for lk in urdf.robot.links if lk.name not in by_child]
    if len(roots) != 1:
        raise URDFError(f"{where}: expected one root link, found {roots}; the URDF must be a tree")
    return by_child, roots[0]


def _path(by_child: dict[str, Any], root: str, link: str) -> list[Any]:
    """The URDF joints from ``root`` down to ``link``, in order."""
    out = []
    while link != root:
        out.append(by_child[link])
        link = out[-1].parent
    return out[::-1]


def _dof(path: list[Any]) -> int:
    """Joint coordinates along a path: its movable joints that are not mimic joints."""
    return sum(j.type in _MOVABLE and j.mimic is None for j in path)


def _pick_tip(urdf: Any, by_child: dict[str, Any], root: str, tip: str | None,
              where: str) -> str:
    """``tip`` checked, or, for ``None``, the end link of the longest chain (logged)."""
    links = [lk.name for lk in urdf.robot.links]
    if tip is not None:
        if tip not in links:
            raise FrameNotFoundError(tip, links)
        return tip
    parents = {j.parent for j in urdf.robot.joints}
    ends = [name for name in links if name not in parents]
    paths = {name: _path(by_child, root, name) for name in ends}
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
    kept = [j for j in path if j.type in _MOVABLE
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
              if j.type in _MOVABLE and j.name not in kept_names}
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


def _build_model(text: str, urdf: Any, path: list[Any],
                 where: str) -> tuple[pin.Model, dict[str, float]]:
    """The Pinocchio model of the path's joints, the others locked; and the locked values."""
    kept, locked = _split(urdf, path, where)
    on_path_mimic = any(j.mimic is not None for j in kept)
    xml = _pinocchio_text(text, drop_mimic=set(locked))
    try:  # the mimic flag only when needed: Pinocchio < 3.4 lacks it
        full = pin.buildModelFromXML(xml, True) if on_path_mimic else pin.buildModelFromXML(xml)
    except TypeError:
        raise URDFError(f"{where}: mimic joints on the path to {path[-1].child!r} need "
                        f"Pinocchio >= 3.4 (installed: {pin.__version__}); pip install -U pin"
                        ) from None
    except (RuntimeError, ValueError) as exc:
        raise URDFError(f"Pinocchio could not build {where}: {exc}") from None
    if not locked:
        return full, locked
    q_ref = pin.neutral(full)
    for name, value in locked.items():
        q_ref[full.joints[full.getJointId(name)].idx_q] = value
    ids = [full.getJointId(name) for name in locked]
    return pin.buildReducedModel(full, ids, q_ref), locked


def _unbound_continuous(model: pin.Model, urdf: Any) -> None:
    """Set the position limits of the (former) continuous joints to ``±inf``."""
    lower, upper = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    for j in urdf.robot.joints:
        if j.type == "continuous" and model.existJointName(j.name):
            jm = model.joints[model.getJointId(j.name)]
            if jm.nq == 1:
                lower[jm.idx_q], upper[jm.idx_q] = -np.inf, np.inf
    model.lowerPositionLimit, model.upperPositionLimit = lower, upper


def _chain_joint(model: pin.Model, k: int, urdf_joints: dict[str, Any]) -> ChainJoint:
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


# ---------------------------------------------------------------------- meshes
def _mesh_found(fname: str, folder: str) -> bool:
    """Whether yourdfpy's ``filename_handler_magic`` would resolve ``fname`` (without its log)."""
    import yourdfpy

    depth = len(Path(folder).parts) if folder else 0
    candidates = [yourdfpy.filename_handler_relative(fname, folder),
                  yourdfpy.filename_handler_ignore_directive(fname)]
    candidates += [yourdfpy.filename_handler_relative_to_urdf_file_recursive(fname, folder, k)
                   for k in range(depth)]
    return any(Path(c).is_file() for c in candidates)


def _warn_missing_meshes(urdf: Any, folder: str, where: str) -> None:
    """One ``logging`` warning naming the mesh files that cannot be found, if any."""
    names = [g.geometry.mesh.filename for link in urdf.robot.links
             for g in (*link.visuals, *link.collisions)
             if g.geometry is not None and g.geometry.mesh is not None]
    missing = sorted({f for f in names if not _mesh_found(f, folder)})
    if missing:
        log.warning("%s: %d mesh file(s) cannot be found (e.g. %r); they are skipped: "
                    "kinematics do not use meshes", where, len(missing), missing[0])


#: the attributes of the ``<scara_opt/>`` extension element of a URDF joint
EXTENSION_ATTRIBUTES = ("acceleration",)


def _acceleration_value(joint: ET.Element, ext: ET.Element, where: str) -> float:
    """The checked ``acceleration`` of one ``<scara_opt/>`` element [rad/s² or m/s²]."""
    name = joint.get("name", "")
    unknown = sorted(set(ext.attrib) - set(EXTENSION_ATTRIBUTES))
    if unknown or "acceleration" not in ext.attrib:
        raise URDFError(f"{where}: joint {name!r} has <scara_opt {_attrs(ext)}/>; the element "
                        f"takes {', '.join(EXTENSION_ATTRIBUTES)} only, e.g. "
                        '<scara_opt acceleration="12.5"/> [rad/s² or m/s²]')
    text = ext.get("acceleration", "")
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise URDFError(f"{where}: joint {name!r} has <scara_opt acceleration=\"{text}\"/>; "
                        "the acceleration limit must be a finite number > 0 [rad/s² or m/s²] "
                        "(leave the element out for no limit)")
    return value


def _attrs(element: ET.Element) -> str:
    return " ".join(f'{k}="{v}"' for k, v in element.attrib.items())


def _accelerations(text: str, where: str = "URDF") -> dict[str, float]:
    """The ``<scara_opt acceleration=…/>`` extension written by :mod:`scara_opt.dh`, checked.

    One element at most per movable joint, nowhere else.

    Raises:
        URDFError: a value that is not a finite number > 0, an unknown attribute, a second
            element, or the element outside a movable ``<joint>`` (names the joint and value).
    """
    root = ET.fromstring(text)
    out: dict[str, float] = {}
    hosts = {ext: joint for joint in root.iter("joint") for ext in joint.findall("scara_opt")}
    for ext in root.iter("scara_opt"):
        joint = hosts.get(ext)
        if joint is None or joint.get("type") not in _MOVABLE:
            owner = "a fixed joint" if joint is not None else "outside any <joint>"
            raise URDFError(f"{where}: <scara_opt {_attrs(ext)}/> is on {owner}; it belongs "
                            "inside a revolute, continuous or prismatic <joint>")
        name = joint.get("name", "")
        if name in out:
            raise URDFError(f"{where}: joint {name!r} has more than one <scara_opt/> element; "
                            "keep one")
        out[name] = _acceleration_value(joint, ext, where)
    return out


class Robot:
    """The serial chain of revolute/prismatic joints from a URDF's root link to a tip frame.

    Joints off that chain are locked (see the module docstring for the rules on trees,
    continuous and mimic joints). ``q`` always has one value per joint of
    :attr:`joint_names`: an angle [rad] for revolute and continuous joints, a length [m]
    for prismatic ones.

    Attributes:
        name: robot name (the URDF's, or the bundled robot's).
        model: the (reduced) Pinocchio model, ``model.nq == nq``; ``data`` its workspace.
        tip: name of the tip frame whose pose :meth:`fk` returns.
        chain: the movable joints of the model in order: one per coordinate of ``q``, plus
            any mimic joint on the path (which reads ``q[index]``, see :class:`ChainJoint`).
        locked: ``{joint name: value}`` of the joints off the path, held at their
            reference [rad or m]: zero, or mid-range when zero is outside the range.
        tip_placement: 4×4 placement of the tip in the last joint's frame [m].
        source: where the robot comes from (paper, file path).
        metadata: extra data of a robot file (for bundled robots: the whole parsed TOML,
            e.g. a ``[footprint]`` table); empty for a plain URDF.
    """

    def __init__(self, urdf_text: str, tip: str | None = None, *, name: str | None = None,
                 where: str = "URDF", source: str = "", notes: str = "",
                 mesh_dir: str | None = None, metadata: dict | None = None) -> None:
        if not isinstance(urdf_text, str):
            raise InputError(f"urdf_text must be the URDF's XML as a str (to load a file, use "
                             f"Robot.from_urdf(path) or so.load_robot(path)); got "
                             f"{describe(urdf_text)}")
        _check_tip(tip)
        _check_xml(urdf_text, where)
        urdf = _load_urdf(urdf_text, mesh_dir, where)
        by_child, root = _tree(urdf, where)
        self.tip = _pick_tip(urdf, by_child, root, tip, where)
        self._init_args = (urdf_text, self.tip, name, where, source, notes, mesh_dir)
        _warn_missing_meshes(urdf, mesh_dir or "", where)
        self.model, self.locked = _build_model(urdf_text, urdf, _path(by_child, root, self.tip),
                                               where)
        _unbound_continuous(self.model, urdf)
        self._local = threading.local()
        self.name = name or urdf.robot.name
        self.source = source or where
        self.notes = notes
        self.metadata: dict = dict(metadata or {})
        joints = {j.name: j for j in urdf.robot.joints}
        self.chain: tuple[ChainJoint, ...] = tuple(
            _chain_joint(self.model, k, joints) for k in range(1, self.model.njoints))
        if not self.chain:
            raise URDFError(f"{where} has no movable joint between its root {root!r} and the tip "
                            f"{self.tip!r}; IK and trajectories need at least one: pick another "
                            "tip=")
        self.tip_id = self.model.getFrameId(self.tip)
        self.tip_placement: Array = self.model.frames[self.tip_id].placement.homogeneous.copy()
        self._set_rate_limits(urdf_text, where)

    @property
    def data(self) -> pin.Data:
        """This thread's Pinocchio workspace for :attr:`model`.

        One per thread: Pinocchio's algorithms write into it, so threads never share one.
        """
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = self.model.createData()
        return data

    def _set_rate_limits(self, urdf_text: str, where: str) -> None:
        """Velocity limits from the model, accelerations from the scara_opt URDF extension."""
        acc = _accelerations(urdf_text, where)
        self._acceleration = np.array([acc.get(name, np.inf) for name in self.joint_names])
        vel = np.array(self.model.velocityLimit, float)
        if np.any(vel <= 0):
            log.warning("%s: joints with velocity limit <= 0 are treated as unlimited", where)
            vel = np.where(vel > 0, vel, np.inf)
        self._velocity = vel

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_urdf(cls, path: str | Path, tip: str | None = None) -> Robot:
        """Load a URDF file: the chain from its root link to ``tip``, other joints locked.

        Every movable joint off the path to ``tip`` is locked at zero, or at the middle of
        its range when zero is outside it (a mimic joint at its leader's reference times
        the multiplier plus the offset); :attr:`locked` lists them. A Panda with its
        fingers gives a 7-joint arm to ``tip="panda_hand_tcp"``. Continuous joints are one
        angle each with limits ``±inf``; mimic joints on the path follow their leader.
        Mesh files that cannot be found are skipped with one ``logging`` warning.

        Args:
            path: path to a ``.urdf`` file.
            tip: name of the tip link. ``None`` takes the end link of the longest chain
                (most joint coordinates, then most joints, then the first in the file) and,
                when the URDF has several end links, logs a warning naming the one taken.

        Raises:
            InputError: ``path`` not a str or Path, ``tip`` not a str or None.
            URDFError: missing or non-UTF-8 file, malformed XML, not a tree (duplicate
                names, undeclared links, a cycle, a link with two parent joints, several
                root links), an unsupported joint type (floating, planar), a zero-length or
                non-finite joint axis, a ``<limit velocity=/effort=>`` that is not a finite
                number >= 0, a ``<scara_opt acceleration=/>`` that is not a finite number
                > 0 (or misplaced, repeated, misspelt), a mimic joint that does not follow a
                movable joint (or follows one after it on the path), or no movable joint on
                the path to the tip.
            FrameNotFoundError: ``tip`` is not a link of the URDF (the message lists them).
            JointLimitError: a joint's lower limit is not below its upper limit, or the
                range's width overflows.
        """
        if not isinstance(path, (str, PathLike)):
            raise InputError(f"path must be the path of a .urdf file (a str or pathlib.Path); "
                             f"got {describe(path)}")
        _check_tip(tip)
        path = Path(path)
        if not path.is_file():
            raise URDFError(f"URDF file {str(path)!r} does not exist; check the path")
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise URDFError(f"URDF file {str(path)!r} is not UTF-8 text ({exc.reason} at byte "
                            f"{exc.start}); pass a URDF (XML) file, saved as UTF-8") from None
        return cls(text, tip, where=f"URDF {str(path)!r}", mesh_dir=str(path.parent))

    @classmethod
    def from_dh(cls, dh: DHRobot, tip: str | None = "tool") -> Robot:
        """Build a robot from a DH table (see :mod:`scara_opt.dh`)."""
        from scara_opt.dh import dh_to_urdf

        return cls(dh_to_urdf(dh), tip, name=dh.name, where=f"robot {dh.name!r}",
                   source=dh.source, notes=dh.notes)

    # ------------------------------------------------------------------ properties
    @property
    def nq(self) -> int:
        """Number of joint coordinates (continuous joints count once, mimic joints not)."""
        return int(self.model.nq)

    @property
    def joint_names(self) -> list[str]:
        """Joint names in the order of ``q``."""
        return [j.name for j in self.chain if not j.mimic]

    @property
    def joint_types(self) -> list[str]:
        """``"revolute"`` (continuous joints too) or ``"prismatic"`` per joint."""
        return [j.kind for j in self.chain if not j.mimic]

    @property
    def lower(self) -> Array:
        """Lower joint limits (nq,) [rad or m]; ``-inf`` for continuous joints."""
        return np.array(self.model.lowerPositionLimit, float)

    @property
    def upper(self) -> Array:
        """Upper joint limits (nq,) [rad or m]; ``+inf`` for continuous joints."""
        return np.array(self.model.upperPositionLimit, float)

    @property
    def sampling_lower(self) -> Array:
        """Lower end (nq,) [rad or m] of the box that random samplers draw ``q`` from.

        :attr:`lower`, except ``-π`` where it is infinite (continuous joints): every
        angle of such a joint is reached within one turn, ``[-π, π]``. For the multi-start
        of IPOPT, the metaheuristics' populations and the Monte Carlo workspace.
        """
        lower = self.lower
        return np.where(np.isfinite(lower), lower, -math.pi)

    @property
    def sampling_upper(self) -> Array:
        """Upper end (nq,) [rad or m] of the sampling box: :attr:`upper`, ``π`` where infinite."""
        upper = self.upper
        return np.where(np.isfinite(upper), upper, math.pi)

    @property
    def velocity_limit(self) -> Array:
        """Joint velocity limits (nq,) [rad/s or m/s]; ``inf`` where the URDF gives none."""
        return self._velocity.copy()

    @property
    def acceleration_limit(self) -> Array:
        """Joint acceleration limits (nq,) [rad/s² or m/s²]; ``inf`` where none is given."""
        return self._acceleration.copy()

    def __reduce__(self) -> tuple:
        """Pickle as the constructor's arguments plus the current limits (for process pools).

        Unpickling in a worker process reuses one rebuilt robot per distinct robot, so its
        cached NLPs and closed-form geometry are built once per process, not once per job.
        """
        limits = (tuple(self.lower), tuple(self.upper))
        return (_rebuild_robot, (self._init_args, self.metadata, limits))

    def with_limits(self, **ranges: tuple[float, float]) -> Robot:
        """A copy with some joints' position limits replaced, by joint name [rad or m].

        Example: ``robot.with_limits(z0=(-0.005, 0.040))`` widens peng2025's stroke. A
        continuous joint given a range becomes bounded (and so does its sampling box).

        Raises:
            JointLimitError: unknown joint, not a pair of numbers (bools and strings
                refused), non-finite values, lower >= upper, or a width that overflows.
        """
        # a fresh object with the constructor's attributes, none of the caches (copy.copy
        # would go through __reduce__ and hand back the per-process rebuilt robot itself)
        new = object.__new__(Robot)
        new.__dict__.update({k: self.__dict__[k] for k in _CORE})
        new.model = pin.Model(self.model)
        new.metadata = dict(self.metadata)
        new._local = threading.local()
        lower, upper = new.model.lowerPositionLimit.copy(), new.model.upperPositionLimit.copy()
        for name, value in ranges.items():
            if name not in self.joint_names:
                raise JointLimitError(f"with_limits: no joint named {name!r}; joints: "
                                      f"{self.joint_names}", joint=name)
            pair = tuple(value) if isinstance(value, (tuple, list, np.ndarray)) else ()
            if len(pair) != 2 or not all(map(is_real, pair)):
                raise JointLimitError(f"with_limits: {name} needs a (lower, upper) pair of "
                                      f"numbers [rad or m]; got {describe(value)}", joint=name)
            try:
                lo, hi = (float(v) for v in pair)
            except OverflowError:  # ints beyond the float range
                lo, hi = -math.inf, math.inf
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi
                    and math.isfinite(hi - lo)):
                raise JointLimitError(
                    f"with_limits: joint {name!r} range ({lo}, {hi}) is not finite with lower < "
                    "upper (and a finite width); pass (lower, upper) in rad or m", joint=name)
            k = self.joint_names.index(name)
            lower[k], upper[k] = lo, hi
        new.model.lowerPositionLimit, new.model.upperPositionLimit = lower, upper
        return new

    def __repr__(self) -> str:
        joints = ", ".join(f"{name}:{kind[0].upper()}"
                           for name, kind in zip(self.joint_names, self.joint_types, strict=True))
        return f"Robot({self.name!r}, nq={self.nq}, joints=[{joints}], tip={self.tip!r})"

    # ------------------------------------------------------------------ input checks
    def check_q(self, q: object, name: str = "q") -> Array:
        """Return ``q`` as a float array of shape (nq,), or raise :class:`InputError`."""
        try:
            arr = float_array(q, name)
        except InputError:
            raise InputError(f"{name} must be numeric, one value per joint "
                             f"{self.joint_names}; got {describe(q)}") from None
        if arr.shape != (self.nq,):
            raise InputError(
                f"{name} must have shape ({self.nq},), one value per joint {self.joint_names} "
                f"[rad or m]; got shape {arr.shape}"
            )
        bad = ~np.isfinite(arr)
        if bad.any():
            names = [self.joint_names[i] for i in np.flatnonzero(bad)]
            raise InputError(f"{name} has non-finite values (NaN or inf) at joints {names}; "
                             "pass finite joint values")
        return arr

    def check_q_batch(self, Q: object, name: str = "Q") -> Array:
        """Return ``Q`` as a float array of shape (n, nq), or raise :class:`InputError`."""
        try:
            arr = float_array(Q, name)
        except InputError:
            raise InputError(f"{name} must be a numeric array of shape (n, {self.nq}); got "
                             f"{describe(Q)}") from None
        if arr.ndim != 2 or arr.shape[1] != self.nq:
            raise InputError(
                f"{name} must have shape (n, {self.nq}), one row per configuration; "
                f"got shape {arr.shape}"
            )
        if not np.isfinite(arr).all():
            rows = np.flatnonzero(~np.isfinite(arr).all(axis=1))
            raise InputError(f"{name} has non-finite values in rows {rows[:10].tolist()}; "
                             "pass finite joint values")
        return arr

    def within_limits(self, q: object, tol: float = 0.0) -> bool | NDArray[np.bool_]:
        """Whether ``q`` (nq,) — or each row of (n, nq) — lies within [lower - tol, upper + tol].

        Raises:
            InputError: ``q`` not numeric or misshaped; ``tol`` not a finite number >= 0.
        """
        tol = check_real("tol", tol, 0.0, unit="rad or m")
        arr = float_array(q, "q")
        arr = self.check_q(arr) if arr.ndim == 1 else self.check_q_batch(arr)
        ok = np.all((arr >= self.lower - tol) & (arr <= self.upper + tol), axis=-1)
        return bool(ok) if arr.ndim == 1 else ok

    # ------------------------------------------------------------------ kinematics
    def fk(self, q: object) -> Array:
        """Tip pose (4×4 homogeneous matrix, world frame, [m]) at ``q`` (nq,), by Pinocchio."""
        qa = self.check_q(q)
        data = self.data
        pin.forwardKinematics(self.model, data, qa)
        return pin.updateFramePlacement(self.model, data, self.tip_id).homogeneous.copy()

    def position(self, q: object) -> Array:
        """Tip position (3,) [m] at ``q``."""
        return self.fk(q)[:3, 3]

    def jacobian(self, q: object) -> Array:
        """Tip Jacobian (6, nq): rows ``[v; ω]`` in the world-aligned frame at the tip.

        A mimic joint on the path adds ``scaling`` times its own column to its leader's
        (the chain rule; Pinocchio's mimic joints do it).
        """
        qa = self.check_q(q)
        return pin.computeFrameJacobian(
            self.model, self.data, qa, self.tip_id, pin.LOCAL_WORLD_ALIGNED
        ).copy()

    def fk_batch(self, Q: object) -> Array:
        """Tip poses (n, 4, 4) for configurations ``Q`` (n, nq), vectorised with numpy.

        Walks the chain read from the Pinocchio model once per joint for the whole
        batch (no Python loop over configurations).
        """
        Qa = self.check_q_batch(Q)
        p, R = self._poses(Qa)
        out = np.zeros((Qa.shape[0], 4, 4))
        out[:, :3, :3] = R
        out[:, :3, 3] = p
        out[:, 3, 3] = 1.0
        return out

    def positions(self, Q: object) -> Array:
        """Tip positions (n, 3) [m] for ``Q`` (n, nq); the batch form of :meth:`position`."""
        Qa = self.check_q_batch(Q)
        if 0 < Qa.shape[0] <= SMALL_BATCH_POSITIONS:
            return small_batch_poses(self, Qa, rotations=False)[0]
        return self._fk_batch_rp(Qa)[1]

    def _poses(self, Q: Array) -> tuple[Array, Array]:
        """Positions (n, 3) and rotations (n, 3, 3) of checked ``Q`` (n, nq).

        Small batches (the populations of the metaheuristics) go through the casadi
        expression, whose per-call cost is ~1 µs; large ones through the numpy chain walk,
        whose ~60 µs per call is then spread over many configurations.
        """
        if 0 < Q.shape[0] <= SMALL_BATCH:
            p, R = small_batch_poses(self, Q)
            return p, cast(Array, R)
        R, p = self._fk_batch_rp(Q)
        return p, R

    def joint_origins(self, Q: object) -> Array:
        """World positions (n, len(chain) + 1, 3) [m] of every joint frame's origin, then the tip.

        ``len(chain)`` is ``nq`` unless mimic joints lie on the path (they have frames too).

        For drawing the arm as a stick figure and checking links against obstacles.
        """
        Qa = self.check_q_batch(Q)
        frames: list[Array] = []
        p = self._fk_batch_rp(Qa, frames)[1]
        return np.stack([f.T for f in frames] + [p], axis=1)

    @cached_property
    def _plan(self) -> tuple[list[tuple], tuple]:
        """The chain compiled once for :meth:`_fk_batch_rp`: only the non-zero terms remain."""
        steps = [(_terms(j.placement[:3, 3]), _rotation_terms(j.placement[:3, :3]), j.kind,
                  _terms(j.axis), _aligned(j.axis), j) for j in self.chain]
        tip = (_terms(self.tip_placement[:3, 3]), _rotation_terms(self.tip_placement[:3, :3]))
        return steps, tip

    def _fk_batch_rp(self, Q: Array, frames: list[Array] | None = None) -> tuple[Array, Array]:
        # R is kept as its three columns, each (3, n), so every step is a few fused
        # elementwise operations over the batch instead of stacked 3×3 products; the
        # constant parts were reduced to their non-zero terms once (_plan).
        n = Q.shape[0]
        cols: list[Array] = [np.tile(e[:, None], (1, n)) for e in np.eye(3)]
        p: Array = np.zeros((3, n))
        steps, (tip_t, tip_R) = self._plan
        for t_terms, R_terms, kind, axis_terms, aligned, j in steps:
            p = _add_terms(p, cols, t_terms)
            if frames is not None:
                frames.append(p)
            if R_terms is not None:
                cols = [_sum_terms(cols, col) for col in R_terms]
            q = Q[:, j.index]
            if j.mimic:
                q = j.scaling * q + j.offset
            if kind == "prismatic":
                p = p + _sum_terms(cols, axis_terms) * q
            elif aligned is not None:
                a, b, sign = aligned
                c, s = np.cos(q), np.sin(q) * sign
                cols = list(cols)
                cols[a], cols[b] = cols[a] * c + cols[b] * s, cols[b] * c - cols[a] * s
            else:
                cols = _rotate_var(cols, j.axis, q)
        p = _add_terms(p, cols, tip_t)
        if tip_R is not None:
            cols = [_sum_terms(cols, col) for col in tip_R]
        return np.stack(cols, axis=-1).transpose(1, 0, 2), p.T

    @cached_property
    def symbolic_fk(self) -> casadi.Function:
        """casadi Function ``q (nq,) -> (p (3,), R (3×3))``, built from the model tree.

        Use ``robot.symbolic_fk.map(n)`` to evaluate a batch of ``n`` columns.
        """
        from scara_opt.symbolic import build_symbolic_fk

        return build_symbolic_fk(self.chain, self.tip_placement, name=f"fk_{self.name}")

    # ------------------------------------------------------------------ planar tool angle
    @cached_property
    def yaw_axis(self) -> Array | None:
        """World axis (3,) about which the tool turns, if every revolute axis is parallel.

        That holds for SCARA-type chains (and stays true for every ``q``, since rotating
        about parallel axes keeps them parallel). ``None`` otherwise: such a robot has no
        single tool angle, and a yaw target is refused for it.
        """
        q0 = np.clip(np.zeros(self.nq), self.lower, self.upper)
        data = self.data
        pin.forwardKinematics(self.model, data, q0)
        axes = [data.oMi[k].rotation @ j.axis
                for k, j in enumerate(self.chain, start=1) if j.kind == "revolute"]
        if not axes:
            return None
        n = axes[0] / np.linalg.norm(axes[0])
        if all(np.linalg.norm(np.cross(n, a)) < 1e-9 for a in axes[1:]):
            return n
        return None

    def yaw(self, q: object) -> float:
        """Tool angle [rad] about :attr:`yaw_axis`, in (-π, π].

        Measured as the angle of the tool's x-axis in the plane normal to the axis, from
        the world axis of :meth:`yaw_basis` ``e1`` toward ``e2`` (for a SCARA with a
        vertical axis: the angle from world x to the tool x-axis, :math:`θ_1+θ_2+θ_4`).

        Raises:
            TargetError: the robot has no yaw axis (see :attr:`yaw_axis`).
        """
        e1, e2 = self.yaw_basis()
        x = self.fk(q)[:3, 0]
        return float(math.atan2(x @ e2, x @ e1))

    def yaw_basis(self) -> tuple[Array, Array]:
        """Orthonormal (e1, e2) spanning the plane normal to :attr:`yaw_axis`, e1 × e2 = axis.

        Computed once (read-only arrays): every yaw cost and error uses it.
        """
        basis: tuple[Array, Array] | None = self.__dict__.get("_yaw_basis")
        if basis is not None:
            return basis
        n = self.yaw_axis
        if n is None:
            raise TargetError(
                f"robot {self.name!r} has no single tool-angle axis (its revolute axes are not "
                "all parallel); give a full rotation= instead of yaw="
            )
        ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = ref - (ref @ n) * n
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        e1.setflags(write=False)
        e2.setflags(write=False)
        self.__dict__["_yaw_basis"] = (e1, e2)
        return e1, e2


#: the attributes :class:`Robot`'s constructor sets; everything else in its ``__dict__`` is a
#: cache (casadi Functions, IPOPT solvers, the SCARA geometry, ...) that a copy must not share
_CORE = ("tip", "_init_args", "model", "locked", "name", "source", "notes", "metadata",
         "chain", "tip_id", "tip_placement", "_acceleration", "_velocity")

_REBUILT: dict[tuple, Robot] = {}


def _rebuild_robot(init_args: tuple, metadata: dict, limits: tuple) -> Robot:
    """Unpickle a :class:`Robot` (see :meth:`Robot.__reduce__`); one instance per process."""
    key = (init_args, limits)
    if key not in _REBUILT:
        text, tip, name, where, source, notes, mesh_dir = init_args
        robot = Robot(text, tip, name=name, where=where, source=source, notes=notes,
                      mesh_dir=mesh_dir, metadata=metadata)
        lower, upper = np.array(limits[0]), np.array(limits[1])
        if not (np.array_equal(lower, robot.lower) and np.array_equal(upper, robot.upper)):
            robot = robot.with_limits(**{n: (lo, hi) for n, lo, hi in
                                         zip(robot.joint_names, lower, upper, strict=True)})
        _REBUILT[key] = robot
    return _REBUILT[key]


def _terms(w: Array) -> tuple[tuple[int, float], ...]:
    """The non-zero entries of a constant (3,) vector as (index, value) pairs."""
    return tuple((i, float(v)) for i, v in enumerate(w) if v != 0.0)


def _rotation_terms(Rf: Array) -> tuple | None:
    """Per column of a constant 3×3 rotation, its non-zero terms; ``None`` for the identity."""
    if np.array_equal(Rf, np.eye(3)):
        return None
    return tuple(_terms(Rf[:, j]) for j in range(3))


def _aligned(axis: Array) -> tuple[int, int, float] | None:
    """For an axis along ±x, ±y or ±z: the two columns it mixes and its sign; else ``None``."""
    k = np.flatnonzero(axis)
    if k.size != 1:
        return None
    i = int(k[0])
    return (i + 1) % 3, (i + 2) % 3, float(np.sign(axis[i]))


def _sum_terms(cols: list[Array], terms: tuple[tuple[int, float], ...]) -> Array:
    """Σ cols[i] · w over the (i, w) terms (at least one term: rotation columns never vanish)."""
    (i0, w0), *rest = terms
    out = cols[i0] if w0 == 1.0 else cols[i0] * w0
    for i, w in rest:
        out = out + (cols[i] if w == 1.0 else cols[i] * w)
    return out


def _add_terms(p: Array, cols: list[Array], terms: tuple[tuple[int, float], ...]) -> Array:
    """``p`` + Σ cols[i] · w; ``p`` itself when there are no terms."""
    return p + _sum_terms(cols, terms) if terms else p


def _rotate_var(cols: list[Array], axis: Array, q: Array) -> list[Array]:
    """Columns of R @ Rot(axis, q) for angles ``q`` (n,) [rad] about a unit ``axis``."""
    c, s = np.cos(q), np.sin(q)
    k = np.flatnonzero(axis)
    if k.size == 1:  # axis-aligned: a planar rotation of the two other columns
        i = int(k[0])
        a, b = (i + 1) % 3, (i + 2) % 3
        s = s * axis[i]
        out = list(cols)
        out[a] = cols[a] * c + cols[b] * s
        out[b] = cols[b] * c - cols[a] * s
        return out
    x, y, z = axis
    C = 1.0 - c
    rot = [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
           [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
           [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]
    return [cols[0] * rot[0][j] + cols[1] * rot[1][j] + cols[2] * rot[2][j] for j in range(3)]


# ---------------------------------------------------------------------- bundled robots
def list_robots() -> list[str]:
    """Names of the bundled robots (``robots/<name>.toml``)."""
    from scara_opt.dh import bundled_dir

    return sorted(p.stem for p in bundled_dir().glob("*.toml"))


def load_robot(name: str | Path, tip: str | None = None) -> Robot:
    """Load a bundled robot by name, or a robot file by path (``.urdf`` or DH ``.toml``).

    Args:
        name: a name from :func:`list_robots` (e.g. ``"zavar2024"``) or a file path.
        tip: tip frame; bundled robots default to their ``"tool"`` frame.

    Raises:
        InputError: ``name`` not a str or Path, ``tip`` not a str or None.
        RobotNotFoundError: neither a bundled name nor an existing file (lists the names).
        URDFError: the file is malformed (see :meth:`Robot.from_urdf` and
            :func:`scara_opt.dh.load_dh`).
    """
    from scara_opt.dh import bundled_dir, load_dh

    if not isinstance(name, (str, PathLike)):
        raise InputError(f"name must be a bundled robot name ({', '.join(list_robots())}) or "
                         f"the path of a .urdf or .toml file; got {describe(name)}")
    _check_tip(tip)
    if isinstance(name, str) and name in list_robots():
        folder = bundled_dir()
        dh = load_dh(folder / f"{name}.toml")
        urdf = folder / f"{name}.urdf"
        return Robot(urdf.read_text(), tip or "tool", name=name, where=f"robot {name!r}",
                     source=dh.source, notes=dh.notes,
                     metadata=tomllib.loads((folder / f"{name}.toml").read_text()))
    path = Path(name)
    if not path.is_file():
        raise RobotNotFoundError(str(name), list_robots())
    if path.suffix == ".toml":
        robot = Robot.from_dh(load_dh(path), tip or "tool")
        robot.metadata = tomllib.loads(path.read_text())
        return robot
    return Robot.from_urdf(path, tip)


#: the optional package of robot descriptions, and the extra that installs it
EXAMPLE_ROBOT_DATA = "example-robot-data"
ROBOTS_EXTRA = "pip install 'scara-opt[robots]'"


def example_robot_data_urdf(relative: str) -> Path:
    """Path of a URDF shipped by the optional ``example-robot-data`` package.

    The package (version 4.4 and later) holds only the robot files, under
    ``…/share/example-robot-data/robots/``; they are found through the installed
    distribution's file list, without importing anything.

    Args:
        relative: the file's path below ``robots/``, e.g.
            ``"panda_description/urdf/panda.urdf"`` or ``"ur_description/urdf/ur5_robot.urdf"``.

    Returns:
        The absolute path of the URDF file.

    Raises:
        ModuleNotFoundError: ``example-robot-data`` is not installed (the message names
            the extra to install).
        URDFError: the package has no such file (the message lists its URDFs).
    """
    from importlib import metadata

    try:
        files = metadata.distribution(EXAMPLE_ROBOT_DATA).files or []
    except metadata.PackageNotFoundError:
        raise ModuleNotFoundError(f"{EXAMPLE_ROBOT_DATA} is not installed; {ROBOTS_EXTRA}",
                                  name=EXAMPLE_ROBOT_DATA) from None
    suffix = "/robots/" + relative.strip("/")
    match = [f for f in files if f.as_posix().endswith(suffix)]
    if not match:
        urdfs = sorted(f.as_posix().split("/robots/", 1)[1] for f in files
                       if f.suffix == ".urdf" and "/robots/" in f.as_posix())
        raise URDFError(f"{EXAMPLE_ROBOT_DATA} has no file robots/{relative}; its URDFs: "
                        f"{', '.join(urdfs)}; pass one of these paths")
    return Path(str(match[0].locate())).resolve()
