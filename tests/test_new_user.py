"""The rough edges a new user hit (issue 31), one test each, driven as that user drove them."""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so


def test_nguyen_cycle_strokes_up_against_gravity_and_across_level(robots):
    """nguyen's robot file puts base z up: the 25 mm strokes go along +z, the 305 mm level.

    Before: its 25 mm "up/down" strokes were along -y (horizontal) and the 305 mm "across"
    along z (vertical), because the cycle followed the revolute axis, horizontal on nguyen.
    The vertical SCARAs keep their placement (zavar2024: 2.2303 s). Mutations caught: the
    strokes along the axis again (``Au, Bu = A + up * UP, ...`` -> ``A + up * n``) and the
    across stroke across the ray (``w = np.cross(g.n, u) if vertical else level`` ->
    ``np.cross(g.n, u)``: vertical on nguyen), each fails.
    """
    robot = robots["nguyen"]
    res = so.cycle_time(robot)
    steps = np.diff(robot.positions(res.corners), axis=0)
    np.testing.assert_allclose(steps[[0, 3]], [[0, 0, 0.025]] * 2, atol=1e-9)  # up
    np.testing.assert_allclose(steps[[2, 5]], [[0, 0, -0.025]] * 2, atol=1e-9)  # down
    for k in (1, 4):  # across: level, 305 mm
        assert abs(steps[k, 2]) < 1e-9 and np.linalg.norm(steps[k]) == pytest.approx(0.305)
    zavar = so.cycle_time(robots["zavar2024"])
    assert zavar.durations["toppra"] == pytest.approx(2.2303, abs=1e-4)
