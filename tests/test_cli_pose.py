"""Full poses at the command line: ``ik --rpy/--quat``, ``fk`` orientation, through cli.main."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt import pose
from scara_opt.cli import main
from tests.conftest import DATA

ARM6 = str(DATA / "arm6.urdf")
Q6 = [0.1, 0.2, 0.3, 0.1, 0.2, 0.3]


def _num(v: float) -> str:
    return repr(float(v))


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    """Exit code, stdout, stderr of ``scara-opt argv`` (argparse's SystemExit counted as a code)."""
    try:
        code = main(list(argv))
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_fk_prints_rpy_and_quaternion(capsys):
    """fk gives the orientation as RPY [deg] and quaternion (w, x, y, z), text and JSON.

    Mutations caught: rpy_deg printed in radians (np.degrees dropped); the quaternion's
    order x, y, z, w.
    """
    robot = so.Robot.from_urdf(ARM6)
    R = robot.fk(Q6)[:3, :3]
    code, out, _ = _run(capsys, "fk", ARM6, *map(str, Q6), "--json")
    assert code == 0
    data = json.loads(out)
    np.testing.assert_allclose(pose.rpy_to_matrix(np.radians(data["rpy_deg"])), R, atol=1e-12)
    np.testing.assert_allclose(pose.quat_to_matrix(data["quaternion_wxyz"]), R, atol=1e-12)
    assert data["quaternion_wxyz"][0] >= 0
    code, out, _ = _run(capsys, "fk", "zavar2024", "30", "45", "20", "10", "--deg", "--mm")
    assert code == 0
    assert "orientation: rpy (0, 0, 85) deg, quaternion (w, x, y, z) (0.737277, 0, 0, 0.67559)" \
        in out


@pytest.mark.parametrize("form", ["rpy_deg", "rpy_rad", "quat"])
def test_ik_full_pose_round_trip_on_a_6_joint_arm(capsys, form):
    """fk's pose asked back through ik --rpy (deg or rad) or --quat is reached to 1e-9.

    Mutation caught: --rpy-unit ignored (rad values read as degrees).
    """
    robot = so.Robot.from_urdf(ARM6)
    T = robot.fk(Q6)
    rpy = pose.matrix_to_rpy(T[:3, :3])
    orient = {"rpy_deg": ["--rpy", *map(_num, np.degrees(rpy))],
              "rpy_rad": ["--rpy", *map(_num, rpy), "--rpy-unit", "rad"],
              "quat": ["--quat", *map(_num, pose.matrix_to_quat(T[:3, :3]))]}[form]
    code, out, err = _run(capsys, "ik", ARM6, "--xyz", *map(_num, T[:3, 3]), *orient, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["success"], data["message"]
    np.testing.assert_allclose(robot.fk(data["q"]), T, atol=1e-9)
    assert data["rotation_error_deg"] < 1e-6
    np.testing.assert_allclose(data["reached_orientation"]["quaternion_wxyz"],
                               data["target_orientation"]["quaternion_wxyz"], atol=1e-9)


def test_scara_rpy_about_z_is_the_yaw(capsys):
    """On a SCARA, --rpy 0 0 Y asks the same pose as --yaw Y."""
    robot = so.load_robot("zavar2024")
    args = ["ik", "zavar2024", "--xyz", "0.3", "0.1", "-0.07", "--json"]
    code_r, out_r, _ = _run(capsys, *args, "--rpy", "0", "0", "30")
    code_y, out_y, _ = _run(capsys, *args, "--yaw", "30")
    assert code_r == code_y == 0
    T_r, T_y = (robot.fk(json.loads(o)["q"]) for o in (out_r, out_y))
    np.testing.assert_allclose(T_r, T_y, atol=1e-9)
    assert math.degrees(robot.yaw(json.loads(out_r)["q"])) == pytest.approx(30)


@pytest.mark.parametrize("extra, message", [
    (["--yaw", "3", "--rpy", "0", "0", "3"], "not allowed with"),
    (["--rpy", "0", "0", "3", "--quat", "1", "0", "0", "0"], "not allowed with"),
    (["--quat", "0", "0", "0", "0"], "unit quaternion"),
    (["--rpy-unit", "rad"], "--rpy-unit sets the unit of --rpy only"),
    (["--rpy", "0", "nan", "0"], "NaN or inf"),
])
def test_bad_orientation_options_exit_2(capsys, extra, message):
    """Two orientations at once, a zero quaternion, a lone --rpy-unit: exit 2, one message.

    Mutation caught: --rpy added outside the mutually exclusive group.
    """
    code, _, err = _run(capsys, "ik", "zavar2024", "--xyz", "0.3", "0.1", "-0.07", *extra)
    assert code == 2 and message in err
