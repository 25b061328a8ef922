"""The scara-opt command line, driven as a user would (subprocess)."""

from __future__ import annotations

import json

import pytest

from tests.conftest import BUNDLED
from tests.conftest import run_cli as run


def test_robots_lists_every_bundled_robot_with_limits_and_source():
    """`scara-opt robots` exits 0 and names each robot, its joints' limits and its paper.

    Mutation caught: cmd_robots not printing the [citation] line.
    """
    out = run("robots")
    assert out.returncode == 0, out.stderr
    for name in BUNDLED:
        assert name in out.stdout
    assert "[-120.0, 120.0] deg" in out.stdout and "seeds/" not in out.stdout
    assert ("paper:  Mahdi Zavar, Niki Manouchehri, Alireza Safa (2024). “Forward and Inverse "
            "Kinematics of 4-DoF SCARA: Using Optimization Algorithms”. Not stated in the "
            "paper's text: venue, doi.") in out.stdout


@pytest.mark.parametrize("command", ["robots", "solvers", "doctor", "cache", "fk", "ik",
                                     "compare", "path", "cycle", "plan", "run", "workspace",
                                     "reproduce"])
def test_help_everywhere(command):
    """Every subcommand answers --help with exit code 0."""
    out = run(command, "--help")
    assert out.returncode == 0 and "usage: scara-opt" in out.stdout


def test_fk_text_and_json():
    """fk prints the tip in the asked units; --json has a stable schema."""
    out = run("fk", "zavar2024", "30", "45", "20", "10", "--deg", "--mm")
    assert out.returncode == 0 and "tip at (224.969, 293.185, -70) mm, yaw 85 deg" in out.stdout
    data = json.loads(run("fk", "zavar2024", "0", "0", "0.01", "0", "--json").stdout)
    assert set(data) >= {"robot", "q", "q_units", "position", "position_unit", "rotation",
                         "within_limits", "yaw_deg"}
    assert data["position"] == pytest.approx([0.4, 0.0, -0.06])


IK_KEYS = {"robot", "method", "status", "success", "q", "q_units", "error", "position_error",
           "position_error_unit", "yaw_error_deg", "iterations", "evaluations", "time_s",
           "message", "error_unit", "route"}


def test_ik_json_schema_and_unreachable_verdict():
    """ik --json reports the status honestly: zavar2024's paper target is unreachable, and
    the exit code says it (1: not solved; 0: solved), so scripts need not parse text.

    Mutation caught: cmd_ik returning 0 whatever the status (the audit's exit-0 unreachable).
    """
    out = run("ik", "zavar2024", "--xyz", "-0.23", "0.20", "-0.20", "--json")
    data = json.loads(out.stdout)
    assert set(data) == IK_KEYS
    assert data["status"] == "unreachable" and data["error"] == pytest.approx(0.102, abs=1e-3)
    assert out.returncode == 1 and out.stderr == ""
    text = run("ik", "zavar2024", "--xyz", "1", "2", "3")
    assert text.returncode == 1 and text.stdout.startswith("unreachable:")
    out = run("ik", "zavar2024", "--xyz", "-230", "200", "-70", "--mm", "--deg",
              "--method", "analytic", "--json")
    ok = json.loads(out.stdout)
    assert ok["success"] and ok["q_units"] == ["deg", "deg", "mm", "deg"]
    assert out.returncode == 0


def test_ik_all_lists_the_branches():
    """ik --all --json lists every closed-form branch (peng2025 with yaw: elbow x wrist turns)."""
    rows = json.loads(run("ik", "peng2025", "--xyz", "400", "-120", "180", "--yaw", "0", "--mm",
                          "--all", "--json").stdout)
    assert len(rows) >= 2 and all(r["success"] for r in rows)
    assert all(set(r) == IK_KEYS for r in rows)
    none = run("ik", "peng2025", "--xyz", "2000", "0", "180", "--yaw", "0", "--mm", "--all")
    assert none.returncode == 1 and "no closed-form solution" in none.stdout


