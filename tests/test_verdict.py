"""Every status is a claim with its evidence: certificates, witnesses and invariants."""

from __future__ import annotations

import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik.base import TOL_FLOOR
from scara_opt.ik.certificates import certify, reach_bound
from scara_opt.ik.closed_form import solve_all
from scara_opt.ik.task import default_q0
from tests.conftest import BUNDLED, random_q

FOUR_JOINT = ["fang", "peng2025", "zavar2024"]


def fk_targets(robot: so.Robot, n: int, seed: int) -> list[so.Target]:
    """FK of ``n`` random in-limit configurations: reachable by construction.

    Even entries carry the tool angle, odd ones are position-only.
    """
    out = []
    for k, q in enumerate(random_q(robot, n, seed)):
        T = robot.fk(q)
        out.append(so.Target(T[:3, 3], yaw=robot.yaw(q)) if k % 2 == 0 else so.Target(T[:3, 3]))
    return out


# ------------------------------------------------------------------ the random invariants
@pytest.mark.parametrize("method", ["lm", "auto", "analytic"])
@pytest.mark.parametrize("name", BUNDLED)
def test_random_invariants_on_5000_reachable_targets(robots, name, method):
    """5,000 FK targets per fast exact method and bundled robot: never "unreachable", never
    "solved" above tol, q always within the limits, the same verdict when asked twice.

    Mutations caught: the closed form holding a redundant joint at q0's value (25/40 of
    nguyen's targets "unreachable" before); a verdict that says "unreachable" whenever the
    solver misses (lm's misses); a verdict that depends on a global random state (the
    repeated call differs).
    """
    robot = robots[name]
    targets = fk_targets(robot, 5000, seed=11)
    for k, t in enumerate(targets):
        res = so.solve_ik(robot, t, method=method)
        assert res.status != "unreachable", (k, res)
        assert res.success == (res.status == "solved") and (not res.success or res.error <= 1e-9)
        assert robot.within_limits(res.q)
        if method == "analytic":  # the closed form itself, not its IPOPT fallback, reached it
            assert res.success and "no closed-form branch" not in res.message, (k, res)
        if k % 50 == 0:
            again = so.solve_ik(robot, t, method=method)
            assert (again.status, again.reason) == (res.status, res.reason)
            np.testing.assert_array_equal(again.q, res.q)


# ------------------------------------------------------------------ the closed form's range
@pytest.mark.parametrize("name", ["nguyen", "inverted5"])
def test_closed_form_solves_redundant_robots_over_the_whole_range(robots, name):
    """The closed form of a redundant robot finds every FK target, whatever q0 holds.

    Before, the rail (nguyen) or the first stroke (inverted5) stayed at q0's value and 25/40
    (17/40) such targets came back "unreachable". Mutation caught: ``solve_all`` without
    the search over the redundant joint's range (held values only) -> misses.
    """
    robot = robots[name]
    for q0 in (None, robot.lower, robot.upper):
        for t in fk_targets(robot, 200, seed=3):
            res = so.solve_ik(robot, t, method="analytic", q0=q0)
            assert res.success, (q0, t, res)


def test_closed_form_keeps_the_hold_when_it_works_and_moves_least_otherwise(robots):
    """inverted5: P1 keeps q0's value when a branch exists there; else the least move.

    The target needs P1 + P5 = 0.15 m with each stroke in [0, 0.100076] m. From P1 = 0.07
    (P5 = 0.08 works) P1 stays; from P1 = 0.01 (P5 would need 0.14) P5 goes to its end and
    P1 to 0.15 - 0.100076. Mutation caught: the fallback splitting the move between the
    strokes (not the least move of the held one) -> P1 differs.
    """
    robot = robots["inverted5"]
    q = np.array([0.06, 0.7, 1.4, -0.2, 0.09])
    t = so.Target(robot.position(q))
    for p1, want in ((0.07, 0.07), (0.01, 0.15 - robot.upper[4])):
        q0 = np.array([p1, 0.7, 1.4, -0.2, 0.05])
        sols = solve_all(robot, t, q0)
        assert sols and all(s[0] == pytest.approx(want, abs=1e-12) for s in sols)
        assert all(s[0] + s[4] == pytest.approx(0.15, abs=1e-12) for s in sols)


