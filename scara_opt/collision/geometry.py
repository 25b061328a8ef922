"""The robot's collision bodies: a Pinocchio ``GeometryModel`` attached to the Robot's joints.

* **A URDF with ``<collision>`` elements** gives its meshes and primitives through
  Pinocchio's ``buildGeomFromUrdfString`` (coal shapes; meshes found beside the URDF or
  through ``package://``). A mesh that cannot be found is a :class:`MeshNotFoundError`,
  unless ``missing_mesh="capsule"`` asks for the capsule of that link instead (logged).
* **A robot without any** (every DH robot file, the bundled ones included) gets capsules
  built from its own kinematics, radii from the robot file's ``radius`` keys (one per
  ``[[joints]]`` row, the link that joint moves) or from ``radius=``. The assumptions:
  the link of joint *k* is a capsule from joint *k*'s frame origin to the next joint's
  (the last link to the tip frame; a zero-length one is a ball); the link of a prismatic
  joint also has a *shaft* ``<link>_shaft``, a capsule of the same radius along its axis,
  as long as the stroke and trailing behind its motion (a SCARA's spline quill, which
  passes through the arm above the tool; a zero-length link then has its shaft only).

**Self-collision pairs** leave out: bodies on the same or adjacent joints; pairs in contact
at the robot's reference configuration (zero, clipped to the limits): taken to be built
that way, as MoveIt's setup assistant disables its "Default" pairs (a quill passing through
its arm); and the pairs of an SRDF's ``<disable_collisions link1= link2=/>`` or of
``allowed=``. Each left-out pair and its reason is in :attr:`RobotGeometry.skipped`.

Every body also carries *support points* in its joint's frame: the body lies within the
convex hull of the points grown by ``pad`` [m]. :mod:`scara_opt.collision.continuous`
bounds how far a body can move from them.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.checks import check_real, describe
from scara_opt.errors import CellError, InputError, MeshNotFoundError, UnknownBodyError
from scara_opt.model.robot import Robot, check_robot

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

__all__ = ["Body", "RobotGeometry", "capsule_object", "pair_distance",
           "reference_configuration", "robot_geometry", "support_points"]

#: how a link without a mesh file may be replaced (``missing_mesh=``)
MISSING_MESH = ("error", "capsule")


@dataclass(frozen=True)
class Body:
    """One collision body.

    Attributes:
        name: unique name: a URDF link's name (``<link>_<k>`` for each of the shapes of a
            link with several), a capsule's link name, a shaft's ``<link>_shaft``, or an
            obstacle's name.
        link: the URDF link it belongs to (the obstacle's name for an obstacle).
        joint: the Pinocchio joint it moves with (0: fixed in the world).
        points: (k, 3) support points in the joint's frame [m].
        pad: the body lies within the convex hull of ``points`` grown by ``pad`` [m].
    """

    name: str
    link: str
    joint: int
    points: Array
    pad: float


@dataclass(frozen=True, eq=False)
class RobotGeometry:
    """The robot's collision bodies and the self-collision pairs to check.

    Attributes:
        robot: the robot.
        model: the Pinocchio ``GeometryModel`` of the robot's bodies (attached to
            ``robot.model``'s joints), without collision pairs.
        bodies: one :class:`Body` per geometry object, in the model's order.
        pairs: the self-collision pairs to check, ``(i, j)`` indices into ``bodies``.
        skipped: ``{(name_i, name_j): reason}`` of the self pairs left out.
        source: how the bodies were made (``"URDF <collision>"`` or the capsule rule).
    """

    robot: Robot
    model: pin.GeometryModel
    bodies: tuple[Body, ...]
    pairs: tuple[tuple[int, int], ...]
    skipped: dict[tuple[str, str], str] = field(default_factory=dict)
    source: str = ""

    @property
    def names(self) -> list[str]:
        """The bodies' names, in order."""
        return [b.name for b in self.bodies]

    @property
    def links(self) -> list[str]:
        """The links that have bodies, in chain order, each once."""
        return list(dict.fromkeys(b.link for b in self.bodies))

    def __repr__(self) -> str:
        return (f"RobotGeometry({self.robot.name!r}: {len(self.bodies)} bodies, "
                f"{len(self.pairs)} self pairs checked, {len(self.skipped)} left out; "
                f"{self.source})")


def support_points(shape: coal.CollisionGeometry, placement: pin.SE3) -> tuple[Array, float]:
    """Points (k, 3) and a pad [m]: ``shape`` at ``placement`` lies in their hull grown by pad.

    Spheres, capsules and cylinders by their axis ends and radius (a cylinder within its
    capsule), anything else (box, convex, mesh, ...) by the corners of its local AABB.
    """
    R, t = placement.rotation, placement.translation
    if isinstance(shape, coal.Sphere):
        return t[None, :].copy(), float(shape.radius)
    if isinstance(shape, (coal.Capsule, coal.Cylinder)):
        h = float(shape.halfLength)
        ends = np.array([[0.0, 0.0, -h], [0.0, 0.0, h]]) @ R.T + t
        return ends, float(shape.radius)
    shape.computeLocalAABB()
    lo, hi = np.asarray(shape.aabb_local.min_), np.asarray(shape.aabb_local.max_)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    return corners @ R.T + t, 0.0


def pair_distance(geom: pin.GeometryModel, gdata: pin.GeometryData, i: int, j: int) -> float:
    """Coal's signed distance [m] of objects ``i`` and ``j`` as placed in ``gdata``, afresh.

    A fresh request (no GJK guess from an earlier call): what every verdict is decided by
    (:meth:`~scara_opt.collision.checker.CollisionChecker.collides`).
    """
    req, res = coal.DistanceRequest(), coal.DistanceResult()
    return float(coal.distance(geom.geometryObjects[i].geometry, gdata.oMg[i],
                               geom.geometryObjects[j].geometry, gdata.oMg[j], req, res))


def capsule_object(name: str, joint: int, a: Array, b: Array, radius: float
                   ) -> pin.GeometryObject:
    """A coal capsule from ``a`` to ``b`` (3,) in joint ``joint``'s frame [m]."""
    d = np.asarray(b, float) - np.asarray(a, float)
    length = float(np.linalg.norm(d))
    R = np.eye(3)
    if length > 1e-12:
        z = d / length
        helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        R = np.column_stack([x, np.cross(z, x), z])
    placement = pin.SE3(R, (np.asarray(a, float) + np.asarray(b, float)) / 2)
    return pin.GeometryObject(name, joint, placement, coal.Capsule(radius, length))


def reference_configuration(robot: Robot) -> Array:
    """Zero clipped to the joint limits (nq,): where self pairs in contact are taken as built."""
    return np.clip(np.zeros(robot.nq), robot.lower, robot.upper)


def _link_names(robot: Robot) -> list[str]:
    """The URDF link each Pinocchio joint moves (index 0: the root link)."""
    model = robot.model
    names = [model.frames[0].name] * model.njoints
    for k in range(1, model.njoints):
        for f in model.frames:
            if f.type == pin.FrameType.BODY and f.parentJoint == k:
                names[k] = f.name
                break
    return names


def _radii(robot: Robot, radius: object) -> dict[str, float]:
    """Capsule radius by joint name [m]: ``radius=`` (a number or a dict), else the file's."""
    from scara_opt.model.dh_file import collision_radii

    names = robot.joint_names
    if radius is None:
        return collision_radii(robot.metadata)
    if isinstance(radius, dict):
        unknown = [k for k in radius if k not in names]
        if unknown:
            raise InputError(f"radius= names joints {unknown} that {robot.name!r} does not have; "
                             f"joints: {', '.join(names)}")
        return {k: check_real(f"radius[{k!r}]", v, 0.0, low_open=True, unit="m",
                              error=CellError) for k, v in radius.items()}
    r = check_real("radius", radius, 0.0, low_open=True, unit="m", error=CellError)
    return dict.fromkeys(names, r)


def _capsules(robot: Robot, radius: object, only: set[str] | None = None
              ) -> list[pin.GeometryObject]:
    """The capsule rule of the module docstring, for every link (or the links in ``only``)."""
    radii = _radii(robot, radius)
    model, links = robot.model, _link_names(robot)
    out = []
    for k, cj in enumerate(robot.chain, start=1):
        name = model.names[k]
        key = robot.joint_names[cj.index] if cj.mimic else name
        if only is not None and links[k] not in only:
            continue
        if key not in radii:
            raise CellError(
                f"robot {robot.name!r}: the link of joint {name!r} has no collision geometry "
                "and no capsule radius; add radius = ... (its half-width, in the file's "
                "length unit) to that [[joints]] row of the robot file, <collision> elements "
                "to the URDF, or pass radius= (a number [m] or {joint: radius})")
        r = radii[key]
        end = (model.jointPlacements[k + 1].translation if k + 1 < model.njoints
               else robot.tip_placement[:3, 3])
        if cj.kind != "prismatic" or np.linalg.norm(end) > 1e-12:  # else its shaft alone
            out.append(capsule_object(links[k], k, np.zeros(3), end, r))
        if cj.kind == "prismatic":
            lo, hi = robot.lower[cj.index], robot.upper[cj.index]
            stroke = abs(cj.scaling) * (hi - lo)
            if not np.isfinite(stroke):
                raise CellError(f"robot {robot.name!r}: prismatic joint {name!r} has no finite "
                                "stroke, so its shaft has no length; give it limits")
            out.append(capsule_object(f"{links[k]}_shaft", k, np.zeros(3),
                                      -np.sign(cj.scaling) * stroke * cj.axis, r))
    return out


def _mesh_files(urdf_text: str) -> list[tuple[str, str]]:
    """``(link, filename)`` of every ``<collision>`` mesh of the URDF."""
    root = ET.fromstring(urdf_text)
    return [(link.get("name", ""), mesh.get("filename", ""))
            for link in root.iter("link") for col in link.findall("collision")
            for mesh in col.iter("mesh")]


def _urdf_bodies(robot: Robot, radius: object, missing_mesh: str) -> list[pin.GeometryObject]:
    """The URDF's ``<collision>`` objects, a missing mesh's link as capsules if asked.

    Every mesh file is found as yourdfpy finds it (relative to the URDF, or a
    ``package://`` URI from a folder above it: example-robot-data's layout) and handed
    to Pinocchio as that absolute path, so Pinocchio needs no package folders.
    """
    from scara_opt.model.urdf_checks import resolve_mesh

    urdf_text, mesh_dir = robot._init_args[0], robot._init_args[6] or ""
    root = ET.fromstring(urdf_text)
    missing: list[tuple[str, str]] = []
    for link in root.iter("link"):
        for col in link.findall("collision"):
            for mesh in col.iter("mesh"):
                fname = mesh.get("filename", "")
                found = resolve_mesh(fname, mesh_dir)
                if found is None:
                    missing.append((link.get("name", ""), fname))
                else:
                    mesh.set("filename", str(found))
    lost: set[str] = set()
    if missing:
        link, fname = missing[0]
        if missing_mesh == "error":
            raise MeshNotFoundError(
                fname, f"robot {robot.name!r}, <collision> of link {link!r}",
                f"{len(missing)} collision mesh(es) missing; install the package that ships "
                "them, fix the path (relative to the URDF), or pass missing_mesh='capsule' "
                "to give those links capsules (with radius=)")
        lost = {link for link, _ in missing}
        log.warning("robot %r: collision meshes of links %s cannot be found (e.g. %r); those "
                    "links get capsules instead (missing_mesh='capsule')", robot.name,
                    sorted(lost), fname)
        for node in root.iter("link"):
            if node.get("name") in lost:
                for col in node.findall("collision"):
                    node.remove(col)
    urdf_text = ET.tostring(root, encoding="unicode")
    geom = pin.buildGeomFromUrdfString(robot.model, urdf_text, pin.GeometryType.COLLISION,
                                       package_dirs=[mesh_dir] if mesh_dir else [])
    objects = list(geom.geometryObjects)
    _link_named(robot, objects)
    _check_mesh_sizes(robot, objects)
    if lost:
        objects += _capsules(robot, radius, only=lost)
    return objects


def _check_mesh_sizes(robot: Robot, objects: list[pin.GeometryObject]) -> None:
    """Refuse a link mesh metres across (a file in mm with no ``scale`` on its ``<mesh>``).

    Raises:
        CellError: a mesh wider than :data:`~scara_opt.collision.obstacles.MESH_EXTENT`.
    """
    from scara_opt.collision.obstacles import MESH_EXTENT

    for obj in objects:
        shape = obj.geometry
        if not isinstance(shape, coal.BVHModelBase) or not shape.num_vertices:
            continue
        V = np.asarray(shape.vertices(), float)
        extent = float((V.max(axis=0) - V.min(axis=0)).max())
        if extent > MESH_EXTENT:
            raise CellError(f"robot {robot.name!r}: the collision mesh of link {obj.name!r} "
                            f"({obj.meshPath}) spans {extent:.4g} m; a file in mm needs "
                            "<mesh filename=... scale=\"0.001 0.001 0.001\"/> in the URDF")


def _link_named(robot: Robot, objects: list[pin.GeometryObject]) -> None:
    """Each object renamed after its URDF link (Pinocchio's ``<link>_<k>`` where it has several).

    Pinocchio files a link's shapes under the joint that moves it (a fixed base under
    ``universe``, a tool link under the last joint); its frame is the link's own.
    """
    frames = robot.model.frames
    links = [frames[o.parentFrame].name for o in objects]
    for obj, link in zip(objects, links, strict=True):
        if links.count(link) == 1:
            obj.name = link


def _srdf_pairs(srdf: str | Path) -> list[tuple[str, str]]:
    """The ``<disable_collisions link1= link2=/>`` pairs of an SRDF file (or its text)."""
    if not isinstance(srdf, (str, Path)):
        raise InputError(f"srdf must be an SRDF file's path or its XML text; got "
                         f"{describe(srdf)}")
    text = str(srdf)
    if not text.lstrip().startswith("<"):
        path = Path(srdf)
        if not path.is_file():
            raise CellError(f"SRDF file {text!r} does not exist; check the path")
        text = path.read_text(encoding="utf-8")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise CellError(f"the SRDF is not well-formed XML ({exc}); fix it") from None
    pairs = []
    for e in root.iter("disable_collisions"):
        a, b = e.get("link1"), e.get("link2")
        if not a or not b:
            raise CellError(f"SRDF <disable_collisions {e.attrib}> needs link1= and link2=")
        pairs.append((a, b))
    return pairs


def name_pairs(pairs: object, where: str) -> list[tuple[str, str]]:
    """``pairs`` as a list of (str, str).

    Raises:
        InputError: not a sequence of pairs of names.
    """
    items: list[tuple[object, ...]] | None = None
    if isinstance(pairs, Iterable) and not isinstance(pairs, (str, bytes, dict)):
        try:
            items = [tuple(p) for p in pairs]
        except TypeError:
            items = None
    if items is None:
        raise InputError(f"{where} must be a list of (body, body) pairs; got "
                         f"{describe(pairs)}")
    out: list[tuple[str, str]] = []
    for p in items:
        a, b = p if len(p) == 2 else (None, None)
        if not (isinstance(a, str) and isinstance(b, str)):
            raise InputError(f"{where}: each entry must be a pair of body names (str, str); "
                             f"got {p!r}")
        out.append((a, b))
    return out


def check_pair_names(pairs: object, known: dict[str, set[int]], where: str
                     ) -> list[tuple[set[int], set[int]]]:
    """Pairs of body or link names as pairs of body-index sets.

    Raises:
        InputError: not a sequence of pairs of str.
        UnknownBodyError: a name that is no body or link (the message lists them).
    """
    out = []
    for p in name_pairs(pairs, where):
        for n in p:
            if n not in known:
                raise UnknownBodyError(n, known, where)
        out.append((known[p[0]], known[p[1]]))
    return out


def robot_geometry(robot: Robot, *, radius: object = None, srdf: str | Path | None = None,
                   allowed: object = (), missing_mesh: str = "error") -> RobotGeometry:
    """The robot's collision bodies (see the module docstring for the rules).

    Args:
        robot: the robot.
        radius: capsule radius [m] for a robot without ``<collision>``: a number for every
            link, or ``{joint name: radius}``; default the robot file's ``radius`` keys.
        srdf: an SRDF file (or its XML text) whose ``<disable_collisions>`` pairs are not
            checked against each other.
        allowed: more self pairs not to check, ``[(link or body, link or body), ...]``.
        missing_mesh: ``"error"`` (default) or ``"capsule"``: a link whose collision mesh
            cannot be found gets capsules instead (with a logged warning).

    Raises:
        CellError: a link without geometry and without a radius; a radius <= 0; a bad SRDF.
        MeshNotFoundError: a collision mesh that cannot be found (``missing_mesh="error"``).
        UnknownBodyError: a name in ``srdf`` or ``allowed`` that is no link or body.
    """
    robot = check_robot(robot)
    if missing_mesh not in MISSING_MESH:
        raise InputError(f"missing_mesh must be one of {MISSING_MESH}; got {missing_mesh!r}")
    if "<collision" in robot._init_args[0]:
        objects, source = _urdf_bodies(robot, radius, missing_mesh), "URDF <collision>"
    else:
        objects, source = _capsules(robot, radius), "capsules from the kinematics"
    if not objects:
        raise CellError(f"robot {robot.name!r} has no collision body; add <collision> "
                        "elements or radius keys")
    geom = pin.GeometryModel()
    bodies = []
    frames = robot.model.frames
    for obj in objects:
        geom.addGeometryObject(obj)
        points, pad = support_points(obj.geometry, obj.placement)
        if source == "URDF <collision>" and obj.parentFrame < len(frames) and \
                frames[obj.parentFrame].type == pin.FrameType.BODY:
            link = frames[obj.parentFrame].name  # the URDF link it belongs to
        else:  # capsules: their own link's name (a shaft's, less "_shaft")
            link = obj.name.removesuffix("_shaft")
        bodies.append(Body(obj.name, link, int(obj.parentJoint), points, pad))
    known: dict[str, set[int]] = {}
    for i, b in enumerate(bodies):
        known.setdefault(b.name, set()).add(i)
        known.setdefault(b.link, set()).add(i)
    given = check_pair_names(_srdf_pairs(srdf) if srdf is not None else [], known, "SRDF")
    given += check_pair_names(allowed, known, "allowed")
    skipped: dict[tuple[str, str], str] = {}
    candidates = []
    for i in range(len(bodies)):
        for j in range(i + 1, len(bodies)):
            a, b = bodies[i], bodies[j]
            key = (a.name, b.name)
            if abs(a.joint - b.joint) <= 1:
                skipped[key] = "adjacent"
            elif any((i in x and j in y) or (j in x and i in y) for x, y in given):
                skipped[key] = "allowed"
            else:
                candidates.append((i, j))
    pairs = _touching_at_reference(robot, geom, bodies, candidates, skipped)
    return RobotGeometry(robot, geom, tuple(bodies), tuple(pairs), skipped, source)


def _touching_at_reference(robot: Robot, geom: pin.GeometryModel, bodies: list[Body],
                           candidates: list[tuple[int, int]],
                           skipped: dict[tuple[str, str], str]) -> list[tuple[int, int]]:
    """The candidate pairs apart at the reference configuration; the others into ``skipped``."""
    if not candidates:
        return []
    q = reference_configuration(robot)
    data = robot.model.createData()
    gdata = pin.GeometryData(geom)
    pin.updateGeometryPlacements(robot.model, data, geom, gdata, q)
    kept = []
    for i, j in candidates:
        hit = pair_distance(geom, gdata, i, j) <= 0.0
        if hit:
            skipped[(bodies[i].name, bodies[j].name)] = "in contact at the reference configuration"
            log.info("robot %r: self pair %s-%s in contact at the reference configuration %s: "
                     "not checked", robot.name, bodies[i].name, bodies[j].name, q.tolist())
        else:
            kept.append((i, j))
    return kept
