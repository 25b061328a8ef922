"""``scara-opt reproduce PAPER|all --out DIR``: the papers' tables, figures and summary.md.

A line per paper as it finishes (its verdicts and time), then the summary's path. The
papers run in ``--jobs`` processes at once (:func:`scara_opt.reports.reproduce`).
"""

from __future__ import annotations

import argparse
import os
from typing import TYPE_CHECKING

from scara_opt.cli.args import add_out, int_at_least
from scara_opt.cli.outputs import OutputDir

if TYPE_CHECKING:
    from scara_opt.reports import PaperReport

#: most processes --jobs starts
MAX_JOBS = 256


def _line(rep: PaperReport) -> str:
    """``paper: 3 matched, 1 differs (2.1 s)``."""
    verdicts = [f.verdict for f in rep.findings]
    counts = ", ".join(f"{verdicts.count(v)} {v}" for v in dict.fromkeys(verdicts))
    return f"{rep.paper}: {counts} ({rep.time_s:.1f} s)"


def cmd_reproduce(args: argparse.Namespace) -> int:
    """Reproduce one paper or all: tables, figures and summary.md."""
    from scara_opt.reports import PAPERS, reproduce

    papers = PAPERS if args.paper == "all" else [args.paper]
    writes = ["summary.md", *(f"{p}_*" for p in papers)]
    with OutputDir(args.out, writes, args.force, last=["summary.md"]) as out:
        assert out.staging is not None
        reproduce(args.paper, out.staging, quick=args.quick, jobs=args.jobs,
                  progress=lambda rep: print(_line(rep), flush=True))
    print(f"wrote {out.final / 'summary.md'}")
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``reproduce`` to the subparsers ``sub``."""
    from scara_opt.reports import PAPERS

    p = sub.add_parser("reproduce", parents=parents,
                       help="reproduce a paper's tables and figures, or all")
    p.add_argument("paper", metavar="PAPER", choices=[*PAPERS, "all"],
                   help=f"one of {', '.join(PAPERS)}, or all")
    add_out(p, required=True, what=" (summary.md, CSV, PNG)")
    p.add_argument("--quick", action="store_true", help="reduced sweeps for a first look")
    p.add_argument("--jobs", type=int_at_least(1, MAX_JOBS),
                   default=min(2, os.cpu_count() or 1), metavar="N",
                   help="papers run in N processes at once (default: 2, or 1 on a single "
                        "core; the files are those of a serial run)")
    p.set_defaults(func=cmd_reproduce)
