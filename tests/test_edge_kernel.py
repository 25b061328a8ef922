"""The compiled edge proof (collision/edge_kernel.cpp) against its Python form and Pinocchio."""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.collision.edge_kernel import shape_code
from scara_opt.errors import FallbackWarning
from scara_opt.planning.ompl_backend import RESOLUTION, EdgeProver
from tests.conftest import DATA, pinocchio_collides

SCARA = so.load_robot("zavar2024")
TABLE = so.Cell([so.Box("table", (0.9, 0.9, 0.02), xyz=(0.1, 0.0, -0.14)),
                 so.Cylinder("tall", 0.025, 0.3, xyz=(0.30, -0.12, 0.0)),
                 so.Box("block", (0.06, 0.06, 0.05), xyz=(0.32, 0.12, -0.105), rpy=(0, 0, 0.5)),
                 so.Sphere("ball", 0.025, xyz=(0.22, 0.05, -0.105)),
                 so.Capsule("pipe", 0.012, 0.25, xyz=(-0.05, 0.3, -0.09), rpy=(0, 1.5708, 0.3))])


def _arm():
    arm = so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")
    return arm.with_limits(**{n: (-math.pi, math.pi) for n in arm.joint_names})


SHELF = so.Cell([so.Box("shelf", (0.3, 0.8, 0.02), xyz=(0.55, 0.0, 0.25), rpy=(0.1, 0, 0.2)),
                 so.Box("back", (0.02, 0.8, 0.7), xyz=(0.71, 0.0, 0.35)),
                 so.Cylinder("post", 0.04, 0.8, xyz=(-0.35, 0.35, 0.4))])


def _checkers():
    return [so.CollisionChecker(SCARA, TABLE),
            so.CollisionChecker(SCARA, TABLE, margin=0.004),
            so.CollisionChecker(_arm(), SHELF, radius=0.045)]


@pytest.fixture(scope="module", params=[0, 1, 2], ids=["scara", "scara-margin", "6R"])
def checker(request):
    kernel_checker = _checkers()[request.param]
    if kernel_checker._kernel() is None:  # pragma: no cover - no compiler on this machine
        pytest.skip("the edge kernel does not compile here (the Python form runs)")
    return kernel_checker


def test_kernel_distances_are_pinocchios(checker):
    """Every pair's distance at 300 random configurations, the kernel's (coal's functors,
    bodies placed by the compiled casadi Function) against Pinocchio's computeDistances, to
    coal's own tolerance (1e-6 m, which the proof's DISTANCE_TOL covers ten times).

    Mutation caught: the rotation read column by column (``R << x[0], x[3], x[6], ...``):
    rotated bodies sit elsewhere, distances differ by centimetres. Mutation caught: a body's
    placement in its joint frame left out of the Function (``Rg = R``): the same.
    """
    robot = checker.robot
    rng = np.random.default_rng(5)
    Q = rng.uniform(robot.lower, robot.upper, (300, robot.nq))
    ours = checker._kernel().batch(Q)
    ref = np.array([checker.distances(q) for q in Q])
    assert ours.shape == ref.shape == (300, checker.npairs)
    assert np.abs(ours - ref).max() < 1e-6
    cols = [checker.npairs - 1, 0]
    assert np.abs(checker._kernel().batch(Q, cols) - ref[:, cols]).max() < 1e-6
    assert np.abs(checker.pair_distances(Q, np.array(cols)) - ref[:, cols]).max() < 1e-6


def test_kernel_contacts_are_coals_fresh_distances(checker):
    """Contact tests of 4,000 random configurations (about a fifth in contact), the kernel's
    loop against each pair's signed distance from Pinocchio's ``computeDistances`` with
    fresh GJK starts (``pinocchio_collides``), one by one, and ``collides_many`` in one and
    two threads: the same answer for every configuration.

    Mutation caught: the loop stopping after the first pair (``p < 1``): contacts of the
    other pairs missed. Mutation caught: the answer of the last pair kept instead of any
    (``hit = touching(p)`` without the early exit, ``|=`` dropped): contacts lost.
    Mutation caught: the balls' radii halved in ``holding_ball`` (pairs skipped that touch).
    """
    robot = checker.robot
    rng = np.random.default_rng(9)
    Q = rng.uniform(robot.lower, robot.upper, (4000, robot.nq))
    ours = checker._kernel().collides(Q)
    assert ours.dtype == bool and 0.05 < ours.mean() < 0.95
    assert np.array_equal(ours[:1000], pinocchio_collides(checker, Q[:1000]))
    assert np.array_equal(ours, checker.collides_many(Q, threads=2))
    assert np.array_equal(ours, checker.collides_many(Q))


