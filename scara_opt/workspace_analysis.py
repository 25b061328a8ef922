r"""Workspace by Monte Carlo: reach, the base's exclusion zone, reachability queries, plots.

:func:`workspace` draws ``n`` configurations uniformly within the joint limits from a seeded
generator, evaluates the FK of all of them as one batch and returns a :class:`Workspace`
(peng2025 Sec. 3, N = 60,000, Fig. 4; zavar2024 Fig. 3).

**The plane.** "XY" means the plane of motion: the plane normal to the robot's
:attr:`~scara_opt.Robot.yaw_axis` ``n`` (world z when the robot has none). When ``n`` is a
world axis, the plane's coordinates ``(u, v)`` are the two other world axes in the order
x, y, z (world x–y for a vertical SCARA; x–z for nguyen, whose arm turns about −y);
otherwise an orthonormal pair normal to ``n``. Heights are measured along ``n``.

**Base axis and radius.** The base axis is the line along ``n`` through the origin of the
first revolute joint at the reference configuration (every joint at zero, or mid-range
where zero is outside the limits; the world origin when no joint is revolute). The radius
of a point is its distance from that line (peng2025: the shoulder axis J1, 120 mm from the
base centre; zavar2024: the base axis at the origin).

**Area.** The samples' ``(u, v)`` fall into an occupancy grid of square cells of side
``cell`` [m]. A cell is on the edge of the region when one of its four neighbours is empty;
the edge crosses such a cell, covering on average half of it, so the area is

.. math:: A = h^2 \left(N_\text{interior} + \tfrac12 N_\text{edge}\right)

which removes the first-order bias of plain cell counting (about
:math:`\tfrac{2}{\pi} P h` for a region of perimeter :math:`P`). The automatic cell holds
about :data:`SAMPLES_PER_CELL` samples on average, so empty cells inside the region are rare
(joint-uniform samples are densest near the reach circles and sparsest where the arm's
Jacobian determinant is largest).

**Uncertainty.** The edge could run anywhere through the edge cells, so the grid pins the
area down to :math:`\pm \tfrac12 h^2 N_\text{edge}` (:attr:`Workspace.xy_area_uncertainty`,
shown in the repr): large for few samples (coarse cells, most of them on the edge), small
for many. On a planar 2R arm with joint limits, whose area is known in closed form, the
interval held the exact area in all of 20 seeds at every ``n`` from 10 to 60,000 (with the
error at most 0.6 of the half-width); at ``n = 2`` or 5 it did not, so :func:`workspace`
refuses fewer than :data:`MIN_SAMPLES` samples.

**Reachability.** :meth:`Workspace.contains` is exact for SCARA-type robots without a
redundant joint (fang, peng2025, zavar2024): the closed form
(:func:`scara_opt.ik.analytic.solve_batch`) gives both elbow branches and a point counts as
reachable when one branch lies within the limits and, with a footprint, keeps its links
clear of it. Otherwise (nguyen and inverted5, whose redundant joint the closed form holds
fixed, and non-SCARA chains) it answers from the occupancy grid and the sampled height
range: accurate to about one cell at the edge of the region, and, for a chain whose height
depends on its planar position, an over-approximation (a box in height over the planar
region).

**Exclusion zone.** A robot file may declare the base footprint as a ``[footprint]`` table
(see :class:`~scara_opt.footprint.Footprint`): samples where a checked link segment,
projected on the plane, passes through it are dropped (peng2025 Fig. 5–6).

peng2025's file declares a circle of radius :math:`R = L_1 \sin 120° ≈ 190.53` mm about the
shoulder axis J1 (at :math:`(L_0, 0) = (120, 0)` mm, so it also covers the base centre) and
checks the segments from the elbow J2 on (link 2 and the tool). Once :math:`|θ_2| > 90°`
the forearm passes at :math:`L_1 \sin|θ_2|` from the shoulder axis, whatever :math:`θ_1` is,
so it clears the circle exactly when :math:`|θ_2| \le 120°`: the effective elbow limit the
paper states, giving the calibrated workspace of its Fig. 6 (the area drops from about
0.394 m² to 0.286 m²). The paper's text gives no dimensions for Fig. 5; the radius is
chosen to reproduce that limit. Links 0 and 1 sit on the base and are not checked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import (
    check_memory,
    check_real,
    count_text,
    describe,
    memory_guard,
)
from scara_opt.errors import InputError
from scara_opt.footprint import Footprint, world_axis
from scara_opt.ik.analytic import NotScaraError, scara_geometry, solve_batch
from scara_opt.ik.base import check_seed, default_q0
from scara_opt.model import batch_fk
from scara_opt.model.robot import Array, Robot, check_robot

#: average samples per grid cell when the cell size is chosen automatically
SAMPLES_PER_CELL = 10

#: largest occupancy grid built [cells]; a smaller cell would need more memory than sensible
MAX_CELLS = 20_000_000

#: fewest samples :func:`workspace` draws: below about 10 the area's uncertainty interval no
#: longer holds the exact area (see the module docstring); 100 leaves a margin
MIN_SAMPLES = 100

_AXIS_NAMES = "xyz"


# ---------------------------------------------------------------------- the plane
@dataclass(frozen=True, eq=False)
class Plane:
    """The plane of motion, its coordinates and the base axis (see the module docstring).

    Attributes:
        e1, e2: (3,) orthonormal world directions of the plane coordinates ``u``, ``v``.
        n: (3,) unit normal (the yaw axis); heights are measured along it.
        origin: (3,) a point of the base axis [m].
        labels: names of ``u``, ``v`` and the height (e.g. ``("x", "y", "z")``).
    """

    e1: Array
    e2: Array
    n: Array
    origin: Array
    labels: tuple[str, str, str]

    def coords(self, points: Array) -> Array:
        """Plane coordinates (..., 2) [m] of world points (..., 3) [m].

        A view of (2, ...) contiguous rows, so reducing over the samples (``min(axis=0)``)
        runs along contiguous memory: ~100x faster at 60,000 samples than on (m, 2) in C
        order, whose inner loop is two long (issue 18). The points are flattened to (s, 3)
        first: one matrix-vector product per coordinate, where (n, k, 3) @ (3,) would run n
        small ones (4.4 -> 1.7 ms for 60,000 five-point chains, the same numbers).
        """
        flat = points.reshape(-1, 3)
        rows = np.stack([flat @ self.e1, flat @ self.e2])
        return np.moveaxis(rows.reshape(2, *points.shape[:-1]), 0, -1)

    def columns(self, points: Array) -> tuple[Array, Array]:
        """Plane coordinates ``u``, ``v`` (...,) [m] of world points (..., 3) [m], apart.

        Where ``e1`` (``e2``) is a world axis, as for every vertical SCARA, ``u`` (``v``) is
        a view of the points' own column: no arithmetic, no copy (a footprint's checked
        points of 60,000 chains: 6.3 -> 2.0 ms with the test, the same values).
        """
        return _along(points, self.e1), _along(points, self.e2)

    def height(self, points: Array) -> Array:
        """Height (...,) [m] of world points (..., 3) along :attr:`n`."""
        return points @ self.n

    def radius(self, points: Array) -> Array:
        """Distance (...,) [m] of world points (..., 3) from the base axis."""
        return np.linalg.norm(self.coords(points - self.origin), axis=-1)


def _along(points: Array, e: Array) -> Array:
    """``points @ e`` (...,); a view of one column where ``e`` is a world axis."""
    axis = world_axis(e)
    return points @ e if axis is None else points[..., axis]


def _uniform(rng: np.random.Generator, lo: Array, hi: Array, n: int) -> Array:
    """``rng.uniform(lo, hi, (n, len(lo)))``, the same numbers, in about half the time.

    numpy draws each entry as ``lo + (hi - lo) * u`` from ``u = rng.random()`` in C order,
    element by element through the broadcast; here the draws come in one block and the
    two operations run in place over it (60,000 × 4: 2.1 -> 1.1 ms).
    """
    out = rng.random((n, len(lo)))
    out *= hi - lo
    out += lo
    return out


def workspace_plane(robot: Robot) -> Plane:
    """The :class:`Plane` of ``robot``: normal to its yaw axis, through its first revolute joint.

    Args:
        robot: any robot.

    Returns:
        The plane; world x–y with normal +z when the robot has no yaw axis.
    """
    n = robot.yaw_axis
    n = np.array([0.0, 0.0, 1.0]) if n is None else np.asarray(n, float)
    k = int(np.argmax(np.abs(n)))
    if abs(n[k]) > 1.0 - 1e-9:  # a world axis: the two others, in the order x, y, z
        n = np.sign(n[k]) * np.eye(3)[k]
        i, j = (a for a in range(3) if a != k)
        e1, e2 = np.eye(3)[i], np.eye(3)[j]
        labels = (_AXIS_NAMES[i], _AXIS_NAMES[j], ("-" if n[k] < 0 else "") + _AXIS_NAMES[k])
    else:
        ref = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
        e1 = ref - (ref @ n) * n
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        labels = ("u", "v", "h")
    revolute = [idx for idx, kind in enumerate(robot.joint_types) if kind == "revolute"]
    origin = np.zeros(3)
    if revolute:
        origin = robot.joint_origins(default_q0(robot)[None])[0, revolute[0]]
    return Plane(e1=e1, e2=e2, n=n, origin=origin, labels=labels)


# ---------------------------------------------------------------------- the grid
@dataclass(frozen=True, eq=False)
class OccupancyGrid:
    """Square cells of the plane that hold at least one sample.

    An empty cell whose four neighbours hold samples is counted as occupied: a gap of one
    cell is a sampling gap (joint-uniform samples are sparse in places), below the grid's
    resolution.

    Attributes:
        origin: (2,) plane coordinates [m] of the lower corner of cell (0, 0).
        cell: side of a cell [m].
        occupied: (nu, nv) True where a sample fell (or a lone gap was filled).
    """

    origin: Array
    cell: float
    occupied: NDArray[np.bool_]

    @classmethod
    def from_points(cls, uv: Array, cell: float) -> OccupancyGrid:
        """Grid of the points ``uv`` (m, 2) [m] with cells of side ``cell`` [m].

        Raises:
            InputError: the grid would exceed :data:`MAX_CELLS` cells.
        """
        lo = uv.min(axis=0)
        shape = np.floor((uv.max(axis=0) - lo) / cell).astype(np.int64) + 1
        if shape[0] * shape[1] > MAX_CELLS:
            span = float(np.max(uv.max(axis=0) - lo))
            raise InputError(
                f"grid cell {cell:.3g} m is too small for a workspace {span:.3g} m across "
                f"({shape[0]} x {shape[1]} cells > {MAX_CELLS}); pass a larger grid= or None")
        idx = np.minimum(np.floor((uv - lo) / cell).astype(np.int64), shape - 1)
        occupied = np.zeros(tuple(shape), dtype=bool)
        occupied[idx[:, 0], idx[:, 1]] = True
        # a lone empty cell amid occupied ones is a sampling gap, below the grid's resolution
        occupied |= _surrounded(occupied)
        return cls(origin=lo, cell=float(cell), occupied=occupied)

    @property
    def interior(self) -> NDArray[np.bool_]:
        """(nu, nv) occupied cells whose four neighbours are occupied too."""
        return self.occupied & _surrounded(self.occupied)

    @property
    def area(self) -> float:
        """Area [m²]: interior cells in full, edge cells by half (see the module docstring)."""
        inner = int(self.interior.sum())
        edge = int(self.occupied.sum()) - inner
        return self.cell**2 * (inner + 0.5 * edge)

    @property
    def area_uncertainty(self) -> float:
        """Half-width [m²] of the area's interval: half the area of the edge cells."""
        inner = int(self.interior.sum())
        return 0.5 * self.cell**2 * (int(self.occupied.sum()) - inner)

    def lookup(self, uv: Array) -> NDArray[np.bool_]:
        """(m,) True where the points ``uv`` (m, 2) [m] fall into an occupied cell."""
        idx = np.floor((uv - self.origin) / self.cell)
        inside = np.all((idx >= 0) & (idx < self.occupied.shape), axis=1)
        out = np.zeros(uv.shape[0], dtype=bool)
        k = idx[inside].astype(np.int64)
        out[inside] = self.occupied[k[:, 0], k[:, 1]]
        return out


