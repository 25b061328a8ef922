"""The ``scara-opt`` command line.

Exit codes: 0 success; 1 ``ik`` did not solve (its status says why), or ``plan`` found no
path within its time limit; 2 bad usage or bad
input (one line ``scara-opt: error: ...`` on stderr); 130 interrupted (Ctrl-C; one line
``scara-opt: interrupted``).

Units are explicit at this edge: lengths in metres unless ``--mm``, joint angles in radians
unless ``--deg``; ``--yaw`` is always in degrees. Output folders (``--out``) are handled by
:mod:`scara_opt.outputs`: files the run would overwrite are refused unless ``--force``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any, NoReturn

import numpy as np

from scara_opt import cli_motion, cli_plan, interrupt
from scara_opt.cli_args import add_limit_options, degrees, int_at_least, joint_limits
from scara_opt.cli_args import joint_scale as _joint_scale
from scara_opt.cli_args import joint_units as _units
from scara_opt.errors import InputError, ScaraOptError, ScaraOptWarning
from scara_opt.outputs import (
    COMPARE_FILES,
    FORCE_HELP,
    OutputDir,
    html_name,
    write_animation,
    write_compare,
    write_joint_path,
)

#: exit code of ``ik`` when the target was not solved (the printed status says why)
EXIT_NOT_SOLVED = 1


def _fmt_limit(kind: str, lo: float, hi: float) -> str:
    if kind == "revolute":
        return f"[{math.degrees(lo):.1f}, {math.degrees(hi):.1f}] deg"
    return f"[{lo * 1000:.1f}, {hi * 1000:.1f}] mm"


def cmd_robots(args: argparse.Namespace) -> int:
    """List the bundled robots with joints, limits, source and the paper's full reference."""
    from scara_opt.model.catalogue import list_robots, load_robot
    from scara_opt.model.citation import format_citation

    for name in list_robots():
        robot = load_robot(name)
        print(f"{name}  ({robot.nq} joints, tip {robot.tip!r})")
        for jname, kind, lo, hi in zip(robot.joint_names, robot.joint_types, robot.lower,
                                       robot.upper, strict=True):
            print(f"  {jname:<8} {kind:<9} {_fmt_limit(kind, lo, hi)}")
        print(f"  source: {robot.source}")
        citation = robot.metadata.get("citation")
        if citation:
            print(f"  paper:  {format_citation(citation)}")
            if "note" in citation:
                print(f"          ({citation['note']})")
    return 0


def cmd_fk(args: argparse.Namespace) -> int:
    """Forward kinematics of one configuration: position, RPY [deg] and quaternion (w, x, y, z)."""
    from scara_opt.cli_pose import orientation, orientation_text
    from scara_opt.model.catalogue import load_robot

    robot = load_robot(args.robot)
    q = robot.check_q(args.q) / _joint_scale(robot, args.deg, args.mm)
    T = robot.fk(q)
    L = 1000.0 if args.mm else 1.0
    out: dict[str, Any] = {
        "robot": robot.name, "q": q.tolist(), "q_units": _units(robot, False, False),
        "position": (T[:3, 3] * L).tolist(), "position_unit": "mm" if args.mm else "m",
        "rotation": T[:3, :3].tolist(), "within_limits": bool(robot.within_limits(q)),
    }
    out.update(orientation(T[:3, :3]))
    if robot.yaw_axis is not None:
        out["yaw_deg"] = math.degrees(robot.yaw(q))
    if args.json:
        print(json.dumps(out))
        return 0
    unit = out["position_unit"]
    print(f"{robot.name}: tip at ({', '.join(f'{v:.6g}' for v in out['position'])}) {unit}"
          + (f", yaw {out['yaw_deg']:.6g} deg" if "yaw_deg" in out else ""))
    print(f"  orientation: {orientation_text(out)}")
    if not out["within_limits"]:
        print("note: q is outside the joint limits")
    return 0


def _result_dict(robot: Any, res: Any, deg: bool, mm: bool) -> dict[str, Any]:
    L = 1000.0 if mm else 1.0
    return {
        "robot": robot.name, "method": res.method, "status": res.status.value,
        "success": res.success, "q": (res.q * _joint_scale(robot, deg, mm)).tolist(),
        "q_units": _units(robot, deg, mm), "error": res.error,
        "error_unit": "m" if res.yaw_error is None else "m and rad",
        "position_error": (res.position_error * L).tolist(),
        "position_error_unit": "mm" if mm else "m",
        "yaw_error_deg": None if res.yaw_error is None else math.degrees(res.yaw_error),
        "iterations": res.iterations, "evaluations": res.evaluations, "time_s": res.time_s,
        "message": res.message,
    }


