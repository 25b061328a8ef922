"""The scara_opt exception family: every error the toolkit raises on bad input.

Each class subclasses :class:`ScaraOptError` and the matching builtin, so both
``except ScaraOptError`` and ``except ValueError`` catch it. Messages say what
was wrong, where, and what to do.
"""

from __future__ import annotations

from collections.abc import Iterable


class ScaraOptError(Exception):
    """Base class of every scara_opt error."""


class InputError(ScaraOptError, ValueError):
    """An argument has the wrong shape, type, or a non-finite value."""


class URDFError(ScaraOptError, ValueError):
    """A URDF (or DH robot file) is missing, malformed or not usable as a serial chain."""


class RobotNotFoundError(URDFError, LookupError):
    """A bundled robot name is unknown and is not a path to a file either."""

    def __init__(self, name: str, available: Iterable[str]) -> None:
        self.name = name
        self.available = sorted(available)
        super().__init__(
            f"no bundled robot named {name!r} and no file at that path; "
            f"bundled robots: {', '.join(self.available)}; "
            "pass one of these names or the path to a .urdf or .toml file"
        )


class FrameNotFoundError(URDFError, LookupError):
    """A frame (link) name does not exist in the model."""

    def __init__(self, frame: str, available: Iterable[str]) -> None:
        self.frame = frame
        self.available = list(available)
        super().__init__(
            f"frame {frame!r} is not in the URDF; frames that exist: "
            f"{', '.join(self.available)}; pass one of them as tip="
        )


class JointLimitError(ScaraOptError, ValueError):
    """A joint value or a joint-limit specification is invalid."""

    def __init__(self, message: str, joint: str | None = None) -> None:
        self.joint = joint
        super().__init__(message)


class TargetError(InputError):
    """An IK target is malformed or asks for a task the robot cannot do.

    A kind of :class:`InputError` (a malformed pose is bad input like any other), hence
    also a ``ValueError``.
    """


class UnknownSolverError(ScaraOptError, KeyError):
    """A solver (or time-parameterisation) method name is not registered."""

    def __init__(self, name: str, available: Iterable[str], kind: str = "IK method") -> None:
        self.name = name
        self.available = sorted(available)
        super().__init__(name)
        self._message = (
            f"unknown {kind} {name!r}; registered: {', '.join(self.available)}"
        )

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self._message


class SolverOptionError(ScaraOptError, TypeError):
    """A solver was given an option it does not accept."""

    def __init__(self, method: str, unknown: Iterable[str], accepted: Iterable[str]) -> None:
        self.method = method
        self.unknown = sorted(unknown)
        self.accepted = sorted(accepted)
        super().__init__(
            f"method {method!r} does not accept option(s) {', '.join(self.unknown)}; "
            f"accepted: {', '.join(self.accepted) or '(none)'}"
        )


class TrajectoryError(ScaraOptError, ValueError):
    """A path or its limits cannot be time-parameterised as asked."""


class DynamicsError(ScaraOptError, ValueError):
    """A robot lacks the inertial data or torque limits a dynamic computation needs."""


class MoveError(TrajectoryError):
    """A move of a motion program cannot be planned as given.

    Attributes:
        index: the move's position in the program (0-based).
    """

    def __init__(self, index: int, message: str) -> None:
        self.index = index
        super().__init__(f"move {index}: {message}")


class BranchError(MoveError):
    """A LIN/CIRC cannot stay on its elbow branch.

    Attributes:
        point: index (into the move's Cartesian points after the start) where it leaves.
        side: the branch it started on (``"lefty"`` / ``"righty"``).
    """

    def __init__(self, index: int, message: str, point: int, side: str) -> None:
        self.point = point
        self.side = side
        super().__init__(index, message)


class CellError(InputError):
    """A cell, one of its obstacles, or a robot's collision geometry is malformed.

    Raised for a cell file that is not valid TOML or has unknown keys, an obstacle with a
    zero, negative or non-finite size, a bad pose, a duplicate name, or a collision radius
    that is missing or not positive.
    """


