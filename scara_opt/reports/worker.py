"""Papers run in a fresh process, for ``reproduce(jobs=N)``.

``python -m scara_opt.reports.worker OUT QUICK RESULTS PAPER [PAPER ...]``: runs
:func:`~scara_opt.reports.run_paper` of each paper in turn into ``OUT`` (``QUICK`` is ``1``
or ``0``) and pickles each :class:`~scara_opt.reports.PaperReport` into
``RESULTS/<paper>.pkl`` as soon as it is done (the animation, written already, is not sent
back), written under another name and renamed, so the parent never reads half a file. The
warnings it raises are pickled into ``RESULTS/<first paper>.warnings`` for the parent to
issue again (Python would print them as ``<frozen runpy>:88: CompilingWarning: ...``).

SIGINT is ignored: the parent process stops the workers. A worker whose parent is gone
(ended by SIGKILL, or any way that skipped its clean-up) is ended with it (Linux's
``PR_SET_PDEATHSIG``; elsewhere a thread looks every :data:`WATCH_S`), so it never goes on
writing into a folder nobody will collect.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
import threading
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: the environment variable by which the parent gives its process id (a worker still
#: loading when its parent died would otherwise take its new parent for it)
PARENT_ENV = "SCARA_OPT_REPRODUCE_PARENT"
#: how often a worker checks that its parent is still there [s]
WATCH_S = 0.2


def _watch_parent(parent: int) -> None:
    """End this process at once when its parent is gone (it is then adopted: a new ppid)."""
    while True:
        time.sleep(WATCH_S)
        if os.getppid() != parent:
            os._exit(1)


def _end_with_parent(parent: int) -> None:
    """Have the kernel end this process with its parent (Linux ``PR_SET_PDEATHSIG``).

    A thread watches the parent as well (other systems; a long C call that holds the GIL
    delays only the thread).
    """
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):  # not Linux
        pass
    if os.getppid() != parent:  # gone before the line above
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def _write(path: Path, data: bytes) -> None:
    """``data`` into ``path`` through a temporary name and a rename."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def main(argv: Sequence[str]) -> None:
    """Run the papers named in ``argv`` and write their pickled reports (see the module)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _end_with_parent(int(os.environ.get(PARENT_ENV, os.getppid())))
    out, quick, results, *papers = argv
    caught: list[tuple[type[Warning], str]] = []

    def keep(message: Warning | str, category: type[Warning], filename: str, lineno: int,
             file: Any = None, line: str | None = None) -> None:
        caught.append((category, str(message)))

    warnings.showwarning = keep
    from scara_opt.reports import run_paper

    try:
        for paper in papers:
            report = run_paper(paper, out, quick == "1")
            report.animation = None
            _write(Path(results, f"{paper}.pkl"), pickle.dumps(report))
    finally:
        if caught:
            _write(Path(results, f"{papers[0]}.warnings"), pickle.dumps(caught))


if __name__ == "__main__":
    main(sys.argv[1:])
