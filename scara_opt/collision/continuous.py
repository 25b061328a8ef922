r"""Motions proven clear of collision between checked configurations, not sampled and hoped.

**The bound** (:mod:`scara_opt.collision.bound`): along a motion, each checked pair's
bodies move relative to each other by at most :math:`w \cdot |\Delta q|` [m], ``w`` per pair
(:attr:`~scara_opt.collision.checker.CollisionChecker.weights`).

**The rule.** Along a straight joint segment :math:`q(s) = q_a + s\,\Delta q`, the pair's
bodies move relative to each other by at most :math:`s\,M` with
:math:`M = w \cdot |\Delta q|`, so their distance obeys :math:`d(s) \ge d_a - sM` and
:math:`d(s) \ge d_b - (1 - s)M`; the larger of the two is smallest where they cross, at
:math:`(d_a + d_b - M) / 2`. Hence **if** :math:`M < d_a + d_b` **for every pair, the whole
segment is clear**, with at least :math:`(d_a + d_b - M)/2` to spare. Otherwise the interval
is split at its middle, the middle is checked, and each half is tried again
(:func:`prove`). A sample in contact ends the proof (the motion collides); an interval that
still fails when its bound :math:`M` is below :data:`RESOLUTION` (the bodies graze) is not
proven and counts as a contact. With a margin *m*, every *d* is replaced by
*d − m − ε*, ε = :data:`DISTANCE_TOL` covering the distance computation's own tolerance.

**Timed trajectories** are not straight segments: the spline between two samples may bulge
away from their chord. On :math:`[t_0, t_1]` the relative motion is at most
:math:`(t_1 - t_0)\, w \cdot \bar v` with :math:`\bar v_j` a bound on :math:`|\dot q_j|` over
the interval: each polynomial piece's :math:`|\dot q_j|` lies within the range of its
Bernstein coefficients (convex hull property), and an interval takes the largest over the
pieces it covers (:class:`VelocityBound`). The same rule then proves the trajectory
(:func:`check_trajectory`), and the first contact is located to :data:`TIME_TOL`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PPoly

from scara_opt.collision.checker import DISTANCE_TOL, CollisionChecker

if TYPE_CHECKING:
    from scara_opt.model.robot import Robot

Array = NDArray[np.float64]
Index = NDArray[np.intp]

__all__ = ["CollisionReport", "Contact", "LeastClearance", "Proof", "VelocityBound", "check_path",
           "check_trajectory", "collision_report", "deepest", "least", "least_clearance",
           "prove", "prove_segment"]

#: an interval whose motion bound is below this [m] and still not proven is not clear
RESOLUTION = 1e-9

#: the first contact of a trajectory is located to within this [s]
TIME_TOL = 1e-4

#: at most this many configurations are checked in one proof (then: not proven)
MAX_EVALUATIONS = 200_000

#: the least clearance of a trajectory is found to within this [m] (:func:`least_clearance`)
LEAST_TOL = 1e-4


# ---------------------------------------------------------------------------- the proof
@dataclass(frozen=True)
class Contact:
    """Where a motion is first not clear.

    Attributes:
        at: the parameter: ``s`` in [0, 1] along a segment, or the time [s] of a trajectory.
        bodies: the pair of bodies, ``(robot body, other body)``.
        distance: their signed distance there [m] (negative: overlap).
        touching: True if a configuration was found there with the bodies in contact
            (closer than the margin, to within :data:`DISTANCE_TOL`); False if the motion
            only could not be proven clear there (an interval where they graze, or the
            evaluation budget ran out).
    """

    at: float
    bodies: tuple[str, str]
    distance: float
    touching: bool = True

    @property
    def depth(self) -> float:
        """Overlap [m] (0 when they only touch or graze)."""
        return max(0.0, -self.distance)


@dataclass(frozen=True)
class Proof:
    """The outcome of a conservative check of a motion.

    Attributes:
        clear: the whole motion is proven clear (every pair farther than the margin).
        contact: the first place not proven clear (``None`` when clear).
        clearance: a proven lower bound on every pair's distance over the motion [m]: the
            checked pairs and those the checker leaves out as never within reach
            (:attr:`~scara_opt.collision.checker.CollisionChecker.apart`, by their least
            gap); ``inf`` when there is nothing to check; meaningful when ``clear``. Not
            the least clearance (see :func:`least_clearance`): the proof stops as soon as
            every pair is proven farther than the margin.
        evaluations: configurations whose distances were computed.
    """

    clear: bool
    contact: Contact | None
    clearance: float
    evaluations: int


def prove(s: Array, D: Array, config: Callable[[Array], Array],
          bound: Callable[[Array, Array], Array],
          distances: Callable[[Array, Index | None], Array],
          names: tuple[tuple[str, str], ...], *, margin: float = 0.0, locate: bool = False,
          tol: float = 0.0, budget: int = MAX_EVALUATIONS,
          apart: Callable[..., Array] | None = None) -> Proof:
    """Prove the motion between the samples ``s`` clear by the rule of the module docstring.

    All intervals are tried at once, level by level: those where every pair passes are
    done, the others are split at their middle. A pair proven on an interval is proven on
    both its halves: they take its distance at the middle as infinite, and the compiled
    form computes at a middle only the pairs that failed on its interval (here, those
    failing on any interval, then set aside). On the UR5 meshes' timed trajectories of
    benchmarks/bench_plan.py (3 cells), check_path 9.6-12.6 -> 5.2-7.2 ms a call against
    computing at every middle each pair failing on some interval, the same trajectories.
    The clearance is the least of the pairs' lower bounds where each was proven.

    Args:
        s: (m,) increasing parameters of the first samples (the motion's ends included).
        D: (m, npairs) signed distances of every pair at them [m].
        config: parameters (k,) -> configurations (k, nq).
        bound: interval ends (k,), (k,) -> bounds (k, npairs) on each pair's relative motion
            over each interval [m].
        distances: configurations (k, nq) and pair indices (or None: all) -> signed
            distances (k, len) [m].
        names: the pairs' body names.
        margin: clearance to keep [m].
        locate: find the *first* contact to within ``tol`` (else stop at any contact).
        tol: the location tolerance on the parameter.
        budget: most configurations to evaluate; beyond, the rest is not proven.
        apart: optional ``(lo, hi, Qlo, Qhi) -> (k, npairs)`` proven lower bounds on each
            pair's distance over each interval by other means [m], less margin and
            tolerance (> 0: apart there; e.g. a SCARA's height gaps).
    """
    s = np.asarray(s, float)
    shift = margin + DISTANCE_TOL
    D = np.asarray(D, float) - shift
    npairs = D.shape[1]
    if not npairs:
        return Proof(True, None, math.inf, 0)
    contact: Contact | None = None

    def found(at: float, d: Array, sample: bool = True) -> Contact:
        k = int(np.argmin(d))
        dist = float(d[k] + shift)
        return Contact(float(at), names[k], dist, sample)

    bad = np.flatnonzero((D <= 0).any(axis=1))
    if bad.size:
        contact = found(s[bad[0]], D[bad[0]])
        if not locate or bad[0] == 0:
            return Proof(False, contact, -math.inf, 0)
    Q = config(s)
    lo, hi, Dlo, Dhi, Qlo, Qhi = s[:-1], s[1:], D[:-1], D[1:], Q[:-1], Q[1:]
    spare, evals = math.inf, 0
    while lo.size:
        M = bound(lo, hi)
        slack = Dlo + Dhi - M
        fine = np.where((Dlo > 0) & (Dhi > 0), slack / 2, -math.inf)  # per-pair lower bounds
        if apart is not None:
            fine = np.maximum(fine, apart(lo, hi, Qlo, Qhi))
        passed = fine > 0  # the pair proven on the interval: its halves inherit that (inf)
        ok = passed.all(axis=1)
        if passed.any():
            spare = min(spare, float(fine[passed].min()))
        rest = ~ok
        if contact is not None:  # only what lies before the first contact matters
            rest &= (lo < contact.at) & ~((hi >= contact.at) & (hi - lo <= tol))
        if not rest.any():
            break
        lo, hi, Dlo, Dhi, Qlo, Qhi, M = (x[rest] for x in (lo, hi, Dlo, Dhi, Qlo, Qhi, M))
        passed = passed[rest]
        grazing = np.where(passed, 0.0, M).max(axis=1) < RESOLUTION
        if grazing.any() or evals + lo.size > budget:
            k = int(np.argmin(np.where(grazing, lo, np.inf))) if grazing.any() else 0
            c = found(lo[k], np.minimum(Dlo[k], Dhi[k]), sample=False)
            if contact is None or c.at < contact.at:
                contact = c
            if not locate or not grazing.any():
                break
            keep = ~grazing & (lo < contact.at)
            lo, hi, Dlo, Dhi, Qlo, Qhi = (x[keep] for x in (lo, hi, Dlo, Dhi, Qlo, Qhi))
            passed = passed[keep]
            if not lo.size:
                break
        mid = (lo + hi) / 2
        Qm = config(mid)
        cols = np.flatnonzero(~passed.all(axis=0))  # pairs failing somewhere
        Dm = np.full((len(mid), npairs), math.inf)
        Dm[:, cols] = distances(Qm, None if len(cols) == npairs else cols) - shift
        Dm[passed] = math.inf  # proven on the interval (the kernel does not compute them)
        evals += mid.size
        hit = np.flatnonzero((Dm <= 0).any(axis=1))
        if hit.size:
            k = int(hit[np.argmin(mid[hit])])
            if contact is None or mid[k] < contact.at:
                contact = found(mid[k], Dm[k])
            if not locate:
                break
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        Dlo, Dhi = np.concatenate([Dlo, Dm]), np.concatenate([Dm, Dhi])
        Qlo, Qhi = np.concatenate([Qlo, Qm]), np.concatenate([Qm, Qhi])
    if contact is not None:
        return Proof(False, contact, -math.inf, evals)
    return Proof(True, None, shift + spare, evals)


def prove_segment(checker: CollisionChecker, qa: ArrayLike, qb: ArrayLike, *,
                  locate: bool = False) -> Proof:
    """Prove the straight joint segment from ``qa`` to ``qb`` (nq,) clear of collision.

    ``Proof.contact.at`` is the fraction ``s`` in [0, 1] along the segment; with
    ``locate``, the first contact to within 1e-6.
    """
    q0, q1 = checker.robot.check_q(qa, "qa"), checker.robot.check_q(qb, "qb")
    W = checker.weights
    dq = q1 - q0
    M = W @ np.abs(dq)

    def config(s: Array) -> Array:
        return q0 + s[:, None] * dq

    def bound(lo: Array, hi: Array) -> Array:
        return np.outer(hi - lo, M)

    D = checker.pair_distances(np.array([q0, q1]), None, "rest")
    gaps = checker.gaps
    apart: Callable[..., Array] | None = None
    if gaps is not None:
        A, a, b = gaps
        shift = checker.margin + DISTANCE_TOL
        ha, hb = A @ q0, A @ q1  # affine along the segment: the smaller end bounds it

        def heights(lo: Array, hi: Array, Qlo: Array, Qhi: Array) -> Array:
            h0 = np.outer(1 - lo, ha) + np.outer(lo, hb)
            h1 = np.outer(1 - hi, ha) + np.outer(hi, hb)
            return np.maximum(np.minimum(h0, h1) + a, b - np.maximum(h0, h1)) - shift

        apart = heights

    p = prove(np.array([0.0, 1.0]), D, config, bound, checker.pair_distances,
              checker.pair_names, margin=checker.margin, locate=locate, tol=1e-6, apart=apart)
    return _every_pair(checker, replace(p, evaluations=p.evaluations + 2))


def _every_pair(checker: CollisionChecker, proof: Proof) -> Proof:
    """``proof`` with its clearance over the checker's apart pairs too (their least gap)."""
    if proof.clear and checker.apart:
        return replace(proof, clearance=min(proof.clearance, checker.least_apart))
    return proof


# ---------------------------------------------------------------------------- trajectories
class SpeedBounded(Protocol):
    """What :class:`VelocityBound` reads: a trajectory, or a path (:class:`_PathBounds`)."""

    def speed_bounds(self) -> list[tuple[Array, Array]]:
        """Per joint: breakpoints (m + 1,) and a bound (m,) on the speed on each piece."""
        ...


class Trajectory(SpeedBounded, Protocol):
    """What the proofs read of a :class:`~scara_opt.Trajectory` (it imports this module)."""

    @property
    def waypoint_times(self) -> Array:
        """When it passes its waypoints [s]."""
        ...

    @property
    def duration(self) -> float:
        """Its duration [s]."""
        ...

    def evaluate(self, t: ArrayLike, order: int = 0) -> Array:
        """Its joint values (or a derivative) at times ``t`` [s]."""
        ...


class VelocityBound:
    """Bounds on ``|q̇_j|`` over any time interval of a trajectory, per joint.

    From the trajectory's :meth:`~scara_opt.Trajectory.speed_bounds` (a Bernstein bound per
    polynomial piece); an interval takes the largest over the pieces it covers (a sparse
    table answers each query in two lookups). Joints whose pieces share their breakpoints
    (toppra's, a spline's) are looked up together.
    """

    def __init__(self, traj: SpeedBounded) -> None:
        bounds = traj.speed_bounds()
        self.nq = len(bounds)
        groups: list[tuple[Array, list[int]]] = []
        for j, (x, _) in enumerate(bounds):
            for breaks, cols in groups:
                if breaks is x or np.array_equal(breaks, x):
                    cols.append(j)
                    break
            else:
                groups.append((x, [j]))
        # per group: breakpoints, joints, table (levels, pieces, joints): row L the largest
        # over 2**L pieces
        self.groups: list[tuple[Array, list[int], Array]] = []
        for x, cols in groups:
            b = np.column_stack([bounds[j][1] for j in cols])
            rows, step = [b], 1
            while 2 * step <= len(b):
                rows.append(np.maximum(rows[-1][:-step], rows[-1][step:]))
                step *= 2
            table = np.zeros((len(rows),) + b.shape)
            for level, row in enumerate(rows):
                table[level, :len(row)] = row
            self.groups.append((np.asarray(x, float), cols, table))

    def __call__(self, t0: Array, t1: Array) -> Array:
        """Bounds (k, nq) on ``|q̇|`` over each interval ``[t0[i], t1[i]]`` [rad/s or m/s]."""
        out = np.empty((len(t0), self.nq))
        for x, cols, table in self.groups:
            n = table.shape[1]
            a = np.minimum(np.maximum(np.searchsorted(x, t0, side="right") - 1, 0), n - 1)
            b = np.minimum(np.maximum(np.searchsorted(x, t1, side="left") - 1, a), n - 1)
            k = np.minimum(np.log2(b - a + 1).astype(int), table.shape[0] - 1)
            out[:, cols] = np.maximum(table[k, a], table[k, b - (1 << k) + 1])
        return out


def check_trajectory(checker: CollisionChecker, traj: Trajectory, *, locate: bool = True,
                     samples: int = 32) -> Proof:
    """Prove a timed trajectory clear of collision, or find its first contact.

    Args:
        checker: the robot in its cell.
        traj: a :class:`~scara_opt.Trajectory` of the checker's robot.
        locate: find the first contact to within :data:`TIME_TOL` (else any contact).
        samples: intervals of the first, uniform split of the duration (the waypoint times
            are added).

    Returns:
        A :class:`Proof`; ``contact.at`` is the time [s].
    """
    T = traj.duration
    t = np.unique(np.concatenate([np.linspace(0.0, T, samples + 1),
                                  np.clip(traj.waypoint_times, 0.0, T)]))
    return _prove_curve(checker, t, traj.evaluate, VelocityBound(traj), locate, TIME_TOL)


class _PathBounds:
    """A joint path seen as :class:`VelocityBound` sees a trajectory.

    Per joint: the path's breakpoints and a bound on ``|q'(s)|`` on each piece (the
    largest Bernstein coefficient, :func:`~scara_opt.trajectory.bernstein.piece_bounds`).
    """

    def __init__(self, path: PPoly) -> None:
        from scara_opt.trajectory.bernstein import piece_bounds

        x = np.asarray(path.x, float)
        self.per_piece = bounds = piece_bounds(path.derivative())  # (pieces, nq)
        self._bounds = [(x, bounds[:, j]) for j in range(bounds.shape[1])]

    def speed_bounds(self) -> list[tuple[Array, Array]]:
        """Per joint: breakpoints (m + 1,) and a bound (m,) on ``|q'(s)|`` on each piece."""
        return self._bounds


def check_path(checker: CollisionChecker, path: PPoly, *, locate: bool = False) -> Proof:
    r"""Prove a joint path :math:`q(s)` clear of collision over its whole domain.

    The rule of the module docstring with the path parameter in place of time: on
    :math:`[s_0, s_1]` the relative motion of a pair is at most
    :math:`(s_1 - s_0)\, w \cdot \bar v` with :math:`\bar v_j` a bound on
    :math:`|q_j'(s)|` there (each piece's Bernstein coefficients). A trajectory that runs
    along the path, :math:`q(s(t))` with :math:`s(t)` nondecreasing over the domain (as
    every timing of :func:`~scara_opt.motion.timing.time_section` does), visits only its
    configurations: the path proven clear, so is the trajectory.

    Args:
        checker: the robot in its cell.
        path: a :class:`~scara_opt.Trajectory`-free joint path: a ``PPoly`` whose values
            are (nq,) (toppra's ``SplineInterpolator.cspl``), its breakpoints the waypoints.
        locate: find the first contact to within 1e-6 of the parameter.

    Returns:
        A :class:`Proof`; ``contact.at`` is the path parameter.
    """
    x = np.asarray(path.x, float)
    bounds = _PathBounds(path)
    kernel = None if locate else checker._kernel()
    if kernel is not None:  # the same proof, compiled (collision/edge_kernel.cpp)
        c = np.asarray(path.c, float).reshape(path.c.shape[0], len(x) - 1, -1)
        clear, spare, at, dist, pair, touching, evals = kernel.prove_path(
            x, c, bounds.per_piece, checker.weights, checker.gaps, RESOLUTION,
            MAX_EVALUATIONS)
        evals += len(x)
        if clear:
            return _every_pair(checker, Proof(True, None, spare, evals))
        return Proof(False, Contact(at, checker.pair_names[pair], dist, touching), -math.inf,
                     evals)

    def evaluate(u: Array) -> Array:
        return path(np.clip(u, x[0], x[-1]))

    return _prove_curve(checker, x, evaluate, VelocityBound(bounds), locate, 1e-6)


def _prove_curve(checker: CollisionChecker, t: Array, evaluate: Callable[[Array], Array],
                 vel: VelocityBound, locate: bool, tol: float) -> Proof:
    """:func:`prove` over a curve from the samples ``t``, its speed bounded by ``vel``."""
    D = checker.pair_distances(evaluate(t), None, "rest")
    W = checker.weights
    seen: list = [None, None]

    def speeds(lo: Array, hi: Array) -> Array:  # the bound and the gaps ask for the same
        if seen[0] is not lo:
            seen[0], seen[1] = lo, vel(lo, hi)
        return seen[1]

    def bound(lo: Array, hi: Array) -> Array:
        return (hi - lo)[:, None] * (speeds(lo, hi) @ W.T)

    p = prove(t, D, evaluate, bound, checker.pair_distances, checker.pair_names,
              margin=checker.margin, locate=locate, tol=tol,
              apart=_trajectory_gaps(checker, speeds))
    return _every_pair(checker, replace(p, evaluations=p.evaluations + len(t)))


def _trajectory_gaps(checker: CollisionChecker, vel: Callable[[Array, Array], Array],
                     shift: float | None = None) -> Callable[..., Array] | None:
    """A SCARA's height gaps over trajectory intervals (None for other robots).

    On ``[t0, t1]`` each joint stays within ``(q0 + q1)/2 ± v̄ (t1 - t0)/2`` (it cannot go
    farther at speed ``v̄`` and still reach both ends); the gaps are affine in ``q``, so their
    least over that box bounds them (less ``shift``, default the proofs' margin and
    tolerance).
    """
    gaps = checker.gaps
    if gaps is None:
        return None
    A, a, b = gaps
    Ap, An = np.maximum(A, 0.0), np.minimum(A, 0.0)
    if shift is None:
        shift = checker.margin + DISTANCE_TOL

    def apart(lo: Array, hi: Array, Qlo: Array, Qhi: Array) -> Array:
        half = vel(lo, hi) * ((hi - lo) / 2)[:, None]
        mid = (Qlo + Qhi) / 2
        qmin, qmax = mid - half, mid + half
        low = qmin @ Ap.T + qmax @ An.T   # least of A q over the box
        high = qmax @ Ap.T + qmin @ An.T  # largest
        return np.maximum(low + a, b - high) - shift

    return apart


# ---------------------------------------------------------------------------- least clearance
@dataclass(frozen=True)
class LeastClearance:
    """The least clearance of a motion over every pair, found to a stated tolerance.

    ``distance`` is a sampled value (the motion does come this close) and ``lower`` a
    proven lower bound over the whole motion (the bound of the module docstring), with
    ``distance - lower <= tolerance`` when ``converged``: the true least clearance lies
    between them.

    Attributes:
        distance: the least signed distance found [m], at ``at``.
        at: when [s] (or the path parameter).
        bodies: the pair there, ``(robot body, other body)``.
        lower: proven: no pair comes closer than this anywhere along the motion [m].
        tolerance: the tolerance it was found to [m].
        converged: ``distance - lower <= tolerance`` (else the evaluation budget ran out).
        evaluations: configurations whose distances were computed.
    """

    distance: float
    at: float
    bodies: tuple[str, str]
    lower: float
    tolerance: float
    converged: bool
    evaluations: int

    def within(self, budget: str = " (budget)") -> str:
        """``to 0.1 mm``, or ``not to 0.1 mm`` and ``budget`` when the budget ran out."""
        return (f"to {self.tolerance * 1e3:g} mm" if self.converged
                else f"not to {self.tolerance * 1e3:g} mm{budget}")

    def __repr__(self) -> str:
        return (f"LeastClearance({self.distance * 1e3:.3f} mm at {self.at:.4f} s, "
                f"{'-'.join(self.bodies)}, found {self.within(': the budget ran out')}; "
                f"proven >= "
                f"{self.lower * 1e3:.3f} mm)")


def least(s: Array, D: Array, config: Callable[[Array], Array],
          bound: Callable[[Array, Array], Array],
          distances: Callable[[Array, Index | None], Array], tol: float, *,
          budget: int = MAX_EVALUATIONS, apart: Callable[..., Array] | None = None,
          exact: Callable[[Array, Index | None], Array] | None = None
          ) -> tuple[float, float, int, float, bool, int]:
    """The least signed distance over a motion, by branch and bound on its intervals.

    On an interval each pair's distance is at least :math:`(d_a + d_b - M)/2` (the rule of
    the module docstring, any sign) and at least its height gap (``apart``); an interval
    whose least pair bound is within ``tol`` of the least distance sampled so far cannot
    hold anything ``tol`` closer, and is closed; the others are split at their middle,
    where every pair is computed.

    Args:
        s: (m,) the first samples' parameters, as :func:`prove`'s.
        D: (m, npairs) their distances [m], not shifted; with ``exact``, lower bounds.
        config: as :func:`prove`'s.
        bound: as :func:`prove`'s.
        distances: as :func:`prove`'s; with ``exact``, lower bounds.
        tol: the tolerance [m].
        budget: most configurations to evaluate.
        apart: as :func:`prove`'s, with no shift.
        exact: the exact distances, where ``distances`` gives bounds (a mesh's tree of
            hulls): asked only where a bound is below the least found so far, which only
            an exact value may set.

    Returns:
        ``(distance, at, pair, lower, converged, evaluations)``.
    """
    s = np.asarray(s, float)
    D = np.asarray(D, float)
    if exact is not None:
        D = _exact_where_low(s, config(s), D, math.inf, exact)
    k = np.unravel_index(int(np.argmin(D)), D.shape)
    best, at, pair = float(D[k]), float(s[k[0]]), int(k[1])
    Q = config(s)
    lo, hi, Dlo, Dhi, Qlo, Qhi = s[:-1], s[1:], D[:-1], D[1:], Q[:-1], Q[1:]
    lower, evals = best, 0
    while lo.size:
        fine = (Dlo + Dhi - bound(lo, hi)) / 2
        if apart is not None:
            fine = np.maximum(fine, apart(lo, hi, Qlo, Qhi))
        least_bound = fine.min(axis=1)
        done = least_bound >= best - tol
        if done.any():
            lower = min(lower, float(least_bound[done].min()))
        rest = ~done
        if not rest.any():
            break
        if evals + int(rest.sum()) > budget:
            return best, at, pair, min(lower, float(least_bound[rest].min())), False, evals
        lo, hi, Dlo, Dhi, Qlo, Qhi = (x[rest] for x in (lo, hi, Dlo, Dhi, Qlo, Qhi))
        mid = (lo + hi) / 2
        Qm = config(mid)
        Dm = distances(Qm, None)
        if exact is not None:
            Dm = _exact_where_low(mid, Qm, Dm, best, exact)
        evals += mid.size
        i, j = np.unravel_index(int(np.argmin(Dm)), Dm.shape)
        if Dm[i, j] < best:
            best, at, pair = float(Dm[i, j]), float(mid[i]), int(j)
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        Dlo, Dhi = np.concatenate([Dlo, Dm]), np.concatenate([Dm, Dhi])
        Qlo, Qhi = np.concatenate([Qlo, Qm]), np.concatenate([Qm, Qhi])
    return best, at, pair, min(lower, best), True, evals


def _exact_where_low(s: Array, Q: Array, D: Array, best: float,
                     exact: Callable[[Array, Index | None], Array]) -> Array:
    """``D`` (k, npairs) bounds with the exact values where a bound is below ``best``."""
    low = D < best
    out = D.copy()
    for r in np.flatnonzero(low.any(axis=1)):
        cols = np.flatnonzero(low[r])
        out[r, cols] = exact(Q[r:r + 1], cols)[0]
    return out


def least_clearance(checker: CollisionChecker, traj: Trajectory, tol: float = LEAST_TOL, *,
                    samples: int = 32) -> LeastClearance | None:
    """The least clearance of a timed trajectory over every pair, to within ``tol`` [m].

    Every pair the checker reports on (:attr:`~scara_opt.collision.checker.
    CollisionChecker.everything`: its apart pairs too), whatever its margin; by
    :func:`least` from ``samples`` uniform intervals and the waypoint times. ``None`` when
    there is no pair.
    """
    full = checker.everything
    if not full.npairs:
        return None
    T = traj.duration
    t = np.unique(np.concatenate([np.linspace(0.0, T, samples + 1),
                                  np.clip(traj.waypoint_times, 0.0, T)]))
    vel, W = VelocityBound(traj), full.weights
    seen: list = [None, None]

    def speeds(lo: Array, hi: Array) -> Array:
        if seen[0] is not lo:
            seen[0], seen[1] = lo, vel(lo, hi)
        return seen[1]

    def bound(lo: Array, hi: Array) -> Array:
        return (hi - lo)[:, None] * (speeds(lo, hi) @ W.T)

    meshy = full._meshes.any  # bounds first, exact values where they may be the least

    def exact(Q: Array, cols: Index | None) -> Array:
        return full.pair_distances(Q, cols, "exact")

    D = full.pair_distances(traj.evaluate(t), None, "bound" if meshy else "exact")
    d, at, pair, lower, ok, evals = least(t, D, traj.evaluate, bound, full.pair_distances, tol,
                                          apart=_trajectory_gaps(full, speeds, 0.0),
                                          exact=exact if meshy else None)
    return LeastClearance(d, at, full.pair_names[pair], lower, tol, ok, evals + len(t))


def deepest(checker: CollisionChecker, traj: Trajectory, contact: Contact, dt: float = 1e-3
            ) -> float:
    """The largest overlap [m] of the contact's pair while it lasts, sampled every ``dt`` [s]."""
    k = checker.pair_names.index(contact.bodies)
    t, depth, T = contact.at, contact.depth, traj.duration
    while t <= T:
        ts = np.minimum(t + dt * np.arange(1, 65), T)
        d = checker.distances_many(traj.evaluate(ts))[:, k]
        apart = np.flatnonzero(d > checker.margin)
        if apart.size:
            d = d[:apart[0]]
        if d.size:
            depth = max(depth, float(-d.min()))
        if apart.size or ts[-1] >= T:
            break
        t = float(ts[-1])
    return max(depth, 0.0)


@dataclass(frozen=True)
class CollisionReport:
    """A trajectory proven clear of its cell, or its first contact.

    Two numbers for a clear trajectory, not to be confused: ``least`` is how close it
    comes to the cell (the least clearance over every pair along the whole trajectory,
    found to a stated tolerance: :func:`least_clearance`), ``clearance`` what is proven
    (no pair comes closer anywhere; with ``least`` it is ``least.lower``).

    Attributes:
        clear: proven clear (every pair farther than the margin all along).
        time: when the first contact begins [s], to :data:`TIME_TOL` (``None`` when clear).
        bodies: the pair in contact, ``(robot body, other body)`` (``None`` when clear).
        depth: the deepest overlap of that pair during that contact [m], sampled at 1 kHz
            (0 for a contact that is only not proven: grazing).
        touching: the bodies really touch (not only a part not proven clear).
        clearance: a proven lower bound on the clearance over the whole trajectory, every
            pair [m] (``inf``: nothing to check; ``-inf`` when not clear).
        margin: the clearance that was required [m].
        evaluations: configurations whose distances were computed (the least clearance's
            search included).
        least: the least clearance found (``None``: not asked for, not clear, or nothing
            to check).
    """

    clear: bool
    time: float | None
    bodies: tuple[str, str] | None
    depth: float
    touching: bool
    clearance: float
    margin: float
    evaluations: int
    least: LeastClearance | None = None

    @property
    def ratio(self) -> float:
        """Required over proven clearance: <= 1 means proven clear with the margin.

        ``inf`` when not clear; 0 with no margin.
        """
        if not self.clear:
            return math.inf
        return 0.0 if self.margin == 0 else self.margin / self.clearance

    def clearance_text(self) -> str:
        """The two numbers in words, as the command line prints them.

        ``least clearance 2.247 mm at 0.7469 s (link4-rack), found to 0.1 mm; proven >=
        2.147 mm`` (the proven bound alone without ``least``).
        """
        if not self.clear:
            return "not clear"
        if self.least is None:
            return f"proven >= {self.clearance * 1e3:.3f} mm from every pair"
        c = self.least
        return (f"least clearance {c.distance * 1e3:.3f} mm at {c.at:.4f} s "
                f"({'-'.join(c.bodies)}), found {c.within()}; proven >= "
                f"{self.clearance * 1e3:.3f} mm")

    def __repr__(self) -> str:
        if self.clear:
            if self.least is None:
                return (f"CollisionReport(clear: proven >= {self.clearance * 1e3:.3f} mm from "
                        f"every pair, {self.evaluations} checks)")
            c = self.least
            return (f"CollisionReport(clear: least clearance {c.distance * 1e3:.3f} mm at "
                    f"{c.at:.4f} s, {'-'.join(c.bodies)}, found {c.within()}; proven >= "
                    f"{self.clearance * 1e3:.3f} mm; {self.evaluations} checks)")
        what = f"{self.depth * 1e3:.3f} mm deep" if self.touching else "not proven clear"
        return (f"CollisionReport(first contact at {self.time or 0.0:.4f} s: "
                f"{'-'.join(self.bodies or ())}, {what}; {self.evaluations} checks)")


def collision_report(checker: CollisionChecker, traj: Trajectory, *, least: bool = True,
                     tol: float = LEAST_TOL) -> CollisionReport:
    """:func:`check_trajectory` with the first contact located and its depth measured.

    Args:
        checker: the robot in its cell.
        traj: the trajectory.
        least: when clear, also find the least clearance (:func:`least_clearance`).
        tol: its tolerance [m].
    """
    p = check_trajectory(checker, traj, locate=True)
    if p.clear:
        found = least_clearance(checker, traj, tol) if least else None
        if found is None:
            return CollisionReport(True, None, None, 0.0, False, p.clearance, checker.margin,
                                   p.evaluations)
        return CollisionReport(True, None, None, 0.0, False, max(found.lower, p.clearance),
                               checker.margin, p.evaluations + found.evaluations, found)
    c = p.contact
    if c is None:  # pragma: no cover - prove() names the contact of every proof not clear
        raise RuntimeError("a proof that is not clear names no contact")
    depth = deepest(checker, traj, c) if c.touching else 0.0
    return CollisionReport(False, c.at, c.bodies, depth, c.touching, -math.inf,
                           checker.margin, p.evaluations)


def make_checker(cell: object, robot: Robot | None, margin: float | None, nq: int
                 ) -> CollisionChecker:
    """A checker from a Cell and a robot, or the checker given (for a trajectory of ``nq``).

    ``margin`` [m]: ``None`` keeps a checker's own (0 for a Cell); any other value is used,
    with a checker too (:meth:`~scara_opt.collision.checker.CollisionChecker.with_margin`).

    Raises:
        InputError: neither a Cell nor a checker, no robot with a Cell, another joint count,
            a bad margin.
    """
    from scara_opt.checks import describe
    from scara_opt.collision.cell import Cell
    from scara_opt.errors import InputError

    if isinstance(cell, CollisionChecker):
        checker = cell if margin is None else cell.with_margin(margin)
    elif isinstance(cell, Cell):
        if robot is None:
            raise InputError("check_collisions(cell) needs the robot: pass robot= (or a "
                             "CollisionChecker(robot, cell))")
        checker = CollisionChecker(robot, cell, margin=0.0 if margin is None else margin)
    else:
        raise InputError(f"cell must be a scara_opt.Cell or a CollisionChecker; got "
                         f"{describe(cell)}")
    if checker.robot.nq != nq:
        raise InputError(f"the trajectory has {nq} joints, robot {checker.robot.name!r} "
                         f"{checker.robot.nq}; pass the robot it was timed for")
    return checker