def test_native_edges_agree_with_the_python_form(checker):
    """The same verdict and the same number of midpoints (and states), edge by edge, on
    edges between free random configurations (whole, 30 % and 5 % of the way: long, short
    and grazing; and one joint at a time), a SCARA's height spans included.

    Mutation caught: the interval's bound not scaled by its length (``M[p] < dl + dh``):
    fewer midpoints, and edges through obstacles pass. Mutation caught: the spans ignored
    (``apart`` returning false): more midpoints on the SCARA. Mutation caught: the halves'
    ends swapped (``dl``, ``dh`` both ``dm``): counts differ. Mutation caught: the states'
    cache keyed without the first joint: a state moved by that joint alone reads another's
    distances.
    """
    robot = checker.robot
    native, python = EdgeProver(checker), EdgeProver(checker, native=False)
    assert native._native is not None and python._native is None
    rng = np.random.default_rng(11)
    Q = rng.uniform(robot.lower, robot.upper, (800, robot.nq))
    Q = Q[~checker.collides_many(Q)][:400]
    verdicts = []
    for a, b in zip(Q[0::2], Q[1::2], strict=False):
        ends = [a + frac * (b - a) for frac in (1.0, 0.3, 0.05)]
        ends += [np.where(np.arange(robot.nq) == j, b, a) for j in range(robot.nq)]
        for end in ends:  # long, short, grazing; one joint at a time
            ka, kb = tuple(a.tolist()), tuple(end.tolist())
            m0, m1 = native.midpoints, python.midpoints
            verdict = native.edge(ka, kb)
            assert verdict == python.edge(ka, kb)
            assert native.midpoints - m0 == python.midpoints - m1
            assert native.states == python.states
            verdicts.append(verdict)
    assert 0.2 < np.mean(verdicts) < 0.95  # both kinds, many of each
    assert native.midpoints > 500


def test_a_state_in_contact_stops_at_its_first_pair_in_contact(checker):
    """States of 300 random configurations (many in contact): the compiled prover's
    verdicts are the Python form's, found with fewer pair distances than states times
    pairs; asked for afterwards, a refused state's distances are all there and are the
    Python form's; and an edge from a state in contact is refused without its end.

    Mutation caught: the early exit dropped (every pair at every state): the count of pair
    distances is states times pairs. Mutation caught: the exit on the first pair whatever
    its distance (``if (!all) return``): states not in contact refused. Mutation caught:
    a cached state not completed when its distances are asked for: NaN distances.
    Mutation caught: the Python form's ``_prove`` computing the end before it looks at
    the start: 301 states.
    """
    robot = checker.robot
    rng = np.random.default_rng(13)
    keys = [tuple(q) for q in rng.uniform(robot.lower, robot.upper, (300, robot.nq)).tolist()]
    native, python = EdgeProver(checker), EdgeProver(checker, native=False)
    verdicts = [native.valid(k) for k in keys]
    assert verdicts == [python.valid(k) for k in keys]
    assert 0.1 < np.mean(verdicts) < 0.9
    compiled = native._native
    assert compiled is not None
    assert compiled.states == 300 and compiled.pairs < 300 * checker.npairs
    for k in keys[:60]:
        assert np.abs(np.subtract(native.distances(k), python.distances(k))).max() < 1e-6
    assert compiled.states == 300  # completed in place, not computed anew
    hit = keys[verdicts.index(False)]
    end = tuple(np.add(hit, 0.01).tolist())
    assert not native.edge(hit, end) and not python.edge(hit, end)
    assert compiled.states == 300  # the end of an edge from a contact is not computed
    assert python.states == 300  # nor by the Python form


def test_a_midpoint_asks_first_the_pair_that_last_refused_one(checker):
    """Short edges from random states, refused at their first midpoint: where the pair
    that refused the midpoint before (known when one pair alone was in contact there, by
    the Python form's distances) is in contact again, one pair distance is computed at the
    midpoint; the verdicts are the Python form's.

    Mutation caught: the lead pair ignored (the midpoint's pairs in their open order):
    later refusals compute the pairs before it as well.
    """
    robot = checker.robot
    rng = np.random.default_rng(21)
    native, python = EdgeProver(checker), EdgeProver(checker, native=False)
    compiled = native._native
    assert compiled is not None
    last: int | None = None
    repeats, later = 0, 0
    for _ in range(12000):
        qa = rng.uniform(robot.lower, robot.upper)
        qb = np.clip(qa + rng.normal(0.0, 1.0, robot.nq), robot.lower, robot.upper)
        a, b = tuple(qa.tolist()), tuple(qb.tolist())
        if not (native.valid(a) and native.valid(b)):
            continue
        mid = tuple(((np.array(a) + np.array(b)) / 2).tolist())
        inside = [k for k, d in enumerate(python.distances(mid)) if d <= 0]
        m0, p0 = compiled.midpoints, compiled.midpoint_pairs
        verdict = native._native.edge(a, b, RESOLUTION)
        assert verdict == python._prove(a, b)
        if verdict:
            continue  # a proven edge leaves the lead pair as it was
        if compiled.midpoints == m0 + 1 and last in inside:
            repeats += 1
            later += compiled.midpoint_pairs - p0
        elif compiled.midpoints == m0 + 1 and len(inside) == 1:
            last = inside[0]
        else:
            last = None  # refused by a pair the test does not know
    assert repeats >= 5 and later == repeats


