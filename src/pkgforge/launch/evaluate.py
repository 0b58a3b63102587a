"""Evaluating one launch file in the worker: load it, then visit it once per branch.

An argument with choices, or with a true/false default, is evaluated for every
value (so both sides of `gui` are checked); `--launch-arg` values are fixed.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.util
import os
import re
import sys
import traceback
from collections.abc import Callable, Iterator
from typing import Any

from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.actions import TimerAction
from pkgforge.launch.builtin.launch.command import running_xacro
from pkgforge.launch.builtin.launch.errors import (
    FAILURE_PROGRAM,
    FAILURE_VARIABLE,
    Unresolved,
    failure_mark,
    failure_text,
    failure_type,
    missing_configuration,
)
from pkgforge.launch.builtin.launch.event_handlers import EVENT_READ, HANDLING, HandledEvent, handler_event
from pkgforge.launch.builtin.launch.frontend_reader import FrontendReader, register
from pkgforge.launch.builtin.launch.launch_context import MISSING_PACKAGE_ROOT, RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.launch_description_sources import load_description
from pkgforge.launch.builtin.launch_ros.substitutions import lookup_package
from pkgforge.launch.frontend import parse_file, parse_substitution
from pkgforge.launch.place import LAUNCH_FILES, here
from pkgforge.launch.records import (
    BranchBudget,
    Error,
    ErrorRecordDict,
    ErrorStage,
    LaunchResultDict,
    Recorder,
    Status,
    UnsetUse,
    as_dict,
    evaluate_branches,
    from_dict,
)

# the launch API reaches the XML/YAML reader through frontend_reader (an included XML file, a
# parameter file's $(...)): wired here, above both, as launch finds launch_xml by entry point
register(FrontendReader(parse_file=parse_file, parse_substitution=parse_substitution))

MAX_DEPTH = 32
NOT_FOUND = re.compile(r"package '([^']+)' not found")
IMPORTED_FROM = re.compile(r" \((?:/|<)[^\n]*?\.py\)$")


def _location_in(path: str, error: BaseException) -> int | None:
    """The deepest traceback line inside the launch file (or any launch file being evaluated)."""
    line = None
    for frame in traceback.extract_tb(error.__traceback__):
        if frame.filename == path or frame.filename in LAUNCH_FILES:
            line = frame.lineno
    if line is None and isinstance(error, SyntaxError) and error.filename == path:
        line = error.lineno
    return line


def _missing_package_of(error: BaseException) -> str | None:
    """The package not found here whose stand-in folder this error touched (a consequence of
    that lookup, already reported), else None."""
    texts = [str(error), str(getattr(error, "filename", "") or "")]
    for text in texts:
        index = text.find(MISSING_PACKAGE_ROOT + "/")
        if index >= 0:
            rest = text[index + len(MISSING_PACKAGE_ROOT) + 1 :]
            return re.split(r"[/'\"\s]", rest, maxsplit=1)[0] or None
    # a module looked for in a folder the file put on sys.path from a package not found here
    # (sys.path.append(os.path.join(get_package_share_directory('realsense2_camera'), 'launch')))
    return _package_folder_on_path(MISSING_PACKAGE_ROOT + "/", error)


def _empty_read_consequence(error: BaseException) -> bool:
    """Whether a failure is what reading a file that is not there becomes in a launch file's own
    code: its helper returned None (the MoveIt tutorials' load_yaml: `except EnvironmentError:
    return None`) or an empty list, and the next line used it. A NameError, an ImportError, a
    KeyError or a TypeError about anything but None (Node() without executable=) is the file's."""
    if isinstance(error, IndexError):
        return True
    return isinstance(error, (TypeError, AttributeError)) and "NoneType" in str(error)


# spans of RECORDER.stand_in_reads, (start, end); end None: to the last one
Spans = list[tuple[int, "int | None"]]


def _read_package(root: str, spans: Spans | None = None) -> str | None:
    """The package whose folder under `root` (`root`/<package>/...) the file read first, among
    the reads in `spans` (all of them when None)."""
    reads = RECORDER.stand_in_reads
    chosen = reads if spans is None else [path for start, end in spans for path in reads[start:end]]
    for path in chosen:
        if path.startswith(root):
            return path[len(root) :].split(os.sep)[0] or None
    return None


def _missing_package_read() -> str | None:
    """The package not found here whose empty stand-in the loading file read (opened or listed)
    first. Where the package is not found either, its lookup raised PackageNotFoundError and
    loading stopped there; here the lookup returned the stand-in and loading went on, so a
    failure an empty read leads to is that lookup's consequence: doosan's dsr_moveit2.launch.py
    reads a YAML file from the stand-in, its own try returns None, and `dict.update(None)` raised
    a TypeError at a line with nothing wrong on it. A failure with no such read before it stays
    the file's own (a lookup caught by a try in a caller may return the stand-in too)."""
    return _read_package(MISSING_PACKAGE_ROOT + os.sep)


def _not_installed_read(error: BaseException, spans: Spans | None = None) -> str | None:
    """The declared package, not installed here (its share folder an empty phantom), that the
    loading file read from when its loading failed: the file not found there, or (for a failure
    an empty read leads to) the first such package whose share folder it opened or listed. On the
    user's machine the package is installed and the file is there: not the launch file's fault."""
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    if not phantom:
        return None
    share = os.path.join(phantom, "share") + os.sep
    filename = getattr(error, "filename", None)
    if isinstance(error, OSError) and isinstance(filename, str):
        return filename[len(share) :].split(os.sep)[0] or None if filename.startswith(share) else None
    return _read_package(share, spans) if _empty_read_consequence(error) else None


# what reading a file (or a folder) is to Python's audit hooks
READ_EVENTS = frozenset({"open", "os.listdir", "os.scandir", "glob.glob"})
_READS_WATCHED: list[bool] = []


def _watch_stand_in_reads() -> None:
    """Note every path the launch file opens or lists in a package's stand-in (not found here) or
    phantom share folder (declared, not installed here): an audit hook, once per process (a hook
    cannot be removed; it notes into the recorder of the file being evaluated)."""
    if _READS_WATCHED:
        return
    _READS_WATCHED.append(True)
    roots = [MISSING_PACKAGE_ROOT + os.sep]
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    if phantom:
        roots.append(os.path.join(phantom, "share") + os.sep)
    prefixes = tuple(roots)
    index = tuple(os.path.join(root, "ament_index") + os.sep for root in roots)

    def note(event: str, args: tuple[Any, ...]) -> None:
        if event not in READ_EVENTS or not args or not isinstance(args[0], str):
            return
        # (the package lookups' own reads of the ament index are not the file's)
        if args[0].startswith(prefixes) and not args[0].startswith(index):
            RECORDER.stand_in_reads.append(args[0])

    sys.addaudithook(note)


def _nowhere_else(error: BaseException) -> bool:
    """A module not found whose top-level name is found nowhere on the path: a module of its own
    (rs_launch), not a misspelt name inside an installed one (launch_ros.actionz)."""
    if not isinstance(error, ModuleNotFoundError) or not error.name:
        return False
    try:
        return importlib.util.find_spec(error.name.split(".")[0]) is None
    except (ImportError, ValueError):
        return False


def _package_folder_on_path(root: str, error: BaseException) -> str | None:
    """The package under `root` whose folder the file put on sys.path (the last one) when `error`
    is the import of a module found nowhere else: the module is that package's."""
    if not _nowhere_else(error):
        return None
    for entry in reversed(sys.path):
        if isinstance(entry, str) and entry.startswith(root):
            return entry[len(root) :].split(os.sep)[0] or None
    return None


def _declared_folder_on_path(error: BaseException) -> str | None:
    """The declared package, not installed here, whose (empty, phantom) share folder the file put
    on sys.path to import a module from."""
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    return _package_folder_on_path(os.path.join(phantom, "share") + os.sep, error) if phantom else None


# the command-line tools of a ROS 2 (and Gazebo) installation: a launch file may run one while
# loading, and this machine may have none. Any other program not found is the file's own error
# programs a sourced ROS (or the simulator it brings) puts on PATH: install(TARGETS ... DESTINATION
# bin), not lib/<package>/ as a node's executable (rviz2's CMakeLists, rqt_gui's setup.py)
ROS_PROGRAMS = frozenset({"ros2", "gz", "ign", "rviz2", "rqt", "gazebo", "gzserver", "gzclient"})


def _ros_program_not_found(error: BaseException) -> str | None:
    """The program FindExecutable did not find on PATH, when it is one a sourced ROS puts there
    (ros2, gz): a node's executable lives in lib/<package>/, never on PATH, and a misspelt name
    (pyhton3, xacroo) fails everywhere, so those stay the file's error."""
    found = failure_mark(error, FAILURE_PROGRAM)
    return found if found in ROS_PROGRAMS else None


def _program_not_found(error: BaseException) -> str | None:
    """The ROS tool a subprocess call named by its bare name and did not find on PATH
    (realsense's `subprocess.run(['ros2', 'component', 'types'])` where ROS is not installed), or
    that FindExecutable did not find (`FindExecutable(name='ros2')`, the "Using event handlers"
    tutorial): on the user's machine, with ROS sourced, PATH has it."""
    found = _ros_program_not_found(error)
    if found is not None:
        return found
    name = getattr(error, "filename", None)
    if not isinstance(error, FileNotFoundError) or name not in ROS_PROGRAMS:
        return None
    frames = traceback.extract_tb(error.__traceback__)
    return name if any(os.path.basename(f.filename) == "subprocess.py" for f in frames) else None


def _error_record(path: str, error: BaseException, stage: ErrorStage) -> ErrorRecordDict:
    shown: BaseException = error
    if type(error).__name__ == "FrontendError" and error.__cause__ is not None:
        # the built-in front end's refusal of an element wraps what building it raised: that
        # error (launch's own, as the real engine reports it) at the element's line
        shown = error.__cause__
    message = failure_text(shown)
    if isinstance(error, SystemExit):
        message = f"SystemExit: the launch file called sys.exit({error.code!r})"
    if isinstance(error, ImportError) and not isinstance(error, ModuleNotFoundError):
        # "cannot import name 'X' from 'launch.substitutions' (/opt/ros/.../__init__.py)": where
        # the module lives (the distro's, or pkgforge's stand-in of it) is not the user's problem,
        # and the same refusal must read the same through both engines
        message = IMPORTED_FROM.sub("", message)
    record: ErrorRecordDict = {
        "stage": stage,
        "type": failure_type(shown),
        "message": message,
        "file": path,
        "line": _location_in(path, error),
    }
    if type(error).__name__ == "PackageNotFoundError":
        match = NOT_FOUND.search(str(error))
        record["package"] = match.group(1) if match else str(error).strip("'\"")
    missing = _missing_package_of(error)
    if missing is None and stage == "load" and _empty_read_consequence(error):
        missing = _missing_package_read()
    if missing is not None:
        # the file stopped on the empty stand-in of a package not found: that lookup is the cause
        lookup = next((p for p in RECORDER.packages if p.name == missing and p.found is False), None)
        record.update(
            {
                "type": "PackageNotFoundError",
                "package": missing,
                "message": f"PackageNotFoundError: package '{missing}' not found",
            }
        )
        if lookup is not None:
            record["file"], record["line"] = lookup.file, lookup.line
            return as_dict(from_dict(Error, record))
    if missing is None and stage == "load":
        absent = _not_installed_read(error)
        if absent is not None:
            record["read_from"] = absent
    if isinstance(error, ModuleNotFoundError):
        record["module"] = error.name
        owner = _declared_folder_on_path(error)
        if owner is not None:
            record["package"] = owner
    program = _program_not_found(error)
    if program is not None:
        record["program"] = program
    variable = failure_mark(error, FAILURE_VARIABLE)
    if variable is not None:
        record["variable"] = variable
    line = getattr(error, "line", None)  # the built-in front end's FrontendError
    if line and type(error).__name__ == "FrontendError":
        record["line"] = line
    if record["line"] is None and stage == "load":
        record["line"] = _null_byte_line(path, message)
    frames = traceback.extract_tb(error.__traceback__)
    origin = next((f for f in reversed(frames) if f.filename in LAUNCH_FILES), None)
    if origin is not None:
        record["file"], record["line"] = origin.filename, origin.lineno
    return as_dict(from_dict(Error, record))


def _null_byte_line(path: str, message: str) -> int | None:
    """Python's refusal of a launch file with a NUL byte (a UTF-16 file) names no line: the line
    of the file's first NUL, when the file itself has one (not a module it imports)."""
    if "source code string cannot contain null bytes" not in message or not path.endswith(".py"):
        return None
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError:
        return None
    index = data.find(b"\0")
    return data.count(b"\n", 0, index) + 1 if index >= 0 else None


# what an event handler runs with the event's effects (nav2_minimal_tb4_sim's OnShutdown
# OpaqueFunction removes the file an ExecuteProcess wrote): its failure before the event is no finding
RUNS_ON_THE_EVENT = ("OpaqueFunction", "OpaqueCoroutine")


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


def _configurations_set_by(entity: object) -> set[str]:
    """The launch configurations `entity` sets when it executes, as far as its names are plain
    text (both engines' DeclareLaunchArgument, SetLaunchConfiguration (<let>) and include
    arguments): when it fails, a use of them after it fails as a consequence, not on its own."""
    kind = type(entity).__name__
    if kind == "DeclareLaunchArgument":
        name = getattr(entity, "name", None)
        return {name} if isinstance(name, str) else set()
    names: list[object] = []
    if kind == "SetLaunchConfiguration":
        names = [getattr(entity, "name", None)]
    elif kind in INCLUDES:
        names = [pair[0] for pair in getattr(entity, "launch_arguments", None) or [] if len(pair) == 2]
    return {text for text in map(_plain_name, names) if text}


def _plain_name(name: object) -> str | None:
    """A configuration's name given as text (a str, or TextSubstitutions only), else None."""
    if isinstance(name, str):
        return name
    parts = name if isinstance(name, (list, tuple)) else [name]
    texts = [getattr(part, "text", None) for part in parts]
    return (
        "".join(t for t in texts if isinstance(t, str))
        if texts and all(isinstance(t, str) for t in texts)
        else None
    )


def record_visit_failure(
    entity: object, error: Exception, spans: Spans | None = None, loading: Spans | None = None
) -> None:
    """What an entity's failure during the visit records; the visit goes on (both engines).
    `spans`: the stand-in reads that are the entity's own and its OpaqueFunction ancestors';
    `loading`: those the included files it came from made while loading."""
    unset = missing_configuration(error)
    would_set = _configurations_set_by(entity)
    if unset is not None:  # settled when the visit is done (settle_unset_uses)
        name, at = unset
        running = RUNNING[-1] if RUNNING else None
        RECORDER.unset_uses.append(
            UnsetUse(
                name,
                type(entity).__name__,
                (getattr(entity, "_file", None), getattr(entity, "_line", None)),
                at,
                running.kind if running else None,
                running is not None and name in running.configurations,
                RECORDER.unfollowed[-1] if RECORDER.unfollowed else None,
                name in RECORDER.failed_sets,
            )
        )
        RECORDER.failed_sets.update(would_set)
        return
    RECORDER.failed_sets.update(would_set)
    if type(entity).__name__ in INCLUDES:  # what the included file declares is not known now
        located = (getattr(entity, "_file", None), getattr(entity, "_line", None))
        last = RECORDER.includes[-1] if RECORDER.includes else None
        RECORDER.unfollowed.append(last.path if last and (last.file, last.line) == located else "")
    if isinstance(error, Unresolved):
        RECORDER.add("required", {"name": error.name, "skipped": type(entity).__name__}, entity)
        return
    missing = _missing_package_of(error)
    if missing is not None:  # a consequence of a lookup already reported
        RECORDER.add(
            "required", {"name": f"<package {missing} not found>", "skipped": type(entity).__name__}, entity
        )
        return
    if type(error).__name__ == "PackageNotFoundError":
        match = NOT_FOUND.search(str(error))
        RECORDER.add(
            "packages",
            {
                "name": match.group(1) if match else str(error).strip("'\""),
                "via": type(entity).__name__,
                "found": False,
            },
            entity,
        )
        return
    named = failure_mark(error, FAILURE_PROGRAM)
    record: ErrorRecordDict = {
        "stage": "visit",
        "type": type(error).__name__,
        # (the real library formats FindExecutable's name, a list of substitutions: its program)
        "message": f"executable '{named}' not found on the PATH" if named else str(error),
        "file": getattr(entity, "_file", None),
        "line": getattr(entity, "_line", None),
        "entity": type(entity).__name__,
    }
    if isinstance(error, ModuleNotFoundError):  # an included file's import (its package's, maybe)
        record["module"] = error.name
    # (a subprocess's program not found stays the action's error here: only FindExecutable's)
    program = _ros_program_not_found(error)
    if program is not None:  # FindExecutable(name='ros2'): on PATH where ROS is sourced
        record["program"] = program
    variable = failure_mark(error, FAILURE_VARIABLE)
    if variable is not None:  # EnvironmentVariable('USER') without a default, not set here
        record["variable"] = variable
    if HANDLING and EVENT_READ[0] and _empty_read_consequence(error):
        record["event_values"] = True  # event.cmd[0], event.action.process_details['name']
    absent = _not_installed_read(error, spans)
    if absent is not None:  # an OpaqueFunction reading a declared package's file, not installed here
        record["read_from"] = absent
    elif spans is not None and (
        before := _not_installed_read(error, [(0, RECORDER.load_reads), *(loading or [])])
    ):
        record["read_before"] = before  # what loading read: maybe the cause, maybe not
    RECORDER.add("errors", record)


def _watch_xacro() -> None:
    """Record models a Python launch file processes with the xacro module itself (seed 000's style)."""
    import xacro

    if getattr(xacro, "_pkgforge_watched", False):
        return
    real_parse, real_process_file = xacro.parse, xacro.process_file

    def note(path: object, via: str, mappings: object = None) -> None:
        # only a call from the launch file itself: xacro calls parse() for every include too
        caller = sys._getframe(2).f_code.co_filename
        if caller not in LAUNCH_FILES:
            return
        if isinstance(path, os.PathLike):  # xacro opens a pathlib.Path as it opens a str
            path = os.fspath(path)
        if not running_xacro() and isinstance(path, str) and os.path.isabs(path):
            file, line = here()
            # the xacro arguments it gives (andino's spawn_robot: use_gazebo_ros_control), so the
            # model is checked as the file processes it, not failing for want of them
            given = (
                {str(k): str(v) for k, v in mappings.items() if isinstance(v, (str, int, float, bool))}
                if isinstance(mappings, dict)
                else {}
            )
            RECORDER.add(
                "commands",
                {
                    "command": ["xacro", path, *(f"{k}:={v}" for k, v in sorted(given.items()))],
                    "ok": True,
                    "message": "",
                    "model": path,
                    "mappings": given,
                    "via": via,
                    "file": file,
                    "line": line,
                },
            )
            RECORDER.add("packages", {"name": "xacro", "via": via, "file": file, "line": line})

    def parse(inp: Any, filename: str | None = None, **kwargs: Any) -> Any:
        note(filename or getattr(inp, "name", None), "xacro.parse")
        return real_parse(inp, filename, **kwargs)

    def process_file(input_file_name: str, **kwargs: Any) -> Any:
        note(input_file_name, "xacro.process_file", kwargs.get("mappings"))
        return real_process_file(input_file_name, **kwargs)

    xacro._pkgforge_real_process_file = real_process_file  # Command(['xacro', ...]) records itself
    xacro.parse, xacro.process_file = parse, process_file
    xacro._pkgforge_watched = True


def _watch_ament() -> None:
    """A launch file's own ament_index lookups are recorded; a package not found here is
    reported and stands in as an empty package, so the rest of the file is still checked
    (lookups by xacro or by the launch API itself are left alone)."""
    try:
        import ament_index_python
        import ament_index_python.packages as packages
    except ImportError:
        return
    if getattr(packages, "_pkgforge_watched", False):
        return

    def from_launch_file() -> bool:
        return sys._getframe(2).f_code.co_filename in LAUNCH_FILES

    real_prefix = packages.get_package_prefix
    real_share = packages.get_package_share_directory
    real_share_path: Callable[..., Any] | None = getattr(packages, "get_package_share_path", None)

    def get_package_prefix(package_name: str) -> str:
        if from_launch_file():
            return lookup_package(package_name, "get_package_prefix", here(), "prefix")
        return real_prefix(package_name)

    def get_package_share_directory(package_name: str, *args: Any, **kwargs: Any) -> str:
        if from_launch_file():
            return lookup_package(package_name, "get_package_share_directory", here())
        return real_share(package_name, *args, **kwargs)

    def get_package_share_path(package_name: str, *args: Any, **kwargs: Any) -> Any:
        import pathlib

        if from_launch_file():
            return pathlib.Path(lookup_package(package_name, "get_package_share_path", here()))
        assert real_share_path is not None  # patched in only where the module has it
        return real_share_path(package_name, *args, **kwargs)

    get_package_prefix.__dict__["_pkgforge_real"] = real_prefix  # lookup_package calls it
    patched: dict[str, Callable[..., Any]] = {
        "get_package_prefix": get_package_prefix,
        "get_package_share_directory": get_package_share_directory,
    }
    if real_share_path is not None:
        patched["get_package_share_path"] = get_package_share_path
    for module in (packages, ament_index_python):
        for name, function in patched.items():
            if hasattr(module, name):
                setattr(module, name, function)
    vars(packages)["_pkgforge_watched"] = True


def evaluate(path: str, overrides: dict[str, str], budget: BranchBudget | None = None) -> LaunchResultDict:
    """Resolve one launch file; the result is plain data (JSON). `budget`: how long the argument
    combinations past the defaults may run (records.evaluate_branches)."""
    # what the file adds to sys.path (a folder of another package's share, to import a module
    # from: openmanipulator's rs_launch) is its own: the next file in this worker starts without it
    path_before = list(sys.path)
    try:
        return _evaluate(path, overrides, budget)
    finally:
        sys.path[:] = path_before


def _evaluate(path: str, overrides: dict[str, str], budget: BranchBudget | None) -> LaunchResultDict:
    _watch_xacro()
    _watch_ament()
    _watch_stand_in_reads()
    RECORDER.reset()  # a fresh record for each file
    LAUNCH_FILES.clear()
    LAUNCH_FILES.add(path)
    try:
        description = load_description(path)
    except BaseException as error:  # noqa: BLE001 - SystemExit and friends included
        return _result("load-error", _error_record(path, error, "load"), RECORDER)
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
