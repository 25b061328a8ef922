"""A robot in a cell: is a configuration in collision, and how far is it from one.

:class:`CollisionChecker` puts the robot's bodies (:mod:`~scara_opt.collision.geometry`)
and the cell's obstacles into one Pinocchio ``GeometryModel`` with the pairs to check:
every robot body against every obstacle (but the cell's ``allowed`` contacts) and the
robot's own self pairs. Pinocchio's ``computeCollisions`` / ``computeDistances`` (coal)
do the work; distances are *signed*: negative is the depth of an overlap [m] (coal's
signed distance for convex shapes; a mesh reports 0 when in contact).

``margin`` [m] makes the checker demand that much clearance: a configuration collides when
a pair is closer than the margin.

A robot whose revolute axes are all parallel (a SCARA) keeps every body within a fixed
range along that axis, whatever the joints do (the prismatic strokes bound it exactly:
:func:`~scara_opt.collision.bound.height_range`). A robot body and an obstacle whose
ranges never come within the margin (the arms and a table below the tool's lowest
reach) are not checked against each other; :attr:`CollisionChecker.skipped` says so, and
:attr:`CollisionChecker.apart` keeps each such pair's least gap [m]: a proven lower bound on
its distance at every configuration. Verdicts need only the checked pairs; a *reported*
clearance (:meth:`CollisionChecker.clearance`, ``clearance_many``) covers every pair but
the allowed ones, the far pairs too (:attr:`CollisionChecker.everything`).
"""

from __future__ import annotations

import logging
import math
import threading
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import check_flag, check_int, check_real, describe
from scara_opt.collision.bound import height_gaps, height_range, pair_weights
from scara_opt.collision.cell import Cell
from scara_opt.collision.edge_kernel import EdgeKernel, edge_kernel
from scara_opt.collision.geometry import (
    Body,
    RobotGeometry,
    check_pair_names,
    name_pairs,
    robot_geometry,
    support_points,
)
from scara_opt.errors import CellError, InputError
from scara_opt.model.robot import Robot, check_robot

log = logging.getLogger(__name__)

Array = NDArray[np.float64]

__all__ = ["Clearance", "CollisionChecker", "always_touching"]

_F64 = np.dtype(np.float64)


#: distances below this [m] do not count as clear in a proof
#: (:mod:`~scara_opt.collision.continuous`): coal's GJK distance is exact to its tolerance
#: (1e-6 m), the proof keeps ten times that in hand
DISTANCE_TOL = 1e-5

#: a robot-obstacle pair is not checked when its bodies' ranges along the common joint
#: axis of a SCARA-type robot stay this much farther apart than the margin [m]
GAP_TOL = 1e-4


def fresh_starts(gdata: pin.GeometryData) -> None:
    """Every request of ``gdata`` starts coal's GJK afresh (Pinocchio caches the last guess).

    A guess carried over from an earlier query made ``computeCollisions`` answer "free"
    on a 44 mm overlap; a distance started afresh is the same whatever came before.
    """
    import warnings

    with warnings.catch_warnings():  # coal marks the flag deprecated (Pinocchio sets it)
        warnings.simplefilter("ignore", DeprecationWarning)
        for req in (*gdata.distanceRequests, *gdata.collisionRequests):
            req.enable_cached_gjk_guess = False


#: random configurations a moving body must touch an obstacle at, every one, to be taken as
#: always touching it (:func:`always_touching`)
ALWAYS_SAMPLES = 200


