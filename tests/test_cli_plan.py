"""`scara-opt plan` and `scara-opt cycle --cell`, driven as a user would (subprocess)."""

from __future__ import annotations

import json

import pytest

from tests.conftest import DATA
from tests.conftest import run_cli as run


@pytest.fixture
def rack():
    return str(DATA / "rack_cell.toml")


def test_plan_over_a_rack_exits_0_with_a_clean_stderr(rack, tmp_path):
    """A PTP across a rack (the straight move lowers the tool through it) plans, says it is
    proven clear, writes its CSV, and leaves stderr empty (no nanobind leak report at exit).

    Mutation caught: the OMPL objects kept alive past the query (a module-level cache of the
    SpaceInformation): nanobind then lists leaked instances on stderr at exit.
    """
    out = run("plan", "zavar2024", "--start", "30", "60", "40", "0", "--goal", "-40", "70", "40",
              "0", "--deg", "--mm", "--cell", rack, "--out", str(tmp_path / "o"), "--csv")
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""
    assert "solved: zavar2024 PTP" in out.stdout and "proven clear of 'rack demo'" in out.stdout
    assert (tmp_path / "o" / "plan.csv").is_file()


def test_plan_json_and_no_path_exit_code(tmp_path):
    """--json gives the status; a goal in a closed slot gives no_path and exit code 1."""
    slot = DATA / "slot_cell.toml"
    out = run("plan", "zavar2024", "--start", "-1.5", "0.3", "0.02", "0", "--goal", "0", "0",
              "0.02", "0", "--cell", str(slot), "--time-limit", "0.2", "--json")
    assert out.returncode == 1, out.stderr
    data = json.loads(out.stdout)
    assert data["status"] == "no_path" and "no path found within the time limit" in data[
        "message"]
    assert data["states"] > 0


@pytest.mark.parametrize("args, match", [
    (["--goal", "-40", "70", "40", "0", "--margin", "2"], "give --cell FILE"),
    (["--goal", "300", "0", "0", "0"], "joint 'theta1' = 5.23599 rad is outside"),
    (["--xyz", "250", "0", "-80", "--cell", "RACK"], "goal is in collision: link4 and rack"),
    ([], "give the goal as joints"),
    (["--goal", "-40", "70", "40", "0", "--cell", "missing.toml"], "does not exist"),
    (["--goal", "-40", "70", "40", "0", "--cell", "RACK", "--time-limit", "0"], "must be a "
                                                                               "finite number"),
])
def test_plan_bad_input_is_one_line_exit_2(rack, args, match):
    """Bad input to plan: exit 2 and one line naming what to change."""
    args = [rack if a == "RACK" else a for a in args]
    out = run("plan", "zavar2024", "--start", "30", "60", "40", "0", "--deg", "--mm", *args)
    assert out.returncode == 2
    assert match in out.stderr and out.stderr.count("\n") == 1


def test_cycle_in_a_cell(rack):
    """`cycle --cell` plans the cycle in the cell and says it is proven clear."""
    out = run("cycle", "zavar2024", "--across", "200", "--cell", rack, "--margin", "2")
    assert out.returncode == 0, out.stderr
    assert "proven clear of 'rack demo'" in out.stdout and out.stderr == ""
