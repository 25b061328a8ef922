"""A workspace's figures: the projection on the plane and the 3D sample cloud, as PNG.

Drawn on Agg-backed matplotlib Figures (no pyplot, no global state); called by
:meth:`Workspace.plot_xy <scara_opt.workspace_analysis.result.Workspace.plot_xy>` and
:meth:`~scara_opt.workspace_analysis.result.Workspace.plot_3d`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from scara_opt.errors import InputError

if TYPE_CHECKING:
    from scara_opt.workspace_analysis.result import Workspace


def plot_xy(ws: Workspace, path: str | Path, title: str | None = None) -> Path:
    """Save the projection of ``ws`` on its plane as a PNG (see ``Workspace.plot_xy``)."""
    fig, out = _figure(path)
    ax = fig.add_subplot()
    g, (lu, lv, _) = ws.grid, ws.plane.labels
    corner = g.origin + g.cell * np.array(g.occupied.shape)
    ax.imshow(g.occupied.T, origin="lower", cmap="Greys", vmin=0, vmax=4, aspect="equal",
              extent=(g.origin[0], corner[0], g.origin[1], corner[1]), interpolation="none")
    uv = ws.plane.coords(ws.points)
    ax.scatter(uv[:, 0], uv[:, 1], s=0.2, c="tab:blue", alpha=0.5, linewidths=0,
               rasterized=True)
    ax.plot([], [], ".", color="tab:blue", label=f"{uv.shape[0]} samples")
    ax.plot([], [], "s", color="lightgrey", label=f"grid, {g.cell * 1e3:.3g} mm cells")
    if ws.footprint is not None:
        ring = ws.footprint.outline()
        ax.plot(ring[:, 0], ring[:, 1], "r--", lw=1.2, label="base footprint")
    base = ws.plane.coords(ws.plane.origin)
    ax.plot(base[0], base[1], "k+", ms=10, label="base axis")
    ax.set_xlabel(f"{lu} [m]")
    ax.set_ylabel(f"{lv} [m]")
    ax.set_aspect("equal")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title or f"{ws.robot.name}: workspace, {lu}{lv} projection, "
                 f"area {ws.xy_area:.4f} m²")
    fig.savefig(out, dpi=150)
    return out


def plot_3d(ws: Workspace, path: str | Path, title: str | None = None) -> Path:
    """Save the sample cloud of ``ws`` in 3D as a PNG (see ``Workspace.plot_3d``)."""
    from matplotlib.ticker import MaxNLocator

    fig, out = _figure(path)
    ax = fig.add_subplot(projection="3d")
    P = ws.points
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
    ax.set_title(title or f"{ws.robot.name}: Monte Carlo workspace, "
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