def cmd_ik(args: argparse.Namespace) -> int:
    """Inverse kinematics of one target (position, and --yaw, --rpy or --quat) by any method."""
    import scara_opt as so
    from scara_opt.cli_pose import orientation, target_from_args

    robot = so.load_robot(args.robot)
    L = 1000.0 if args.mm else 1.0
    target = target_from_args(args, np.asarray(args.xyz, float) / L)
    if args.all:
        given = [o for o, v in (("--method", args.method), ("--seed", args.seed)) if v is not None]
        if given:
            raise InputError(f"--all lists the closed-form branches; it does not take "
                             f"{' or '.join(given)}; drop {' and '.join(given)} or --all")
        results = so.ik_all(robot, target, tol=args.tol)
    else:
        results = [so.solve_ik(robot, target, method="auto" if args.method is None
                               else args.method, seed=args.seed or 0, tol=args.tol)]
    rows = [_result_dict(robot, r, args.deg, args.mm) for r in results]
    if target.kind == "rotation":  # the angle error is the rotation's, not a yaw's
        for row, res in zip(rows, results, strict=True):
            row["rotation_error_deg"] = row.pop("yaw_error_deg")
            row["target_orientation"] = orientation(target.rotation)
            row["reached_orientation"] = orientation(robot.fk(res.q)[:3, :3])
    code = 0 if rows and all(row["success"] for row in rows) else EXIT_NOT_SOLVED
    if args.json:
        print(json.dumps(rows if args.all else rows[0]))
        return code
    if not rows:
        print(f"{robot.name}: no closed-form solution within the joint limits (unreachable)")
    for row in rows:
        q = ", ".join(f"{name}={v:.6g} {u}" for name, v, u in
                      zip(robot.joint_names, row["q"], row["q_units"], strict=True))
        print(f"{row['status']}: {q}  (error {row['error']:.3g} {row['error_unit']}, "
              f"{row['method']}, "
              f"{row['time_s'] * 1e3:.2f} ms)")
        if not row["success"]:
            print(f"  {row['message']}")
    return code


#: most worker processes --workers starts (this machine's cores, a few times over)
MAX_WORKERS = 256


def _entries(text: str, what: str) -> list[str]:
    """The comma-separated entries of ``text``, stripped.

    An empty entry (``10,,20``, a trailing comma) is refused, not skipped.
    """
    entries = [v.strip() for v in text.split(",")]
    if "" in entries:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated {what}, got {text!r}, which has an empty entry")
    return entries


def _int_list(text: str) -> list[int]:
    entries = _entries(text, "integers")
    try:
        values = [int(v) for v in entries]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated integers, got {text!r}") from None
    if any(v <= 0 for v in values):  # _entries refused an empty one
        raise argparse.ArgumentTypeError(f"expected positive integers, got {text!r}")
    return values


def _methods(text: str) -> list[str] | str:
    """``--methods``: ``all``, or comma-separated names (none empty)."""
    return text if text == "all" else _entries(text, "method names")


def _ignore_sigint() -> None:
    """A worker's initializer: Ctrl-C and scara_opt's warnings as in the main process.

    Ctrl-C is handled by the main process (one line, exit 130); a warning is one ``note:``
    line.
    """
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warnings.showwarning = _show_warning


@contextmanager
def _executor(args: argparse.Namespace) -> Iterator[Any]:
    """A process pool for --workers N, a dask client's executor for --dask ADDRESS, or None.

    On leaving, the pool is shut down (its queued jobs cancelled), the dask client closed.
    """
    if args.dask:
        try:
            from distributed import Client
        except ImportError:
            raise ScaraOptError(
                "--dask needs dask.distributed: pip install 'scara-opt[dask]'") from None
        try:
            client = Client(args.dask, timeout=10)
        except (OSError, ValueError, TypeError) as exc:
            raise ScaraOptError(f"cannot reach a dask scheduler at {args.dask!r} ({exc}); "
                                "pass its address, e.g. --dask tcp://host:8786") from None
        try:
            yield client.get_executor()
        finally:
            client.close()
    elif args.workers and args.workers > 1:
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(args.workers, initializer=_ignore_sigint)
        try:
            yield pool
        finally:
            pool.shutdown(cancel_futures=True)
    else:
        yield None