def test_closed_form_moves_the_rail_only_as_far_as_needed(robots):
    """nguyen: a target the arm cannot reach from the held rail value gets the nearest rail
    value from which a branch exists, found among the intervals of :func:`rail_intervals`.

    Mutation caught: taking any feasible rail value (e.g. the middle of an interval) instead of
    the nearest end -> the rail moves further than needed.
    """
    robot = robots["nguyen"]
    q = np.array([0.50, 0.4, 1.2, 0.05, 0.3])
    t = so.Target(robot.position(q), yaw=robot.yaw(q))
    held = np.array([0.0, 0.4, 1.2, 0.05, 0.3])
    sols = solve_all(robot, t, held)
    assert sols and len({s[0] for s in sols}) == 1  # every branch at the one rail value
    rail = sols[0][0]
    assert 0.0 < rail < 0.5  # moved, but not back to the generating value
    # no rail value nearer to the held 0 reaches: held 1e-6 m nearer, the closed form fails
    assert not solve_all(robot, t, held, fixed={"d1": rail - 1e-6})
    assert solve_all(robot, t, held, fixed={"d1": rail})


# ------------------------------------------------------------------ certificates
def test_each_certificate_reason_is_reachable(robots):
    """Height, beyond reach, inside the hole and no branch within limits each have a target."""
    zavar = robots["zavar2024"]
    cases = {
        "height_out_of_stroke": so.Target([-0.23, 0.20, -0.20]),
        "beyond_reach": so.Target([0.5, 0.1, -0.07]),
        "inside_hole": so.Target([0.1, 0.05, -0.07]),
        # reachable position, but a tool angle the wrist's +-120 deg cannot add
        "no_branch_within_limits": so.Target([-0.23, 0.20, -0.07], yaw=np.radians(-30)),
    }
    for reason, target in cases.items():
        res = so.solve_ik(zavar, target)
        assert (res.status, res.reason) == ("unreachable", reason), res
        assert res.evidence.startswith("proof: ")
        assert res.error >= certify(zavar, target, 1e-9).bound - 1e-12


@pytest.mark.parametrize("name", BUNDLED)
def test_certificates_are_sound_and_complete_on_random_targets(robots, name):
    """150 random targets in a box around each workspace: where a certificate exists, no
    configuration found by a 40-start search beats its bound; where none exists, the exact
    solver reaches the target within tol.

    Mutations caught: a certificate whose bound omits a stroke (claims too much: the search
    beats it); the joint-limit argument with its tool-angle band not widened by tol (a yaw
    target within tol of the workspace is certified); a reach interval that ignores
    the elbow's limits (certifies nothing inside the hole: the exact solver then misses).
    """
    robot = robots[name]
    rng = np.random.default_rng(5)
    P = robot.positions(random_q(robot, 400, seed=5))
    lo, hi = P.min(axis=0) - 0.05, P.max(axis=0) + 0.05
    for k in range(150):
        p = rng.uniform(lo, hi)
        q = random_q(robot, 1, seed=1000 + k)[0]
        t = so.Target(p, yaw=robot.yaw(q)) if k % 2 else so.Target(p)
        cert = certify(robot, t, 1e-9)
        res = so.solve_ik(robot, t, method="auto", restarts=40)
        if cert is None:
            assert res.success, (k, t, res)
        else:
            assert res.status == "unreachable" and res.error >= cert.bound - 1e-12, (k, res)


def test_target_just_outside_within_tol_is_not_certified(robots):
    """A target 1e-10 m beyond the stretched arm is within tol 1e-9 of the workspace: no
    certificate, and the exact solvers call it solved.

    Mutation caught: certifying with the exact (not widened) reach -> "unreachable".
    """
    robot = robots["zavar2024"]
    t = so.Target([0.4 + 1e-10, 0.0, -0.07])
    assert certify(robot, t, 1e-9) is None
    assert so.solve_ik(robot, t).success
    assert certify(robot, so.Target([0.4 + 1e-6, 0.0, -0.07]), 1e-9).reason == "beyond_reach"


