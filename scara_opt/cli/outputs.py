"""Output folders of the command line: checked first, never overwritten unasked, atomic.

A command's files are written into a hidden staging folder inside ``--out``
(``.scara-opt-partial-*``) and moved into ``--out`` with :func:`os.replace` only when the
run has finished, the file that says the run is complete (``summary.md``) last. A run
stopped part way (Ctrl-C, an error) removes its staging folder and leaves ``--out`` as it
was: no half-written file, no old ``summary.md`` beside new partial files.

Files already in ``--out`` that the run would write are refused before any work unless
the user passes ``--force``. A staging folder is named after the process that writes it
(``.scara-opt-partial-<pid>-*``): one whose process is gone (killed by SIGKILL, the machine
restarted) is removed by the next run into the same folder, so it never outlives its run
for long. :func:`write_animation` writes the ``--html`` page of a command.
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

STAGING_PREFIX = ".scara-opt-partial-"
#: the ``--force`` option's help, for every command that writes into ``--out``
FORCE_HELP = "overwrite files of an earlier run in --out (refused without it)"


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


def _alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (one of another user's counts as alive)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # PermissionError: it exists
        return True
    return True


def remove_stale_staging(folder: Path) -> list[Path]:
    """Remove the staging folders in ``folder`` whose process is gone; returns them.

    A run's own staging folder is removed when it ends (even by SIGTERM or SIGHUP, which
    the command line turns into an orderly stop); one left by a run killed outright is
    named with that run's process id, which no longer exists. A folder without a process
    id in its name is left alone.
    """
    removed = []
    for entry in folder.glob(f"{STAGING_PREFIX}*"):
        pid = entry.name[len(STAGING_PREFIX):].partition("-")[0]
        if entry.is_dir() and pid.isdigit() and int(pid) != os.getpid() \
                and not _alive(int(pid)):
            shutil.rmtree(entry, ignore_errors=True)
            removed.append(entry)
    return removed


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
            remove_stale_staging(self.final)
            self.staging = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-",
                                                 dir=self.final))
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
