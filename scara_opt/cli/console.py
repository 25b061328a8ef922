"""The ``scara-opt`` console script: :func:`scara_opt.cli.app.main`, one line at every end.

A Ctrl-C while the command line's modules load (numpy, pandas: the first few tenths of a
second) printed Python's traceback of the import; one after the command finished could
print "Exception ignored ..." or kill the process by SIGINT with no message. Here the
first is the command line's one line ``scara-opt: interrupted`` and exit code 130, as
during the command, and the end is immediate (:func:`scara_opt.interrupt.exit_now`). An
error nobody expected, while loading or after, is one line naming it and exit code
:data:`~scara_opt.cli.messages.EXIT_INTERNAL` (never a silent 130). Only Python's own
start-up, before any of this package runs, is left to Python.
"""

from __future__ import annotations

import sys
from typing import NoReturn

from scara_opt import interrupt
from scara_opt.cli.messages import EXIT_INTERNAL, report_internal


def main() -> NoReturn:
    """Load and run the command line, then end the process with its exit code.

    130 and one line on a Ctrl-C at any point; an unexpected error is one line and
    :data:`~scara_opt.cli.messages.EXIT_INTERNAL`; the end skips Python's teardown
    (:func:`scara_opt.interrupt.exit_now`: a Ctrl-C there would be a traceback or a death
    by SIGINT with no message).
    """
    code = EXIT_INTERNAL
    try:
        try:
            with interrupt.watch():  # an import that turns the interrupt into another error
                from scara_opt.cli.app import main as run
            code = run()
        except KeyboardInterrupt:
            code = 130
            print("scara-opt: interrupted", file=sys.stderr)
        except Exception as exc:  # the command line itself failed to load
            code = report_internal(exc)
    except KeyboardInterrupt:  # a Ctrl-C while the lines above reported
        code = 130
    finally:  # also after a Ctrl-C between the lines above
        interrupt.exit_now(code)


if __name__ == "__main__":
    main()
