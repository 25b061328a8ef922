"""Shared fixtures and the papers' closed-form forward kinematics (the independent reference)."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import scara_opt as so

# The Ctrl-C tests need SIGINT delivered. A shell that starts a job in the background (`cmd &`
# without job control, as some CI runners do) makes it ignore SIGINT, and Python keeps an
# ignored SIGINT ignored, in this process and in the child processes the tests start (an
# ignored signal stays ignored across exec). Python's own handler here makes the children's
# disposition the default again, and their Python installs its handler in turn.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).resolve().parent.parent
IN = 0.0254  # metres per inch
BUNDLED = ["fang", "inverted5", "nguyen", "peng2025", "zavar2024"]


def _rz(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def paper_fk(name: str, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tip position [m] and rotation of each bundled robot, typed in from its paper."""
    if name == "zavar2024":  # zavar2024 eq. 3/5: a1 = a2 = 0.2 m, z = -d3 - d4, d4 = 0.05 m
        t1, t2, d3, t4 = q
        p = [0.2 * np.cos(t1) + 0.2 * np.cos(t1 + t2), 0.2 * np.sin(t1) + 0.2 * np.sin(t1 + t2),
             -d3 - 0.05]
        return np.array(p), _rz(t1 + t2 + t4)
    if name == "fang":  # fang eq. 1: L1 = L2 = 200 mm, z = -d3 - d4 with d4 = 15 mm
        t1, t2, d3, t4 = q
        p = [0.2 * np.cos(t1) + 0.2 * np.cos(t1 + t2), 0.2 * np.sin(t1) + 0.2 * np.sin(t1 + t2),
             -d3 - 0.015]
        return np.array(p), _rz(t1 + t2 + t4)
    if name == "peng2025":  # peng2025 eq. 4.6 (mm): x = 120 + 220 c1 + 200 c12, z = z0 + 172
        z0, t1, t2, t3 = q
        p = [0.12 + 0.22 * np.cos(t1) + 0.2 * np.cos(t1 + t2),
             0.22 * np.sin(t1) + 0.2 * np.sin(t1 + t2), z0 + 0.172]
        return np.array(p), _rz(t1 + t2 + t3)
    if name == "nguyen":  # nguyen eq. 5/7: a2 = a3 = 300 mm, d5 = 80 mm
        d1, t2, t3, d4, t5 = q
        A = t2 + t3 + t5
        p = [0.3 * np.cos(t2) + 0.3 * np.cos(t2 + t3), -d4 - 0.08,
             d1 + 0.3 * np.sin(t2) + 0.3 * np.sin(t2 + t3)]
        R = np.array([[np.cos(A), -np.sin(A), 0.0], [0.0, 0.0, -1.0], [np.sin(A), np.cos(A), 0.0]])
        return np.array(p), R
    if name == "inverted5":  # inverted5 Sec. III: L2 = L3 = L4 = 7.87 in, z = -P1 - P5
        P1, t1, t2, t3, P5 = q
        L = 7.87 * IN
        p = [L + L * np.cos(t1 - np.pi) + L * np.cos(t1 + t2 - 2 * np.pi),
             L * np.sin(t1 - np.pi) + L * np.sin(t1 + t2 - 2 * np.pi), -P1 - P5]
        return np.array(p), _rz(t1 + t2 + t3 - 2 * np.pi)
    raise KeyError(name)


@pytest.fixture(scope="session")
def robots() -> dict[str, so.Robot]:
    return {name: so.load_robot(name) for name in BUNDLED}


@pytest.fixture(scope="session")
def arm6() -> so.Robot:
    return so.Robot.from_urdf(DATA / "arm6.urdf")


@pytest.fixture(scope="session")
def ur5_arm() -> so.Robot:
    """UR5 (CB3) 6R arm from its published standard DH table (tests/data/ur5_dh.toml)."""
    return so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")


@pytest.fixture(scope="session")
def panda_arm() -> so.Robot:
    """Franka Panda 7R arm from its published modified DH table, tip at the flange."""
    return so.Robot.from_urdf(DATA / "panda_dh.urdf", tip="tool")


def random_q(robot: so.Robot, n: int, seed: int = 0) -> np.ndarray:
    """``n`` configurations drawn uniformly within the joint limits, (n, nq)."""
    return np.random.default_rng(seed).uniform(robot.lower, robot.upper, (n, robot.nq))


def run_cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """``python -m scara_opt.cli ARGS`` in a new process, as a user's shell runs it.

    The note of a first call that compiles native code (``doc_blocks.MACHINE_NOTE``: the
    machine's state, not the command's output) is taken out of stderr, as for the docs'
    commands: on a fresh machine the process that compiles first prints it.
    """
    from tests.doc_blocks import MACHINE_NOTE

    out = subprocess.run([sys.executable, "-m", "scara_opt.cli", *args],
                         capture_output=True, text=True, timeout=timeout)
    out.stderr = MACHINE_NOTE.sub("", out.stderr)
    return out


def c_compiler():
    """The package's C compiler (:class:`scara_opt.model.compiled.Toolchain`), or ``None``."""
    from scara_opt.model import compiled

    found = compiled.toolchain()
    return found if isinstance(found, compiled.Toolchain) else None


def pinocchio_distances(checker, Q):
    """(n, npairs) signed distances [m] of the checker's pairs at each row of Q, by
    Pinocchio's own ``computeDistances`` on the checker's model, every GJK started afresh
    (Pinocchio's requests carry the last guess over by default): the dense checks'
    reference, independent of scara_opt's compiled kernel (collision/edge_kernel.cpp).
    """
    import warnings

    import pinocchio as pin

    model, gmodel = checker.robot.model, checker.model
    data, gdata = model.createData(), pin.GeometryData(gmodel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for req in gdata.distanceRequests:
            req.enable_cached_gjk_guess = False
    Q = np.atleast_2d(np.asarray(Q, float))
    out = np.empty((len(Q), len(gmodel.collisionPairs)))
    for i, q in enumerate(Q):
        pin.computeDistances(model, data, gmodel, gdata, q)
        out[i] = [r.min_distance for r in gdata.distanceResults]
    return out


def pinocchio_collides(checker, Q):
    """(n,) bool: each row of Q in contact (a signed distance <= 0), or closer than the
    checker's margin, by :func:`pinocchio_distances` (not ``computeCollisions``, whose
    boolean test can miss a deep overlap).
    """
    D = pinocchio_distances(checker, Q)
    if not D.shape[1]:
        return np.zeros(len(D), dtype=bool)
    return (D < checker.margin).any(axis=1) if checker.margin else (D <= 0).any(axis=1)


def dense_first_contact(checker, qa, qb, step=1e-3):
    """First fraction along qa->qb in collision by sampling every ``step`` of joint motion
    (rad or m): the independent check the collision proofs are tested against; None if clear.
    """
    n = int(np.ceil(np.abs(qb - qa).max() / step)) + 1
    s = np.linspace(0.0, 1.0, n)
    hit = pinocchio_collides(checker, qa + s[:, None] * (qb - qa))
    return float(s[np.argmax(hit)]) if hit.any() else None