@pytest.mark.parametrize("args, message", [
    (("ik", "zavar2024", "--xyz", "0", "0", "nan"), "NaN or inf"),
    (("ik", "zavar2024", "--xyz", "0.2", "0.1", "-0.06", "--method", "bogus"),
     "unknown IK method 'bogus'; registered:"),
    (("fk", "zavar2024", "1", "2"), "must have shape (4,)"),
    (("fk", "no_such_robot", "1"), "no bundled robot named 'no_such_robot'"),
    (("ik", "zavar2024", "--xyz", "0.2", "0.1", "-0.06", "--yaw", "nan"),
     "--yaw: nan deg: an angle must be finite"),
    (("workspace", "zavar2024", "-n", "0", "--out", "OUT"), "n"),
    # zavar2024 Table 3's circle (r = 16 cm, z = -6 cm) lies inside the hole around the base
    (("path", "zavar2024", "--circle", "0", "0", "160", "-60", "--mm", "-n", "10", "--out",
      "OUT"), "10 of 10 path points were not reached"),
    (("path", "zavar2024", "--line", "0.25", "0", "-0.07", "0.25", "0", "-0.07", "--yaw",
      "tangent", "--out", "OUT"), "start and end are the same point"),
    (("path", "zavar2024", "--line", "0.25", "0", "-0.07", "0.25", "0", "-0.05", "--yaw",
      "tangent", "--out", "OUT"), "no tangent direction"),
    # checked for every (method, population) before the first solve, not halfway through
    (("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "pso,sfla",
      "--populations", "10,2", "--iterations", "5", "--seeds", "1", "--out",
      "OUT"), "sfla"),
    (("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "pso",
      "--out", "/proc/scara_opt_forbidden"), "cannot write into --out"),
    (("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "pso",
      "--dask", "notanaddress", "--out", "OUT"), "cannot reach a dask scheduler"),
    # an empty method ran auto; an empty entry of a list was skipped
    (("ik", "zavar2024", "--xyz", "0.2", "0.1", "-0.06", "--method", ""),
     "unknown IK method ''; registered:"),
    (("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "pso",
      "--populations", "10,,20", "--out", "OUT"), "got '10,,20', which has an empty entry"),
    (("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "pso,",
      "--out", "OUT"), "got 'pso,', which has an empty entry"),
])
def test_bad_input_is_one_line_and_exit_2(args, message, tmp_path):
    """Bad input: exit code 2, a one-line error on stderr, no traceback.

    Mutations caught: ``args.method or "auto"`` again -> ``--method ""`` solves, exit 0;
    empty entries skipped in ``_entries`` -> ``10,,20`` accepted; both fail.
    """
    out = run(*(str(tmp_path) if a == "OUT" else a for a in args))
    assert out.returncode == 2, out
    assert message in out.stderr and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_bad_usage_exits_2():
    """An unknown subcommand or paper is a usage error: exit code 2, message on stderr."""
    out = run("no-such-command")
    assert out.returncode == 2 and "invalid choice" in out.stderr
    out = run("reproduce", "nobody2020", "--out", "/tmp/x")
    assert out.returncode == 2 and "invalid choice" in out.stderr
    out = run("path", "zavar2024", "--circle", "0.25", "0", "0.05", "-0.07", "--line", "0", "0",
              "0", "1", "1", "1", "--out", "/tmp/x")
    assert out.returncode == 2 and "not allowed with" in out.stderr
    out = run("path", "zavar2024", "--circle", "0.25", "0", "0.05", "-0.07", "--yaw", "north",
              "--out", "/tmp/x")
    assert out.returncode == 2 and "expected degrees or 'tangent'" in out.stderr
    for command in (("ik", "zavar2024", "--xyz", "0.3", "0", "-0.07"),
                    ("workspace", "zavar2024", "--out", "/tmp/x")):
        out = run(*command, "--seed", "-1")
        assert out.returncode == 2 and "expected an integer >= 0, got -1" in out.stderr
    out = run("compare", "zavar2024", "--target", "0", "0", "0", "--workers", "-3", "--out",
              "/tmp/x")
    assert out.returncode == 2 and "expected an integer >= 1, got -3" in out.stderr


def test_compare_writes_the_table_and_figures(tmp_path):
    """compare writes runs.csv, summary.csv and three figures."""
    out = run("compare", "zavar2024", "--target", "-0.23", "0.20", "-0.07", "--methods", "ipopt",
              "--seeds", "1", "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    for name in ("runs.csv", "summary.csv", "convergence.png", "time_vs_population.png",
                 "error_time_boxes.png"):
        assert (tmp_path / name).is_file(), name
    header = (tmp_path / "runs.csv").read_text().splitlines()[0].split(",")
    assert {"x_m", "abs_err_z_m", "error_m_rad", "time_s"} <= set(header)  # units in the names


PATH_KEYS = {"robot", "method", "timing", "points", "solved", "max_error", "jumps", "duration_s",
             "limit_ratios", "files"}


@pytest.mark.parametrize("timing", ["toppra", "ruckig"])
def test_path_solves_times_and_writes(tmp_path, timing):
    """path: a reachable circle is solved at every point, timed within the limits, written."""
    out = run("path", "zavar2024", "--circle", "280", "0", "50", "-70", "--mm", "-n", "24",
              "--time", timing, "--json", "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert set(data) == PATH_KEYS
    assert data["points"] == data["solved"] == 24 and data["max_error"] <= 1e-9
    assert data["jumps"] == [] and data["duration_s"] > 0
    assert all(r <= 1 + 1e-6 for r in data["limit_ratios"].values())
    for name in ("joint_path.csv", "trajectory.csv", "trajectory.png"):
        assert (tmp_path / name).is_file(), name


def test_path_html_writes_the_animation_in_out(tmp_path):
    """path --html writes a meshcat page of the timed path inside --out as path.html,
    listed with the other files: a flag, as on plan, cycle and run (issue 38: it took a
    file name on path and was a flag elsewhere); a file name after it is a usage error.

    Mutation caught: the --html branch of cmd_path not writing the page.
    """
    out = run("path", "zavar2024", "--circle", "280", "0", "50", "-70", "--mm", "-n", "12",
              "--out", str(tmp_path), "--html")
    assert out.returncode == 0, out.stderr
    page = tmp_path / "path.html"
    assert page.is_file() and "new MeshCat.Viewer" in page.read_text()
    assert str(page) in out.stdout
    out = run("path", "zavar2024", "--circle", "280", "0", "50", "-70", "--mm", "-n", "12",
              "--out", str(tmp_path / "other"), "--html", "circle.html")
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "unrecognized arguments: circle.html" in out.stderr


def test_workspace_and_reproduce(tmp_path):
    """workspace writes its figures; reproduce writes summary.md with the paper's findings."""
    out = run("workspace", "zavar2024", "-n", "5000", "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "zavar2024_workspace_xy.png").is_file()
    out = run("reproduce", "inverted5", "--quick", "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    summary = (tmp_path / "summary.md").read_text()
    assert "## inverted5" in summary and "matched" in summary
