"""The parser of every subcommand, and :func:`main`: exit codes and one line per error.

Each subcommand lives in its own module of :mod:`scara_opt.cli` (``plan`` in
``cli/plan.py``), which gives ``add_parser(sub)`` and the command itself; this module wires
them together (:data:`SUBCOMMANDS`, in the order ``--help`` lists them) and runs one.

Exit codes: see :data:`EXIT_CODES`. Units are explicit at this edge: lengths in metres
unless ``--mm``, joint angles in radians unless ``--deg``; ``--yaw`` is always in degrees.
Output folders (``--out``) are handled by :mod:`scara_opt.cli.outputs`: files the run would
overwrite are refused unless ``--force``.
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from types import FrameType
from typing import NoReturn

from scara_opt import __version__, interrupt
from scara_opt.cli.messages import (
    EXIT_INTERNAL,
    TRACEBACK_ENV,
    TRACEBACK_OPTION,
    one_line,
    report_internal,
    show_warning,
)
from scara_opt.errors import ScaraOptError

#: the subcommands' modules of :mod:`scara_opt.cli`, in the order ``--help`` lists them
SUBCOMMANDS = ("robots", "solvers", "doctor", "cache", "fk", "ik", "compare", "path",
               "cycle", "plan", "run", "workspace", "reproduce")

#: the exit codes, as ``--help`` and the README list them
EXIT_CODES = (f"exit codes: 0 success; 1 ik did not solve (unreachable, failed, max_iter: the "
              f"status says which), or no path was found within the time limit (plan, run); "
              f"2 bad input or usage; {EXIT_INTERNAL} an unexpected error (one line; "
              f"{TRACEBACK_OPTION} or {TRACEBACK_ENV}=1 shows where); 130 interrupted "
              f"(Ctrl-C); 129 and 143 ended by SIGHUP and SIGTERM; 141 the reader of the "
              f"output left (`scara-opt robots | head -2`)")


class UsageError(Exception):
    """A command line argparse refused (reported as one line, exit code 2)."""


class _Parser(argparse.ArgumentParser):
    """argparse with its errors raised, so that main() prints them as one line."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{message} (see `{self.prog} --help`)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand of :data:`SUBCOMMANDS`."""
    parser = _Parser(
        prog="scara-opt",
        description="Kinematics, IK and trajectories of SCARA robots and serial URDF chains.",
        epilog=EXIT_CODES,
    )
    parser.add_argument("--version", action="version", version=f"scara-opt {__version__}")
    common = _Parser(add_help=False)  # accepted before or after the subcommand
    for p in (parser, common):
        p.add_argument(TRACEBACK_OPTION, action="store_true",
                       default=False if p is parser else argparse.SUPPRESS,
                       help="on an unexpected error, print its traceback")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND",
                                parser_class=_Parser)
    for name in SUBCOMMANDS:
        module = importlib.import_module(f"scara_opt.cli.{name}")
        module.add_parser(sub, [common])
    return parser


class Terminated(BaseException):
    """SIGTERM or SIGHUP arrived: the command stops as after Ctrl-C (its files are not kept).

    A ``BaseException``, as ``KeyboardInterrupt``: no library's ``except Exception`` takes it.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


_TERMINATED: list[int] = []  # the signal that arrived, for an error that hid it


def _terminate(signum: int, frame: FrameType | None) -> None:
    _TERMINATED.append(signum)
    raise Terminated(signum)


@contextmanager
def _on_termination() -> Iterator[None]:
    """SIGTERM and SIGHUP raise :class:`Terminated` in the block (the main thread only).

    The command then unwinds as after a Ctrl-C: worker processes are ended and the
    ``--out`` staging folder removed (their default action would end the process at once
    and leave both behind).
    """
    del _TERMINATED[:]
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    signals = [s for s in (getattr(signal, "SIGTERM", None), getattr(signal, "SIGHUP", None))
               if s is not None]
    prior = {s: signal.signal(s, _terminate) for s in signals}
    try:
        yield
    except Exception:
        if _TERMINATED:  # a library turned the signal into another error
            raise Terminated(_TERMINATED[0]) from None
        raise
    finally:
        for s, handler in prior.items():
            signal.signal(s, handler)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (:data:`EXIT_CODES`)."""
    try:
        # watch(): an error that follows a SIGINT leaves as the KeyboardInterrupt it was
        with interrupt.quiet_casadi_warning(), interrupt.watch(), _on_termination(), \
                warnings.catch_warnings():  # one line below
            warnings.showwarning = show_warning
            try:
                args = build_parser().parse_args(argv)
                return int(args.func(args))
            except SystemExit as exc:  # --help, --version (0)
                return exc.code if isinstance(exc.code, int) else 0
    except KeyboardInterrupt:
        print("scara-opt: interrupted", file=sys.stderr)
        return 130
    except Terminated as exc:
        name = signal.Signals(exc.signum).name
        print(f"scara-opt: ended by {name}", file=sys.stderr)
        return 128 + exc.signum
    except BrokenPipeError:  # the reader left (`scara-opt robots | head -2`): quietly, as cat
        return 141  # 128 + SIGPIPE, what a shell shows for a command the pipe ended
    except (ScaraOptError, UsageError, OSError) as exc:  # bad input, an unwritable file
        print(f"scara-opt: error: {one_line(exc)}", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug (ours or a library's): one line naming it, its own code
        return report_internal(exc, argv)
