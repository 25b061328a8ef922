"""Argument checks shared by the public entry points: types, numbers, flags, memory.

Each check raises :class:`~scara_opt.errors.InputError` (or the subclass passed as
``error``) naming the argument, what it got and what it takes. Numbers are real numbers
(``int``, ``float``, numpy scalars), never ``bool`` and never strings: ``"0.5"`` or
``True`` where a length is expected is a mistake, not a value.

**Memory.** Functions that allocate in proportion to a count their caller chooses (the
samples of :func:`~scara_opt.workspace_analysis.workspace`, the points of
:mod:`scara_opt.paths`, the jobs of :func:`~scara_opt.comparison.compare`) estimate the
bytes first (:func:`check_memory`) and refuse, before allocating anything, above
:data:`MAX_BYTES`: the message gives the estimate and how to lower it. To go beyond on
purpose, raise the limit::

    import scara_opt.checks
    scara_opt.checks.MAX_BYTES = 32 * 2**30   # 32 GiB

A ``MemoryError`` that still happens below the limit (a machine with less free memory) is
turned into the same kind of message (:func:`memory_guard`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterator
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import Any, TypeGuard

import numpy as np
from numpy.typing import NDArray

from scara_opt.errors import InputError

#: largest memory estimate [bytes] a call may allocate (4 GiB); raise it to allow more
MAX_BYTES = 4 * 2**30

_UNITS = ("B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB")


def short_repr(value: object, width: int = 60) -> str:
    """``repr(value)`` cut at ``width`` characters, for messages.

    An integer of 10**15 or more is written as its order of magnitude, e.g. ``1e+5000``
    (Python refuses to print one above 4,300 digits whole).
    """
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**15:
        return count_text(value)
    try:
        text = repr(value)
    except ValueError:  # holds an integer above 4,300 digits
        return f"a {type(value).__name__} holding an integer too long to print"
    return text if len(text) <= width else text[:width - 3] + "..."


def describe(value: object) -> str:
    """A short description of a value for messages: its repr (cut at 60 characters) and type."""
    return f"{short_repr(value)} ({type(value).__name__})"


def human_bytes(n: float) -> str:
    """``n`` bytes in binary units, e.g. ``"29.1 TiB"``; beyond EiB in powers of ten."""
    if isinstance(n, int) and n >= 1024**7:  # beyond EiB (and beyond a float, at any size)
        return f"{count_text(n)} B"
    size = float(n)
    for unit in _UNITS:
        if size < 1024 or unit == _UNITS[-1]:
            break
        size /= 1024
    if size >= 1024:
        return f"{float(n):.3g} B"
    return f"{size:.3g} {unit}" if unit != "B" else f"{int(n)} B"


def count_text(n: int) -> str:
    """An item count for messages: ``1,000,000`` up to 10**15, then ``1e+30`` (any size)."""
    if abs(n) < 10**15:
        return f"{n:,}"
    exponent = math.floor(math.log10(abs(n)))  # any int (no float overflow); may be one high
    exponent -= abs(n) < 10**exponent
    mantissa = abs(n) // 10**(exponent - 2) / 100  # three digits, exact
    return f"{'-' if n < 0 else ''}{mantissa:.3g}e+{exponent}"


def check_memory(what: str, count: int, per_item: int, advice: str) -> int:
    """Refuse ``count`` items of about ``per_item`` bytes each above :data:`MAX_BYTES`.

    Args:
        what: the call, e.g. ``"workspace(n=10**12)"``.
        count: number of items (any size of Python int: the product is exact).
        per_item: estimated bytes per item.
        advice: what to lower, e.g. ``"lower n (60_000 is the papers' count)"``.

    Returns:
        The estimate [bytes].

    Raises:
        InputError: the estimate exceeds :data:`MAX_BYTES`; the message names the
            estimate, the limit, the advice and the override.
    """
    estimate = int(count) * int(per_item)
    if estimate > MAX_BYTES:
        raise InputError(
            f"{what} would need about {human_bytes(estimate)} of memory ({count_text(count)} x "
            f"{count_text(per_item)} B), more than the {human_bytes(MAX_BYTES)} allowed; "
            f"{advice}, or, if this machine really has the memory, raise "
            "scara_opt.checks.MAX_BYTES")
    return estimate


@contextmanager
def memory_guard(what: str, estimate: int, advice: str) -> Iterator[None]:
    """Turn a ``MemoryError`` inside the block into an :class:`InputError` with advice.

    Raises:
        InputError: the block ran out of memory (names the estimate and the advice).
    """
    try:
        yield
    except MemoryError:
        raise InputError(f"{what} ran out of memory (estimated {human_bytes(estimate)}); "
                         f"{advice}") from None


def is_real(value: object) -> TypeGuard[numbers.Real]:
    """Whether ``value`` is a real number: int, float or numpy scalar; not bool, not str."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def check_real(name: str, value: object, low: float = -math.inf, high: float = math.inf, *,
               low_open: bool = False, unit: str = "", error: type[Exception] = InputError,
               ) -> float:
    """``value`` as a finite float within ``[low, high]`` (``(low, ...`` with ``low_open``).

    Raises:
        InputError: not a real number (bools and strings included), not finite, or out of
            range; the message names ``name``, the value and the range.
    """
    ok = False
    if is_real(value):
        try:
            v = float(value)
        except OverflowError:  # an int beyond the float range
            v = -math.inf if value < 0 else math.inf
        ok = math.isfinite(v) and (v > low if low_open else v >= low) and v <= high
    if not ok:
        unit_text = f" [{unit}]" if unit else ""
        if math.isinf(low) and math.isinf(high):
            span = "a finite number"
        elif math.isinf(high):
            span = f"a finite number {'>' if low_open else '>='} {low:g}"
        else:
            span = f"a number in {'(' if low_open else '['}{low:g}, {high:g}]"
        raise error(f"{name} must be {span}{unit_text}; got {describe(value)}")
    return v


