"""The fast solver's start loop in C (scara_opt/ik/lm_driver.c) against its Python form."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik import lm_driver
from scara_opt.ik.lm_batch import solve_many
from scara_opt.ik.lm_driver import Driver, phase_driver
from scara_opt.ik.lm_functions import limits, phase_arrays
from scara_opt.ik.lm_run import residual_tol
from scara_opt.ik.lm_search import lm_search
from scara_opt.ik.problem import fill_params
from scara_opt.model.compiled import c_library


def _targets(robot: so.Robot, kind: str, n: int, seed: int) -> list[so.Target]:
    Q = np.random.default_rng(seed).uniform(robot.sampling_lower, robot.sampling_upper,
                                            (n, robot.nq))
    out = []
    for q in Q:
        T = robot.fk(q)
        out.append(so.Target(T[:3, 3], rotation=T[:3, :3]) if kind == "rotation" else
                   so.Target(T[:3, 3], yaw=robot.yaw(q)) if kind == "yaw" else
                   so.Target(T[:3, 3]))
    return out


def _driver_or_skip(robot: so.Robot, kind: str) -> Driver:
    driver = phase_driver(robot, kind)
    if driver is None:
        pytest.skip("no C compiler here: the Python loop runs (tested everywhere else)")
    return driver


@pytest.mark.parametrize(("robot_name", "kind", "n", "nearest"), [
    ("ur5_arm", "rotation", 150, True), ("panda_arm", "rotation", 150, True),
    ("ur5_arm", "position", 60, True), ("zavar2024", "position", 60, True),
    ("fang", "yaw", 60, True), ("panda_arm", "rotation", 40, False)])
def test_c_loop_gives_the_python_loops_numbers_bit_for_bit(robot_name, kind, n, nearest,
                                                             request, robots):
    """From q0 and then seeded random starts (a tight budget of 12 iterations a start, so
    many starts stall, run out of budget mid-slide, or converge only at their last
    call), the C loop and ``lm_run.Run`` give the same q, ‖r‖², iterations, evaluations,
    starts and history, bit for bit: every branch of the loop is compared.

    Mutations caught (each in lm_driver.c): a stall counted at a 2 % decrease instead of
    1 % (``1 - stall_decrease`` -> ``1 - 2 * stall_decrease``); the full candidate set
    tried whenever the Newton step is refused (pull test dropped); the polish's result
    kept even where it did not converge (``if (ok)`` dropped); the best residual taken as
    the last (``if (e < run->best)`` dropped); with ``nearest=False``, the slide run anyway
    (``run->nearest`` dropped from ``lm_start``'s test).
    """
    robot = robots[robot_name] if robot_name in robots else request.getfixturevalue(robot_name)
    _driver_or_skip(robot, kind)
    q0 = 0.5 * (robot.sampling_lower + robot.sampling_upper)
    rng_starts = np.random.default_rng(2).uniform(robot.sampling_lower, robot.sampling_upper,
                                                  (6, robot.nq))
    for max_iter in (12, 100):
        for t in _targets(robot, kind, n, seed=8):
            found = [lm_search(robot, t, q0, iter([q0, *rng_starts]), tol=1e-9,
                                  max_iter=max_iter, c_loop=c_loop, nearest=nearest)
                     for c_loop in (True, False)]
            c, py = found
            np.testing.assert_array_equal(c.q, py.q)
            assert (c.e, c.iterations, c.evaluations, c.starts) == \
                (py.e, py.iterations, py.evaluations, py.starts)
            assert c.history == py.history


def test_solves_and_batches_run_the_c_loop_and_the_mapped_path_agrees(ur5_arm):
    """``solve_ik`` and ``solve_many`` use the C loop where the phases are compiled;
    without it (``jit=False``: casadi's virtual machine, no driver) ``solve_many`` still
    runs the mapped batch path, and both give the single solves' q bit for bit.

    Mutation caught: ``phase_driver`` built for ``jit=False`` too (the Functions' names find
    the libraries compiled earlier in the process, so compiled code would run under
    ``jit=False``: the assertion on it fails).
    """
    _driver_or_skip(ur5_arm, "rotation")
    assert phase_driver(ur5_arm, "rotation", jit=False) is None
    targets = _targets(ur5_arm, "rotation", 12, seed=9)
    for jit in (True, False):
        batch = solve_many(ur5_arm, targets, jit=jit, analytic=False)  # the descent batched
        single = [so.solve_ik(ur5_arm, t, method="lm", jit=jit, analytic=False)
                  for t in targets]  # the descent itself, as the batch above
        np.testing.assert_array_equal(batch.q, np.array([r.q for r in single]))
        assert batch.iterations.tolist() == [r.iterations for r in single]


def test_a_full_history_is_an_error_not_an_overrun(ur5_arm):
    """The C loop writes the history into a buffer of a given size; a start that needs more
    calls than it holds (here: room for one) stops with an error instead of writing past it.

    Mutations caught: the size check in ``call`` (lm_driver.c) dropped (no error); the
    status of ``lm_start`` ignored in ``Driver.start`` (no error).
    """
    driver = _driver_or_skip(ur5_arm, "rotation")
    t = _targets(ur5_arm, "rotation", 1, seed=10)[0]
    f = phase_arrays(ur5_arm, "rotation")
    q0 = 0.5 * (ur5_arm.lower + ur5_arm.upper)
    fill_params(f.par[0], t, q0, 0.0)
    f.box[0] = limits(ur5_arm)[0]
    driver.reset(residual_tol(t.weights, 1e-9), 100)
    driver.budget = 100
    driver._c.history_size = 1  # a target from q0 takes several calls
    with pytest.raises(RuntimeError, match="lm_start failed"):
        driver.start(q0)


def test_the_c_loop_compiles_with_the_package(tmp_path, monkeypatch):
    """lm_driver.c compiles with the kernels' flags (a syntax error would silently leave
    the Python loop running everywhere: this test says so instead)."""
    monkeypatch.setenv("SCARA_OPT_CACHE", str(tmp_path))
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("no C compiler")
    assert c_library(Path(lm_driver.__file__).with_name("lm_driver.c")) is not None