def cmd_compare(args: argparse.Namespace) -> int:
    """Compare IK methods on one target: CSV table, summary and figures."""
    import scara_opt as so
    from scara_opt.comparison import compare

    robot = so.load_robot(args.robot)
    L = 1000.0 if args.mm else 1.0
    out = OutputDir(args.out, COMPARE_FILES, args.force, last=["summary.csv"])
    with out:
        with _executor(args) as executor:
            # "all" goes to the library as is: it leaves out methods the robot cannot use
            table = compare(robot, [np.asarray(args.target, float) / L], methods=args.methods,
                            populations=args.populations, iterations=args.iterations,
                            seeds=range(args.seeds), executor=executor, progress=True,
                            tol=args.tol)
        summary = write_compare(out, table, args.tol)
    print(summary.to_string(index=False))
    print(f"wrote runs.csv, summary.csv and 3 figures in {out.final}")
    return 0


def cmd_workspace(args: argparse.Namespace) -> int:
    """Monte Carlo workspace: areas, ranges and the XY/3-D figures."""
    import scara_opt as so

    robot = so.load_robot(args.robot)
    names = [f"{robot.name}_workspace_xy.png", f"{robot.name}_workspace_3d.png"]
    with OutputDir(args.out, names, args.force) as out:
        ws = so.workspace(robot, n=args.n, seed=args.seed, footprint=not args.no_footprint)
        ws.plot_xy(out / names[0])
        ws.plot_3d(out / names[1])
    print(repr(ws))
    print(f"XY area: {ws.xy_area:.6f} m^2")
    print("wrote " + ", ".join(str(out.final / n) for n in names))
    return 0


def _yaw_arg(text: str) -> float | str:
    """``--yaw`` of a path: degrees, or ``tangent``."""
    if text == "tangent":
        return text
    try:
        float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected degrees or 'tangent', got {text!r}") from None
    return math.radians(degrees(text))


def _path_targets(args: argparse.Namespace) -> list[Any]:
    """The path's targets in SI from --circle CX CY R Z or --line X0 Y0 Z0 X1 Y1 Z1."""
    from scara_opt import paths

    L = 1000.0 if args.mm else 1.0
    if args.circle:
        cx, cy, r, z = (v / L for v in args.circle)
        return paths.circle((cx, cy), r, z, n=args.n, yaw=args.yaw)
    xyz = np.asarray(args.line, float) / L
    return paths.line(xyz[:3], xyz[3:], args.n, yaw=args.yaw)


def cmd_path(args: argparse.Namespace) -> int:
    """IK along a circle or a line, then time the joint path: CSV tables and a figure."""
    import scara_opt as so

    robot = so.load_robot(args.robot)
    q_start = None
    if args.q_start is not None:
        q_start = robot.check_q(args.q_start, "--q-start") / _joint_scale(robot, args.deg,
                                                                           args.mm)
    targets = _path_targets(args)
    limits = joint_limits(args, robot, need_jerk=args.time == "ruckig")  # before any IK
    names = ["joint_path.csv", "trajectory.csv", "trajectory.png"]
    if args.html is not None:
        names.append(html_name(args.html))
    with OutputDir(args.out, names, args.force, last=["trajectory.csv"]) as out:
        jp = so.ik_path(robot, targets, method=args.method, q_start=q_start,
                        seed=args.seed, tol=args.tol)
        write_joint_path(jp, robot, out / "joint_path.csv")
        out.commit()  # joint_path.csv is kept when the path is refused below
        if not args.json:
            print(jp.summary())
        jp.raise_if_invalid(allow_jumps=args.allow_jumps)  # exit 2
        traj = so.time_parameterize(jp, robot, method=args.time, vmax=limits.vmax,
                                    amax=limits.amax, jmax=limits.jmax,
                                    allow_jumps=args.allow_jumps)
        traj.to_csv(out / "trajectory.csv")
        traj.plot(out / "trajectory.png")
        if args.html is not None:
            write_animation(robot, traj, out / names[-1], f"{robot.name}: {len(jp)}-point "
                            f"path, {args.time} {traj.duration:.3f} s")
    files = [out.final / n for n in names]
    ratios = {k: float(np.max(v)) for k, v in traj.check_limits().items()}
    if args.json:
        print(json.dumps({
            "robot": robot.name, "method": jp.method, "timing": args.time, "points": len(jp),
            "solved": int(jp.solved.sum()), "max_error": float(jp.error.max()),
            "jumps": [j.index for j in jp.jumps], "duration_s": traj.duration,
            "limit_ratios": ratios, "files": [str(f) for f in files]}))
        return 0
    peaks = ", ".join(f"{k} {v:.3f}" for k, v in ratios.items())
    print(f"{args.time}: {traj.duration:.4f} s; largest ratio to the limits: {peaks}")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


