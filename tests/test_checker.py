"""The checker's verdicts against coal's signed distance: in sequences, fresh, in batches."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import scara_opt as so

from .conftest import pinocchio_distances

SCARA = so.load_robot("zavar2024")

#: a configuration in a 35 mm overlap that Pinocchio's computeCollisions (GJK guess cached,
#: Pinocchio's default) calls free right after PRIMING; cell: one cylinder (r, length, xyz, rpy)
GUESSED = ((0.042423388628016555, 0.3105144132737194,
            (0.08128561962538716, 0.06360303084350305, -0.11957780618927835),
            (-0.4303143244951886, -0.05915625512103784, 0.5979273078469871)),
           [0.7491226292700883, -0.9046899437230551, 0.025290825007547046, -2.084361094748621])
PRIMING = [-1.9448427167348998, 0.9682612974961198, 0.01446306123900771, 1.7762677157591074]

#: overlaps (42 and 88 mm) that coal's collision test misses even started afresh, without
#: its contact computation (9 of 2 million random queries did)
MISSED = [((0.03599959846286549, 0.2675737895052981,
            (-0.053669579800396605, -0.06466515582863092, -0.05995673390674594),
            (0.14142577618688001, 0.468240903570007, -0.12630664737528852)),
           [-1.4743415581750536, -1.5055130708544673, 0.025669435292230695, 1.8943368797286326]),
          ((0.05729991715045796, 0.33806405378276877,
            (-0.027910679044857722, -0.06149825368659456, -0.022866123223412),
            (-0.2545064663123935, 0.42396697162941166, -0.5893443055622762)),
           [-1.7372021928628323, 0.4766795922605831, 0.0003407092485569354,
            -1.5161098069467578])]


def _cylinder_checker(spec, **kw):
    """zavar2024 and one cylinder; every pair checked (a cylinder through link1's base may
    touch it in every configuration: not left out here)."""
    r, length, xyz, rpy = spec
    return so.CollisionChecker(SCARA, so.Cell([so.Cylinder("o2", r, length, xyz=xyz, rpy=rpy)]),
                               check_touching=True, **kw)


def test_a_guess_from_an_earlier_query_changes_no_verdict():
    """The 35 mm overlap that Pinocchio's computeCollisions calls free after one earlier
    query: ``collides``, ``collides_many`` and ``contacts`` say contact, before and after it,
    in one checker; Pinocchio's own call with its default (cached) guess is the trap.

    Mutation caught: ``collides`` by Pinocchio's ``computeCollisions`` on the checker's data
    with Pinocchio's requests (as before: no ``fresh_starts``) -> False after the priming
    query; fails.
    """
    spec, q = GUESSED
    checker = _cylinder_checker(spec)
    q, prime = np.array(q), np.array(PRIMING)
    model, data = SCARA.model, SCARA.model.createData()
    gdata = pin.GeometryData(checker.model)
    pin.computeCollisions(model, data, checker.model, gdata, prime, True)
    trap = pin.computeCollisions(model, data, checker.model, gdata, q, True)
    for order in ([prime, q], [q, prime, q], [prime, prime, q]):
        verdicts = [checker.collides(x) for x in order]
        assert verdicts[-1] is True, trap
        assert checker.collides_many(np.array(order))[-1]
        assert checker.clearance(q).distance < -0.03
        assert checker.contacts(q)


@pytest.mark.parametrize("case", range(len(MISSED)))
def test_a_deep_overlap_coals_collision_test_misses_is_a_contact(case):
    """Capsule-cylinder overlaps of 42 and 88 mm that coal's boolean collision test misses
    (started afresh, no contact computation): a brand-new checker says contact, one by one
    and in a batch, as its own signed distance does.

    Mutation caught: ``collides`` by ``computeCollisions`` with fresh starts -> False; fails.
    """
    spec, q = MISSED[case]
    checker = _cylinder_checker(spec)
    assert checker.clearance(q).distance < -0.01
    assert _cylinder_checker(spec).collides(q)
    assert _cylinder_checker(spec).collides_many(np.array([q]))[0]


def _random_cell(rng):
    """Three random primitives around zavar2024's reach."""
    obs = []
    for k in range(3):
        xyz = tuple(rng.uniform([-0.4, -0.4, -0.2], [0.4, 0.4, 0.1]))
        rpy = tuple(rng.uniform(-1, 1, 3))
        kind = int(rng.integers(4))
        if kind == 0:
            obs.append(so.Cylinder(f"o{k}", rng.uniform(0.01, 0.08), rng.uniform(0.05, 0.4),
                                   xyz=xyz, rpy=rpy))
        elif kind == 1:
            obs.append(so.Box(f"o{k}", tuple(rng.uniform(0.002, 0.3, 3)), xyz=xyz, rpy=rpy))
        elif kind == 2:
            obs.append(so.Capsule(f"o{k}", rng.uniform(0.01, 0.08), rng.uniform(0.05, 0.4),
                                  xyz=xyz, rpy=rpy))
        else:
            obs.append(so.Sphere(f"o{k}", rng.uniform(0.01, 0.08), xyz=xyz))
    return so.Cell(obs)


