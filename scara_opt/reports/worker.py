"""Papers run in a fresh process, for ``reproduce(jobs=N)``.

``python -m scara_opt.reports.worker OUT QUICK RESULTS PAPER [PAPER ...]``: runs
:func:`~scara_opt.reports.run_paper` of each paper in turn into ``OUT`` (``QUICK`` is ``1``
or ``0``) and pickles each :class:`~scara_opt.reports.PaperReport` into
``RESULTS/<paper>.pkl`` (the animation, written already, is not sent back). SIGINT is
ignored: the parent process stops the workers.
"""

from __future__ import annotations

import pickle
import signal
import sys
from collections.abc import Sequence
from pathlib import Path


def main(argv: Sequence[str]) -> None:
    """Run the papers named in ``argv`` and write their pickled reports (see the module)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    out, quick, results, *papers = argv
    from scara_opt.reports import run_paper

    for paper in papers:
        report = run_paper(paper, out, quick == "1")
        report.animation = None
        Path(results, f"{paper}.pkl").write_bytes(pickle.dumps(report))


if __name__ == "__main__":
    main(sys.argv[1:])
