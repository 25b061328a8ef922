"""Workspace by Monte Carlo: reach, the base's exclusion zone, reachability queries, plots.

``so.workspace(robot, n=60_000, seed=0)`` returns a :class:`Workspace`. The package, one
job a module:

* :mod:`~scara_opt.workspace_analysis.sampling`: :func:`workspace`, the seeded joint
  samples, their FK as one batch and the exclusion zone (peng2025 Sec. 3, Fig. 4–6);
* :mod:`~scara_opt.workspace_analysis.plane`: the plane of motion, its coordinates and the
  base axis (:class:`Plane`, :func:`workspace_plane`);
* :mod:`~scara_opt.workspace_analysis.grid`: the occupancy grid, the area and its
  uncertainty (:class:`OccupancyGrid`);
* :mod:`~scara_opt.workspace_analysis.reach`: whether points are reachable (exact by the
  closed form for non-redundant SCARAs, else from the grid);
* :mod:`~scara_opt.workspace_analysis.result`: the :class:`Workspace` result;
* :mod:`~scara_opt.workspace_analysis.figures`: its PNG figures.
"""

from scara_opt.workspace_analysis.grid import MAX_CELLS, SAMPLES_PER_CELL, OccupancyGrid
from scara_opt.workspace_analysis.plane import Plane, workspace_plane
from scara_opt.workspace_analysis.result import Workspace
from scara_opt.workspace_analysis.sampling import MIN_SAMPLES, bytes_per_sample, workspace

__all__ = ["MAX_CELLS", "MIN_SAMPLES", "SAMPLES_PER_CELL", "OccupancyGrid", "Plane",
           "Workspace", "bytes_per_sample", "workspace", "workspace_plane"]
