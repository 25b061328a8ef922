"""Issue 38 (and 36's command-line items), one test per symptom, driven as the user drove it."""

from __future__ import annotations

import json
import os
import pickle
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import scara_opt as so
from scara_opt.cli.app import main
from tests.conftest import ROOT

WALL = """name = "wall cell"
length_unit = "mm"
angle_unit = "deg"

[[obstacles]]
name = "wall"
type = "box"
size = [10, 120, 40]
xyz = [173, 100, -85]
rpy = [0, 0, -60]
"""


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def _raises(exc: BaseException):
    def command(args):
        raise exc
    return command


def test_an_unexpected_error_is_one_line_naming_it_with_its_own_code(capsys, monkeypatch):
    """An exception nobody expected (here injected: the 400-zero radius overflow, a seed too
    big for the planner) is one line naming it and a hint, exit 70; --traceback shows where.

    Before (issue 36): nothing printed, exit 130. Mutation caught: app.main's last
    ``except Exception`` removed -> the OverflowError escapes main(), fails.
    """
    monkeypatch.setattr("scara_opt.cli.solvers.cmd_solvers",
                        _raises(OverflowError("int too large to convert to float")))
    code, out, err = _cli(capsys, "solvers")
    assert code == 70 and out == ""
    assert err.count("\n") == 1 and err.startswith("scara-opt: internal error: OverflowError: "
                                                   "int too large to convert to float")
    assert "--traceback" in err and "SCARA_OPT_TRACEBACK=1" in err
    code, _, err = _cli(capsys, "solvers", "--traceback")
    assert code == 70 and "Traceback (most recent call last)" in err and "in command" in err


