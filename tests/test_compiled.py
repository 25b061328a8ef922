"""The native-code cache cannot take a process down: checked loads, rebuilds, locks, fallbacks.

Each damage is done to a real cache built by a real process; then a NEW process (as a user
would start one) must solve, with the numbers of the undamaged cache.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
import warnings
from pathlib import Path

import pytest

from scara_opt.errors import CompilingWarning, FallbackWarning
from scara_opt.model import compiled
from tests.conftest import c_compiler

#: a new process's run over every kind of cached library: the casadi Functions (batch FK,
#: the fast IK's three phases, the footprint test) and the C kernels (lm_driver, fa_sweep,
#: ga_breed, aco_ants); prints a hash of all the numbers, then each library's fate
SOLVE = r"""
import hashlib
import numpy as np
import scara_opt as so
from scara_opt.model import compiled
r = so.load_robot("zavar2024")
rng = np.random.default_rng(3)
Q = r.lower + rng.random((6, r.nq)) * (r.upper - r.lower)
P = r.fk_batch(Q)[:, :3, 3]
h = hashlib.sha256()
for p in P:
    res = so.solve_ik(r, p)
    assert res.success, res
    h.update(res.q.tobytes())
h.update(so.solve_many(r, P).q.tobytes())
for m in ("fa", "ga", "aco"):  # an unreachable target: every generation runs its kernel
    h.update(so.solve_ik(r, (0.5, 0.5, -0.07), method=m, population=12, iterations=6,
                         seed=1).q.tobytes())
