"""Many IK targets at once: the Levenberg–Marquardt phases of :mod:`scara_opt.ik.lm`, batched.

Where the iterations are compiled, each target's search runs in C, target by target
(:func:`~scara_opt.ik.lm_driver.phase_driver`): the Python work per target is a few µs,
the rest is its iterations. Elsewhere (no C compiler, ``jit=False``) the casadi
iterations are mapped over the targets still running (``Function.map``, padded to a
power of two and evaluated through :meth:`casadi.Function.buffer`), so the Python work is
per iteration round, not per target. Either way each target follows exactly the steps of
:func:`scara_opt.solve_ik` with ``method="lm"``: its ``q0`` (or the default start) first,
then up to ``restarts`` starts from a generator seeded with ``seed`` (the same draws as a
single solve with that seed), so both give the same answers.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from itertools import chain
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import float_array
from scara_opt.errors import InputError
from scara_opt.ik.arm_route import served, solve_nearest
from scara_opt.ik.base import (
    LIMIT_SLACK,
    LazyGenerator,
    check_flag,
    check_q0,
    check_seed,
    check_tol,
)
from scara_opt.ik.lm_driver import phase_driver
from scara_opt.ik.lm_functions import limits, phase_arrays
from scara_opt.ik.lm_run import (
    SLIDE_TOL,
    STALL_CALLS,
    STALL_DECREASE,
    STEP_TOL,
    residual_tol,
    within_tol,
)
from scara_opt.ik.lm_search import check_budget, random_starts, search_filled
from scara_opt.ik.lm_steps import LAMBDA0, LAMBDA_MAX, UNROLL
from scara_opt.ik.problem import nlp_params
from scara_opt.ik.task import check_task, errors_from_poses
from scara_opt.ik.turns import nearest_turns
from scara_opt.model.robot import Array, Robot, check_robot
from scara_opt.target import Target, as_target

#: most targets evaluated in one mapped call
CHUNK = 512


@dataclass(frozen=True)
class BatchResult:
    """Outcome of :func:`solve_many`, one row per target.

    Attributes:
        q: (n, nq) configurations [rad or m], within the joint limits.
        error: (n,) honest residual max(|Δp| [m], |Δangle| [rad]) from the robot's FK.
        success: (n,) ``error <= tol`` (and within the limits).
        iterations: (n,) iterations used over all starts and phases.
        starts: (n,) starts used.
        time_s: wall-clock time of the whole batch [s].
        tol: the tolerance ``success`` was judged against [m, rad].
    """

    q: Array
    error: Array
    success: NDArray[np.bool_]
    iterations: NDArray[np.int64]
    starts: NDArray[np.int64]
    time_s: float
    tol: float

    def __len__(self) -> int:
        return len(self.q)

    def __repr__(self) -> str:
        n, ok = len(self.q), int(np.sum(self.success))
        worst = f", largest error {np.max(self.error):.3g}" if n else ""
        return (f"BatchResult({ok}/{n} solved within tol {self.tol:g}{worst}, "
                f"{self.time_s * 1e3:.2f} ms)")

    __str__ = __repr__


@dataclass(frozen=True)
class _Stacked:
    """Targets of one kind stacked along a first axis (``errors_from_poses`` broadcasts)."""

    kind: str
    position: Array
    yaw: Array | None
    rotation: Array | None


def _targets(robot: Robot, targets: ArrayLike | Sequence[Target]
             ) -> tuple[_Stacked, list[Target] | None]:
    """Stacked targets from an (n, 3) / (n, 4) array [m, rad] or a sequence of Target."""
    if isinstance(targets, Sequence) and targets and isinstance(targets[0], Target):
        ts = [as_target(t) for t in targets]
        kinds = {t.kind for t in ts}
        if len(kinds) != 1:
            raise InputError(f"solve_many takes targets of one kind; got {sorted(kinds)}: call "
                             "it once per kind")
        check_task(robot, ts[0])  # depends on the kind only
        rot = np.array([t.rotation for t in ts]) if ts[0].kind == "rotation" else None
        yaw = np.array([t.yaw for t in ts]) if ts[0].kind == "yaw" else None
        return _Stacked(ts[0].kind, np.array([t.position for t in ts]), yaw, rot), ts
    A = float_array(targets, "targets, an (n, 3) or (n, 4) array [x, y, z(, yaw)] [m, rad] or "
                    "a sequence of Target,")
    if A.ndim != 2 or A.shape[1] not in (3, 4) or len(A) == 0 or not np.isfinite(A).all():
        raise InputError("targets must be a finite, non-empty (n, 3) or (n, 4) array "
                         f"[x, y, z(, yaw)] [m, rad]; got shape {A.shape}")
    if A.shape[1] == 4:
        check_task(robot, Target(A[0, :3], yaw=float(A[0, 3])))
        return _Stacked("yaw", A[:, :3], A[:, 3], None), None
    return _Stacked("position", A, None, None), None


def _q0s(robot: Robot, q0s: ArrayLike | None, n: int) -> Array:
    """(n, nq) references: the default start, one (nq,) for all, or one row per target."""
    if q0s is None:
        return np.tile(limits(robot)[1], (n, 1))
    Q = float_array(q0s, "q0s")
    if Q.ndim == 1:
        return np.tile(cast(Array, check_q0(robot, Q)), (n, 1))
    Q = robot.check_q_batch(Q, "q0s")
    if len(Q) != n:
        raise InputError(f"q0s has {len(Q)} rows for {n} targets; give one per target")
    for row in Q[~robot.within_limits(Q, LIMIT_SLACK)][:1]:
        check_q0(robot, row)  # raises JointLimitError naming the joint, value and range
    return np.clip(Q, robot.lower, robot.upper)


def _params_rows(stacked: _Stacked, ts: list[Target] | None, Q_ref: Array) -> Array:
    """The NLP parameter rows (n, n_par) of every target (see ``problem.nlp_params``)."""
    if ts is not None:
        return np.array([nlp_params(t, q, 0.0) for t, q in zip(ts, Q_ref, strict=True)])
    n = len(Q_ref)
    ang = (np.zeros((n, 0)) if stacked.yaw is None
           else np.column_stack([np.cos(stacked.yaw), np.sin(stacked.yaw)]))
    return np.column_stack([stacked.position, ang, Q_ref, np.ones(n), np.ones(n),
                            np.zeros(n)])


def _call(robot: Robot, phase: str, kind: str, box: Array, inputs: dict[str, Array],
          jit: bool) -> dict[str, Array]:
    """Evaluate a phase Function on the rows of ``inputs``, in padded power-of-two chunks."""
    m = len(inputs["q"])
    chunks: dict[str, list[Array]] = {}
    for lo in range(0, m, CHUNK):
        k = min(CHUNK, m - lo)
        size = 1 << (k - 1).bit_length()
        fa = phase_arrays(robot, kind, size, jit)
        f = getattr(fa, phase)
        fa.box[:] = box
        for name, a in inputs.items():
            f.arg[name][:k] = a[lo:lo + k]
            f.arg[name][k:] = a[lo]  # padding columns repeat a real one
        f()
        for name, a in f.res.items():
            chunks.setdefault(name, []).append(a[:k].copy())
    return {name: np.concatenate(parts) for name, parts in chunks.items()}


@dataclass
class _Batch:
    """What every phase of one start needs: the targets' parameters, limits and budgets."""

    robot: Robot
    kind: str
    par: Array
    box: Array
    e_tol: Array
    max_iter: int
    jit: bool
    nearest: bool

    def descend(self, rows: NDArray[np.intp], Q: Array,
                used: NDArray[np.int64]) -> tuple[Array, Array, NDArray[np.bool_], Array]:
        """Phase 1 (and 3) for ``rows``: (Q, ‖r‖², converged, slide entry); ``used`` grows."""
        n = len(rows)
        Q, lam = Q.copy(), np.full(n, LAMBDA0)
        e, prev, slide = np.full(n, math.inf), np.full(n, math.inf), np.zeros(n)
        stall, conv, active = np.zeros(n, int), np.zeros(n, bool), used[rows] < self.max_iter
        while active.any():
            a = np.flatnonzero(active)
            out = _call(self.robot, "lm", self.kind, self.box,
                        {"q": Q[a], "lam": lam[a, None], "par": self.par[rows[a]]}, self.jit)
            Q[a], lam[a], e[a] = out["q_next"], out["lam_next"][:, 0], out["e_next"][:, 0]
            used[rows[a]] += UNROLL
            ok = (e[a] <= self.e_tol[rows[a]]) & (out["step"][:, 0] <= STEP_TOL)
            conv[a[ok]], slide[a[ok]] = True, out["slide"][ok, 0]
            stall[a] = np.where(e[a] >= (1 - STALL_DECREASE) * prev[a], stall[a] + 1, 0)
            prev[a] = np.minimum(prev[a], e[a])
            stop = ok | (stall[a] >= STALL_CALLS) | (lam[a] >= LAMBDA_MAX)
            active[a[stop | (used[rows[a]] >= self.max_iter)]] = False
        return Q, e, conv | (e <= self.e_tol[rows]), slide

    def slide(self, rows: NDArray[np.intp], Q: Array,
              used: NDArray[np.int64]) -> tuple[Array, NDArray[np.bool_]]:
        """Phase 2 for ``rows``: (Q, moved)."""
        Q, moved = Q.copy(), np.zeros(len(rows), bool)
        active = used[rows] < self.max_iter
        while active.any():  # the Newton step alone first, as lm's slide_toward
            a = np.flatnonzero(active)
            out = _call(self.robot, "newton", self.kind, self.box,
                        {"q": Q[a], "par": self.par[rows[a]]}, self.jit)
            used[rows[a]] += 1
            full = (out["step"][:, 0] == 0) & (out["pull"][:, 0] > SLIDE_TOL)
            if full.any():
                b = a[full]
                more = _call(self.robot, "slide", self.kind, self.box,
                             {"q": Q[b], "par": self.par[rows[b]]}, self.jit)
                for name in out:
                    out[name][full] = more[name]
                used[rows[b]] += 1
            Q[a], step = out["q_next"], out["step"][:, 0]
            moved[a] |= step > 0
            active[a[(step <= SLIDE_TOL) | (used[rows[a]] >= self.max_iter)]] = False
        return Q, moved

    def start(self, rows: NDArray[np.intp], Q0: Array,
              used: NDArray[np.int64]) -> tuple[Array, Array]:
        """All three phases from the starts ``Q0`` of ``rows``: (Q, ‖r‖²)."""
        Q, e, conv, slide = self.descend(rows, Q0, used)
        need = np.flatnonzero(conv & (slide > SLIDE_TOL) & self.nearest)
        if need.size:
            Qs, moved = self.slide(rows[need], Q[need], used)
            m = need[moved]
            if m.size:
                Qp, ep, okp, _ = self.descend(rows[m], Qs[moved], used)
                Q[m[okp]], e[m[okp]] = Qp[okp], ep[okp]
        return Q, e


