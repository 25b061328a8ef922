"""Shared CLI arguments: --vmax/--amax/--jmax checked before IK, angles in degrees.

``path`` and ``cycle`` reach the end for any robot.

A URDF carries no acceleration limit. Before: ``scara-opt path`` on such a robot ran its IK
(7-13 s) and then failed with "pass amax=", an option it did not have. Driven in-process
through ``main`` so that the IK can be replaced by a trap.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import scara_opt as so
from scara_opt import cli
from tests.conftest import DATA, ROOT

ARM = str(ROOT / "examples" / "arm6.urdf")  # no <scara_opt acceleration=>: no amax
LINE = ["--line", "0.6", "0.1", "0.2", "0.6", "0.3", "0.2", "-n", "12"]


@pytest.fixture()
def no_ik(monkeypatch):
    """Make any IK along a path fail loudly: the limits must be refused before it."""
    def trap(*args, **kwargs):
        raise AssertionError("IK ran before the limits were checked")

    monkeypatch.setattr(so, "ik_path", trap)
    monkeypatch.setattr("scara_opt.motion.cycle.place_cycle", trap)


def scara_without_amax(tmp_path: Path) -> str:
    """zavar2024's URDF with its acceleration limits (the toolkit's extension) removed."""
    text = (ROOT / "robots" / "zavar2024.urdf").read_text()
    stripped = re.sub(r"\s*<scara_opt acceleration=\"[^\"]*\"\s*/>", "", text)
    assert stripped != text
    path = tmp_path / "scara.urdf"
    path.write_text(stripped)
    return str(path)


@pytest.mark.parametrize("time", ["toppra", "ruckig", "quintic"])
def test_path_refuses_a_missing_limit_before_any_ik(no_ik, tmp_path, capsys, time):
    """No --amax for a robot without one: exit 2 naming --amax, and no IK run.

    Mutation caught: the limits left to the timing after the IK (``limits =
    joint_limits(...)`` -> ``limits = None`` in cmd_path) -> the trap fires, fails.
    """
    code = cli.main(["path", ARM, *LINE, "--time", time, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "pass --amax" in err and "amax=" not in err


def test_path_with_amax_reaches_the_end(tmp_path, capsys):
    """--amax for all joints (one value) and --vmax per joint: timed within them, files out.

    Mutation caught: the CLI's limits not passed on (``vmax=limits.vmax`` dropped in
    cmd_path) -> timed at the robot's own velocity limits (3.15 rad/s), above 1.0, fails.
    """
    out = tmp_path / "o"
    code = cli.main(["path", ARM, *LINE, "--amax", "5", "--vmax", "1", "1", "1", "0.2", "1",
                     "1", "--out", str(out), "--json"])
    assert code == 0, capsys.readouterr().err
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    names = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    qd = rows[:, [k for k, n in enumerate(names) if n.endswith("_per_s")]]
    assert (np.abs(qd).max(axis=0) <= np.array([1, 1, 1, 0.2, 1, 1]) + 1e-9).all()


@pytest.mark.parametrize(("extra", "message"), [
    (["--amax", "5", "4"], "--amax takes one value for all joints or 6"),
    (["--amax", "5", "--jmax", "50"], "--jmax limits the jerk of --time ruckig only"),
    (["--amax", "0"], "must be a finite number > 0"),
    (["--amax", "1e9"], "pass --amax within that range"),
    (["--amax", "5", "--time", "ruckig", "--jmax", "1e7"], "pass --jmax <= 100000 x amax"),
])
def test_path_limit_options_are_checked(no_ik, tmp_path, capsys, extra, message):
    """Bad counts, values and combinations: exit 2 with the option named, before any IK."""
    code = cli.main(["path", ARM, *LINE, *extra, "--out", str(tmp_path / "o")])
    assert code == 2 and message in capsys.readouterr().err


def test_cycle_takes_joint_limits_and_refuses_a_missing_one(no_ik, tmp_path, capsys):
    """cycle on a SCARA URDF without acceleration limits: exit 2 naming --amax, no IK."""
    code = cli.main(["cycle", scara_without_amax(tmp_path)])
    assert code == 2 and "pass --amax" in capsys.readouterr().err


def test_cycle_times_within_the_given_joint_limits(tmp_path, capsys):
    """cycle with --amax per joint and --vmax for all: each ratio <= 1 against those limits.

    Mutation caught: cycle_time's limits not given to the toppra plan (``vmax=vmax,
    amax=amax`` dropped from its first ``plan``) -> "no amax" from the robot's own, fails.
    """
    urdf = scara_without_amax(tmp_path)
    code = cli.main(["cycle", urdf, "--amax", "10", "10", "2", "20", "--vmax", "2",
                     "--json"])
    assert code == 0, capsys.readouterr().err
    robot = so.Robot.from_urdf(urdf)
    res = so.cycle_time(robot, vmax=2.0, amax=[10, 10, 2, 20])
    lim = res.trajectory.limits
    assert np.allclose(lim.vmax, 2.0) and np.allclose(lim.amax, [10, 10, 2, 20])
    assert max(float(v.max()) for v in res.trajectory.check_limits().values()) <= 1 + 1e-9


def test_continuous_wrist_robot_is_not_a_special_case():
    """The wrist without limits (tests/data) still has its acceleration from the extension."""
    robot = so.Robot.from_urdf(DATA / "scara_continuous_wrist.urdf")
    assert np.isfinite(robot.acceleration_limit).all()
