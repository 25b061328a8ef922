"""``scara-opt compare ROBOT --target X Y Z``: IK methods compared, a table and figures.

Serially, in a process pool (``--workers N``) or on a dask cluster (``--dask ADDRESS``),
with the same numbers either way (:func:`scara_opt.compare`).
"""

from __future__ import annotations

import argparse
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from scara_opt.cli.args import add_out, add_robot, int_at_least, load_robot
from scara_opt.cli.messages import show_warning
from scara_opt.cli.outputs import OutputDir
from scara_opt.errors import ScaraOptError

#: the files of ``scara-opt compare``
FILES = ("runs.csv", "summary.csv", "convergence.png", "time_vs_population.png",
         "error_time_boxes.png")

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
    warnings.showwarning = show_warning


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


def write_compare(out: OutputDir, table: Any, tol: float) -> Any:
    """compare's :data:`FILES` (CSV with units in the column names, 3 figures).

    Returns:
        The summary table (a DataFrame, SI units).
    """
    from scara_opt.comparison import convergence, summarize, with_units
    from scara_opt.plots import plot_boxes, plot_convergence, plot_time_vs_population

    with_units(table.drop(columns=["history"])).to_csv(out / "runs.csv", index=False)
    summary = summarize(table, tol=tol)
    with_units(summary).to_csv(out / "summary.csv", index=False)
    plot_convergence(convergence(table), out / "convergence.png")
    plot_time_vs_population(summary, out / "time_vs_population.png")
    plot_boxes(table, ["error", "time_s"], out / "error_time_boxes.png")
    return summary


def cmd_compare(args: argparse.Namespace) -> int:
    """Compare IK methods on one target: CSV table, summary and figures."""
    from scara_opt.comparison import compare

    robot = load_robot(args)
    L = 1000.0 if args.mm else 1.0
    out = OutputDir(args.out, FILES, args.force, last=["summary.csv"])
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


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``compare`` to the subparsers ``sub``."""
    p = sub.add_parser("compare", parents=parents,
                       help="compare IK methods on a target (table + figures)")
    add_robot(p)
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
    add_out(p, required=True)
    group = p.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int_at_least(1, MAX_WORKERS), default=1,
                       help=f"local worker processes (at most {MAX_WORKERS})")
    group.add_argument("--dask", metavar="ADDRESS", help="dask scheduler address")
    p.set_defaults(func=cmd_compare)
