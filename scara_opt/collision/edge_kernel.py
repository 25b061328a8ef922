"""The proofs' inner loops compiled: coal's distances with no Python between two states.

:class:`~scara_opt.planning.ompl_backend.EdgeProver` spent most of a planning query
splitting edges: at each midpoint it placed the bodies (Pinocchio) and asked coal for the
distance of each open pair, ~2 µs of Python call per pair around ~0.5 µs of coal's work.
``edge_kernel.cpp`` runs the same loops in C++ against coal's own library (the one the
``pin`` wheel installs), each with the same rule, the same intervals in the same order and
the same counts as its Python form, which stays as the reference the tests hold it to:

* :class:`NativeProver`: ``EdgeProver``'s states and edges (the per-state cache, the rule
  from the two ends, a SCARA's height spans, the split middle first);
* :meth:`EdgeKernel.prove_path`: :func:`~scara_opt.collision.continuous.check_path`
  (``locate=False``), the proof of the spline a planned move is timed along;
* :meth:`EdgeKernel.batch` and :meth:`EdgeKernel.collides`: the checker's batches of
  distances and of contact tests (per pair coal's distance functor, every call started
  afresh: no GJK guess carried from an earlier query; a contact is a signed distance
  below the margin, a pair skipped only when the balls holding its bodies are farther
  apart than that).

The robot's bodies are placed by a compiled casadi Function of their world placements
(:func:`~scara_opt.model.symbolic.chain_walk`'s frames times each body's placement in its
joint frame: Pinocchio's ``oMg``). It is built once per machine like every native kernel
(:mod:`scara_opt.model.compiled`: the cache, the checks, ``SCARA_OPT_NO_COMPILE``), with
coal's headers and library from the ``pin`` wheel's prefix and Eigen's headers from
casadi's wheel. Where any piece is missing (no compiler, no headers, a body that is not a
sphere, box, capsule, cylinder or triangle mesh), :func:`edge_kernel` returns ``None`` and
the Python forms run: the same verdicts, slower.

**Meshes** (coal's ``BVHModel``: a URDF's ``<collision>`` meshes, a cell's STL fixtures)
go in with their tree of convex hulls (:mod:`~scara_opt.collision.mesh_bounds`): the
proofs take the trees' best-first lower bound on the surface distance (microseconds),
coal's exact BVH distance only where that bound is within the margin; a contact test first
asks coal's own collision test (trusted where it finds the surfaces meeting), then the
bounds; a body inside a closed mesh is a contact. For a pair with a mesh, the kernel's
proofs are as sound as the Python form's but not step for step the same (the Python form
takes the exact distances): the same verdicts at rest, other counts along a motion.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from scara_opt.collision.mesh_bounds import MeshParts, mesh_parts
from scara_opt.model import symbolic
from scara_opt.model.batch_fk import kinematic_key
from scara_opt.model.compiled import c_library, compiled, library_path, source_hash

if TYPE_CHECKING:
    from scara_opt.collision.checker import CollisionChecker

Array = NDArray[np.float64]

__all__ = ["EdgeKernel", "NativeProver", "edge_kernel", "shape_code"]

SOURCE = Path(__file__).with_name("edge_kernel.cpp")

_P, _I, _D = ctypes.c_void_p, ctypes.c_int, ctypes.c_double

#: the kinds of distance the kernel's batch gives (EdgeKernel.batch)
KINDS = {"bound": 0, "exact": 1, "rest": 2}
_IP, _DP = ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_double)


def shape_code(shape: Any) -> tuple[int, tuple[float, float, float]] | None:
    """The kernel's code and parameters of a coal shape, or ``None`` (not supported).

    0 sphere (radius), 1 box (full sides), 2 capsule and 3 cylinder (radius, full length)
    [m]: the arguments coal's constructors take; 4 a triangle mesh (a ``BVHModel``: its
    parts go in by ``edge_kernel_add_mesh``).
    """
    import coal

    if isinstance(shape, coal.BVHModelBase):
        return 4, (0.0, 0.0, 0.0)
    if isinstance(shape, coal.Sphere):
        return 0, (float(shape.radius), 0.0, 0.0)
    if isinstance(shape, coal.Box):
        x, y, z = (2.0 * np.asarray(shape.halfSide, float)).tolist()
        return 1, (x, y, z)
    if isinstance(shape, coal.Capsule):
        return 2, (float(shape.radius), 2.0 * float(shape.halfLength), 0.0)
    if isinstance(shape, coal.Cylinder):
        return 3, (float(shape.radius), 2.0 * float(shape.halfLength), 0.0)
    return None


@functools.lru_cache(maxsize=1)
def build_arguments() -> tuple[str, ...] | str:
    """The compiler's arguments for coal and Eigen (folders, libraries), or why none.

    coal's headers and ``libcoal.so`` sit in the prefix the ``pin`` wheel installs (the
    folder above coal's Python package holding ``include/coal``); Eigen's headers in that
    prefix or in casadi's wheel (``casadi/include/eigen3``).
    """
    import coal

    prefix = next((p for p in Path(coal.__file__).resolve().parents
                   if (p / "include" / "coal" / "distance.h").is_file()
                   and any((p / "lib").glob("libcoal.so*"))), None)
    if prefix is None:
        return f"coal's headers and library were not found above {coal.__file__}"
    eigen = [p for p in (prefix / "include" / "eigen3",
                         Path(ca.__file__).parent / "include" / "eigen3")
             if (p / "Eigen" / "Core").is_file()]
    if not eigen:
        return "Eigen's headers were not found (in coal's prefix or casadi's wheel)"
    lib = prefix / "lib"
    return (f"-I{prefix / 'include'}", f"-I{eigen[0]}", "-DCOAL_HAS_OCTOMAP", f"-L{lib}",
            "-lcoal", f"-Wl,-rpath,{lib}")


@functools.lru_cache(maxsize=1)
def _library() -> ctypes.CDLL | None:
    """The compiled kernel, its functions' signatures set, or ``None`` (the Python form)."""
    lib = c_library(SOURCE, build_arguments)  # headers looked for only when compiling
    if lib is None:
        return None
    if lib.edge_kernel_casadi_int_size() != ctypes.sizeof(ctypes.c_longlong):
        return None  # pragma: no cover - casadi's default integer
    lib.edge_kernel_new.argtypes = [_I, _P, _I, _I, _I, _I, _IP, _DP, _DP, _IP, _D, _D]
    lib.edge_kernel_new.restype = _P
    lib.edge_kernel_add_mesh.argtypes = [_P, _I, _I, _DP, _I, _IP, _I, _IP, _DP, _IP, _IP, _DP,
                                         _DP, _I, _DP, _I, _DP]
    lib.edge_kernel_add_mesh.restype = _I
    lib.edge_kernel_pairs.argtypes = [_P, _I, _IP]
    lib.edge_kernel_free.argtypes = [_P]
    lib.edge_kernel_batch.argtypes = [_P, _P, _I, _P, _I, _I, _P]
    lib.edge_kernel_collides.argtypes = [_P, _P, _I, _P]
    lib.edge_kernel_prove_path.argtypes = [_P, _I, _I, _P, _P, _P, _P, _P, _P, _P, _D,
                                           ctypes.c_longlong, _P]
    lib.edge_kernel_prove_path.restype = _I
    lib.edge_prover_new.argtypes = [_P, _P, _P, _P, _P]
    lib.edge_prover_new.restype = _P
    lib.edge_prover_free.argtypes = [_P]
    lib.edge_prover_state.argtypes = [_P, _P, _P, _P]
    lib.edge_prover_state.restype = _I
    lib.edge_prover_edge.argtypes = [_P, _P, _P, _D, _P]
    lib.edge_prover_edge.restype = _I
    return lib