def solve_many(robot: Robot, targets: ArrayLike | Sequence[Target],
               q0s: ArrayLike | None = None, *,
               tol: float = 1e-9, max_iter: int = 100, restarts: int = 50,
               seed: int | None = 0, jit: bool = True, nearest: bool = True,
               analytic: bool = True) -> BatchResult:
    """Solve IK for many targets at once with the fast solver (``method="lm"``).

    Args:
        robot: the robot.
        targets: an (n, 3) array of positions [m], an (n, 4) array ``[x, y, z, yaw]``
            [m, rad], or a sequence of :class:`~scara_opt.Target` of one kind.
        q0s: ``None`` (default start), one (nq,) ``q0`` for all, or (n, nq), one per
            target; each is the first start and the configuration to stay nearest to
            (whole turns of the revolute joints included, as for ``solve_ik``).
        tol: residual [m, rad] below which a target counts as reached.
        max_iter: iterations per start and target.
        restarts: further seeded random starts for a target whose start stalls.
        seed: seed of each target's generator (the draws of a single solve with it).
        jit: the iterations compiled to C, cached per machine (default True; casadi's
            virtual machine where no compiler works; False: the virtual machine always).
        nearest: slide to the solution nearest each ``q0`` (default True); ``False``: the
            solution the descent reaches (``solve_ik``'s lm option of that name).
        analytic: on the 6R and 7R arms whose closed form serves them
            (:mod:`~scara_opt.ik.arm_route`), full poses go there first, target by target,
            as ``solve_ik``'s lm option of that name (default True); the descent runs on
            the targets it does not solve. ``False``: the descent alone.

    Returns:
        BatchResult: configurations, honest residuals and success flags, one row each.

    Raises:
        InputError: malformed targets or ``q0s``, or targets of mixed kinds.
        TargetError: a yaw for a robot whose tool cannot turn.
        JointLimitError: a ``q0s`` row outside the joint limits.
    """
    clock = time.perf_counter()
    robot = check_robot(robot)
    tol = check_tol(tol)
    check_seed(seed)
    check_budget({"restarts": restarts, "max_iter": max_iter, "jit": jit})
    check_flag("nearest", nearest)
    check_flag("analytic", analytic)
    stacked, ts = _targets(robot, targets)
    n = len(stacked.position)
    Q_ref = _q0s(robot, q0s, n)
    if analytic and ts is not None and stacked.kind == "rotation":
        closed = _closed_form_first(robot, ts, Q_ref, q0s is not None, tol=tol,
                                    max_iter=max_iter, restarts=restarts, seed=seed, jit=jit,
                                    nearest=nearest)
        if closed is not None:
            Q, iterations, starts = closed
            return _result(robot, stacked, Q, iterations, starts, time.perf_counter() - clock,
                           tol, None if q0s is None else Q_ref)
    weights = [t.weights for t in ts] if ts is not None else [(1.0, 1.0)] * n
    batch = _Batch(robot, stacked.kind, _params_rows(stacked, ts, Q_ref), limits(robot)[0],
                   np.array([residual_tol(w, tol) for w in weights]), int(max_iter), bool(jit),
                   nearest)
    near = None if q0s is None else Q_ref  # as solve_ik: the turns nearest a given q0
    if phase_driver(robot, stacked.kind, bool(jit)) is not None:  # the C loop, target by target
        return _result(robot, stacked, *_one_by_one(batch, Q_ref, int(restarts), seed),
                       time.perf_counter() - clock, tol, near)
    best_Q, best_e = Q_ref.copy(), np.full(n, math.inf)
    iterations, starts = np.zeros(n, np.int64), np.zeros(n, np.int64)
    draws: dict[int, Iterator[Array]] = {}  # per target: the draws of a single solve
    rows = np.arange(n)
    for attempt in range(int(restarts) + 1):
        if attempt == 0:
            Q0 = Q_ref[rows]
        else:
            for i in rows[[int(i) not in draws for i in rows]]:
                draws[int(i)] = random_starts(robot, np.random.default_rng(seed), int(restarts))
            Q0 = np.array([next(draws[int(i)]) for i in rows])
        used = np.zeros(n, np.int64)
        Q, e = batch.start(rows, Q0, used)
        iterations += used
        starts[rows] += 1
        better = e < best_e[rows]
        best_Q[rows[better]], best_e[rows[better]] = Q[better], e[better]
        rows = rows[best_e[rows] > within_tol(batch.e_tol[rows])]  # as search_filled
        if not rows.size:
            break
    return _result(robot, stacked, best_Q, iterations, starts, time.perf_counter() - clock, tol,
                   near)


