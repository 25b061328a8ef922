"""Certificates sound to the last digit, and ``auto`` complete where IPOPT is.

A target within ``tol`` of what some in-limit configuration reaches must never be called
``unreachable``: these tests build such targets where proofs break (joint limits, the arm
stretched or folded, tol from 1e-12 to 1e-3) and try every certificate and every method.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import least_squares

import scara_opt as so
from scara_opt.ik.auto import AutoSolver
from scara_opt.ik.certificates import certify
from scara_opt.ik.geometry import NotScaraError, scara_geometry
from scara_opt.ik.ipopt import IpoptSolver
from scara_opt.ik.verdict import residual
from tests.conftest import BUNDLED, DATA

ROBOTS = [*BUNDLED, "irb910sc_like", "ur5_dh", "panda_dh"]
TOLS = (1e-12, 1e-9, 1e-6, 1e-3)


def load(name: str) -> so.Robot:
    """A bundled robot, or a test robot of tests/data (a DH table)."""
    return so.load_robot(DATA / f"{name}.toml" if name not in BUNDLED else name)


def edge_configurations(robot: so.Robot, n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, nq) configurations within the limits, most joints at a limit or a singular value.

    Each joint, with probability 0.6, takes a limit, 0, ±π/2 or ±π (for a SCARA's elbow:
    the arm stretched or folded), moved inward by 0 to 1e-3; else a uniform value.
    """
    lo, hi = robot.sampling_lower, robot.sampling_upper
    try:
        geom = scara_geometry(robot)
    except NotScaraError:
        geom = None
    special = []
    for k, j in enumerate(robot.chain):
        v = [lo[k], hi[k]]
        if j.kind == "revolute":
            v += [0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi]
            if geom is not None and k == geom.elbow:  # γ = 0 or ±π
                v += [geom.s[k] * (g - (geom.phi2 - geom.phi1)) for g in (0, math.pi, -math.pi)]
        special.append([x for x in v if lo[k] <= x <= hi[k]])
    Q = rng.uniform(lo, hi, (n, robot.nq))
    for k in range(robot.nq):
        pick = rng.random(n) < 0.6
        x = np.array(special[k])[rng.integers(len(special[k]), size=n)]
        d = rng.choice([0.0, 1e-12, 1e-9, 1e-6, 1e-3], size=n) * rng.random(n)
        x = np.where(x - lo[k] < hi[k] - x, x + d, x - d)  # inward
        Q[pick, k] = np.clip(x, lo[k], hi[k])[pick]
    return Q


def near_targets(robot: so.Robot, q: np.ndarray, tol: float, rng: np.random.Generator,
                 tilt: bool = True) -> list[so.Target]:
    """Targets 0.99 tol from what ``q`` reaches: position, with yaw, full pose.

    The position moves by 0.99 tol, half the time straight away from (or toward) the
    first joint's axis, the way the arm cannot follow at full stretch; the yaw by ±0.99
    tol; the rotation by 0.99 tol about a random axis (``tilt=False``: about the yaw axis).
    """
    T = robot.fk(q)
    p = T[:3, 3]
    u = rng.normal(size=3)
    n = robot.yaw_axis
    if n is not None and rng.random() < 0.5:
        r = p - robot.model.jointPlacements[1].translation
        r -= (r @ n) * n
        u = r * rng.choice([-1.0, 1.0])
    u /= np.linalg.norm(u)
    p = p + 0.99 * tol * u
    out = [so.Target(p)]
    if n is not None:
        out.append(so.Target(p, yaw=robot.yaw(q) + 0.99 * tol * rng.choice([-1.0, 1.0])))
    axis = rng.normal(size=3) if tilt or n is None else n.copy()
    M = np.eye(4)
    M[:3, :3] = T[:3, :3] @ pin.exp3(0.99 * tol * axis / np.linalg.norm(axis))
    M[:3, 3] = p
    out.append(so.Target(M))
    return out


