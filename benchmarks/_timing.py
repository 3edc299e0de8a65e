"""Best-of-repeats wall-clock timing, the same for every benchmark."""

from __future__ import annotations

import time


def best_time(fn, *, repeat: int = 7, min_time: float = 0.05) -> float:
    """Best time per call (s) over ``repeat`` rounds of enough calls to last ``min_time``."""
    fn()
    n = 1
    while True:
        t = time.perf_counter()
        for _ in range(n):
            fn()
        dt = time.perf_counter() - t
        if dt >= min_time or n >= 1 << 20:
            break
        n *= 2
    best = dt / n
    for _ in range(repeat - 1):
        t = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, (time.perf_counter() - t) / n)
    return best
