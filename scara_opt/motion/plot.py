"""Figure of a planned motion: tool speed (FK, 1 kHz) and each joint's position and velocity."""

from __future__ import annotations

from pathlib import Path

from scara_opt.model.robot import Robot
from scara_opt.motion.tool_limits import tool_peaks
from scara_opt.trajectory.trajectory import Trajectory


def plot_motion(robot: Robot, traj: Trajectory, path: str | Path, title: str = "") -> Path:
    """Save a PNG: tool speed [m/s] over time, then q and qd per joint; returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = traj.times(1e-3)
    q, qd, _ = traj.sample(t)
    speed = tool_peaks(robot, q, float(t[1] - t[0]))["speed"]
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    axes[0].plot((t[1:] + t[:-1]) / 2, speed)
    axes[0].set_ylabel("tool speed [m/s]")
    for k, name in enumerate(traj.limits.joint_names):
        unit = traj.limits.unit(k)
        axes[1].plot(t, q[:, k], label=f"{name} [{unit}]")
        axes[2].plot(t, qd[:, k] / traj.limits.vmax[k], label=name)
    axes[1].set_ylabel("q")
    axes[2].set_ylabel("qd / vmax")
    axes[2].set_xlabel("time [s]")
    for ax in axes[1:]:
        ax.legend(fontsize="small", loc="upper right")
    for tw in traj.waypoint_times:
        for ax in axes:
            ax.axvline(tw, color="0.85", lw=0.8, zorder=0)
    fig.suptitle(title or f"{traj.duration:.4f} s")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = ["plot_motion"]
