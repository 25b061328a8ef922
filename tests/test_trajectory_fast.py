"""The fast ruckig timing: its pieces bit for bit, and the fast paths of its input checks.

``time_parameterize(method="ruckig")`` converts Ruckig's profiles joint by joint on Python
floats, reuses one Ruckig calculator per trajectory, and skips the numpy checks of plain
inputs (a float64 waypoint array, float64 limits within range). Each fast part is compared
here with the slow one it replaced: the old per-joint numpy conversion (kept below as the
reference) and the full checks (the fast path switched off).
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.interpolate import PPoly

import scara_opt as so
from scara_opt import paths
from scara_opt.errors import TrajectoryError
from scara_opt.trajectory import (
    ik_path,
    passing,
    registry,
    resolve_limits,
    ruckig_point_to_point,
    time_parameterize,
)
from scara_opt.trajectory import limits as limits_mod
from scara_opt.trajectory import waypoints as waypoints_mod
from scara_opt.trajectory.limits import LIMIT_RANGES, _per_joint
from scara_opt.trajectory.ruckig_backend import (
    _add_phases,
    _Ruckig,
    _timed_pieces,
    _within_position_limits,
    ruckig_segment,
)
from scara_opt.trajectory.trajectory import concatenate
from scara_opt.trajectory.waypoints import DUPLICATE_TOL, LIMIT_SLACK, prepare_waypoints

DEG, MM = math.pi / 180, 1e-3
FANG_MOVES = [np.array([(0.0, 0.0, 0.0, -15.0), (-64.4042, 128.8085, 15.1500, -61.4099)]),
              np.array([(64.4042, 128.8085, 15.15, 61.4099),
                        (-52.6250, -106.8207, 0.03, -52.7509)])]
FANG_UNITS = np.array([DEG, DEG, MM, DEG])


# ------------------------------------------------------------- the reference conversion
def _reference_pieces(t, j, a, v, p, duration: float) -> PPoly:
    """The conversion before the fast one (per joint, numpy on arrays of 7), verbatim."""
    keep = t > 1e-14
    breaks = np.concatenate([[0.0], np.cumsum(t[keep])])
    coeffs = np.array([j[keep] / 6, a[:-1][keep] / 2, v[:-1][keep], p[:-1][keep]])
    if not keep.any():
        coeffs = np.array([[0.0], [0.0], [0.0], [p[-1]]])
        breaks = np.array([0.0, duration])
    elif breaks[-1] < duration - 1e-12:
        coeffs = np.hstack([coeffs, [[0.0], [0.0], [0.0], [p[-1]]]])
        breaks = np.append(breaks, duration)
    else:
        breaks[-1] = duration
    return PPoly.construct_fast(coeffs, breaks, extrapolate=False)


def _reference_trajectory(Q: np.ndarray, limits, V: np.ndarray | None = None
                          ) -> tuple[list[PPoly], np.ndarray]:
    """Fresh Ruckig objects per segment, each joint converted alone, then concatenated.

    ``V``: the waypoint velocities (default: rest at each).
    """
    import ruckig

    nq = Q.shape[1]
    V = np.zeros_like(Q) if V is None else V
    segments, durations = [], []
    for i, (qa, qb) in enumerate(zip(Q[:-1], Q[1:], strict=True)):
        otg, inp, out = ruckig.Ruckig(nq), ruckig.InputParameter(nq), ruckig.Trajectory(nq)
        inp.current_position, inp.target_position = list(qa), list(qb)
        inp.current_velocity, inp.target_velocity = list(V[i]), list(V[i + 1])
        inp.max_velocity, inp.max_acceleration = list(limits.vmax), list(limits.amax)
        inp.max_jerk = list(limits.jmax)
        inp.synchronization = ruckig.Synchronization.Time
        otg.calculate(inp, out)
        T = float(out.duration)
        fields = [np.array([getattr(prof, name) for prof in out.profiles[0]], dtype=float)
                  for name in ("t", "j", "a", "v", "p")]
        segments.append([_reference_pieces(*(f[k] for f in fields), T) for k in range(nq)])
        durations.append(T)
    pieces = [concatenate([seg[k] for seg in segments]) for k in range(nq)]
    return pieces, np.concatenate([[0.0], np.cumsum(durations)])


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _cases() -> list[tuple[so.Robot | None, np.ndarray, dict]]:
    """Robot, waypoints, limits: fang's moves, zavar's circle, seeded random paths with
    joints that do not move, tiny and large moves, one to six joints."""
    fang, zavar = so.load_robot("fang"), so.load_robot("zavar2024")
    out = [(fang, Q * FANG_UNITS, {}) for Q in FANG_MOVES]
    out.append((zavar, ik_path(zavar, paths.zavar2024_circle(True)).q, {}))
    rng = np.random.default_rng(20261125)
    for _ in range(40):
        n, nq = int(rng.integers(2, 6)), int(rng.integers(1, 7))
        Q = rng.normal(size=(n, nq)) * rng.choice([1e-6, 1e-3, 1.0, 10.0])
        Q[:, rng.random(nq) < 0.3] = 0.0                      # joints that do not move
        Q[:, 0] += np.arange(n)                                # no duplicate waypoints
        out.append((None, Q, {"vmax": rng.uniform(0.1, 5, nq), "amax": rng.uniform(0.5, 50, nq),
                              "jmax": float(rng.uniform(5, 500))}))
    return out


def test_ruckig_pieces_equal_the_reference_conversion_bit_for_bit():
    """Same breaks, coefficients (dtype, shape, every bit), duration and waypoint times as
    the per-joint numpy conversion with fresh Ruckig objects per segment: at rest at every
    waypoint, and joined at the path's velocities.

    Each after a timing of the same joints under other limits (most fail: -101), which
    leaves this thread's kept Ruckig set as it may, and the rest-to-rest conversion after
    a joined one. Mutations caught: the limits set only when the set is made; ``x / 6`` ->
    ``x * (1 / 6)`` (differs in the last bit); ``ends[-1] = duration`` dropped (the last
    break is the phases' sum, not the duration); the segment start not added to the
    breaks; ``c`` in Fortran order (the values the same); the velocities of a joined
    timing not reset (``self.moving[0] = False`` and the reset dropped) -> the next
    rest-to-rest conversion differs.
    """
    for robot, Q, kw in _cases():
        try:  # this thread's kept Ruckig set, left by a failure under other limits
            time_parameterize(Q, robot, method="ruckig", **{**kw, "vmax": 1e-6, "jmax": 1e3})
        except TrajectoryError:
            pass
        limits = resolve_limits(robot, Q.shape[1], need_jerk=True, **kw)
        runs = [None]
        if len(Q) > 2:
            V = passing.passing_velocities(Q, limits)
            runs.insert(0, _within_position_limits(_Ruckig(Q.shape[1], limits), Q, V, limits))
        for V in runs:
            ours, times = _timed_pieces(Q, limits, V)
            pieces, ref_times = _reference_trajectory(Q, limits, V)
            assert _same_bits(np.array(times), ref_times)
            for mine, ref in zip(ours, pieces, strict=True):
                assert _same_bits(mine.x, ref.x) and _same_bits(mine.c, ref.c)
                assert mine.c.flags.c_contiguous and mine.extrapolate is False
        traj = time_parameterize(Q, robot, method="ruckig", **kw)
        if len(Q) == 2:  # rest to rest, and the public one-segment helper too
            assert _same_bits(traj.waypoint_times, ref_times)
            assert traj.duration == pieces[0].x[-1]
            seg, T = ruckig_segment(Q[0], Q[1], limits)
            assert T == ref_times[-1]
            assert all(_same_bits(s.x, r.x) and _same_bits(s.c, r.c)
                       for s, r in zip(seg, pieces, strict=True))


def test_each_thread_keeps_its_own_ruckig_set(robots):
    """The same set within a thread, another in another thread; four threads timing fang's
    two moves at once get the serial answer, bit for bit.

    Mutation: one set for all threads (``_LOCAL = threading``) -> fails.
    """
    fang = robots["fang"]
    limits = resolve_limits(fang, 4, need_jerk=True)
    mine = _Ruckig(4, limits).otg
    assert _Ruckig(4, limits).otg is mine
    with ThreadPoolExecutor(1) as pool:
        assert pool.submit(lambda: _Ruckig(4, limits).otg).result() is not mine

    moves = [Q * FANG_UNITS for Q in FANG_MOVES] * 2

    def bits(Q):
        traj = time_parameterize(Q, fang, method="ruckig")
        return [(p.x.tobytes(), p.c.tobytes()) for p in traj.pieces]

    serial = [bits(Q) for Q in moves]
    with ThreadPoolExecutor(4) as pool:
        for _ in range(50):
            assert list(pool.map(bits, moves)) == serial


def test_ruckig_phases_ending_early_rest_and_ending_late_are_refused():
    """The last kept phase is stretched to the duration; one ending before the phase before
    it would give decreasing breaks (PPoly skips its checks), and phases ending more than
    1e-12 s early get a rest at the target. Ruckig's synchronised profiles do neither (the
    fang and random moves above never reach these branches), so a made-up profile: phases
    of 0.5, 0.5 and 0.2 s in a segment of 0.8 s, 1.2 s + 1e-13 s and 1.25 s.

    Mutations caught: _add_phases without its ``elif ends[-2] > duration`` branch; the
    rest appended only for a joint that does not move (``not ends`` alone).
    """
    t = [0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.2]
    prof = SimpleNamespace(t=t, j=[1.0] * 7, a=[0.0] * 8, v=[0.0] * 8, p=[0.0] * 7 + [2.0])

    def pieces(duration):
        rows = [[], [], [], [], [0.0]]
        _add_phases(rows, prof, 0.0, duration)
        return rows

    with pytest.raises(TrajectoryError, match=r"phases end at 1\.0 s, after its duration 0\.8"):
        pieces(0.8)
    *cubic, breaks = pieces(1.2 + 1e-13)  # the last end becomes the duration
    assert breaks == [0.0, 0.5, 1.0, 1.2 + 1e-13] and cubic[0] == [1 / 6] * 3
    *cubic, breaks = pieces(1.25)  # ends early: rests at the target
    assert breaks == [0.0, 0.5, 1.0, 1.2, 1.25] and [row[-1] for row in cubic] == [0, 0, 0, 2]


# --------------------------------------------------------------- the limits' fast path
LIMIT_INPUTS = [
    np.array([1.0, 2.0, 3.0, 4.0]), np.array([1e-6, 1e6, 1e-6, 1e6]),
    np.array([1e-6 * (1 - 1e-15), 1.0, 1.0, 1.0]), np.array([1.0, 1e6 * (1 + 1e-15), 1, 1]),
    np.array([1.0, np.nan, 1.0, 1.0]), np.array([1.0, np.inf, 1.0, 1.0]),
    np.array([1.0, -np.inf, 1.0, 1.0]), np.array([0.0, 1.0, 1.0, 1.0]),
    np.array([-0.0, 1.0, 1.0, 1.0]), np.array([-1.0, 1.0, 1.0, 1.0]),
    np.array([1, 2, 3, 4]), np.array([1.0, 2.0, 3.0, 4.0], dtype=np.float32),
    np.array([1.0, 2.0, 3.0, 4.0]).astype(">f8"), np.array([1.0, 2.0, 3.0]),
    np.array([[1.0, 2.0, 3.0, 4.0]]), np.array(2.0), np.ma.masked_array([1.0, 2, 3, 4]),
    [1.0, 2.0, 3.0, 4.0], 2.0, 2, 1e-6, 1e6, 1e-7, 1e7, 0.0, -0.0, -2.0, math.nan, math.inf,
    np.float64(2.0), True, "2", None, [1.0, "a", 3.0, 4.0],
]


def _outcome(fn, *args):
    try:
        out = fn(*args)
    except Exception as exc:  # noqa: BLE001 - compared by type and message
        return type(exc), str(exc)
    return type(out), out.dtype, out.shape, out.tobytes()


@pytest.mark.parametrize("value", LIMIT_INPUTS, ids=repr)
@pytest.mark.parametrize("what", sorted(LIMIT_RANGES))
def test_limit_fast_path_agrees_with_the_full_check(monkeypatch, value, what):
    """Same array (type, dtype, shape, bits) or same error (type and message) as the full
    check, on limits at and just beyond the range ends, NaN, ±inf, ±0, ints, float32,
    big-endian, masked, misshaped, scalars of every kind; plain values take the fast path.

    Mutations caught: ``_in_range`` checking no entry (NaN, 0, inf pass); not checking the
    shape ((3,) passes for 4 joints); ``low <= v`` -> ``0 <= v`` (1e-6 x (1 - 1e-15) passes);
    a float returned without its range check (1e7 passes).
    """
    names = ("a", "b", "c", "d")
    fast = _outcome(_per_joint, value, 4, what, "unit", names)
    monkeypatch.setattr(limits_mod, "_in_range", lambda *args: None)
    assert fast == _outcome(_per_joint, value, 4, what, "unit", names)
    monkeypatch.undo()
    plain = ((type(value) is float or (type(value) is np.ndarray and value.dtype == "<f8"
                                      and value.shape == (4,)))
             and fast[0] is np.ndarray)
    assert (limits_mod._in_range(value, 4, what) is not None) == plain


def test_robot_limits_take_the_fast_path_with_the_same_answer(monkeypatch, robots):
    """Every bundled robot's own limits resolve to the same Limits with or without it.

    Mutation: ``pick`` returning the robot's array without ``_in_range`` -> fails for a
    robot whose own limit is out of range (the ``slow`` robot of test_trajectory).
    """
    def resolved(robot):
        try:
            lim = resolve_limits(robot, robot.nq, need_jerk=True)
        except Exception as exc:  # noqa: BLE001 - compared by type and message
            return type(exc), str(exc)
        return tuple(x.tobytes() for x in (lim.vmax, lim.amax, lim.jmax, lim.lower, lim.upper))

    fang = robots["fang"]
    text = fang._init_args[0].replace('acceleration="12.566370614359172"',
                                      'acceleration="1e-9"', 1)
    everyone = [*robots.values(), so.Robot(text, "tool", name="slow")]
    fast = [resolved(r) for r in everyone]
    assert isinstance(fast[-1][0], type) and "own limit" in fast[-1][1]
    monkeypatch.setattr(limits_mod, "_in_range", lambda *args: None)
    assert fast == [resolved(r) for r in everyone]


# ------------------------------------------------------------- the waypoints' fast path
def _waypoint_inputs(robot: so.Robot) -> list[object]:
    lo, hi = robot.lower, robot.upper
    mid = (lo + hi) / 2
    step = np.where(np.isfinite(hi - lo), (hi - lo) / 4, 0.5)
    base = np.array([mid, mid + step])
    edge = np.array([lo - LIMIT_SLACK, hi + LIMIT_SLACK])          # just within the slack
    beyond = np.array([lo - 1.5 * LIMIT_SLACK, hi])               # just beyond it
    dup = base.copy()
    dup[1] = dup[0]
    dup[1, 0] += DUPLICATE_TOL                                     # a duplicate, just
    apart = base.copy()
    apart[1] = apart[0]
    apart[1, 0] = np.nextafter(apart[0, 0] + DUPLICATE_TOL, np.inf)
    nan, inf = base.copy(), base.copy()
    nan[1, 1], inf[0, 2] = np.nan, np.inf
    three = np.array([mid, mid + step, mid + step])
    many = np.linspace(mid, mid + step, 20)                        # beyond FAST_SIZE values
    return [base, edge, beyond, dup, apart, nan, inf, three, many, base[:1], base[:, :2],
            np.asfortranarray(base), base.astype(np.float32), base.astype(">f8"),
            np.round(base).astype(int), base.tolist(), base.ravel(), np.zeros((2, 0)),
            np.ma.masked_array(base), base.reshape(1, 2, -1)]


@pytest.mark.parametrize("name", ["fang", "zavar2024", None])
def test_waypoint_fast_path_agrees_with_the_full_check(monkeypatch, robots, name):
    """Same array (type, dtype, shape, bits, C/F order) or same error (type and message) as
    the full checks on waypoints at and just beyond the limits' slack, a duplicate exactly
    DUPLICATE_TOL apart and one a bit more, NaN, inf, three rows, more than FAST_SIZE
    values, one row, the wrong joint count, Fortran order, float32, big-endian, ints, a
    list, 1-D, 3-D, masked; the plain ones take the fast path.

    Mutations caught: the fast path without the limit check, with ``2 * LIMIT_SLACK``, or
    with ``>=`` for the duplicate test; returning ``path`` itself (not a copy); not
    comparing the joint count with the robot's (a ValueError from zip instead).
    """
    robot = robots[name] if name else None
    inputs = _waypoint_inputs(robot or robots["fang"])
    if robot is None:  # no limits: any finite value passes
        inputs.append(np.array([[-1e300, 0.0], [1e300, 1.0]]))

    def outcome(path):
        try:
            Q = prepare_waypoints(path, robot)
        except Exception as exc:  # noqa: BLE001 - compared by type and message
            return type(exc), str(exc)
        assert Q is not path and not np.shares_memory(Q, np.asarray(path))
        return type(Q), Q.dtype, Q.shape, Q.tobytes(), Q.flags.c_contiguous

    fast = [outcome(p) for p in inputs]
    taken = [waypoints_mod._plain(p, robot) for p in inputs]
    monkeypatch.setattr(waypoints_mod, "_plain", lambda *args: False)
    assert fast == [outcome(p) for p in inputs]
    plain = {0, 1, 4, 11} | ({2, 10, 20} if robot is None else set())  # 2: no limits
    assert taken == [k in plain for k in range(len(inputs))]


# ------------------------------------------------------------ ruckig_point_to_point's pair
@pytest.mark.parametrize("case", ["plain", "same", "outside", "short", "ints", "list",
                                  "float32", "rows", "big-endian"])
def test_point_to_point_pair_agrees_with_the_list(monkeypatch, robots, case):
    """ruckig_point_to_point stacks two float64 (nq,) arrays itself (then the waypoints'
    fast path takes them): the same trajectory, bit for bit, or the same error (type and
    message) as from the list ``[q_start, q_goal]`` it passed before.

    Mutations caught: the pair stacked in the wrong order; stacked without comparing the
    shapes (numpy's ValueError instead of the InputError for a (4,) and a (3,) array).
    """
    fang = robots["fang"]
    a, b = (row.copy() for row in FANG_MOVES[0] * FANG_UNITS)
    args = {"plain": (a, b), "same": (a, a.copy()), "outside": (a, b + [0, 10, 0, 0]),
            "short": (a, b[:3]), "ints": (a.astype(int), b.astype(int)), "list": (list(a), b),
            "float32": (a, b.astype(np.float32)), "rows": (a[None], b[None]),
            "big-endian": (a.astype(">f8"), b.astype(">f8"))}[case]

    def outcome():
        try:
            traj = ruckig_point_to_point(*args, fang)
        except Exception as exc:  # noqa: BLE001 - compared by type and message
            return type(exc), str(exc)
        return (traj.waypoints.tobytes(), traj.waypoint_times.tobytes(),
                [(p.x.tobytes(), p.c.tobytes()) for p in traj.pieces])

    stacked = registry._pair(*args)
    assert isinstance(stacked, np.ndarray) == (case in ("plain", "same", "outside"))
    fast = outcome()
    assert (type(fast[0]) is bytes) == (case in ("plain", "ints", "list", "float32", "big-endian"))
    monkeypatch.setattr(registry, "_pair", lambda q_start, q_goal: [q_start, q_goal])
    assert fast == outcome()
