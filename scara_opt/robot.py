"""The :class:`Robot`: a serial URDF chain loaded into Pinocchio, with FK and Jacobians.

Pinocchio is the numeric source of truth (:meth:`Robot.fk`, :meth:`Robot.jacobian`).
For batches, :meth:`Robot.fk_batch` walks the same model tree with numpy, and
:attr:`Robot.symbolic_fk` builds the casadi expression from it; both are tested
against Pinocchio.
"""

from __future__ import annotations

import copy
import io
import logging
import math
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.errors import (
    FrameNotFoundError,
    InputError,
    JointLimitError,
    RobotNotFoundError,
    TargetError,
    URDFError,
)

if TYPE_CHECKING:
    import casadi

    from scara_opt.dh import DHRobot

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class ChainJoint:
    """One movable joint of the chain, as Pinocchio stores it.

    Attributes:
        name: joint name.
        kind: ``"revolute"`` or ``"prismatic"``.
        axis: unit axis (3,) in the joint frame.
        placement: 4×4 placement of the joint frame in the parent joint's frame [m].
    """

    name: str
    kind: str
    axis: Array
    placement: Array


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


def _check_xml(text: str, where: str) -> None:
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise URDFError(f"{where} is not well-formed XML ({exc}); fix the file") from None
    if root.tag != "robot":
        raise URDFError(f"{where}: the root element is <{root.tag}>, a URDF needs <robot>")


def _tree(urdf, where: str) -> tuple[dict[str, object], str]:
    """Joints by child link, and the root link; checks the joint types."""
    by_child: dict[str, object] = {}
    for j in urdf.robot.joints:
        if j.type not in ("revolute", "prismatic", "fixed"):
            raise URDFError(
                f"{where}: joint {j.name!r} is {j.type!r}; only revolute, prismatic and fixed "
                "joints are supported (give a continuous joint limits and type revolute)"
            )
        if j.mimic is not None:
            raise URDFError(f"{where}: joint {j.name!r} is a mimic joint, which is not supported")
        if j.type != "fixed":
            lim = j.limit
            if lim is None or lim.lower is None or lim.upper is None:
                raise URDFError(
                    f"{where}: joint {j.name!r} has no <limit lower= upper=>; add its range"
                )
            if not (math.isfinite(lim.lower) and math.isfinite(lim.upper)):
                raise JointLimitError(f"{where}: joint {j.name!r} has non-finite limits", j.name)
            if not lim.lower < lim.upper:
                raise JointLimitError(
                    f"{where}: joint {j.name!r} has lower limit {lim.lower} >= upper limit "
                    f"{lim.upper}; swap them or fix the URDF",
                    j.name,
                )
        by_child[j.child] = j
    roots = [lk.name for lk in urdf.robot.links if lk.name not in by_child]
    if len(roots) != 1:
        raise URDFError(f"{where}: expected one root link, found {roots}; the URDF must be a tree")
    return by_child, roots[0]


def _chain_to_tip(urdf, tip: str | None, where: str) -> str:
    """Check that the URDF is one serial chain from the root to ``tip``; return ``tip``."""
    by_child, root = _tree(urdf, where)
    links = [lk.name for lk in urdf.robot.links]
    parents = {j.parent for j in urdf.robot.joints}
    leaves = [name for name in links if name not in parents]
    if tip is None:
        if len(leaves) != 1:
            raise URDFError(
                f"{where}: the URDF branches into several end links {leaves}; a serial chain "
                "is needed: remove the branches or pass tip= (still every joint must lie on "
                "the path to it)"
            )
        tip = leaves[0]
    if tip not in links:
        raise FrameNotFoundError(tip, links)
    on_path, link = set(), tip
    while link != root:
        j = by_child[link]
        on_path.add(j.name)
        link = j.parent
    off = [j.name for j in urdf.robot.joints if j.name not in on_path and j.type != "fixed"]
    if off:
        raise URDFError(
            f"{where}: movable joints {off} are not on the path from {root!r} to the tip "
            f"{tip!r}: the URDF branches or continues past the tip; only a serial chain ending "
            "at the tip is supported: remove those joints or pick another tip"
        )
    return tip


