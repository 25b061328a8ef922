"""The ``scara-opt`` console script: :func:`scara_opt.cli.main`, Ctrl-C one line throughout.

A Ctrl-C while the command line's modules load (numpy, pandas: the first few tenths of a
second) printed Python's traceback of the import; one after the command finished could
print "Exception ignored ..." or kill the process by SIGINT with no message. Here the
first is the command line's one line ``scara-opt: interrupted`` and exit code 130, as
during the command, and the end is immediate (:func:`scara_opt.interrupt.exit_now`). Only
Python's own start-up, before any of this package runs, is left to Python.
"""

from __future__ import annotations

import sys
from typing import NoReturn

from scara_opt import interrupt


def main() -> NoReturn:
    """Load and run the command line, then end the process with its exit code.

    130 and one line on a Ctrl-C at any point; the end skips Python's teardown
    (:func:`scara_opt.interrupt.exit_now`: a Ctrl-C there would be a traceback or a death
    by SIGINT with no message).
    """
    code = 130
    try:
        with interrupt.watch():  # an import that turns the interrupt into another error
            from scara_opt.cli import main as run
        code = run()
    except KeyboardInterrupt:
        code = 130
        print("scara-opt: interrupted", file=sys.stderr)
    finally:  # also after a Ctrl-C between the lines above
        interrupt.exit_now(code)


if __name__ == "__main__":
    main()