def test_reach_bound_certifies_far_targets_on_any_chain(ur5_arm, panda_arm):
    """A 6R and a 7R arm: a target beyond the sum of link offsets is unreachable with that
    proof; a pose inside it that no search reaches is "failed", never "unreachable".

    The bound is the sum of the DH link offsets sqrt(a^2 + d^2) after the first joint's
    origin, from the published tables (UR5: d1, a2, a3, d4, d5, d6; Panda: d3, a4, a5/d5,
    a7, flange). Mutation caught: the bound without one link offset (too small: a reachable
    target near full stretch could be certified).
    """
    ur5 = 0.089159 + 0.425 + 0.39225 + 0.10915 + 0.09465 + 0.0823
    panda = 0.316 + 0.0825 + np.hypot(0.0825, 0.384) + 0.088 + 0.107
    for arm, want in ((ur5_arm, ur5), (panda_arm, panda)):
        origin, reach = reach_bound(arm)
        assert reach == pytest.approx(want, abs=1e-12)
        Q = random_q(arm, 2000, seed=2)
        dist = np.linalg.norm(arm.positions(Q) - origin, axis=1)
        assert dist.max() <= reach  # the bound holds on samples
        far = so.Target(origin + [reach + 0.01, 0.0, 0.0])
        res = so.solve_ik(arm, far, method="lm")
        assert (res.status, res.reason) == ("unreachable", "beyond_reach")
        assert res.error >= 0.01 - 1e-12
    # inside the reach bound, a full rotation the arm cannot take with its tip there: failed
    near = so.Target(origin + [0.0, 0.0, 0.05], rotation=np.eye(3))
    res = so.solve_ik(panda_arm, near, method="lm", restarts=2)
    if not res.success:
        assert (res.status, res.reason) == ("failed", "no_certificate")


# ------------------------------------------------------------------ verdicts of misses
def test_a_metaheuristic_miss_is_max_iter_with_a_witness(robots):
    """A budget too small for PSO on a reachable target: max_iter, with the witness that the
    closed form reaches it; on an arm, the witness comes from the exact auto method.

    Mutation caught: a witness search that ignores the caller's seed (the verdict then
    changes with a global state), and a verdict that calls every miss "unreachable".
    """
    zavar = robots["zavar2024"]
    res = so.solve_ik(zavar, [-0.23, 0.20, -0.07], method="pso", population=4, iterations=2)
    assert (res.status, res.reason) == ("max_iter", "budget")
    assert "closed form reaches it" in res.evidence


def test_the_verdict_uses_the_callers_seed_and_is_repeatable(ur5_arm):
    """On an arm (no closed form) a metaheuristic's miss is judged by the exact method with
    the caller's seed and q0: twice the same call, the same verdict and evidence."""
    q = random_q(ur5_arm, 1, seed=4)[0]
    T = ur5_arm.fk(q)
    t = so.Target(T[:3, 3], rotation=T[:3, :3])
    a, b = (so.solve_ik(ur5_arm, t, method="pso", population=6, iterations=3, seed=9)
            for _ in range(2))
    assert (a.status, a.reason, a.evidence) == (b.status, b.reason, b.evidence)
    assert a.status == "max_iter" and "'auto' reaches it" in a.evidence


def test_held_joints_make_a_failure_not_unreachable(robots):
    """Infeasible only because the caller held P1: failed (held_joints), with P1 kept."""
    robot = robots["inverted5"]
    far = robot.position(np.array([0.07, 0.7, 1.4, -0.2, 0.08]))
    res = so.solve_ik(robot, far, method="analytic", fixed={"P1": 0.0})
    assert (res.status, res.reason) == ("failed", "held_joints") and res.q[0] == 0.0
    assert so.solve_ik(robot, far, method="analytic").success


