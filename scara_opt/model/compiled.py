"""casadi Functions (and small C kernels) compiled once per machine, kept in a cache folder.

:func:`compiled` returns a casadi Function from a shared library in the cache folder when
one exists for its key (loading it costs well under a millisecond: no symbolic build, no
compilation); otherwise it builds the Function, generates its C code (casadi
``Function.generate``), compiles it with the system's C compiler and keeps the library for
every later process. Where no compiler works (or ``SCARA_OPT_NO_COMPILE=1``), the built
Function is returned as it is, evaluated by casadi's virtual machine: the same numbers,
slower.

:func:`c_library` does the same for a hand-written C source shipped with the package (a
metaheuristic's inner loop): the loaded ``ctypes`` library, or ``None`` where nothing
compiles, so the caller runs its numpy form instead.

The key is a hash of what the Function depends on, given by the caller (e.g. the robot's
kinematic parameters and the source of the module that builds it), together with the
casadi version and the compiler flags: a change to any of them compiles anew.

Folder: ``$SCARA_OPT_CACHE``, else ``$XDG_CACHE_HOME/scara_opt``, else
``~/.cache/scara_opt``. Libraries are written under a temporary name and renamed, so
concurrent processes never load a half-written file.
"""

from __future__ import annotations

import ctypes
import hashlib
import logging
import os
import shutil
import subprocess
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import casadi as ca

log = logging.getLogger(__name__)

#: the C compiler and its flags (``$CC`` overrides the compiler); no fused multiply-add:
#: the metaheuristics' kernels give numpy's bits only with one rounding per operation (none
#: in x86-64's base set anyway; aarch64 would fuse ``a * b + c``)
FLAGS = ("-O2", "-ffp-contract=off", "-shared", "-fPIC")
#: set to 1 to never compile (casadi's virtual machine evaluates the Functions)
NO_COMPILE_ENV = "SCARA_OPT_NO_COMPILE"
#: the cache folder's environment variable
CACHE_ENV = "SCARA_OPT_CACHE"

_LOCK = threading.Lock()
_LOADED: dict[str, ca.Function] = {}
_PATHS: dict[str, Path] = {}  # Function name -> the library it was loaded from
_LIBRARIES: dict[str, ctypes.CDLL | None] = {}
_WARNED: set[str] = set()


def cache_dir() -> Path:
    """The folder compiled libraries are kept in (see the module docstring)."""
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "scara_opt"


def source_hash(*paths: str | Path) -> str:
    """A hash of files' contents: part of a key, so a code change compiles anew."""
    h = hashlib.sha256()
    for path in paths:
        h.update(Path(path).read_bytes())
    return h.hexdigest()


def _compiler() -> str | None:
    return os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")


def compiled(name: str, key: str, build: Callable[[], ca.Function]) -> ca.Function:
    """The Function ``name`` for ``key``: loaded from the cache, or built and compiled.

    Args:
        name: the Function's name (a C identifier; ``build`` must name it so).
        key: everything the Function depends on, as text (hashed here).
        build: builds the Function (called only when no library is cached).

    Returns:
        The compiled Function, or the built one where compiling is off or fails (logged
        once per name).
    """
    digest = hashlib.sha256(repr((key, ca.__version__, FLAGS)).encode()).hexdigest()[:24]
    path = cache_dir() / f"{name}_{digest}.so"
    with _LOCK:
        if str(path) in _LOADED:
            return _LOADED[str(path)]
        if path.is_file():
            try:
                _LOADED[str(path)] = ca.external(name, str(path))
                _PATHS[name] = path
                return _LOADED[str(path)]
            except RuntimeError:  # a corrupt or foreign library: build it again
                path.unlink(missing_ok=True)
    f = build()
    if os.environ.get(NO_COMPILE_ENV) == "1" or (cc := _compiler()) is None:
        return f
    try:
        _compile(f, name, cc, path)
        loaded = ca.external(name, str(path))
    except (OSError, RuntimeError, subprocess.SubprocessError) as exc:
        if name not in _WARNED:
            _WARNED.add(name)
            log.warning("could not compile %s (%s); casadi's virtual machine evaluates it "
                        "(same numbers, slower)", name, exc)
        return f
    with _LOCK:
        _LOADED[str(path)] = loaded
        _PATHS[name] = path
    return loaded


def library_path(name: str) -> Path | None:
    """The library :func:`compiled` loaded the Function ``name`` from, or ``None``.

    ``None``: not compiled in this process (casadi's virtual machine evaluates it). The
    library's C entry point is ``name`` with casadi's signature, for C code that calls it
    directly (:mod:`scara_opt.ik.lm_driver`).
    """
    return _PATHS.get(name)


def _compile(f: ca.Function, name: str, cc: str, path: Path) -> None:
    """Generate ``f``'s C code and compile it into ``path`` (written atomically)."""
    def generate(tmp: str) -> str:
        generator = ca.CodeGenerator(f"{name}.c")
        generator.add(f)
        return generator.generate(tmp + os.sep)

    _build(cc, path, generate)


def _build(cc: str, path: Path, source: Callable[[str], str], libs: tuple[str, ...] = ()) -> None:
    """Compile the C file ``source(tmp)`` returns into the library ``path``, atomically.

    ``tmp``: a scratch folder beside ``path`` (for generated sources); the library is written
    there under a temporary name and renamed, so no process loads a half-written file.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=path.parent) as tmp:
        partial = Path(tmp) / path.name
        subprocess.run([cc, *FLAGS, "-o", str(partial), source(tmp), *libs], check=True,
                       capture_output=True, timeout=600)
        os.replace(partial, path)


def c_library(source: str | Path) -> ctypes.CDLL | None:
    """The C file ``source`` compiled into a shared library in the cache folder, loaded.

    Compiled once per machine (keyed by the source's contents and the flags), loaded once
    per process. ``None`` where compiling is off (``SCARA_OPT_NO_COMPILE=1``) or no compiler
    works (logged once): the caller falls back to its numpy form.
    """
    source = Path(source)
    digest = hashlib.sha256(repr((source_hash(source), FLAGS)).encode()).hexdigest()[:24]
    path = cache_dir() / f"{source.stem}_{digest}.so"
    with _LOCK:
        if str(path) in _LIBRARIES:
            return _LIBRARIES[str(path)]
    lib = None
    if os.environ.get(NO_COMPILE_ENV) != "1" and (cc := _compiler()) is not None:
        try:
            if not path.is_file():
                _build(cc, path, lambda _tmp: str(source), ("-lm",))
            lib = ctypes.CDLL(str(path))
        except (OSError, subprocess.SubprocessError) as exc:
            if source.stem not in _WARNED:
                _WARNED.add(source.stem)
                log.warning("could not compile %s (%s); its numpy form runs instead (same "
                            "rule, slower)", source.name, exc)
    with _LOCK:
        _LIBRARIES[str(path)] = lib
    return lib


def c_function(source: str | Path, name: str, argtypes: list[Any],
               restype: Any = None) -> Callable[..., Any] | None:
    """Function ``name`` of the C file ``source``, with its ctypes signature set.

    Compiled and loaded by :func:`c_library`; ``None`` where nothing compiles (the caller
    runs its numpy form).
    """
    lib = c_library(source)
    if lib is None:
        return None
    fn = getattr(lib, name)
    fn.argtypes, fn.restype = argtypes, restype
    return fn
