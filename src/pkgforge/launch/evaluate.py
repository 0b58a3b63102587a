"""Evaluating one launch file in the worker: load it, then visit it once per branch.

An argument with choices, or with a true/false default, is evaluated for every
value (so both sides of `gui` are checked); `--launch-arg` values are fixed.
"""

from __future__ import annotations

import sys

from pkgforge.launch.branches import BranchBudget, evaluate_branches
from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.actions import TimerAction
from pkgforge.launch.builtin.launch.event_handlers import handler_event
from pkgforge.launch.builtin.launch.frontend_reader import FrontendReader, register
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.launch_description_sources import load_description
from pkgforge.launch.deferred import (
    RUNS_ON_THE_EVENT,
    Deferred,
    begin_visit,
    child_spans,
    defer,
    executed,
    run_deferred,
    settle_unset_uses,
)
from pkgforge.launch.failures import error_record, record_visit_failure
from pkgforge.launch.frontend import parse_file, parse_substitution
from pkgforge.launch.place import LAUNCH_FILES
from pkgforge.launch.records import (
    ErrorRecordDict,
    LaunchResultDict,
    Recorder,
    Status,
)
from pkgforge.launch.watch import watch_ament, watch_stand_in_reads, watch_xacro

# the launch API reaches the XML/YAML reader through frontend_reader (an included XML file, a
# parameter file's $(...)): wired here, above both, as launch finds launch_xml by entry point
register(FrontendReader(parse_file=parse_file, parse_substitution=parse_substitution))

MAX_DEPTH = 32


def visit(
    entities: list[object],
    context: LaunchContext,
    depth: int = 0,
    in_handler: bool = False,
    ancestors: tuple[tuple[int, int], ...] = (),
    loading: tuple[tuple[int, int], ...] = (),
) -> None:
    """Visit the entities; `ancestors`: the stand-in reads the OpaqueFunctions they came from made
    themselves; `loading`: those the included files they came from made while loading (spans of
    RECORDER.stand_in_reads)."""
    if depth > MAX_DEPTH:
        RECORDER.add(
            "errors",
            {
                "stage": "visit",
                "type": "RecursionError",
                "message": f"launch files include each other more than {MAX_DEPTH} deep",
                "file": context.current_file,
                "line": None,
            },
        )
        return
    for entity in entities:
        if not isinstance(entity, LaunchDescriptionEntity):
            continue
        condition = getattr(entity, "condition", None) if isinstance(entity, Action) else None
        start = len(RECORDER.stand_in_reads)  # (what this entity reads from here on is its own)
        try:
            if condition is not None:
                taken = bool(condition.evaluate(context))
                RECORDER.add(
                    "conditions",
                    {"condition": type(condition).__name__, "entity": type(entity).__name__, "taken": taken},
                    entity,
                )
                if not taken:
                    continue
            executed(entity)
            children = entity.visit(context)
        except Exception as error:  # noqa: BLE001 - every failure is a finding, none a crash
            if not (in_handler and type(entity).__name__ in RUNS_ON_THE_EVENT):
                record_visit_failure(entity, error, [*ancestors, (start, None)], list(loading))
            continue
        if children:
            spans = child_spans(entity, start, ancestors, loading)
            kind = type(entity).__name__
            if isinstance(entity, TimerAction):  # (ROSTimer too)
                defer(
                    context,
                    list(children),
                    "TimerAction",
                    None,
                    depth + 1,
                    in_handler,
                    spans,
                    context.current_file,
                )
            elif kind == "RegisterEventHandler":
                handler = getattr(entity, "event_handler", None)
                event = handler_event(handler, getattr(handler, "target_action", None))
                kind = type(handler).__name__
                defer(context, list(children), kind, event, depth + 1, True, spans, context.current_file)
            else:
                visit(list(children), context, depth + 1, in_handler, *spans)


def evaluate(path: str, overrides: dict[str, str], budget: BranchBudget | None = None) -> LaunchResultDict:
    """Resolve one launch file; the result is plain data (JSON). `budget`: how long the argument
    combinations past the defaults may run (branches.evaluate_branches)."""
    # what the file adds to sys.path (a folder of another package's share, to import a module
    # from: openmanipulator's rs_launch) is its own: the next file in this worker starts without it
    path_before = list(sys.path)
    try:
        return _evaluate(path, overrides, budget)
    finally:
        sys.path[:] = path_before


def _evaluate(path: str, overrides: dict[str, str], budget: BranchBudget | None) -> LaunchResultDict:
    watch_xacro()
    watch_ament()
    watch_stand_in_reads()
    RECORDER.reset()  # a fresh record for each file
    LAUNCH_FILES.clear()
    LAUNCH_FILES.add(path)
    try:
        description = load_description(path)
    except BaseException as error:  # noqa: BLE001 - SystemExit and friends included
        return _result("load-error", error_record(path, error, "load"), RECORDER)
    RECORDER.load_reads = len(RECORDER.stand_in_reads)

    def run(values: dict[str, str], label: dict[str, str]) -> None:
        RECORDER.branch = label
        context = LaunchContext()
        context.current_file = path
        context.launch_configurations.update(overrides)
        context.launch_configurations.update(values)
        declared_from = begin_visit()
        visit([description], context)

        def run_one(item: Deferred) -> None:
            previous, context.current_file = context.current_file, item.current_file
            try:
                visit(item.entities, context, item.depth, item.in_handler, *item.spans)
            finally:
                context.current_file = previous

        run_deferred(context, run_one)
        settle_unset_uses(declared_from)

    branching = evaluate_branches(RECORDER, path, overrides, run, budget)
    result = _result("ok", None, RECORDER)
    result["branching"] = branching.as_reply()
    return result


def _result(status: Status, error: ErrorRecordDict | None, recorder: Recorder) -> LaunchResultDict:
    result: LaunchResultDict = {"status": status, "error": error}
    recorder.dump_into(result)
    result["files"] = sorted(LAUNCH_FILES)
    result["engine"] = "builtin"
    return result
