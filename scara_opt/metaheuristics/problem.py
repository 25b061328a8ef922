"""The search box and the counted, vectorised cost of one IK solve (:class:`Problem`).

Every metaheuristic moves its individuals through :meth:`Problem.repair` and costs them
through :meth:`Problem.cost`; both keep per-batch-size buffers (:class:`_Sized`) so that a
generation's numpy calls run on full-shape, preallocated operands (issue 18).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from scara_opt.ik.task import config_errors, cost_batch, cost_of, wrap_angle
from scara_opt.model import batch_fk
from scara_opt.model.robot import Robot
from scara_opt.target import Target

Array = NDArray[np.float64]


class Problem:
    """The search box and the counted, vectorised cost of one IK solve.

    The box is the robot's joint limits, except that a joint without limits (a
    continuous joint) is searched over one turn, ``[-π, π]``
    (:attr:`Robot.sampling_lower` / :attr:`Robot.sampling_upper`).

    Bounds rule (the only one any metaheuristic uses, through :meth:`repair`): a
    coordinate that leaves ``[lower, upper]`` is **reflected** once at the limit it
    crossed, then **clipped**, so a step that overshoots by more than the whole range
    lands on the limit. Reflection keeps the step's length and does not pile
    individuals up on the limits the way clipping alone does. A continuous joint's
    angle is **wrapped** into ``[-π, π)`` instead: the same angle, no limit to hit.

    Attributes:
        robot: the robot.
        target: the IK target.
        lower: (nq,) lower end of the search box [rad or m].
        upper: (nq,) upper end of the search box [rad or m].
        span: (nq,) ``upper - lower``.
        periodic: (nq,) bool, the joints without limits (wrapped, not reflected).
        stop_cost: a cost at or below which the residual is within ``tol`` (see
            :meth:`PopulationSolver._solve`).
        evaluations: FK evaluations so far (rows passed to :meth:`cost`).
    """

    def __init__(self, robot: Robot, target: Target, tol: float) -> None:
        self.robot = robot
        self.target = target
        self.lower: Array = robot.sampling_lower
        self.upper: Array = robot.sampling_upper
        self.span: Array = self.upper - self.lower
        self.periodic = ~(np.isfinite(robot.lower) & np.isfinite(robot.upper))
        self._any_periodic = bool(self.periodic.any())
        self._position = target.kind == "position"
        self._wp2 = target.weights[0] ** 2
        self._sized: dict[int, _Sized] = {}
        wp, wa = target.weights
        # cost^2 = wp^2 |dp|^2 + wa^2 da^2 >= min(wp, wa)^2 max(|dp|, |da|)^2 = (w error)^2
        w = wp if target.kind == "position" else min(wp, wa)
        self.stop_cost = tol * w * (1.0 - 1e-9)
        self.evaluations = 0

    @property
    def nq(self) -> int:
        """Number of joint coordinates."""
        return self.lower.shape[0]

    def cost(self, X: Array) -> Array:
        """Costs (n,) of ``X`` (n, nq): one vectorised FK call, counted in :attr:`evaluations`.

        The same numbers as :func:`~scara_opt.ik.task.cost_batch`. For a position target
        the rows go straight into the batch FK's buffers (every row came through
        :meth:`repair` or :meth:`uniform`, so the robot's input check is skipped), and
        eq. 8 is evaluated on them as :func:`~scara_opt.ik.task.cost_from_errors` does,
        with the target tiled to the batch (issue 18: 18 -> 11 µs a call at n = 100).
        """
        n = X.shape[0]
        self.evaluations += n
        if not self._position or not 0 < n <= batch_fk.CHUNK:
            return cost_batch(self.robot, self.target, X)
        sized = self._for(n)
        fk = sized.fk
        fk.arg["q"][...] = X
        fk()
        dp = np.subtract(fk.res["rows"], sized.target, out=sized.dp)
        sq = np.einsum("ij,ij->i", dp, dp)
        if self._wp2 != 1.0:                  # w_p^2 |dp|^2, as cost_from_errors (x 1 = x)
            sq *= self._wp2
        return np.sqrt(sq, out=sq)

    def cost_one(self, x: Array) -> float:
        """Cost of one configuration ``x`` (nq,) (for scalar local searches such as Nelder–Mead).

        One Pinocchio FK call (~5 µs), cheaper than a batch of one; the same cost up to
        round-off. Counted in :attr:`evaluations`.
        """
        self.evaluations += 1
        return cost_of(self.target, *config_errors(self.robot, self.target, x))

    def repair(self, X: Array) -> Array:
        """``X`` (n, nq) brought into the box (reflect, clip; wrap continuous joints).

        Reflection as a maximum: below ``lower``, ``2 lower - x`` is the larger of the two;
        above, ``x`` is (equal at the limit), so ``max(x, 2 lower - x)`` is exactly the
        reflected value, in one ufunc instead of a comparison and a ``where`` (the same at
        ``upper`` with a minimum). After both reflections no value is above ``upper``, so
        the clip only has the lower limit left to enforce. Bit for bit the rule above.
        The limits are tiled to ``X``'s shape once per size (:meth:`_for`): a (nq,) row
        broadcast over (n, nq) runs n short loops, ~3x slower at nq = 4 (issue 18).
        """
        b = self._for(X.shape[0])
        Y = np.subtract(b.mirror_lo, X)
        np.maximum(X, Y, out=Y)
        T = np.subtract(b.mirror_hi, Y, out=b.scratch)
        np.minimum(Y, T, out=Y)
        np.maximum(Y, b.lower, out=Y)
        if self._any_periodic:
            Y[:, self.periodic] = wrap_angle(X[:, self.periodic])
        return Y

    def uniform(self, rng: np.random.Generator, n: int) -> Array:
        """``n`` configurations (n, nq) drawn uniformly within the search box."""
        return rng.uniform(self.lower, self.upper, (n, self.nq))

    def _for(self, n: int) -> _Sized:
        """The buffers of batches of ``n`` rows (made at the first batch of that size)."""
        sized = self._sized.get(n)
        if sized is None:
            sized = self._sized[n] = _Sized(self, n)
        return sized


class _Sized:
    """Per batch size ``n``: the limits and target tiled to ``n`` rows, scratch, FK buffers.

    Made inside the solve (so in its thread: the FK buffers are per thread).
    """

    def __init__(self, problem: Problem, n: int) -> None:
        self.lower = tiled(problem.lower, n)
        self.mirror_lo = tiled(2.0 * problem.lower, n)
        self.mirror_hi = tiled(2.0 * problem.upper, n)
        self.scratch = np.empty((n, problem.nq))
        if problem._position and 0 < n <= batch_fk.CHUNK:
            self.target = tiled(problem.target.position, n)
            self.dp = np.empty((n, 3))
            self.fk = batch_fk.fk_arrays(problem.robot, "position", n)


def tiled(row: Array, n: int) -> Array:
    """``row`` (k,) repeated as ``n`` contiguous rows (n, k).

    An operand of the full shape lets numpy run an elementwise operation as one loop; a
    (k,) row broadcast over (n, k) runs n loops of k, ~3x slower at k = 4 (issue 18).
    """
    return np.broadcast_to(row, (n, row.shape[0])).copy()
