"""Output folders of the command line: checked first, never overwritten unasked, atomic.

A command's files are written into a hidden staging folder inside ``--out``
(``.scara-opt-partial-*``) and moved into ``--out`` with :func:`os.replace` only when the
run has finished, the file that says the run is complete (``summary.md``) last. A run
stopped part way (Ctrl-C, an error) removes its staging folder and leaves ``--out`` as it
was: no half-written file, no old ``summary.md`` beside new partial files.

Files already in ``--out`` that the run would write are refused before any work unless
the user passes ``--force``. :func:`write_compare` and :func:`write_joint_path` write the
tables and figures of ``compare`` and ``path``.
"""

from __future__ import annotations

import fnmatch
import os
import shutil
import tempfile
from collections.abc import Iterable
from pathlib import Path
from types import TracebackType
from typing import Any

from scara_opt import interrupt
from scara_opt.errors import InputError

#: the files of ``scara-opt compare``
COMPARE_FILES = ("runs.csv", "summary.csv", "convergence.png", "time_vs_population.png",
                 "error_time_boxes.png")

STAGING_PREFIX = ".scara-opt-partial-"
#: the ``--force`` option's help, for every command that writes into ``--out``
FORCE_HELP = "overwrite files of an earlier run in --out (refused without it)"


def html_name(text: object, option: str = "--html") -> str:
    """``text`` as the name of an HTML file written inside ``--out``: ``name.html``, no folder.

    Raises:
        InputError: empty, a NUL byte, a folder part, or not ending in ``.html``.
    """
    name = check_path_text(option, text)
    if Path(name).name != name or name in (".", "..") or not name.lower().endswith(".html"):
        raise InputError(f"{option} takes a file name ending in .html, written inside --out "
                         f"(e.g. {option} path.html); got {name!r}")
    return name