# ------------------------------------------------------------------ IPOPT on its own
@pytest.mark.parametrize("name", FOUR_JOINT)
def test_ipopt_alone_reaches_1e10_on_1000_targets(robots, name):
    """IPOPT without the fast solver's polish: <= 1e-10 on >= 99.9 % of 1000 FK targets.

    Before: 0/40 below 1e-9 (IPOPT stopped at its "acceptable" level 1e-5, and the
    regulariser left an offset). Mutation caught: the nearest NLP removed (only the
    regularised least squares) -> median ~1e-8, the test fails.
    """
    robot = robots[name]
    errors = np.array([so.solve_ik(robot, t, method="ipopt", polish=False).error
                       for t in fk_targets(robot, 1000, seed=21)])
    assert np.mean(errors <= 1e-10) >= 0.999, np.sort(errors)[-5:]


# ------------------------------------------------------------------ tol floor
def test_tol_below_round_off_is_refused(robots):
    """tol below the floor is an InputError naming the floor; at the floor, both branches.

    Before: tol 1e-300 gave "unreachable" at residual 5.6e-17, and tol 1e-17 one branch of
    two. Mutation caught: the floor check removed -> no InputError.
    """
    robot = robots["zavar2024"]
    with pytest.raises(so.InputError, match="round-off"):
        so.solve_ik(robot, [0.3, 0.0, -0.07], tol=1e-300)
    with pytest.raises(so.InputError, match=f"{TOL_FLOOR:g}"):
        so.ik_all(robot, [0.3, 0.0, -0.07], tol=1e-17)
    assert len(so.ik_all(robot, [0.3, 0.0, -0.07], tol=TOL_FLOOR)) == 2
    assert so.solve_ik(robot, [0.3, 0.0, -0.07], tol=TOL_FLOOR).status != "unreachable"


def test_default_start_is_used_when_q0_is_none(robots):
    """The witness and the solvers share one default start (zero, or mid-range)."""
    robot = robots["peng2025"]
    q0 = default_q0(robot)
    assert robot.within_limits(q0)


@pytest.mark.parametrize("name", BUNDLED)
def test_a_tilted_rotation_on_a_scara_is_unreachable_with_a_sound_bound(name):
    """A full-rotation target that tilts the yaw axis of a SCARA-type robot is
    ``unreachable`` (reason ``tilt_out_of_plane``) with the tilt as its bound; the bound is
    below the rotation error of 2,000 random in-limit configurations (sound), and a rotation
    about the axis itself stays reachable.

    Mutations caught: ``tilt_certificate`` left out of ``certify`` (status ``failed``); the
    bound measured from ``R* n`` without the reference orientation (``R_refᵀ``): on a tool
    that points down it claims ~π - 0.1 rad instead of 0.1.
    """
    import pinocchio as pin

    robot = so.load_robot(name)
    n = robot.yaw_axis
    q = random_q(robot, 1, seed=4)[0]
    T = robot.fk(q)
    axis = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    tilt = pin.exp3(0.1 * axis / np.linalg.norm(axis)) @ T[:3, :3]
    res = so.solve_ik(robot, so.Target(T[:3, 3], rotation=tilt))
    assert res.status.value == "unreachable" and res.reason.value == "tilt_out_of_plane"
    cert = certify(robot, so.Target(T[:3, 3], rotation=tilt), 1e-9)
    assert cert is not None and cert.bound == pytest.approx(0.1, abs=1e-12)
    Q = random_q(robot, 2000, seed=5)
    errors = [np.linalg.norm(pin.log3(robot.fk(x)[:3, :3].T @ tilt)) for x in Q]
    assert min(errors) >= cert.bound - 1e-12
    turned = pin.exp3(0.7 * n) @ T[:3, :3]  # about the axis itself: no tilt
    assert certify(robot, so.Target(T[:3, 3], rotation=turned), 1e-9) is None
    assert so.solve_ik(robot, so.Target(T[:3, 3], rotation=turned)).success
