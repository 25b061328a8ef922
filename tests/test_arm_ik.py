"""Every IK solution of a 6R arm by its closed form (IK-Geo's subproblems), and 7R arms.

The referee is independent of the closed form: the robot's Pinocchio FK for every answer,
and a dense multi-start of the fast solver's descent (``lm_search``, ``nearest=False``,
hundreds of seeded uniform starts) for the set of solutions: every distinct solution it
finds (up to whole turns) must be among the closed form's, and away from singularities the
two sets must be equal.
"""

from __future__ import annotations

import re

import casadi as ca
import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik.arm_geometry import arm_model
from scara_opt.ik.lm_search import lm_search
from scara_opt.ik.subproblems import rot, sp1, sp2, sp3, sp4
from scara_opt.ik.verdict import residual
from scara_opt.model.catalogue import example_robot_data_urdf
from scara_opt.trajectory import branches as walk
from tests.conftest import DATA

TURN = 2 * np.pi


def wrapped(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| up to whole turns, per joint (every joint here is revolute)."""
    return np.abs((a - b + np.pi) % TURN - np.pi)


def distinct(Q) -> list[np.ndarray]:
    """The rows of Q that differ up to whole turns (by more than 1e-6 in some joint)."""
    out: list[np.ndarray] = []
    for q in Q:
        if all(wrapped(q, r).max() > 1e-6 for r in out):
            out.append(np.asarray(q))
    return out


def dense(robot: so.Robot, target: so.Target, n: int, seed: int) -> list[np.ndarray]:
    """The distinct solutions (up to turns) the descent reaches from n seeded starts."""
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(n):
        s = rng.uniform(robot.sampling_lower, robot.sampling_upper)
        f = lm_search(robot, target, s, [s], tol=1e-9, max_iter=100, nearest=False)
        if f.converged and residual(robot, target, f.q) <= 1e-9:
            found.append(f.q)
    return distinct(found)


def covered(found: list[np.ndarray], by: list[np.ndarray], atol: float = 1e-6) -> bool:
    """Every solution of ``found`` is one of ``by`` up to whole turns."""
    return all(any(wrapped(q, r).max() <= atol for r in by) for q in found)


def pose(robot: so.Robot, q: np.ndarray) -> so.Target:
    return so.Target(robot.fk(q))


@pytest.fixture(scope="module")
def ur5_erd() -> so.Robot:
    """The UR5 of example-robot-data (joint limits ±2π, the elbow ±π)."""
    try:
        path = example_robot_data_urdf("ur_description/urdf/ur5_robot.urdf")
    except ModuleNotFoundError:
        pytest.skip("needs example-robot-data: pip install 'scara-opt[robots]'")
    return so.Robot.from_urdf(path, tip="tool0")


# ------------------------------------------------------------------ the subproblems


def _numeric(*values):
    """Evaluate casadi SX scalars free of symbols to floats (n,)."""
    return np.array([float(ca.evalf(v)) for v in values])


def _matrix(value) -> np.ndarray:
    """Evaluate a casadi SX matrix free of symbols."""
    return np.array(ca.evalf(value), dtype=float)


def test_subproblems_solve_their_equations():
    """SP1–SP4 on random instances with exact solutions: each candidate satisfies its
    equation to 1e-12, and the two candidates of SP2/SP3/SP4 are the two solutions (the
    planted angle is one of them).

    Mutations caught: SP4's ``phi - half`` -> ``phi + half`` (one solution twice: the
    planted angle missed); SP1's cosine axis ``-k x (k x p)`` -> ``k x (k x p)`` (wrong
    angle); SP2's ``sp4(k2, p1, k1, ...)`` -> ``sp4(k2, p1, -k1, ...)``.
    """
    rng = np.random.default_rng(3)
    for _ in range(50):
        k, k2, p1, h = (v / np.linalg.norm(v) for v in rng.normal(size=(4, 3)))
        p1 = rng.normal(size=3)
        t, t2 = rng.uniform(-np.pi, np.pi, 2)
        Rt = _matrix(rot(k, t))
        R2 = _matrix(rot(k2, t2))
        p2 = Rt @ p1
        assert wrapped(_numeric(sp1(p1, p2, k)), np.array([t]))[0] < 1e-10
        thetas = _numeric(*sp4(h, p1, k, float(h @ p2)))
        assert min(wrapped(thetas, np.full(2, t))) < 1e-9
        for th in thetas:
            Rth = _matrix(rot(k, th))
            assert abs(h @ Rth @ p1 - h @ p2) < 1e-12
        c = rng.normal(size=3)
        for th in _numeric(*sp3(p1, c, k, float(np.linalg.norm(p2 - c)))):
            Rth = _matrix(rot(k, th))
            assert abs(np.linalg.norm(Rth @ p1 - c) - np.linalg.norm(p2 - c)) < 1e-12
        q2 = R2.T @ p2  # R(k, t) p1 = R(k2, t2) q2
        pairs = [_numeric(a, b) for a, b in sp2(p1, q2, k, k2)]
        assert min(wrapped(pr, np.array([t, t2])).max() for pr in pairs) < 1e-8
        for a, b in pairs:
            Ra = _matrix(rot(k, a))
            Rb = _matrix(rot(k2, b))
            assert np.abs(Ra @ p1 - Rb @ q2).max() < 1e-10


# ------------------------------------------------------------------ cases read from the model


def _wrist_offset(dx: float) -> so.Robot:
    """tests/data's UR5 with its last joint's origin moved ``dx`` [m] sideways (along x of
    the 5th joint's frame): the 5th and 6th axes then miss each other by ``dx``."""
    text = (DATA / "ur5_dh.urdf").read_text()
    m = re.search(r'<joint name="wrist_3".*?<origin xyz="([^"]+)"', text, re.S)
    assert m is not None, "the URDF's layout changed"
    x, y, z = (float(v) for v in m.group(1).split())
    moved = text.replace(m.group(0), m.group(0).replace(m.group(1), f"{x + dx} {y} {z}"))
    return so.Robot(moved, tip="tool", name=f"ur5_offset_{round(dx * 1e9)}nm")


def test_the_cases_of_the_published_arms(ur5_arm, panda_arm, arm6):
    """UR5: three parallel axes and two meeting; the Panda with its last joint held: a
    spherical wrist read backwards; arm6 (a prismatic joint) and a UR5 whose wrist axes
    miss by 5 cm (no case either way round): not served.

    Mutation caught: ``_meet``'s distance test dropped (lines that miss "meet") -> the
    offset UR5 read as a UR, fails.
    """
    assert arm_model(ur5_arm).label == "three_parallel_two_intersecting"
    m = arm_model(panda_arm)
    assert m.label == "spherical_two_intersecting, read backwards" and m.held == 6
    assert arm_model(arm6) is None
    assert arm_model(_wrist_offset(0.05)) is None


# ------------------------------------------------------------------ every branch


def test_every_branch_reaches_the_pose_and_the_sampled_q_is_one(ur5_arm):
    """On 60 random configurations of the UR5 (limits ±2π): every solution ik_all lists
    reaches the pose within 1e-9 by Pinocchio's FK, within the limits, all distinct; the
    configuration the pose came from is one of them (turns included); a solution's
    whole turns within the limits are listed too; at most 8 branches.

    Mutations caught: a dropped branch (``sp3(...)`` in ``_three_parallel`` iterated over
    its first root only) -> the sampled q missing on some pose, fails; a wrong sign of one
    subproblem (``sp4(h2, p16, h1, ...)`` for ``-h1``) -> no branch reaches (or q missing).
    """
    Q = np.random.default_rng(7).uniform(-np.pi, np.pi, (60, 6))
    for q in Q:
        t = pose(ur5_arm, q)
        sols = so.ik_all(ur5_arm, t)
        S = np.array([r.q for r in sols])
        assert all(r.success and r.error <= 1e-9 and r.route.startswith("analytic")
                   for r in sols)
        assert all(residual(ur5_arm, t, s) <= 1e-9 for s in S)
        assert ur5_arm.within_limits(S).all() if S.ndim == 2 else True
        assert np.abs(S - q).max(axis=1).min() < 1e-9, "the sampled configuration is missing"
        assert 1 <= len(distinct(S)) <= 8
        D = np.abs(S[:, None, :] - S[None, :, :]).max(axis=2) + np.eye(len(S))
        assert D.min() > 1e-6
        for s in S[:5]:
            for k in range(6):
                for m in (-1, 1):
                    o = s.copy()
                    o[k] += m * TURN
                    if ur5_arm.lower[k] <= o[k] <= ur5_arm.upper[k]:
                        assert np.abs(S - o).max(axis=1).min() < 1e-9


def test_the_branches_are_what_a_dense_multi_start_finds(ur5_arm):
    """Away from singularities (10 random poses of the UR5): the distinct solutions up to
    whole turns are exactly those 300 seeded descents find (up to 8).

    Mutation caught: a dropped branch (the second root of SP4 for q5 in
    ``_three_parallel`` replaced by the first) -> the multi-start finds a branch ik_all
    lacks, fails.
    """
    rng = np.random.default_rng(11)
    counts = []
    for i in range(10):
        q = rng.uniform(-np.pi, np.pi, 6)
        q[4] = rng.choice([-1, 1]) * rng.uniform(0.3, 2.8)  # away from the wrist singularity
        t = pose(ur5_arm, q)
        mine = distinct([r.q for r in so.ik_all(ur5_arm, t)])
        theirs = dense(ur5_arm, t, 300, seed=i)
        assert covered(theirs, mine) and covered(mine, theirs), (i, len(mine), len(theirs))
        counts.append(len(mine))
    assert max(counts) == 8


@pytest.mark.parametrize("kind", ["wrist", "elbow", "shoulder"])
def test_near_singularities_no_branch_is_lost(ur5_arm, kind):
    """Near the UR5's singularities (wrist q5 -> 0, elbow stretched q3 -> 0, the wrist
    centre near the base axis), 1e-3 to 1e-6 away: every solution a dense multi-start
    finds is among ik_all's, each of ik_all's within 1e-9; at the singularity itself
    (a continuum of solutions there), the closed form still answers within 1e-9.

    Mutation caught: ``DISTINCT`` (arm_route) 1e-6 -> 1e-4 (the elbow's two branches
    1e-5 from stretched told as one) -> a branch the multi-start finds is lost, fails.
    """
    rng = np.random.default_rng({"wrist": 1, "elbow": 2, "shoulder": 3}[kind])
    for i, eps in enumerate([1e-3, 1e-4, 1e-5, 1e-6, 0.0]):
        q = rng.uniform(-2.5, 2.5, 6)
        if kind == "wrist":
            q[4] = eps
        elif kind == "elbow":
            q[2] = eps
        else:  # the wrist centre on the base axis: solve for q2, q3 numerically
            q = _shoulder_singular(ur5_arm, q, eps)
        t = pose(ur5_arm, q)
        sols = so.ik_all(ur5_arm, t)
        assert sols and all(residual(ur5_arm, t, r.q) <= 1e-9 for r in sols)
        assert sols[0].route.startswith("analytic"), sols[0].route
        if eps == 0.0:
            continue
        mine = distinct([r.q for r in sols])
        assert covered([q], mine, 1e-5)
        theirs = dense(ur5_arm, t, 200, seed=i)
        assert covered(theirs, mine, 1e-5), (kind, eps, len(mine), len(theirs))


def _shoulder_singular(robot: so.Robot, q: np.ndarray, eps: float) -> np.ndarray:
    """``q`` with q2 moved so that the 5th joint's origin lies ``eps`` from the base z axis
    in the radial direction (a 1-D root by bisection)."""
    def radial(a: float) -> float:
        qq = q.copy()
        qq[1] = a
        o = robot.joint_origins(qq[None])[0, 4]
        return float(np.hypot(o[0], o[1]))

    grid = np.linspace(-np.pi, np.pi, 721)
    k = int(np.argmin([radial(a) for a in grid]))
    out = q.copy()
    out[1] = grid[k]
    return out if radial(grid[k]) > eps else q


def test_at_joint_limits_no_branch_is_lost(ur5_arm):
    """Limits tightened to ±1.2 rad (the elbow ±2.5): poses of configurations with joints
    at or 1e-9 inside a limit keep every branch a dense multi-start finds within them, and
    none outside.

    Mutation caught: the fit test in ``_turned`` made strict (``first <= last`` ->
    ``first < last``: a joint where exactly one turn fits counts as not fitting) -> the
    branches are lost (the multi-start's net answers instead: its route), fails.
    """
    tight = ur5_arm.with_limits(**{n: (-1.2, 1.2) for n in ur5_arm.joint_names[:2]},
                                **{ur5_arm.joint_names[2]: (-2.5, 2.5)},
                                **{n: (-1.2, 1.2) for n in ur5_arm.joint_names[3:]})
    rng = np.random.default_rng(4)
    for i in range(12):
        q = rng.uniform(tight.lower, tight.upper)
        k = i % 6
        q[k] = (tight.upper if i % 2 else tight.lower)[k] - (1e-9 if i % 4 < 2 else 0.0) * (
            1 if i % 2 else -1)
        t = pose(tight, q)
        sols = so.ik_all(tight, t)
        S = [r.q for r in sols]
        assert sols[0].route.startswith("analytic"), sols[0].route
        assert all(tight.within_limits(s) for s in S)
        assert covered([q], S, 1e-7)
        theirs = dense(tight, t, 200, seed=i)
        assert covered([x for x in theirs if tight.within_limits(x)], S, 1e-6)


def test_the_turns_of_a_published_ur5(ur5_erd):
    """example-robot-data's UR5 (±2π, elbow ±π): each branch comes with every whole turn
    of the five ±2π joints within the limits (up to 8 × 2⁵ = 256 solutions), and the
    distinct branches are the dense multi-start's.

    Mutation caught: ``every_turn`` listing the nearest turn only -> fewer solutions than
    the turns' product, fails.
    """
    rng = np.random.default_rng(21)
    for i in range(4):
        q = rng.uniform(-1.5, 1.5, 6)
        t = pose(ur5_erd, q)
        S = [r.q for r in so.ik_all(ur5_erd, t)]
        reps = distinct(S)
        expected = 0
        for r in reps:
            n = 1
            for k in range(6):
                lo, hi = ur5_erd.lower[k], ur5_erd.upper[k]
                base = r[k] - TURN * np.floor((r[k] - lo) / TURN)
                n *= int(np.floor((hi - base) / TURN)) + 1
            expected += n
        assert len(S) == expected and len(S) <= 256
        assert covered(dense(ur5_erd, t, 200, seed=i), reps)


# ------------------------------------------------------------------ routes and 7R arms


def test_the_route_is_named(ur5_arm, panda_arm, arm6):
    """Results say their route: the closed form's case, the 7R's sampled joint and its
    sampling, or the multi-start where no closed form serves.

    Mutation caught: ``route=route`` dropped from ``ik_all``'s SolverOutput -> empty
    route, fails.
    """
    q = np.array([0.3, -0.6, 0.9, -0.5, 0.7, 0.2])
    assert so.ik_all(ur5_arm, pose(ur5_arm, q))[0].route == \
        "analytic (three_parallel_two_intersecting)"
    assert so.solve_ik(ur5_arm, pose(ur5_arm, q)).route == \
        "analytic (three_parallel_two_intersecting)"
    qp = np.array([0.3, -0.6, 0.4, -1.9, 0.5, 1.6, 0.3])
    r = so.ik_all(panda_arm, pose(panda_arm, qp), samples=16)[0]
    assert "sampled at 16 values evenly over [-2.897, 2.897] rad" in r.route
    assert so.solve_ik(arm6, pose(arm6, np.zeros(6) + 0.2)).route == ""
    assert so.ik_all(arm6, pose(arm6, np.zeros(6) + 0.2))[0].route.startswith("multi-start")


def test_panda_solutions_over_the_held_joint(panda_arm):
    """The Panda (6 configurations in the middle half of its limits): every solution
    within 1e-9 and the limits; with ``fixed`` the 7th joint keeps that value and the
    sampled configuration is among the solutions; without, the 7th joint of each solution
    is one of the 12 samples, and solutions are found at 12 or more (pose, sample) pairs
    (measured 17: a pose reaches its orientation over a band of the 7th joint, some 0.9
    to 2.7 rad wide here).

    Mutation caught: the held joint's transform applied on the wrong side
    (``RG @ E`` -> ``E @ RG`` for the last joint) -> no branch within tol, fails.
    """
    rng = np.random.default_rng(8)
    mid, half = (panda_arm.lower + panda_arm.upper) / 2, (panda_arm.upper - panda_arm.lower) / 4
    grid = np.linspace(panda_arm.lower[6], panda_arm.upper[6], 12)
    pairs = 0
    for _ in range(6):
        q = rng.uniform(mid - half, mid + half)
        t = pose(panda_arm, q)
        held = so.ik_all(panda_arm, t, fixed={"panda_joint7": float(q[6])})
        assert held and all(r.q[6] == q[6] and r.error <= 1e-9 for r in held)
        assert min(np.abs(r.q - q).max() for r in held) < 1e-8
        sampled = so.ik_all(panda_arm, t, samples=12)
        assert all(r.error <= 1e-9 and panda_arm.within_limits(r.q) for r in sampled)
        assert all(np.abs(grid - r.q[6]).min() < 1e-12 for r in sampled)
        pairs += len({round(float(r.q[6]), 9) for r in sampled})
    assert pairs >= 12


def test_solve_ik_returns_the_nearest_of_every_solution(ur5_arm, panda_arm):
    """``lm`` and ``auto`` on the UR5: the solution nearest ``q0`` of all ik_all lists; on
    the Panda with ``nearest=False`` the 7th joint stays at ``q0``'s value unless the route
    says it moved (no branch there), and the default's slide along the branch ends no
    farther from ``q0`` (range-scaled) than that start; every answer within 1e-9.

    Mutations caught: the compiled choice keeping the farthest branch (``d < score`` ->
    ``d > score``) -> not the nearest, fails; the slide keeping steps that move away
    (``f_new < f`` -> ``f_new > f`` in ``build_slide``) -> farther, fails.
    """
    rng = np.random.default_rng(9)
    slides = 0
    for _ in range(20):
        q, q0 = rng.uniform(-np.pi, np.pi, (2, 6))
        t = pose(ur5_arm, q)
        best = min(so.ik_all(ur5_arm, t), key=lambda r: np.linalg.norm(r.q - q0))
        for method in ("lm", "auto"):
            res = so.solve_ik(ur5_arm, t, method=method, q0=q0)
            assert res.success and res.error <= 1e-9
            assert np.linalg.norm(res.q - q0) <= np.linalg.norm(best.q - q0) + 1e-9
        qp, qp0 = rng.uniform(panda_arm.lower, panda_arm.upper, (2, 7))
        res = so.solve_ik(panda_arm, pose(panda_arm, qp), method="lm", q0=qp0, nearest=False)
        assert res.success
        assert res.q[6] == qp0[6] or "moved from q0's value" in res.route or res.route == ""
        slid = so.solve_ik(panda_arm, pose(panda_arm, qp), method="lm", q0=qp0)
        assert slid.success and slid.error <= 1e-9
        if "slid along its branch" in slid.route:  # never farther than where it started
            span = panda_arm.upper - panda_arm.lower
            assert np.linalg.norm((slid.q - qp0) / span) <= np.linalg.norm(
                (res.q - qp0) / span) + 1e-12
            slides += 1
        res = so.solve_ik(panda_arm, pose(panda_arm, qp), q0=qp0)
        assert res.success and res.error <= 1e-9
    assert slides >= 10


def test_a_geometry_a_hair_off_is_polished(ur5_arm):
    """A UR5 whose 5th and 6th axes miss each other by 3e-8 m (within the case's 1e-7):
    the closed form is 1e-8 off, the fast solver's polish takes every branch to 1e-9, and
    they are still every branch the multi-start finds.

    Mutation caught: the polish skipped in ``all_solutions`` (``q = Q[k]`` always) ->
    residuals above tol, fails.
    """
    bent = _wrist_offset(3e-8)
    assert arm_model(bent) is not None
    q = np.array([0.4, -0.7, 1.1, -0.3, 0.8, 0.5])
    t = pose(bent, q)
    sols = so.ik_all(bent, t)
    assert sols and all(r.error <= 1e-9 for r in sols)
    assert covered(dense(bent, t, 200, seed=1), distinct([r.q for r in sols]))


# ------------------------------------------------------------------ ik_path


def test_ik_path_never_travels_more_than_a_sampled_sequence(ur5_arm):
    """On 20 random sequences of 5 poses (configurations in [-1.5, 1.5]^6, q_start the
    first): by default (``objective="travel"``) its weighted travel is never more than
    the sampled configurations' own sequence, one valid IK sequence; with
    ``objective="fewest_jumps"``, (jumps, weighted travel) is never worse (fewest jumps
    first, then travel).

    Mutations caught: the state before (``candidates_arm`` returning None and ``auto``'s
    ``analytic`` default False: the descent's multi-start) -> 9.86 s of weighted travel
    against the sampled sequence's 9.07 on one, fails; the default objective back to
    the fewest jumps first (issue 40's default before) -> more travel on some, fails.
    """
    w = walk.travel_weights(ur5_arm)
    thr = np.full(6, np.pi / 2)

    def cost(Qp, q_start):
        D = np.abs(np.diff(np.vstack([q_start, Qp]), axis=0))
        return int((D[1:] > thr).any(axis=1).sum()), float((D @ w).sum())

    for s in range(20):
        Q = np.random.default_rng(s).uniform(-1.5, 1.5, (5, 6))
        targets = [pose(ur5_arm, q) for q in Q]
        path = so.ik_path(ur5_arm, targets, q_start=Q[0], objective="fewest_jumps")
        assert path.solved.all() and path.branches == "global"
        mine, theirs = cost(path.q, Q[0]), cost(Q, Q[0])
        assert mine[0] < theirs[0] or (mine[0] == theirs[0] and mine[1] <= theirs[1] + 1e-9)
        least = so.ik_path(ur5_arm, targets, q_start=Q[0])
        assert least.solved.all() and cost(least.q, Q[0])[1] <= theirs[1] + 1e-9


def test_the_layered_walk_equals_dijkstra():
    """The layer-by-layer walk (large candidate sets) finds walks of the same jumps and
    travel as SciPy's Dijkstra over the whole graph, on 30 random candidate sets.

    Mutation caught: the jump count left out of the layered comparison (``Jc.min`` over
    travel only) -> more jumps than Dijkstra's on some, fails.
    """
    rng = np.random.default_rng(0)
    for _ in range(30):
        n, K, nq = rng.integers(2, 7), rng.integers(1, 9), 3
        Q = rng.uniform(-3, 3, (n, K, nq))
        valid = rng.random((n, K)) < 0.8
        valid[:, 0] = True
        thr, w = np.full(nq, 1.5), rng.uniform(0.5, 2, nq)
        q_start = rng.uniform(-3, 3, nq) if rng.random() < 0.5 else None
        fewest = bool(rng.random() < 0.5)
        a = walk.least_cost_walk(Q, valid, thr, w, q_start, fewest)
        t0, o0 = ((np.zeros(K), np.zeros(K, bool)) if q_start is None else
                  (np.abs(Q[0] - q_start) @ w, (np.abs(Q[0] - q_start) > thr).any(axis=1)))
        b = walk._layered_walk(Q, valid, thr, w, t0, o0, fewest)
        if fewest:
            assert (len(a.jumps), a.start_jump) == (len(b.jumps), b.start_jump)
        assert abs(a.travel - b.travel) <= 1e-9
        assert a.forced_by == b.forced_by or a.jumps != b.jumps


def test_a_pose_at_two_singularities_and_the_limits_is_solved(ur5_arm):
    """A UR5 pose with three joints at +2π (their limit), the wrist 6e-7 rad and the elbow
    1e-4 rad from singular: the closed form's round-off there is 0.008-0.03, its branches
    are polished to 1e-9; ``solve_ik`` and ``ik_all`` both reach it.

    Mutation caught: the polish gate back at 1e-6 (``POLISH``) -> ik_all's closed form
    finds none (the multi-start's safety net then answers: the route says so), fails.
    """
    q = np.array([0.573557052, TURN, TURN - 1.1933e-4, 6.20198943, TURN - 1e-8, -6.28325e-7])
    t = pose(ur5_arm, q)
    sols = so.ik_all(ur5_arm, t)
    assert sols and all(r.error <= 1e-9 for r in sols)
    assert sols[0].route == "analytic (three_parallel_two_intersecting)"
    res = so.solve_ik(ur5_arm, t, q0=np.zeros(6))
    assert res.success and res.route.startswith("analytic")
