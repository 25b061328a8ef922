"""What a timing method is: its entry in the registry, and the checks of its options.

Each backend module (:mod:`~scara_opt.trajectory.quintic`,
:mod:`~scara_opt.trajectory.toppra_backend`, :mod:`~scara_opt.trajectory.ruckig_backend`)
declares its ``METHOD``; :mod:`~scara_opt.trajectory.registry` reads them (backends never
import the registry).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from scara_opt.errors import InputError
from scara_opt.ik.base import check_flag, check_number
from scara_opt.trajectory.trajectory import Trajectory

#: a backend: ``(Q (n, nq), limits, duration or None, **options) -> Trajectory``
Backend = Callable[..., Trajectory]


@dataclass(frozen=True)
class TimingMethod:
    """A registered timing method.

    Attributes:
        name: registry key.
        backend: the function doing the work.
        options: every accepted option with its default.
        uses_jerk: whether it honours ``jmax``.
        takes_duration: whether it accepts a fixed ``duration``.
        uses_torque: whether it honours joint torque limits (``torque_limits=``,
            ``payload=``), given as its ``dynamics=`` argument.
    """

    name: str
    backend: Backend
    options: dict[str, Any] = field(default_factory=dict)
    uses_jerk: bool = False
    takes_duration: bool = False
    uses_torque: bool = False


def check_option(method: str, name: str, value: Any, low: float, high: float = math.inf, *,
                 integer: bool = False, low_open: bool = False, high_open: bool = False,
                 default: Any = None) -> None:
    """:func:`~scara_opt.ik.base.check_number` for an option of timing ``method``.

    Raises:
        InputError: wrong type, NaN or out of range; names the method, option, value, range
            and ``default``.
    """
    try:
        check_number(name, value, low, high, integer=integer, low_open=low_open,
                     high_open=high_open)
    except InputError as exc:
        raise InputError(f"method {method!r}: {exc}; pass one in that range, or omit {name}= "
                         f"for the default {default!r}") from None


def check_option_flag(method: str, name: str, value: Any) -> None:
    """Refuse a flag option of timing ``method`` that is not True or False.

    Raises:
        InputError: names the method, the option and the value given.
    """
    try:
        check_flag(name, value)
    except InputError as exc:
        raise InputError(f"method {method!r}: {exc}") from None
