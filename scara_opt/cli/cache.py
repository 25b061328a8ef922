"""``scara-opt cache [clear]``: the native-code cache folder, and emptying it.

``scara-opt cache`` says where the folder is and what it holds; ``scara-opt cache clear``
removes the libraries in it (each ``<name>_<key>.so`` with its record ``.json`` and its
lock file), and nothing else: a folder that ``$SCARA_OPT_CACHE`` points at may hold other
files, and they are left alone. A library whose lock another process holds (it is being
built, or waited for) is left too, and said; the libraries are built again when next used
(:mod:`scara_opt.model.compiled`).
"""

from __future__ import annotations

import argparse
import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

#: a cache entry's name: ``<name>_<24 hex digits>`` and one of these suffixes
ENTRY = re.compile(r"^(?P<stem>.+_[0-9a-f]{24})\.(so|json|lock)$")


def entries(folder: Path) -> dict[str, list[Path]]:
    """The cache's entries in ``folder``: the library stem -> its files (.so, .json, .lock)."""
    found: dict[str, list[Path]] = {}
    if folder.is_dir():
        for path in sorted(folder.iterdir()):
            match = ENTRY.match(path.name)
            if match and path.is_file():
                found.setdefault(match["stem"], []).append(path)
    return found


@contextmanager
def _held(lock: Path) -> Iterator[bool]:
    """Hold ``lock`` (``flock``, not waiting): whether it was taken (or is absent).

    False when another process holds it (a build under way, or one waited for).
    """
    try:
        import fcntl
    except ImportError:  # not POSIX: the builds hold no lock either
        yield True
        return
    try:
        fd = os.open(lock, os.O_RDWR)
    except OSError:  # no lock file
        yield True
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            yield False
            return
        yield True
    finally:
        os.close(fd)  # releases the lock


def clear(folder: Path) -> tuple[int, int, list[str]]:
    """Remove the cache's libraries in ``folder``; returns (libraries, bytes, those in use).

    Each library's lock is taken first and held while its files go (the lock file last):
    one held by another process (a build under way) is skipped and named.
    """
    removed, size, busy = 0, 0, []
    for stem, files in entries(folder).items():
        with _held(folder / f"{stem}.lock") as free:
            if not free:
                busy.append(stem)
                continue
            for path in sorted(files, key=lambda p: p.suffix == ".lock"):
                try:
                    size += path.stat().st_size
                    path.unlink()
                except FileNotFoundError:  # removed by another clear meanwhile
                    pass
            removed += any(p.suffix == ".so" for p in files)
    return removed, size, busy


def cmd_cache(args: argparse.Namespace) -> int:
    """Where the cache is and what it holds; ``clear`` empties it of its libraries."""
    from scara_opt.model import compiled

    folder = compiled.cache_dir()
    if args.action == "clear":
        removed, size, busy = clear(folder)
        print(f"removed {removed} libraries ({size / 1024:.0f} KiB) from {folder}"
              + (f"; left {len(busy)} in use by another process: {', '.join(busy)}"
                 if busy else ""))
        return 0
    found = entries(folder)
    libraries = [p for files in found.values() for p in files if p.suffix == ".so"]
    size = sum(p.stat().st_size for files in found.values() for p in files)
    print(f"cache folder: {folder}"
          + ("" if folder.is_dir() else " (not created yet)"))
    print(f"  {len(libraries)} libraries, {size / 1024:.0f} KiB; `scara-opt cache clear` "
          "removes them (built again when next used)")
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``cache`` to the subparsers ``sub``."""
    p = sub.add_parser("cache", parents=parents,
                       help="the native-code cache: where, what it holds; clear empties it")
    p.add_argument("action", nargs="?", choices=["show", "clear"], default="show",
                   help="show (default) or clear")
    p.set_defaults(func=cmd_cache)