def check_path_text(option: str, text: object) -> str:
    """``text`` as a path string: not empty, no NUL byte.

    Raises:
        InputError: names the option and what to pass instead.
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError(f"{option} must be a path; got {text!r}; pass a folder name, "
                         "e.g. results")
    if "\0" in text:
        raise InputError(f"{option} contains a NUL byte ({text!r}); pass a plain path")
    return text


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in its folder and a rename."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


class OutputDir:
    """The ``--out`` folder of one command (a context manager around the staging folder).

    Args:
        path: the folder the user named (created if missing).
        writes: names (glob patterns allowed) of the files the command writes there.
        force: overwrite files of ``writes`` that are already there.
        last: the files moved in last, after every other (e.g. ``summary.md``).
        option: the option's name, for messages.

    Raises:
        InputError: an empty path or one with a NUL byte, an existing file, the filesystem
            root, a folder that cannot be created or written, or (without ``force``)
            files of ``writes`` already in the folder.
    """

    def __init__(self, path: str, writes: Iterable[str], force: bool = False,
                 last: Iterable[str] = (), option: str = "--out") -> None:
        self.option = option
        self.final = Path(check_path_text(option, path))
        self.writes, self.last, self.force = list(writes), list(last), force
        self.staging: Path | None = None
        self._moved: set[str] = set()
        try:
            is_file = self.final.exists() and not self.final.is_dir()
            is_root = self.final.resolve() == Path(self.final.resolve().anchor)
        except OSError as exc:  # a name too long, a loop of links
            raise InputError(f"cannot use {option} {path!r}: {exc.strerror or exc}; pass "
                             "another folder") from None
        if is_file:
            raise InputError(f"{option} {path!r} is a file, not a folder; pass a folder "
                             "(it is created if missing)")
        if is_root:
            raise InputError(f"{option} {path!r} is the filesystem root; pass a folder of "
                             "its own, e.g. results")
        if not force:
            self._refuse(self.conflicts())

    def conflicts(self) -> list[str]:
        """Files already in the folder that this command would write (sorted names)."""
        if not self.final.is_dir():
            return []
        return sorted(p.name for p in self.final.iterdir() if p.name not in self._moved
                      and any(fnmatch.fnmatchcase(p.name, w) for w in self.writes))

    def _refuse(self, names: list[str]) -> None:
        if names:
            shown = ", ".join(names[:8]) + (f" and {len(names) - 8} more" if len(names) > 8
                                            else "")
            raise InputError(f"{self.option} {str(self.final)!r} already holds {shown}, which "
                             "this run would overwrite; pass --force to overwrite them, or "
                             "choose a new folder")

    def __enter__(self) -> OutputDir:
        try:
            self.final.mkdir(parents=True, exist_ok=True)
            self.staging = Path(tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=self.final))
        except OSError as exc:
            raise InputError(f"cannot write into {self.option} {str(self.final)!r}: "
                             f"{exc.strerror or exc}; pass a writable folder") from None
        return self

    def __truediv__(self, name: str) -> Path:
        """Where the command writes ``name`` now (inside the staging folder)."""
        if self.staging is None:
            raise RuntimeError("OutputDir used outside its with block")
        return self.staging / name

    def final_path(self, path: str | Path) -> Path:
        """The path in ``--out`` that a staged file ends up at."""
        return self.final / Path(path).name

    def commit(self) -> list[Path]:
        """Move every staged file into the folder, the ``last`` ones last; returns them.

        An old file of ``last`` is removed first, so that until the new one is in place
        no ``summary.md`` says the folder is complete.
        """
        assert self.staging is not None
        if not self.force:  # a file that appeared while the command ran
            self._refuse(self.conflicts())
        staged = sorted(p for p in self.staging.iterdir() if p.is_file())
        late = [p for p in staged if p.name in self.last]
        for p in late:
            (self.final / p.name).unlink(missing_ok=True)
        moved = []
        for p in [p for p in staged if p.name not in self.last] + late:
            os.replace(p, self.final / p.name)
            self._moved.add(p.name)
            moved.append(self.final / p.name)
        return moved

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        try:
            if kind is None:
                interrupt.raise_if_received()  # a Ctrl-C that a library swallowed
                self.commit()
        finally:
            if self.staging is not None:
                shutil.rmtree(self.staging, ignore_errors=True)
                self.staging = None


def write_compare(out: OutputDir, table: Any, tol: float) -> Any:
    """compare's :data:`COMPARE_FILES` (CSV with units in the column names, 3 figures).

    Returns:
        The summary table (a DataFrame, SI units).
    """
    from scara_opt.comparison import convergence, summarize, with_units
    from scara_opt.plots import plot_boxes, plot_convergence, plot_time_vs_population

    with_units(table.drop(columns=["history"])).to_csv(out / "runs.csv", index=False)
    summary = summarize(table, tol=tol)
    with_units(summary).to_csv(out / "summary.csv", index=False)
    plot_convergence(convergence(table), out / "convergence.png")
    plot_time_vs_population(summary, out / "time_vs_population.png")
    plot_boxes(table, ["error", "time_s"], out / "error_time_boxes.png")
    return summary


def write_joint_path(jp: Any, robot: Any, path: Path) -> None:
    """One CSV row per path point: target, status, residual and q, in SI units."""
    import pandas as pd

    units = ["rad" if t == "revolute" else "m" for t in robot.joint_types]
    rows = []
    for i, (t, res) in enumerate(zip(jp.targets, jp.results, strict=True)):
        row: dict[str, Any] = {"point": i, "x_m": t.position[0], "y_m": t.position[1],
                               "z_m": t.position[2], "status": res.status.value,
                               "error_m_rad": res.error}
        row.update({f"{n}_{u}": v for n, u, v in zip(robot.joint_names, units, res.q,
                                                     strict=True)})
        rows.append(row)
    pd.DataFrame(rows).to_csv(path, index=False)


def write_animation(robot: Any, motion: Any, path: Path, title: str) -> Path:
    """``--html``: the 3-D animation of ``motion`` (:func:`scara_opt.view.write_html`).

    Raises:
        InputError: the view extra (meshcat) is not installed (the message says how to get it).
    """
    from scara_opt.view import write_html

    try:
        return write_html(robot, motion, path, title=title)
    except ModuleNotFoundError as exc:  # meshcat is imported at the first page
        raise InputError(f"--html: {exc}; or drop --html") from None
