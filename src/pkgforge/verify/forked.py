"""A function mapped over items in forked processes that share this one's memory.

verify's checks run after every launch file is evaluated, on one core while the
others wait. Forked children see the models, resolutions and install tree as they
are here (copy on write: nothing is pickled on the way in), each checks a slice
of the packages while this process checks the first, and only the answers come
back. A child that fails in any way
(killed, an answer that cannot be pickled) costs nothing but time: its slice is
done again here, so the answers are always this process's own.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

T = TypeVar("T")
A = TypeVar("A")

# below this many items the fork costs more than it saves (~10 ms for a 100 MiB process)
FORK_THRESHOLD = 32
# the function and items of the map under way: set before the children fork, which inherit them
_WORK: list[tuple[Callable[[Any], Any], Sequence[Any]]] = []


def _slice(start: int, stop: int) -> list[Any]:
    function, items = _WORK[-1]
    return [function(item) for item in items[start:stop]]


def forked_map(function: Callable[[T], A], items: Sequence[T], jobs: int) -> list[A]:
    """[function(item) for item in items], in `jobs` forked processes when there are enough
    items and this process may fork (no other thread running: a lock it held would stay held
    in the child); in order, exceptions as the serial map raises them."""
    if jobs <= 1 or len(items) < FORK_THRESHOLD or threading.active_count() > 1:
        return [function(item) for item in items]
    from concurrent.futures import Future, ProcessPoolExecutor
    from multiprocessing import get_context

    size = -(-len(items) // jobs)
    bounds = [(start, min(start + size, len(items))) for start in range(0, len(items), size)]
    answers: list[list[A] | None] = [None] * len(bounds)
    _WORK.append((function, items))
    try:
        # the first slice is this process's own, done while the children do theirs: one fork fewer
        with ProcessPoolExecutor(max_workers=len(bounds) - 1, mp_context=get_context("fork")) as pool:
            futures: list[Future[list[A]] | None] = []
            for start, stop in bounds[1:]:
                try:
                    futures.append(pool.submit(_slice, start, stop))
                except Exception:  # noqa: BLE001 - no child (the fork refused: EAGAIN, ENOMEM): done here
                    futures.append(None)
            answers[0] = _slice(*bounds[0])
            for index, future in enumerate(futures, start=1):
                try:
                    answers[index] = future.result() if future is not None else None
                except Exception:  # noqa: BLE001 - the slice is done again below, where `function`'s own exception is raised
                    pass
    finally:
        _WORK.pop()
    out: list[A] = []
    for (start, stop), answer in zip(bounds, answers, strict=True):
        out.extend(answer if answer is not None else [function(item) for item in items[start:stop]])
    return out