def cmd_reproduce(args: argparse.Namespace) -> int:
    """Reproduce one paper or all: tables, figures and summary.md."""
    from scara_opt.reports import PAPERS, reproduce

    papers = PAPERS if args.paper == "all" else [args.paper]
    writes = ["summary.md", *(f"{p}_*" for p in papers)]
    with OutputDir(args.out, writes, args.force, last=["summary.md"]) as out:
        assert out.staging is not None
        reports = reproduce(args.paper, out.staging, quick=args.quick, jobs=args.jobs)
    for rep in reports:
        verdicts = [f.verdict for f in rep.findings]
        counts = ", ".join(f"{verdicts.count(v)} {v}" for v in dict.fromkeys(verdicts))
        print(f"{rep.paper}: {counts} ({rep.time_s:.1f} s)")
    print(f"wrote {out.final / 'summary.md'}")
    return 0


def cmd_doctor(args: argparse.Namespace) -> int:
    """Versions, compiler, cache folder, and what is compiled or falls back (exit 0)."""
    from scara_opt.doctor import report

    print("\n".join(report()))
    return 0


def cmd_solvers(args: argparse.Namespace) -> int:
    """List the registered IK methods."""
    import scara_opt as so

    print("\n".join(so.solvers()))
    return 0


class UsageError(Exception):
    """A command line argparse refused (reported as one line, exit code 2)."""


class _Parser(argparse.ArgumentParser):
    """argparse with its errors raised, so that main() prints them as one line."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{message} (see `{self.prog} --help`)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand."""
    from scara_opt.reports import PAPERS

    parser = _Parser(
        prog="scara-opt",
        description="Kinematics, IK and trajectories of SCARA robots and serial URDF chains.",
        epilog="exit codes: 0 success; 1 ik did not solve (unreachable, failed, max_iter: the "
               "status says which), or plan found no path within its time limit; 2 bad input "
               "or usage; 130 interrupted (Ctrl-C)",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("robots", help="list the bundled robots with joints, limits and source")
    p.set_defaults(func=cmd_robots)

    p = sub.add_parser("solvers", help="list the registered IK methods")
    p.set_defaults(func=cmd_solvers)

    p = sub.add_parser("doctor", help="versions, C compiler, cache folder, and what is "
                       "compiled or falls back")
    p.set_defaults(func=cmd_doctor)

    units = _Parser(add_help=False)
    units.add_argument("--mm", action="store_true",
                       help="lengths (positions, prismatic joints) in mm instead of m")
    units.add_argument("--deg", action="store_true",
                       help="revolute joint values in degrees instead of radians")
    units.add_argument("--json", action="store_true", help="print JSON for scripts")

    p = sub.add_parser("fk", parents=[units], help="forward kinematics of one configuration")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("q", metavar="q", type=float, nargs="+", help="joint values, one per joint")
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("ik", parents=[units], help="inverse kinematics of one target")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--xyz", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"),
                   help="target position (m, or mm with --mm)")
    from scara_opt.cli_pose import add_orientation_arguments
    add_orientation_arguments(p)  # --yaw | --rpy | --quat, and --rpy-unit
    p.add_argument("--method", help="IK method (see `scara-opt solvers`; default auto)")
    p.add_argument("--seed", type=int_at_least(0), help="random seed (default 0)")
    p.add_argument("--tol", type=float, default=1e-9, help="residual counted as solved [m]")
    p.add_argument("--all", action="store_true",
                   help="every closed-form branch (SCARA only; no --method or --seed)")
    p.set_defaults(func=cmd_ik)

    p = sub.add_parser("compare", help="compare IK methods on a target (table + figures)")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("--target", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"),
                   help="target position (m, or mm with --mm)")
    p.add_argument("--mm", action="store_true", help="target in mm")
    p.add_argument("--methods", type=_methods, default="all",
                   help="comma-separated names, or all")
    p.add_argument("--populations", type=_int_list, default=[20, 40, 60, 80, 100],
                   help="comma-separated population sizes (default 20,40,60,80,100)")
    p.add_argument("--iterations", type=int_at_least(1), default=200,
                   help="iterations (default 200)")
    p.add_argument("--seeds", type=int_at_least(1), default=10,
                   help="number of seeds 0..N-1 (default 10)")
    p.add_argument("--tol", type=float, default=1e-9, help="residual counted as solved [m]")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    group = p.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int_at_least(1, MAX_WORKERS), default=1,
                       help=f"local worker processes (at most {MAX_WORKERS})")
    group.add_argument("--dask", metavar="ADDRESS", help="dask scheduler address")
    p.set_defaults(func=cmd_compare)

    p = sub.add_parser("path", parents=[units],
                       help="IK along a circle or line, then time it (CSV + figure)")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    shape = p.add_mutually_exclusive_group(required=True)
    shape.add_argument("--circle", type=float, nargs=4, metavar=("CX", "CY", "R", "Z"),
                       help="horizontal circle: centre, radius, height (m, or mm with --mm)")
    shape.add_argument("--line", type=float, nargs=6,
                       metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"),
                       help="straight line from start to end (m, or mm with --mm)")
    p.add_argument("-n", type=int, default=36, help="path points (default 36)")
    p.add_argument("--yaw", type=_yaw_arg, metavar="DEG|tangent",
                   help="tool angle along the path [deg], or 'tangent' to the path")
    p.add_argument("--method", default="auto",
                   help="IK method (see `scara-opt solvers`; default auto)")
    p.add_argument("--time", default="toppra", choices=["toppra", "ruckig", "quintic"],
                   help="time parameterisation (default toppra)")
    p.add_argument("--q-start", type=float, nargs="+", metavar="q",
                   help="configuration the path starts from (units per --deg/--mm)")
    p.add_argument("--allow-jumps", action="store_true",
                   help="time the path even if the joints jump (elbow flip, wrist turn)")
    add_limit_options(p, jerk="--time ruckig only (default 10/s x amax)")
    p.add_argument("--seed", type=int_at_least(0), default=0, help="random seed (default 0)")
    p.add_argument("--tol", type=float, default=1e-9, help="residual counted as solved [m]")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--html", metavar="FILE", help="also write a 3-D animation FILE (.html, in "
                   "--out; needs the view extra)")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    p.set_defaults(func=cmd_path)

    cli_motion.add_parser(sub)  # cycle
    cli_plan.add_parser(sub)  # plan

    p = sub.add_parser("workspace", help="Monte Carlo workspace with figures")
    p.add_argument("robot", metavar="ROBOT", help="bundled robot name or path to .urdf/.toml")
    p.add_argument("-n", type=int, default=60_000, help="samples (default 60000)")
    p.add_argument("--seed", type=int_at_least(0), default=0, help="random seed (default 0)")
    p.add_argument("--no-footprint", action="store_true", help="ignore the base exclusion zone")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    p.set_defaults(func=cmd_workspace)

    p = sub.add_parser("reproduce", help="reproduce a paper's tables and figures, or all")
    p.add_argument("paper", metavar="PAPER", choices=[*PAPERS, "all"],
                   help=f"one of {', '.join(PAPERS)}, or all")
    p.add_argument("--out", required=True, help="output folder (summary.md, CSV, PNG)")
    p.add_argument("--force", action="store_true", help=FORCE_HELP)
    p.add_argument("--quick", action="store_true", help="reduced sweeps for a first look")
    p.add_argument("--jobs", type=int_at_least(1, MAX_WORKERS),
                   default=min(2, os.cpu_count() or 1), metavar="N",
                   help="papers run in N processes at once (default: 2, or 1 on a single "
                        "core; the files are those of a serial run)")
    p.set_defaults(func=cmd_reproduce)
    return parser


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


