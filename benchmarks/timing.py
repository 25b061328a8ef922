"""Shared by the benchmark scripts: the least disturbed of several wall-clock timings."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def best_time(fn: Callable[..., Any], *args: Any, repeats: int = 7, **kwargs: Any) -> float:
    """Best of ``repeats`` wall-clock times of ``fn(*args, **kwargs)`` [s] (machines are
    shared: the least disturbed run is the fairest estimate)."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn(*args, **kwargs)
        times.append(time.perf_counter() - t)
    return min(times)
