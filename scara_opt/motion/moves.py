"""Moves as values: ``PTP(goal)``, ``LIN(goal)``, ``CIRC(via, goal)``, as a SCARA cell runs them.

A goal is a joint vector (nq,) [rad or m] or a :class:`~scara_opt.Target` (tip position [m],
optional yaw [rad]). Every move may carry its own tool ``speed`` [m/s], tool
``acceleration`` [m/s²] and ``blend`` radius [m]; ``elbow`` picks the SCARA arm branch
(``"righty"``: the forearm turns counter-clockwise from the upper arm about the yaw axis,
``"lefty"``: clockwise; see :mod:`scara_opt.motion.branch`). A PTP may change branch, a
LIN or CIRC keeps the branch it starts on.

Constructors only store; :func:`check_move` validates a move at its place in a program and
raises :class:`~scara_opt.errors.MoveError` naming the index and what to change.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Literal, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scara_opt.checks import describe, is_real
from scara_opt.errors import MoveError, ScaraOptError
from scara_opt.target import Target

Array = NDArray[np.float64]

#: the arm branches a SCARA move may ask for
ELBOWS = ("lefty", "righty")


@dataclass(frozen=True, eq=False)
class Move:
    """Fields shared by every move (see the module docstring for units)."""

    goal: Any
    speed: float | None = None
    acceleration: float | None = None
    blend: float = 0.0
    elbow: str | None = None

    kind = "move"


@dataclass(frozen=True, eq=False)
class PTP(Move):
    """Point to point: a straight line in joint space to ``goal``; tool limits only if set."""

    kind = "PTP"


@dataclass(frozen=True, eq=False)
class LIN(Move):
    """Straight tool line to ``goal``, yaw interpolated linearly (nearest turn)."""

    kind = "LIN"


@dataclass(frozen=True, eq=False, init=False)
class CIRC(Move):
    """Circular arc from the current tool position through ``via`` to ``goal``.

    ``via``: a (3,) position [m] or a Target (its yaw is ignored) on the arc.
    """

    via: Any = None
    kind = "CIRC"

    def __init__(self, via: Target | ArrayLike, goal: Target | ArrayLike,
                 speed: float | None = None, acceleration: float | None = None, blend: float = 0.0,
                 elbow: str | None = None) -> None:
        for name, value in (("goal", goal), ("speed", speed), ("acceleration", acceleration),
                            ("blend", blend), ("elbow", elbow), ("via", via)):
            object.__setattr__(self, name, value)


def _positive(index: int, move: Move, name: str, value: object, unit: str) -> None:
    if value is None:
        return
    number = float(value) if is_real(value) else math.nan
    if not (math.isfinite(number) and number > 0):
        raise MoveError(index, f"{move.kind} {name}={describe(value)}: a tool {name} must be a "
                               f"finite number > 0 [{unit}]; pass a positive {name}= or None "
                               "for the program's limit")


def check_move(index: int, move: object, nq: int) -> Move:
    """``move`` if it is a valid PTP/LIN/CIRC for a robot of ``nq`` joints.

    Raises:
        MoveError: not a move, a goal neither (nq,) nor a Target, a zero/negative/NaN
            speed, acceleration or blend radius, an unknown ``elbow``.
    """
    if not isinstance(move, Move) or type(move) is Move:
        raise MoveError(index, f"expected PTP(goal), LIN(goal) or CIRC(via, goal); got "
                               f"{describe(move)}")
    _positive(index, move, "speed", move.speed, "m/s")
    _positive(index, move, "acceleration", move.acceleration, "m/s²")
    if not is_real(move.blend) or not (math.isfinite(float(move.blend)) and float(move.blend) >= 0):
        raise MoveError(index, f"blend={describe(move.blend)}: a blend radius must be a finite "
                               "number >= 0 [m] (0: stop exactly at the goal)")
    if move.elbow is not None and move.elbow not in ELBOWS:
        raise MoveError(index, f"elbow={move.elbow!r}: pass 'lefty', 'righty' or None (keep "
                               "the current branch)")
    goal_point(index, move.goal, nq, "goal")
    if isinstance(move, CIRC):
        goal_point(index, move.via, nq, "via", joints=False)
    return move


@overload
def goal_point(index: int, goal: object, nq: int, what: str,
               joints: Literal[True] = ...) -> Target | Array: ...


@overload
def goal_point(index: int, goal: object, nq: int, what: str,
               joints: Literal[False]) -> Target: ...


def goal_point(index: int, goal: object, nq: int, what: str,
               joints: bool = True) -> Target | Array:
    """A goal as a Target or a joint vector (nq,); a via point as a Target.

    A (3,) array is a position [m], unless ``nq == 3`` and it is a goal (then joints).

    Raises:
        MoveError: neither form (the message says which shapes are accepted).
    """
    if isinstance(goal, Target):
        return goal
    try:
        arr = np.asarray(goal, dtype=float)
    except (TypeError, ValueError):
        arr = np.empty(0)
    if arr.ndim == 1 and np.isfinite(arr).all():
        if joints and arr.shape == (nq,):
            return arr
        if arr.shape == (3,):
            return Target(arr)
    shapes = (f"a joint vector ({nq},) [rad or m], a (3,) position [m] or a Target"
              if joints else "a (3,) position [m] or a Target")
    raise MoveError(index, f"{what} must be {shapes}; got {describe(goal)}")


def as_moves(moves: Move | Iterable[Move], nq: int) -> list[Move]:
    """The program as a checked list of moves.

    Raises:
        MoveError: a bad move (its index named). InputError: not a sequence or empty.
    """
    from scara_opt.errors import InputError

    if isinstance(moves, Move):
        moves = [moves]
    try:
        seq: list[object] = list(moves)
    except TypeError:
        raise InputError(f"moves must be a sequence of PTP/LIN/CIRC; got "
                         f"{describe(moves)}") from None
    if not seq:
        raise InputError("moves is empty: give at least one PTP, LIN or CIRC")
    out = []
    for i, m in enumerate(seq):
        try:
            out.append(check_move(i, m, nq))
        except MoveError:
            raise
        except ScaraOptError as exc:  # a Target's own check (e.g. a via)
            raise MoveError(i, str(exc)) from None
    return out
