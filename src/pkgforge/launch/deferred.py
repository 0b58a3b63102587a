"""What both engines' visits share: entities deferred to their event or timer, what was executed.

launch runs a handler's or timer's entities when their event comes; verify starts nothing, so
they are visited once each after the description, in the order launch would reach them.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Callable, Iterator
from typing import Any

from pkgforge.launch.builtin.launch.event_handlers import EVENT_READ, HANDLING, HandledEvent
from pkgforge.launch.builtin.launch.launch_context import RECORDER

# what an event handler runs with the event's effects (nav2_minimal_tb4_sim's OnShutdown
# OpaqueFunction removes the file an ExecuteProcess wrote): its failure before the event is no finding
RUNS_ON_THE_EVENT = ("OpaqueFunction", "OpaqueCoroutine")


@dataclasses.dataclass
class Deferred:
    """Entities launch runs after the launch description is done (both engines): a TimerAction's
    actions when its period has passed, an event handler's when its event comes. Launch visits
    the whole description at once, then handles events: these run with the launch
    configurations, environment and namespace as the description left them (a scoped
    GroupAction they stood in has ended: ros2/launch#825), and with the locals they had where
    they stood (a TimerAction keeps them; for a handler, so that ThisLaunchFileDir still names
    its file)."""

    entities: list[object]
    kind: str  # TimerAction, or the handler's class (OnProcessExit, OnShutdown...)
    event: object | None  # the stand-in event a handler's entities see; None for a timer
    locals: dict[str, Any]
    configurations: frozenset[str]  # the launch configurations set where it stood
    current_file: str | None  # the built-in engine's file being visited there
    depth: int
    in_handler: bool
    spans: tuple[ReadSpans, ReadSpans]
    # the action whose process the handler watches (target_action): its event never comes when the
    # action never executes (its condition false), and then neither do the handler's entities
    target: object | None = None


DEFERRED: list[Deferred] = []  # in the order they were met (launch's order when all come at once)
RUNNING: list[Deferred] = []  # the deferred entities being visited
EXECUTED: set[int] = set()  # the actions the visit executed (their condition held), by id()


def executed(entity: object) -> None:
    """`entity` is executed in this visit (both engines: its condition held)."""
    EXECUTED.add(id(entity))


def defer(
    context: Any,
    entities: list[object],
    kind: str,
    event: object | None,
    depth: int,
    in_handler: bool,
    spans: tuple[ReadSpans, ReadSpans],
    current_file: str | None = None,
) -> None:
    """Keep a timer's or a handler's entities for when the description is done (both engines)."""
    configurations = frozenset(k for k in context.launch_configurations if isinstance(k, str))
    # (read without marking the stand-in event as read: HandledEvent)
    target = vars(event).get("action") if isinstance(event, HandledEvent) else None
    DEFERRED.append(
        Deferred(
            entities,
            kind,
            event,
            dict(context.get_locals_as_dict()),
            configurations,
            current_file,
            depth,
            in_handler,
            spans,
            target,
        )
    )


def run_deferred(context: Any, run: Callable[[Deferred], None]) -> None:
    """Visit what timers and handlers would run, once the description is done, in the order they
    were met (and what those register, after them): `run(item)` visits one's entities. A handler
    of a process whose action has not executed waits for it (a TimerAction may start it); one
    whose action never executes never runs, as its event never comes."""
    waiting: list[Deferred] = []
    while True:
        while DEFERRED:
            item = DEFERRED.pop(0)
            if item.target is not None and id(item.target) not in EXECUTED:
                waiting.append(item)
                continue
            _run_deferred(context, item, run)
        ready = [w for w in waiting if id(w.target) in EXECUTED]
        if not ready:
            return
        waiting = [w for w in waiting if id(w.target) not in EXECUTED]
        DEFERRED.extend(ready)


def _run_deferred(context: Any, item: Deferred, run: Callable[[Deferred], None]) -> None:
    context._push_locals()
    context.extend_locals(item.locals)
    RUNNING.append(item)
    try:
        if item.event is None:
            run(item)
        else:
            with handling(context, item.event):
                run(item)
    finally:
        RUNNING.pop()
        context._pop_locals()


def begin_visit() -> int:
    """Before one visit (both engines): nothing deferred or unsettled from another; the mark
    settle_unset_uses needs."""
    DEFERRED.clear()
    RUNNING.clear()
    EXECUTED.clear()
    RECORDER.unset_uses.clear()
    RECORDER.unfollowed.clear()
    RECORDER.failed_sets.clear()
    return len(RECORDER.required)


def settle_unset_uses(declared_from: int) -> None:
    """After one visit (both engines): each use of a launch configuration not set is verify's
    want of a value when the visit declared that argument without a default (`ros2 launch`
    refuses to start without it: the user gives it, PF309 says so), and what needed it is
    skipped; any other is launch's SubstitutionFailure, an error at the substitution."""
    declared = {r.name for r in RECORDER.required[declared_from:] if r.skipped is None}
    uses, RECORDER.unset_uses = RECORDER.unset_uses, []
    for use in uses:
        if use.name in declared or use.after_failed_set:
            file, line = use.entity_at
            RECORDER.add("required", {"name": use.name, "skipped": use.entity, "file": file, "line": line})
            continue
        file, line = use.at if use.at[1] is not None else use.entity_at
        RECORDER.add(
            "errors",
            {
                "stage": "visit",
                "type": "SubstitutionFailure",
                "message": f"launch configuration '{use.name}' does not exist",
                "file": file,
                "line": line,
                "entity": use.entity,
                "configuration": use.name,
                "deferred": use.deferred,
                "scoped_away": use.scoped_away,
                "unevaluated_include": use.unevaluated_include,
            },
        )


@contextlib.contextmanager
def handling(context: Any, event: object) -> Iterator[None]:
    """What launch does around an event handler's entities (LaunchService.__process_event, both
    engines): the locals pushed, `event` added (BaseEventHandler.handle), the locals popped after."""
    context._push_locals()
    context.extend_locals({"event": event})
    HANDLING.append(event)
    read, EVENT_READ[0] = EVENT_READ[0], False
    try:
        yield
    finally:
        EVENT_READ[0] = read
        HANDLING.pop()
        context._pop_locals()


# the actions that load another launch file when visited
INCLUDES = ("IncludeLaunchDescription", "ScopedIncludeLaunchDescription")
ReadSpans = tuple[tuple[int, int], ...]


def child_spans(
    entity: object, start: int, ancestors: ReadSpans, loading: ReadSpans
) -> tuple[ReadSpans, ReadSpans]:
    """(ancestors, loading) for the entities `entity` returned, its visit having begun at stand-in
    read `start` (both engines): an OpaqueFunction's own reads count for the actions it returns,
    an include's for what the included file loaded; a description's or a group's children are
    siblings, each with its own reads."""
    own = (start, len(RECORDER.stand_in_reads))
    kind = type(entity).__name__
    return (
        (*ancestors, own) if kind in RUNS_ON_THE_EVENT else ancestors,
        (*loading, own) if kind in INCLUDES else loading,
    )