def _closed_form_first(robot: Robot, ts: list[Target], Q_ref: Array, given: bool, *,
                       tol: float, max_iter: int, restarts: int, seed: int | None, jit: bool,
                       nearest: bool
                       ) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]] | None:
    """The arm route's closed form target by target, the descent for what it misses.

    ``None`` where the closed form does not serve the robot (the caller's descent runs on
    every target). Otherwise ``(Q, iterations, starts)``: a closed-form row counts one
    start and no iteration; the rows it leaves go to :func:`solve_many` without it (their
    own ``q0s`` rows where ``given``).
    """
    if served(robot, ts[0]) is None:
        return None
    n = len(ts)
    Q, iterations, starts = Q_ref.copy(), np.zeros(n, np.int64), np.ones(n, np.int64)
    rest = []
    for i, t in enumerate(ts):
        out = solve_nearest(robot, t, Q_ref[i], tol, jit, nearest)
        if out is None:
            rest.append(i)
        else:
            Q[i] = out.q
    if rest:
        left = solve_many(robot, [ts[i] for i in rest], Q_ref[rest] if given else None,
                          tol=tol, max_iter=max_iter, restarts=restarts, seed=seed, jit=jit,
                          nearest=nearest, analytic=False)
        Q[rest], iterations[rest], starts[rest] = left.q, left.iterations, left.starts
    return Q, iterations, starts


