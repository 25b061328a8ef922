"""Export a timed trajectory for a controller: JSON and a ROS ``JointTrajectory``-shaped dict/YAML.

Samples on the grid ``Trajectory.times(dt)`` (ending exactly at the duration), SI units
(rad or m, per s, per s²). The ROS form follows ``trajectory_msgs/JointTrajectory``:
``joint_names`` and ``points`` with ``positions``, ``velocities``, ``accelerations`` and
``time_from_start`` as ``{sec, nanosec}``; ROS is not needed to write or read it. The CSV
form is :meth:`~scara_opt.Trajectory.to_csv`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from scara_opt.checks import check_path
from scara_opt.trajectory.trajectory import Trajectory


def _units(traj: Trajectory) -> list[str]:
    return [traj.limits.unit(k) for k in range(traj.nq)]


def to_dict(traj: Trajectory, dt: float = 0.01) -> dict[str, Any]:
    """``{"joint_names", "units", "duration_s", "t_s", "q", "qd", "qdd"}`` sampled every ``dt``."""
    t = traj.times(dt)
    q, qd, qdd = traj.sample(t)
    return {"joint_names": list(traj.limits.joint_names), "units": _units(traj),
            "duration_s": traj.duration, "dt_s": float(dt), "t_s": t.tolist(),
            "q": q.tolist(), "qd": qd.tolist(), "qdd": qdd.tolist()}


def to_json(traj: Trajectory, path: str | Path, dt: float = 0.01) -> Path:
    """Write :func:`to_dict` as JSON; returns the path."""
    path = check_path("path", path)
    path.write_text(json.dumps(to_dict(traj, dt)))
    return path


def stamp(t: float) -> dict[str, int]:
    """``{"sec", "nanosec"}`` of a time ``t`` >= 0 [s], nanosec in [0, 1e9)."""
    ns = round(t * 1e9)
    return {"sec": int(ns // 1_000_000_000), "nanosec": int(ns % 1_000_000_000)}


def to_ros(traj: Trajectory, dt: float = 0.01) -> dict[str, Any]:
    """A ``trajectory_msgs/JointTrajectory``-shaped dict sampled every ``dt`` [s]."""
    t = traj.times(dt)
    q, qd, qdd = traj.sample(t)
    points = [{"positions": q[i].tolist(), "velocities": qd[i].tolist(),
               "accelerations": qdd[i].tolist(), "time_from_start": stamp(float(t[i]))}
              for i in range(len(t))]
    return {"joint_names": list(traj.limits.joint_names), "points": points}


def _flow(values: list[float]) -> str:
    return "[" + ", ".join(repr(float(v)) if math.isfinite(v) else "0.0" for v in values) + "]"


def to_ros_yaml(traj: Trajectory, path: str | Path, dt: float = 0.01) -> Path:
    """Write :func:`to_ros` as YAML (block mapping, flow lists; no YAML library needed)."""
    msg = to_ros(traj, dt)
    lines = ["joint_names: [" + ", ".join(json.dumps(n) for n in msg["joint_names"]) + "]",
             "points:"]
    for p in msg["points"]:
        ts = p["time_from_start"]
        lines += [f"  - positions: {_flow(p['positions'])}",
                  f"    velocities: {_flow(p['velocities'])}",
                  f"    accelerations: {_flow(p['accelerations'])}",
                  f"    time_from_start: {{sec: {ts['sec']}, nanosec: {ts['nanosec']}}}"]
    path = check_path("path", path)
    path.write_text("\n".join(lines) + "\n")
    return path