def test_the_console_script_reports_a_failing_load_as_an_error_not_as_ctrl_c():
    """An exception while the command line loads (injected in the import of its app) is
    one line and exit 70 from the console script, never a silent 130.

    Before (issue 36, console.py): ``code = 130`` first and ``exit_now(code)`` in finally.
    Mutation caught: console.main without its ``except Exception`` and with ``code = 130``
    first -> exit 130, empty stderr, fails.
    """
    code = """
import sys
class Hook:
    def find_spec(self, name, path, target=None):
        if name == "scara_opt.cli.app":
            raise ValueError("injected")
sys.meta_path.insert(0, Hook())
sys.argv = ["scara-opt", "robots"]
from scara_opt.cli.console import main
main()
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 70, out.stderr
    assert out.stderr.startswith("scara-opt: internal error: ValueError: injected")
    assert out.stderr.count("\n") == 1 and out.stdout == ""


def test_version_and_every_exit_code_in_the_help(capsys):
    """``scara-opt --version`` prints the version (exit 0); --help lists every exit code.

    Before: "the following arguments are required: COMMAND"; --help listed 0/1/2/130 only.
    Mutation caught: the --version argument dropped -> exit 2, fails.
    """
    assert _cli(capsys, "--version") == (0, f"scara-opt {so.__version__}\n", "")
    code, out, _ = _cli(capsys, "--help")
    assert code == 0
    text = " ".join(out.split())
    for number in ("0 success", "1 ik", "2 bad input", "70 an unexpected", "130 interrupted",
                   "129 and 143", "141 the reader"):
        assert number in text, number


def test_doctor_lists_ompl_coal_and_meshcat():
    """doctor's versions name ompl, coal and meshcat (the planner, the collision library,
    the viewer). Mutation caught: PACKAGES without them (as before) -> fails."""
    from scara_opt.cli.doctor import versions

    names = [line.split()[0] for line in versions()]
    assert {"ompl", "coal", "meshcat"} <= set(names)


def test_cache_clear_removes_the_cache_libraries_only_and_skips_one_being_built(
        tmp_path, monkeypatch, capsys):
    """``scara-opt cache clear`` removes each library with its record and lock, leaves other
    files of the folder, and skips a library whose lock another build holds.

    Before: no command cleared the cache (142 libraries after one test run). Mutation
    caught: the lock not tried (``_held`` always True) -> the busy library is removed, fails.
    """
    import fcntl

    monkeypatch.setenv("SCARA_OPT_CACHE", str(tmp_path))
    stems = [f"scara_opt_fk_pose_{'a' * 24}", f"fa_sweep_{'b' * 24}"]
    for stem in stems:
        for suffix in (".so", ".json", ".lock"):
            (tmp_path / f"{stem}{suffix}").write_text("x" * 100)
    (tmp_path / "notes.txt").write_text("mine")
    code, out, _ = _cli(capsys, "cache")
    assert code == 0 and "2 libraries" in out
    fd = os.open(tmp_path / f"{stems[1]}.lock", os.O_RDWR)
    fcntl.flock(fd, fcntl.LOCK_EX)  # a build of fa_sweep under way
    try:
        code, out, _ = _cli(capsys, "cache", "clear")
    finally:
        os.close(fd)
    assert code == 0 and "removed 1 libraries" in out and "left 1 in use" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["notes.txt", *(f"{stems[1]}{s}" for s in (".so", ".json", ".lock"))])


def test_reproduce_reports_each_paper_as_it_finishes(tmp_path):
    """reproduce hands each paper's report on as soon as it is done, before summary.md;
    the command line prints a line per paper then.

    Before: all lines arrived at the end (22 s later). Mutation caught: ``done`` called
    after the loop (all at the end) -> summary.md exists at the first call, fails.
    """
    from scara_opt.reports import reproduce

    seen = []
    folder = [tmp_path / "jobs"]

    def done(report):
        seen.append((report.paper, (folder[0] / "summary.md").exists()))

    reproduce(["inverted5", "peng2025"], folder[0], quick=True, jobs=2, progress=done)
    assert sorted(p for p, _ in seen) == ["inverted5", "peng2025"]
    assert not any(written for _, written in seen)
    folder[0] = tmp_path / "serial"
    reproduce(["inverted5"], folder[0], quick=True, progress=done)
    assert seen[-1] == ("inverted5", False)


def test_summary_md_is_0644_with_a_rollup_and_one_animation_note(tmp_path, monkeypatch):
    """summary.md gets the mode of every other output, a roll-up across the papers, and
    says once that the 3-D animations were not written (no view extra).

    Before: 0600 (mkstemp's), the note repeated per paper, no roll-up. Mutations caught:
    ``os.fchmod`` dropped -> 0600; the note back in each report's notes -> twice; each
    fails.
    """
    import scara_opt.view as view
    from scara_opt.reports import reproduce

    def missing(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'umsgpack'")

    monkeypatch.setattr(view, "write_html", missing)
    reproduce(["inverted5", "peng2025"], tmp_path, quick=True)
    summary = tmp_path / "summary.md"
    mask = os.umask(0)
    os.umask(mask)
    assert summary.stat().st_mode & 0o777 == 0o666 & ~mask
    text = summary.read_text()
    assert text.count("umsgpack") == 1 and "(inverted5, peng2025)" in text
    assert "| **all** |" in text and "| inverted5 |" in text


def test_worker_warnings_are_issued_again_once_each(tmp_path):
    """The workers' warnings come back to the parent as warnings (the command line then
    prints its one ``note:`` line), each once however many workers said it.

    Before: ``<frozen runpy>:88: CompilingWarning: ...`` once per worker. Mutation caught:
    the ``seen`` check dropped -> two warnings, fails.
    """
    from scara_opt.reports import _pass_on

    said = [(so.CompilingWarning, "compiling native code ...")]
    (tmp_path / "a.warnings").write_bytes(pickle.dumps(said))
    (tmp_path / "b.warnings").write_bytes(pickle.dumps(said))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _pass_on(tmp_path)
    assert [(w.category, str(w.message)) for w in caught] == said


def _workers(out: Path) -> list[int]:
    """Process ids of reproduce workers writing into ``out``."""
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                cmd = (entry / "cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if b"scara_opt.reports.worker" in cmd and any(str(out).encode() in c for c in cmd):
                pids.append(int(entry.name))
    return pids


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGKILL])
def test_a_stopped_reproduce_leaves_no_worker_and_no_partial_folder(tmp_path, sig):
    """SIGTERM or SIGHUP to reproduce: exit 128 + the signal, one line, its workers ended
    and its staging folder gone. SIGKILL (nothing can be cleaned): the workers end by
    themselves, and the next run into the folder removes the staging folder left.

    Before (issue 36): the workers kept running and writing into ``.scara-opt-partial-*``,
    which survived later runs. Mutations caught: ``_on_termination`` not entered in main()
    -> the workers survive SIGTERM, fails; ``_end_with_parent`` not called in the worker -> they
    survive SIGKILL, fails; ``remove_stale_staging`` not called -> the folder stays, fails.
    """
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "scara_opt.cli", "reproduce", "all",
                             "--quick", "--jobs", "2", "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while len(_workers(out)) < 2 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    workers = _workers(out)
    assert len(workers) == 2, "the workers did not start"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    for _ in range(50):  # a worker's parent watch looks every 0.2 s
        if not _workers(out):
            break
        time.sleep(0.1)
    assert _workers(out) == []
    staging = list(out.glob(".scara-opt-partial-*"))
    if sig == signal.SIGKILL:
        assert proc.returncode == -signal.SIGKILL and staging
        from scara_opt.cli.outputs import OutputDir

        with OutputDir(str(out), ["x"]):
            pass
        assert list(out.glob(".scara-opt-partial-*")) == []
    else:
        assert proc.returncode == 128 + sig, err
        assert err.strip().endswith(f"scara-opt: ended by {signal.Signals(sig).name}")
        assert staging == [] and not (out / "summary.md").exists()


def test_a_time_limit_too_short_to_keep_is_refused(capsys):
    """``--time-limit 0.0001`` is refused naming the shortest (before: accepted, and the
    planning took 30.5 ms). Mutation caught: ``time_limit`` type back to ``positive``."""
    code, _, err = _cli(capsys, "plan", "zavar2024", "--start", "0", "0", "0", "0", "--goal",
                        "0.1", "0", "0", "0", "--cell", str(ROOT / "examples/scara_cell.toml"),
                        "--time-limit", "0.0001")
    assert code == 2 and "pass at least 0.01 s" in err


def test_cycle_in_an_enclosed_cell_says_why_quintic_is_missing_and_ruckig_slow(
        tmp_path, capsys):
    """In a cell whose wall blocks the straight PTPs: the quintic line's absence and
    ruckig's 2x are said (text, --json, repr), with the cell and the proven clearance.

    Before: quintic dropped without a word, ruckig 9.82 s against toppra 3.80 s with no
    word why, and neither the repr nor --json named the cell. Mutation caught:
    ``_cell_notes`` returning () -> no note, fails.
    """
    cell = tmp_path / "wall.toml"
    cell.write_text(WALL)
    res = so.cycle_time(so.load_robot("zavar2024"), across=0.2, cell=so.load_cell(cell))
    assert "quintic" not in res.durations and res.cell == "wall cell"
    assert res.clearance is not None and res.clearance > 0
    assert any(n.startswith("quintic not timed") for n in res.notes)
    slower = res.durations["ruckig"] / res.durations["toppra"]  # 2.00x when written
    assert any(n.startswith(f"ruckig takes {slower:.2f}x toppra's time") for n in res.notes)
    assert "planned in 'wall cell', proven clear of it" in repr(res)
    code, out, _ = _cli(capsys, "cycle", "zavar2024", "--across", "200", "--cell", str(cell))
    assert code == 0 and "note: quintic not timed" in out and "note: ruckig takes" in out
    code, out, _ = _cli(capsys, "cycle", "zavar2024", "--across", "200", "--cell", str(cell),
                        "--json")
    data = json.loads(out)
    assert data["cell"] == "wall cell" and data["least_clearance_m"] > 0 and len(data["notes"]) == 2


def test_a_urdf_without_collision_geometry_plans_from_the_cli(tmp_path, capsys):
    """plan on a URDF: --amax (a URDF has none) and --radius (no <collision>) are options.

    Before: "has no amax ... pass amax=", then "unrecognized arguments: --amax"; no
    --radius on plan or cycle. Mutation caught: ``radius=`` not passed to the checker
    (``make_checker`` ignoring ``--radius``) -> "no capsule radius", exit 2, fails.
    """
    cell = tmp_path / "shelf.toml"
    cell.write_text('name = "shelf"\nlength_unit = "mm"\n[[obstacles]]\nname = "shelf"\n'
                    'type = "box"\nsize = [300, 600, 20]\nxyz = [500, 0, 700]\n')
    args = ["plan", str(ROOT / "examples/arm6.urdf"), "--start", "0", "0", "0", "0", "0", "0",
            "--goal", "0.3", "0", "0", "0", "0", "0", "--cell", str(cell), "--amax", "5"]
    code, _, err = _cli(capsys, *args)
    assert code == 2 and "radius" in err
    code, out, err = _cli(capsys, *args, "--radius", "40", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["status"] == "solved" and data["cell"] == "shelf" and data["least_clearance_m"] > 0


def test_run_a_pick_and_place_program_file(tmp_path, capsys):
    """``scara-opt run`` plans the example program file: each move's duration and least
    clearance (>= the 2 mm margin), the files plan writes; load_program gives the same.

    Mutation caught: the file's margin not converted from mm (``margin * reader.L`` ->
    ``margin``: 2 m) -> the goal is refused, fails.
    """
    program = ROOT / "examples/pick_and_place.toml"
    code, out, err = _cli(capsys, "run", str(program), "--json", "--out", str(tmp_path),
                          "--csv", "--trajectory-json", "--ros")
    assert code == 0, err
    data = json.loads(out)
    moves = data["moves"]
    assert [m["type"] for m in moves] == ["PTP", "LIN", "LIN", "PTP", "LIN", "LIN"]
    assert sum(m["duration_s"] for m in moves) == pytest.approx(data["duration_s"])
    assert min(m["least_clearance_m"] for m in moves) >= 0.002 and data["cell"] == "scara cell"
    for name in ("program.csv", "program.json", "program_ros.yaml"):
        assert (tmp_path / name).is_file()
    loaded = so.load_program(program)
    traj = loaded.plan()
    assert traj.duration == pytest.approx(data["duration_s"], rel=1e-9)
    np.testing.assert_allclose(loaded.start, np.radians([-20, 50, 0, 0]) + [0, 0, 0.01, 0])
    assert (loaded.limits.speed, loaded.limits.acceleration) == pytest.approx((0.5, 3.0))
    assert loaded.limits.yaw_rate == pytest.approx(np.pi)


@pytest.mark.parametrize("edit, match", [
    (('type = "LIN"', 'tpye = "LIN"'), "'tpye': did you mean 'type'?"),
    (('type = "LIN"', 'type = "LNI"'), "did you mean 'LIN'?"),
    (("speed = 100", "speed = -100"), "speed = -100 mm/s: it must be > 0"),
    (('robot = "zavar2024"\n', ""), "names no robot"),
    (("xyz = [320, -50, -90]\nyaw = 0", "joints = [1, 2]"), "joints must be a list of 4 finite"),
    (('length_unit = "mm"', 'length_unit = "furlong"'), "length_unit must be one of"),
])
def test_a_bad_program_file_says_where_and_what(tmp_path, edit, match):
    """Program-file mistakes are ProgramError naming the file, the move and the key, in
    the file's units, with a close match. Mutation caught: ``check_keys`` on the moves
    dropped -> the misspelt key is ignored, fails."""
    text = (ROOT / "examples/pick_and_place.toml").read_text().replace(*edit, 1)
    path = tmp_path / "p.toml"
    path.write_text(text.replace('cell = "scara_cell.toml"',
                                 f'cell = "{ROOT / "examples/scara_cell.toml"}"'))
    with pytest.raises(so.ProgramError, match="p.toml") as info:
        so.load_program(path)
    assert match in str(info.value)


def test_ik_mm_gives_the_error_in_mm(capsys):
    """ik --mm reports the residual in mm (and the yaw error in degrees).

    Before: ``d3=5 mm`` beside ``error 0 m``. Mutation caught: _error_text ignoring the unit.
    """
    code, out, _ = _cli(capsys, "ik", "zavar2024", "--xyz", "-230", "200", "-200", "--mm")
    assert code == 1 and "position error 102 mm" in out
    code, out, _ = _cli(capsys, "ik", "zavar2024", "--xyz", "300", "100", "-70", "--mm",
                        "--yaw", "30")
    assert code == 0 and " mm, yaw error " in out and " deg; auto" in out


def test_cell_file_mistakes_are_said_in_its_own_units(tmp_path):
    """A misspelt ``type`` key gets its did-you-mean; a size <= 0 is quoted in the file's
    unit with the file's name; a mesh's ``scale = 0.001`` is one number for all axes; one
    obstacle is "1 obstacle".

    Before: no hint for tpye, "-0.03 [m]" without the file, scale refused, "1 obstacles".
    Mutation caught: the size check in the file's units dropped -> "[m]", fails.
    """
    head = 'name = "c"\nlength_unit = "mm"\n[[obstacles]]\nname = "a"\n'
    path = tmp_path / "c.toml"
    path.write_text(head + 'tpye = "box"\nsize = [1, 2, 3]\n')
    with pytest.raises(so.CellError, match="did you mean 'type'"):
        so.load_cell(path)
    path.write_text(head + 'type = "cylinder"\nradius = -30\nlength = 400\n')
    with pytest.raises(so.CellError, match=r"c\.toml.*radius -30 mm: a size must be > 0"):
        so.load_cell(path)
    stl = tmp_path / "tet.stl"
    stl.write_text("solid t\n" + "".join(
        f"facet normal 0 0 0\nouter loop\n{''.join(f'vertex {v}' + chr(10) for v in face)}"
        "endloop\nendfacet\n" for face in [("0 0 0", "1000 0 0", "0 1000 0"),
                                           ("0 0 0", "0 1000 0", "0 0 1000"),
                                           ("0 0 0", "0 0 1000", "1000 0 0"),
                                           ("1000 0 0", "0 1000 0", "0 0 1000")])
        + "endsolid t\n")
    path.write_text(head + 'type = "mesh"\nfile = "tet.stl"\nscale = 0.001\n')
    cell = so.load_cell(path)
    assert cell["a"].scale == (1e-6, 1e-6, 1e-6) and repr(cell).startswith(
        "Cell('c': 1 obstacle [a])")
