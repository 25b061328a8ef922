"""The one result type of every IK solver: :class:`IKResult`, its status and evidence.

Also :class:`Certificate` (a proof of unreachability) and :class:`SolverOutput` (what a
solver hands to the verdict).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from enum import Enum
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


class Status(str, Enum):  # noqa: UP042  (StrEnum's str() differs; we keep value semantics)
    """How a solve ended; compares equal to its plain string (``res.status == "solved"``).

    * ``solved``: the residual is within ``tol``;
    * ``unreachable``: a certificate proves that no configuration within the limits reaches
      the target within ``tol`` (:attr:`IKResult.reason` says which);
    * ``max_iter``: the target is reachable (a witness configuration was found by an exact
      method) but this method's budget ran out above ``tol``;
    * ``failed``: neither: no solution found, and no proof that none exists (or the
      joints the caller held make it infeasible, or the solver misbehaved).
    """

    SOLVED = "solved"
    UNREACHABLE = "unreachable"
    MAX_ITER = "max_iter"
    FAILED = "failed"

    def __str__(self) -> str:
        return self.value


class Reason(str, Enum):  # noqa: UP042
    """Why a solve has its status: the evidence behind it, for programs to read."""

    #: solved: the residual is within tol
    REACHED = "reached"
    #: unreachable: the target's height along the tool axis is outside what the strokes reach
    HEIGHT = "height_out_of_stroke"
    #: unreachable: farther from the arm's base than any configuration reaches
    BEYOND_REACH = "beyond_reach"
    #: unreachable: nearer to the shoulder axis than the elbow's range lets the arm fold
    INSIDE_HOLE = "inside_hole"
    #: unreachable: the tool only turns about the yaw axis (every revolute axis parallel to
    #: it), and the target's rotation tilts that axis
    TILT = "tilt_out_of_plane"
    #: unreachable: the closed form over the whole range of every redundant joint finds no
    #: branch within the joint limits (shoulder, elbow or wrist limits exclude the target)
    NO_BRANCH = "no_branch_within_limits"
    #: max_iter: an exact method reaches the target; this method's budget ran out
    BUDGET = "budget"
    #: failed: nothing found within tol, and no proof either way
    NO_CERTIFICATE = "no_certificate"
    #: failed: reachable, but not with the joints the caller held
    HELD_JOINTS = "held_joints"
    #: failed: the solver returned a configuration outside the joint limits
    SOLVER_ERROR = "solver_error"

    def __str__(self) -> str:
        return self.value


STATUS_MESSAGES = {
    Status.SOLVED: "target reached within tolerance",
    Status.UNREACHABLE: "target is outside the reachable workspace (proof below); q is the "
                        "closest configuration found and error the true residual",
    Status.MAX_ITER: "the target is reachable, but the iteration or evaluation budget ran out "
                     "before reaching the tolerance",
    Status.FAILED: "no solution within tolerance was found, and none was proved impossible",
}


@dataclass(frozen=True)
class Certificate:
    """A checkable proof that a target cannot be reached within ``tol``.

    Attributes:
        reason: which argument proves it.
        bound: a proven lower bound on the residual of every configuration within the
            limits [m, rad]; 0.0 where the proof is "no configuration reaches it exactly".
        detail: the argument in words, with the numbers a reader can check.
    """

    reason: Reason
    bound: float
    detail: str


@dataclass
class SolverOutput:
    """What a solver's ``_solve`` hands back (the verdict judges it, see :mod:`.verdict`).

    Attributes:
        q: (nq,) the best configuration found.
        iterations: iterations (generations) run.
        evaluations: FK evaluations used.
        history: best cost per iteration.
        message: specifics to append to the standard message.
        held: the solve was infeasible because of joints the caller held (``fixed``).
        setup_s: one-off setup done inside the search (a fallback's first build) [s]: the
            base moves it from ``time_s`` to ``setup_s``.
        route: how the answer was found, where a solver has several ways (see
            :attr:`IKResult.route`).
        turned: ``q`` is already at each joint's whole turn nearest ``q0`` (the base then
            skips :func:`~scara_opt.ik.turns.nearest_turn`).
    """

    q: Array
    iterations: int = 0
    evaluations: int = 0
    history: Array = field(default_factory=lambda: np.zeros(0))
    message: str = ""
    held: bool = False
    setup_s: float = 0.0
    route: str = ""
    turned: bool = False


@dataclass(frozen=True, repr=False)
class IKResult:
    """Outcome of one IK solve.

    Invariants: ``q`` within the joint limits; ``success`` iff ``status == "solved"``, and
    then ``error <= tol``; ``status == "unreachable"`` only with a certificate (its reason
    in :attr:`reason`, its numbers in :attr:`message`).

    Attributes:
        q: (nq,) joint values [rad or m], always within the joint limits.
        success: ``status == "solved"``.
        status: one of :class:`Status`.
        message: what happened, in words (never empty), with the evidence for the status.
        position_error: (3,) ``p(q) - p*`` [m].
        yaw_error: wrapped tool-angle error [rad] for a yaw target (rotation angle for a
            rotation target), else ``None``.
        error: max(|position_error| [m], |yaw_error| [rad]): the honest residual.
        cost: the weighted task cost (zavar2024 eq. 8 / nguyen eq. 10) at ``q``.
        iterations: solver iterations (generations for metaheuristics).
        evaluations: forward-kinematics evaluations used.
        time_s: wall-clock time of the search [s], one-off setup excluded.
        history: best cost per iteration (non-increasing for population methods).
        method: registry name of the solver.
        seed: the seed used.
        tol: the tolerance ``error`` was judged against.
        reason: the kind of evidence behind ``status`` (:class:`Reason`).
        evidence: the evidence in words, with its numbers: the certificate's argument for
            ``unreachable``, the witness for ``max_iter``; empty when solved.
        setup_s: one-off setup this call paid (casadi builds, compilation) [s]; 0 once cached.
        route: the way the answer was found where there are several: ``"analytic (<case>)"``
            (a 6R or 7R arm's closed form, :mod:`~scara_opt.ik.arm_route`, the case and any
            sampled joint named), ``"multi-start"`` (an arm the closed form does not serve);
            empty for the other solvers.
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
    reason: Reason = Reason.REACHED
    evidence: str = ""
    setup_s: float = 0.0
    route: str = ""

    @classmethod
    def _new(cls, **values: Any) -> IKResult:
        """``IKResult(**values)``, ~1.5 µs faster when every field is given (the verdict's).

        The frozen dataclass's ``__init__`` sets each of the 19 fields through
        ``object.__setattr__``; this fills ``__dict__`` at once (no ``__post_init__`` is
        skipped: there is none). The result is as frozen. Any other set of names goes
        through ``__init__`` (its defaults and its errors).
        """
        if values.keys() != _FIELD_NAMES:
            return cls(**values)
        result = object.__new__(cls)
        result.__dict__.update(values)
        return result

    def __repr__(self) -> str:
        q = np.array2string(self.q, precision=4, separator=", ")
        return (f"IKResult({self.status.value}, error={self.error:.3g}, method={self.method!r}, "
                f"q={q}, iterations={self.iterations}, time={self.time_s * 1e3:.2f} ms"
                f"{'' if self.success else ' [' + self.reason.value + ']: ' + self.message})")

    __str__ = __repr__


#: the names of :class:`IKResult`'s fields (:meth:`IKResult._new` fills them all)
_FIELD_NAMES = frozenset(f.name for f in fields(IKResult))
