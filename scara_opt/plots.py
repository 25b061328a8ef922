"""Figures: the arm as a stick figure, path animations, and the comparison plots of the papers.

Every function draws with matplotlib's object API and saves to a file when given a path;
nothing is shown on screen (use the Agg backend on machines without a display).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from scara_opt.comparison import takes_budget
from scara_opt.ik.registry import method_label

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.axes3d import Axes3D

    from scara_opt.model.robot import Robot
    from scara_opt.target import Target
    from scara_opt.trajectory.path import JointPath


def _figure(**kw: Any) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)


def _axes3d(fig: Figure) -> Axes3D:
    """A new 3-D axes filling ``fig``."""
    from mpl_toolkits.mplot3d.axes3d import Axes3D

    ax = fig.add_subplot(projection="3d")
    assert isinstance(ax, Axes3D), "projection='3d' makes an Axes3D"  # (typed as Axes)
    return ax


def root_figure(ax: Axes) -> Figure:
    """The figure to save for ``ax``: its own, or the top one when ``ax`` is in a subfigure."""
    return ax.figure.figure  # a SubFigure's .figure is the root Figure, a Figure's is itself


def _save(fig: Figure, path: str | Path | None) -> Path | None:
    if path is None:
        return None
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    return path


def draw_robot(robot: Robot, q: ArrayLike, ax: Axes3D | None = None,
               path: str | Path | None = None, color: str = "C0", label: str | None = None,
               title: str | None = None) -> Axes3D:
    """Draw the arm at ``q`` as a 3-D stick figure through every joint origin and the tip.

    Args:
        robot: the robot.
        q: (nq,) joint values [rad or m].
        ax: a 3-D axes to draw into; a new figure is made when ``None``.
        path: save the figure here (PNG) when given.
        color: line colour.
        label: legend label.
        title: axes title; default: the robot's name.

    Returns:
        The axes drawn into.
    """
    pts = robot.joint_origins(np.atleast_2d(robot.check_q(q)))[0] * 1000.0
    if ax is None:
        ax = _axes3d(_figure(figsize=(6, 5)))
    ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], "-o", color=color, lw=3, ms=5, label=label)
    first = not any(line.get_label() == "base" for line in ax.lines)
    ax.plot([pts[0, 0]], [pts[0, 1]], [pts[0, 2]], "ks", ms=9, label="base" if first else None)
    ax.plot([pts[-1, 0]], [pts[-1, 1]], [pts[-1, 2]], "*", color="C3", ms=12,
            label="tool tip" if first else None)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_title(title or robot.name, fontsize=10)
    ax.legend(fontsize="small")
    _set_equal(ax)
    _save(root_figure(ax), path)
    return ax


def _set_equal(ax: Axes3D) -> None:
    """Equal scale on the three axes of a 3-D plot."""
    lims = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])
    center, half = lims.mean(axis=1), (lims[:, 1] - lims[:, 0]).max() / 2
    ax.set_xlim3d(center[0] - half, center[0] + half)
    ax.set_ylim3d(center[1] - half, center[1] + half)
    ax.set_zlim3d(center[2] - half, center[2] + half)


def animate(robot: Robot, joint_path: JointPath | ArrayLike, path_to_gif: str | Path,
            fps: int = 10, targets: Sequence[Target] | ArrayLike | None = None) -> Path:
    """Animate the arm along a joint path and save a GIF.

    Args:
        robot: the robot.
        joint_path: a :class:`~scara_opt.trajectory.path.JointPath` or an (n, nq) array.
        path_to_gif: output file (``.gif``).
        fps: frames per second.
        targets: optional path to follow, drawn dotted: :class:`~scara_opt.Target` objects
            or an (m, 3) array of points [m].

    Returns:
        The path of the saved GIF.

    Raises:
        InputError: a file name not ending in ``.gif``, ``fps`` not a positive integer,
            or a malformed joint path or ``targets``.
    """
    from matplotlib.animation import FuncAnimation, PillowWriter

    from scara_opt.errors import InputError

    out = Path(path_to_gif)
    if out.suffix.lower() != ".gif":
        raise InputError(f"animate writes a GIF; name the file *.gif, not {out.name!r}")
    if not (isinstance(fps, (int, np.integer)) and fps > 0):
        raise InputError(f"fps must be a positive integer; got {fps!r}")
    Q = np.asarray(getattr(joint_path, "q", joint_path), dtype=float)
    pts = robot.joint_origins(robot.check_q_batch(Q)) * 1000.0
    fig = _figure(figsize=(6, 5))
    ax = _axes3d(fig)
    lo, hi = pts.reshape(-1, 3).min(axis=0), pts.reshape(-1, 3).max(axis=0)
    ax.set_xlim3d(lo[0], hi[0])
    ax.set_ylim3d(lo[1], hi[1])
    ax.set_zlim3d(lo[2], hi[2])
    _set_equal(ax)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    if targets is not None:
        from scara_opt.paths import as_targets

        T = np.array([t.position for t in as_targets(targets)]) * 1000.0
        ax.plot(T[:, 0], T[:, 1], T[:, 2], ":", color="0.5")
    (arm,) = ax.plot([], [], [], "-o", lw=3, color="C0")
    (trace,) = ax.plot([], [], [], "-", color="C3")

    def frame(k: int) -> tuple:
        arm.set_data_3d(pts[k, :, 0], pts[k, :, 1], pts[k, :, 2])
        trace.set_data_3d(pts[: k + 1, -1, 0], pts[: k + 1, -1, 1], pts[: k + 1, -1, 2])
        ax.set_title(f"{robot.name}: point {k + 1}/{len(pts)}")
        return arm, trace

    out.parent.mkdir(parents=True, exist_ok=True)
    FuncAnimation(fig, frame, frames=len(pts), blit=False).save(out, writer=PillowWriter(fps=fps))
    return out


def plot_convergence(curves: Mapping[tuple[str, Any], np.ndarray], path: str | Path | None = None,
                     title: str = "best cost per iteration") -> Figure:
    """One panel per method: median best-cost histories (zavar2024 Fig. 4), log scale."""
    methods = sorted({m for m, _ in curves})
    fig = _figure(figsize=(4 * min(3, len(methods)), 3.2 * ((len(methods) + 2) // 3)))
    for i, method in enumerate(methods):
        ax = fig.add_subplot((len(methods) + 2) // 3, min(3, len(methods)), i + 1)
        for (m, pop), h in sorted(curves.items(), key=lambda kv: kv[0][1] or 0):
            if m == method:
                ax.semilogy(np.arange(1, len(h) + 1), np.maximum(h, 1e-17),
                            label=f"pop {pop}" if pop is not None else m)
        ax.set_title(method_label(method))
        ax.set_xlabel("iteration")
        ax.set_ylabel("cost [m]")
        ax.legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    _save(fig, path)
    return fig


def plot_time_vs_population(summary: pd.DataFrame, path: str | Path | None = None,
                            title: str = "median time per solve") -> Figure:
    """Median time per solve against population size, one line per method (zavar2024 Fig. 5)."""
    fig = _figure(figsize=(6, 4))
    ax = fig.add_subplot()
    pop = summary.dropna(subset=["population"])
    for method, grp in pop.groupby("method", sort=True):
        ax.plot(grp["population"], grp["time_s"] * 1e3, "-o", label=method_label(str(method)))
    ax.set_xlabel("population")
    ax.set_ylabel("median time per solve [ms]\n(one-off setup excluded)")
    ax.set_yscale("log")
    ax.legend()
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    _save(fig, path)
    return fig


#: axis labels of :func:`scara_opt.comparison.compare` columns (SI units)
LABELS = {"abs_err_x": "|x error| [m]", "abs_err_y": "|y error| [m]",
          "abs_err_z": "|z error| [m]", "yaw_error": "|tool-angle error| [rad]",
          "error": "error [m, or m and rad]", "cost": "cost, eq. (8) [m]",
          "time_s": "time per solve [s]", "setup_s": "one-off setup [s]"}


def _label(column: str) -> str:
    return LABELS.get(column, column)


def plot_boxes(table: pd.DataFrame, columns: Sequence[str], path: str | Path | None = None,
               by: str = "method", log: bool = True, title: str = "") -> Figure:
    """Box plots of ``columns`` grouped by ``by``, one panel per column, over all runs."""
    fig = _figure(figsize=(3.6 * len(columns), 3.9))
    groups = sorted(table[by].unique())
    for i, col in enumerate(columns):
        ax = fig.add_subplot(1, len(columns), i + 1)
        data = [np.maximum(table.loc[table[by] == g, col].to_numpy(float), 1e-17) for g in groups]
        ticks = [method_label(str(g)) if by == "method" else str(g) for g in groups]
        ax.boxplot(data, tick_labels=ticks)
        if log:
            ax.set_yscale("log")
        ax.set_ylabel(_label(col))
        for tick in ax.get_xticklabels():
            tick.set(rotation=45, ha="right", rotation_mode="anchor")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    _save(fig, path)
    return fig


def plot_path_runs(table: pd.DataFrame, columns: Sequence[str], path: str | Path | None = None,
                   title: str = "") -> Figure:
    """A path rerun by several methods (zavar2024 Fig. 7), one line per method.

    Where each point was reached, and each of ``columns`` per path point (median over seeds,
    log scale).

    ``table`` is :func:`scara_opt.comparison.compare`'s, the targets in path order. The first
    panel is the xy plane [m]: target points as open circles, each run's reached point as a
    dot of its method's colour. Exact zeros are drawn at 1e-17 (a log axis has no zero); the
    exact methods are dashed.
    """
    methods = sorted(table["method"].unique())
    ncol = 3
    nrow = (len(columns) + 1 + ncol - 1) // ncol
    fig = _figure(figsize=(5.2 * ncol, 4.0 * nrow + 0.8))
    style = {m: {"color": f"C{i % 10}", "ls": "-" if takes_budget(m) else "--"}
             for i, m in enumerate(methods)}
    ax = fig.add_subplot(nrow, ncol, 1)
    points = table.drop_duplicates("target").sort_values("target")
    for m in methods:
        runs = table[table["method"] == m]
        ax.plot(runs["reached_x"], runs["reached_y"], ".", ms=5, color=style[m]["color"])
    ax.plot(points["x"], points["y"], "o", mfc="none", mec="k", ms=11, label="target point")
    for _, p in points.iterrows():
        ax.annotate(str(int(p["target"]) + 1), (p["x"], p["y"]), fontsize=7,
                    xytext=(6, 6), textcoords="offset points")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("targets (circles) and every run's reached point (dots)")
    handles = ax.get_legend_handles_labels()
    for i, col in enumerate(columns):
        ax = fig.add_subplot(nrow, ncol, i + 2)
        for m in methods:
            med = table[table["method"] == m].groupby("target")[col].median()
            ax.semilogy(med.index + 1, np.maximum(med.to_numpy(float), 1e-17), marker="o",
                        ms=3, label=method_label(m), **style[m])
        ax.set_xlabel("path point")
        ax.set_ylabel(_label(col))
        ax.set_title(f"{_label(col).split(' [')[0]} per point, median over seeds", fontsize=10)
    lines, labels = ax.get_legend_handles_labels()
    fig.legend(handles[0] + lines, handles[1] + labels, loc="lower center",
               ncol=len(methods) + 1, fontsize=9)
    fig.text(0.995, 0.005, "log axes: exact zeros drawn at 1e-17", ha="right", fontsize=7)
    if title:
        fig.suptitle(title)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    _save(fig, path)
    return fig
