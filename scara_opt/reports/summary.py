"""``summary.md``: a roll-up across the papers, then each paper's findings; written atomically.

The roll-up counts every verdict per paper and in all; what the papers share (the 3-D
animations not written without the ``view`` extra) is said once there, not once per paper.
The file is written through a temporary file and a rename, with the permissions of any
other file the run writes (``0666`` less the umask: ``0644`` as a rule).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from scara_opt.reports.verdicts import VERDICTS

if TYPE_CHECKING:
    from scara_opt.reports import PaperReport


def _umask() -> int:
    """The process's umask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in its folder and a rename.

    The file gets the mode an ordinary ``open(path, "w")`` would (``0666`` less the umask),
    not the ``0600`` of a temporary file.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def rollup(reports: Sequence[PaperReport]) -> list[str]:
    """The roll-up table: each verdict's count per paper and in all (verdicts seen only)."""
    counts = {r.paper: {v: sum(f.verdict == v for f in r.findings) for v in VERDICTS}
              for r in reports}
    seen = [v for v in VERDICTS if any(c[v] for c in counts.values())]
    lines = ["| paper | " + " | ".join(seen) + " | findings | time |",
             "|---" * (len(seen) + 3) + "|"]
    for r in reports:
        row = [str(counts[r.paper][v]) for v in seen]
        lines.append(f"| {r.paper} | " + " | ".join(row)
                     + f" | {len(r.findings)} | {r.time_s:.1f} s |")
    total = [str(sum(c[v] for c in counts.values())) for v in seen]
    lines.append("| **all** | " + " | ".join(total)
                 + f" | {sum(len(r.findings) for r in reports)} | "
                 f"{sum(r.time_s for r in reports):.1f} s |")
    return lines


def summary_text(reports: Sequence[PaperReport], quick: bool) -> str:
    """The whole of ``summary.md``: header, roll-up, shared notes, then each paper."""
    lines = ["# scara_opt: reproduction of the papers", "",
             f"Mode: {'quick (reduced sweeps)' if quick else 'full'}. Each section lists what "
             "was checked against the paper, what matched, what did not, and why. Verdicts: "
             "matched; ours better / ours worse (a difference, and which side ours is on: "
             "faster or slower, a smaller or larger error); differs (a difference with no "
             "better side: another ranking); paper inconsistent (the paper claims what a "
             "certificate disproves); figure only; beyond the paper.", "", *rollup(reports),
             ""]
    missing = [r for r in reports if r.animation_error]
    if missing:
        reasons = sorted({r.animation_error for r in missing})
        lines += [f"3-D animations not written ({', '.join(r.paper for r in missing)}): "
                  + "; ".join(reasons), ""]
    return "\n".join(lines + [r.to_markdown() for r in reports])