def always_touching(robot: Robot, model: pin.GeometryModel, bodies: list[Body],
                    pairs: list[tuple[int, int]], samples: int = ALWAYS_SAMPLES
                    ) -> dict[tuple[int, int], str]:
    """The robot-obstacle ``pairs`` in contact in every configuration, and why.

    A body fixed in the world (Pinocchio's joint 0: a base link) touching an obstacle
    touches it whatever the joints do: exact. A moving body touching it at each of
    ``samples`` random configurations within the limits (seed 0), as MoveIt's setup
    assistant finds its "Always" pairs: a sample, not a proof; such pairs are reported.
    A contact is a signed distance <= 0 (coal, fresh requests).
    """
    from scara_opt.collision.geometry import pair_distance

    candidates = [(i, j) for i, j in pairs if bodies[j].joint == 0]
    if not candidates:
        return {}
    data, gdata = robot.model.createData(), pin.GeometryData(model)
    Q = np.random.default_rng(0).uniform(robot.sampling_lower, robot.sampling_upper,
                                         (samples, robot.nq))
    Q[0] = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    out: dict[tuple[int, int], str] = {}
    open_ = candidates
    for k, q in enumerate(Q):
        pin.updateGeometryPlacements(robot.model, data, model, gdata, q)
        open_ = [(i, j) for i, j in open_ if pair_distance(model, gdata, i, j) <= 0.0]
        for i, j in [p for p in open_ if bodies[p[0]].joint == 0]:
            out[(i, j)] = "always in contact (fixed in the world, overlapping the obstacle)"
        open_ = [p for p in open_ if bodies[p[0]].joint != 0]
        if not open_:
            break
        if k == len(Q) - 1:
            for p in open_:
                out[p] = f"always in contact (touching at each of {samples} random configurations)"
    return out


def _heights(robot: Robot, bodies: list[Body]) -> tuple[Array, list] | None:
    """The common axis of a SCARA-type robot and each body's range along it (else None)."""
    n = robot.yaw_axis
    if n is None:
        return None
    return n, [height_range(robot, b, n) for b in bodies]


def _gap(heights: tuple | None, i: int, obj: pin.GeometryObject) -> float:
    """How far apart body ``i`` and the obstacle ``obj`` always stay along the axis [m]."""
    if heights is None:
        return -math.inf
    n, ranges = heights
    points, pad = support_points(obj.geometry, obj.placement)
    h = points @ n
    lo, hi = ranges[i]
    return max(float(h.min()) - pad - hi, lo - float(h.max()) - pad)


class MeshPairs:
    """The meshes among a checker's bodies, for the Python form of their distances.

    The rules of the compiled kernel (:mod:`~scara_opt.collision.edge_kernel`): a pair
    with a mesh is no deeper than the balls holding its bodies allow (coal's BVH distance
    can be ``-DBL_MAX``), and a body inside a closed mesh (its point's winding number:
    :mod:`~scara_opt.collision.mesh_bounds`) is a contact, its distance negated.
    """

    def __init__(self, model: pin.GeometryModel, pairs: NDArray[np.int64]) -> None:
        from scara_opt.collision.edge_kernel import shape_code
        from scara_opt.collision.mesh_bounds import mesh_parts

        objects = model.geometryObjects
        self.parts: list[Any] = []
        self.radius: list[float] = []
        self.point: list[Array] = []
        for o in objects:
            code = shape_code(o.geometry)
            if code is not None and code[0] == 4:
                parts = mesh_parts(o.geometry)
                self.parts.append(parts)
                self.radius.append(float(parts.ball[3]))
                self.point.append(parts.point)
            else:
                self.parts.append(None)
                self.radius.append(_holding_radius(o.geometry))
                self.point.append(np.zeros(3))
        self.pairs = pairs
        self.pair = [self.parts[int(i)] is not None or self.parts[int(j)] is not None
                     for i, j in pairs]
        self.any = any(self.pair)

    def corrected(self, k: int, d: float, model: pin.GeometryModel, gdata: pin.GeometryData,
                  kind: str) -> float:
        """Pair ``k``'s distance ``d`` [m] by the kernel's rules (bodies placed in gdata).

        ``kind`` as :meth:`~scara_opt.collision.edge_kernel.EdgeKernel.batch`'s: the
        surface distance is the bound inside a motion; reported (``"exact"``) it is 0
        where coal's collision test finds the surfaces meeting, negated inside a closed
        mesh; at a motion's start (``"rest"``) a body inside one is a contact (-1 m).
        """
        import coal

        a, b = (int(x) for x in self.pairs[k])
        deepest = -(self.radius[a] + self.radius[b])
        d = deepest if not math.isfinite(d) or d < deepest else d
        if kind == "bound" or d <= 0:
            return d
        if kind == "exact":
            objects = model.geometryObjects
            request, result = coal.CollisionRequest(coal.NO_REQUEST, 1), coal.CollisionResult()
            if coal.collide(objects[a].geometry, gdata.oMg[a], objects[b].geometry,
                            gdata.oMg[b], request, result):
                return 0.0
        if self.inside(a, b, gdata):
            return -d if kind == "exact" else -1.0
        return d

    def inside(self, a: int, b: int, gdata: pin.GeometryData) -> bool:
        """Whether body ``a`` lies inside ``b`` or ``b`` inside ``a``, a closed mesh."""
        from scara_opt.collision.mesh_bounds import winding_number

        for outer, body in ((b, a), (a, b)):
            parts = self.parts[outer]
            if parts is None or not parts.closed:
                continue
            p = gdata.oMg[outer].actInv(gdata.oMg[body].act(self.point[body]))
            if (parts.hull[:, :3] @ p + parts.hull[:, 3] <= 1e-12).all() and \
                    abs(winding_number(parts, p)) > 0.5:
                return True
        return False


