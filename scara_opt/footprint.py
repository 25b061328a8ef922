"""The base's exclusion zone (a circle or a polygon in the plane of motion) that links must clear.

A robot file may declare it as a ``[footprint]`` table (:class:`Footprint`);
:func:`scara_opt.workspace_analysis.workspace` drops the samples where a checked link
segment, projected on the plane, passes through it, and the closed-form
:meth:`Workspace.contains <scara_opt.workspace_analysis.Workspace.contains>` keeps only
branches that clear it.

The segment test of a circle is written once (:func:`_segment_within`) for both of its
uses: on numpy columns of given chains (:meth:`Footprint.blocks`), and as casadi
expressions inside the compiled FK of the workspace's samples (:meth:`Footprint.kernel`),
which then returns the tip and the verdict without the chain of joint origins in between
(peng2025's 60,000 samples: 14.5 -> 12.5 ms). A polygon is tested on the chains.
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import describe, float_array
from scara_opt.errors import InputError, URDFError
from scara_opt.model import symbolic
from scara_opt.model.batch_fk import kinematic_key
from scara_opt.model.compiled import compiled, source_hash
from scara_opt.model.dh import LENGTH_UNITS
from scara_opt.model.robot import Array, Robot

if TYPE_CHECKING:
    from scara_opt.workspace_analysis import Plane


class _Ops(NamedTuple):
    """The few operations the segment test needs beyond arithmetic, per array kind."""

    where: Callable[..., Any]
    clip: Callable[..., Any]
    any: Callable[[list[Any]], Any]


_NUMPY = _Ops(np.where, np.clip, lambda hits: functools.reduce(np.logical_or, hits))
_CASADI = _Ops(ca.if_else, lambda t, lo, hi: ca.fmin(ca.fmax(t, lo), hi),
               lambda hits: functools.reduce(ca.logic_or, hits))


@dataclass(frozen=True, eq=False)
class Footprint:
    """An exclusion zone in the plane of motion (a circle or a polygon) that links must clear.

    Declared in a robot file as a ``[footprint]`` table, lengths in the file's
    ``length_unit``, coordinates ``(u, v)`` of the plane (world x, y for a vertical SCARA)::

        [footprint]
        shape = "circle"         # or "polygon" with vertices = [[u, v], ...]
        center = [120, 0]
        radius = 190.53
        links_from = "theta2"    # check the segments from this joint's origin to the tip

    The checked segments join consecutive points of :meth:`Robot.joint_origins
    <scara_opt.Robot.joint_origins>` from joint ``links_from`` on (every joint when absent),
    projected on the plane. A segment blocks when it passes through the zone's interior
    (touching the boundary is allowed).

    Attributes:
        shape: ``"circle"`` or ``"polygon"``.
        center: (2,) circle centre [m]; ``radius`` [m].
        vertices: (k, 2) polygon vertices [m], in order (either sense).
        links_from: name of the first joint whose outgoing segment is checked, or ``None``.
    """

    shape: str
    center: Array | None = None
    radius: float = 0.0
    vertices: Array | None = None
    links_from: str | None = None

    def __post_init__(self) -> None:
        if self.links_from is not None and not isinstance(self.links_from, str):
            raise InputError(f"footprint links_from must be a joint name (a str) or None; got "
                             f"{describe(self.links_from)}")
        if self.shape == "circle":
            if self.vertices is not None:
                raise InputError("a circle footprint takes center and radius, not vertices; "
                                 "drop vertices or use shape='polygon'")
            c = _finite(self.center, (2,), "footprint center")
            r = _finite(self.radius, (), "footprint radius")
            if not r > 0:
                raise InputError(f"footprint radius must be a positive length [m]; got "
                                 f"{self.radius!r}")
            object.__setattr__(self, "center", c)
            object.__setattr__(self, "radius", float(r))
        elif self.shape == "polygon":
            if self.center is not None or self.radius != 0.0:
                raise InputError("a polygon footprint takes vertices, not center or radius; "
                                 "drop them or use shape='circle'")
            v = _finite(self.vertices, (None, 2), "footprint vertices")
            if v.shape[0] < 3:
                raise InputError(f"a footprint polygon needs at least 3 vertices [[u, v], ...]; "
                                 f"got {v.shape[0]}")
            object.__setattr__(self, "vertices", v)
        else:
            raise InputError(f"footprint shape must be 'circle' or 'polygon'; got "
                             f"{describe(self.shape)}")

    @classmethod
    def from_robot(cls, robot: Robot) -> Footprint | None:
        """The footprint a robot file declares (its ``[footprint]`` table), or ``None``.

        Raises:
            URDFError: the table is malformed (the message names the entry and the rule).
        """
        table = robot.metadata.get("footprint")
        if table is None:
            return None
        where = f"robot {robot.name!r}: [footprint]"
        length_unit = robot.metadata.get("length_unit")
        unit = LENGTH_UNITS.get(length_unit) if isinstance(length_unit, str) else None
        if not isinstance(table, dict) or unit is None:
            raise URDFError(f"{where} must be a table in a robot file with a length_unit "
                            f"({', '.join(LENGTH_UNITS)})")
        unknown = set(table) - {"shape", "center", "radius", "vertices", "links_from"}
        if unknown:
            raise URDFError(f"{where} has unknown keys {sorted(unknown)}; accepted: shape, "
                            "center, radius (circle), vertices (polygon), links_from")
        try:
            lengths = {key: float_array(table[key], f"footprint {key}") * unit
                       for key in ("center", "radius", "vertices") if key in table}
            r = lengths.get("radius")
            radius = 0.0 if r is None else float(_finite(r, (), "footprint radius"))
            fp = cls(shape=table.get("shape", ""), center=lengths.get("center"), radius=radius,
                     vertices=lengths.get("vertices"),
                     links_from=table.get("links_from"))
            fp.first_origin(robot)
        except InputError as exc:
            raise URDFError(f"{where}: {exc}; fix the robot file") from None
        return fp

    def first_origin(self, robot: Robot) -> int:
        """Index into ``robot.joint_origins`` of the first checked point.

        Raises:
            InputError: ``links_from`` is not a joint of ``robot`` (lists the joints).
        """
        if self.links_from is None:
            return 0
        if self.links_from not in robot.joint_names:
            raise InputError(f"footprint links_from = {self.links_from!r} is not a joint of "
                             f"robot {robot.name!r}; joints: {robot.joint_names}")
        return robot.joint_names.index(self.links_from)

    def blocks_arms(self, robot: Robot, plane: Plane, chain: Array) -> NDArray[np.bool_]:
        """:meth:`blocks` of world chains: (n,) True where an arm passes through the zone.

        ``chain``: (n, k, 3) [m] joint origins and tip (:meth:`Robot.joint_origins
        <scara_opt.Robot.joint_origins>`); only the checked points, from
        :meth:`first_origin` on, are put into ``plane``'s coordinates (for a circle as
        ``Plane.columns``, point by point).
        """
        first = self.first_origin(robot)
        if self.shape == "circle":
            return self._circle_hits([plane.columns(chain[:, k])
                                      for k in range(first, chain.shape[1])])
        return self.blocks(plane.coords(chain[:, first:]))

    def blocks(self, chain_uv: Array, first: int = 0) -> NDArray[np.bool_]:
        """Which arms pass through the zone.

        Args:
            chain_uv: (n, k, 2) plane coordinates [m] of each arm's joint origins and tip.
            first: index of the first checked point (see :meth:`first_origin`).

        Returns:
            (n,) True where a segment between consecutive checked points enters the zone.
        """
        pts = chain_uv[:, first:]
        if self.shape == "circle":
            return self._circle_hits([(pts[:, k, 0], pts[:, k, 1]) for k in range(pts.shape[1])])
        A, B = (pts, pts) if pts.shape[1] == 1 else (pts[:, :-1], pts[:, 1:])  # (n, m, 2)
        hit = _segments_hit_polygon(A.reshape(-1, 2), B.reshape(-1, 2), self._polygon())
        return np.asarray(hit.reshape(chain_uv.shape[0], -1).any(axis=1))

    def _circle_hits(self, ends: list[tuple[Any, Any]], ops: _Ops = _NUMPY) -> Any:
        """True where a segment between consecutive ``ends`` enters the circle.

        ``ends``: the checked points' (u, v) [m]: numpy columns (n,) (then (n,) bools), or
        casadi expressions (``ops=_CASADI``: then one expression, 1 or 0). Segment by
        segment: no (n, m, 2) copies.
        """
        pairs = list(zip(ends[:-1], ends[1:], strict=True)) or [(ends[0], ends[0])]
        # one checked point: the segment from it to itself
        return ops.any([_segment_within(*a, *b, self._circle(), self.radius, ops)
                        for a, b in pairs])

    def kernel(self, robot: Robot, plane: Plane) -> ca.Function | None:
        """For a circle, the compiled FK with :meth:`blocks_arms`' test; ``None`` for a polygon.

        ``q (nq,) -> rows (4,)``: the tip position [m], then 1 where the arm passes through
        the zone, 0 where it clears: the test as casadi expressions of the joint origins,
        compiled with the FK once per machine (:mod:`scara_opt.model.compiled`). Evaluate
        it with :func:`scara_opt.model.batch_fk.evaluate_function`.
        """
        if self.shape != "circle":
            return None
        first = self.first_origin(robot)
        spec = repr((kinematic_key(robot), plane.e1.tolist(), plane.e2.tolist(),
                     self._circle().tolist(), self.radius, first))
        digest = hashlib.sha256(spec.encode()).hexdigest()[:12]
        cache: dict[str, ca.Function] = robot.__dict__.setdefault("_footprint_kernels", {})
        if digest not in cache:
            name = f"scara_opt_footprint_{digest}"

            def build() -> ca.Function:
                q = ca.SX.sym("q", robot.nq)
                origins, p, _ = symbolic.chain_walk(robot.chain, robot.tip_placement, q)
                ends = [(_sx_along(o, plane.e1), _sx_along(o, plane.e2))
                        for o in [*origins, p][first:]]
                rows = ca.vertcat(ca.simplify(p), self._circle_hits(ends, _CASADI))
                return ca.Function(name, [q], [ca.cse(rows)], ["q"], ["rows"])

            cache[digest] = compiled(name, f"{spec} {_CODE}", build)
        return cache[digest]

    def outline(self) -> Array:
        """Closed outline (m, 2) [m] of the zone, for plots."""
        if self.shape == "circle":
            t = np.linspace(0.0, 2 * np.pi, 181)
            return self._circle() + self.radius * np.column_stack([np.cos(t), np.sin(t)])
        V = self._polygon()
        return np.vstack([V, V[:1]])

    def _circle(self) -> Array:
        """The centre (2,) [m] of a circle footprint (``__post_init__`` has checked it)."""
        assert self.center is not None, "a circle footprint always has a center"
        return self.center

    def _polygon(self) -> Array:
        """The vertices (k, 2) [m] of a polygon footprint (``__post_init__`` has checked them)."""
        assert self.vertices is not None, "a polygon footprint always has vertices"
        return self.vertices


def _finite(value: object, shape: tuple[int | None, ...], what: str) -> Array:
    try:
        arr = float_array(value, what)
    except InputError:
        arr = np.array(np.nan)
    ok = arr.ndim == len(shape) and all(s is None or s == d
                                        for s, d in zip(shape, arr.shape, strict=True))
    if not ok or not np.isfinite(arr).all():
        wants: dict[tuple[int | None, ...], str] = {(): "() (a number)", (2,): "(2,) [u, v]"}
        want = wants.get(shape, "(k, 2) [[u, v], ...]")
        raise InputError(f"{what} must be finite numbers of shape {want} [m]; got {value!r}")
    return arr


def _segment_within(ax: Any, ay: Any, bx: Any, by: Any, c: Array, radius: float,
                    ops: _Ops = _NUMPY) -> Any:
    """Which segments (ax, ay)–(bx, by) pass nearer than ``radius`` to ``c`` (2,) [m].

    The squared distance from the centre to the segment's nearest point against the squared
    radius (no square root). On numpy columns (n,) (then (n,) bools), or on casadi
    expressions with ``ops=_CASADI`` (then 1 or 0): the same operations, in the same order.
    """
    c0, c1 = float(c[0]), float(c[1])
    ax, ay = ax - c0, ay - c1  # relative to the centre
    dx, dy = bx - c0 - ax, by - c1 - ay
    L2 = dx * dx + dy * dy
    t = ops.clip(-(ax * dx + ay * dy) / ops.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    ex, ey = ax + t * dx, ay + t * dy  # the nearest point, relative to the centre
    return ex * ex + ey * ey < radius * radius


def world_axis(e: Array) -> int | None:
    """The index of the world axis that the unit vector ``e`` (3,) is (+x, +y or +z), or None.

    Along it a point's coordinate is its own entry, no arithmetic
    (``workspace_analysis.Plane.columns``, :func:`_sx_along`).
    """
    k = np.flatnonzero(e)
    return int(k[0]) if len(k) == 1 and e[k[0]] == 1.0 else None


def _sx_along(point: ca.SX, e: Array) -> ca.SX:
    """The coordinate of a symbolic point (3,) along ``e`` (3,).

    Its entry on :func:`world_axis`, else the dot product.
    """
    axis = world_axis(e)
    return ca.dot(ca.DM(e), point) if axis is None else point[axis]


#: the source the kernels are built from: part of the compiled cache's key
_CODE = source_hash(Path(__file__), symbolic.__file__)


def _cross(a: Array, b: Array) -> Array:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _inside_polygon(P: Array, V: Array) -> NDArray[np.bool_]:
    """Even-odd rule: which points P (s, 2) lie inside polygon V (k, 2)."""
    W = np.roll(V, -1, axis=0)
    y = P[:, 1:2]
    spans = (V[:, 1] > y) != (W[:, 1] > y)  # (s, k): the edge crosses the horizontal line
    dy = np.where(W[:, 1] != V[:, 1], W[:, 1] - V[:, 1], 1.0)
    x_cross = V[:, 0] + (y - V[:, 1]) * (W[:, 0] - V[:, 0]) / dy
    return (spans & (P[:, 0:1] < x_cross)).sum(axis=1) % 2 == 1


def _segments_hit_polygon(A: Array, B: Array, V: Array) -> NDArray[np.bool_]:
    """Which segments A[i]–B[i] (s, 2) enter polygon V (k, 2): an end inside or a crossing."""
    C, D = V[None], np.roll(V, -1, axis=0)[None]
    d = (B - A)[:, None]
    o1, o2 = _cross(d, C - A[:, None]), _cross(d, D - A[:, None])
    o3, o4 = _cross(D - C, A[:, None] - C), _cross(D - C, B[:, None] - C)
    crossing = ((o1 * o2) < 0) & ((o3 * o4) < 0)
    return _inside_polygon(A, V) | _inside_polygon(B, V) | crossing.any(axis=1)