def _surrounded(occupied: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """(nu, nv) True where all four neighbours of a cell are occupied (none on the border)."""
    out = np.zeros_like(occupied)
    o = occupied
    out[1:-1, 1:-1] = o[:-2, 1:-1] & o[2:, 1:-1] & o[1:-1, :-2] & o[1:-1, 2:]
    return out


def _auto_cell(uv: Array) -> float:
    """Cell side [m] holding about :data:`SAMPLES_PER_CELL` samples (two passes)."""
    m = uv.shape[0]
    span = np.maximum(uv.max(axis=0) - uv.min(axis=0), 0.0)
    if span.min() <= 1e-12:  # the projection is a point or a segment: no area to resolve
        return max(float(span.max()), 1e-6) / 100.0
    coarse = math.sqrt(SAMPLES_PER_CELL * float(span.prod()) / m)  # the box's area: coarser
    rough = OccupancyGrid.from_points(uv, coarse).area
    return min(coarse, math.sqrt(SAMPLES_PER_CELL * rough / m))


def _column_extremes(A: Array) -> Array:
    """(2, k) least and greatest value of each column of ``A`` (m, k).

    Column by column: numpy reduces a C-ordered (m, 3) array over axis 0 with an inner
    loop three long, ~20x slower at 60,000 rows (issue 18).
    """
    return np.array([[c.min() for c in A.T], [c.max() for c in A.T]])


# ---------------------------------------------------------------------- the result
@dataclass(frozen=True, eq=False)
class Workspace:
    """A Monte Carlo workspace (see :func:`workspace` and the module docstring).

    Every range is measured over the kept samples (slightly inside the true extremes).

    Attributes:
        robot: the robot sampled.
        points: (m, 3) tip positions [m] of the kept samples (m <= n_samples).
        q: (m, nq) their configurations [rad or m].
        n_samples: number of configurations drawn.
        seed: the seed they were drawn with.
        plane: the plane of motion and the base axis (:class:`Plane`).
        footprint: the exclusion zone applied, or ``None``.
        grid: the occupancy grid of the plane (:class:`OccupancyGrid`).
        bounds: (2, 3) lower and upper corner of the bounding box [m].
        z_range: (min, max) world z [m].
        height_range: (min, max) height along the plane normal [m] (= ``z_range`` for a
            SCARA with an upward axis).
        radial_range: (min, max) distance from the base axis [m].
        xy_area: area of the projection on the plane [m²] (from ``grid``); see
            :attr:`xy_area_uncertainty`.
        contains_method: ``"closed_form"`` or ``"grid"``: how :meth:`contains` decides.
    """

    robot: Robot
    points: Array
    q: Array
    n_samples: int
    seed: object
    plane: Plane
    footprint: Footprint | None
    grid: OccupancyGrid
    bounds: Array
    z_range: tuple[float, float]
    height_range: tuple[float, float]
    radial_range: tuple[float, float]
    xy_area: float
    contains_method: str

    @property
    def n_dropped(self) -> int:
        """Samples dropped because a link passed through the footprint."""
        return self.n_samples - self.points.shape[0]

    @property
    def cell(self) -> float:
        """Side of a grid cell [m]."""
        return self.grid.cell

    @property
    def xy_area_uncertainty(self) -> float:
        """Half-width [m²] of the interval the grid pins :attr:`xy_area` down to.

        The edge of the region could run anywhere through the edge cells (counted by half),
        so the area lies within ``xy_area ± xy_area_uncertainty`` as far as the grid resolves
        the region (see the module docstring); 0 for a projection without area.
        """
        return 0.0 if self.xy_area == 0.0 else self.grid.area_uncertainty

    def __repr__(self) -> str:
        lo, hi = self.radial_range
        return (f"Workspace({self.robot.name!r}, samples={self.points.shape[0]}/"
                f"{self.n_samples}, xy_area={self.xy_area:.5g} ± "
                f"{self.xy_area_uncertainty:.2g} m², radius=[{lo:.4g}, {hi:.4g}] m, "
                f"contains={self.contains_method})")

    def contains(self, points: object) -> NDArray[np.bool_]:
        """Whether the robot reaches each point (see the module docstring for the method).

        Args:
            points: (m, 3) world positions [m].

        Returns:
            (m,) bool.

        Raises:
            InputError: not an (m, 3) array, or non-finite entries (the rows are named).
        """
        P = _check_points(points)
        if self.contains_method == "closed_form":
            return _closed_form_contains(self.robot, P, self.plane, self.footprint)
        h = self.plane.height(P)
        lo, hi = self.height_range
        return (h >= lo) & (h <= hi) & self.grid.lookup(self.plane.coords(P))

    def plot_xy(self, path: str | Path, title: str | None = None) -> Path:
        """Save the projection on the plane as a PNG (zavar2024 Fig. 3a, peng2025 Fig. 3/6).

        Draws the samples, the occupied grid cells (light), the footprint (dashed) and the
        base axis (+). Axes in metres.

        Args:
            path: ``.png`` file to write; its folder must exist.
            title: figure title; default names the robot, sample count and area.

        Returns:
            The path written.

        Raises:
            InputError: not a ``.png`` path, or its folder does not exist.
        """
        fig, out = _figure(path)
        ax = fig.add_subplot()
        g, (lu, lv, _) = self.grid, self.plane.labels
        corner = g.origin + g.cell * np.array(g.occupied.shape)
        ax.imshow(g.occupied.T, origin="lower", cmap="Greys", vmin=0, vmax=4, aspect="equal",
                  extent=(g.origin[0], corner[0], g.origin[1], corner[1]), interpolation="none")
        uv = self.plane.coords(self.points)
        ax.scatter(uv[:, 0], uv[:, 1], s=0.2, c="tab:blue", alpha=0.5, linewidths=0,
                   rasterized=True)
        ax.plot([], [], ".", color="tab:blue", label=f"{uv.shape[0]} samples")
        ax.plot([], [], "s", color="lightgrey", label=f"grid, {g.cell * 1e3:.3g} mm cells")
        if self.footprint is not None:
            ring = self.footprint.outline()
            ax.plot(ring[:, 0], ring[:, 1], "r--", lw=1.2, label="base footprint")
        base = self.plane.coords(self.plane.origin)
        ax.plot(base[0], base[1], "k+", ms=10, label="base axis")
        ax.set_xlabel(f"{lu} [m]")
        ax.set_ylabel(f"{lv} [m]")
        ax.set_aspect("equal")
        ax.legend(loc="upper right", fontsize=8)
        ax.set_title(title or f"{self.robot.name}: workspace, {lu}{lv} projection, "
                     f"area {self.xy_area:.4f} m²")
        fig.savefig(out, dpi=150)
        return out

    def plot_3d(self, path: str | Path, title: str | None = None) -> Path:
        """Save the sample cloud in 3D as a PNG (zavar2024 Fig. 3b, peng2025 Fig. 4).

        Args:
            path: ``.png`` file to write; its folder must exist.
            title: figure title; default names the robot and the sample count.

        Returns:
            The path written.

        Raises:
            InputError: not a ``.png`` path, or its folder does not exist.
        """
        from matplotlib.ticker import MaxNLocator

        fig, out = _figure(path)
        ax = fig.add_subplot(projection="3d")
        P = self.points
        cloud = ax.scatter(P[:, 0], P[:, 1], P[:, 2], s=0.2, c=P[:, 2], cmap="viridis",
                           linewidths=0, rasterized=True)
        fig.colorbar(cloud, ax=ax, shrink=0.6, label="z [m]")
        span = np.maximum(np.ptp(P, axis=0), 1e-9)
        span[2] = max(span[2], 0.25 * span[:2].max())  # true x:y; a flat slab stays readable
        ax.set_box_aspect(tuple(span))
        ax.zaxis.set_major_locator(MaxNLocator(4))
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(title or f"{self.robot.name}: Monte Carlo workspace, "
                     f"{P.shape[0]} samples")
        fig.savefig(out, dpi=150)
        return out


def _figure(path: str | Path) -> tuple[Any, Path]:
    """A new Agg-backed matplotlib Figure (no pyplot, no global state) and the checked path."""
    out = Path(path)
    if out.suffix.lower() != ".png":
        raise InputError(f"plots are saved as PNG: pass a path ending in .png; got {str(out)!r}")
    if not out.parent.is_dir():
        raise InputError(f"folder {str(out.parent)!r} does not exist; create it first")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 5.6), layout="constrained")
    FigureCanvasAgg(fig)
    return fig, out


