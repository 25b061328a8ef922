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


@pytest.mark.parametrize("weights", [(1e200, 1.0), (1.0, 1e-300), (True, 1.0), ("1", "1"),
                                     (1.0, 10**400)])
def test_weights_outside_their_range_are_refused(weights):
    """(1e200, 1) was accepted: its square overflows the cost to inf. The range is stated.

    Mutation: WEIGHT_RANGE = (0, inf) -> fails.
    """
    with pytest.raises(so.TargetError, match=r"each within \[1e-06, 1e\+06\]"):
        so.Target([0, 0, 0], weights=weights)


@pytest.mark.parametrize("kwargs, match", [
    (dict(position=[1e308, 0, 0]), r"beyond ±1e\+06 m"),
    (dict(position=[0, 0, 10**30]), r"beyond ±1e\+06 m"),
    (dict(position=["0.1", "0", "0"]), "must be numeric"),
    (dict(position=[0, 0, 0], yaw=1e308), r"within ±1e\+06 rad"),
    (dict(position=[0, 0, 0], yaw=10**400), r"within ±1e\+06 rad"),
    (dict(position=[0, 0, 0], yaw=True), "yaw must be a number"),
    (dict(position=[0, 0, 0], yaw="0.5"), "yaw must be a number"),
])
def test_absurd_or_mistyped_targets_are_refused(kwargs, match):
    """Coordinates of 1e308 m gave an inf residual; yaw strings and bools were converted.

    Mutation: the MAX_COORDINATE check removed -> fails.
    """
    with pytest.raises(so.TargetError, match=match):
        so.Target(**kwargs)


def test_target_does_not_freeze_the_callers_arrays():
    """The target keeps read-only copies; the arrays passed in stay writeable.

    Mutation: the position kept without a copy (the caller's array set read-only) -> fails.
    """
    p, R = np.array([0.3, 0.0, -0.07]), np.eye(3)
    t = so.Target(p, rotation=R)
    assert p.flags.writeable and R.flags.writeable
    assert not t.position.flags.writeable and not t.rotation.flags.writeable


@pytest.mark.parametrize("bad, match", [
    ([np.nan, 0.0, 0.0], "NaN or inf"), ([0.0, np.inf, 0.0], "NaN or inf"),
    ([0.0, 0.0, -np.inf], "NaN or inf"), ([1e308, 0.0, 0.0], r"beyond ±1e\+06 m"),
    ([0.0, -2e6, 0.0], r"beyond ±1e\+06 m"),
])
def test_a_float_array_position_is_checked_like_any_other(bad, match):
    """A float64 (3,) array takes the fast path (three comparisons): NaN, inf and
    out-of-range coordinates still get their own errors, and a valid one is copied, not
    frozen in the caller's hands.

    Mutations caught: the fast path without its range comparisons (NaN accepted); the
    fast path returning the caller's array un-copied (test_target_does_not_freeze...).
    """
    with pytest.raises(so.TargetError, match=match):
        so.Target(np.array(bad))
    p = np.array([0.1, -0.2, 0.3])
    assert so.Target(p).position.tolist() == [0.1, -0.2, 0.3]
