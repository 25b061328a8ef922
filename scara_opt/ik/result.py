"""The one result type of every IK solver: :class:`IKResult`, with its :class:`Status`."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


class Status(str, Enum):  # noqa: UP042  (StrEnum's str() differs; we keep value semantics)
    """How a solve ended; compares equal to its plain string (``res.status == "solved"``)."""

    SOLVED = "solved"
    UNREACHABLE = "unreachable"
    MAX_ITER = "max_iter"
    FAILED = "failed"

    def __str__(self) -> str:
        return self.value


STATUS_MESSAGES = {
    Status.SOLVED: "target reached within tolerance",
    Status.UNREACHABLE: "target is outside the reachable workspace; q is the closest "
                        "configuration found and error the true residual",
    Status.MAX_ITER: "iteration or evaluation budget used up before reaching the tolerance",
    Status.FAILED: "the solver failed",
}


@dataclass(frozen=True, repr=False)
class IKResult:
    """Outcome of one IK solve.

    Invariants: ``q`` within the joint limits; ``success`` iff ``status == "solved"``, and
    then ``error <= tol``.

    Attributes:
        q: (nq,) joint values [rad or m], always within the joint limits.
        success: ``status == "solved"``.
        status: one of :class:`Status`.
        message: what happened, in words (never empty).
        position_error: (3,) ``p(q) - p*`` [m].
        yaw_error: wrapped tool-angle error [rad] for a yaw target (rotation angle for a
            rotation target), else ``None``.
        error: max(|position_error| [m], |yaw_error| [rad]): the honest residual.
        cost: the weighted task cost (zavar2024 eq. 8 / nguyen eq. 10) at ``q``.
        iterations: solver iterations (generations for metaheuristics).
        evaluations: forward-kinematics evaluations used.
        time_s: wall-clock time of the solve [s].
        history: best cost per iteration (non-increasing for population methods).
        method: registry name of the solver.
        seed: the seed used.
        tol: the tolerance ``error`` was judged against.
    """

    q: Array
    success: bool
    status: Status
    message: str
    position_error: Array
    yaw_error: float | None
    error: float
    cost: float
    iterations: int
    evaluations: int
    time_s: float
    history: Array = field(default_factory=lambda: np.zeros(0))
    method: str = ""
    seed: int | None = None
    tol: float = 1e-9

    def __repr__(self) -> str:
        q = np.array2string(self.q, precision=4, separator=", ")
        return (f"IKResult({self.status.value}, error={self.error:.3g}, method={self.method!r}, "
                f"q={q}, iterations={self.iterations}, time={self.time_s * 1e3:.2f} ms"
                f"{'' if self.success else ': ' + self.message})")

    __str__ = __repr__
