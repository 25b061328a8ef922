"""What the command line says on stderr: one line per error, per warning, per signal.

``scara-opt: error: ...`` for bad input (exit 2); ``scara-opt: note: ...`` for scara_opt's
warnings; ``scara-opt: internal error: NAME: ...`` for an exception nobody expected (exit
:data:`EXIT_INTERNAL`), with a hint to rerun with ``--traceback`` (or
``SCARA_OPT_TRACEBACK=1``) to see where it came from.
"""

from __future__ import annotations

import os
import sys
import traceback
import warnings
from collections.abc import Sequence
from typing import Any

from scara_opt.errors import ScaraOptWarning

#: exit code of an unexpected error (sysexits.h's EX_SOFTWARE: an internal software error)
EXIT_INTERNAL = 70
#: the option and the environment variable that print an unexpected error's traceback
TRACEBACK_OPTION = "--traceback"
TRACEBACK_ENV = "SCARA_OPT_TRACEBACK"


def one_line(exc: BaseException) -> str:
    """The exception's message on one line (its class name when it has none)."""
    return " ".join(str(exc).split()) or type(exc).__name__


def wants_traceback(argv: Sequence[str] | None) -> bool:
    """Whether ``--traceback`` is among the arguments or ``$SCARA_OPT_TRACEBACK`` is set."""
    args = sys.argv[1:] if argv is None else argv
    return TRACEBACK_OPTION in args or os.environ.get(TRACEBACK_ENV, "") not in ("", "0")


def report_internal(exc: BaseException, argv: Sequence[str] | None = None) -> int:
    """Say an unexpected error in one line (its traceback too when asked); returns its code.

    The line names the exception's class and message and how to see the traceback; with
    ``--traceback`` or ``SCARA_OPT_TRACEBACK=1`` the traceback is printed first.
    """
    if wants_traceback(argv):
        traceback.print_exception(exc, file=sys.stderr)
        hint = "please report it with the traceback above"
    else:
        hint = (f"rerun with {TRACEBACK_OPTION} (or {TRACEBACK_ENV}=1) to see where, and "
                "please report it")
    name = type(exc).__qualname__
    text = " ".join(str(exc).split())
    print(f"scara-opt: internal error: {name}{': ' + text if text else ''} ({hint})",
          file=sys.stderr)
    return EXIT_INTERNAL


_PYTHON_SHOWWARNING = warnings.showwarning


def show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                 file: Any = None, line: str | None = None) -> None:
    """scara_opt's warnings as one line ``scara-opt: note: ...`` on stderr; others as Python."""
    if issubclass(category, ScaraOptWarning):
        print(f"scara-opt: note: {' '.join(str(message).split())}", file=sys.stderr)
    else:
        _PYTHON_SHOWWARNING(message, category, filename, lineno, file, line)