class ProgramError(InputError):
    """A program file (TOML moves, :func:`scara_opt.load_program`) is malformed.

    Raised for a file that is not valid TOML, an unknown or misspelt key or move type, a
    missing goal, a value that is not a number in the file's units or is out of range, or
    no robot to run it on; the message names the file, the move and the key.
    """


class MeshNotFoundError(CellError):
    """A mesh file named by an obstacle or a robot's ``<collision>`` cannot be found.

    Attributes:
        path: the file as given.
        where: what named it (the obstacle, or the URDF link).
    """

    def __init__(self, path: str, where: str, remedy: str) -> None:
        self.path = path
        self.where = where
        super().__init__(f"{where}: mesh file {path!r} cannot be found; {remedy}")


class UnknownBodyError(CellError, LookupError):
    """A body named in an allowed-contact list (or an SRDF) is not a body of the robot or cell.

    Attributes:
        name: the unknown name.
        available: the robot links and obstacles that do exist.
    """

    def __init__(self, name: str, available: Iterable[str], where: str) -> None:
        self.name = name
        self.available = sorted(available)
        super().__init__(name)
        self._message = (f"{where}: no body named {name!r}; bodies: "
                         f"{', '.join(self.available)}; use one of these names")

    def __str__(self) -> str:  # LookupError's KeyError cousin would quote; keep the message
        return self._message


class CollisionError(ScaraOptError, ValueError):
    """A configuration (a start, a goal) or a motion touches an obstacle or the robot itself.

    Attributes:
        bodies: the two bodies in contact, ``(robot body, other body)``.
        depth: how deep they overlap [m] (0 when they just touch).
        time: when the contact begins [s] (``None`` for a single configuration).
    """

    def __init__(self, message: str, bodies: tuple[str, str], depth: float,
                 time: float | None = None) -> None:
        self.bodies = tuple(bodies)
        self.depth = float(depth)
        self.time = time
        super().__init__(message)


class MoveCollisionError(MoveError, CollisionError):
    """A move of a motion program (a LIN, a CIRC, a blended run) hits an obstacle.

    Attributes:
        index: the move's position in the program; ``time``, ``bodies``, ``depth`` as in
            :class:`CollisionError`.
    """

    def __init__(self, index: int, message: str, bodies: tuple[str, str], depth: float,
                 time: float | None = None) -> None:
        self.index = index
        CollisionError.__init__(self, f"move {index}: {message}", bodies, depth, time)


class NoPathFoundError(MoveError):
    """A sampling planner found no collision-free path within its time limit.

    Not a proof that none exists (a sampling planner proves nothing): the move may still
    be possible with more time, another seed, or a smaller margin.

    Attributes:
        index: the move's position in the program.
        time_s: the time spent [s]; ``time_limit``: the limit [s].
        states: the states the planner's trees held; ``checks``: the state and motion checks.
    """

    def __init__(self, index: int, message: str, time_s: float, time_limit: float,
                 states: int, checks: int) -> None:
        self.time_s = time_s
        self.time_limit = time_limit
        self.states = states
        self.checks = checks
        super().__init__(index, message)


class ScaraOptWarning(UserWarning):
    """Base class of every scara_opt warning (filter them all with this class)."""


class NativeCodeWarning(ScaraOptWarning):
    """Something about the native code compiled for this machine (:mod:`scara_opt.model.compiled`).

    Said at most once per process for each of its kinds below; filter this class to
    silence both.
    """


class CompilingWarning(NativeCodeWarning):
    """A one-off build of native code took a noticeable time (the first call's cost).

    The library is kept in the cache folder: later processes load it instead.
    """


class FallbackWarning(NativeCodeWarning):
    """Native code is unavailable here (no compiler, a failing one, an unwritable cache).

    The pure forms run instead (casadi's virtual machine, numpy): the same numbers, slower.
    The message names the cause (with the compiler's own error text) and the remedy.
    """