def _holding_radius(shape: Any) -> float:
    """The radius [m] of a ball about a primitive's centre holding it (as the kernel's)."""
    import coal

    if isinstance(shape, coal.Sphere):
        return float(shape.radius)
    if isinstance(shape, coal.Box):
        return float(np.linalg.norm(np.asarray(shape.halfSide, float)))
    if isinstance(shape, coal.Capsule):
        return float(shape.radius + shape.halfLength)
    if isinstance(shape, (coal.Cylinder, coal.Cone)):
        return float(math.hypot(shape.radius, shape.halfLength))
    shape.computeLocalAABB()
    return float(np.linalg.norm(np.maximum(np.abs(np.asarray(shape.aabb_local.min_)),
                                           np.abs(np.asarray(shape.aabb_local.max_)))))


@dataclass(frozen=True)
class Clearance:
    """The closest pair of bodies at one configuration.

    Attributes:
        distance: their signed distance [m]; negative: they overlap by ``-distance``.
        bodies: ``(robot body, other body)`` names.
    """

    distance: float
    bodies: tuple[str, str]

    @property
    def depth(self) -> float:
        """How deep the bodies overlap [m] (0 when apart)."""
        return max(0.0, -self.distance)

    def __repr__(self) -> str:
        return f"Clearance({self.distance * 1e3:.3f} mm, {self.bodies[0]}-{self.bodies[1]})"


