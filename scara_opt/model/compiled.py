"""Native code compiled once per machine, kept in a cache folder, checked before each load.

:func:`compiled` returns a casadi Function from a shared library in the cache folder when
one exists for its key (loading it costs well under a millisecond: no symbolic build, no
compilation); otherwise it builds the Function, generates its C code (casadi
``Function.generate``), compiles it with the system's C compiler and keeps the library for
every later process. :func:`c_library` does the same for a hand-written C source shipped
with the package (a metaheuristic's inner loop, the fast IK's start loop): the loaded
``ctypes`` library, or ``None``, so the caller runs its numpy form instead.

**Checked, never trusted.** A library is loaded only after its size and SHA-256 match the
record written beside it when it was built (``<library>.json``): a truncated, garbled or
half-copied file is built again, never mapped (a truncated library mapped into a process
kills it with SIGBUS). Libraries and records are written under temporary names and
renamed.

**One build per key.** A build holds a lock on ``<library>.lock`` (``flock``, so another
process waits for it) and a lock per library in the process (so does another thread);
whoever waited then loads what was built. Three processes starting together on an empty
cache compile each library once.

**Key.** A hash of what the code depends on (given by the caller: the robot's kinematic
parameters and the source of the modules that build it), the casadi version, the compiler
flags, the platform (OS, machine architecture, C library) and the compiler (its command
and the first line of its ``--version``): a change to any compiles anew, and machines that
share a home folder keep apart libraries.

**Compiler.** ``$CC``, split into words like a shell does (``CC="ccache gcc"``), else
``cc`` or ``gcc`` on the ``PATH``. **Folder.** ``$SCARA_OPT_CACHE``, else
``$XDG_CACHE_HOME/scara_opt``, else ``~/.cache/scara_opt``; delete it at any time.
``SCARA_OPT_NO_COMPILE=1``: compile nothing; the C kernels stay off (their numpy forms
run) and casadi Functions load from the cache only where already there.

**Fallback, said once.** Where no compiler works, a build fails, or the cache folder is not
writable, the pure forms run (casadi's virtual machine, numpy): the same numbers, slower.
That is said once per process as a :class:`~scara_opt.errors.FallbackWarning`, with the
cause (the compiler's own error text included) and the remedy; a build slower than
:data:`SLOW_BUILD_S` in all (the first call's one-off cost) once as a
:class:`~scara_opt.errors.CompilingWarning`. The command line prints each as one
``note:`` line. :func:`natives` lists what this process loaded, built and fell back on
(``scara-opt doctor``).
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import json
import logging
import os
import platform
import shlex
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import Any, TypeVar

import casadi as ca

from scara_opt.errors import CompilingWarning, FallbackWarning, NativeCodeWarning

try:
    import fcntl
except ImportError:  # not a POSIX system: the thread lock alone
    _FLOCK = False
else:
    _FLOCK = True

log = logging.getLogger(__name__)

#: the compiler flags; no fused multiply-add: the metaheuristics' kernels give numpy's bits
#: only with one rounding per operation (none in x86-64's base set anyway; aarch64 would
#: fuse ``a * b + c``)
FLAGS = ("-O2", "-ffp-contract=off", "-shared", "-fPIC")
#: set to 1 to never compile (casadi's virtual machine and numpy run)
NO_COMPILE_ENV = "SCARA_OPT_NO_COMPILE"
#: the cache folder's environment variable
CACHE_ENV = "SCARA_OPT_CACHE"
#: builds longer than this in all [s] are said once per process (a ``CompilingWarning``)
SLOW_BUILD_S = 0.5
#: longest a compiler may run on one library [s]
BUILD_TIMEOUT_S = 600.0
#: characters of the compiler's error output a warning keeps (its end; the log has it all)
ERROR_TEXT_CHARS = 1200

T = TypeVar("T")

_CASADI = str(getattr(ca, "__version__", "unknown"))  # part of every key

_LOCK = threading.Lock()                    # guards the dicts and the set below
_KEY_LOCKS: dict[str, threading.Lock] = {}  # one per library path: one build per key
_LOADED: dict[str, ca.Function] = {}        # library path -> its Function (or the fallback)
_PATHS: dict[str, Path] = {}                # Function name -> the library it was loaded from
_LIBRARIES: dict[str, ctypes.CDLL | None] = {}  # library path -> the C library (None: numpy)
_NATIVES: dict[str, Native] = {}            # name -> what became of it in this process
_SAID: set[type[NativeCodeWarning]] = set()
_BUILD_S = [0.0]                            # seconds spent building in this process


class _BuildFailed(Exception):
    """The compiler refused or could not run (the message has its error text)."""


@dataclass(frozen=True)
class Toolchain:
    """The C compiler that builds the libraries.

    Attributes:
        command: ``$CC`` split into words like a shell does, or the ``cc``/``gcc`` found.
        version: the first line of ``command --version`` (part of every library's key).
        origin: ``"$CC"`` or ``"PATH"``.
    """

    command: tuple[str, ...]
    version: str
    origin: str

    @property
    def identity(self) -> str:
        """The command and its version, as the key holds them."""
        return f"{shlex.join(self.command)} | {self.version}"


@dataclass(frozen=True)
class Native:
    """What became of one native library in this process (see :func:`natives`).

    Attributes:
        name: the casadi Function's name, or the C file's.
        state: ``"loaded"`` (from the cache, checked), ``"built"`` (compiled now),
            ``"fallback"`` (the pure form runs; ``detail`` says why) or ``"off"``
            (``SCARA_OPT_NO_COMPILE=1``).
        path: the library, or ``None``.
        detail: the build time, or the reason for the fallback.
    """

    name: str
    state: str
    path: Path | None
    detail: str = ""


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


def platform_id() -> str:
    """The OS, machine architecture and C library, as every key holds them."""
    try:
        libc = os.confstr("CS_GNU_LIBC_VERSION") or ""
    except (AttributeError, ValueError, OSError):  # not glibc, or no confstr
        libc = ""
    return " ".join(filter(None, (sys.platform, platform.machine(), libc)))


def toolchain() -> Toolchain | str:
    """The C compiler (``$CC`` split like a shell, else ``cc``/``gcc``), or why there is none.

    Found once per process for each ``$CC`` and ``$PATH`` (running ``--version`` costs a
    few milliseconds).
    """
    return _toolchain(os.environ.get("CC", ""), os.environ.get("PATH", os.defpath))


@functools.lru_cache(maxsize=8)
def _toolchain(cc: str, search: str) -> Toolchain | str:
    if cc.strip():
        try:
            command = tuple(shlex.split(cc))
        except ValueError as exc:
            return f"CC={cc!r} cannot be split into words like a shell does ({exc}); fix CC"
        if shutil.which(command[0], path=search) is None:
            return (f"CC={cc!r} names {command[0]!r}, which is not an executable on the PATH; "
                    "install it, or fix or unset CC")
        origin = "$CC"
    else:
        found = shutil.which("cc", path=search) or shutil.which("gcc", path=search)
        if found is None:
            return ("no C compiler found (CC is not set, and neither cc nor gcc is on the "
                    "PATH); install one (e.g. `apt install gcc`) or set CC")
        command, origin = (found,), "PATH"
    try:
        run = subprocess.run([*command, "--version"], capture_output=True, text=True,
                             timeout=60)
    except (OSError, subprocess.SubprocessError) as exc:
        return f"the C compiler `{shlex.join(command)}` does not run ({exc}); fix or unset CC"
    lines = [line.strip() for line in run.stdout.splitlines() if line.strip()]
    version = lines[0] if run.returncode == 0 and lines else \
        f"unknown (`--version` exited with {run.returncode})"
    return Toolchain(command, version, origin)


def _library(stem: str, key: str, chain: Toolchain) -> Path:
    """The library's path in the cache folder for ``key`` on this platform and compiler."""
    text = repr((key, _CASADI, FLAGS, platform_id(), chain.identity))
    return cache_dir() / f"{stem}_{hashlib.sha256(text.encode()).hexdigest()[:24]}.so"


def record_path(library: Path) -> Path:
    """Where the size and SHA-256 of ``library`` are recorded (written with it)."""
    return library.with_suffix(".json")


def check_library(library: Path) -> bool:
    """Whether ``library`` is, byte for byte, the one built: its size and SHA-256 as recorded.

    ``False`` for a missing, truncated or garbled library, or a missing or garbled record:
    such a library is built again, never loaded.
    """
    try:
        record = json.loads(record_path(library).read_text())
        data = library.read_bytes()
    except (OSError, ValueError):
        return False
    return (isinstance(record, dict) and record.get("size") == len(data)
            and record.get("sha256") == hashlib.sha256(data).hexdigest())


@contextmanager
def _build_lock(library: Path) -> Iterator[None]:
    """Hold the library's lock: this process's threads and other processes wait.

    Raises:
        OSError: the cache folder cannot be created or written (no lock file).
    """
    with _LOCK:
        lock = _KEY_LOCKS.setdefault(str(library), threading.Lock())
    with lock:
        library.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(library.with_suffix(".lock"), os.O_RDWR | os.O_CREAT, 0o666)
        try:
            if _FLOCK:
                fcntl.flock(fd, fcntl.LOCK_EX)
            yield
        finally:
            os.close(fd)  # releases the flock


def _build(chain: Toolchain, library: Path, source: Callable[[str], tuple[str, tuple[str, ...]]],
           ) -> float:
    """Compile ``source(tmp)`` (a C file and extra link flags) into ``library`` and its record.

    ``tmp``: a scratch folder beside ``library`` (for generated sources). The library and
    its record are written there and renamed into place.

    Returns:
        The build's time [s].

    Raises:
        _BuildFailed: the compiler did not run or failed (the message has its error text).
        OSError: the cache folder is not writable.
    """
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(dir=library.parent, prefix=".build-") as tmp:
        partial = Path(tmp) / library.name
        try:
            c_file, libs = source(tmp)
        except RuntimeError as exc:  # casadi's code generation
            raise _BuildFailed(f"its C code was not generated ({exc})") from None
        cmd = [*chain.command, *FLAGS, "-o", str(partial), c_file, *libs]
        try:
            run = subprocess.run(cmd, capture_output=True, text=True, timeout=BUILD_TIMEOUT_S)
        except (OSError, subprocess.SubprocessError) as exc:
            raise _BuildFailed(f"`{shlex.join(chain.command)}` did not run ({exc})") from None
        if run.returncode != 0 or not partial.is_file():
            text = "\n".join(t.strip() for t in (run.stderr, run.stdout) if t.strip())
            log.info("%s failed (exit %s):\n%s", shlex.join(cmd), run.returncode, text)
            tail = text[-ERROR_TEXT_CHARS:] if text else "(no output)"
            raise _BuildFailed(f"`{shlex.join(chain.command)}` failed (exit {run.returncode}); "
                               f"it said: {' | '.join(tail.splitlines())}")
        data = partial.read_bytes()
        seconds = time.perf_counter() - start
        record = {"size": len(data), "sha256": hashlib.sha256(data).hexdigest(),
                  "compiler": chain.identity, "platform": platform_id(),
                  "casadi": _CASADI, "flags": list(FLAGS), "build_s": round(seconds, 3)}
        Path(tmp, "record.json").write_text(json.dumps(record, indent=1))
        os.replace(partial, library)
        os.replace(Path(tmp, "record.json"), record_path(library))
    return seconds


def _obtain(name: str, library: Path, chain: Toolchain,
            source: Callable[[str], tuple[str, tuple[str, ...]]],
            load: Callable[[Path], T]) -> T | None:
    """``library`` loaded (checked first), else built under its lock and loaded.

    ``None`` where it cannot be: the fallback, said once.
    """
    if check_library(library):
        try:
            loaded = load(library)
        except (OSError, RuntimeError) as exc:  # a checked library that does not load
            log.warning("the cached %s does not load (%s); building it again", library, exc)
        else:
            _note(Native(name, "loaded", library))
            return loaded
    try:
        with _build_lock(library):
            # built meanwhile by another process or thread
            if (meanwhile := _load_checked(name, library, load)) is not None:
                return meanwhile
            seconds = _build(chain, library, source)
    except _BuildFailed as exc:
        reason = f"it could not be compiled: {exc}; fix or unset CC"
    except OSError as exc:  # no lock file, no scratch folder, no rename: not writable
        reason = (f"the cache folder {library.parent} is not writable ({exc}), and the library "
                  f"is not in it (or its copy there is damaged); set {CACHE_ENV} to a writable "
                  "folder")
    else:
        try:
            loaded = load(library)
        except (OSError, RuntimeError) as exc:
            reason = f"it was compiled but does not load ({exc}); fix or unset CC"
        else:
            _note(Native(name, "built", library, f"{seconds:.2f} s"))
            with _LOCK:
                _BUILD_S[0] += seconds
                total = _BUILD_S[0]
            if total > SLOW_BUILD_S:
                _say(CompilingWarning,
                     f"compiling native code for this machine ({total:.1f} s so far, the "
                     f"latest {name}): a one-off cost of a first call (a few seconds in all); "
                     f"kept in {library.parent}, where later processes load it in under a "
                     "millisecond")
            return loaded
    _fall_back(name, reason)
    return None


def compiled(name: str, key: str, build: Callable[[], ca.Function]) -> ca.Function:
    """The Function ``name`` for ``key``: loaded from the cache, or built and compiled.

    Args:
        name: the Function's name (a C identifier; ``build`` must name it so).
        key: everything the Function depends on, as text (hashed here).
        build: builds the Function (called only when no checked library is cached).

    Returns:
        The compiled Function, or the built one where compiling is off or falls back
        (said once per process; see the module docstring).
    """
    chain = toolchain()
    off = os.environ.get(NO_COMPILE_ENV) == "1"
    if not isinstance(chain, Toolchain):
        return _fallback_function(name, build, "off" if off else chain)
    library = _library(name, key, chain)
    with _LOCK:
        if str(library) in _LOADED:
            return _LOADED[str(library)]
    built: list[ca.Function] = []

    def source(tmp: str) -> tuple[str, tuple[str, ...]]:
        built.append(build())
        generator = ca.CodeGenerator(f"{name}.c")
        generator.add(built[0])
        return generator.generate(tmp + os.sep), ()

    if off:
        f = _load_checked(name, library, lambda p: ca.external(name, str(p)))
        if f is None:
            return _fallback_function(name, build, "off")
    else:
        f = _obtain(name, library, chain, source, lambda p: ca.external(name, str(p)))
    with _LOCK:
        if f is not None:
            _PATHS[name] = library
        else:
            f = built[0] if built else build()
        _LOADED[str(library)] = f
    return f


def _load_checked(name: str, library: Path, load: Callable[[Path], T]) -> T | None:
    """A checked library loaded without building, or ``None``.

    Used where compiling is off, and under the lock (another process may have built it).
    """
    if not check_library(library):
        return None
    try:
        loaded = load(library)
    except (OSError, RuntimeError):
        return None
    _note(Native(name, "loaded", library))
    return loaded


def _fallback_function(name: str, build: Callable[[], ca.Function],
                       reason: str) -> ca.Function:
    """The built Function, evaluated by casadi's virtual machine (the fallback said once)."""
    if reason == "off":
        _note(Native(name, "off", None, f"{NO_COMPILE_ENV}=1"))
    else:
        _fall_back(name, reason)
    return build()


def _fall_back(name: str, reason: str) -> None:
    _note(Native(name, "fallback", None, reason))
    _say(FallbackWarning,
         f"native code falls back ({name} first): {reason}. The pure forms run instead "
         "(casadi's virtual machine, numpy): the same numbers, slower (measured on a SCARA: "
         "solve_many 1.3x, an FA solve 6.7x). `scara-opt doctor` lists what falls back")


def library_path(name: str) -> Path | None:
    """The library :func:`compiled` loaded the Function ``name`` from, or ``None``.

    ``None``: not compiled in this process (casadi's virtual machine evaluates it). The
    library's C entry point is ``name`` with casadi's signature, for C code that calls it
    directly (:mod:`scara_opt.ik.lm_driver`).
    """
    return _PATHS.get(name)


def c_library(source: str | Path,
              extra: tuple[str, ...] | Callable[[], tuple[str, ...] | str] = ()
              ) -> ctypes.CDLL | None:
    """The C file ``source`` compiled into a shared library in the cache folder, loaded.

    Compiled once per machine (keyed by the source's contents, ``extra``, the flags, the
    platform and the compiler), checked and loaded once per process. ``None`` where
    compiling is off (``SCARA_OPT_NO_COMPILE=1``) or falls back (said once per process):
    the caller runs its numpy form. A ``.cpp`` file is compiled as C++ (the compiler
    driver knows it by its suffix) and linked with the C++ library; ``extra``: more
    arguments after the file (include and library folders, libraries), or a function
    that finds them, asked only when compiling is on, and returning why not (a string:
    the fallback's reason) where they cannot be found.
    """
    source = Path(source)
    if os.environ.get(NO_COMPILE_ENV) == "1":
        _note(Native(source.name, "off", None, f"{NO_COMPILE_ENV}=1"))
        return None
    chain = toolchain()
    if not isinstance(chain, Toolchain):
        _fall_back(source.name, chain)
        return None
    found = extra() if callable(extra) else extra
    if isinstance(found, str):
        _fall_back(source.name, found)
        return None
    libs = ("-lm", *(("-lstdc++",) if source.suffix == ".cpp" else ()), *found)
    library = _library(source.stem, f"{source_hash(source)} {libs}", chain)
    with _LOCK:
        if str(library) in _LIBRARIES:
            return _LIBRARIES[str(library)]
    lib = _obtain(source.name, library, chain, lambda _tmp: (str(source), libs),
                  lambda p: ctypes.CDLL(str(p)))
    with _LOCK:
        return _LIBRARIES.setdefault(str(library), lib)


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


def natives() -> list[Native]:
    """What became of each native library this process asked for, in order of first use."""
    with _LOCK:
        return list(_NATIVES.values())


def _note(native: Native) -> None:
    with _LOCK:
        _NATIVES.setdefault(native.name, native)


def _say(category: type[NativeCodeWarning], text: str) -> None:
    """Warn ``text`` once per process for ``category``, at the caller's line outside scara_opt."""
    with _LOCK:
        if category in _SAID:
            return
        _SAID.add(category)
    package = str(Path(__file__).resolve().parent.parent)
    frame: FrameType | None = sys._getframe(0)
    level = 1
    while frame is not None and frame.f_code.co_filename.startswith(package):
        frame, level = frame.f_back, level + 1
    warnings.warn(text, category, stacklevel=level)
