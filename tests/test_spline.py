"""The geometric path built without scipy's and toppra's overhead is theirs, to round-off."""

import numpy as np
import pytest

from scara_opt.trajectory.spline import geometric_path, not_a_knot


def _paths(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    s = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 1.0, n - 1))])
    return s / s[-1], rng.uniform(-2.0, 2.0, (n, 4))


@pytest.mark.parametrize("n", [2, 3, 4, 5, 7, 12, 31])
def test_the_not_a_knot_spline_is_scipys(n):
    """Values and first three derivatives equal scipy's CubicSpline(s, Q) (not-a-knot) to
    1e-9 relative, on uneven steps, over the whole parameter range and at its ends.

    Mutations caught: the first row's right-hand side with ``dx[1]`` and ``dx[0]`` swapped
    (-> fails for n >= 4); the last row's off-diagonal ``dx[-2]`` in place of
    ``s[-1] - s[-3]`` (-> fails for n >= 4); the slopes of a two-point spline set to 0
    (-> fails for n = 2).
    """
    from scipy.interpolate import CubicSpline

    for seed in range(5):
        s, Q = _paths(n, seed)
        want, got = CubicSpline(s, Q), not_a_knot(s, Q)
        x = np.concatenate([np.linspace(0.0, 1.0, 97), s])
        for nu in range(4):
            a, b = want(x, nu), got(x, nu)
            scale = max(np.abs(a).max(), 1.0)
            assert np.allclose(b, a, rtol=1e-9, atol=1e-9 * scale), (n, seed, nu)
        assert np.array_equal(got.x, want.x)
        assert got.c.shape == want.c.shape


def test_the_three_point_passing_spline_is_toppras():
    """The parabola built for three waypoints is toppra's not-a-knot spline, its value and
    first two derivatives, on uneven parameter steps.

    Mutation caught: the middle slope weighted the wrong way round (m0 * h0 + m1 * h1)
    -> fails.
    """
    import toppra

    from scara_opt.trajectory.spline import _parabola

    Q = np.random.default_rng(0).uniform(-1, 1, (3, 4))
    s = np.array([0.0, 0.3, 1.0])
    want, got = toppra.SplineInterpolator(s, Q).cspl, _parabola(s, Q)
    x = np.linspace(0.0, 1.0, 21)
    for nu in range(3):
        assert np.allclose(got(x, nu), want(x, nu), atol=1e-12)


def test_the_geometric_path_is_toppras():
    """geometric_path(s, Q) answers as toppra's SplineInterpolator(s, Q): path(s, order) for
    orders 0-2, its waypoints, interval and dof; toppra's joint constraints give the same
    parameters on a grid (what the timing reads from it).

    Mutation caught: the second derivative taken as the first (``cspldd = cspld``) -> the
    order-2 values and the acceleration constraint's parameters differ -> fails.
    """
    import toppra
    import toppra.constraint as constraint

    s, Q = _paths(9, 3)
    want, got = toppra.SplineInterpolator(s, Q), geometric_path(s, Q)
    grid = np.linspace(0.0, 1.0, 41)
    for order in range(3):
        assert np.allclose(got(grid, order), want(grid, order), rtol=1e-9, atol=1e-9)
    assert np.array_equal(got.path_interval, want.path_interval)
    assert got.dof == want.dof == 4
    assert all(np.array_equal(a, b) for a, b in zip(got.waypoints, want.waypoints, strict=True))
    acc = constraint.JointAccelerationConstraint(np.full(4, 3.0))
    for a, b in zip(acc.compute_constraint_params(got, grid),
                    acc.compute_constraint_params(want, grid), strict=True):
        assert (a is None and b is None) or np.allclose(a, b, rtol=1e-9, atol=1e-9)


def test_parameters_not_increasing_are_refused():
    """A repeated or decreasing parameter (a zero-length segment) raises, as scipy does,
    instead of dividing by zero into NaN coefficients.

    Mutation caught: the check dropped -> NaN coefficients, no error, fails.
    """
    Q = np.zeros((4, 2))
    for s in ([0.0, 0.5, 0.5, 1.0], [0.0, 0.6, 0.4, 1.0], [0.0]):
        with pytest.raises(ValueError, match="strictly increasing"):
            not_a_knot(np.array(s), Q[:len(s)])
