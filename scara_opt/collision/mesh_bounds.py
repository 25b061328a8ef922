r"""Bounds on the distance to a triangle mesh: convex pieces that cover it, and its solid.

A coal ``BVHModel`` is a surface: its exact distance (coal's BVH traversal, a triangle at a
time) costs tens to hundreds of microseconds, and a body inside a closed mesh is reported
*outside* it (the distance to the nearest triangle). :class:`MeshParts` gives the compiled
kernel (:mod:`~scara_opt.collision.edge_kernel`) what it needs to do better:

* **A tree of hulls.** The triangles are cut in two at the median of their centroids
  along the widest axis, each half again, down to groups of at most
  :data:`PIECE_TRIANGLES`; every node of that tree is the convex hull of its triangles'
  vertices (the root: the mesh's hull; the leaves: its *pieces*). A node's hull holds
  its triangles, so for any body *X* and any node *N*,

  .. math:: d(\mathrm{hull}(N), X) \le \min_{t \in N} d(t, X)

  (a distance to a superset is never more; signed, a deeper overlap likewise), and the
  least over the leaves bounds the distance to the whole surface from below. This is the
  lower bound the proofs use: branch and bound down both bodies' trees (convex distances,
  GJK, best first), stopping where the bound is far enough or at two leaves. Where the
  bound is too small to prove anything (within the margin), the kernel asks coal for the
  exact BVH distance instead.
* **The solid.** A closed mesh (watertight, consistently wound) is a solid. A body with no
  point on the surface is either outside or wholly inside; one point tells which. A point
  outside the mesh's convex hull (its half-spaces) is outside; else its generalized
  winding number over the triangles (the sum of their solid angles over 4π) is 1 inside,
  0 outside. An open mesh is a surface only (a cell's :class:`~scara_opt.collision.
  obstacles.Mesh` says so when it is loaded).

Along a motion the proofs need the solid only at the ends: a motion whose surface distance
is proven positive all along never crosses the surface, so it stays on its first
configuration's side.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError

Array = NDArray[np.float64]
Index = NDArray[np.intc]

__all__ = ["MeshParts", "PIECE_TRIANGLES", "is_closed", "mesh_arrays", "mesh_parts",
           "winding_number"]

#: the most triangles in one convex piece (measured on the UR5's collision meshes, 446-1,176
#: triangles a link: see benchmarks/bench_plan.py)
PIECE_TRIANGLES = 24

#: a flat group of triangles gets this thickness [m] on both sides so that it has a hull
#: (it still contains the triangles)
FLAT = 1e-7


@dataclass(frozen=True, eq=False)
class MeshParts:
    """A mesh's triangles, its covering convex pieces, its hull and whether it is a solid.

    All in the mesh's own frame [m].

    Attributes:
        vertices: (n, 3); triangles: (m, 3) indices.
        nodes: the tree of hulls, depth first (the root first): per node ``(points (k, 3),
            triangles (h, 3))``, a convex hull holding its triangles.
        children: (nodes, 2) each node's two children (-1: a leaf, a piece).
        balls: (nodes, 4): a ball holding each node (centre, radius).
        ball: (4,) a ball holding the whole mesh.
        shell: ``(points, triangles)`` of the mesh's convex hull.
        hull: (f, 4) its half-spaces, ``n · x + c <= 0`` inside.
        closed: watertight and consistently wound: a solid.
        point: (3,) a point of the mesh (a vertex): where a body it may be inside is tested.
    """

    vertices: Array
    triangles: NDArray[np.int64]
    nodes: tuple[tuple[Array, NDArray[np.intc]], ...]
    children: NDArray[np.intc]
    balls: Array
    ball: Array
    hull: Array
    closed: bool
    point: Array


def mesh_arrays(shape: object) -> tuple[Array, NDArray[np.int64]]:
    """Vertices (n, 3) [m] and triangles (m, 3) of a coal ``BVHModel``."""
    V = np.asarray(shape.vertices(), float).reshape(-1, 3)  # type: ignore[attr-defined]
    n = int(shape.num_tris)  # type: ignore[attr-defined]
    T = np.empty((n, 3), np.int64)
    for i in range(n):
        t = shape.tri_indices(i)  # type: ignore[attr-defined]
        T[i] = t[0], t[1], t[2]
    return V, T


def _ball(points: Array) -> Array:
    """A ball holding ``points`` (k, 3): the centre of their box, the farthest point."""
    c = (points.min(axis=0) + points.max(axis=0)) / 2
    return np.array([*c, float(np.linalg.norm(points - c, axis=1).max())])


def _hull(points: Array) -> tuple[Array, NDArray[np.intc]]:
    """The convex hull of ``points`` (k, 3): its vertices and triangles (into them).

    Points that span no volume (a flat group) are given :data:`FLAT` on both sides of
    their plane first: the hull of the thickened set still holds them.
    """
    try:
        h = ConvexHull(points)
    except QhullError:
        c = points.mean(axis=0)
        normal = np.linalg.svd(points - c)[2][-1]
        points = np.vstack([points + FLAT * normal, points - FLAT * normal])
        try:
            h = ConvexHull(points)
        except QhullError:  # collinear or a point: a thin box around it
            lo, hi = points.min(axis=0) - FLAT, points.max(axis=0) + FLAT
            points = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                               for z in (lo[2], hi[2])])
            h = ConvexHull(points)
    keep = np.asarray(h.vertices)
    where = np.full(len(points), -1, np.intc)
    where[keep] = np.arange(len(keep), dtype=np.intc)
    return np.ascontiguousarray(points[keep]), np.ascontiguousarray(where[h.simplices])


def _tree(V: Array, T: NDArray[np.int64], most: int
          ) -> tuple[list[NDArray[np.int64]], list[tuple[int, int]]]:
    """The triangles (indices) of every node, depth first, and each node's children.

    A node of more than ``most`` triangles is cut at the median of their centroids along
    the widest axis of those; the others are leaves (children ``(-1, -1)``).
    """
    centres = V[T].mean(axis=1)
    groups: list[NDArray[np.int64]] = []
    children: list[tuple[int, int]] = []

    def grow(idx: NDArray[np.int64]) -> int:
        node = len(groups)
        groups.append(idx)
        children.append((-1, -1))
        if len(idx) > most:
            c = centres[idx]
            axis = int(np.argmax(c.max(axis=0) - c.min(axis=0)))
            order = idx[np.argsort(c[:, axis], kind="stable")]
            half = len(order) // 2
            left = grow(order[:half])
            children[node] = (left, grow(order[half:]))
        return node

    grow(np.arange(len(T)))
    return groups, children


def is_closed(V: Array, T: NDArray[np.int64]) -> bool:
    """Watertight (every edge in two triangles) and consistently wound (opposite ways)."""
    edges = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    if len(directed) != len(edges):  # an edge walked twice the same way
        return False
    return all((b, a) in directed for a, b in directed)


_CACHE: dict[str, MeshParts] = {}


def mesh_parts(shape: object) -> MeshParts:
    """The :class:`MeshParts` of a coal ``BVHModel`` (cached by its vertices and triangles)."""
    V, T = mesh_arrays(shape)
    key = hashlib.sha256(V.tobytes() + T.tobytes()).hexdigest()
    if key in _CACHE:
        return _CACHE[key]
    nodes, balls = [], []
    groups, children = _tree(V, T, PIECE_TRIANGLES)
    for group in groups:
        points = V[np.unique(T[group])]
        nodes.append(_hull(points))
        balls.append(_ball(points))
    hull = ConvexHull(nodes[0][0])
    closed = is_closed(V, T)
    parts = MeshParts(V, T, tuple(nodes), np.array(children, np.intc), np.array(balls),
                      _ball(V), np.ascontiguousarray(hull.equations), closed,
                      V[T[0, 0]].copy())
    _CACHE[key] = parts
    return parts


def winding_number(parts: MeshParts, p: Array) -> float:
    """The generalized winding number of the mesh around the point ``p`` (3,) [-].

    The triangles' solid angles seen from ``p`` (Van Oosterom and Strackee's formula), over
    4π: ±1 inside a closed mesh (the sign its winding gives), 0 outside.
    """
    a, b, c = (parts.vertices[parts.triangles[:, k]] - p for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb
           + np.einsum("ij,ij->i", b, c) * la)
    return float(2.0 * np.arctan2(num, den).sum() / (4.0 * np.pi))
