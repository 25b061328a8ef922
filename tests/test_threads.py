"""Several threads give the serial answers: per-thread Pinocchio data and casadi/IPOPT objects."""

from __future__ import annotations

import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import scara_opt as so
from tests.conftest import random_q

#: small budgets: the point is many solves, not good ones
BUDGET = {"population": 20, "iterations": 3}


@pytest.fixture
def fast_switching():
    """Switch threads every 0.1 ms (the default is 5 ms), as the audit did, to expose races."""
    old = sys.getswitchinterval()
    sys.setswitchinterval(1e-4)
    yield
    sys.setswitchinterval(old)


def test_fk_from_four_threads_equals_serial(fast_switching):
    """100,000 Robot.fk calls from 4 threads equal the serial ones, bit for bit.

    Mutation caught: one Pinocchio Data shared by every thread (Robot.data not per thread):
    fk's two Pinocchio calls interleave and some poses come back wrong.
    """
    robot = so.load_robot("zavar2024")
    Q = random_q(robot, 100_000, seed=1)
    serial = [robot.fk(q) for q in Q]
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(robot.fk, Q, chunksize=64))
    assert all(np.array_equal(a, b) for a, b in zip(serial, threaded, strict=True))


@pytest.mark.parametrize("method", so.solvers())
def test_solve_ik_from_four_threads_equals_serial(fast_switching, method):
    """1,000 solves per method through a 4-thread pool, on a robot no thread has used yet
    (its casadi and IPOPT objects are built under the threads): the serial answers.

    Mutations caught: IPOPT's NLP cached per robot only (not per thread) -> a crash or
    wrong statuses; the fast solver's buffers shared between threads -> wrong q.
    """
    opts = BUDGET if "population" in so.get_solver(method).defaults else {}
    robot = so.load_robot("nguyen" if method == "analytic" else "zavar2024")
    fresh = so.load_robot(robot.name)
    P = robot.positions(random_q(robot, 1000, seed=2))
    P[::10, 2] -= 0.2  # every tenth target out of reach: the verdicts run under threads too
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(lambda p: so.solve_ik(fresh, p, method=method, **opts), P))
    serial = [so.solve_ik(robot, p, method=method, **opts) for p in P]
    for a, b in zip(serial, threaded, strict=True):
        assert (a.status, a.reason) == (b.status, b.reason)
        np.testing.assert_array_equal(a.q, b.q)


def test_compare_with_a_thread_pool_equals_serial(fast_switching):
    """compare(executor=ThreadPoolExecutor(4)) gives the serial table (times aside)."""
    robot = so.load_robot("zavar2024")
    args = dict(methods=["pso", "gha", "ipopt"], populations=[8], iterations=10,
                seeds=range(3), progress=False)
    targets = [[-0.23, 0.20, -0.07], [-0.23, 0.20, -0.20], [0.3, 0.1, -0.06]]
    with ThreadPoolExecutor(4) as pool:
        threaded = so.compare(robot, targets, executor=pool, **args)
    serial = so.compare(robot, targets, **args)
    same = [c for c in serial.columns if c not in ("time_s", "setup_s", "history")]
    assert threaded[same].equals(serial[same])