def test_the_compiled_path_proof_is_the_python_forms(checker, monkeypatch):
    """Cubic splines through short chains of random clear states (toppra's joint paths'
    form): the compiled ``check_path`` gives the Python form's verdict, evaluations and
    clearance (to 1e-9 m), and some of them are proven. At the middles it computes at most
    the pairs the Python form does (each pair failing on some interval of the level), and
    fewer on some paths: a pair proven on an interval is not computed at its middle.

    Mutation caught: a pair proven on an interval computed again at its middle (``if
    (false) continue``): more pair distances than the Python form's. Mutation caught: the
    pairs failing on any interval computed (as before): never fewer.
    """
    from scipy.interpolate import CubicSpline

    from scara_opt.collision.continuous import check_path

    robot = checker.robot
    rng = np.random.default_rng(5)
    cases, proven, fewer = 0, 0, 0
    while cases < 40:
        q = rng.uniform(robot.lower, robot.upper)
        Q = [q]
        for _ in range(3):
            Q.append(np.clip(Q[-1] + rng.normal(0.0, 0.3, robot.nq), robot.lower, robot.upper))
        if any(checker.collides(x) for x in Q):
            continue
        cases += 1
        path = CubicSpline(np.arange(4.0), np.array(Q), bc_type="clamped")
        native = check_path(checker, path)
        computed = checker._kernel().path_pairs
        asked = [0, 0]  # calls; the Python form's pair distances at middles
        distances = checker.pair_distances

        def counted(Q, cols=None, kind="exact", asked=asked, distances=distances):
            if asked[0]:  # not the first call (the breakpoints)
                asked[1] += len(Q) * (checker.npairs if cols is None else len(cols))
            asked[0] += 1
            return distances(Q, cols, kind)

        with monkeypatch.context() as m:
            m.setattr(checker, "_kernel", lambda: None)
            m.setattr(checker, "pair_distances", counted)
            python = check_path(checker, path)
        assert (native.clear, native.evaluations) == (python.clear, python.evaluations)
        assert computed <= asked[1]
        fewer += computed < asked[1]
        if native.clear:
            proven += 1
            assert abs(native.clearance - python.clearance) < 1e-9
    assert 5 <= proven < 40 and fewer >= 5


def test_native_plans_are_the_python_forms():
    """A planned PTP around a post: the same path (bit for bit) with the kernel and without.

    Mutation caught: the kernel's states shifted by the margin twice (``raw(k) - 2 *
    shift``): other edges pass, the paths differ.
    """
    from scara_opt.planning import plan_path
    from scara_opt.planning import planner as planner_module

    checker = so.CollisionChecker(SCARA, so.Cell([so.Cylinder("post", 0.03, 0.4,
                                                               xyz=(0.3, 0.15, 0.0))]),
                                  margin=0.002)
    qa, qb = np.array([-0.5, 0.5, 0.0, 0.0]), np.array([1.2, 0.5, 0.0, 0.0])
    native = plan_path(checker, qa, qb, seed=4)
    original = planner_module.EdgeProver
    try:
        planner_module.EdgeProver = lambda c: original(c, native=False)  # type: ignore
        python = plan_path(checker, qa, qb, seed=4)
    finally:
        planner_module.EdgeProver = original
    assert native.path is not None and np.array_equal(native.path, python.path)
    assert (native.states, native.checks) == (python.states, python.checks)


def test_meshes_go_through_the_kernel(tmp_path):
    """A cell with a mesh obstacle (an open, one-triangle wedge) runs the compiled kernel
    too: the prover is native, and the kernel's reported distances are the Python form's
    (coal's own BVH distance) to 1e-9 m.

    Mutation caught: ``shape_code`` not knowing meshes (as before) -> no kernel; fails.
    """
    stl = tmp_path / "wedge.stl"
    stl.write_text("solid w\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\n"
                   "vertex 0 0.1 0\nendloop\nendfacet\nendsolid w\n")
    cell = so.Cell([so.Mesh("wedge", stl, xyz=(0.3, 0.0, -0.05))])
    checker = so.CollisionChecker(SCARA, cell)
    assert shape_code(checker.model.geometryObjects[-1].geometry)[0] == 4
    assert checker._kernel() is not None and EdgeProver(checker)._native is not None
    Q = np.random.default_rng(2).uniform(SCARA.lower, SCARA.upper, (200, 4))
    python = checker._python_distances(Q, None, "exact")
    assert np.abs(checker.distances_many(Q) - python).max() < 1e-9


