"""Paper reproductions: one module per paper of ``shared/seeds``, one :class:`PaperReport` each.

Each module's ``run(out, quick)`` recomputes the paper's tables and figures with the toolkit,
writes them into ``out`` (CSV and PNG), and lists :class:`Finding` rows that say, item by
item, what matched the paper, what did not, and why. :func:`reproduce` runs one paper or all
and writes ``summary.md``. The CLI's ``scara-opt reproduce`` and the examples call these.
"""

from __future__ import annotations

import importlib
import time
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from scara_opt.errors import InputError
from scara_opt.reports.summary import summary_text, write_text_atomic
from scara_opt.reports.verdicts import VERDICTS

PAPERS = ("zavar2024", "peng2025", "nguyen", "inverted5", "fang")


@dataclass(frozen=True)
class Finding:
    """One checked item: the paper's value, ours, and the verdict with its rule.

    Attributes:
        item: what was checked (e.g. "Table 2, CA at population 40").
        paper: the paper's value, as printed.
        ours: our value, with units.
        verdict: one of :data:`~scara_opt.reports.verdicts.VERDICTS`, computed by a rule of
            :mod:`scara_opt.reports.verdicts` from what was measured (never a constant).
        why: the reason when it is not a plain match.
        rule: the rule the verdict was computed by, in words.
        basis: what the measurement rests on: ``"ik"``, ``"timing"``, ``"fk"`` or
            ``"workspace"`` (a test breaks each and checks no verdict still says matched).
    """

    item: str
    paper: str
    ours: str
    verdict: str
    why: str = ""
    rule: str = ""
    basis: str = ""

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"unknown verdict {self.verdict!r}; one of {VERDICTS}")


@dataclass
class PaperReport:
    """Tables (DataFrames, also written as CSV), figure files and findings of one paper."""

    paper: str
    title: str
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    figures: list[Path] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    time_s: float = 0.0
    #: (robot, motion, title) to animate in 3-D: a Trajectory, JointPath or (n, nq) poses
    animation: tuple[Any, Any, str] | None = None
    #: the 3-D animation written (``<paper>_animation.html``), if any
    animation_file: Path | None = None
    #: why the animation was not written (the ``view`` extra missing), or ""
    animation_error: str = ""

    def add_table(self, name: str, table: pd.DataFrame, out: Path) -> None:
        """Keep ``table`` and write it as ``out/<paper>_<name>.csv``."""
        self.tables[name] = table
        out.mkdir(parents=True, exist_ok=True)
        table.to_csv(out / f"{self.paper}_{name}.csv", index=False)

    def animation_note(self) -> str:
        """The note that the animation was not written, and why ("" when it was)."""
        return f"3-D animation not written ({self.animation_error})" if self.animation_error \
            else ""

    def to_markdown(self) -> str:
        """The paper's section of ``summary.md`` (the animation note is said in its header)."""
        lines = [f"## {self.paper}: {self.title}", ""]
        counts = {v: sum(f.verdict == v for f in self.findings) for v in VERDICTS}
        lines.append(", ".join(f"{n} {v}" for v, n in counts.items() if n) or "no findings")
        lines += ["", "| item | paper | ours | verdict | rule | why |",
                  "|---|---|---|---|---|---|"]
        for f in self.findings:
            cells = (f.item, f.paper, f.ours, f.verdict, f.rule, f.why)
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines += [""] + [f"- {n}" for n in self.notes if n != self.animation_note()]
        if self.figures:
            lines += ["", "Figures: " + ", ".join(f"[{p.name}]({p.name})" for p in self.figures)]
        if self.animation_file is not None:
            name = self.animation_file.name
            lines += ["", f"3-D animation (opens in a browser): [{name}]({name})"]
        lines += ["", f"(computed in {self.time_s:.1f} s)", ""]
        return "\n".join(lines)


def reference_data(paper: str) -> dict:
    """The paper's printed numbers (``reports/reference/<paper>.toml``), units, tolerance."""
    return tomllib.loads((Path(__file__).parent / "reference" / f"{paper}.toml").read_text())


def _check_paper(paper: str) -> None:
    """Raise InputError for a name not in :data:`PAPERS` (the message lists them)."""
    if paper not in PAPERS:
        raise InputError(f"unknown paper {paper!r}; papers: {', '.join(PAPERS)}, or 'all'")


def run_paper(paper: str, out: str | Path, quick: bool = False) -> PaperReport:
    """Reproduce one paper into ``out``.

    Raises:
        InputError: unknown paper name (the message lists them).
    """
    _check_paper(paper)
    module = importlib.import_module(f"scara_opt.reports.{paper}")
    start = time.perf_counter()
    report: PaperReport = module.run(Path(out), quick=quick)
    _write_animation(report, Path(out))
    report.time_s = time.perf_counter() - start
    return report


def _write_animation(report: PaperReport, out: Path) -> None:
    """``<paper>_animation.html`` of the report's motion (:mod:`scara_opt.view`).

    Without the ``view`` extra (meshcat) the report keeps why in its notes and
    :attr:`PaperReport.animation_error` (said once for all papers in ``summary.md``);
    nothing else changes.
    """
    if report.animation is None:
        return
    from scara_opt.view import write_html  # meshcat itself is imported at the first page

    robot, motion, title = report.animation
    try:
        report.animation_file = write_html(robot, motion,
                                           out / f"{report.paper}_animation.html", title=title)
    except ModuleNotFoundError as exc:  # the view extra (meshcat) is not installed
        report.animation_error = str(exc)
        report.notes.append(report.animation_note())


