"""Shared by the benchmark scripts: the least disturbed of several wall-clock timings."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")

#: passes over a benchmark's targets: each target's least time counts
PASSES = 3


def best_time(fn: Callable[..., Any], *args: Any, repeats: int = 7, **kwargs: Any) -> float:
    """Best of ``repeats`` wall-clock times of ``fn(*args, **kwargs)`` [s] (machines are
    shared: the least disturbed run is the fairest estimate)."""
    return best_time_and_result(fn, *args, repeats=repeats, **kwargs)[0]


def best_time_and_result(fn: Callable[..., T], *args: Any, repeats: int = 7,
                         **kwargs: Any) -> tuple[float, T]:
    """:func:`best_time` [s], and the last run's result (for deterministic ``fn``)."""
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        result = fn(*args, **kwargs)
        best = min(best, time.perf_counter() - t)
    return best, result


def least_per_call(solve: Callable[[int], T], n: int,
                   passes: int = PASSES) -> tuple[np.ndarray, list[T]]:
    """Per-call wall times [s] (n,) of ``solve(k)``, k < n, each the least over ``passes``
    passes over all k (a pause of the shared machine does not land in one method's row),
    and the last pass's answers (every solver timed here is deterministic)."""
    times = np.full(n, np.inf)
    for _ in range(passes):
        answers = []
        for k in range(n):
            t = time.perf_counter()
            answers.append(solve(k))
            times[k] = min(times[k], time.perf_counter() - t)
    return times, answers