def _check_points(points: object) -> Array:
    try:
        P = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"points must be a numeric (m, 3) array [m]; got {points!r}") from None
    if P.ndim != 2 or P.shape[1] != 3:
        raise InputError(f"points must have shape (m, 3), one world position [m] per row "
                         f"(a single point as [[x, y, z]]); got shape {P.shape}")
    bad = ~np.isfinite(P).all(axis=1)
    if bad.any():
        raise InputError(f"points has NaN or inf in rows {np.flatnonzero(bad)[:10].tolist()}; "
                         "pass finite positions")
    return P


def _closed_form(robot: Robot) -> bool:
    """Whether the closed form decides reachability of the whole robot (no redundant joint)."""
    try:
        return not scara_geometry(robot).redundant
    except NotScaraError:
        return False


def _closed_form_contains(robot: Robot, P: Array, plane: Plane,
                          footprint: Footprint | None) -> NDArray[np.bool_]:
    if P.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    Q, valid = solve_batch(robot, P)
    if footprint is not None and valid.any():
        rows, branch = np.nonzero(valid)
        valid[rows, branch] = ~footprint.blocks_arms(robot, plane,
                                                     robot.joint_origins(Q[rows, branch]))
    return valid.any(axis=1)


def _tips_clear_of(robot: Robot, zone: Footprint, plane: Plane,
                   Q: Array) -> tuple[Array, NDArray[np.bool_]]:
    """Tip positions (n, 3) [m] of ``Q`` (n, nq) and (n,) True where the arm clears ``zone``.

    A circle is tested in its compiled kernel with the FK
    (:meth:`~scara_opt.footprint.Footprint.kernel`); a polygon on the chains of joint
    origins (:meth:`~scara_opt.footprint.Footprint.blocks_arms`).
    """
    kernel = zone.kernel(robot, plane)
    if kernel is not None:
        rows = batch_fk.evaluate_function(robot, kernel, robot.check_q_batch(Q))
        return rows[:, :3], rows[:, 3] == 0.0
    chain = robot.joint_origins(Q)
    return chain[:, -1], ~zone.blocks_arms(robot, plane, chain)


