"""Checks of joint values against a robot's joints: shapes, finiteness, limits.

A mixin of :class:`~scara_opt.model.robot.Robot` (it reads ``nq``, ``joint_names``,
``lower`` and ``upper``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from scara_opt.checks import check_real, describe, float_array
from scara_opt.errors import InputError

Array = NDArray[np.float64]


class JointChecks:
    """``q`` (nq,) and ``Q`` (n, nq) checked against the robot's joints."""

    nq: int
    joint_names: list[str]
    lower: Array
    upper: Array

    def check_q(self, q: object, name: str = "q") -> Array:
        """Return ``q`` as a float array of shape (nq,), or raise :class:`InputError`."""
        arr = _numeric(q, name, f"numeric, one value per joint {self.joint_names}")
        if arr.shape != (self.nq,):
            raise InputError(
                f"{name} must have shape ({self.nq},), one value per joint {self.joint_names} "
                f"[rad or m]; got shape {arr.shape}"
            )
        finite = np.isfinite(arr)
        if not finite.all():
            names = [self.joint_names[i] for i in np.flatnonzero(~finite)]
            raise InputError(f"{name} has non-finite values (NaN or inf) at joints {names}; "
                             "pass finite joint values")
        return arr

    def check_q_batch(self, Q: object, name: str = "Q") -> Array:
        """Return ``Q`` as a float array of shape (n, nq), or raise :class:`InputError`."""
        arr = _numeric(Q, name, f"a numeric array of shape (n, {self.nq})")
        if arr.ndim != 2 or arr.shape[1] != self.nq:
            raise InputError(
                f"{name} must have shape (n, {self.nq}), one row per configuration; "
                f"got shape {arr.shape}"
            )
        finite = np.isfinite(arr)
        if not finite.all():
            rows = np.flatnonzero(~finite.all(axis=1))
            raise InputError(f"{name} has non-finite values in rows {rows[:10].tolist()}; "
                             "pass finite joint values")
        return arr

    def within_limits(self, q: object, tol: float = 0.0) -> bool | NDArray[np.bool_]:
        """Whether ``q`` (nq,) — or each row of (n, nq) — lies within [lower - tol, upper + tol].

        Raises:
            InputError: ``q`` not numeric or misshaped; ``tol`` not a finite number >= 0.
        """
        tol = check_real("tol", tol, 0.0, unit="rad or m")
        arr = float_array(q, "q")
        arr = self.check_q(arr) if arr.ndim == 1 else self.check_q_batch(arr)
        ok = np.all((arr >= self.lower - tol) & (arr <= self.upper + tol), axis=-1)
        return bool(ok) if arr.ndim == 1 else ok


def _numeric(value: object, name: str, want: str) -> Array:
    """``value`` as a float array, or InputError: "``name`` must be ``want``; got ..."."""
    try:
        return float_array(value, name)
    except InputError:
        raise InputError(f"{name} must be {want}; got {describe(value)}") from None
