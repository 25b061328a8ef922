"""Cartesian paths: the papers' presets, circles, lines, contours, and their array form."""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt import paths
from scara_opt.errors import InputError


def positions(targets: list[so.Target]) -> np.ndarray:
    return np.array([t.position for t in targets])


def test_zavar2024_table3_in_si_with_the_sign_typo_fixed():
    """The ten Table 3 points in metres at z = -0.06 m; point 7 is (0.14, -0.0775)."""
    P = positions(paths.zavar2024_circle())
    assert P.shape == (10, 3)
    # ROBOTS.md / zavar2024 Table 3 [cm], point 7 with its sign fixed
    table3 = [(-14, 7.75), (-8, 13.85), (0, 16), (8, 13.85), (14, 7.75), (16, 0),
              (14, -7.75), (8, -13.85), (0, -16), (-8, -13.85)]
    np.testing.assert_allclose(P[:, :2], np.array(table3) / 100.0, atol=1e-15)
    assert np.allclose(P[6], (0.14, -0.0775, -0.06))
    assert np.allclose(P[:, 2], -0.06)
    assert np.allclose(np.hypot(P[:, 0], P[:, 1]), 0.16, atol=2e-4)
    angles = np.degrees(np.unwrap(np.arctan2(P[:, 1], P[:, 0])))
    assert np.all(np.diff(angles) < 0)  # clockwise, no repeated point
    assert all(t.kind == "position" for t in paths.zavar2024_circle())


def test_zavar2024_reachable_variant_keeps_the_angles():
    """The reachable variant: same polar angles at r = 0.30 m, z = -0.07 m."""
    paper = positions(paths.zavar2024_circle())
    P = positions(paths.zavar2024_circle(reachable=True))
    assert np.allclose(np.hypot(P[:, 0], P[:, 1]), 0.30)
    assert np.allclose(P[:, 2], -0.07)
    assert np.allclose(np.arctan2(P[:, 1], P[:, 0]), np.arctan2(paper[:, 1], paper[:, 0]))


def test_circle_full_turn_does_not_repeat_the_first_point():
    """n points over a full turn are 2π/n apart; a partial sweep includes both ends."""
    P = positions(paths.circle((0.1, -0.2), 0.3, 0.05, 8))
    assert np.allclose(np.hypot(P[:, 0] - 0.1, P[:, 1] + 0.2), 0.3)
    assert np.allclose(np.linalg.norm(np.diff(P, axis=0), axis=1), 2 * 0.3 * math.sin(math.pi / 8))
    arc = positions(paths.circle((0, 0), 1.0, 0.0, 3, start=0.0, sweep=-math.pi))
    assert np.allclose(arc, [[1, 0, 0], [0, -1, 0], [-1, 0, 0]], atol=1e-15)


def test_circle_tangent_yaw_is_the_direction_of_travel():
    """yaw='tangent' points along the motion, for both senses of travel."""
    for sweep in (math.pi, -math.pi):
        ts = paths.circle((0, 0), 0.3, 0.0, 50, sweep=sweep, yaw="tangent")
        P = positions(ts)
        d = np.diff(P, axis=0)
        heading = np.arctan2(d[:, 1], d[:, 0])
        mid = np.array([(a.yaw + b.yaw) / 2 for a, b in zip(ts[:-1], ts[1:], strict=True)])
        assert np.abs(np.angle(np.exp(1j * (heading - mid)))).max() < 1e-9
    const = paths.circle((0, 0), 0.3, 0.0, angles=[0.0, 1.0], yaw=0.25)
    assert [t.yaw for t in const] == [0.25, 0.25]


@pytest.mark.parametrize("kwargs", [
    {"n": 4, "angles": [0.0]}, {}, {"n": 0}, {"n": 3, "sweep": 0.0},
    {"angles": [[0.0]]}, {"angles": [math.nan]}, {"n": 3, "yaw": "normal"},
    {"n": 3, "yaw": math.inf},
])
def test_circle_rejects_bad_arguments(kwargs):
    """Both or neither of n/angles, a bad count, sweep or yaw: InputError."""
    with pytest.raises(InputError):
        paths.circle((0, 0), 0.3, 0.0, **kwargs)


@pytest.mark.parametrize("center, radius", [((0, 0, 0), 0.3), ((0, 0), -0.3), ((0, 0), 0.0)])
def test_circle_rejects_bad_geometry(center, radius):
    """A centre that is not (x, y), or a non-positive radius: InputError."""
    with pytest.raises(InputError):
        paths.circle(center, radius, 0.0, 4)