def _rows(placement: Any) -> list[float]:
    """A pinocchio SE3 as the kernel's 12 numbers: rotation row by row, then translation."""
    return [*np.asarray(placement.rotation, float).ravel().tolist(),
            *np.asarray(placement.translation, float).tolist()]


def _placements(checker: CollisionChecker, moving: list[int]) -> ca.Function | None:
    """The compiled Function ``q -> 12 numbers per moving body`` (world R row-major, p)."""
    robot, objects = checker.robot, checker.model.geometryObjects
    spec = hashlib.sha256(repr([(objects[g].parentJoint, _rows(objects[g].placement))
                                for g in moving]).encode()).hexdigest()
    name = f"scara_opt_bodies_{spec[:8]}_{kinematic_key(robot)[:8]}"

    def build() -> ca.Function:
        q = ca.SX.sym("q", robot.nq)
        frames: list[tuple[ca.SX, ca.SX]] = []
        symbolic.chain_walk(robot.chain, robot.tip_placement, q, frames)
        rows = []
        for g in moving:
            R, p = frames[objects[g].parentJoint - 1]
            M = objects[g].placement
            Rg = R @ ca.DM(np.asarray(M.rotation, float))
            rows += [ca.reshape(Rg.T, 9, 1), p + R @ ca.DM(np.asarray(M.translation, float))]
        return ca.Function(name, [q], [ca.cse(ca.vertcat(*rows))], ["q"], ["rows"])

    code = source_hash(symbolic.__file__, __file__)  # a change to either builds anew
    f = compiled(name, f"{spec} {kinematic_key(robot)} {code}", build)
    return f if library_path(name) is not None else None