# ---------------------------------------------------------------------- the entry point
def bytes_per_sample(robot: Robot) -> int:
    """Estimated peak memory of one workspace sample [bytes].

    ``q``, the position, the joint origins and the FK's temporaries; measured peaks: 216 B
    (zavar2024), 488 B with peng2025's footprint check, 352 B for a 6-joint arm.
    """
    return 8 * (2 * robot.nq + 6 * (len(robot.chain) + 1) + 27)


def _check_args(robot: object, n: object, grid: object, footprint: object) -> int:
    """The checked arguments of :func:`workspace`; returns the memory estimate [bytes]."""
    robot = check_robot(robot)
    if (isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer))
            or n < MIN_SAMPLES):
        raise InputError(f"n (number of samples) must be an integer >= {MIN_SAMPLES}, e.g. "
                         f"60_000 (fewer give no usable area, see Workspace.xy_area_uncertainty); "
                         f"got {describe(n)}")
    if grid is not None:  # an int beyond any float counts as infinite, refused
        check_real("grid (cell size, or None: automatic)", grid, 0.0, low_open=True, unit="m")
    if not isinstance(footprint, (bool, Footprint)) and footprint is not None:
        raise InputError(f"footprint must be True (the robot file's), False/None, or a "
                         f"Footprint; got {describe(footprint)}")
    return check_memory(f"workspace(n={count_text(int(n))})", int(n), bytes_per_sample(robot),
                        "lower n (the papers use 60_000)")


