"""A Monte Carlo workspace: its samples, ranges and area, reachability queries, figures.

The result of :func:`~scara_opt.workspace_analysis.sampling.workspace`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.footprint import Footprint
from scara_opt.model.robot import Array, Robot
from scara_opt.workspace_analysis import figures
from scara_opt.workspace_analysis.grid import OccupancyGrid
from scara_opt.workspace_analysis.plane import Plane
from scara_opt.workspace_analysis.reach import check_points, closed_form_contains


@dataclass(frozen=True, eq=False)
class Workspace:
    """A Monte Carlo workspace (see :func:`~scara_opt.workspace_analysis.sampling.workspace`).

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
        the region (:mod:`~scara_opt.workspace_analysis.grid`); 0 for a projection without area.
        """
        return 0.0 if self.xy_area == 0.0 else self.grid.area_uncertainty

    def __repr__(self) -> str:
        lo, hi = self.radial_range
        return (f"Workspace({self.robot.name!r}, samples={self.points.shape[0]}/"
                f"{self.n_samples}, xy_area={self.xy_area:.5g} ± "
                f"{self.xy_area_uncertainty:.2g} m², radius=[{lo:.4g}, {hi:.4g}] m, "
                f"contains={self.contains_method})")

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether the robot reaches each point (how: :mod:`~scara_opt.workspace_analysis.reach`).

        Args:
            points: (m, 3) world positions [m].

        Returns:
            (m,) bool.

        Raises:
            InputError: not an (m, 3) array, or non-finite entries (the rows are named).
        """
        P = check_points(points)
        if self.contains_method == "closed_form":
            return closed_form_contains(self.robot, P, self.plane, self.footprint)
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
        return figures.plot_xy(self, path, title)

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
        return figures.plot_3d(self, path, title)