class EdgeKernel:
    """A checker's compiled kernel (one per thread: it holds the placed bodies).

    Attributes:
        nq, npairs: the robot's joints and the checker's pairs.
    """

    def __init__(self, lib: ctypes.CDLL, checker: CollisionChecker, f: ca.Function,
                 entry: Any, moving: list[int], shift: float) -> None:
        objects = checker.model.geometryObjects
        codes = [shape_code(o.geometry) for o in objects]
        slot = {g: k for k, g in enumerate(moving)}
        types = np.array([c[0] for c in codes if c is not None], np.intc)
        params = np.array([c[1] for c in codes if c is not None], float)
        fixed = np.array([_rows(o.placement) for o in objects], float)
        slots = np.array([slot.get(g, -1) for g in range(len(objects))], np.intc)
        pairs = np.ascontiguousarray(checker.pairs, np.intc)
        self._lib = lib
        self._handle = lib.edge_kernel_new(
            checker.robot.nq, entry[0], f.sz_iw(), f.sz_w(), len(moving), len(objects),
            _ip(types), _dp(params), _dp(fixed), _ip(slots), shift, checker.margin)
        for g, o in enumerate(objects):
            if types[g] == 4:
                _add_mesh(lib, self._handle, g, mesh_parts(o.geometry))
        lib.edge_kernel_pairs(self._handle, len(pairs), _ip(pairs))
        self.nq, self.npairs = checker.robot.nq, len(pairs)
        self._open = np.zeros(self.npairs, np.intc)  # the pairs asked for by batch
        self._batch, self._prove_path = lib.edge_kernel_batch, lib.edge_kernel_prove_path
        self._collides = lib.edge_kernel_collides
        self.path_pairs = 0  # the last prove_path's pair distances at middles

    def __del__(self) -> None:
        handle = getattr(self, "_handle", None)
        if handle:
            self._lib.edge_kernel_free(handle)

    def batch(self, Q: Array, cols: list[int] | None = None, kind: str = "exact") -> Array:
        """Signed distances (n, len(cols)) [m] of pairs ``cols`` (None: all) at rows ``Q``.

        ``kind``: ``"exact"`` as reported; ``"bound"`` what a proof takes inside a motion (a
        lower bound: for a pair with a mesh, its tree of hulls' where above the margin and
        tolerance); ``"rest"`` at a motion's start (the bound, and a contact where a body
        lies inside a closed mesh). The same for primitives.
        """
        Q = np.ascontiguousarray(Q, float)
        n = len(cols) if cols is not None else self.npairs
        out = np.empty((len(Q), n))
        if cols is not None:
            self._open[:n] = cols
        self._batch(self._handle, Q.ctypes.data, len(Q),
                    None if cols is None else self._open.ctypes.data, n, KINDS[kind],
                    out.ctypes.data)
        return out

    def collides(self, Q: Array) -> NDArray[np.bool_]:
        """Whether any pair is in contact (n,) at each row of ``Q`` (n, nq).

        Closer than the checker's margin (with none: a signed distance <= 0), by coal's
        signed distance with a fresh start: the verdict of
        :meth:`~scara_opt.collision.checker.CollisionChecker.collides`.
        """
        Q = np.ascontiguousarray(Q, float)
        out = np.zeros(len(Q), np.uint8)
        self._collides(self._handle, Q.ctypes.data, len(Q), out.ctypes.data)
        return out.view(np.bool_)

    def prove_path(self, x: Array, c: Array, V: Array, W: Array,
                   gaps: tuple[Array, Array, Array] | None, resolution: float, budget: int
                   ) -> tuple[bool, float, float, float, int, bool, int]:
        """:func:`~scara_opt.collision.continuous.check_path` (``locate=False``), compiled.

        Args:
            x: (m + 1,) the path's breakpoints.
            c: (k + 1, m, nq) its coefficients (scipy's ``PPoly.c``).
            V: (m, nq) bounds on ``|q'|`` per piece.
            W: (npairs, nq) the pairs' weights.
            gaps: a SCARA's ``(A, a, b)`` (the checker's ``gaps``), or None.
            resolution: the grazing bound [m].
            budget: the most configurations to compute.

        Returns:
            ``(clear, spare, at, distance, pair, touching, evaluations)``: as
            :func:`~scara_opt.collision.continuous.prove`'s Proof and Contact hold them
            (``spare``: the proven clearance [m]; ``pair``: -1 when clear). ``path_pairs``
            then holds the pair distances computed at middles (a pair proven on an
            interval is not computed at its middle).
        """
        x, c = np.ascontiguousarray(x, float), np.ascontiguousarray(c, float)
        V, W = np.ascontiguousarray(V, float), np.ascontiguousarray(W, float)
        A, a, b = (None, None, None) if gaps is None else (
            np.ascontiguousarray(g, float) for g in gaps)
        out = np.zeros(7)
        ok = self._prove_path(self._handle, len(x) - 1, c.shape[0] - 1, x.ctypes.data,
                              c.ctypes.data, V.ctypes.data, W.ctypes.data,
                              *(None if g is None else g.ctypes.data for g in (A, a, b)),
                              resolution, budget, out.ctypes.data)
        spare, at, dist, pair, touching, evals, computed = out.tolist()
        self.path_pairs = int(computed)
        return bool(ok), spare, at, dist, int(pair), bool(touching), int(evals)