def _one_by_one(batch: _Batch, Q_ref: Array, restarts: int, seed: int | None,
                ) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
    """Each target's search as a single solve runs it, in C: (Q, iterations, starts).

    Where the C loop runs (:func:`~scara_opt.ik.lm_driver.phase_driver`), a target costs
    its iterations alone; the mapped rounds' padding and bookkeeping would cost more than
    they save.
    """
    def rng(seed: int | None) -> np.random.Generator:  # seeded at its first draw, as solve_ik
        return cast(np.random.Generator, LazyGenerator(seed))

    n = len(Q_ref)
    f = phase_arrays(batch.robot, batch.kind, 1, batch.jit)
    f.box[0] = batch.box
    Q, iterations, starts = np.empty_like(Q_ref), np.zeros(n, np.int64), np.zeros(n, np.int64)
    for i in range(n):
        f.par[0] = batch.par[i]
        found = search_filled(
            batch.robot, batch.kind, float(batch.e_tol[i]), Q_ref[i],
            chain([Q_ref[i]], random_starts(batch.robot, rng(seed), restarts)),
            max_iter=batch.max_iter, jit=batch.jit, nearest=batch.nearest)
        Q[i], iterations[i], starts[i] = found.q, found.iterations, found.starts
    return Q, iterations, starts


def _result(robot: Robot, stacked: _Stacked, Q: Array, iterations: NDArray[np.int64],
            starts: NDArray[np.int64], time_s: float, tol: float,
            Q_ref: Array | None = None) -> BatchResult:
    """Judge every row by the robot's own FK, as the base does for single solves.

    With ``Q_ref`` (the given ``q0s``), each row first takes the whole turns nearest its
    row of ``Q_ref`` (:func:`~scara_opt.ik.turns.nearest_turns`), as ``solve_ik`` does.
    """
    Q = np.clip(Q, robot.lower, robot.upper)
    if Q_ref is not None:
        Q = nearest_turns(robot, Q, Q_ref)
    dp, dang = errors_from_poses(robot, stacked, robot.fk_batch(Q))  # type: ignore[arg-type]
    error = np.linalg.norm(dp, axis=1)
    if dang is not None:
        error = np.maximum(error, np.abs(dang))
    ok = (error <= tol) & robot.within_limits(Q)
    return BatchResult(Q, error, ok, iterations, starts, time_s, float(tol))