h.update(so.workspace(so.load_robot("peng2025"), n=2000, seed=0).points.tobytes())
print(h.hexdigest())
print(" ".join(f"{n.name}={n.state}" for n in compiled.natives()))
"""

#: the libraries SOLVE uses, by the start of their names
KINDS = ("scara_opt_fk_", "scara_opt_lm_", "scara_opt_slide_", "scara_opt_newton_",
         "scara_opt_footprint_", "lm_driver_", "fa_sweep_", "ga_breed_", "aco_ants_")


def _env(cache: Path, **extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("CC", compiled.NO_COMPILE_ENV)}
    return {**env, compiled.CACHE_ENV: str(cache), "PYTHONWARNINGS": "default", **extra}


def _solve(cache: Path, prefix: tuple[str, ...] = (), **extra: str,
           ) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*prefix, sys.executable, "-c", SOLVE], env=_env(cache, **extra),
                          capture_output=True, text=True, timeout=600)


def _states(run: subprocess.CompletedProcess[str]) -> dict[str, str]:
    return dict(item.split("=") for item in run.stdout.split("\n")[1].split())


def _public_dir() -> Path:
    """A folder another user can enter (pytest's tmp_path sits in a private one)."""
    folder = Path(tempfile.mkdtemp(prefix="scara_opt_test_"))
    folder.chmod(0o755)
    return folder


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """A cache built by one process, and the hash of that process's numbers."""
    if c_compiler() is None:
        pytest.skip("no C compiler: nothing is cached")
    cache = tmp_path_factory.mktemp("pristine") / "cache"
    run = _solve(cache)
    assert run.returncode == 0, run.stderr
    assert set(_states(run).values()) == {"built"}
    for kind in KINDS:
        assert list(cache.glob(f"{kind}*.so")), kind
    return cache, run.stdout.split("\n")[0]


def _copy(pristine: tuple[Path, str], folder: Path) -> Path:
    cache = folder / "cache"
    shutil.copytree(pristine[0], cache)
    return cache


@pytest.mark.parametrize("damage", ["truncate", "garble"])
def test_a_damaged_library_of_each_kind_is_rebuilt_by_a_new_process(pristine, tmp_path, damage):
    """Every cached library truncated to half (or overwritten with random bytes of its
    size): a new process exits 0 with the numbers of the undamaged cache, having rebuilt
    each library, which then passes its size and SHA-256 check.

    Mutation caught: ``check_library`` skipped before the load (``if True:``) -> the
    truncated library is mapped and the process dies by SIGBUS (-7), or the garbled C
    kernel never loads and is never rebuilt; fails.
    """
    cache = _copy(pristine, tmp_path)
    libraries = sorted(cache.glob("*.so"))
    rng = __import__("random").Random(7)
    for lib in libraries:
        size = lib.stat().st_size
        if damage == "truncate":
            os.truncate(lib, size // 2)
        else:
            lib.write_bytes(bytes(rng.getrandbits(8) for _ in range(size)))
    run = _solve(cache)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[0] == pristine[1]
    assert set(_states(run).values()) == {"built"}
    assert all(compiled.check_library(lib) for lib in libraries)
    assert "FallbackWarning" not in run.stderr


def test_a_read_only_cache_with_a_damaged_library_solves_and_says_why(pristine):
    """A cache the process cannot write, with one casadi library and one C kernel garbled:
    the damaged two fall back (one FallbackWarning naming the folder and SCARA_OPT_CACHE),
    the others load, the numbers are the undamaged cache's, nothing in it changes.

    Run as another user when this one is root (root writes anywhere). Mutation caught: the
    OSError of the lock file not caught -> PermissionError out of solve_ik, exit 1; fails.
    """
    folder = _public_dir()
    try:
        cache = _copy(pristine, folder)
        damaged = [next(cache.glob("scara_opt_lm_*.so")), next(cache.glob("fa_sweep_*.so"))]
        for lib in damaged:
            lib.write_bytes(b"\x7fELF garbage" * 100)
        before = {p.name: p.read_bytes() for p in cache.iterdir()}
        prefix: tuple[str, ...] = ()
        if os.geteuid() == 0:
            setpriv = shutil.which("setpriv")
            if setpriv is None:
                pytest.skip("root, and no setpriv to run as another user")
            prefix = (setpriv, "--reuid=65534", "--regid=65534", "--clear-groups")
            probe = subprocess.run([*prefix, sys.executable, "-c", "import scara_opt"],
                                   capture_output=True, timeout=60)
            if probe.returncode != 0:
                pytest.skip("the unprivileged user cannot read this Python installation")
        for path in (cache, *cache.iterdir()):
            path.chmod(path.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
        mpl = Path(tempfile.mkdtemp(dir=folder))
        mpl.chmod(0o777)
        run = _solve(cache, prefix, MPLCONFIGDIR=str(mpl), HOME=str(mpl))
        assert run.returncode == 0, run.stderr
        assert run.stdout.split("\n")[0] == pristine[1]
        states = _states(run)
        assert states["fa_sweep.c"] == "fallback"
        assert sorted(n for n, s in states.items() if s == "fallback") == sorted(
            ["fa_sweep.c", next(n for n in states if n.startswith("scara_opt_lm_"))])
        assert run.stderr.count("FallbackWarning") == 1
        assert "not writable" in run.stderr and compiled.CACHE_ENV in run.stderr
        assert {p.name: p.read_bytes() for p in cache.iterdir() if p.is_file()} == before
    finally:
        for path in folder.rglob("*"):
            path.chmod(0o755)
        shutil.rmtree(folder)


def test_without_a_compiler_the_same_numbers_and_one_warning(pristine, tmp_path):
    """No $CC and no cc/gcc on the PATH, an empty cache: the same numbers as compiled code,
    every library falls back, one FallbackWarning that names the cause and the remedy.

    Mutation caught: the fallback not said (``_say`` returning early) -> no warning; fails.
    """
    bin_dir = Path(sys.executable).parent
    run = _solve(tmp_path / "cache", PATH=str(bin_dir))
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[0] == pristine[1]
    assert set(_states(run).values()) == {"fallback"}
    assert run.stderr.count("FallbackWarning") == 1
    assert "no C compiler found" in run.stderr and "set CC" in run.stderr


def test_a_failing_compiler_says_what_it_said(pristine, tmp_path):
    """A compiler that fails: the same numbers, one FallbackWarning carrying its error text.

    Mutation caught: the compiler's stderr dropped from the message (as before) -> fails.
    """
    cc = tmp_path / "badcc"
    cc.write_text("#!/bin/sh\n[ \"$1\" = --version ] && { echo badcc 1.0; exit 0; }\n"
                  "echo 'badcc: fatal error: simulated failure' >&2\nexit 1\n")
    cc.chmod(0o755)
    run = _solve(tmp_path / "cache", CC=str(cc))
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[0] == pristine[1]
    assert set(_states(run).values()) == {"fallback"}
    assert run.stderr.count("FallbackWarning") == 1
    assert "badcc: fatal error: simulated failure" in run.stderr


def test_three_processes_on_an_empty_cache_build_each_library_once(pristine, tmp_path):
    """Three processes started together on an empty cache, CC a command of two words (a
    wrapper as ccache is, split like a shell): each library is compiled once in all, and
    every process gets the numbers of the pristine cache.

    Mutations caught: the flock dropped -> libraries compiled two or three times; CC not
    split (``(cc,)``) -> "not an executable", every process falls back; both fail.
    """
    log = tmp_path / "builds.log"
    wrapper = tmp_path / "wrap"
    wrapper.write_text(f"#!/bin/sh\ncase \" $* \" in *' -o '*) echo \"$*\" >> {log};; esac\n"
                       "exec \"$@\"\n")
    wrapper.chmod(0o755)
    cache = tmp_path / "cache"
    env = _env(cache, CC=f"{wrapper} {c_compiler().command[0]}")
    procs = [subprocess.Popen([sys.executable, "-c", SOLVE], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(3)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0, 0], [o[1] for o in outs]
    assert {o[0].split("\n")[0] for o in outs} == {pristine[1]}
    built = log.read_text().splitlines()
    assert len(built) == len(list(cache.glob("*.so"))) == len(_states(
        subprocess.CompletedProcess([], 0, outs[0][0], "")))


def test_threads_of_one_process_build_a_library_once(tmp_path, monkeypatch):
    """Eight threads asking at once for the same new C library: one compile, one library.

    Mutation caught: ``_build_lock`` a no-op -> several compiles; fails.
    """
    if c_compiler() is None:
        pytest.skip("no C compiler")
    log = tmp_path / "builds.log"
    wrapper = tmp_path / "wrap"
    wrapper.write_text(f"#!/bin/sh\ncase \" $* \" in *' -o '*) echo x >> {log};; esac\n"
                       "sleep 0.3\nexec \"$@\"\n")
    wrapper.chmod(0o755)
    monkeypatch.setenv("CC", f"{wrapper} {c_compiler().command[0]}")
    monkeypatch.setenv(compiled.CACHE_ENV, str(tmp_path / "cache"))
    src = tmp_path / "thrice.c"
    src.write_text("double thrice(double x) { return 3.0 * x; }\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out: list[ctypes.CDLL | None] = []
        threads = [threading.Thread(target=lambda: out.append(compiled.c_library(src)))
                   for _ in range(8)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    assert len(log.read_text().splitlines()) == 1
    assert len({id(lib) for lib in out}) == 1 and out[0] is not None


def test_the_key_holds_platform_machine_and_compiler(monkeypatch):
    """The library's name changes with the machine architecture, the OS, the C library, the
    compiler's command and its version; not otherwise.

    Mutation caught: ``platform_id()`` or the compiler identity left out of the key -> two
    of the paths below are equal; fails.
    """
    gcc = compiled.Toolchain(("gcc",), "gcc 12.2.0", "PATH")
    base = compiled._library("f", "key", gcc)
    assert compiled._library("f", "key", gcc) == base
    others = {compiled._library("f", "key", compiled.Toolchain(("gcc",), "gcc 13.1.0", "PATH")),
              compiled._library("f", "key", compiled.Toolchain(("clang",), "gcc 12.2.0", "$CC"))}
    monkeypatch.setattr(compiled.platform, "machine", lambda: "aarch64")
    others.add(compiled._library("f", "key", gcc))
    monkeypatch.undo()
    monkeypatch.setattr(compiled.sys, "platform", "darwin")
    others.add(compiled._library("f", "key", gcc))
    monkeypatch.undo()
    monkeypatch.setattr(compiled.os, "confstr", lambda name: "glibc 2.17")
    others.add(compiled._library("f", "key", gcc))
    assert len(others) == 5 and base not in others


def test_cc_is_split_like_a_shell(monkeypatch):
    """``CC`` with quoted words is split as a shell does; an unknown first word is named."""
    monkeypatch.setenv("CC", "'my cc' -m64")
    assert compiled.toolchain() == ("CC=\"'my cc' -m64\" names 'my cc', which is not an "
                                    "executable on the PATH; install it, or fix or unset CC")
    monkeypatch.setenv("CC", "")
    cc = c_compiler()
    if cc is None:
        pytest.skip("no C compiler")
    monkeypatch.setenv("CC", f"{cc.command[0]} -m64")
    assert compiled.toolchain().command == (cc.command[0], "-m64")


def test_a_slow_build_is_said_once_as_a_compiling_warning(tmp_path, monkeypatch):
    """Builds longer than SLOW_BUILD_S in all: one CompilingWarning naming the cache folder,
    at the caller's line; a second build says nothing more.

    Mutation caught: the notice said on every build -> two warnings; fails.
    """
    if c_compiler() is None:
        pytest.skip("no C compiler")
    monkeypatch.setattr(compiled, "SLOW_BUILD_S", 0.0)
    monkeypatch.setattr(compiled, "_SAID", set())
    monkeypatch.setattr(compiled, "_BUILD_S", [0.0])
    monkeypatch.setenv(compiled.CACHE_ENV, str(tmp_path / "cache"))
    sources = []
    for k in range(2):
        sources.append(tmp_path / f"once{k}.c")
        sources[-1].write_text(f"double once{k}(double x) {{ return x + {k}; }}\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for src in sources:
            assert compiled.c_library(src) is not None
    said = [w for w in caught if issubclass(w.category, CompilingWarning)]
    assert len(said) == 1
    assert str(tmp_path / "cache") in str(said[0].message)
    assert said[0].filename == __file__


def test_fallback_is_said_once_and_only_for_a_real_fallback(tmp_path, monkeypatch):
    """SCARA_OPT_NO_COMPILE=1 (asked for) says nothing; a missing compiler says so once for
    any number of libraries.

    Mutation caught: the once-per-process set ignored -> two warnings; fails.
    """
    monkeypatch.setattr(compiled, "_SAID", set())
    monkeypatch.setenv(compiled.CACHE_ENV, str(tmp_path / "cache"))
    srcs = [tmp_path / "a.c", tmp_path / "b.c"]
    for src in srcs:
        src.write_text("int f(void) { return 1; }\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        monkeypatch.setenv(compiled.NO_COMPILE_ENV, "1")
        assert compiled.c_library(srcs[0]) is None
        assert not caught
        monkeypatch.delenv(compiled.NO_COMPILE_ENV)
        monkeypatch.setenv("PATH", str(tmp_path))
        monkeypatch.delenv("CC", raising=False)
        assert [compiled.c_library(s) for s in srcs] == [None, None]
    assert [w.category for w in caught] == [FallbackWarning]


def test_the_cli_says_a_fallback_in_one_note_line(tmp_path):
    """``scara-opt ik`` without a compiler: the answer, and on stderr exactly one line
    ``scara-opt: note: native code falls back: no C compiler found ...``.

    Mutation caught: the CLI's warning display not installed -> Python's two-line
    ``file:line: FallbackWarning`` format; fails.
    """
    env = _env(tmp_path / "cache", PATH=str(Path(sys.executable).parent))
    run = subprocess.run([sys.executable, "-m", "scara_opt.cli", "ik", "zavar2024", "--xyz",
                          "0.3", "0.1", "-0.07"], env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("solved:")
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("scara-opt: note: native code falls back ("
                                                   ), run.stderr
    assert "first): no C compiler found" in lines[0]


def test_doctor_lists_versions_compiler_cache_and_every_library(capsys):
    """``scara-opt doctor`` prints the versions, the compiler, the cache folder and one line
    per native library of every kind, compiled or falling back (exit 0).

    Mutation caught: a kernel left out of ``doctor.exercise`` -> its line missing; fails
    (``toppra_passes._kernel`` left out: checked alone, ``-n 0``).
    """
    from scara_opt.cli import main

    assert main(["doctor"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("versions: python ")
    for word in ("casadi ", "pin ", "numpy ", "platform: ", "C compiler: ", "cache folder: "):
        assert word in out
    listed = [line.split()[0] for line in out.split("native code, after")[1].splitlines()[1:]
              if line.startswith("  ") and not line.startswith("      why")]
    for kind in (*KINDS, "toppra_passes"):  # toppra's passes: not in SOLVE (round-off)
        assert any(name.startswith(kind.rstrip("_")) for name in listed), kind


def test_the_fast_ik_key_hashes_every_source_its_functions_are_built_from():
    """Building each phase of the fast IK (every task kind, a SCARA and a 7R arm, fresh
    robots so nothing is cached) runs code from the modules whose sources the compiled
    cache's key hashes (``lm_functions.SOURCES``) and, of the robot model, only accessors
    of data the kinematic key holds: a change to any source that shapes the generated code
    compiles anew instead of loading a stale library.

    Mutations caught: ``tool_angle`` (the yaw basis) left out of ``SOURCES`` (the key
    before the split of lm.py lacked it); the builders moved to a module the key does not
    hash (a split of ``lm_steps.py`` without updating ``SOURCES``). The files are told
    apart by the package's folder, not by "scara_opt" in their path: a clone named
    scara_opt with its .venv inside made numpy's and casadi's files count (4 failures).
    """
    import scara_opt as so
    from scara_opt.ik import lm_functions
    from scara_opt.ik.lm_steps import BUILDERS
    from tests.conftest import DATA

    robots = [so.load_robot("fang"), so.Robot.from_urdf(DATA / "panda_dh.urdf", tip="tool")]
    called: dict[str, set[str]] = {}
    package = Path(so.__file__).resolve().parent  # the package's own files: not numpy's in a
    # .venv inside a clone named scara_opt, whose path holds the package's name too

    def profile(frame, event, arg):
        code = frame.f_code
        if event == "call" and Path(code.co_filename).resolve().is_relative_to(package):
            called.setdefault(str(Path(code.co_filename).resolve()), set()).add(code.co_name)

    sys.setprofile(profile)
    try:
        for robot in robots:
            for kind in ("position", "yaw", "rotation"):
                if kind == "yaw" and robot.yaw_axis is None:
                    continue
                for phase, build in BUILDERS.items():
                    lm_functions._merged(build(robot, kind), f"check_{phase}")
    finally:
        sys.setprofile(None)
    hashed = {str(Path(p).resolve()) for p in lm_functions.SOURCES}
    robot_py = str(Path(sys.modules[so.Robot.__module__].__file__).resolve())
    readers = {"nq", "lower", "upper", "_limits", "data", "symbolic_fk"}  # model data only
    assert set(called) - hashed - {robot_py} == set(), called
    assert called.get(robot_py, set()) <= readers, called[robot_py]
