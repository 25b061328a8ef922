"""Units and numbers at the command line's edge: SI inside, ``--deg`` and ``--mm`` outside."""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

__all__ = ["joint_scale", "joint_units", "nonnegative", "positive"]


def joint_scale(robot: Any, deg: bool, mm: bool) -> np.ndarray:
    """Factor from SI joint values to the display units (``--deg``, ``--mm``), per joint."""
    rev = np.array([t == "revolute" for t in robot.joint_types])
    return np.where(rev, 180 / math.pi if deg else 1.0, 1000.0 if mm else 1.0)


def joint_units(robot: Any, deg: bool, mm: bool) -> list[str]:
    """The display unit of each joint (``rad``/``deg``, ``m``/``mm``)."""
    return [("deg" if deg else "rad") if t == "revolute" else ("mm" if mm else "m")
            for t in robot.joint_types]


def positive(text: str) -> float:
    """An argparse type: a finite number > 0."""
    value = float(text)
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0; got {text}")
    return value


def nonnegative(text: str) -> float:
    """An argparse type: a finite number >= 0."""
    value = float(text)
    if not (value >= 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0; got {text}")
    return value