def test_line_includes_both_ends_and_has_a_tangent():
    """n evenly spaced points from start to end; the tangent is the line's heading."""
    ts = paths.line((0, 0, 0), (0.3, 0.3, -0.1), 4, yaw="tangent")
    P = positions(ts)
    assert np.allclose(P[0], 0) and np.allclose(P[-1], (0.3, 0.3, -0.1))
    assert np.allclose(np.diff(P, axis=0), (0.1, 0.1, -0.1 / 3))
    assert all(math.isclose(t.yaw, math.pi / 4) for t in ts)
    with pytest.raises(InputError, match="tangent"):
        paths.line((0, 0, 0), (0, 0, -0.1), 3, yaw="tangent")
    with pytest.raises(InputError):
        paths.line((0, 0, 0), (0.1, 0, 0), 1)


def test_point_to_point_gives_two_targets():
    """Two targets, with a yaw at both ends or at neither."""
    a, b = paths.point_to_point((0.3, 0, 0), (0, 0.3, 0), 0.1, 0.2)
    assert (a.yaw, b.yaw) == (0.1, 0.2) and np.allclose(b.position, (0, 0.3, 0))
    assert all(t.kind == "position" for t in paths.point_to_point((0.3, 0, 0), (0, 0.3, 0)))
    with pytest.raises(InputError, match="both"):
        paths.point_to_point((0.3, 0, 0), (0, 0.3, 0), yaw_start=0.1)


def test_rounded_rectangle_is_evenly_spaced_closed_and_tangent():
    """Equal arc-length steps, the last point closes the contour, the tool is tangent."""
    n = 80
    ts = paths.rounded_rectangle(n, (0.4, 0.3), 0.2, 0.3, 0.04, origin=(0, -0.1, 0),
                                 e1=(1, 0, 0), e2=(0, 0, 1))
    P = positions(ts)
    A = np.array([t.yaw for t in ts])
    assert len(ts) == n + 1
    assert np.allclose(P[0], P[-1]) and math.isclose(A[-1] - A[0], 2 * math.pi)
    assert np.allclose(P[:, 1], -0.1)
    assert np.allclose(P[:, [0, 2]].min(0), (0.3, 0.15)) and np.allclose(P[:, [0, 2]].max(0),
                                                                         (0.5, 0.45))
    steps = np.linalg.norm(np.diff(P, axis=0), axis=1)
    perimeter = 2 * (0.2 - 0.08) + 2 * (0.3 - 0.08) + 2 * math.pi * 0.04
    assert steps.max() <= perimeter / n + 1e-12 and steps.min() > 0.97 * perimeter / n
    d = np.diff(P[:, [0, 2]], axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    # chord heading vs mean tangent: equal on sides and arcs, within 0.05 rad where they meet
    assert np.abs(np.angle(np.exp(1j * (heading - (A[:-1] + A[1:]) / 2)))).max() < 0.05
    assert np.all(np.diff(A) >= 0)  # counter-clockwise: the tangent only turns one way


def test_rounded_rectangle_clockwise_turns_the_other_way():
    """Clockwise: the same rectangle, the tangent angle decreasing by 2π."""
    ts = paths.rounded_rectangle(40, (0, 0), 0.2, 0.1, 0.02, clockwise=True)
    A = np.array([t.yaw for t in ts])
    assert math.isclose(A[-1] - A[0], -2 * math.pi) and np.all(np.diff(A) <= 0)
    open_ = paths.rounded_rectangle(40, (0, 0), 0.2, 0.1, 0.02, closed=False, yaw=None)
    assert len(open_) == 40 and open_[0].kind == "position"


@pytest.mark.parametrize("kwargs", [
    {"corner_radius": 0.2}, {"width": -0.1}, {"e2": (1, 0, 0)}, {"e1": (2, 0, 0)}, {"n": 3},
])
def test_rounded_rectangle_rejects_bad_shapes(kwargs):
    """Corner radius above half a side, non-positive size, non-orthonormal axes: InputError."""
    args = {"n": 20, "center": (0, 0), "width": 0.2, "height": 0.1, "corner_radius": 0.02}
    args.update(kwargs)
    with pytest.raises(InputError):
        paths.rounded_rectangle(**args)


def test_nguyen_contour_lies_in_the_arm_plane_of_the_robot(robots):
    """The contour's plane axes are nguyen's yaw basis, so its tangent is nguyen's tool angle A."""
    robot = robots["nguyen"]
    e1, e2 = robot.yaw_basis()
    assert np.allclose(e1, (1, 0, 0)) and np.allclose(e2, (0, 0, 1))
    ts = paths.nguyen_contour(40)
    P = positions(ts)
    assert np.allclose(P[:, 1], -0.13) and all(t.kind == "yaw" for t in ts)
    # every fourth point is reached with its tool angle by the exact solver
    for t in ts[::4]:
        res = so.solve_ik(robot, t, method="ipopt")
        assert res.success, res
        assert abs(math.remainder(robot.yaw(res.q) - t.yaw, 2 * math.pi)) < 1e-9


def test_array_form_round_trip():
    """to_array gives (n, 3) or (n, 4) rows; as_targets reads them back."""
    ts = paths.circle((0, 0), 0.3, 0.0, 5, yaw="tangent")
    arr = paths.to_array(ts)
    assert arr.shape == (5, 4)
    back = paths.as_targets(arr)
    assert all(np.allclose(a.position, b.position) and math.isclose(a.yaw, b.yaw)
               for a, b in zip(ts, back, strict=True))
    assert paths.to_array(paths.zavar2024_circle()).shape == (10, 3)
    assert len(paths.as_targets(ts[0])) == 1


@pytest.mark.parametrize("bad", [np.zeros((3, 2)), np.zeros((0, 3)), [[0, 0, math.nan]], "x"])
def test_as_targets_rejects_bad_arrays(bad):
    """Arrays that are not (n, 3)/(n, 4), empty, or with NaN: InputError."""
    with pytest.raises(InputError):
        paths.as_targets(bad)


def test_to_array_refuses_mixed_kinds():
    """Some targets with a yaw and some without have no single array form."""
    with pytest.raises(InputError, match="all"):
        paths.to_array([so.Target((0.3, 0, 0)), so.Target((0.3, 0, 0), yaw=0.1)])


# ---------------------------------------------------------------------- degenerate and huge paths
@pytest.mark.parametrize("call, match", [
    (lambda: paths.line([0.3, 0, 0], [0.3, 0, 0], 5), r"start and end are the same point"),
    (lambda: paths.line([0.3, 0, 0], [np.nextafter(0.3, 1), 0, 0], 5),
     "points 0 and 1 of the path coincide"),
    (lambda: paths.circle((0, 0), 0.0, 0.0, 5), r"radius \[m\] must be a number in \(0, 1e\+06\]"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, angles=[0.0, 0.0, 1.0]), "points 0 and 1"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, 5, start=1.0, sweep=1e-300), "larger sweep"),
    (lambda: paths.point_to_point([0.3, 0, 0], [0.3, 0, 0]), "there is no move"),
    (lambda: paths.point_to_point([0.3, 0, 0], [0.3, 0, 0], 0.5, 0.5), "there is no move"),
])
def test_degenerate_paths_are_refused(call, match):
    """line(a, a, n) returned n identical targets; a radius of 0, equal angles or a sweep
    too small for n points stack points too; a point-to-point move to itself is no move.

    Mutation: line without its equal-ends check, and _distinct not called -> fails.
    """
    with pytest.raises(InputError, match=match):
        call()