def _accelerations(text: str) -> dict[str, float]:
    """The ``<scara_opt acceleration=…/>`` extension written by :mod:`scara_opt.dh`."""
    out = {}
    for joint in ET.fromstring(text).iter("joint"):
        ext = joint.find("scara_opt")
        if ext is not None and ext.get("acceleration") is not None:
            out[joint.get("name", "")] = float(ext.get("acceleration"))
    return out


class Robot:
    """A serial chain of revolute/prismatic joints (fixed joints in between) and a tip frame.

    Attributes:
        name: robot name (the URDF's, or the bundled robot's).
        model: the Pinocchio model; ``data`` its workspace.
        tip: name of the tip frame whose pose :meth:`fk` returns.
        chain: the movable joints in order, read from the Pinocchio model.
        tip_placement: 4×4 placement of the tip in the last joint's frame [m].
        source: where the robot comes from (paper, file path).
        metadata: extra data of a robot file (for bundled robots: the whole parsed TOML,
            e.g. a ``[footprint]`` table); empty for a plain URDF.
    """

    def __init__(self, urdf_text: str, tip: str | None = None, *, name: str | None = None,
                 where: str = "URDF", source: str = "", notes: str = "",
                 mesh_dir: str | None = None, metadata: dict | None = None) -> None:
        import yourdfpy

        _check_xml(urdf_text, where)
        self._init_args = (urdf_text, tip, name, where, source, notes, mesh_dir)
        try:
            urdf = yourdfpy.URDF.load(
                io.BytesIO(urdf_text.encode()), build_scene_graph=False, load_meshes=False,
                build_collision_scene_graph=False, load_collision_meshes=False,
                mesh_dir=mesh_dir or "",
            )
        except Exception as exc:  # yourdfpy raises bare KeyError/ValueError on bad structure
            raise URDFError(f"{where} is not a valid URDF: {type(exc).__name__}: {exc}") from None
        self.tip = _chain_to_tip(urdf, tip, where)
        try:
            self.model: pin.Model = pin.buildModelFromXML(urdf_text)
        except (RuntimeError, ValueError) as exc:
            raise URDFError(f"Pinocchio could not build {where}: {exc}") from None
        self.data: pin.Data = self.model.createData()
        self.name = name or urdf.robot.name
        self.source = source or where
        self.notes = notes
        self.metadata: dict = dict(metadata or {})
        if not self.model.existFrame(self.tip):
            raise FrameNotFoundError(self.tip, [f.name for f in self.model.frames])
        self.tip_id = self.model.getFrameId(self.tip)
        self.chain: tuple[ChainJoint, ...] = tuple(
            ChainJoint(self.model.names[j], *_joint_kind(self.model.joints[j]),
                       self.model.jointPlacements[j].homogeneous.copy())
            for j in range(1, self.model.njoints)
        )
        if not self.chain:
            raise URDFError(f"{where} has no movable joint; IK and trajectories need at least one")
        self.tip_placement: Array = self.model.frames[self.tip_id].placement.homogeneous.copy()
        acc = _accelerations(urdf_text)
        self._acceleration = np.array([acc.get(j.name, np.inf) for j in self.chain])
        vel = np.array(self.model.velocityLimit, float)
        if np.any(vel <= 0):
            log.warning("%s: joints with velocity limit <= 0 are treated as unlimited", where)
            vel = np.where(vel > 0, vel, np.inf)
        self._velocity = vel

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_urdf(cls, path: str | Path, tip: str | None = None) -> Robot:
        """Load a URDF file.

        Args:
            path: path to a ``.urdf`` file.
            tip: name of the tip link or frame; ``None`` takes the chain's last link.

        Raises:
            URDFError: missing file, malformed XML, not a serial chain, unsupported joint.
            FrameNotFoundError: ``tip`` is not a link of the URDF (the message lists them).
            JointLimitError: a joint's lower limit is not below its upper limit.
        """
        path = Path(path)
        if not path.is_file():
            raise URDFError(f"URDF file {str(path)!r} does not exist; check the path")
        return cls(path.read_text(), tip, where=f"URDF {str(path)!r}", mesh_dir=str(path.parent))

    @classmethod
    def from_dh(cls, dh: DHRobot, tip: str | None = "tool") -> Robot:
        """Build a robot from a DH table (see :mod:`scara_opt.dh`)."""
        from scara_opt.dh import dh_to_urdf

        return cls(dh_to_urdf(dh), tip, name=dh.name, where=f"robot {dh.name!r}",
                   source=dh.source, notes=dh.notes)

    # ------------------------------------------------------------------ properties
    @property
    def nq(self) -> int:
        """Number of joint coordinates."""
        return len(self.chain)

    @property
    def joint_names(self) -> list[str]:
        """Joint names in the order of ``q``."""
        return [j.name for j in self.chain]

    @property
    def joint_types(self) -> list[str]:
        """``"revolute"`` or ``"prismatic"`` per joint."""
        return [j.kind for j in self.chain]

    @property
    def lower(self) -> Array:
        """Lower joint limits (nq,) [rad or m]."""
        return np.array(self.model.lowerPositionLimit, float)

    @property
    def upper(self) -> Array:
        """Upper joint limits (nq,) [rad or m]."""
        return np.array(self.model.upperPositionLimit, float)

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

        Example: ``robot.with_limits(z0=(-0.005, 0.040))`` widens peng2025's stroke.

        Raises:
            JointLimitError: unknown joint, non-finite values, or lower >= upper.
        """
        new = copy.copy(self)
        new.model = pin.Model(self.model)
        new.data = new.model.createData()
        new.__dict__.pop("_ik_nlp_cache", None)
        new.__dict__.pop("_scara_geometry", None)
        lower, upper = new.model.lowerPositionLimit.copy(), new.model.upperPositionLimit.copy()
        for name, value in ranges.items():
            if name not in self.joint_names:
                raise JointLimitError(f"with_limits: no joint named {name!r}; joints: "
                                      f"{self.joint_names}", joint=name)
            try:
                lo, hi = (float(v) for v in value)
            except (TypeError, ValueError):
                raise JointLimitError(f"with_limits: {name} needs a (lower, upper) pair; got "
                                      f"{value!r}", joint=name) from None
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise JointLimitError(
                    f"with_limits: joint {name!r} range ({lo}, {hi}) is not finite with lower < "
                    "upper; pass (lower, upper) in rad or m", joint=name)
            k = self.joint_names.index(name)
            lower[k], upper[k] = lo, hi
        new.model.lowerPositionLimit, new.model.upperPositionLimit = lower, upper
        return new

    def __repr__(self) -> str:
        joints = ", ".join(f"{j.name}:{j.kind[0].upper()}" for j in self.chain)
        return f"Robot({self.name!r}, nq={self.nq}, joints=[{joints}], tip={self.tip!r})"

    # ------------------------------------------------------------------ input checks
    def check_q(self, q: object, name: str = "q") -> Array:
        """Return ``q`` as a float array of shape (nq,), or raise :class:`InputError`."""
        try:
            arr = np.asarray(q, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be numeric, one value per joint "
                             f"{self.joint_names}; got {q!r}") from None
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
            arr = np.asarray(Q, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be a numeric array of shape (n, {self.nq})") from None
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
        """Whether ``q`` (nq,) — or each row of (n, nq) — lies within [lower - tol, upper + tol]."""
        arr = np.asarray(q, dtype=float)
        arr = self.check_q(arr) if arr.ndim == 1 else self.check_q_batch(arr)
        ok = np.all((arr >= self.lower - tol) & (arr <= self.upper + tol), axis=-1)
        return bool(ok) if arr.ndim == 1 else ok

    # ------------------------------------------------------------------ kinematics
    def fk(self, q: object) -> Array:
        """Tip pose (4×4 homogeneous matrix, world frame, [m]) at ``q`` (nq,), by Pinocchio."""
        qa = self.check_q(q)
        pin.forwardKinematics(self.model, self.data, qa)
        return pin.updateFramePlacement(self.model, self.data, self.tip_id).homogeneous.copy()

    def position(self, q: object) -> Array:
        """Tip position (3,) [m] at ``q``."""
        return self.fk(q)[:3, 3]

    def jacobian(self, q: object) -> Array:
        """Tip Jacobian (6, nq): rows ``[v; ω]`` in the world-aligned frame at the tip."""
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
        R, p = self._fk_batch_rp(Qa)
        out = np.zeros((Qa.shape[0], 4, 4))
        out[:, :3, :3] = R
        out[:, :3, 3] = p
        out[:, 3, 3] = 1.0
        return out

    def positions(self, Q: object) -> Array:
        """Tip positions (n, 3) [m] for ``Q`` (n, nq); the batch form of :meth:`position`."""
        return self._fk_batch_rp(self.check_q_batch(Q))[1]

    def joint_origins(self, Q: object) -> Array:
        """World positions (n, nq + 1, 3) [m] of every joint frame's origin, then the tip.

        For drawing the arm as a stick figure and checking links against obstacles.
        """
        Qa = self.check_q_batch(Q)
        frames: list[Array] = []
        p = self._fk_batch_rp(Qa, frames)[1]
        return np.stack([f.T for f in frames] + [p], axis=1)

    def _fk_batch_rp(self, Q: Array, frames: list[Array] | None = None) -> tuple[Array, Array]:
        # R is kept as its three columns, each (3, n), so every step is a few fused
        # elementwise operations over the batch instead of stacked 3×3 products.
        n = Q.shape[0]
        cols = [np.tile(e[:, None], (1, n)) for e in np.eye(3)]
        p = np.zeros((3, n))
        for k, j in enumerate(self.chain):
            p = p + _combine(cols, j.placement[:3, 3])
            if frames is not None:
                frames.append(np.broadcast_to(p, (3, n)))
            cols = _rotate_const(cols, j.placement[:3, :3])
            q = Q[:, k]
            if j.kind == "prismatic":
                p = p + _combine(cols, j.axis) * q
            else:
                cols = _rotate_var(cols, j.axis, q)
        p = p + _combine(cols, self.tip_placement[:3, 3])
        cols = _rotate_const(cols, self.tip_placement[:3, :3])
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
        pin.forwardKinematics(self.model, self.data, q0)
        axes = [self.data.oMi[k + 1].rotation @ j.axis
                for k, j in enumerate(self.chain) if j.kind == "revolute"]
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
        """Orthonormal (e1, e2) spanning the plane normal to :attr:`yaw_axis`, e1 × e2 = axis."""
        n = self.yaw_axis
        if n is None:
            raise TargetError(
                f"robot {self.name!r} has no single tool-angle axis (its revolute axes are not "
                "all parallel); give a full rotation= instead of yaw="
            )
        ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = ref - (ref @ n) * n
        e1 /= np.linalg.norm(e1)
        return e1, np.cross(n, e1)


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


def _combine(cols: list[Array], w: Array) -> Array | float:
    """Σ_i cols[i] · w[i] for a constant (3,) vector ``w``, skipping zero entries."""
    out: Array | float = 0.0
    for c, wi in zip(cols, w, strict=True):
        if wi != 0.0:
            out = out + (c if wi == 1.0 else c * wi)
    return out


def _rotate_const(cols: list[Array], Rf: Array) -> list[Array]:
    """Columns of R @ Rf for a constant 3×3 ``Rf``."""
    if np.array_equal(Rf, np.eye(3)):
        return cols
    return [_combine(cols, Rf[:, j]) for j in range(3)]  # type: ignore[misc]


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
        RobotNotFoundError: neither a bundled name nor an existing file (lists the names).
        URDFError: the file is malformed (see :meth:`Robot.from_urdf`).
    """
    from scara_opt.dh import bundled_dir, load_dh

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