_PYTHON_SHOWWARNING = warnings.showwarning


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: Any = None, line: str | None = None) -> None:
    """scara_opt's warnings as one line ``scara-opt: note: ...`` on stderr; others as Python."""
    if issubclass(category, ScaraOptWarning):
        print(f"scara-opt: note: {' '.join(str(message).split())}", file=sys.stderr)
    else:
        _PYTHON_SHOWWARNING(message, category, filename, lineno, file, line)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code.

    0 done, 1 an IK that did not solve, 2 bad input, 130 interrupted, 141 the reader of its
    output left.
    """
    try:
        # watch(): an error that follows a SIGINT leaves as the KeyboardInterrupt it was
        with interrupt.quiet_casadi_warning(), interrupt.watch(), \
                warnings.catch_warnings():  # one line below
            warnings.showwarning = _show_warning
            try:
                args = build_parser().parse_args(argv)
                return int(args.func(args))
            except SystemExit as exc:  # --help (0)
                return exc.code if isinstance(exc.code, int) else 0
    except KeyboardInterrupt:
        print("scara-opt: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader left (`scara-opt robots | head -2`): quietly, as cat
        return 141  # 128 + SIGPIPE, what a shell shows for a command the pipe ended
    except (ScaraOptError, UsageError, OSError) as exc:  # bad input, an unwritable file
        print(f"scara-opt: error: {_one_line(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # python -m scara_opt.cli: it ends as the scara-opt script does
    interrupt.exit_now(main())
