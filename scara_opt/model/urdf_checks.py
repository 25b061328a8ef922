"""URDF checks: well-formed XML, a tree of supported joints, limits, axes, mimics, extensions.

Everything is checked before Pinocchio sees the file, so a malformed URDF ends in a
:class:`~scara_opt.errors.URDFError` (or :class:`~scara_opt.errors.JointLimitError`) that
says what is wrong and what to fix, never in a library's bare exception. Also here: the
toolkit's own ``<scara_opt acceleration="..."/>`` extension, checked where it is read, and
the one warning about mesh files that cannot be found (kinematics never load meshes).
"""

from __future__ import annotations

import io
import logging
import math
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

from scara_opt.checks import describe
from scara_opt.errors import InputError, JointLimitError, URDFError

log = logging.getLogger(__name__)

MOVABLE = ("revolute", "continuous", "prismatic")

def check_tip(tip: object) -> None:
    """``tip`` is a link name (str) or ``None``."""
    if tip is not None and not isinstance(tip, str):
        raise InputError(f"tip must be the name of a link (a str) or None; got {describe(tip)}")

def check_xml(text: str, where: str) -> None:
    """``text`` is well-formed XML whose root element is ``<robot>``."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise URDFError(f"{where} is not well-formed XML ({exc}); fix the file") from None
    if root.tag != "robot":
        raise URDFError(f"{where}: the root element is <{root.tag}>, a URDF needs <robot>")

def load_urdf(text: str, mesh_dir: str | None, where: str) -> Any:
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
    if leader is None or leader.type not in MOVABLE:
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

def check_tree(urdf: Any, where: str) -> tuple[dict[str, Any], str]:
    """Joints by child link, and the root link; checks tree, joint types, axes, limits, mimics."""
    by_child = _check_structure(urdf, where)
    joints = {j.name: j for j in urdf.robot.joints}
    for j in urdf.robot.joints:
        if j.type not in (*MOVABLE, "fixed"):
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

def resolve_mesh(fname: str, folder: str) -> Path | None:
    """The file yourdfpy's ``filename_handler_magic`` resolves ``fname`` to, or None.

    Relative to the URDF's folder, the URI's directive (``package://``, ``file://``)
    dropped, or relative to a folder above it (how a ``package://pkg/...`` URI finds the
    package's share folder); the first candidate that is a file.
    """
    import yourdfpy

    depth = len(Path(folder).parts) if folder else 0
    candidates = [yourdfpy.filename_handler_relative(fname, folder),
                  yourdfpy.filename_handler_ignore_directive(fname)]
    candidates += [yourdfpy.filename_handler_relative_to_urdf_file_recursive(fname, folder, k)
                   for k in range(depth)]
    return next((Path(c).resolve() for c in candidates if Path(c).is_file()), None)


def _mesh_found(fname: str, folder: str) -> bool:
    """Whether yourdfpy's ``filename_handler_magic`` would resolve ``fname`` (without its log)."""
    return resolve_mesh(fname, folder) is not None

def warn_missing_meshes(urdf: Any, folder: str, where: str) -> None:
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

def accelerations(text: str, where: str = "URDF") -> dict[str, float]:
    """The ``<scara_opt acceleration=…/>`` extension written by :mod:`scara_opt.model.dh`, checked.

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
        if joint is None or joint.get("type") not in MOVABLE:
            owner = "a fixed joint" if joint is not None else "outside any <joint>"
            raise URDFError(f"{where}: <scara_opt {_attrs(ext)}/> is on {owner}; it belongs "
                            "inside a revolute, continuous or prismatic <joint>")
        name = joint.get("name", "")
        if name in out:
            raise URDFError(f"{where}: joint {name!r} has more than one <scara_opt/> element; "
                            "keep one")
        out[name] = _acceleration_value(joint, ext, where)
    return out