@pytest.mark.parametrize("name", ROBOTS)
def test_no_certificate_within_tol_of_a_reachable_target(name):
    """2,000-3,000 targets per robot, each within 0.99 tol of an in-limit configuration at
    limits and singular poses, tol 1e-12 to 1e-3: no certificate at all.

    Before: 197 of these 22,000 targets were "proved" unreachable by the old "no branch
    within the widened limits" argument (inverted5 102, peng2025 38, zavar2024 23, fang 16,
    irb910sc_like 14, nguyen 4); after: 0 (runs of this construction at the fix).
    Mutations caught: the old argument (the closed form with the limits widened by
    2 tol / min(l1, l2, 1 m) rad: fails on all six SCARAs); the singular arcs (γ = kπ) left
    out; the tool-angle band not widened by tol; the reach test of a rail's segment at its
    first end only; the segment-arc crossing test left out; the closed-form membership test
    of the segment's end left out; the round-off margin added instead of taken off; the
    folded arm's arc given the radius l1 + l2.
    """
    robot = load(name)
    rng = np.random.default_rng(29)
    checked = 0
    for tol in TOLS:
        for q in edge_configurations(robot, 250, rng):
            for t in near_targets(robot, q, tol, rng):
                assert residual(robot, t, q) <= tol  # q is the witness
                cert = certify(robot, t, tol)
                assert cert is None, (tol, q.tolist(), t, cert)
                checked += 1
    assert checked >= 2000


@pytest.mark.parametrize("name", ROBOTS)
def test_no_certificate_at_the_smallest_tols(name):
    """Targets within 0.99 tol of edge configurations at tol 1e-15 to 1e-13 (the API takes
    any tol > 0): no certificate, the round-off of the FK the solvers are judged by included
    (nguyen, d4 at its upper limit, a target 8.9e-16 m from FK(q) was "1.041e-15 m" out of
    the height range at tol 1e-15).

    Mutation caught: the height certificate without its round-off margin (``dz > tol``, as
    before) -> nguyen certified; fails.
    """
    robot = load(name)
    rng = np.random.default_rng(31)
    for tol in (1e-15, 1e-14, 1e-13):
        for q in edge_configurations(robot, 400, rng):
            for t in near_targets(robot, q, tol, rng):
                if residual(robot, t, q) > tol:  # round-off in the test's own construction
                    continue
                cert = certify(robot, t, tol)
                assert cert is None, (tol, q.tolist(), t, cert)


METHOD_OPTIONS = {"ipopt": {"restarts": 3}, "lm": {"restarts": 3},
                  "auto": {"restarts": 3, "ipopt_restarts": 3},
                  "sfla": {"population": 20, "iterations": 3, "memeplexes": 2},
                  "analytic": {}}
META = {"population": 10, "iterations": 3}


@pytest.mark.parametrize("name", ROBOTS)
def test_no_method_calls_a_target_within_tol_unreachable(name):
    """Every registered method, on targets within 0.99 tol of edge configurations (tol 1e-12
    to 1e-3; position, yaw, full pose): never ``unreachable``.

    Every status comes from the one verdict, so the certificates' soundness above carries
    over; this runs the methods themselves (small budgets: misses are expected, and judged
    ``max_iter`` or ``failed``). Full poses turn about the yaw axis here (their tilted kind
    is in the test above), so that the witness searches stay short.
    Mutation caught: a verdict that answers ``unreachable`` where the closed form finds no
    exact witness, without a certificate (the metaheuristics' misses on the arms, and edge
    targets of the SCARAs, are then called unreachable).
    """
    robot = load(name)
    rng = np.random.default_rng(30)
    methods = so.solvers()
    statuses = set()
    for tol in TOLS:
        for q in edge_configurations(robot, 2, rng):
            for t in near_targets(robot, q, tol, rng, tilt=False):
                for method in methods:
                    if method == "analytic" and (t.kind == "rotation" or robot.nq > 5):
                        continue  # the closed form takes SCARA position and yaw targets
                    res = so.solve_ik(robot, t, method=method, tol=tol, seed=1,
                                      **METHOD_OPTIONS.get(method, META))
                    assert res.status != "unreachable", (method, tol, q.tolist(), res)
                    statuses.add(res.status.value)
    assert "solved" in statuses


def test_zavar2024_reproducer_is_solved_not_proved_unreachable():
    """The issue's reproducer: q = [2π/3, 3e-8, 0.048, −2π/3] reaches the target at
    9.99e-10 < tol 1e-9.

    Before: ``analytic`` and ``ipopt`` answered ``unreachable`` ("widened by 1e-08 rad").
    Now ``lm`` and ``auto`` solve it and no method claims a proof.
    Mutation caught: the old widened "no branch" argument.
    """
    robot = so.load_robot("zavar2024")
    q = np.array([2 * math.pi / 3, 3e-8, 0.048, -2 * math.pi / 3])
    t = so.Target([-0.20000000569565232, 0.3464101593789348, -0.098])
    assert residual(robot, t, q) <= 1e-9
    assert certify(robot, t, 1e-9) is None
    for method in ("analytic", "ipopt", "lm", "auto"):
        res = so.solve_ik(robot, t, method=method)
        assert res.status != "unreachable", res
        if method in ("lm", "auto"):
            assert res.success, res


