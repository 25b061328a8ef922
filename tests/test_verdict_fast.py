"""The fast paths of every solve's fixed cost give exactly the slow paths' results.

``Robot.fits_limits`` lets ``check_q0`` and the verdict skip numpy's checks and clip for the
common case (a float (nq,) array within the limits); ``config_errors``, ``error_from`` and
``cost_of`` use ``a.dot(b)`` and Python floats. Each is compared here, bit for bit, with the
code it replaced (copied below as the reference) on the edge cases: NaN, ±inf on a
continuous joint, a value 1e-12 and 1e-6 outside, exactly on a limit, a zero of the other
sign on a zero limit, ints, lists, float32, wrong shapes.
"""

from __future__ import annotations

import math
import numbers
import sys

import numpy as np
import pytest

import scara_opt as so
from scara_opt.errors import InputError, JointLimitError
from scara_opt.ik.base import (
    TOL_CEILING,
    TOL_FLOOR,
    _check_number_full,
    _check_q0_full,
    check_number,
    check_q0,
    check_seed,
    check_tol,
)
from scara_opt.ik.result import SolverOutput
from scara_opt.ik.task import LIMIT_SLACK, config_errors, cost_of, error_from, wrap_angle
from scara_opt.ik.verdict import _in_limits, judge
from tests.conftest import DATA


def random_q(robot: so.Robot, n: int, seed: int) -> np.ndarray:
    """``n`` configurations (n, nq) drawn in the sampling box (±π for continuous joints)."""
    return np.random.default_rng(seed).uniform(robot.sampling_lower, robot.sampling_upper,
                                               (n, robot.nq))


# ------------------------------------------------------------------ the replaced code
def ref_check_q0(robot: so.Robot, q0: object) -> np.ndarray:
    """``check_q0`` before its fast path: its full check, which it falls back to."""
    return _check_q0_full(robot, q0)


def ref_in_limits(robot: so.Robot, out: SolverOutput) -> tuple[np.ndarray, bool, str]:
    """The verdict's clip before its fast path."""
    lower, upper = robot.lower, robot.upper
    q_out = np.asarray(out.q, dtype=float)
    q = np.minimum(np.maximum(q_out, lower), upper)
    over = float(np.abs(q - q_out).max())
    extra = out.message
    bug = not over <= LIMIT_SLACK
    if bug:
        extra = f"solver returned q outside the limits by {over:.3g}; " + extra
        q = np.clip(np.nan_to_num(q_out), lower, upper)
    return q, bug, extra


def ref_config_errors(robot, target, q):
    """``config_errors`` with ``@`` and numpy's wrap."""
    T = robot.fk_checked(q)
    dp = T[:3, 3] - target.position
    if target.kind == "position":
        return dp, None
    if target.kind == "yaw":
        e1, e2 = robot.yaw_basis()
        x = T[:3, 0]
        return dp, float(wrap_angle(math.atan2(float(x @ e2), float(x @ e1)) - target.yaw))
    d = (T[:3, :3] - target.rotation).ravel()
    frob = math.sqrt(float(d @ d))
    return dp, 2.0 * math.asin(min(frob / (2.0 * math.sqrt(2.0)), 1.0))


def ref_error_from(dp, dang):
    err = math.sqrt(float(dp @ dp))
    return err if dang is None else max(err, abs(float(dang)))


def ref_cost_of(target, dp, dang):
    wp, wa = target.weights
    sq = wp**2 * float(dp @ dp)
    return math.sqrt(sq if dang is None else sq + wa**2 * dang**2)