def test_compiled_path_proofs_are_the_python_forms(checker, monkeypatch):
    """``check_path`` of 80 cubic splines through random waypoints (2-5, short and long
    steps), compiled and in Python: the same verdict and the same number of
    configurations; when clear the same proven clearance, else the same contact (place,
    distance, touching; the bodies too, but where two pairs are in a tie to 1e-9 m).

    Mutation caught: the pieces' speed bounds ignored past the first joint (``j < 1``):
    fewer configurations, splines through obstacles pass. Mutation caught: the SCARA's
    height gaps left out (``A`` passed as NULL): more configurations. Mutation caught: the
    halves' ends swapped (``dh = &Dlo[...]``): counts differ. Mutation caught: scipy's
    power sum replaced by ``z *= s`` before the first term: configurations elsewhere.
    """
    from scara_opt.collision.continuous import check_path
    from scara_opt.motion.timing import section_spline
    from scara_opt.trajectory.limits import resolve_limits

    robot = checker.robot
    limits = resolve_limits(robot, robot.nq)
    rng = np.random.default_rng(3)
    verdicts = []
    for trial in range(80):
        a = rng.uniform(robot.lower, robot.upper)
        steps = rng.normal(0.0, 0.15 if trial % 2 else 0.5, (rng.integers(2, 6), robot.nq))
        Q = np.clip(a + np.cumsum(steps, axis=0), robot.lower, robot.upper)
        spline = section_spline(Q, limits).cspl
        native = check_path(checker, spline)
        with monkeypatch.context() as m:
            m.setattr(checker, "_kernel", lambda: None)
            python = check_path(checker, spline)
        assert (native.clear, native.evaluations) == (python.clear, python.evaluations)
        if native.clear:
            assert native.clearance == pytest.approx(python.clearance, abs=1e-12)
        else:
            c, d = native.contact, python.contact
            assert (c.at, c.touching) == (d.at, d.touching)
            assert c.distance == pytest.approx(d.distance, abs=1e-9)
            if c.bodies != d.bodies:  # a tie: both pairs equally deep there
                k, j = checker.pair_names.index(c.bodies), checker.pair_names.index(d.bodies)
                dist = checker.distances(spline(c.at))
                assert abs(dist[k] - dist[j]) < 1e-9
        verdicts.append(native.clear)
    assert 0.1 < np.mean(verdicts) < 0.9


def test_missing_headers_fall_back_and_say_so(monkeypatch):
    """Where coal's or Eigen's headers are not found, the kernel is not built: the Python
    form runs, the fallback is said (a FallbackWarning) and recorded with its reason
    (``scara-opt doctor`` lists it). With ``SCARA_OPT_NO_COMPILE=1`` the headers are not
    looked for: the kernel is "off", as every native piece, and nothing is said.

    Mutation caught: the reason dropped (``c_library`` returning None for a string from
    ``extra`` without ``_fall_back``): no record of the fallback. Mutation caught: the
    headers looked for before the ``SCARA_OPT_NO_COMPILE`` test: "fallback" instead of
    "off".
    """
    from scara_opt.collision import edge_kernel as ek
    from scara_opt.model import compiled

    monkeypatch.setattr(ek, "build_arguments", lambda: "coal's headers were not found (test)")
    monkeypatch.setattr(compiled, "_NATIVES", {})  # this process's record, fresh
    monkeypatch.setattr(compiled, "_SAID", set())
    ek._library.cache_clear()
    try:
        checker = so.CollisionChecker(SCARA, TABLE)
        with pytest.warns(FallbackWarning, match="edge_kernel.cpp"):
            assert checker._kernel() is None
        assert EdgeProver(checker)._native is None
        said = [n for n in compiled.natives() if n.name == "edge_kernel.cpp"]
        assert said and said[-1].state == "fallback" and "(test)" in said[-1].detail
        monkeypatch.setattr(compiled, "_NATIVES", {})
        monkeypatch.setenv("SCARA_OPT_NO_COMPILE", "1")
        ek._library.cache_clear()
        assert so.CollisionChecker(SCARA, TABLE)._kernel() is None
        said = [n for n in compiled.natives() if n.name == "edge_kernel.cpp"]
        assert [n.state for n in said] == ["off"]
    finally:
        ek._library.cache_clear()