class NativeProver:
    """One query's states and edges on a kernel (``EdgeProver``'s compiled form).

    The states' distances (less the shift) and a SCARA's height gaps are cached per
    configuration in C++; :meth:`edge` is ``EdgeProver.edge`` without its memory of proven
    edges. A state's pairs are computed until the first in contact, which refuses it
    whatever the others' distances (the same verdict as all of them: the least is <= 0
    either way); RRTConnect's samples and extensions are mostly such states (on the UR5's
    meshes in the STL-fixture cell of benchmarks/bench_plan.py, the planner's part of a
    call 17.9 -> 8.5 ms, the same paths). Likewise a midpoint inside an edge asks first
    the pair that last refused one. ``states``, ``midpoints``, ``pairs``,
    ``midpoint_pairs``: the counts so far.
    """

    def __init__(self, kernel: EdgeKernel, W: Array,
                 gaps: tuple[Array, Array, Array] | None) -> None:
        self._lib, self._kernel = kernel._lib, kernel  # the kernel outlives this
        W = np.ascontiguousarray(W, float)
        A, a, b = (None, None, None) if gaps is None else (
            np.ascontiguousarray(g, float) for g in gaps)
        self._handle = self._lib.edge_prover_new(
            kernel._handle, W.ctypes.data, *(None if g is None else g.ctypes.data
                                             for g in (A, a, b)))
        # buffers the calls fill, and their addresses (ctypes' conversions cost ~6 µs each)
        self._q = np.zeros((2, kernel.nq))
        self._d = np.zeros(kernel.npairs)
        self._counts = np.zeros(4, np.int64)
        self._at = (self._q.ctypes.data, self._q[1].ctypes.data, self._d.ctypes.data,
                    self._counts.ctypes.data)
        self._state, self._edge = self._lib.edge_prover_state, self._lib.edge_prover_edge

    def __del__(self) -> None:
        handle = getattr(self, "_handle", None)
        if handle:
            self._lib.edge_prover_free(handle)

    @property
    def states(self) -> int:
        """Configurations whose distances were all computed."""
        return int(self._counts[0])

    @property
    def midpoints(self) -> int:
        """Configurations computed inside edges."""
        return int(self._counts[1])

    @property
    def pairs(self) -> int:
        """Pair distances computed at states (a state in contact: up to its first one).

        The pair last found in contact is asked first; :meth:`distances` completes a state.
        """
        return int(self._counts[2])

    @property
    def midpoint_pairs(self) -> int:
        """Pair distances computed at midpoints of edges, on this prover's kernel.

        All the kernel's queries count. The pair that last refused a midpoint is asked first.
        """
        return int(self._counts[3])

    def distances(self, key: tuple[float, ...]) -> list[float]:
        """Distances less the shift (npairs,) at ``key`` (cached)."""
        self._q[0] = key
        at = self._at
        self._state(self._handle, at[0], at[2], at[3])
        return self._d.tolist()

    def valid(self, key: tuple[float, ...]) -> bool:
        """Whether every pair is farther than the margin at ``key`` (cached)."""
        self._q[0] = key
        at = self._at
        return bool(self._state(self._handle, at[0], None, at[3]))

    def edge(self, a: tuple[float, ...], b: tuple[float, ...], resolution: float) -> bool:
        """Whether the straight segment ``a`` -> ``b`` is proven clear (EdgeProver's rule)."""
        q = self._q
        q[0], q[1] = a, b
        at = self._at
        return bool(self._edge(self._handle, at[0], at[1], resolution, at[3]))


