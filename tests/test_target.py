"""Target: validated on construction (finite, right shapes, a proper rotation)."""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so


def test_target_kinds():
    """A target is a position, a position with yaw, or a position with a rotation."""
    assert so.Target([0.1, 0.2, 0.3]).kind == "position"
    assert so.Target([0.1, 0.2, 0.3], yaw=0.5).kind == "yaw"
    assert so.Target([0.1, 0.2, 0.3], rotation=np.eye(3)).kind == "rotation"
    assert so.Target((0, 0, 0)).weights == (1.0, 1.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(position=[0, 0]), r"shape \(3,\)"),
    (dict(position=[0, np.nan, 0]), "NaN or inf"),
    (dict(position=[0, 0, np.inf]), "NaN or inf"),
    (dict(position="abc"), "numeric"),
    (dict(position=[0, 0, 0], yaw=np.nan), "yaw must be finite"),
    (dict(position=[0, 0, 0], yaw="north"), "yaw must be a number"),
    (dict(position=[0, 0, 0], yaw=0.1, rotation=np.eye(3)), "not both"),
    (dict(position=[0, 0, 0], rotation=np.eye(2)), r"shape \(3, 3\)"),
    (dict(position=[0, 0, 0], rotation=2 * np.eye(3)), "proper rotation"),
    (dict(position=[0, 0, 0], rotation=np.diag([1.0, 1.0, -1.0])), "proper rotation"),
    (dict(position=[0, 0, 0], weights=(1.0, 0.0)), "two positive numbers"),
    (dict(position=[0, 0, 0], weights=(1.0,)), "two positive numbers"),
])
def test_bad_targets_raise_target_error(kwargs, match):
    """Malformed targets raise TargetError saying what is wrong."""
    with pytest.raises(so.TargetError, match=match):
        so.Target(**kwargs)


def test_target_is_immutable():
    """A target's arrays cannot be changed after construction."""
    t = so.Target([0.1, 0.2, 0.3])
    with pytest.raises(ValueError):
        t.position[0] = 1.0