def check_int(name: str, value: object, least: int, most: int | None = None, *,
              error: type[Exception] = InputError) -> int:
    """``value`` as an int in [``least``, ``most``] (Python or numpy integer; not bool, float).

    Raises:
        InputError: names ``name``, the value and the range.
    """
    if (not isinstance(value, (int, np.integer)) or isinstance(value, (bool, np.bool_))
            or value < least or (most is not None and value > most)):
        kind = ("a positive integer" if least == 1 else f"an integer >= {least}"
                ) if most is None else f"an integer in [{least}, {most}]"
        raise error(f"{name} must be {kind}; got {describe(value)}")
    return int(value)


def check_path(name: str, value: object, error: type[Exception] = InputError) -> Path:
    """``value`` as a Path: a str or ``os.PathLike``, not empty, without a NUL byte.

    Raises:
        InputError: (or ``error``) names ``name`` and what it got.
    """
    if not isinstance(value, (str, PathLike)):
        raise error(f"{name} must be a path (a str or pathlib.Path); got {describe(value)}")
    text = str(value)
    if not text:
        raise error(f"{name} is an empty path; give a file name")
    if "\0" in text:
        raise error(f"{name} {text!r} contains a NUL byte, which no file name can hold; "
                    "pass a plain path")
    return Path(text)


def check_text(name: str, value: object, error: type[Exception] = InputError) -> str:
    """``value`` as a name: a non-empty str of printable characters (no NUL, no newline).

    Raises:
        InputError: (or ``error``) names ``name`` and what it got.
    """
    if not isinstance(value, str) or not value:
        raise error(f"{name} must be a non-empty str; got {describe(value)}")
    if not value.isprintable():
        bad = next(c for c in value if not c.isprintable())
        raise error(f"{name} {value!r} holds the control character {bad!r}; use printable "
                    "characters")
    return value


def check_flag(name: str, value: object) -> bool:
    """``value`` as a bool: only ``True`` or ``False`` (numpy bools too).

    Raises:
        InputError: anything else (``"no"`` would otherwise count as true).
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be True or False; got {describe(value)}")
    return bool(value)


def check_name(name: str, value: object, takes: str) -> str:
    """``value`` if it is a str, else :class:`InputError` saying what ``name`` takes."""
    if not isinstance(value, str):
        raise InputError(f"{name} must be {takes} (a str); got {describe(value)}")
    return value


def float_array(value: object, name: str, error: type[Exception] = InputError,
                ) -> NDArray[np.float64]:
    """``value`` as a float array; strings, bools and non-numbers are refused.

    ``np.asarray(["1", "2"], dtype=float)`` would parse the strings and
    ``np.asarray([True, False], dtype=float)`` count the bools: both are refused here.

    Raises:
        InputError: not numeric (the message names ``name`` and the value).
    """
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":  # the common, fast case
        return np.asarray(value, dtype=float)
    try:
        raw = np.asarray(value)
        ok = raw.dtype.kind in "iuf" or (raw.dtype.kind == "O" and all(
            is_real(v) for v in raw.ravel()))
        arr = np.asarray(raw, dtype=float) if ok else None
    except (TypeError, ValueError, OverflowError):
        arr = None
    if arr is None:
        raise error(f"{name} must be numeric (numbers, not strings or bools); got "
                    f"{describe(value)}")
    return arr


def check_options_dict(name: str, value: object) -> dict[str, Any]:
    """``value`` as a dict with str keys (``None`` gives ``{}``).

    Raises:
        InputError: not a dict, or a key that is not a str.
    """
    if value is None:
        return {}
    if not isinstance(value, dict) or not all(isinstance(k, str) for k in value):
        raise InputError(f"{name} must be a dict with str keys, or None; got "
                         f"{describe(value)}")
    return value
