"""casadi FK built from the Pinocchio model agrees with Pinocchio to 1e-12."""

from __future__ import annotations

import numpy as np
import pytest

from tests.conftest import BUNDLED, random_q


@pytest.mark.parametrize("name", BUNDLED + ["arm6"])
def test_symbolic_fk_matches_pinocchio_on_1000_configurations(robots, arm6, name):
    """symbolic_fk.map(1000) gives the same position and rotation as Pinocchio's fk."""
    robot = arm6 if name == "arm6" else robots[name]
    n = 1000
    Q = random_q(robot, n, seed=5)
    P, R = robot.symbolic_fk.map(n)(Q.T)
    P = np.asarray(P).T
    R = np.asarray(R).reshape(3, n, 3).transpose(1, 0, 2)
    T = np.array([robot.fk(q) for q in Q])
    np.testing.assert_allclose(P, T[:, :3, 3], atol=1e-12, rtol=0)
    np.testing.assert_allclose(R, T[:, :3, :3], atol=1e-12, rtol=0)


def test_symbolic_fk_is_differentiable(robots):
    """The casadi expression's Jacobian equals Pinocchio's linear Jacobian."""
    import casadi as ca

    robot = robots["peng2025"]
    q = ca.SX.sym("q", robot.nq)
    jac = ca.Function("j", [q], [ca.jacobian(robot.symbolic_fk(q)[0], q)])
    for qv in random_q(robot, 10, seed=6):
        np.testing.assert_allclose(np.asarray(jac(qv)), robot.jacobian(qv)[:3], atol=1e-12)