def same_bits(a: object, b: object) -> bool:
    """Equal dtype, shape and bytes (so -0.0 differs from 0.0, and NaN equals itself)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# ------------------------------------------------------------------ the robots and cases
@pytest.fixture(scope="module")
def limit_robots() -> dict[str, so.Robot]:
    """Zero limits (zavar2024's d3 from +0.0, a -0.0 lower limit), a negative-only range
    (panda's joint 4) and continuous joints (±inf limits)."""
    zavar = so.load_robot("zavar2024")
    return {"zavar2024": zavar,
            "minus_zero": zavar.with_limits(theta2=(-0.0, 1.0), theta4=(-1.0, 0.0)),
            "panda": so.Robot.from_urdf(DATA / "panda_dh.urdf", tip="tool"),
            "wrist": so.Robot.from_urdf(DATA / "scara_continuous_wrist.urdf", tip="tool"),
            "continuous": so.Robot.from_urdf(DATA / "continuous_arm.urdf")}


def cases(robot: so.Robot) -> list[tuple[str, object]]:
    """(label, q) edge cases for ``robot``, in and out of the limits, well and ill formed."""
    lower, upper = robot.lower, robot.upper
    mid = np.where(np.isfinite(lower), lower, -1.0) * 0.5 + np.where(
        np.isfinite(upper), upper, 1.0) * 0.5
    out: list[tuple[str, object]] = [("mid", mid.copy()), ("mid list", mid.tolist()),
                                     ("mid float32", mid.astype(np.float32)),
                                     ("mid read-only", _read_only(mid)),
                                     ("mid strided", np.repeat(mid, 2)[::2]),
                                     ("rounded ints", np.round(mid).astype(int)),
                                     ("too long", np.append(mid, 0.0)),
                                     ("row", mid[None, :].copy()), ("column", mid[:, None].copy()),
                                     ("big", np.full(robot.nq, 1e308))]
    for k in range(robot.nq):
        for side, limit, step in (("lower", lower[k], -1.0), ("upper", upper[k], 1.0)):
            if not np.isfinite(limit):
                out.append((f"{side} inf at {k}", _with(mid, k, step * math.inf)))
                out.append((f"{side} max float at {k}", _with(mid, k, step * sys.float_info.max)))
                continue
            out.append((f"on {side} {k}", _with(mid, k, limit)))
            out.append((f"1e-12 beyond {side} {k}", _with(mid, k, limit + step * 1e-12)))
            out.append((f"1e-6 beyond {side} {k}", _with(mid, k, limit + step * 1e-6)))
            out.append((f"next float beyond {side} {k}",
                        _with(mid, k, np.nextafter(limit, step * math.inf))))
            if limit == 0.0:
                out.append((f"other zero on {side} {k}",
                            _with(mid, k, -math.copysign(0.0, limit))))
        out.append((f"nan at {k}", _with(mid, k, math.nan)))
    return out


class _Sub(np.ndarray):
    """An ndarray subclass (the fast paths take plain ndarrays only)."""


def _with(q: np.ndarray, k: int, v: float) -> np.ndarray:
    q = q.copy()
    q[k] = v
    return q


def _read_only(q: np.ndarray) -> np.ndarray:
    q = q.copy()
    q.flags.writeable = False
    return q


def _outcome(f, *args):
    """What ``f(*args)`` gives: ("ok", value) or ("raise", type, message)."""
    try:
        return ("ok", f(*args))
    except Exception as exc:  # noqa: BLE001  (the type and message are compared)
        return ("raise", type(exc), str(exc))


NAMES = ["zavar2024", "minus_zero", "panda", "wrist", "continuous"]


# ------------------------------------------------------------------ fits_limits
@pytest.mark.parametrize("name", NAMES)
def test_fits_limits_is_true_exactly_when_the_clip_leaves_q_bit_for_bit(limit_robots, name):
    """``fits_limits`` on every edge case: True iff a float64 (nq,) ndarray is finite and the
    clip to the limits leaves it unchanged bit for bit; on a limit is inside.

    Mutations caught: no finite bound for continuous joints (``(lo, hi)`` kept ±inf: +inf
    and -inf pass); ``lo < v < hi`` for ``lo <= v <= hi`` (on a limit refused); no
    zero-sign loop (-0.0 on a +0.0 limit passes); no dtype check (ints and float32 pass).
    """
    robot = limit_robots[name]
    for label, q in cases(robot):
        want = (type(q) is np.ndarray and q.dtype == np.float64 and q.shape == (robot.nq,)
                and bool(np.isfinite(q).all())
                and same_bits(np.minimum(np.maximum(q, robot.lower), robot.upper), q))
        assert robot.fits_limits(q) is want, label
        if label.startswith("on ") or label == "mid" or "max float" in label:
            assert want, label  # these cases are inside: the fast path takes them
    assert not robot.fits_limits(cases(robot)[0][1].view(_Sub))  # an ndarray subclass


def test_fits_limits_follows_with_limits(limit_robots):
    """A robot from ``with_limits`` has its own table (the parent's is not carried over).

    Mutation caught: the table copied by ``with_limits`` (its name added to copies.CORE).
    """
    zavar = limit_robots["zavar2024"]
    q = np.array([0.0, 0.0, 0.01, 2.0])
    assert zavar.fits_limits(q)
    assert not zavar.with_limits(theta4=(-1.0, 1.0)).fits_limits(q)
    assert zavar.fits_limits(q)


# ------------------------------------------------------------------ check_q0
@pytest.mark.parametrize("name", NAMES)
def test_check_q0_gives_what_the_full_check_gave(limit_robots, name):
    """``check_q0`` on every edge case: the same array (the same object when the full check
    handed back ``q0`` itself), or the same error type and message.

    Mutations caught: the fast path returning a copy (not ``q0`` itself); the finite bound
    dropped (+inf on a continuous joint accepted instead of an InputError); no dtype check
    (an int array handed back as ints).
    """
    robot = limit_robots[name]
    for label, q in cases(robot):
        new, old = _outcome(check_q0, robot, q), _outcome(ref_check_q0, robot, q)
        assert new[0] == old[0], (label, new, old)
        if new[0] == "raise":
            assert new[1:] == old[1:], label
            assert issubclass(new[1], (InputError, JointLimitError)), label
        else:
            assert same_bits(new[1], old[1]), label
            assert (new[1] is q) == (old[1] is q), label


# ------------------------------------------------------------------ the verdict's clip
@pytest.mark.parametrize("name", NAMES)
def test_verdict_clip_gives_what_the_numpy_clip_gave(limit_robots, name):
    """The verdict's in-limit ``q``, bug flag and message on every edge case, bit for bit
    (-0.0 on a +0.0 limit comes back as the limit's +0.0), and never the solver's array.

    Mutations caught: the copy dropped (``q`` is the solver's own array); no zero-sign loop
    (-0.0 kept where the clip gave +0.0); the finite bound dropped (+inf passed on instead
    of a solver_error at the largest float); ``<`` for ``<=`` caught by the fits_limits test.
    """
    robot = limit_robots[name]
    for label, q in cases(robot):
        if np.ndim(q) != 1 or np.shape(q)[0] != robot.nq:
            continue  # a solver's q has the robot's shape (numpy would not broadcast it)
        out = SolverOutput(q=q, message="m")
        with np.errstate(invalid="ignore"):  # inf - inf in both clips' overshoot
            new, old = _in_limits(robot, out), ref_in_limits(robot, out)
        assert same_bits(new[0], old[0]) and new[1:] == old[1:], (label, new, old)
        assert new[0] is not q and not np.shares_memory(new[0], np.asarray(q)), label
        assert new[0].flags.writeable and new[0].flags.c_contiguous, label


def test_verdict_statuses_of_the_edge_cases(limit_robots):
    """End to end through ``judge``: in the limits or 1e-12 outside is judged (solved here);
    1e-6 outside, NaN or +inf is a solver_error at an in-limit point; the result's ``q`` is
    not the solver's array (a later change to it does not reach the result).

    Mutation caught: the copy dropped (the result's q changes with the solver's array).
    """
    robot = limit_robots["wrist"]
    q = np.array([0.3, -0.4, 0.0, 1.0])
    target = so.Target(robot.fk(q)[:3, 3])
    kw = {"tol": 1e-9, "method": "x", "seed": 0, "time_s": 0.0}
    for v in (0.0, -1e-12):
        res = judge(robot, target, SolverOutput(q=_with(q, 2, v)), **kw)
        assert (res.status, res.reason) == ("solved", "reached"), v
        assert robot.within_limits(res.q) and same_bits(res.q[2], 0.0)
    missed = so.Target(robot.fk(_with(q, 2, 0.02))[:3, 3])  # the clipped q misses it
    res = judge(robot, missed, SolverOutput(q=_with(q, 2, -1e-6)), **kw)
    assert (res.status, res.reason) == ("failed", "solver_error")
    assert "outside the limits by 1e-06" in res.message and same_bits(res.q[2], 0.0)
    for bad in (_with(q, 0, math.nan), _with(q, 3, math.inf)):
        with np.errstate(invalid="ignore"):  # inf - inf in the clip's overshoot
            res = judge(robot, missed, SolverOutput(q=bad), **kw)
        assert (res.status, res.reason) == ("failed", "solver_error")
        assert np.isfinite(res.q).all() and robot.within_limits(res.q)
    q_out = q.copy()
    res = judge(robot, target, SolverOutput(q=q_out), **kw)
    q_out[0] = 1.0
    assert res.q[0] == 0.3 and res.success


# ------------------------------------------------------------------ task errors and costs
@pytest.mark.parametrize("name", ["zavar2024", "nguyen", "panda", "continuous"])
def test_task_errors_are_bit_identical_to_the_matmul_forms(limit_robots, robots, name):
    """``config_errors``, ``error_from`` and ``cost_of`` give the numbers of the ``@`` and
    numpy-wrap forms they replaced, bit for bit, for position, yaw (several turns off, so
    the wrap works) and rotation targets, with unit and other weights; and NaN / inf in
    ``dp`` still give NaN / inf (so ``error <= tol`` is False).

    Mutations caught: the yaw not wrapped (``- target.yaw`` alone); ``x*x + y*y + z*z``
    for ``dp.dot(dp)`` in ``error_from`` (a different last bit on ~20 % of vectors: BLAS
    sums with fused multiply-adds); ``max(abs(float(dang)), err)`` for ``max(err, ...)``
    (a NaN residual with an angle comes back as the angle: ``max`` keeps its first
    argument when the comparison with NaN is False).
    """
    robot = limit_robots[name] if name in limit_robots else robots[name]
    rng = np.random.default_rng(5)
    Q = random_q(robot, 60, seed=6)
    for k, (q, q_t) in enumerate(zip(Q[:30], Q[30:], strict=True)):
        T = robot.fk(q_t)
        weights = (1.0, 1.0) if k % 2 else tuple(rng.uniform(0.1, 10.0, 2))
        targets = [so.Target(T[:3, 3], weights=weights),
                   so.Target.from_pose(T, weights=weights)]
        if robot.yaw_axis is not None:
            targets.append(so.Target(T[:3, 3] + rng.normal(0, 1e-6, 3),
                                     yaw=robot.yaw(q_t) + 2 * math.pi * rng.integers(-5, 6)
                                     + rng.normal(0, 1e-3), weights=weights))
        for t in targets:
            for qq in (q, q_t):
                dp, dang = config_errors(robot, t, qq)
                rdp, rdang = ref_config_errors(robot, t, qq)
                assert same_bits(dp, rdp) and type(dang) is type(rdang), (k, t.kind)
                assert dang is None or same_bits(dang, rdang), (k, t.kind)
                assert same_bits(error_from(dp, dang), ref_error_from(rdp, rdang))
                assert same_bits(cost_of(t, dp, dang), ref_cost_of(t, rdp, rdang))
    for dp in rng.normal(size=(2000, 3)) * 10.0 ** rng.integers(-14, 1, (2000, 1)):
        for dang in (None, 1e-7):
            assert same_bits(error_from(dp, dang), ref_error_from(dp, dang))
    for bad, want in (([math.nan, 0, 0], math.nan), ([math.inf, 0, 0], math.inf),
                      ([-math.inf, math.nan, 0], math.nan)):
        for dang in (None, 0.5):
            assert same_bits(error_from(np.array(bad), dang), want)
            assert not error_from(np.array(bad), dang) <= 1.0


def test_fk_checked_returns_a_new_array_each_call(ur5_arm):
    """``fk_checked`` hands back a 4×4 of its own: a later FK does not change it.

    Mutation caught: the pose written into one buffer kept on the robot and returned.
    """
    q1, q2 = random_q(ur5_arm, 2, seed=3)
    T1 = ur5_arm.fk_checked(q1)
    keep = T1.copy()
    T2 = ur5_arm.fk_checked(q2)
    assert not np.shares_memory(T1, T2) and np.array_equal(T1, keep)
    assert not np.array_equal(T1, T2)


# ------------------------------------------------------------------ option checks
def ref_check_number(name, value, low, high=math.inf, *, integer=False, low_open=False,
                     high_open=False):
    """``check_number`` before its fast path: its full check, which it falls back to."""
    _check_number_full(name, value, low, high, integer=integer, low_open=low_open,
                       high_open=high_open)


def ref_check_tol(tol):
    ok = isinstance(tol, numbers.Real) and not isinstance(tol, (bool, np.bool_))
    # an int is finite at any size (10**400: an InputError, not math.isfinite's OverflowError)
    if not (ok and (isinstance(tol, numbers.Integral) or math.isfinite(tol)) and tol > 0):
        raise InputError(f"tol must be a positive number [m, rad]; got {tol!r}")
    if tol < TOL_FLOOR:
        raise InputError("floor")
    if tol > TOL_CEILING:
        raise InputError("ceiling")
    return float(tol)


VALUES = [0, 1, -1, 2, 10, 50, 10_000, 10_001, 2**53, 2**53 + 1, -(2**53) - 1, 10**400,
          0.0, -0.0, 0.5, 1.0, 1.5, 2.0, 4.0, 1e-300, math.nan, math.inf, -math.inf, True,
          False, np.int64(3), np.float64(0.5), np.float32(0.5), np.bool_(True), "1", None,
          1e-16, 1e-15, 1e-9, 1.0 + 1e-16, 1.0000001]


def test_option_checks_give_what_the_full_checks_gave():
    """``check_number``, ``check_tol`` and ``check_seed`` on ints (huge ones too), floats,
    NaN, ±inf, bools, numpy scalars and strings, at and beside each end of open and closed
    ranges: the same value or the same error (type and message) as the full checks.

    Mutations caught: the fast path taking any int (``10**400`` accepted where the full
    check's ``math.isnan`` overflows); taking floats for ``integer=True``; a closed end
    where it is open; check_tol's fast path without its range (1e-16 accepted); check_seed
    taking bools (``type(seed) is int`` weakened to ``isinstance``).
    """
    ranges = [(0, 10_000, True, False, False), (1, 100_000, True, False, False),
              (0.0, 1.0, False, False, False), (0.0, 1.0, False, True, False),
              (0.0, 2.0, False, True, True), (0.0, math.inf, False, False, False),
              (1, math.inf, True, False, False), (-1.0, 1.0, False, False, True)]
    for low, high, integer, low_open, high_open in ranges:
        for value in VALUES + [low, high]:
            kw = {"integer": integer, "low_open": low_open, "high_open": high_open}
            new = _outcome(lambda v, a=(low, high), kw=kw: check_number("x", v, *a, **kw), value)
            old = _outcome(lambda v, a=(low, high), kw=kw: ref_check_number("x", v, *a, **kw),
                           value)
            assert new == old, (value, low, high, kw)
    for value in VALUES:
        new, old = _outcome(check_tol, value), _outcome(ref_check_tol, value)
        assert new[0] == old[0] and (new[0] == "raise" or same_bits(new[1], old[1])), value
        assert new[0] == "ok" or new[1] is old[1], value  # (messages: the full check's)
        seed_new = _outcome(check_seed, value)
        ok = value is None or (isinstance(value, (int, np.integer))
                               and not isinstance(value, (bool, np.bool_)) and value >= 0)
        assert (seed_new[0] == "ok") == ok and (not ok or seed_new[1] is value), value


def test_unknown_option_is_refused_with_the_names():
    """An option a solver does not take: SolverOptionError listing the unknown ones only;
    defaults alone and known options are taken.

    Mutation caught: ``options.keys() >= defaults.keys()`` for ``<=`` (every call with
    fewer options than the defaults refused).
    """
    from scara_opt.errors import SolverOptionError
    from scara_opt.ik.registry import get_solver

    assert get_solver("lm").options == {"restarts": 50, "max_iter": 100, "jit": True,
                                        "nearest": True, "analytic": True}
    assert get_solver("lm", restarts=3).options["restarts"] == 3
    with pytest.raises(SolverOptionError) as info:
        get_solver("lm", restarts=3, bogus=1, other=2)
    assert info.value.unknown == ["bogus", "other"]


# ------------------------------------------------------------------ IKResult._new
def test_ikresult_new_is_the_dataclass_with_every_field():
    """``IKResult._new`` with every field gives what ``IKResult(...)`` gives (equal, frozen,
    the same attributes); with some fields missing it falls back to the constructor's
    defaults; with an unknown name, its TypeError.

    Mutation caught: the fall-back removed (missing fields left unset: AttributeError).
    """
    import dataclasses

    from scara_opt.ik.result import IKResult, Status

    robot = so.load_robot("zavar2024")
    q = np.array([0.3, -0.4, 0.01, 1.0])
    res = judge(robot, so.Target(robot.fk(q)[:3, 3]), SolverOutput(q=q), tol=1e-9,
                method="lm", seed=0, time_s=0.0)
    again = IKResult(**vars(res))
    assert res == again and vars(res).keys() == vars(again).keys()
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.error = 0.0  # type: ignore[misc]
    some = {"q": q, "success": True, "status": Status.SOLVED, "message": "m",
            "position_error": np.zeros(3), "yaw_error": None, "error": 0.0, "cost": 0.0,
            "iterations": 1, "evaluations": 1, "time_s": 0.0}
    short, full = IKResult._new(**some), IKResult(**some)
    for f in dataclasses.fields(IKResult):
        assert same_bits(getattr(short, f.name), getattr(full, f.name)), f.name
    with pytest.raises(TypeError):
        IKResult._new(**some, bogus=1)
