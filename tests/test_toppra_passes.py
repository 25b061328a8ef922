"""TOPP-RA's passes, compiled and on toppra's seidel solver: toppra's TOPPRA's path velocities."""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so
from scara_opt.trajectory import toppra_passes
from scara_opt.trajectory.dynamics import RobotDynamics
from scara_opt.trajectory.toppra_backend import chord_parameter
from scara_opt.trajectory.toppra_passes import reachability_passes, seidel_passes
from tests.conftest import random_q

ROBOT = so.load_robot("zavar2024")


def toppras_own(cons, path, grid):
    """toppra's TOPPRA with the seidel solver, from rest to rest: (sd or None, return code)."""
    import toppra.algorithm as algo

    inst = algo.TOPPRA(cons, path, gridpoints=grid, solver_wrapper="seidel")
    inst.compute_parameterization(0.0, 0.0)
    data = inst.problem_data
    ok = data.return_code == algo.ParameterizationReturnCode.Ok
    return (np.asarray(data.sd_vec) if ok else None), data.return_code


def problem(n: int, seed: int, per: int, torque: float | None = None):
    """Random waypoints within the limits, toppra's spline and constraints, a grid."""
    import toppra
    import toppra.constraint as constraint

    Q = random_q(ROBOT, n, seed)
    s = chord_parameter(Q, ROBOT.velocity_limit)
    path = toppra.SplineInterpolator(s, Q)
    cons = [constraint.JointVelocityConstraint(ROBOT.velocity_limit),
            constraint.JointAccelerationConstraint(
                ROBOT.acceleration_limit,
                discretization_scheme=constraint.DiscretizationType.Interpolation)]
    if torque is not None:
        cons.append(RobotDynamics(ROBOT, torque).toppra_constraint())
    grid = np.append((s[:-1, None] + np.diff(s)[:, None] * np.arange(per) / per).ravel(), 1.0)
    return cons, path, grid


@pytest.mark.parametrize("n, seed, per, torque", [
    (2, 0, 100, None), (5, 1, 20, None), (12, 2, 7, None), (30, 3, 2, None),
    (6, 4, 16, True)])
def test_same_path_velocities_as_toppras_toppra_to_the_bit(n, seed, per, torque):
    """On random paths (2 to 30 waypoints, coarse and fine grids, with torque limits), the
    passes give toppra's own path velocities exactly.

    Mutation caught: the forward pass without toppra's round-off safeguard (``x_next``
    taken as computed, no ``- TINY`` / ``0.9999``): the velocities differ in the last bits.
    Mutation caught: the lower end of the controllable set from the same LP as the upper
    (``g`` not negated): the sets, and the velocities, differ.
    """
    cons, path, grid = problem(n, seed, per, torque)
    ours, code = seidel_passes(cons, path, grid)
    ref, ref_code = toppras_own(cons, path, grid)
    assert code == ref_code and ref is not None
    assert np.array_equal(ours, ref)


CASES = [(2, 0, 100, None), (5, 1, 20, None), (12, 2, 7, None), (30, 3, 2, None),
         (6, 4, 16, True)] + [(k % 9 + 2, 100 + k, k % 5 * 3 + 2, True if k % 3 == 0 else None)
                              for k in range(40)]


@pytest.mark.parametrize("n, seed, per, torque", CASES)
def test_the_compiled_passes_give_toppras_path_velocities(n, seed, per, torque):
    """The compiled passes (toppra_passes.c) on 45 random paths (2 to 30 waypoints, grids of
    2 to 100 intervals a segment, a third with torque limits): toppra's own TOPPRA's path
    velocities to 1e-12 of the largest (measured: 1.4e-14).

    Mutation caught: the row a pair of u-bounds gives in x taken without the rows' slopes
    (``C = cn - cp`` instead of ``ap cn - an cp`` in ``x_range``): the sets, and the
    velocities, differ by far more. Mutation caught: the forward pass's new velocity not
    kept within the next controllable set (its two clamps removed): the velocities leave
    toppra's.
    """
    if toppra_passes._kernel() is None:
        pytest.skip("nothing compiles here: reachability_passes runs seidel_passes")
    cons, path, grid = problem(n, seed, per, torque)
    ours, code = reachability_passes(cons, path, grid)
    ref, ref_code = toppras_own(cons, path, grid)
    assert code == ref_code and ref is not None and ours is not None
    assert np.abs(ours - ref).max() <= 1e-12 * ref.max()


def test_without_a_compiler_the_passes_are_toppras_own_to_the_bit(monkeypatch):
    """With no compiled kernel (``SCARA_OPT_NO_COMPILE=1`` or no compiler), the passes are
    the seidel form: toppra's velocities to the bit.

    Mutation caught: the fallback not taken (the kernel called whatever ``_kernel`` gives):
    ``None`` is called, TypeError.
    """
    monkeypatch.setattr(toppra_passes, "_kernel", lambda: None)
    cons, path, grid = problem(7, 9, 5)
    ours, code = reachability_passes(cons, path, grid)
    ref, ref_code = toppras_own(cons, path, grid)
    assert code == ref_code and np.array_equal(ours, ref)


def test_an_uncontrollable_path_is_refused_as_toppra_refuses_it():
    """Torque limits of 1e-9 N (m) that gravity on the quill exceeds even at rest: no
    velocities, and toppra's own return code (FailUncontrollable).

    Mutation caught: a NaN from the backward pass's LP not checked (in seidel_passes):
    NaN velocities come back as a result. In C each of three checks refuses it alone: a
    pair of rows that cannot both hold (``B = 0``, ``C > 0`` in ``x_range``), an empty x
    range, the start at rest outside K[0]. Mutation caught: all three removed: the forward
    pass fails instead, with another code (ErrUnknown).
    """
    cons, path, grid = problem(4, 5, 10, torque=1e-9)
    ref, ref_code = toppras_own(cons, path, grid)
    for passes in (reachability_passes, seidel_passes):  # compiled (where it compiles), seidel
        ours, code = passes(cons, path, grid)
        assert ours is None and ref is None and code == ref_code