class CollisionChecker:
    """Collision and clearance queries for one robot in one cell.

    Args:
        robot: the robot.
        cell: its :class:`~scara_opt.collision.cell.Cell` (``None``: self-collision only).
        margin: clearance a configuration must keep to count as free [m] (default 0).
        radius: capsule radius [m] of a robot without ``<collision>`` (see
            :func:`~scara_opt.collision.geometry.robot_geometry`).
        srdf: an SRDF (file or text) whose ``<disable_collisions>`` pairs are not checked.
        allowed: more pairs not to check: two robot bodies, or a robot body and an
            obstacle (like the cell's own ``allowed``).
        missing_mesh: ``"error"`` or ``"capsule"`` for a robot mesh that is missing.
        geometry: a :class:`~scara_opt.collision.geometry.RobotGeometry` already built
            (then ``radius``, ``srdf``, ``missing_mesh`` are not used).
        skip_apart: leave out the robot-obstacle pairs of a SCARA-type robot that never come
            within the margin along the joints' common axis (default True; they are in
            :attr:`apart`).
        check_touching: check the robot-obstacle pairs that touch in every configuration
            too (default False: a mounting, such as the fixed base on its table, is left
            out as MoveIt's setup assistant leaves out its "Always" pairs; they are in
            :attr:`always` and :attr:`skipped` either way). See :func:`always_touching`.

    Raises:
        CellError, MeshNotFoundError, UnknownBodyError: see
            :func:`~scara_opt.collision.geometry.robot_geometry`; an ``allowed`` pair of the
            cell naming no robot body or obstacle.
        InputError: ``cell`` not a Cell, ``margin`` not a finite number >= 0.
    """

    def __init__(self, robot: Robot, cell: Cell | None = None, *, margin: float = 0.0,
                 radius: object = None, srdf: str | Path | None = None, allowed: object = (),
                 missing_mesh: str = "error", geometry: RobotGeometry | None = None,
                 skip_apart: bool = True, check_touching: bool = False) -> None:
        self.robot = check_robot(robot)
        check_flag("skip_apart", skip_apart)
        check_flag("check_touching", check_touching)
        if cell is None:
            cell = Cell(name="no obstacles")
        if not isinstance(cell, Cell):
            raise InputError(f"cell must be a scara_opt.Cell (so.load_cell(path) or "
                             f"so.Cell([...])) or None; got {describe(cell)}")
        self.cell = cell
        self.margin = check_real("margin", margin, 0.0, 1.0, unit="m")
        given_pairs = name_pairs(allowed, "allowed")
        self._allowed, self._skip_apart = given_pairs, skip_apart
        self._check_touching = check_touching
        for one, other in given_pairs:
            if one in cell.names and other in cell.names:
                raise CellError(f"allowed pair ({one!r}, {other!r}) names two obstacles: obstacles "
                                "are never checked against each other; an allowed pair is two "
                                "robot bodies, or a robot body and an obstacle")
        robot_pairs = [p for p in given_pairs if not set(p) & set(cell.names)]
        cell_pairs = [p for p in given_pairs if set(p) & set(cell.names)]
        self.geometry = geometry if geometry is not None else robot_geometry(
            robot, radius=radius, srdf=srdf, allowed=robot_pairs, missing_mesh=missing_mesh)
        model = pin.GeometryModel()
        for obj in self.geometry.model.geometryObjects:
            model.addGeometryObject(obj)
        bodies: list[Body] = list(self.geometry.bodies)
        for ob in cell.obstacles:
            model.addGeometryObject(pin.GeometryObject(ob.name, 0, ob.placement, ob.shape()))
            bodies.append(Body(ob.name, ob.name, 0, np.zeros((1, 3)), 0.0))
        known: dict[str, set[int]] = {}
        for i, b in enumerate(bodies):
            known.setdefault(b.name, set()).add(i)
            known.setdefault(b.link, set()).add(i)
        given = check_pair_names(list(cell.allowed) + cell_pairs, known,
                                 f"allowed contacts of {cell.name!r}")
        n_robot = len(self.geometry.bodies)
        pairs = list(self.geometry.pairs)
        self.skipped = dict(self.geometry.skipped)
        self.apart: dict[tuple[str, str], float] = {}
        """``{(robot body, obstacle): least gap [m]}`` of the pairs left out as never within
        reach along a SCARA's axis: a lower bound on their distance everywhere."""
        heights = _heights(self.robot, bodies[:n_robot])
        for i in range(n_robot):
            for j in range(n_robot, len(bodies)):
                key = (bodies[i].name, bodies[j].name)
                if any((i in x and j in y) or (j in x and i in y) for x, y in given):
                    self.skipped[key] = "allowed"
                    continue
                gap = _gap(heights, i, model.geometryObjects[j])
                if skip_apart and gap > self.margin + GAP_TOL:
                    self.skipped[key] = (f"never within reach: at least {gap * 1e3:.3g} mm "
                                         "apart along the joints' common axis")
                    self.apart[key] = gap
                else:
                    pairs.append((i, j))
        #: ``{(robot body, obstacle): why}`` of the pairs in contact in every configuration
        #: (a base mounted on its table), left out unless ``check_touching``
        self.always: dict[tuple[str, str], str] = {}
        if pairs:
            for (i, j), why in always_touching(robot, model, bodies, pairs).items():
                self.always[(bodies[i].name, bodies[j].name)] = why
            if not check_touching:
                self.skipped.update(self.always)
                pairs = [(i, j) for i, j in pairs
                         if (bodies[i].name, bodies[j].name) not in self.always]
                for (one, other), why in self.always.items():
                    level = logging.INFO if "fixed" in why else logging.WARNING
                    log.log(level, "%s and %s are %s: not checked (check_touching=True "
                            "checks them)", one, other, why)
        for i, j in pairs:
            model.addCollisionPair(pin.CollisionPair(i, j))
        self.model = model
        self.bodies: tuple[Body, ...] = tuple(bodies)
        self.pairs: NDArray[np.int64] = np.array(pairs, dtype=np.int64).reshape(-1, 2)
        self.pair_names: tuple[tuple[str, str], ...] = tuple(
            (bodies[i].name, bodies[j].name) for i, j in pairs)
        self._local = threading.local()
        self._robot_model = robot.model
        self._shape = (robot.nq,)

    # ------------------------------------------------------------------ per-thread data
    def _data(self) -> tuple[pin.Data, pin.GeometryData, list]:
        """This thread's Pinocchio and geometry data, and the list of its distance results."""
        local = self._local
        try:
            return local.pair
        except AttributeError:
            gdata = pin.GeometryData(self.model)
            fresh_starts(gdata)
            # the results, fetched once: each element refers into the data's own vector
            local.pair = (self.robot.model.createData(), gdata, list(gdata.distanceResults))
            return local.pair

    def _kernel(self) -> EdgeKernel | None:
        """This thread's compiled distance kernel, or ``None`` (the Pinocchio calls run).

        See :mod:`~scara_opt.collision.edge_kernel`; its distances less ``margin`` and
        :data:`DISTANCE_TOL` for the proofs.
        """
        local = self._local
        try:
            return local.kernel
        except AttributeError:
            local.kernel = edge_kernel(self, self.margin + DISTANCE_TOL)
            return local.kernel

    def _q(self, q: ArrayLike) -> Array:
        """``q`` checked: a float (nq,) array of finite values (the fast path costs ~0.5 µs)."""
        if (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and math.isfinite(sum(q.tolist()))):
            return q
        return self.robot.check_q(q)

    @cached_property
    def weights(self) -> Array:
        """Bound (npairs, nq) on each pair's relative motion per joint motion [m/rad or m/m].

        Along a straight joint segment ``dq``, no point of a pair's bodies moves relative
        to the other body by more than ``weights @ abs(dq)`` (:mod:`scara_opt.collision.bound`).
        """
        return pair_weights(self.robot, self.bodies, self.pairs)

    @cached_property
    def gaps(self) -> tuple[Array, Array, Array] | None:
        """Each pair's gap above and below its obstacle along a SCARA's axis, affine in q.

        ``(A, a, b)``: the gaps are ``A @ q + a`` and ``b - A @ q`` [m] (``-inf`` for self
        pairs); ``None`` for a robot whose revolute axes are not parallel
        (:func:`~scara_opt.collision.bound.height_gaps`).
        """
        obstacles = {}
        for j, obj in enumerate(self.model.geometryObjects):
            if self.bodies[j].joint == 0 and self.robot.yaw_axis is not None:
                points, pad = support_points(obj.geometry, obj.placement)
                h = points @ self.robot.yaw_axis
                obstacles[j] = (float(h.min()) - pad, float(h.max()) + pad)
        return height_gaps(self.robot, list(self.bodies), self.pairs, obstacles)

    @property
    def npairs(self) -> int:
        """Number of pairs checked."""
        return len(self.pair_names)

    @cached_property
    def everything(self) -> CollisionChecker:
        """This checker with no pair left out as :attr:`apart` (itself when none is).

        The same bodies, margin and allowed pairs: what reported clearances are computed on.
        """
        if not self.apart:
            return self
        return CollisionChecker(self.robot, self.cell, margin=self.margin,
                                allowed=self._allowed, geometry=self.geometry,
                                skip_apart=False, check_touching=self._check_touching)

    def with_margin(self, margin: float) -> CollisionChecker:
        """This checker asking for ``margin`` [m] instead (itself when it already does).

        The same bodies, cell and allowed pairs (the pairs left out as :attr:`apart`
        follow the new margin).

        Raises:
            InputError: ``margin`` not a finite number in [0, 1] m.
        """
        margin = check_real("margin", margin, 0.0, 1.0, unit="m")
        if margin == self.margin:
            return self
        return CollisionChecker(self.robot, self.cell, margin=margin, allowed=self._allowed,
                                geometry=self.geometry, skip_apart=self._skip_apart,
                                check_touching=self._check_touching)

    @property
    def least_apart(self) -> float:
        """The least gap of the pairs left out as :attr:`apart` [m] (``inf``: none)."""
        return min(self.apart.values(), default=math.inf)

    # ------------------------------------------------------------------ one configuration
    def touching(self, d: Array) -> NDArray[np.bool_]:
        """Which signed distances ``d`` [m] are contacts: below ``margin`` (none: <= 0)."""
        return np.asarray(d < self.margin if self.margin else d <= 0.0, dtype=bool)

    def collides(self, q: ArrayLike) -> bool:
        """Whether any checked pair is in contact at ``q`` (nq,): :meth:`touching`.

        The verdict is coal's signed distance of each pair, the one :meth:`distances`
        reports, every query started afresh (no GJK guess carried over from an earlier
        one); a pair is not asked of coal only when the balls holding its two bodies are
        farther apart than the margin. It always agrees with :meth:`distances`. (Coal's
        boolean collision test, Pinocchio's ``computeCollisions``, can answer "free" on a
        deep overlap: with a guess carried from the previous query, or without its
        contact computation.)

        Raises:
            InputError: ``q`` not (nq,) finite numbers.
        """
        if not (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and math.isfinite(sum(q.tolist()))):
            q = self.robot.check_q(q)
        if not self.npairs:
            return False
        kernel = self._kernel()
        if kernel is not None:
            return bool(kernel.collides(q[None, :])[0])
        return bool(self.touching(self.distances(q)).any())

    def distances(self, q: ArrayLike) -> Array:
        """Signed distance of every checked pair (npairs,) [m] at ``q`` (nq,).

        Coal's signed distance; a pair with a mesh as :class:`~scara_opt.collision.
        mesh_bounds.MeshParts` says (its surface distance, negated when one body lies
        inside a closed mesh).
        """
        qa = self._q(q)
        if self._meshes.any:
            return self.distances_many(qa[None, :])[0]
        data, gdata, results = self._data()
        pin.computeDistances(self._robot_model, data, self.model, gdata, qa)
        return np.array([r.min_distance for r in results])

    def clearance(self, q: ArrayLike) -> Clearance:
        """The closest pair at ``q`` (nq,) and its signed distance, over every pair.

        Every pair but the allowed ones: the checked pairs and those left out of the checks
        as :attr:`apart` (:attr:`everything`).

        Raises:
            InputError: ``q`` not (nq,) finite numbers, or nothing to check (no pairs).
        """
        full = self.everything
        if not full.npairs:
            raise InputError("the checker has no pair of bodies to check (no obstacle and no "
                             "self pair): add obstacles to the cell")
        d = full.distances(q)
        k = int(np.argmin(d))
        return Clearance(float(d[k]), full.pair_names[k])

    def contacts(self, q: ArrayLike) -> list[Clearance]:
        """Every checked pair closer than ``margin`` at ``q``, deepest first.

        The pairs :meth:`collides` finds in contact, by :meth:`distances`.
        """
        if not self.collides(q):
            return []
        d = self.distances(q)
        hit = np.flatnonzero(d < self.margin) if self.margin else np.flatnonzero(d <= 0.0)
        order = hit[np.argsort(d[hit])]
        return [Clearance(float(d[k]), self.pair_names[k]) for k in order]

    # ------------------------------------------------------------------ batches
    def _batch(self, Q: ArrayLike) -> Array:
        return self.robot.check_q_batch(Q)

    def collides_many(self, Q: ArrayLike, threads: int = 1) -> NDArray[np.bool_]:
        """:meth:`collides` of each row of ``Q`` (n, nq) in one call, (n,) bool.

        The same verdicts as :meth:`collides`, row by row: in the compiled kernel's loop
        (:mod:`~scara_opt.collision.edge_kernel`), the rows split over ``threads``
        threads (each its own kernel; the kernel runs without Python's lock); where no
        kernel runs, :meth:`distances_many`.

        Raises:
            InputError: ``Q`` not (n, nq) finite numbers; ``threads`` not an integer in
                [1, 256].
        """
        Qa = self._batch(Q)
        threads = check_int("threads", threads, 1, 256)
        if not self.npairs or not len(Qa):
            return np.zeros(len(Qa), dtype=bool)
        if self._kernel() is None:
            return np.asarray(self.touching(self.distances_many(Qa)).any(axis=1), dtype=bool)
        if threads == 1 or len(Qa) < 2 * threads:
            return self._kernel_collides(Qa)
        from concurrent.futures import ThreadPoolExecutor

        chunks = np.array_split(Qa, threads)
        with ThreadPoolExecutor(threads) as pool:
            return np.concatenate(list(pool.map(self._kernel_collides, chunks)))

    def _kernel_collides(self, Q: Array) -> NDArray[np.bool_]:
        """This thread's kernel's contact tests of the rows of ``Q`` (n, nq)."""
        kernel = self._kernel()
        if kernel is None:  # pragma: no cover - collides_many asked for one first
            raise RuntimeError("no compiled kernel")
        return kernel.collides(Q)

    def distances_many(self, Q: ArrayLike) -> Array:
        """Signed distances (n, npairs) [m] of every pair at each row of ``Q`` (n, nq)."""
        Qa = self._batch(Q)
        kernel = self._kernel()
        if kernel is not None:
            return kernel.batch(Qa)
        return self._python_distances(Qa, None, "exact")

    def pair_distances(self, Q: Array, pairs: NDArray[np.intp] | None = None,
                       kind: str = "bound") -> Array:
        """Signed distances (n, len(pairs)) of some pairs at each row of ``Q`` (n, nq) [m].

        No checks (the proofs' inner loop): ``Q`` a float array, ``pairs`` indices into
        :attr:`pair_names` (``None``: all). ``kind``: ``"exact"``, as
        :meth:`distances_many`; ``"bound"``, what a proof takes inside a motion, and
        ``"rest"``, at a motion's start: for a pair with a mesh a lower bound on its
        distance outside a solid (the compiled kernel's tree of hulls where above the
        margin and tolerance, else the surface distance), and at rest a body inside a
        closed mesh a contact (:meth:`~scara_opt.collision.edge_kernel.EdgeKernel.batch`).
        The same for every other pair.
        """
        kernel = self._kernel()
        cols = None if pairs is None else [int(k) for k in pairs]
        if kernel is not None:
            return kernel.batch(Q, cols, kind)
        return self._python_distances(Q, cols, kind)

    def _python_distances(self, Q: Array, cols: list[int] | None, kind: str) -> Array:
        """Pinocchio's distances of pairs ``cols`` (None: all) at the rows of ``Q``.

        A pair with a mesh by the kernel's rules (:meth:`MeshPairs.corrected`).
        """
        data, gdata, results = self._data()
        model, gmodel = self._robot_model, self.model
        meshes = self._meshes
        every = cols is None
        cols = list(range(self.npairs)) if cols is None else cols
        out = np.empty((len(Q), len(cols)))
        place, distance = pin.updateGeometryPlacements, pin.computeDistance
        for i, q in enumerate(Q):
            if every:
                pin.computeDistances(model, data, gmodel, gdata, q)
                out[i] = [r.min_distance for r in results]
            else:
                place(model, data, gmodel, gdata, q)
                out[i] = [distance(gmodel, gdata, k).min_distance for k in cols]
            for c, k in enumerate(cols):
                if meshes.pair[k]:
                    out[i, c] = meshes.corrected(k, out[i, c], gmodel, gdata, kind)
        return out

    @cached_property
    def _meshes(self) -> MeshPairs:
        """What the checker's pairs with a mesh need (:class:`MeshPairs`)."""
        return MeshPairs(self.model, self.pairs)

    def clearance_many(self, Q: ArrayLike) -> Array:
        """Smallest signed distance (n,) [m] at each row of ``Q`` (n, nq), over every pair.

        As :meth:`clearance`: the :attr:`apart` pairs too.
        """
        D = self.everything.distances_many(Q)
        return D.min(axis=1) if D.shape[1] else np.full(len(D), np.inf)

    def __repr__(self) -> str:
        return (f"CollisionChecker({self.robot.name!r} in {self.cell!r}: {len(self.bodies)} "
                f"bodies, {self.npairs} pairs, margin {self.margin * 1e3:g} mm)")
