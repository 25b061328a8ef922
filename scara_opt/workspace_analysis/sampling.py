r"""Monte Carlo workspace: joint samples within the limits, their FK as one batch.

:func:`workspace` draws ``n`` configurations uniformly within the joint limits from a seeded
generator, evaluates the FK of all of them as one batch, drops those whose links pass
through the base's exclusion zone and returns a
:class:`~scara_opt.workspace_analysis.result.Workspace` (peng2025 Sec. 3, N = 60,000,
Fig. 4; zavar2024 Fig. 3): its plane (:mod:`~scara_opt.workspace_analysis.plane`), grid
and area (:mod:`~scara_opt.workspace_analysis.grid`).

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
from scara_opt.footprint import Footprint
from scara_opt.ik.base import check_seed
from scara_opt.model import batch_fk
from scara_opt.model.robot import Array, Robot, check_robot
from scara_opt.workspace_analysis.grid import OccupancyGrid, auto_cell
from scara_opt.workspace_analysis.plane import Plane, workspace_plane
from scara_opt.workspace_analysis.reach import closed_form_decides
from scara_opt.workspace_analysis.result import Workspace

#: fewest samples :func:`workspace` draws: below about 10 the area's uncertainty interval no
#: longer holds the exact area (:mod:`~scara_opt.workspace_analysis.grid`); 100 leaves a margin
MIN_SAMPLES = 100


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


def _column_extremes(A: Array) -> Array:
    """(2, k) least and greatest value of each column of ``A`` (m, k).

    Column by column: numpy reduces a C-ordered (m, 3) array over axis 0 with an inner
    loop three long, ~20x slower at 60,000 rows (issue 18).
    """
    return np.array([[c.min() for c in A.T], [c.max() for c in A.T]])


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
    cell = auto_cell(uv) if grid is None else float(grid)
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
        contains_method="closed_form" if closed_form_decides(robot) else "grid",
    )
