"""The trajectory files of ``plan``, ``cycle`` and ``run``: one set of options, one naming.

``--csv`` (``<stem>.csv``: t, q, qd, qdd), ``--trajectory-json`` (``<stem>.json``, the
same columns), ``--ros`` (``<stem>_ros.yaml``, shaped as a ROS
``trajectory_msgs/JointTrajectory``), ``--plot`` (``<stem>.png``: tool speed and joint
profiles) and ``--html`` (``<stem>.html``: the motion in 3-D, with the cell), all sampled at
``--dt``, all written into ``--out`` (:class:`~scara_opt.cli.outputs.OutputDir`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from scara_opt.cli.args import add_out, files_asked, positive

#: option -> (file name after the stem, what it holds)
KINDS = {"csv": (".csv", "the trajectory as CSV (t, q, qd, qdd)"),
         "trajectory_json": (".json", "the trajectory as JSON (t, q, qd, qdd)"),
         "ros": ("_ros.yaml", "the trajectory as ROS JointTrajectory-shaped YAML"),
         "plot": (".png", "tool speed and joint profiles"),
         "html": (".html", "the motion in 3-D, with the cell (needs the view extra)")}


def files(stem: str) -> dict[str, str]:
    """The file name of each option of :data:`KINDS` for a command's ``stem``."""
    return {k: stem + suffix for k, (suffix, _) in KINDS.items()}


def add_export_options(p: argparse.ArgumentParser, stem: str) -> None:
    """``--out``, ``--force``, the options of :data:`KINDS` and ``--dt``."""
    add_out(p)
    for key, name in files(stem).items():
        p.add_argument(f"--{key.replace('_', '-')}", action="store_true",
                       help=f"write {name}: {KINDS[key][1]}")
    p.add_argument("--dt", type=positive, default=0.001,
                   help="sampling step of the CSV, JSON and YAML files [s] (0.001)")


def asked(args: argparse.Namespace, stem: str) -> list[str]:
    """The file options given (checked against ``--out`` before any work)."""
    return files_asked(args, files(stem))


def write_exports(args: argparse.Namespace, stem: str, robot: Any, traj: Any,
                  title: str) -> list[Path]:
    """Write the asked files of ``traj`` into ``--out``; returns their final paths."""
    from scara_opt.cli.outputs import OutputDir, write_animation

    names = files(stem)
    wanted = asked(args, stem)
    if not wanted:
        return []
    with OutputDir(args.out, [names[k] for k in wanted], args.force) as out:
        if "csv" in wanted:
            traj.to_csv(out / names["csv"], dt=args.dt)
        if "trajectory_json" in wanted:
            traj.to_json(out / names["trajectory_json"], dt=args.dt)
        if "ros" in wanted:
            traj.to_ros_yaml(out / names["ros"], dt=args.dt)
        if "plot" in wanted:
            from scara_opt.motion.plot import plot_motion

            plot_motion(robot, traj, out / names["plot"], title=title)
        if "html" in wanted:
            write_animation(robot, traj, out / names["html"], title.replace("\n", "; "))
    return [out.final / names[k] for k in wanted]