def workspace(robot: Robot, n: int = 60_000, seed: int | np.random.Generator | None = 0,
              grid: float | None = None, footprint: bool | Footprint | None = True) -> Workspace:
    """Monte Carlo workspace: ``n`` joint samples, uniform within the limits, FK as one batch.

    Args:
        robot: the robot.
        n: number of configurations to draw, at least :data:`MIN_SAMPLES` (peng2025 uses
            60,000). The memory needed, ``n`` × :func:`bytes_per_sample`, is estimated
            first and refused above :data:`scara_opt.checks.MAX_BYTES` (raise it to go
            beyond on purpose).
        seed: seed (or generator) of the samples: same seed, same points.
        grid: side of the occupancy-grid cells [m]; ``None`` picks it so a cell holds about
            :data:`SAMPLES_PER_CELL` samples on average.
        footprint: ``True`` applies the exclusion zone of the robot file (if it declares
            one), ``False``/``None`` none, or pass a :class:`Footprint`.

    Returns:
        The :class:`Workspace`.

    Raises:
        InputError: ``n`` below :data:`MIN_SAMPLES` or not an integer, more samples than
            :data:`scara_opt.checks.MAX_BYTES` of memory allow (the message gives the
            estimate), a negative ``seed``, a bad ``grid`` (or one larger than the
            workspace) or ``footprint``, or a footprint that blocks every sample.
        URDFError: a malformed ``[footprint]`` table in the robot file.
    """
    estimate = _check_args(robot, n, grid, footprint)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(
        check_seed(seed))
    zone = Footprint.from_robot(robot) if footprint is True else (footprint or None)
    plane = workspace_plane(robot)
    with memory_guard(f"workspace(n={int(n):,})", estimate, "lower n"):
        Q = _uniform(rng, robot.sampling_lower, robot.sampling_upper, int(n))
        if zone is None:
            P = robot.positions(Q)
            uv = plane.coords(P)
        else:
            P, keep = _tips_clear_of(robot, zone, plane, Q)
            if not keep.any():
                raise InputError(f"the footprint blocks all {n} samples of robot "
                                 f"{robot.name!r}; check its center/vertices, radius and "
                                 "links_from")
            Q, P = Q[keep], P[keep]
            uv = plane.coords(P)  # (2, m) rows for the reductions
    span = float(np.ptp(uv, axis=0).max())
    if grid is not None and 0.0 < span < grid:
        raise InputError(f"grid cell {grid:g} m is larger than the workspace ({span:.3g} m "
                         f"across): the area would be a cell or two; pass a cell well below "
                         f"{span:.3g} m, or grid=None (automatic)")
    cell = _auto_cell(uv) if grid is None else float(grid)
    occupancy = OccupancyGrid.from_points(uv, cell)
    flat = float(np.ptp(uv, axis=0).min()) <= 1e-12  # a point or a segment: no area
    o = plane.coords(plane.origin)  # the radius from the plane coordinates already made
    h, r = plane.height(P), np.hypot(uv[:, 0] - o[0], uv[:, 1] - o[1])
    return Workspace(
        robot=robot, points=P, q=Q, n_samples=int(n), seed=seed, plane=plane, footprint=zone,
        grid=occupancy, bounds=_column_extremes(P),
        z_range=(float(P[:, 2].min()), float(P[:, 2].max())),
        height_range=(float(h.min()), float(h.max())),
        radial_range=(float(r.min()), float(r.max())), xy_area=0.0 if flat else occupancy.area,
        contains_method="closed_form" if _closed_form(robot) else "grid",
    )
