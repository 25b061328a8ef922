"""Figures of timed trajectories: q, qd, qdd per joint with their limits, saved as PNG."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from scara_opt.trajectory.trajectory import Trajectory

_ROWS = (("q", "", None), ("qd", "/s", "vmax"), ("qdd", "/s²", "amax"))
_LIMIT_NAMES = {"vmax": "± velocity limit", "amax": "± acceleration limit"}


def new_figure(nrows: int, ncols: int, size: tuple[float, float] = (3.2, 2.4)) -> Figure:
    """A figure on the Agg canvas (no pyplot state, no display needed).

    Args:
        nrows: rows of subplots it will hold.
        ncols: columns of subplots it will hold.
        size: (width, height) of one subplot [inch].
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(size[0] * ncols, size[1] * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def plot_trajectories(trajectories: Sequence[Trajectory], path: str | Path,
                      labels: Sequence[str] | None = None, dt: float | None = None,
                      title: str | None = None) -> Path:
    """Save one PNG comparing trajectories of the same robot: rows q, qd, qdd; a column per joint.

    Velocity and acceleration limits of the first trajectory are drawn as dashed lines,
    position limits (when finite) as dotted lines.

    Args:
        trajectories: trajectories with the same joints.
        path: the PNG file to write (its folder is created).
        labels: one legend label per trajectory; default: their methods.
        dt: sampling step [s]; default: 1/500 of the longest duration.
        title: figure title.

    Returns:
        The path written.
    """
    first = trajectories[0]
    lim = first.limits
    labels = list(labels) if labels is not None else [tr.method for tr in trajectories]
    step = dt or max(tr.duration for tr in trajectories) / 500
    fig = new_figure(3, first.nq)
    axes = fig.subplots(3, first.nq, squeeze=False, sharex=True)
    for tr, label in zip(trajectories, labels, strict=True):
        t = tr.times(step)
        values = tr.sample(t)
        for r in range(len(_ROWS)):
            for k in range(tr.nq):
                axes[r, k].plot(t, values[r][:, k], label=f"{label} ({tr.duration:.3f} s)")
    for k, name in enumerate(lim.joint_names):
        unit = lim.unit(k)
        for r, (sym, per, bound) in enumerate(_ROWS):
            ax = axes[r, k]
            ax.set_ylabel(f"{sym} [{unit}{per}]")
            if bound is not None:
                val = getattr(lim, bound)[k]
                for sign in (-1, 1):
                    ax.axhline(sign * val, color="k", ls="--", lw=0.8,
                               label=_LIMIT_NAMES[bound] if sign > 0 else None)
            elif np.isfinite(lim.lower[k]) and np.isfinite(lim.upper[k]):
                for val, side in ((lim.lower[k], "lower"), (lim.upper[k], "upper")):
                    ax.axhline(val, color="k", ls=":", lw=0.8, label=f"{side} position limit")
            ax.grid(True, lw=0.3)
        axes[0, k].set_title(name)
        axes[-1, k].set_xlabel("t [s]")
    handles: dict[str, Any] = {}
    for ax in axes[:, 0]:
        for h, lb in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lb, h)
    axes[0, 0].legend(list(handles.values()), list(handles), fontsize="x-small")
    fig.suptitle(title or ", ".join(f"{lb}: {tr.duration:.3f} s"
                                    for tr, lb in zip(trajectories, labels, strict=True)))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    return path


def plot_trajectory(trajectory: Trajectory, path: str | Path, dt: float | None = None,
                    title: str | None = None) -> Path:
    """Save a PNG of one trajectory (see :func:`plot_trajectories`)."""
    return plot_trajectories([trajectory], path, dt=dt,
                             title=title or f"{trajectory.method}: {trajectory.duration:.3f} s")
