"""The ``scara-opt`` command line: one module per subcommand, the shared edges beside them.

========================  ==============================================================
module                    what it holds
========================  ==============================================================
``console``               the console script (``scara-opt``): loads :mod:`.app`, one line
                          and exit 130 on a Ctrl-C at any moment, the end without teardown
``app``                   the parser of every subcommand and :func:`main`: exit codes,
                          one line per error, warnings as ``note:`` lines
``robots`` ``solvers``    the listings
``fk`` ``ik``             one configuration, one target
``compare`` ``path``      IK methods compared; IK along a circle or line, timed
``cycle`` ``plan``        the standard cycle; one PTP in a cell
``run``                   a program file (TOML) of PTP / LIN / CIRC moves
``workspace``             Monte Carlo workspace
``reproduce``             the papers' tables and figures
``doctor`` ``cache``      what this installation runs on; the native-code cache
``args``                  arguments several subcommands share (robot, units, limits, cell)
``orientation``           ``--yaw`` / ``--rpy`` / ``--quat`` in, RPY and quaternion out
``outputs``               ``--out`` folders: checked first, never overwritten unasked, atomic
``messages``              errors and warnings as one line each
========================  ==============================================================

Exit codes: 0 success; 1 ``ik`` did not solve, or no path was found within the time limit;
2 bad input or usage (one line ``scara-opt: error: ...``); 70 an unexpected error (one
line naming it; ``--traceback`` or ``SCARA_OPT_TRACEBACK=1`` shows where); 130
interrupted (Ctrl-C); 129 / 143 ended by SIGHUP / SIGTERM; 141 the reader of the output
left. Units are explicit at this edge: lengths in metres unless ``--mm``, joint angles in
radians unless ``--deg``.

``import scara_opt.cli`` loads nothing heavy: :func:`main` and :func:`build_parser` are
:mod:`scara_opt.cli.app`'s, imported at their first use (the console script starts
:mod:`.console` first, so that a Ctrl-C while numpy and the rest load is its one line).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__all__ = ["build_parser", "main"]


def __getattr__(name: str) -> Any:
    """``main`` and ``build_parser`` of :mod:`scara_opt.cli.app`, imported on first use."""
    if name in __all__:
        from scara_opt.cli import app

        return getattr(app, name)
    raise AttributeError(f"module 'scara_opt.cli' has no attribute {name!r}")


if TYPE_CHECKING:
    from scara_opt.cli.app import build_parser, main
