"""Whether a robot reaches given points: exact by the closed form where it decides.

**Reachability.** :meth:`Workspace.contains
<scara_opt.workspace_analysis.result.Workspace.contains>` is exact for SCARA-type robots
without a redundant joint (fang, peng2025, zavar2024): the closed form
(:func:`scara_opt.ik.analytic.solve_batch`) gives both elbow branches and a point counts as
reachable when one branch lies within the limits and, with a footprint, keeps its links
clear of it. Otherwise (nguyen and inverted5, whose redundant joint the closed form holds
fixed, and non-SCARA chains) it answers from the occupancy grid and the sampled height
range: accurate to about one cell at the edge of the region, and, for a chain whose height
depends on its planar position, an over-approximation (a box in height over the planar
region).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.errors import InputError
from scara_opt.footprint import Footprint
from scara_opt.ik.analytic import NotScaraError, scara_geometry, solve_batch
from scara_opt.model.robot import Array, Robot
from scara_opt.workspace_analysis.plane import Plane


def check_points(points: ArrayLike) -> Array:
    """``points`` as a float (m, 3) array of finite world positions [m].

    Raises:
        InputError: not an (m, 3) array, or non-finite entries (the rows are named).
    """
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


def closed_form_decides(robot: Robot) -> bool:
    """Whether the closed form decides reachability of the whole robot (no redundant joint)."""
    try:
        return not scara_geometry(robot).redundant
    except NotScaraError:
        return False


def closed_form_contains(robot: Robot, P: Array, plane: Plane,
                         footprint: Footprint | None) -> NDArray[np.bool_]:
    """(m,) True where an elbow branch of the closed form reaches ``P`` (m, 3) [m].

    A branch counts within the limits and, with ``footprint``, with its links clear of it.
    """
    if P.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    Q, valid = solve_batch(robot, P)
    if footprint is not None and valid.any():
        rows, branch = np.nonzero(valid)
        valid[rows, branch] = ~footprint.blocks_arms(robot, plane,
                                                     robot.joint_origins(Q[rows, branch]))
    return np.asarray(valid.any(axis=1))