@pytest.mark.parametrize("margin", [0.0, 0.004])
def test_verdicts_agree_with_coals_fresh_signed_distance(margin):
    """Six random cells, 1,500 configurations each: ``collides`` in one sequence of queries,
    ``collides`` of a brand-new checker, ``collides_many`` (one and two threads) and
    ``contacts`` all say contact exactly where the checker's own signed distance is below
    the margin (<= 0 without one), and those distances are coal's with a fresh request to
    2e-6 m; away from that tolerance, the verdict is the fresh distance's.

    Mutation caught: the margin dropped from the kernel's contact test (``d <= 0`` alone)
    -> the 4 mm case fails. Mutation caught: the capsule's holding ball half its radius
    (``holding_ball``: pairs in contact skipped) -> fails. Mutation caught:
    ``collides_many`` over threads answering the first chunk for every chunk -> fails.
    """
    rng = np.random.default_rng(11)
    for _ in range(6):
        cell = _random_cell(rng)
        checker = so.CollisionChecker(SCARA, cell, margin=margin)
        Q = rng.uniform(SCARA.lower, SCARA.upper, (1500, SCARA.nq))
        D = checker.distances_many(Q)
        ref = pinocchio_distances(checker, Q)
        assert np.abs(D - ref).max() < 2e-6
        want = (D < margin).any(axis=1) if margin else (D <= 0).any(axis=1)
        seq = np.array([checker.collides(q) for q in Q])
        assert np.array_equal(seq, want)
        assert np.array_equal(checker.collides_many(Q), want)
        assert np.array_equal(checker.collides_many(Q, threads=2), want)
        fresh = [so.CollisionChecker(SCARA, cell, margin=margin).collides(q) for q in Q[:40]]
        assert fresh == want[:40].tolist()
        assert [bool(checker.contacts(q)) for q in Q[:200]] == want[:200].tolist()
        least = ref.min(axis=1)
        sure = np.abs(least - margin) > 2e-6
        assert np.array_equal(want[sure], (least < margin)[sure])


def test_the_python_form_gives_the_kernels_verdicts(monkeypatch):
    """Without the compiled kernel, ``collides`` and ``collides_many`` decide by Pinocchio's
    distances (fresh starts): the kernel's verdicts, row for row.

    Mutation caught: the Python form of ``collides`` by ``computeCollisions`` (as before)
    on the MISSED overlaps -> False; fails.
    """
    rng = np.random.default_rng(3)
    cell = _random_cell(rng)
    checker = so.CollisionChecker(SCARA, cell)
    Q = rng.uniform(SCARA.lower, SCARA.upper, (400, SCARA.nq))
    kernel = checker.collides_many(Q)
    python = so.CollisionChecker(SCARA, cell)
    monkeypatch.setattr(python, "_kernel", lambda: None)
    assert np.array_equal(python.collides_many(Q), kernel)
    assert [python.collides(q) for q in Q] == kernel.tolist()
    spec, q = MISSED[0]
    lone = _cylinder_checker(spec)
    monkeypatch.setattr(lone, "_kernel", lambda: None)
    assert lone.collides(q)


def test_threads_must_be_a_whole_number():
    """``collides_many(threads=1.5)`` is refused, naming threads (it was truncated to 1)."""
    checker = so.CollisionChecker(SCARA, so.Cell([so.Sphere("s", 0.02, xyz=(0.3, 0, 0))]))
    with pytest.raises(so.InputError, match="threads"):
        checker.collides_many(np.zeros((2, 4)), threads=1.5)


def test_fresh_starts_make_the_trap_right():
    """Pinocchio's computeCollisions on the trap query, its requests started afresh
    (``fresh_starts``): contact, so the guess carried over is what lied.

    Mutation caught: ``fresh_starts`` doing nothing -> False; fails.
    """
    from scara_opt.collision.checker import fresh_starts

    spec, q = GUESSED
    checker = _cylinder_checker(spec)
    gdata = pin.GeometryData(checker.model)
    fresh_starts(gdata)
    data = SCARA.model.createData()
    pin.computeCollisions(SCARA.model, data, checker.model, gdata, np.array(PRIMING), True)
    assert pin.computeCollisions(SCARA.model, data, checker.model, gdata, np.array(q), True)