def _add_mesh(lib: ctypes.CDLL, handle: Any, g: int, parts: MeshParts) -> None:
    """Hand body ``g``'s mesh (its BVH, pieces, hull, triangles) to the kernel."""
    V = np.ascontiguousarray(parts.vertices, float)
    T = np.ascontiguousarray(parts.triangles, np.intc)
    every = parts.nodes
    counts = np.array([(len(p), len(t)) for p, t in every], np.intc).ravel()
    points = np.ascontiguousarray(np.vstack([p for p, _ in every]), float)
    tris = np.ascontiguousarray(np.vstack([t for _, t in every]), np.intc)
    children = np.ascontiguousarray(parts.children, np.intc)
    balls = np.ascontiguousarray(parts.balls, float)
    ball = np.ascontiguousarray(parts.ball, float)
    hull = np.ascontiguousarray(parts.hull, float)
    point = np.ascontiguousarray(parts.point, float)
    if lib.edge_kernel_add_mesh(handle, g, len(V), _dp(V), len(T), _ip(T), len(every),
                                _ip(counts), _dp(points), _ip(tris), _ip(children),
                                _dp(balls), _dp(ball), len(hull), _dp(hull), int(parts.closed),
                                _dp(point)):
        raise RuntimeError("coal could not build a mesh's BVH")  # pragma: no cover


def _dp(a: Array) -> Any:
    return a.ctypes.data_as(_DP)


def _ip(a: NDArray[np.intc]) -> Any:
    return a.ctypes.data_as(_IP)


def edge_kernel(checker: CollisionChecker, shift: float) -> EdgeKernel | None:
    """A compiled kernel for one query on ``checker`` (``shift``: margin + tolerance [m]).

    ``None`` where it cannot run (see the module docstring): the caller keeps the Python form.
    """
    objects = checker.model.geometryObjects
    if any(shape_code(o.geometry) is None for o in objects):
        return None
    lib = _library()
    if lib is None:
        return None
    parts = checker.__dict__.get("_edge_kernel_parts")
    if parts is None:
        moving = [g for g, o in enumerate(objects) if o.parentJoint > 0]
        f = _placements(checker, moving)
        parts = checker.__dict__["_edge_kernel_parts"] = (moving, f, None if f is None else
                                                          _entry(f))
    moving, f, entry = parts
    if f is None:
        return None
    return EdgeKernel(lib, checker, f, entry, moving, shift)


def _entry(f: ca.Function) -> tuple[Any, ctypes.CDLL]:
    """The C entry point of the compiled Function ``f`` (and its library, kept loaded)."""
    cdll = ctypes.CDLL(str(library_path(f.name())))
    return ctypes.cast(getattr(cdll, f.name()), _P), cdll
