"""What a launch file's failure is put down to, and where, as both engines record it.

A package not installed here, a program not on PATH, a variable not set, a read of a package
not found: the cause a failure names, at the launch file's line (the deepest frame in a launch
file), so the report says what to do about it.
"""

from __future__ import annotations

import importlib.util
import os
import re
import sys
import traceback

from pkgforge.launch.builtin.launch.errors import (
    FAILURE_PROGRAM,
    FAILURE_VARIABLE,
    Unresolved,
    failure_mark,
    failure_text,
    failure_type,
    missing_configuration,
)
from pkgforge.launch.builtin.launch.event_handlers import EVENT_READ, HANDLING
from pkgforge.launch.builtin.launch.launch_context import MISSING_PACKAGE_ROOT, RECORDER
from pkgforge.launch.deferred import INCLUDES, RUNNING
from pkgforge.launch.place import LAUNCH_FILES
from pkgforge.launch.records import Error, ErrorRecordDict, ErrorStage, UnsetUse, as_dict, from_dict

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


def error_record(path: str, error: BaseException, stage: ErrorStage) -> ErrorRecordDict:
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