def reproduce(papers: str | Sequence[str] = "all", out: str | Path = "results",
              quick: bool = False, jobs: int = 1,
              progress: Callable[[PaperReport], object] | None = None) -> list[PaperReport]:
    """Reproduce papers (``"all"`` or names) into ``out`` and write ``out/summary.md``.

    ``jobs`` > 1 runs the papers in that many processes (each paper's numbers are seeded,
    so the files are those of a serial run; only the times differ). ``progress`` is called
    with each paper's report as soon as that paper is done (in the order they finish).

    Raises:
        InputError: unknown paper, or ``jobs`` not a whole number >= 1.
    """
    names = list(PAPERS) if papers == "all" else [papers] if isinstance(papers, str) else papers
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise InputError(f"jobs must be a whole number >= 1 (processes); got {jobs!r}")
    for name in names:
        _check_paper(name)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    done = progress or (lambda report: None)
    if jobs > 1 and len(names) > 1:
        reports = _in_processes(names, out, quick, min(jobs, len(names)), done)
    else:
        reports = []
        for name in names:
            reports.append(run_paper(name, out, quick))
            done(reports[-1])
    # written last and atomically: a summary.md means every table and figure is there
    write_text_atomic(out / "summary.md", summary_text(reports, quick))
    return reports


#: rough relative run times of the papers, only to share them out among processes
COST = {"zavar2024": 7.0, "nguyen": 3.0, "fang": 1.7, "peng2025": 1.0, "inverted5": 0.4}


def _lanes(names: Sequence[str], jobs: int) -> list[list[str]]:
    """The papers shared out among ``jobs`` processes, the longest first to the least loaded."""
    lanes: list[list[str]] = [[] for _ in range(jobs)]
    load = [0.0] * jobs
    for name in sorted(names, key=lambda n: -COST.get(n, 1.0)):
        k = load.index(min(load))
        lanes[k].append(name)
        load[k] += COST.get(name, 1.0)
    return [lane for lane in lanes if lane]


def _in_processes(names: Sequence[str], out: Path, quick: bool, jobs: int,
                  done: Callable[[PaperReport], object] | None = None) -> list[PaperReport]:
    """:func:`run_paper` of the papers in ``jobs`` fresh processes (:func:`_lanes`).

    Each worker (``python -m scara_opt.reports.worker``) runs in its own session, so a
    Ctrl-C reaches this process only; on any error or interrupt here the workers still
    running are killed before the caller cleans up its output, and a worker whose parent
    is gone (killed outright) ends itself (:mod:`scara_opt.reports.worker`). Each paper's
    report is handed to ``done`` as soon as its worker has written it. A worker that fails
    raises ``RuntimeError`` with the end of its stderr. The workers' warnings are issued
    again here, each once (as in one process: the command line shows them as its notes),
    and the rest of their stderr is passed on.
    """
    import os
    import pickle
    import subprocess
    import sys
    import tempfile

    with tempfile.TemporaryDirectory(prefix="scara_opt_reproduce_") as tmp:
        running = []
        reports: dict[str, PaperReport] = {}

        def collect() -> None:
            for name in names:
                pkl = Path(tmp) / f"{name}.pkl"
                if name not in reports and pkl.exists():
                    reports[name] = pickle.loads(pkl.read_bytes())
                    if done is not None:
                        done(reports[name])

        try:
            for k, lane in enumerate(_lanes(names, jobs)):
                log = Path(tmp) / f"worker{k}.err"
                with log.open("w") as err:
                    running.append((subprocess.Popen(
                        [sys.executable, "-m", "scara_opt.reports.worker", str(out),
                         "1" if quick else "0", tmp, *lane],
                        stdout=subprocess.DEVNULL, stderr=err, start_new_session=True,
                        env={**os.environ, "SCARA_OPT_REPRODUCE_PARENT": str(os.getpid())}),
                        log))
            while running:
                collect()
                for proc, log in list(running):
                    if proc.poll() is None:
                        continue
                    running.remove((proc, log))
                    if proc.returncode != 0:
                        tail = log.read_text()[-2000:].strip()
                        raise RuntimeError(f"reproduce: a worker process failed (exit "
                                           f"{proc.returncode}): {tail}")
                time.sleep(0.02)
            collect()
        finally:
            for proc, _ in running:
                proc.kill()
                proc.wait()
        _pass_on(Path(tmp))
        return [reports[name] for name in names]


def _pass_on(folder: Path) -> None:
    """The workers' warnings issued again here, each once; their other stderr passed on."""
    import pickle
    import sys
    import warnings

    seen: set[tuple[type[Warning], str]] = set()
    for record in sorted(folder.glob("*.warnings")):
        for category, message in pickle.loads(record.read_bytes()):
            if (category, message) not in seen:
                seen.add((category, message))
                warnings.warn(message, category, stacklevel=2)
    for log in sorted(folder.glob("worker*.err")):
        sys.stderr.write(log.read_text())