def test_a_turn_in_place_is_a_move():
    """Same position, different tool angle: a valid point-to-point move."""
    assert len(paths.point_to_point([0.3, 0, 0], [0.3, 0, 0], 0.0, 1.0)) == 2


@pytest.mark.parametrize("call, name", [
    (lambda n: paths.circle((0, 0), 0.3, 0.0, n), "circle"),
    (lambda n: paths.line((0, 0, 0), (1, 0, 0), n), "line"),
    (lambda n: paths.rounded_rectangle(n, (0, 0), 1.0, 1.0, 0.1), "rounded_rectangle"),
    (lambda n: paths.nguyen_contour(n), "nguyen_contour"),
])
@pytest.mark.parametrize("n", [10**12, 10**30])
def test_huge_point_counts_are_refused_with_the_memory_estimate(call, name, n):
    """n = 10**12 raised MemoryError, 10**30 numpy's "Maximum allowed size exceeded".

    Mutation: _count without check_memory -> fails.
    """
    with pytest.raises(InputError, match=rf"{name}\(n=.*\) would need about .*lower n, or.*"
                                         "MAX_BYTES"):
        call(n)


@pytest.mark.parametrize("call, match", [
    (lambda: paths.rounded_rectangle(8, (0, 0), 1, 1, 0.1, clockwise="yes"), "clockwise must"),
    (lambda: paths.rounded_rectangle(8, (0, 0), 1, 1, 0.1, closed=1), "closed must be True"),
    (lambda: paths.zavar2024_circle("no"), "reachable must be True or False"),
    (lambda: paths.circle((0, 0), 0.3, "0.1", 5), "z must be a finite number"),
    (lambda: paths.circle((0, 0), True, 0.0, 5), r"radius \[m\] must be"),
    (lambda: paths.circle(("0", "1"), 0.3, 0.0, 5), "center"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, 5, start=None), "start must be"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, 5, sweep="2pi"), "sweep must be"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, 5, sweep=10**30), r"sweep must be a number in"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, angles=["a"]), "angles must be"),
    (lambda: paths.circle((0, 0), 0.3, 0.0, 5, yaw=True), "yaw must be None, a number"),
    (lambda: paths.nguyen_contour(20, y="-0.13"), "y must be a finite number"),
    (lambda: paths.as_targets([["0.1", "0", "0"]]), "targets must be"),
])
def test_flags_and_numbers_of_the_path_generators_are_typed(call, match):
    """Strings, bools and None where a number or a flag belongs; absurd sweeps.

    Mutation: rounded_rectangle without check_flag ("yes" counted as True) -> fails.
    """
    with pytest.raises(InputError, match=match):
        call()