def _closest(robot: so.Robot, p: np.ndarray, near: np.ndarray,
             rng: np.random.Generator) -> float:
    """The least |FK(q) − p| over the limits, by a search independent of the certificates.

    3,000 uniform and edge samples of the joints; the best of the 3 best of 3 × 3 cells of
    the first two revolute joints' ranges (a target near two branches of the arm), and
    ``near``, polished by scipy's bounded least squares on the robot's FK and Jacobian.
    """
    lo, hi = robot.sampling_lower, robot.sampling_upper
    Q = np.vstack([rng.uniform(lo, hi, (2000, robot.nq)), edge_configurations(robot, 1000, rng)])
    d = np.linalg.norm(robot.positions(Q) - p, axis=1)
    arm = [k for k, j in enumerate(robot.chain) if j.kind == "revolute"][:2]
    cell = sum(3 ** i * np.minimum((3 * (Q[:, k] - lo[k]) / (hi[k] - lo[k])).astype(int), 2)
               for i, k in enumerate(arm))
    bests = sorted((float(d[cell == c].min()), int(np.flatnonzero(cell == c)[np.argmin(
        d[cell == c])])) for c in np.unique(cell))
    starts = [np.clip(near, lo, hi)] + [Q[i] for _, i in bests[:3]]
    best = float(d.min())
    for q in starts:
        sol = least_squares(lambda x: robot.position(x) - p, q, bounds=(lo, hi),
                            jac=lambda x: robot.jacobian(x)[:3], method="trf",
                            xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
        best = min(best, float(np.linalg.norm(robot.position(np.clip(sol.x, lo, hi)) - p)))
    return best


def test_certified_bound_is_the_distance_to_the_workspace():
    """Position targets where a rail, shoulder or elbow is pushed 1e-6 to 0.1 past its limit
    from an edge configuration, on every SCARA: the certificate's bound never exceeds the
    distance an independent search reaches (FK samples polished by scipy), and where the
    joint limits decide (``no_branch_within_limits``) it equals that distance to 1e-9 m:
    the proof is exact, not a safety margin.

    Mutation caught: the singular arcs left out (a bound above the search's distance).
    """
    rng = np.random.default_rng(31)
    exact = {}
    for name in [*BUNDLED, "irb910sc_like"]:
        robot = load(name)
        geom = scara_geometry(robot)
        pushed = [*geom.rails, geom.shoulder, geom.elbow]
        exact[name] = 0
        for q in edge_configurations(robot, 20, rng):
            k = pushed[rng.integers(len(pushed))]
            out = q.copy()
            push = 10 ** rng.uniform(-6, -1)
            out[k] = robot.upper[k] + push if rng.random() < 0.5 else robot.lower[k] - push
            t = so.Target(robot.fk_batch(out[None])[0, :3, 3])
            cert = certify(robot, t, 1e-9)
            if cert is None:
                continue
            ref = _closest(robot, t.position, out, rng)
            assert cert.bound <= ref + 1e-12, (name, q.tolist(), cert, ref)
            if cert.reason == "no_branch_within_limits":
                assert cert.bound >= ref - 1e-9, (name, q.tolist(), cert, ref)
                exact[name] += 1
    assert sum(exact.values()) >= 10, exact


# ------------------------------------------------------------------ auto, complete
def test_lm_never_takes_a_half_turn_for_a_solution():
    """inverted5, the full pose of q = [0, 0, 0, π, 0.0735] (the wrist at its limit, half a
    turn from q0's), seed 254772818, tol 1e-6: ``lm`` and ``auto`` solve it.

    Before: the rotation residual read 0 at a half turn (its small-angle series taken at
    θ = π), so LM stopped "converged" at the default start with an error of 3.14 rad, and
    ``auto`` never reached IPOPT, which solves it. Mutation caught: the series branch
    taken for every |sin θ| below 1e-6 (the old rule) -> failed, error 3.14.
    """
    robot = so.load_robot("inverted5")
    t = so.Target(robot.fk(np.array([0.0, 0.0, 0.0, math.pi, 0.0735])))
    for method in ("lm", "auto", "ipopt"):
        res = so.solve_ik(robot, t, method=method, seed=254772818, tol=1e-6)
        assert res.success, (method, res)


def test_rotation_residual_norm_is_the_angle_up_to_a_half_turn():
    """‖θu‖ of the LM residual equals the rotation angle, from 0 to π, exact half turns too.

    Mutations caught: the small-angle series at θ = π (the residual vanishes: 0 for 3.14);
    no fallback for an exactly symmetric half turn (``v`` = 0: the residual is 0).
    """
    import casadi as ca

    from scara_opt.ik.problem import rotation_vector

    R = ca.SX.sym("R", 3, 3)
    f = ca.Function("f", [R], [rotation_vector(R)])
    rng = np.random.default_rng(0)
    for theta in (0.0, 1e-9, 1e-3, 1.0, 3.0, math.pi - 1e-7, math.pi - 1e-12, math.pi):
        for _ in range(50):
            u = rng.normal(size=3)
            v = np.asarray(f(pin.exp3(theta * u / np.linalg.norm(u)))).ravel()
            assert abs(np.linalg.norm(v) - theta) <= 1e-9 * max(theta, 1e-6), theta
    for d in ([1.0, -1, -1], [-1.0, 1, -1], [-1.0, -1, 1]):
        assert np.linalg.norm(np.asarray(f(np.diag(d))).ravel()) == pytest.approx(math.pi)


def _fallback_cases(robot: so.Robot) -> list[tuple[so.Target, np.ndarray, int]]:
    """UR5 full poses at edge configurations from far starts where 4 LM starts miss."""
    rng = np.random.default_rng(3)
    cases = []
    for i in range(30):
        q = edge_configurations(robot, 1, rng)[0]
        q0 = rng.uniform(robot.sampling_lower, robot.sampling_upper)
        cases.append((so.Target(robot.fk(q)), q0, i))
    return cases


def test_auto_falls_back_to_the_ipopt_methods_own_run(ur5_arm):
    """Where the fast solver misses, ``auto`` returns what ``method="ipopt"`` returns for
    the same seed and q0, bit for bit (its answer was closer), and solves what it solves.

    Mutations caught: the fallback removed (failed where ipopt solves); the fallback's
    starts drawn from the generator the fast solver had used (another q); the closer
    answer chosen the other way round.
    """
    fell_back = 0
    for t, q0, seed in _fallback_cases(ur5_arm):
        # the descent's fallback itself (the arm's closed form, tried first, would solve them)
        res = so.solve_ik(ur5_arm, t, method="auto", q0=q0, seed=seed, restarts=3,
                          analytic=False)
        if "fast solver missed" not in res.message:
            continue
        fell_back += 1
        ref = so.solve_ik(ur5_arm, t, method="ipopt", q0=q0, seed=seed)
        assert np.array_equal(res.q, ref.q), (seed, res, ref)
        assert res.success or not ref.success
    assert fell_back >= 3


def test_auto_takes_ipopts_restarts():
    """``auto``'s IPOPT stage starts as often as the ``ipopt`` method does by default.

    Mutation caught: the old default of 20 restarts (fewer starts than ``ipopt``: a target
    ``ipopt`` reaches at its 30th start would be missed).
    """
    assert AutoSolver.defaults["ipopt_restarts"] == IpoptSolver.defaults["restarts"]


def test_auto_reports_the_fallbacks_setup(ur5_arm, monkeypatch):
    """The IPOPT stage's one-off build is ``setup_s``, apart from ``time_s``.

    Mutation caught: the fallback's setup dropped (``setup_s`` without it).
    """
    monkeypatch.setattr(IpoptSolver, "timed_prepare", lambda self, robot, kind: 7.0)
    for t, q0, seed in _fallback_cases(ur5_arm):
        # the descent's fallback itself (the arm's closed form, tried first, would solve them)
        res = so.solve_ik(ur5_arm, t, method="auto", q0=q0, seed=seed, restarts=3,
                          analytic=False)
        if "fast solver missed" in res.message:
            assert res.setup_s >= 7.0 and res.time_s < 7.0
            return
    pytest.fail("no case reached the fallback")


def test_compare_reports_setup_apart(monkeypatch):
    """``compare``'s table carries each solve's setup in ``setup_s``, never in ``time_s``.

    Mutation caught: ``setup_s`` written as 0 in the table's rows.
    """
    monkeypatch.setattr(IpoptSolver, "timed_prepare", lambda self, robot, kind: 5.0)
    robot = so.load_robot("zavar2024")
    table = so.compare(robot, [so.Target([0.25, 0.1, -0.07])], methods=["ipopt"],
                       reference=False, progress=False)
    assert (table["setup_s"] == 5.0).all() and (table["time_s"] < 5.0).all()
