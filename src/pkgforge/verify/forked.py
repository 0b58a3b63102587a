"""A function mapped over slices of items in forked children that share this process's memory.

verify's checks run after every launch file is evaluated, on one core while the
others wait; the model loaders run beside colcon's discovery. Forked children see
the models, resolutions and install tree as they are here (copy on write: nothing
is pickled on the way in), each maps its slice, and only the answers come back,
pickled through a pipe. Plain fork and pipes, not a process pool: a fork the
system refuses (EAGAIN at the process limit, ENOMEM), a child that dies, an answer
that cannot be pickled all leave that slice to this process, and nothing is left
waiting (a pool whose second fork failed kept its first worker, and the exit
handlers waited for it forever).
"""

from __future__ import annotations

import os
import pickle
import signal
import threading
from collections.abc import Callable, Sequence
from typing import Any, Generic, TypeVar

T = TypeVar("T")
A = TypeVar("A")

# below this many items the fork costs more than it saves (~10 ms for a 100 MiB process)
FORK_THRESHOLD = 32
# what a child answers with when it cannot answer: its slice is done again by the parent
_NO_ANSWER = 1


def slices(count: int, parts: int) -> list[tuple[int, int]]:
    """`parts` (start, stop) bounds, as even as can be, covering range(count)."""
    size = -(-count // max(1, parts))
    return [(start, min(start + size, count)) for start in range(0, count, size)] if count else []


class Forked(Generic[T, A]):
    """Children forked now, one per slice of `items`, each mapping `function` over it; answers()
    collects them (None: that child gave none), stop() ends and reaps any still running."""

    def __init__(self, function: Callable[[T], A], items: Sequence[T], bounds: list[tuple[int, int]]):
        self.bounds = bounds
        self.children: list[tuple[int, int] | None] = [_fork(function, items, *bound) for bound in bounds]

    def answers(self) -> list[list[A] | None]:
        answers: list[list[A] | None] = []
        for index, child in enumerate(self.children):
            answers.append(_collect(child) if child is not None else None)
            self.children[index] = None
        return answers

    def stop(self) -> None:
        for index, child in enumerate(self.children):
            if child is None:
                continue
            pid, pipe = child
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
            _close(pipe)
            _reap(pid)
            self.children[index] = None


def forked_map(function: Callable[[T], A], items: Sequence[T], jobs: int) -> list[A]:
    """[function(item) for item in items], in `jobs` processes (this one does the first slice) when
    there are enough items and this process may fork (no other thread running: a lock it held
    would stay held in the child); in order, exceptions as the serial map raises them."""
    if jobs <= 1 or len(items) < FORK_THRESHOLD or threading.active_count() > 1:
        return [function(item) for item in items]
    bounds = slices(len(items), jobs)
    forked = Forked(function, items, bounds[1:])
    try:
        out = [function(item) for item in items[: bounds[0][1]]]
        answers = forked.answers()
    finally:
        forked.stop()
    for (start, stop), answer in zip(bounds[1:], answers, strict=True):
        # a slice no child answered is done here, where `function`'s own exception is raised
        out.extend(answer if answer is not None else [function(item) for item in items[start:stop]])
    return out


def _fork(
    function: Callable[[Any], Any], items: Sequence[Any], start: int, stop: int
) -> tuple[int, int] | None:
    """(pid, read end of its answer pipe) of a child mapping items[start:stop]; None when the
    system gives no pipe or no process."""
    try:
        read, write = os.pipe()
    except OSError:
        return None
    parent = os.getpid()
    try:
        pid = os.fork()
    except OSError:
        _close(read)
        _close(write)
        return None
    if pid == 0:  # the child: never returns
        status = _NO_ANSWER
        try:
            os.close(read)
            _become_child(parent)
            data = pickle.dumps([function(item) for item in items[start:stop]], pickle.HIGHEST_PROTOCOL)
            with open(write, "wb") as pipe:
                pipe.write(data)
            status = 0
        except BaseException:  # noqa: BLE001, S110 - the parent does the slice and raises what it raises
            pass
        finally:
            os._exit(status)  # no exit handlers of the parent's (its temporary tree), no buffers flushed
    _close(write)
    return pid, read


def _become_child(parent: int) -> None:
    """Signals end the child at once (the parent's handlers would unwind the parent's work), it
    dies with the parent, and its collector does not walk (and so copy) the parent's objects."""
    import gc

    from pkgforge.sandbox.processes import die_with_parent

    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        signal.signal(getattr(signal, name), signal.SIG_DFL)
    die_with_parent(parent)
    gc.disable()


def _collect(child: tuple[int, int]) -> list[Any] | None:
    pid, pipe = child
    try:
        with open(pipe, "rb") as answers:
            data = answers.read()
    except OSError:
        data = b""
    if _reap(pid) != 0:
        return None
    try:
        answer = pickle.loads(data)
    except Exception:  # noqa: BLE001 - cut short: the parent does the slice
        return None
    return answer if isinstance(answer, list) else None


def _reap(pid: int) -> int | None:
    """The child's exit status once it has ended (None: not ours to wait for any more)."""
    try:
        _, status = os.waitpid(pid, 0)
    except ChildProcessError:
        return None
    return os.waitstatus_to_exitcode(status)


def _close(fd: int) -> None:
    try:
        os.close(fd)
    except OSError:
        pass
