"""Every branch of a launch file: its arguments' other values, visited while the worker's budget lasts.

Both engines branch through evaluate_branches, so their records can only differ in what a visit
records, never in which visits run.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TypedDict

from pkgforge.launch.place import LAUNCH_FILES
from pkgforge.launch.records import ITEM_KINDS, Branching, Record, Recorder, RecordKind

MAX_BRANCHES = 16


@dataclass
class BranchBudget:
    """How long a request's extra branches may run (the worker's, per request). The defaults are
    evaluated under the full time limit; a file whose defaults finish is never an error because
    its other argument combinations did not fit: they run only until `deadline` (time.monotonic),
    `limit(seconds)` brings the wall-time alarm forward to it, and a branch the alarm (or the CPU
    limit) stops, raising one of `stops`, is dropped whole and counted as not evaluated."""

    deadline: float
    stops: tuple[type[BaseException], ...]  # the exceptions the worker's limits raise in a launch file
    limit: Callable[[float], None]  # the wall-time alarm no later than that many seconds from now
    release: Callable[[], None]  # the limits off again (the parent's own limit bounds the rest)


_Mark = tuple[list[str], dict[RecordKind, int]]  # a recorder's arguments and record counts


def _mark(recorder: Recorder) -> _Mark:
    return list(recorder.arguments), {kind: len(getattr(recorder, kind)) for kind in ITEM_KINDS}


def _forget(recorder: Recorder, mark: _Mark) -> None:
    """What a stopped branch recorded goes: a half-visited branch is no evaluation."""
    names, lengths = mark
    for name in [n for n in recorder.arguments if n not in names]:
        del recorder.arguments[name]
    for kind, length in lengths.items():
        records: list[Record] = getattr(recorder, kind)
        del records[length:]


# one visit: run(values, label), the argument values it evaluates and the branch its records carry
Visit = Callable[[dict[str, str], dict[str, str]], None]


def evaluate_branches(
    recorder: Recorder,
    path: str,
    overrides: Mapping[str, str],
    run: Visit,
    budget: BranchBudget | None = None,
) -> Branching:
    """Visit once with the defaults, then once per other value of every argument of `path` that has
    choices or a true/false default (at most MAX_BRANCHES), while `budget` lasts. Both engines
    branch through this one function, so their records can only differ in what a visit records,
    never in which visits run. `run(values, label)` performs one visit."""
    # what loading the file recorded (before any visit) holds whatever the arguments: no branch
    loaded = {id(item) for kind in ITEM_KINDS for item in getattr(recorder, kind)}
    run({}, {})
    varying = [
        a
        for a in recorder.arguments.values()
        if a.name not in overrides and a.file == path and (a.choices or a.boolean)
    ]
    if not varying:
        return Branching()
    defaults = {a.name: a.default for a in varying}
    for kind in ITEM_KINDS:
        for item in getattr(recorder, kind):
            if not item.branch and id(item) not in loaded:
                item.branch = dict(defaults)
    # a true/false default written True/False (Python's spelling) gets the other value spelt the
    # same way: a PythonExpression(['not ', flag]) is meant for it, and 'not false' is a NameError
    # (andino's rosbag_record.launch.py, default_value='True'), in ROS as here
    domains = [
        a.choices or (["True", "False"] if a.default in ("True", "False") else ["true", "false"])
        for a in varying
    ]
    for argument, domain in zip(varying, domains, strict=False):
        argument.values = list(domain)
    names = [a.name for a in varying]
    assignments = [
        dict(zip(names, values, strict=False))
        for values in itertools.islice(itertools.product(*domains), MAX_BRANCHES)
    ]
    assignments = [
        a for a in assignments if not all(a[n].lower() == (defaults[n] or "").lower() for n in names)
    ]
    result = Branching(planned=1 + len(assignments))
    if budget is None:
        for assignment in assignments:
            run(assignment, assignment)
        result.evaluated = result.planned
        return result
    current: dict[str, str] | None = None
    mark: _Mark = ([], {})
    try:  # the deadline may come between two branches too: then nothing is running, nothing is lost
        try:
            for assignment in assignments:
                left = budget.deadline - time.monotonic()
                if left <= 0:
                    break
                current, mark = assignment, _mark(recorder)
                budget.limit(left)
                run(assignment, assignment)
                current = None
                result.evaluated += 1
        except budget.stops as stop:
            if current is not None:
                _forget(recorder, mark)
                result.stopped = {
                    "branch": " ".join(f"{k}:={v}" for k, v in sorted(current.items())),
                    **_where_stopped(stop),
                }
        finally:
            budget.release()
    except budget.stops:
        budget.release()
    return result


class _Where(TypedDict):
    file: str | None
    line: int | None


def _where_stopped(error: BaseException) -> _Where:
    """The launch file's line a stopped branch was running (the deepest frame in a launch file)."""
    import traceback

    frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename in LAUNCH_FILES]
    return (
        {"file": frames[-1].filename, "line": frames[-1].lineno} if frames else {"file": None, "line": None}
    )
