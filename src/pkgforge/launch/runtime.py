"""pkgforge's implementation of the ROS 2 launch API that description packages use.

It runs only inside the launch worker subprocess. Objects record where the
launch file constructed them; evaluation visits a LaunchDescription the way
`ros2 launch` would (arguments, conditions, includes, OpaqueFunction) but,
instead of starting processes, records nodes, looked-up packages, resolved
paths and commands into a Recorder. Semantics follow ros2/launch: a list of
substitutions concatenates, Command splits with shlex, a missing launch
configuration is an error, conditions accept true/false/1/0 only.
"""

from __future__ import annotations

import collections.abc
import logging
import os
import re
import shlex
import subprocess
import sys
import typing
from collections.abc import Callable, Iterable, Mapping, Sequence
from types import FrameType, ModuleType
from typing import Any, TypeGuard, TypeVar

# --- where a construct stands in the launch file --------------------------------------------

_LAUNCH_FILES: set[str] = set()  # files being evaluated; frames in them are "user" frames
_FRONTEND_LOCATION: list[
    tuple[str | None, int | None]
] = []  # (file, line) while the XML/YAML frontend builds
_RUNNING_XACRO = False  # pkgforge's own xacro run (a Command), not the launch file's


def here() -> tuple[str | None, int | None]:
    """The launch file and line that constructed the object being created."""
    if _FRONTEND_LOCATION:
        return _FRONTEND_LOCATION[-1]
    frame: FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_filename in _LAUNCH_FILES:
            return frame.f_code.co_filename, frame.f_lineno
        frame = frame.f_back
    return None, None


_Made = TypeVar("_Made", bound="Located")


class Located:
    """Base of every stand-in object: remembers its launch file and line.

    A class exposed under a real API name carries `_pkgforge_check` (set by api.py): the
    real constructor's signature, checked before anything else as ROS would."""

    _file: str | None
    _line: int | None

    def __new__(cls: type[_Made], *args: Any, **kwargs: Any) -> _Made:  # the launch file's arguments
        check = cls.__dict__.get("_pkgforge_check")
        if check is not None:
            check(args, kwargs)
        return object.__new__(cls)

    def __init__(self) -> None:
        self._file, self._line = here()


# --- errors ---------------------------------------------------------------------------------


class SubstitutionFailure(RuntimeError):
    pass


# what a substitution's failure carries of its cause, for the record (evaluate._error_record,
# evaluate.record_visit_failure); both engines set it, on their own SubstitutionFailure
FAILURE_PROGRAM = "_pkgforge_program"  # FindExecutable: the program not found on PATH
FAILURE_VARIABLE = "_pkgforge_variable"  # EnvironmentVariable without a default: the variable not set
FAILURE_CONFIGURATION = "_pkgforge_configuration"  # LaunchConfiguration not set: its name (ros_engine)
FAILURE_CONFIGURATION_AT = "_pkgforge_configuration_at"  # and its place
FAILURE_MARKS = (FAILURE_PROGRAM, FAILURE_VARIABLE, FAILURE_CONFIGURATION)
_Failure = TypeVar("_Failure", bound=BaseException)


def marked(error: _Failure, mark: str, value: str) -> _Failure:
    """`error`, carrying `value` under `mark` (one of FAILURE_MARKS) unless it carries one
    already (the innermost substitution's failure is the cause)."""
    if all(failure_mark(error, known) is None for known in FAILURE_MARKS):
        try:
            setattr(error, mark, value)
        except AttributeError:  # an exception type without a __dict__: no mark
            pass
    return error


def failure_mark(error: BaseException, mark: str) -> str | None:
    value = getattr(error, mark, None)
    return value if isinstance(value, str) else None


class InvalidLaunchFileError(Exception):
    pass


class InvalidPythonLaunchFileError(InvalidLaunchFileError):
    pass


class InvalidFrontendLaunchFileError(InvalidLaunchFileError):
    pass


class InvalidConditionExpressionError(SubstitutionFailure):
    def __init__(
        self,
        expression: str,
        expression_substitutions: object = None,
        valid_expressions: list[str] | None = None,
    ) -> None:
        valid = valid_expressions or VALID_TRUE_EXPRESSIONS + VALID_FALSE_EXPRESSIONS
        super().__init__(f"Unexpected condition expression '{expression}', expected one of: {valid}")


class PackageNotFoundError(KeyError):
    """ament_index_python's error, re-raised by FindPackageShare as in launch_ros."""


class Unresolved(Exception):
    """A launch configuration with no value: what depends on it is skipped, not guessed."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name


class MissingConfiguration(SubstitutionFailure, Unresolved):
    """LaunchConfiguration's failure in launch: no value set and no default. Launch's own
    SubstitutionFailure (a launch file's `except SubstitutionFailure` catches it, as in ROS), and
    Unresolved: verify has no value for a launch argument declared without a default either,
    and what needs one is skipped then (evaluate.settle_unset_uses tells the two apart). `where`:
    the LaunchConfiguration's place in the launch file."""

    def __init__(self, name: str, where: tuple[str | None, int | None]) -> None:
        SubstitutionFailure.__init__(self, f"launch configuration '{name}' does not exist")
        self.name, self.where = name, where


MISSING_CONFIGURATION_TEXT = re.compile(r"launch configuration '([^']*)' does not exist")


def missing_configuration(error: BaseException) -> tuple[str, tuple[str | None, int | None]] | None:
    """(name, the LaunchConfiguration's place or (None, None)) when `error` is launch's failure
    of a launch configuration not set (both engines), else None."""
    if isinstance(error, MissingConfiguration):
        return error.name, error.where
    name = getattr(error, FAILURE_CONFIGURATION, None)
    if isinstance(name, str):
        where = getattr(error, FAILURE_CONFIGURATION_AT, (None, None))
        return name, where
    match = MISSING_CONFIGURATION_TEXT.search(str(error))
    return (match.group(1), (None, None)) if match else None


def failure_type(error: BaseException) -> str:
    """The failure's type as launch names it (both engines: MissingConfiguration is launch's
    SubstitutionFailure)."""
    return "SubstitutionFailure" if isinstance(error, MissingConfiguration) else type(error).__name__


def failure_text(error: BaseException) -> str:
    """An action's failure as both engines write it: launch's exception type and message."""
    return f"{failure_type(error)}: {error}"


# --- the record -----------------------------------------------------------------------------

from pkgforge.launch.records import (  # noqa: E402  (the record format both engines share)
    PREVIEW_LENGTH,
    CommandRunRecordDict,
    ExecutionRecordDict,
    NodeRecordDict,
    PackageLookupRecordDict,
    ParameterForm,
    ParameterRecordDict,
    Recorder,
    runs_at_verify_time,
)

RECORDER = Recorder()

# --- context --------------------------------------------------------------------------------


class LaunchContext:
    def __init__(self, *, argv: list[str] | None = None, noninteractive: bool = False) -> None:
        # name → value; str, except what launch_ros keeps there too: "global_params" (a list of
        # (name, value) and parameter file paths) and "ros_remaps" (a list of (src, dst))
        self.launch_configurations: dict[str, Any] = {}
        self.environment = dict(os.environ)
        self._initial_environment = dict(os.environ)
        self._environment_stack: list[dict[str, str]] = []
        self.locals = _Locals()
        self._locals_stack: list[dict[str, Any]] = []
        self.argv = argv or []
        self.noninteractive = noninteractive
        self._stack: list[dict[str, Any]] = []
        self.current_file: str | None = None

    def perform_substitution(self, substitution: Substitution) -> str:
        return substitution.perform(self)

    def extend_locals(self, values: dict[str, Any]) -> None:  # any objects an action shares
        self.locals.__dict__.update(values)

    def get_locals_as_dict(self) -> dict[str, Any]:
        return dict(self.locals.__dict__)

    def _push_locals(self) -> None:  # launch's own, around an event handler's entities
        self._locals_stack.append(dict(self.locals.__dict__))

    def _pop_locals(self) -> None:
        self.locals.__dict__.clear()
        self.locals.__dict__.update(self._locals_stack.pop())

    def _push(self) -> None:
        self._stack.append(dict(self.launch_configurations))

    def _pop(self) -> None:
        self.launch_configurations = self._stack.pop()


class _Locals:
    pass


# --- substitutions --------------------------------------------------------------------------


class Substitution(Located):
    def perform(self, context: LaunchContext) -> str:  # pragma: no cover - overridden
        raise NotImplementedError

    def describe(self) -> str:
        return type(self).__name__


def normalize(subs: SomeSubstitutionsType) -> list[Substitution]:
    """launch.utilities.normalize_to_list_of_substitutions: str | Substitution | iterable of
    those → list of Substitutions; anything else raises the TypeError ROS raises (iterating
    a bool or an int fails, an item of another type is refused)."""
    if isinstance(subs, str):
        return [TextSubstitution(text=subs)]
    if isinstance(subs, Substitution):
        return [subs]
    out: list[Substitution] = []
    for item in subs:
        if isinstance(item, Substitution):
            out.append(item)
        elif isinstance(item, str):
            out.append(TextSubstitution(text=item))
        else:
            raise TypeError(
                f"Failed to normalize given item of type '{type(item)}', when only "
                "'str' or 'launch.Substitution' were expected."
            )
    return out


def perform(context: LaunchContext, value: SomeSubstitutionsType | None) -> str:
    """Concatenate the performed substitutions (None → ''): pkgforge's own shorthand."""
    if value is None:
        return ""
    return joined(normalize(value), lambda s: s.perform(context))


def perform_substitutions(context: LaunchContext, subs: Iterable[Substitution]) -> str:
    """launch.utilities.perform_substitutions (a list of Substitutions)."""
    return joined(subs, context.perform_substitution)


_Part = TypeVar("_Part")
# what goes on naming one file: a path performed right before one of these is only the start of
# the name the list builds (`[PathJoinSubstitution([share, 'xacro', model]), '.urdf.xacro']`)
_NAME_CHARACTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-/")
JOINED_VIA = "PathJoinSubstitution and the text joined to it"


def joined(parts: Iterable[_Part], perform_one: Callable[[_Part], str]) -> str:
    """A list of substitutions performed and concatenated, as launch does it (both engines: the
    real engine's perform_substitutions calls this too). A path a PathJoinSubstitution recorded
    that is only part of one name in the result (text goes on right after it, or comes right
    before it) names no file of its own: launch gives the whole name to whoever reads it (Command
    joins before it splits). Its record becomes that whole name when that is an absolute path
    (so a typo in the suffix is still a missing file), and is dropped when it is not."""
    texts: list[str] = []
    own: list[tuple[int, int]] = []  # (the part, its PathJoinSubstitution's record)
    complete = False
    try:
        for part in parts:
            mark = len(RECORDER.paths)
            text = perform_one(part)
            for k in range(len(RECORDER.paths) - 1, mark - 1, -1):
                record = RECORDER.paths[k]
                if record.path == text and record.via in ("PathJoinSubstitution", JOINED_VIA):
                    own.append((len(texts), k))
                    break
            texts.append(text)
        complete = True
    finally:  # a part that fails: the names the parts before it began are not known whole
        if own:
            _whole_names(texts, own, complete)
    return "".join(texts)


def _whole_names(texts: list[str], own: list[tuple[int, int]], complete: bool) -> None:
    """`joined`'s records of paths that are only part of a name: each that name, or dropped."""
    result = "".join(texts)
    gone: list[int] = []
    for index, k in own:
        start = sum(len(t) for t in texts[:index])
        end = start + len(texts[index])
        # text before it makes it the end of a name unless that is a separator, name:= or file://
        goes_on = start > 0 and result[start - 1] != "/" and result[start - 1] in _NAME_CHARACTERS
        # a separator after it, or nothing (when no part after it failed)
        ends = (end < len(result) and result[end] not in _NAME_CHARACTERS) or (
            end == len(result) and complete
        )
        if not goes_on and ends:
            continue  # the whole name
        while goes_on and start and result[start - 1] in _NAME_CHARACTERS:
            start -= 1
        own_end = end
        while end < len(result) and result[end] in _NAME_CHARACTERS:
            end += 1
        if set(result[own_end:end]) == {"."}:
            end = own_end  # a sentence's full stop or ellipsis ('Loading ', path, '.'): no part of a name
        if end == own_end and not goes_on and (end < len(result) or complete):
            continue  # only punctuation after it: the whole name
        name = result[start:end]
        if end == len(result) and not complete:
            gone.append(k)  # the part after it failed: where the name ends is not known
        elif os.path.isabs(name) and not name.startswith(MISSING_PACKAGE_ROOT):
            record = RECORDER.paths[k]
            record.path, record.via, record.exists = name, JOINED_VIA, os.path.exists(name)
        else:
            gone.append(k)
    for k in sorted(gone, reverse=True):
        del RECORDER.paths[k]


def _stringify_default(default: object) -> list[Substitution]:
    """LaunchConfiguration's default: items that are not str or Substitution become str()."""
    items = default if isinstance(default, collections.abc.Iterable) else (default,)
    return normalize([i if isinstance(i, (str, Substitution)) else str(i) for i in items])


def _substitution_items(value: object) -> TypeGuard[Iterable[str | Substitution]]:
    """strs and Substitutions, at least one Substitution (launch takes len() of any iterable)."""
    return (
        isinstance(value, collections.abc.Iterable)
        and not isinstance(value, str)
        and len(typing.cast(collections.abc.Sized, value)) > 0
        and all(isinstance(v, (str, Substitution)) for v in value)
        and any(isinstance(v, Substitution) for v in value)
    )


def _plain_text(value: object) -> SomeSubstitutionsType:
    """EqualsSubstitution's operand: None → '', a bool → 'true'/'false', else str()."""
    if isinstance(value, Substitution) or _substitution_items(value):
        return value
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(value).lower()
    return str(value)


class TextSubstitution(Substitution):
    def __init__(self, *, text: str = "") -> None:
        super().__init__()
        self.text = text

    def perform(self, context: LaunchContext) -> str:
        return self.text


class LaunchConfiguration(Substitution):
    def __init__(self, variable_name: SomeSubstitutionsType, *, default: object = None) -> None:
        super().__init__()
        self.variable_name = normalize(variable_name)
        self.default = None if default is None else _stringify_default(default)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.variable_name)
        if name in context.launch_configurations:
            value: str = context.launch_configurations[name]
            return value
        if self.default is not None:
            return perform(context, self.default)
        raise MissingConfiguration(name, (self._file, self._line))


class PathJoinSubstitution(Substitution):
    def __init__(self, substitutions: Iterable[SomeSubstitutionsType]) -> None:
        super().__init__()
        self.substitutions = list(substitutions)

    def perform(self, context: LaunchContext) -> str:
        parts = [perform(context, part) for part in self.substitutions]
        result = os.path.join(*parts) if parts else ""
        _record_path(result, self, "PathJoinSubstitution")
        return result


class EnvironmentVariable(Substitution):
    def __init__(
        self, name: SomeSubstitutionsType, *, default_value: SomeSubstitutionsType | None = None
    ) -> None:
        super().__init__()
        self.name = name
        self.default_value = default_value

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        value = context.environment.get(name)
        if value is None:
            if self.default_value is None:
                failure = SubstitutionFailure(f"environment variable '{name}' does not exist")
                raise marked(failure, FAILURE_VARIABLE, name)
            return perform(context, self.default_value)
        return value


class FindExecutable(Substitution):
    def __init__(self, *, name: SomeSubstitutionsType) -> None:
        super().__init__()
        self.name = name

    def perform(self, context: LaunchContext) -> str:
        import shutil

        name = perform(context, self.name)
        found = shutil.which(name)
        if name == "xacro":
            RECORDER.add("packages", {"name": "xacro", "via": "FindExecutable"}, self)
        if found is None:
            failure = SubstitutionFailure(f"executable '{name}' not found on the PATH")
            raise marked(failure, FAILURE_PROGRAM, name)
        return found


class PythonExpression(Substitution):
    def __init__(
        self,
        expression: SomeSubstitutionsType,
        python_modules: SomeSubstitutionsType = ["math"],  # noqa: B006 - launch's default
    ) -> None:
        super().__init__()
        ensure_argument_type(
            expression, (str, Substitution, collections.abc.Iterable), "expression", "PythonExpression"
        )
        ensure_argument_type(
            python_modules,
            (str, Substitution, collections.abc.Iterable),
            "python_modules",
            "PythonExpression",
        )
        self.expression = normalize(expression)
        self.python_modules = normalize(python_modules)

    def perform(self, context: LaunchContext) -> str:
        import importlib

        names: dict[str, Any] = {}  # what the expression may name: modules and math's functions
        for sub in self.python_modules:
            module = importlib.import_module(context.perform_substitution(sub))
            if module.__name__ == "math":
                names.update(vars(module))
            names[module.__name__] = module
        return str(eval(perform_substitutions(context, self.expression), {}, names))


MISSING_PACKAGE_ROOT = "/nonexistent-pkgforge-missing-package"


class Command(Substitution):
    """Runs only what is a pure function of files (records.runs_at_verify_time); any other
    command (a `ros2 param get`, a script) is run-time only: recorded, not run."""

    def __init__(self, command: SomeSubstitutionsType, *, on_stderr: SomeSubstitutionsType = "fail") -> None:
        super().__init__()
        self.command = normalize(command)
        self.on_stderr = normalize(on_stderr)

    def perform(self, context: LaunchContext) -> str:
        return command_output(
            self, perform_substitutions(context, self.command), perform_substitutions(context, self.on_stderr)
        )


def command_output(
    owner: object, text: str, on_stderr: str, failure: type[Exception] = SubstitutionFailure
) -> str:
    """`Command.perform` of both engines (the real engine's Command calls it too, with launch's
    own SubstitutionFailure): launch's on_stderr rule; a command verify may run is run (once per
    file) and recorded; a run-time only one is recorded as such and its output is '' ."""
    words = shlex.split(text)
    if not words:
        raise failure("empty command")
    if on_stderr not in ("fail", "ignore", "warn", "capture"):
        raise failure("expected 'on_stderr' to be one of: 'fail', 'ignore', 'warn' or 'capture'")
    if not runs_at_verify_time(words):
        RECORDER.add(
            "commands",
            {"command": words, "text": text, "ok": True, "message": "", "runtime_only": True},
            owner,
        )
        return ""
    if any(w.startswith(MISSING_PACKAGE_ROOT) for w in words):
        raise Unresolved(f"<{words[0]} of a file in a package not found>")
    key = tuple(words)
    if key not in RECORDER.command_cache:
        RECORDER.command_cache[key] = _run_command(words)
    ok, output, message, extra = RECORDER.command_cache[key]
    stderr = extra.get("stderr", "")
    extra = extra.copy()  # (the cached one stays whole)
    extra.pop("stderr", None)
    problem = None
    if ok and stderr and on_stderr == "fail":
        # launch fails a Command that writes to stderr unless on_stderr says otherwise
        problem = f"executed command showed stderr output. Command: {text}\nCaptured stderr output:\n{stderr}"
        first = stderr.strip().splitlines()[0] if stderr.strip() else ""
        ok, message = (
            False,
            (
                f"{first} (written to stderr: Command's on_stderr='fail' stops the launch; "
                "fix the warning or pass on_stderr='warn')"
            ),
        )
    elif ok and stderr and on_stderr == "capture":
        output = output + stderr
    record: CommandRunRecordDict = {"command": words, "text": text, "ok": ok, "message": message, **extra}
    if os.path.basename(words[0]) == "xacro":
        RECORDER.add("packages", {"name": "xacro", "via": "Command xacro"}, owner)
        for word in words[1:]:
            if ":=" not in word and not word.startswith("-"):
                _record_path(word, owner, "xacro input")
                record["model"] = word
                break
        record["mappings"] = dict(w.split(":=", 1) for w in words[1:] if ":=" in w)
    RECORDER.add("commands", record, owner)
    if not ok:
        raise failure(
            problem if problem is not None else f"executed command failed. Command: {text}\n{message}"
        )
    return output


def _run_command(words: list[str]) -> tuple[bool, str, str, CommandRunRecordDict]:
    """Run a Command; xacro runs in this process with the real xacro library."""
    if os.path.basename(words[0]) == "xacro":
        return _run_xacro(words[1:])
    try:
        done = subprocess.run(words, capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    except FileNotFoundError as exc:
        return False, "", f"file not found: {exc}", {}
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, "", str(exc), {}
    if done.returncode != 0:
        return False, "", (f"Captured stderr output: {done.stderr}" if done.stderr else ""), {}
    return True, done.stdout, "", {"stderr": done.stderr}


def _run_xacro(args: list[str]) -> tuple[bool, str, str, CommandRunRecordDict]:
    """xacro with the real library (urdf.robot's runner); a success also yields the model's
    structure, so the model checks need not run xacro on it a second time."""
    from pkgforge.urdf.robot import run_xacro, structure_of_output

    files = [a for a in args if ":=" not in a and not a.startswith("-")]
    mappings = dict(a.split(":=", 1) for a in args if ":=" in a)
    if not files:
        return False, "", "xacro: no input file", {}
    global _RUNNING_XACRO
    _RUNNING_XACRO = True
    try:
        run = run_xacro(files[0], mappings)
    finally:
        _RUNNING_XACRO = False
    if run.failure is not None:
        exc = run.failure
        message = getattr(exc, "msg", None) or str(exc) or type(exc).__name__
        return False, "", f"{message}\n{run.stderr.strip()}".strip(), {}
    output = run.document.toprettyxml(indent="  ")
    robot = structure_of_output(files[0], output, run.includes)
    found: CommandRunRecordDict = {"robot": robot, "includes": run.includes} if robot else {}
    return True, output, "", {**found, "stderr": run.stderr}


class ThisLaunchFileDir(Substitution):
    def perform(self, context: LaunchContext) -> str:
        return os.path.dirname(context.current_file or "")


class ThisLaunchFile(Substitution):
    def perform(self, context: LaunchContext) -> str:
        return context.current_file or ""


class AnonName(Substitution):
    def __init__(self, name: SomeSubstitutionsType) -> None:
        super().__init__()
        self.name = name

    def perform(self, context: LaunchContext) -> str:
        return f"{perform(context, self.name)}_{os.getpid()}"


class LocalSubstitution(Substitution):
    def __init__(self, expression: str, description: str | None = None) -> None:
        super().__init__()
        self.expression = expression

    def perform(self, context: LaunchContext) -> str:
        # the value as it is, as launch returns it (an int such as event.returncode fails where
        # the substitutions are joined, as in ROS)
        value: str = eval(self.expression, {}, context.get_locals_as_dict())
        return value


def _truth(text: str) -> bool:
    """A condition's expression (evaluate_condition_expression): true/1, false/0, nothing else."""
    lowered = text.strip().lower()
    if lowered in VALID_TRUE_EXPRESSIONS:
        return True
    if lowered in VALID_FALSE_EXPRESSIONS:
        return False
    raise InvalidConditionExpressionError(lowered)


VALID_TRUE_EXPRESSIONS = ["true", "1"]
VALID_FALSE_EXPRESSIONS = ["false", "0"]


def _typed_bool(context: LaunchContext, subs: Iterable[Substitution]) -> bool:
    """perform_typed_substitution(..., bool): '1'/'0', else YAML's booleans (yes, on, True…)."""
    import yaml

    text = perform_substitutions(context, subs)
    # '1'/'0' are booleans from Iron on; humble's launch reads them as YAML integers (refused)
    value = text if _api_distro() == "humble" else {"1": "true", "0": "false"}.get(text, text)
    try:
        output = yaml.safe_load(value) if value else value
    except yaml.YAMLError as error:
        raise SubstitutionFailure(  # noqa: B904 - launch raises it inside the except, with the YAML error as context
            f"Failed to convert '{value}' to '{bool}': yaml.safe_load() failed\n{error}"
        )
    if isinstance(output, bool):
        return output
    raise SubstitutionFailure(f"Cannot convert value '{value}' to '{bool}'")


class NotSubstitution(Substitution):
    def __init__(self, value: SomeSubstitutionsType) -> None:
        super().__init__()
        self.value = normalize(value)

    def perform(self, context: LaunchContext) -> str:
        return str(not _typed_bool(context, self.value)).lower()


class AndSubstitution(Substitution):
    def __init__(self, left: SomeSubstitutionsType, right: SomeSubstitutionsType) -> None:
        super().__init__()
        self.left, self.right = normalize(left), normalize(right)

    def perform(self, context: LaunchContext) -> str:
        left, right = _typed_bool(context, self.left), _typed_bool(context, self.right)
        return str(left and right).lower()


class OrSubstitution(AndSubstitution):
    def perform(self, context: LaunchContext) -> str:
        left, right = _typed_bool(context, self.left), _typed_bool(context, self.right)
        return str(left or right).lower()


class AllSubstitution(Substitution):
    def __init__(self, *args: SomeSubstitutionsType) -> None:
        super().__init__()
        self.args = [normalize(a) for a in args]

    def perform(self, context: LaunchContext) -> str:
        return str(all([_typed_bool(context, a) for a in self.args])).lower()


class AnySubstitution(AllSubstitution):
    def perform(self, context: LaunchContext) -> str:
        return str(any([_typed_bool(context, a) for a in self.args])).lower()


def _str_is_bool(text: str) -> bool:
    return isinstance(text, str) and text.lower() in ("true", "false", "1", "0")


def _str_is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


class EqualsSubstitution(Substitution):
    """Typed as in launch: booleans compare as booleans (True equals 1), numbers as numbers
    (1 equals 1.0), anything else as text."""

    def __init__(self, left: object, right: object) -> None:  # any value: see _plain_text
        super().__init__()
        self.left, self.right = normalize(_plain_text(left)), normalize(_plain_text(right))

    def _equal(self, context: LaunchContext) -> bool:
        import math

        left = perform_substitutions(context, self.left)
        right = perform_substitutions(context, self.right)
        if _str_is_bool(left) and _str_is_bool(right):
            return (left.lower() in ("true", "1")) == (right.lower() in ("true", "1"))
        if _str_is_float(left) and _str_is_float(right):
            return math.isclose(float(left), float(right))
        return left == right

    def perform(self, context: LaunchContext) -> str:
        return str(self._equal(context)).lower()


class NotEqualsSubstitution(EqualsSubstitution):
    def perform(self, context: LaunchContext) -> str:
        return str(not self._equal(context)).lower()


class IfElseSubstitution(Substitution):
    def __init__(
        self,
        condition: SomeSubstitutionsType,
        if_value: SomeSubstitutionsType = "",
        else_value: SomeSubstitutionsType = "",
    ) -> None:
        super().__init__()
        if if_value == else_value == "":
            raise RuntimeError("One of if_value and else_value must be specified")
        self.condition = normalize(condition)
        self.if_value, self.else_value = normalize(if_value), normalize(else_value)

    def perform(self, context: LaunchContext) -> str:
        chosen = self.if_value if _typed_bool(context, self.condition) else self.else_value
        return perform_substitutions(context, chosen)


class FileContent(Substitution):
    def __init__(self, path: SomeSubstitutionsType) -> None:
        super().__init__()
        self.path = normalize(path)

    def perform(self, context: LaunchContext) -> str:
        path = perform_substitutions(context, self.path)
        _record_path(path, self, "FileContent")
        if path.startswith(MISSING_PACKAGE_ROOT):
            raise Unresolved(f"<a file of a package not found: {path}>")
        try:
            with open(path, encoding="utf-8") as handle:
                return handle.read()
        except FileNotFoundError:
            raise SubstitutionFailure(f"File not found: {path}") from None


# launch_ros substitutions


def lookup_package(
    package: str, via: str, where: object | tuple[str | None, int | None], kind: str = "share"
) -> str:
    """A package's share (or prefix) folder, the lookup recorded. A package not found here is
    recorded as such and stands in as an empty package (a path that exists nowhere), so the
    rest of the file is still evaluated."""
    from ament_index_python.packages import PackageNotFoundError as AmentNotFound
    from ament_index_python.packages import get_package_prefix

    item: PackageLookupRecordDict = {"name": package, "via": via}
    guarded = False
    if isinstance(where, tuple):
        item["file"], item["line"] = where
        guarded = _guarded(*where) or _guarded_on_stack()
        where = None
    known = RECORDER.prefix_cache  # one search of the prefixes per package and file (a file asks ~9 times)
    if package not in known:
        try:
            known[package] = getattr(get_package_prefix, "_pkgforge_real", get_package_prefix)(package)
        except (AmentNotFound, PackageNotFoundError, ValueError) as error:
            known[package] = error
    try:
        found = known[package]
        if isinstance(found, BaseException):
            raise type(found)(*found.args)
        prefix = found
    except (AmentNotFound, PackageNotFoundError, ValueError):
        if guarded:
            raise  # the launch file catches it: probing for an optional package
        RECORDER.add("packages", {**item, "found": False}, where)
        prefix = os.path.join(MISSING_PACKAGE_ROOT, package)
    else:
        RECORDER.add("packages", item, where)
    return prefix if kind == "prefix" else os.path.join(prefix, "share", package)


_GUARDS: dict[str, list[tuple[int, int]]] = {}
CATCHING = {"PackageNotFoundError", "KeyError", "LookupError", "Exception", "BaseException"}


def _guarded_on_stack() -> bool:
    """Whether any launch file's frame on the stack stands inside a try that catches a failed
    lookup: a helper (`def share_of(p): return get_package_share_directory(p)`) called inside the
    try of its caller raises to that try in ROS, as here."""
    frame: FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_filename in _LAUNCH_FILES and _guarded(frame.f_code.co_filename, frame.f_lineno):
            return True
        frame = frame.f_back
    return False


def _guarded(file: str | None, line: int | None) -> bool:
    """Whether the launch file's line is inside a try whose handlers catch a failed lookup."""
    import ast

    if file is None or line is None:
        return False
    if file not in _GUARDS:
        spans: list[tuple[int, int]] = []
        tree: ast.Module | None
        try:
            with open(file, encoding="utf-8") as handle:
                tree = ast.parse(handle.read())
        except (OSError, SyntaxError, ValueError):
            tree = None
        for node in ast.walk(tree) if tree is not None else []:
            if isinstance(node, ast.Try) and node.body:
                names: set[str] = set()
                for handler in node.handlers:
                    if handler.type is None:
                        names.add("BaseException")
                    for part in ast.walk(handler.type) if handler.type is not None else []:
                        if isinstance(part, (ast.Name, ast.Attribute)):
                            names.add(part.id if isinstance(part, ast.Name) else part.attr)
                if names & CATCHING:
                    spans.append((node.body[0].lineno, node.body[-1].end_lineno or node.body[-1].lineno))
        _GUARDS[file] = spans
    return any(start <= line <= end for start, end in _GUARDS[file])


class FindPackage(Substitution):
    _performing = False

    def __init__(self, package: SomeSubstitutionsType) -> None:
        super().__init__()
        self.package = normalize(package)

    def perform(self, context: LaunchContext) -> str:
        self._performing = True
        try:
            return self.find(perform_substitutions(context, self.package))
        finally:
            self._performing = False

    def find(self, package_name: str) -> str:
        raise NotImplementedError()

    def _place_of_lookup(self) -> FindPackage | tuple[str | None, int | None]:
        # performed: the object's place; called directly by the launch file: that call's place
        return self if self._performing else here()


class FindPackagePrefix(FindPackage):
    def find(self, package_name: str) -> str:
        return lookup_package(package_name, "FindPackagePrefix", self._place_of_lookup(), "prefix")


class FindPackageShare(FindPackage):
    def find(self, package_name: str) -> str:
        return lookup_package(package_name, "FindPackageShare", self._place_of_lookup())


class ExecutableInPackage(Substitution):
    def __init__(self, executable: SomeSubstitutionsType, package: SomeSubstitutionsType) -> None:
        super().__init__()
        self.executable, self.package = normalize(executable), normalize(package)

    def perform(self, context: LaunchContext) -> str:
        return executable_in_package(
            self,
            perform_substitutions(context, self.executable),
            perform_substitutions(context, self.package),
        )


def executable_in_package(owner: object, executable: str, package: str) -> str:
    """`ExecutableInPackage.perform` of both engines: the package's prefix looked up (recorded; a
    package not found here stands in as an empty one) and the executable in its lib/<package>
    folder, found there or not. launch_ros refuses an executable that is not there; verify does
    not: a predicted install tree holds no build products, so an executable missing from it says
    nothing about the real install (the package's build installs it)."""
    import shutil

    if PREPARING[0]:  # the node's own package, looked up and recorded by its visit already
        prefix = _quiet_prefix(package)
    else:
        prefix = lookup_package(package, "ExecutableInPackage", owner, "prefix")
    libexec = os.path.join(prefix, "lib", package)
    found = shutil.which(executable, path=libexec) if os.path.isdir(libexec) else None
    return found or os.path.join(libexec, executable)


def _quiet_prefix(package: str) -> str:
    """A package's prefix as lookup_package finds it (its stand-in when not found), unrecorded."""
    from ament_index_python.packages import PackageNotFoundError as AmentNotFound
    from ament_index_python.packages import get_package_prefix

    known = RECORDER.prefix_cache
    if package not in known:
        try:
            known[package] = getattr(get_package_prefix, "_pkgforge_real", get_package_prefix)(package)
        except (AmentNotFound, PackageNotFoundError, ValueError) as error:
            known[package] = error
    found = known[package]
    return os.path.join(MISSING_PACKAGE_ROOT, package) if isinstance(found, BaseException) else found


def _record_path(path: object, obj: object, via: str) -> None:
    """An absolute path the launch file resolves, recorded (both engines); none under a package
    not found here (that lookup is reported already)."""
    if isinstance(path, str) and path and os.path.isabs(path) and not path.startswith(MISSING_PACKAGE_ROOT):
        RECORDER.add("paths", {"path": path, "via": via, "exists": os.path.exists(path)}, obj)


# --- conditions -----------------------------------------------------------------------------


class Condition(Located):
    def __init__(self, *, predicate: Callable[[LaunchContext], bool] | None = None) -> None:
        super().__init__()
        self.predicate = predicate

    def evaluate(self, context: LaunchContext) -> bool:
        return bool(self.predicate(context)) if self.predicate else True


class IfCondition(Condition):
    def __init__(self, predicate_expression: SomeSubstitutionsType) -> None:
        super().__init__()
        self.expression = predicate_expression

    def evaluate(self, context: LaunchContext) -> bool:
        return _truth(perform(context, self.expression))


class UnlessCondition(IfCondition):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


class LaunchConfigurationEquals(Condition):
    def __init__(self, launch_configuration_name: str, expected_value: SomeSubstitutionsType | None) -> None:
        super().__init__()
        self.name, self.expected = launch_configuration_name, expected_value

    def evaluate(self, context: LaunchContext) -> bool:
        value = context.launch_configurations.get(self.name)
        expected = None if self.expected is None else perform(context, self.expected)
        return value == expected


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


def evaluate_condition_expression(context: LaunchContext, expression: SomeSubstitutionsType) -> bool:
    return _truth(perform(context, expression))


# --- entities -------------------------------------------------------------------------------


class LaunchDescriptionEntity(Located):
    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None

    def describe_sub_entities(self) -> list[LaunchDescriptionEntity]:
        return []


class Action(LaunchDescriptionEntity):
    # the other keyword arguments of launch's Action (and its subclasses'), not evaluated
    def __init__(self, *, condition: Condition | None = None, **_ignored: Any) -> None:
        super().__init__()
        self.condition = condition


class LaunchDescription(LaunchDescriptionEntity):
    def __init__(
        self,
        initial_entities: Iterable[LaunchDescriptionEntity] | None = None,
        *,
        deprecated_reason: str | None = None,
    ) -> None:
        super().__init__()
        self.entities = list(initial_entities or [])

    def add_action(self, action: Action) -> None:
        self.entities.append(action)

    def add_entity(self, entity: LaunchDescriptionEntity) -> None:
        self.entities.append(entity)

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return list(self.entities)

    def get_launch_arguments(self, conditional_inclusion: bool = False) -> list[DeclareLaunchArgument]:
        return [e for e in self.entities if isinstance(e, DeclareLaunchArgument)]


class DeclareLaunchArgument(Action):
    def __init__(
        self,
        name: str,
        *,
        default_value: SomeSubstitutionsType | None = None,
        description: str | None = None,
        choices: Sequence[str] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.name = name
        # normalised as launch does: a bool or an int default is a TypeError, as in ROS
        self.default_value = None if default_value is None else normalize(default_value)
        if choices is not None:
            if len(choices) == 0:
                raise RuntimeError("Provided choices arg is empty. Use None to ignore the choice list.")
            if (
                default_value is not None
                and not isinstance(default_value, (Substitution, list))
                and default_value not in choices
            ):
                raise RuntimeError(
                    f'Provided default_value "{default_value}" is not in provided choices "{choices}".'
                )
        self.description = description
        # as launch keeps it: choices=('wxai') is the str 'wxai', and launch's `value not in choices`
        # is then a substring test ('wxai' passes); the branches evaluated are that one word
        self.choices: Sequence[str] | None = (
            choices if isinstance(choices, str) else (list(choices) if choices is not None else None)
        )

    def visit(self, context: LaunchContext) -> None:
        default = None
        if self.default_value is not None:
            try:
                default = perform_substitutions(context, self.default_value)
            except Unresolved:
                default = None
        RECORDER.arguments.setdefault(
            self.name,
            {
                "name": self.name,
                "default": default,
                "choices": [self.choices] if isinstance(self.choices, str) else _as_list(self.choices),
                "file": self._file,
                "line": self._line,
                "boolean": default is not None and default.lower() in ("true", "false"),
            },
        )
        if self.name not in context.launch_configurations:
            if self.default_value is None:
                # ROS stops here (a required argument); verify records it and goes on
                RECORDER.add("required", {"name": self.name}, self)
                return None
            context.launch_configurations[self.name] = perform_substitutions(context, self.default_value)
        value = context.launch_configurations[self.name]
        if self.choices is not None and value not in self.choices:
            raise RuntimeError(
                f'Argument "{self.name}" provided value "{value}" is not valid. Valid options '
                f"are: {self.choices}"
            )
        return None


def _as_list(choices: Sequence[str] | None) -> list[str] | None:
    return None if choices is None else list(choices)


class SetLaunchConfiguration(Action):
    def __init__(self, name: SomeSubstitutionsType, value: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)

    def visit(self, context: LaunchContext) -> None:
        context.launch_configurations[perform_substitutions(context, self.name)] = perform_substitutions(
            context, self.value
        )


class UnsetLaunchConfiguration(Action):
    def __init__(self, name: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = normalize(name)

    def visit(self, context: LaunchContext) -> None:
        context.launch_configurations.pop(perform_substitutions(context, self.name), None)


class GroupAction(Action):
    """Scoped: configurations and environment restored after; forwarding=False: the group
    starts with only its own launch_configurations and the original environment."""

    def __init__(
        self,
        actions: Iterable[Action],
        *,
        scoped: bool = True,
        forwarding: bool = True,
        launch_configurations: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.actions = actions
        self.scoped, self.forwarding = scoped, forwarding
        self.launch_configurations = launch_configurations if launch_configurations is not None else {}

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        actions = list(self.actions)
        sets = [SetLaunchConfiguration(k, v) for k, v in self.launch_configurations.items()]
        if not self.scoped:
            return [*sets, *actions]
        if self.forwarding:
            return [
                PushLaunchConfigurations(),
                PushEnvironment(),
                *sets,
                *actions,
                PopEnvironment(),
                PopLaunchConfigurations(),
            ]
        return [
            PushLaunchConfigurations(),
            PushEnvironment(),
            ResetEnvironment(),
            ResetLaunchConfigurations(self.launch_configurations),
            *actions,
            PopEnvironment(),
            PopLaunchConfigurations(),
        ]


class PushLaunchConfigurations(Action):
    def visit(self, context: LaunchContext) -> None:
        context._push()


class PopLaunchConfigurations(Action):
    def visit(self, context: LaunchContext) -> None:
        context._pop()


class ResetLaunchConfigurations(Action):
    def __init__(
        self,
        launch_configurations: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.keep = launch_configurations

    def visit(self, context: LaunchContext) -> None:
        kept = {
            perform_substitutions(context, normalize(k)): perform_substitutions(context, normalize(v))
            for k, v in (self.keep or {}).items()
        }
        context.launch_configurations.clear()
        context.launch_configurations.update(kept)


class PushEnvironment(Action):
    def visit(self, context: LaunchContext) -> None:
        context._environment_stack.append(dict(context.environment))


class PopEnvironment(Action):
    def visit(self, context: LaunchContext) -> None:
        if not context._environment_stack:
            raise RuntimeError("environment stack unexpectedly empty")
        context.environment = context._environment_stack.pop()


class ResetEnvironment(Action):
    def visit(self, context: LaunchContext) -> None:
        context.environment = dict(context._initial_environment)


class OpaqueFunction(Action):
    def __init__(
        self,
        *,
        function: Callable[..., list[LaunchDescriptionEntity] | None],
        args: Iterable[Any] | None = None,  # the launch file's own values, passed on as they are
        kwargs: dict[str, Any] | None = None,
        **rest: Any,
    ) -> None:
        super().__init__(**rest)
        self.function, self.args, self.kwargs = function, args or [], kwargs or {}

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return self.function(context, *self.args, **self.kwargs)


class SetEnvironmentVariable(Action):
    def __init__(self, name: SomeSubstitutionsType, value: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)

    def visit(self, context: LaunchContext) -> None:
        name, value = perform_substitutions(context, self.name), perform_substitutions(context, self.value)
        context.environment[name] = value


class AppendEnvironmentVariable(Action):
    def __init__(
        self,
        name: SomeSubstitutionsType,
        value: SomeSubstitutionsType,
        *,
        prepend: bool | SomeSubstitutionsType = False,
        separator: SomeSubstitutionsType = os.pathsep,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)
        self.prepend, self.separator = prepend, separator

    def visit(self, context: LaunchContext) -> None:
        name, value = perform_substitutions(context, self.name), perform_substitutions(context, self.value)
        prepend = (
            self.prepend if isinstance(self.prepend, bool) else _typed_bool(context, normalize(self.prepend))
        )
        separator = perform(context, self.separator)
        current = context.environment.get(name)
        if current:
            value = f"{value}{separator}{current}" if prepend else f"{current}{separator}{value}"
        context.environment[name] = value


class UnsetEnvironmentVariable(Action):
    def __init__(self, name: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name = normalize(name)

    def visit(self, context: LaunchContext) -> None:
        context.environment.pop(perform_substitutions(context, self.name), None)


class LogInfo(Action):
    def __init__(self, *, msg: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.msg = normalize(msg)

    def visit(self, context: LaunchContext) -> None:
        perform_substitutions(context, self.msg)  # as launch logs it: its substitutions are performed
        return None


class TimerAction(Action):
    """Its actions would start after `period`: they are checked like any other."""

    def __init__(
        self,
        *,
        period: float | SomeSubstitutionsType,
        actions: Iterable[LaunchDescriptionEntity],
        cancel_on_shutdown: bool | SomeSubstitutionsType = True,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.period = period
        self.actions = list(actions)
        self.cancel_on_shutdown = cancel_on_shutdown

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        # what its execute performs; its actions run when the period has passed (evaluate.defer)
        if not isinstance(self.cancel_on_shutdown, bool):
            _typed_bool(context, normalize(self.cancel_on_shutdown))
        return list(self.actions)


class RegisterEventHandler(Action):
    def __init__(self, event_handler: BaseEventHandler, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.event_handler = event_handler

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        # the handler's entities may run: check them like any other
        return list(getattr(self.event_handler, "entities", []))


# a handler's entities: what it starts, or a function of the event (known only at run time)
HandlerEntities = typing.Union["SomeEntitiesType", Callable[..., object], None]  # noqa: UP007


class BaseEventHandler(Located):
    # matcher: a predicate on launch's events (never seen at verify time); **_ignored: the rest
    # of the real handler's keyword arguments
    def __init__(
        self, *, matcher: Callable[[Any], bool] | None = None, handle_once: bool = False, **_ignored: Any
    ) -> None:
        super().__init__()
        self.entities: list[LaunchDescriptionEntity] = []


class EventHandler(BaseEventHandler):
    def __init__(
        self,
        *,
        matcher: Callable[[Any], bool] | None = None,
        entities: HandlerEntities = None,
        handle_once: bool = False,
        **_ignored: Any,
    ) -> None:
        super().__init__(matcher=matcher, handle_once=handle_once)
        self.entities = _as_entities(entities)


def _as_entities(entities: HandlerEntities) -> list[LaunchDescriptionEntity]:
    if entities is None or callable(entities):
        return []  # a function of the event: only known when the event happens
    if isinstance(entities, LaunchDescriptionEntity):
        return [entities]
    return [e for e in entities if isinstance(e, LaunchDescriptionEntity)]


class _OnEvent(EventHandler):
    HANDLERS = (
        "on_exit",
        "on_start",
        "on_completion",
        "on_stdin",
        "on_stdout",
        "on_stderr",
        "on_shutdown",
        "on_include",
        "on_event",
        "entities",
    )

    # the real handler's keyword arguments (on_exit=…, target_action=…): HANDLERS and the target
    # are read
    def __init__(self, **kwargs: Any) -> None:
        entities: list[LaunchDescriptionEntity] = []
        for key in self.HANDLERS:
            entities.extend(_as_entities(kwargs.get(key)))
        super().__init__()
        self.entities = entities
        target = kwargs.get("target_action", kwargs.get("target_lifecycle_node"))
        self.target_action = target if isinstance(target, Action) else None  # (not a matcher function)


class OnProcessExit(_OnEvent):
    pass


class OnProcessStart(_OnEvent):
    pass


class OnExecutionComplete(_OnEvent):
    pass


class OnProcessIO(_OnEvent):
    pass


class OnShutdown(_OnEvent):
    pass


class OnIncludeLaunchDescription(_OnEvent):
    pass


class OnActionEventBase(_OnEvent):
    pass


class OnStateTransition(_OnEvent):
    pass


def matcher(*args: Any, **kwargs: Any) -> Callable[[object], bool]:  # the real matcher's arguments
    """event_named, matches_action…: a predicate on events, which never come at verify time."""
    return lambda event: False


class HandledEvent:
    """The event launch puts in the context's locals (`event`) before it visits an event
    handler's entities (launch.event_handler.BaseEventHandler.handle), so that
    LocalSubstitution('event.reason') performs: no event happens at verify time, so this stands
    in for launch's event of the handler's kind (launch/events/, launch_ros's StateTransition),
    with its attributes; what only a run tells (a pid, an exit code, output) has a neutral value.
    Its class is named as launch's (an attribute it lacks: "'Shutdown' object has no attribute")."""

    def __init__(self, **attributes: object) -> None:
        self.__dict__.update(attributes)

    def __getattribute__(self, name: str) -> object:
        if not name.startswith("__"):
            EVENT_READ[0] = True  # an action failing after this may fail on the stand-in's values
        return object.__getattribute__(self, name)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} event (no event at verify time)>"


# whether the stand-in event was read since the current handler's entities began (evaluate.handling)
EVENT_READ = [False]


_EVENT_CLASSES: dict[str, type[HandledEvent]] = {}


def _event(kind: str, **attributes: object) -> HandledEvent:
    cls = _EVENT_CLASSES.get(kind)
    if cls is None:
        cls = _EVENT_CLASSES[kind] = type(kind, (HandledEvent,), {})
    return cls(**attributes)


# the stand-in events whose handlers' entities are being visited (evaluate.handling)
HANDLING: list[object] = []


def handler_event(handler: object, target: object = None) -> HandledEvent:
    """The event `handler` (launch's or pkgforge's, by its class's name) handles, standing in
    (both engines); `target`: the action it watches (target_action), None for any."""
    kinds = {cls.__name__ for cls in type(handler).__mro__}
    process: dict[str, object] = {
        "action": target,
        "execute_process_action": target,
        "process_name": "",
        "cmd": [],
        "cwd": None,
        "env": None,
        "pid": 0,
    }
    if "OnShutdown" in kinds:  # launch.events.Shutdown's defaults (a Shutdown action without reason)
        return _event("Shutdown", reason="reason not given", due_to_sigint=False)
    if "OnProcessStart" in kinds:
        return _event("ProcessStarted", **process)
    if "OnProcessExit" in kinds:
        return _event("ProcessExited", **process, returncode=0)
    if "OnProcessIO" in kinds:  # (a line of the process's standard output)
        fd = {"from_stdin": False, "from_stdout": True, "from_stderr": False}
        return _event("ProcessIO", **process, text=b"", **fd)
    if "OnExecutionComplete" in kinds:
        return _event("ExecutionComplete", action=target)
    if "OnIncludeLaunchDescription" in kinds:
        return _event("IncludeLaunchDescription", launch_description=None)
    if "OnStateTransition" in kinds:
        states = {"transition": "", "start_state": "", "goal_state": ""}
        return _event("StateTransition", action=target, msg=None, timestamp=0, **states)
    return _event("Event")  # a handler of its own matcher: which event, only the run tells


class InertEvent(Located):
    """An event class (Shutdown, ChangeState…): emitted at run time; nothing to check."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # the real event's arguments, unread
        super().__init__()


class ExecuteProcess(Action):
    def __init__(
        self,
        *,
        cmd: Iterable[SomeSubstitutionsType],
        name: SomeSubstitutionsType | None = None,
        cwd: SomeSubstitutionsType | None = None,
        env: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        additional_env: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        shell: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.cmd = cmd
        self.shell = shell
        self.process_name, self.cwd = name, cwd
        self.env, self.additional_env = env, additional_env
        # ExecuteLocal's: what its execute performs too (the rest is read only once it runs)
        self.prefix: SomeSubstitutionsType | None = kwargs.get("prefix")
        self.output: SomeSubstitutionsType | dict[str, str] = kwargs.get("output", "log")
        self.respawn: bool | SomeSubstitutionsType = kwargs.get("respawn", False)

    def visit(self, context: LaunchContext) -> None:
        cmd = list(self.cmd)
        RECORDER.add(
            "nodes",
            {"kind": "process", "cmd": [perform(context, part) for part in cmd], "shell": bool(self.shell)},
            self,
        )
        execute_process(context, self, cmd)


# an action's substitutions performed again as its execute performs them: what they record was
# recorded by the visit already (a package looked up for ExecutableInPackage is the node's own)
PREPARING = [False]


def execute_process(
    context: LaunchContext, action: ExecuteProcess, cmd: Sequence[SomeSubstitutionsType]
) -> None:
    """What launch's ExecuteLocal.execute performs before it starts the process (its prepare: the
    command, launch-prefix, name, cwd, environment, respawn; then output), recorded as the
    action's execution; a failure is recorded there too, and raised as launch raises it."""
    PREPARING[0] = True
    try:
        record = _prepared(context, action, cmd)
    except Exception as error:
        RECORDER.add("executions", {"action": type(action).__name__, "failure": failure_text(error)}, action)
        raise
    finally:
        PREPARING[0] = False
    RECORDER.add("executions", record, action)


def _prepared(
    context: LaunchContext, action: ExecuteProcess, cmd: Sequence[SomeSubstitutionsType]
) -> ExecutionRecordDict:
    """launch.descriptions.Executable.prepare and ExecuteLocal's, in their order."""
    words = [perform(context, part) for part in cmd]
    if action.prefix is None:
        # LaunchConfiguration('launch-prefix(-filter)', default=''): a regular expression the
        # executable's name must match for the prefix to apply
        pattern = context.launch_configurations.get("launch-prefix-filter", "")
        applies = re.match(pattern, os.path.basename(words[0])) is not None
        prefix = context.launch_configurations.get("launch-prefix", "") if applies else ""
    else:
        prefix = perform(context, action.prefix)
    words = shlex.split(prefix) + words
    name = (
        os.path.basename(words[0]) if action.process_name is None else perform(context, action.process_name)
    )
    cwd = None if action.cwd is None else perform(context, action.cwd)
    env = None if action.env is None else _environment(context, action.env)
    additional = _environment(context, action.additional_env or {})
    respawn = action.respawn
    if not isinstance(respawn, bool):
        respawn = _typed_bool(context, normalize(respawn))
    output = None if isinstance(action.output, dict) else perform(context, action.output)
    return {
        "action": type(action).__name__,
        "cmd": words,
        "name": name,
        "cwd": cwd,
        "env": env,
        "additional_env": additional,
        "output": output,
        "respawn": respawn,
    }


def _environment(
    context: LaunchContext, variables: dict[SomeSubstitutionsType, SomeSubstitutionsType]
) -> list[list[str]]:
    """env= or additional_env= performed, as launch joins them into one dict (a name twice: the last)."""
    joined = {perform(context, k): perform(context, v) for k, v in variables.items()}
    return [[k, v] for k, v in joined.items()]


class ExecuteLocal(ExecuteProcess):
    def __init__(self, *, process_description: object = None, **kwargs: Any) -> None:
        super().__init__(cmd=[], **kwargs)

    def visit(self, context: LaunchContext) -> None:  # (its description's command is not read)
        RECORDER.add("nodes", {"kind": "process", "cmd": []}, self)


class Shutdown(Action):
    pass


class EmitEvent(Action):
    def __init__(self, *, event: object = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)


# --- launch file sources and includes -------------------------------------------------------


class LaunchDescriptionSource(Located):
    kind: str | None = None

    # the real sources' other arguments (method, launch_description…) are not read
    def __init__(
        self, launch_file_path: SomeSubstitutionsType | None = None, *args: Any, **kwargs: Any
    ) -> None:
        super().__init__()
        self.location = launch_file_path


class PythonLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "py"


class AnyLaunchDescriptionSource(LaunchDescriptionSource):
    kind = None


class FrontendLaunchDescriptionSource(LaunchDescriptionSource):
    kind = None


class XMLLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "xml"


class YAMLLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "yaml"


class IncludeLaunchDescription(Action):
    def __init__(
        self,
        launch_description_source: LaunchDescriptionSource | SomeSubstitutionsType,
        *,
        launch_arguments: Iterable[tuple[SomeSubstitutionsType, SomeSubstitutionsType]] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not isinstance(launch_description_source, LaunchDescriptionSource):
            launch_description_source = AnyLaunchDescriptionSource(launch_description_source)
        self.source = launch_description_source
        self.launch_arguments = list(launch_arguments or [])

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        location = self.source.location
        path = perform(context, location) if location is not None else ""
        arguments = include_arguments(context, self.launch_arguments, perform)
        exists = os.path.isfile(path)
        RECORDER.add("includes", {"path": path, "arguments": arguments, "exists": exists}, self)
        _record_path(path, self, "IncludeLaunchDescription")
        if not exists or _phantom(path):
            RECORDER.unfollowed.append(path)
            return None
        from pkgforge.launch.evaluate import load_description  # noqa: PLC0415  (evaluate imports this module)

        description = load_description(path, self.source.kind)
        previous = context.current_file
        context.current_file = path
        return [description, _RestoreFile(previous)]


def include_arguments(
    context: Any,
    pairs: Iterable[tuple[Any, Any]],
    perform_one: Callable[[Any, Any], str],
) -> dict[str, str]:
    """An include's launch_arguments as launch sets them (both engines): one SetLaunchConfiguration
    after another, so a value may use an argument given before it in the same list. They stay
    set after the include, as in launch (only a scoped GroupAction takes them away)."""
    arguments: dict[str, str] = {}
    for key, value in pairs:
        name = perform_one(context, key)
        arguments[name] = context.launch_configurations[name] = perform_one(context, value)
    return arguments


class ScopedIncludeLaunchDescription(IncludeLaunchDescription):
    pass


class _RestoreFile(LaunchDescriptionEntity):
    def __init__(self, previous: str | None) -> None:
        super().__init__()
        self.previous = previous

    def visit(self, context: LaunchContext) -> None:
        context.current_file = self.previous


def _phantom(path: str) -> bool:
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    return bool(phantom) and os.path.abspath(path).startswith(f"{phantom}{os.sep}")


# --- launch_ros actions ---------------------------------------------------------------------


def is_root_namespace(ns: str) -> bool:
    return ns == "/"


def is_namespace_absolute(ns: str) -> bool:
    return ns.startswith("/")


@typing.overload
def prefix_namespace(base_ns: str, ns: str | None) -> str: ...
@typing.overload
def prefix_namespace(base_ns: str | None, ns: str) -> str: ...
@typing.overload
def prefix_namespace(base_ns: None, ns: None) -> None: ...
@typing.overload
def prefix_namespace(base_ns: str | None, ns: str | None) -> str | None: ...
def prefix_namespace(base_ns: str | None, ns: str | None) -> str | None:
    """launch_ros: ns under base_ns unless ns is absolute; trailing '/' stripped."""
    if ns is None:
        if base_ns is None:
            return None
        combined = base_ns
    elif not base_ns or is_namespace_absolute(ns):
        combined = ns
    else:
        combined = ("" if is_root_namespace(base_ns) else base_ns) + "/" + ns
    return combined if is_root_namespace(combined) else combined.rstrip("/")


@typing.overload
def make_namespace_absolute(ns: str) -> str: ...
@typing.overload
def make_namespace_absolute(ns: None) -> None: ...
@typing.overload
def make_namespace_absolute(ns: str | None) -> str | None: ...
def make_namespace_absolute(ns: str | None) -> str | None:
    if ns is None:
        return None
    return ns if is_namespace_absolute(ns) else "/" + ns


# one item of a node's `parameters`: a dict of name → value (keys str or substitutions, values
# any YAML value or substitutions: the launch file's own data), a Parameter, or a parameter file
ParameterGroup = typing.Union[  # noqa: UP007
    Mapping[Any, Any], "Parameter", "ParameterFile", "SomeSubstitutionsType", "os.PathLike[str]"
]
Remapping = tuple["SomeSubstitutionsType", "SomeSubstitutionsType"]


class Node(ExecuteProcess):
    def __init__(
        self,
        *,
        executable: SomeSubstitutionsType | None = None,
        package: SomeSubstitutionsType | None = None,
        name: SomeSubstitutionsType | None = None,
        namespace: SomeSubstitutionsType | None = None,
        exec_name: SomeSubstitutionsType | None = None,
        parameters: Sequence[ParameterGroup] | None = None,
        remappings: Iterable[Remapping] | None = None,
        ros_arguments: Iterable[SomeSubstitutionsType] | None = None,
        arguments: Iterable[SomeSubstitutionsType] | None = None,
        **kwargs: Any,
    ) -> None:
        kwargs.pop("cmd", None)
        super().__init__(cmd=[], **kwargs)
        self.package = package
        self.executable = executable
        self.node_name = name
        self.namespace = namespace
        if parameters is not None and (
            isinstance(parameters, str) or not isinstance(parameters, collections.abc.Sequence)
        ):
            raise TypeError(f"Expecting list of parameters, got {parameters}")
        self.parameters = list(parameters or [])
        self.remappings = list(remappings or [])
        self.arguments = list(arguments or [])
        self.ros_arguments = list(ros_arguments or [])
        self.ros_arguments_given = ros_arguments is not None
        self.process_name = exec_name  # launch_ros gives ExecuteProcess its exec_name as name

    def _package(self, context: LaunchContext) -> str | None:
        """The package, recorded first: a failure later in the node must not hide it."""
        package = perform(context, self.package) if self.package is not None else None
        if package:
            RECORDER.add("packages", {"name": package, "via": "Node package"}, self)
        return package

    def record(self, context: LaunchContext, package: str | None) -> NodeRecordDict:
        arguments = []
        for argument in self.arguments:
            text = perform(context, argument)
            arguments.append(text)
            _record_path(text, self, "Node arguments")
        namespace = perform(context, self.namespace) if self.namespace is not None else None
        namespace = make_namespace_absolute(
            prefix_namespace(context.launch_configurations.get("ros_namespace"), namespace)
        )
        parameters: list[ParameterRecordDict] = []
        for group in context.launch_configurations.get("global_params") or []:
            if isinstance(group, tuple):
                parameters.append(
                    {
                        "name": group[0],
                        "form": "plain",
                        "value_preview": str(group[1])[:PREVIEW_LENGTH],
                        "file": self._file,
                        "line": self._line,
                    }
                )
        for group in self.parameters:
            parameters.extend(_evaluate_parameters(context, group, self))
        remappings = [list(r) for r in context.launch_configurations.get("ros_remaps") or []]
        remappings += [[perform(context, a), perform(context, b)] for a, b in self.remappings]
        return {
            "kind": "node",
            "package": package,
            "executable": perform(context, self.executable) if self.executable is not None else None,
            "name": perform(context, self.node_name) if self.node_name is not None else None,
            "namespace": namespace,
            "arguments": arguments,
            "parameters": parameters,
            "remappings": remappings,
        }

    def visit(self, context: LaunchContext) -> None:
        try:
            package = self._package(context)
            record = self.record(context, package)
            RECORDER.add("nodes", record, self)
            # recorded as written; then the rules launch_ros applies when it starts the node
            if self.node_name is not None:
                validate_node_name(record["name"])
            for group in self.parameters:
                if isinstance(group, collections.abc.Mapping):
                    for name, value in _flatten(group, None, context):
                        _check_parameter_value(context, name, value)
            _allowed_parameter_files(context, self.parameters)
        except Exception as error:  # the node stops before its execution performs the rest
            RECORDER.add("executions", {"action": type(self).__name__, "failure": failure_text(error)}, self)
            raise
        execute_process(context, self, self.command(record["name"]))

    def command(self, name: str | None) -> list[SomeSubstitutionsType]:
        """The command launch_ros gives ExecuteProcess (Node.__init__), up to what its
        _perform_substitutions adds (namespace, parameters, remappings): the node's name there
        is the `__node:=` its execute puts in the context's locals."""
        executable: SomeSubstitutionsType = (
            ExecutableInPackage(executable=self.executable or "", package=self.package)
            if self.package is not None
            else self.executable or ""
        )
        cmd: list[SomeSubstitutionsType] = [executable, *self.arguments]
        if self.ros_arguments_given:
            cmd += ["--ros-args", *self.ros_arguments]
        cmd.append("--ros-args")
        if self.node_name is not None:
            cmd += ["-r", f"__node:={name}"]
        return cmd


class InvalidNodeNameException(ValueError):
    """rclpy.exceptions.InvalidNodeNameException (rclpy is not needed: rmw's rule, below)."""


def validate_node_name(name: str | None) -> bool:
    """rclpy.validate_node_name: alphanumerics and underscores, not starting with a digit."""
    import re

    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name or ""):
        raise InvalidNodeNameException(
            f"Invalid node name: node name must not be empty, contain only "
            f"alphanumerics and underscores, and not start with a number: '{name}'"
        )
    return True


class LifecycleNode(Node):
    def __init__(
        self, *, name: SomeSubstitutionsType, namespace: SomeSubstitutionsType, **kwargs: Any
    ) -> None:
        super().__init__(name=name, namespace=namespace, **kwargs)


class ParameterValue(Located):
    # value: any YAML value or substitutions; value_type: a type or typing construct (List[str])
    def __init__(self, value: object, *, value_type: object = None) -> None:
        super().__init__()
        self.value, self.value_type = value, value_type


class ParameterFile(Located):
    def __init__(
        self,
        param_file: SomeSubstitutionsType | os.PathLike[str],
        *,
        allow_substs: bool | SomeSubstitutionsType = False,
    ) -> None:
        super().__init__()
        self.param_file = param_file
        self.allow_substs = allow_substs


def _allowed_parameter_files(context: LaunchContext, groups: Sequence[ParameterGroup]) -> None:
    """launch_ros's ParameterFile.evaluate with allow_substs: the file's text is read, its
    substitutions ($(var x)...) performed and the result read as YAML; what fails stops the
    node (a configuration it names that is not set: at the ParameterFile's line)."""
    import yaml

    from pkgforge.launch.frontend import parse_substitution

    for group in groups:
        if not isinstance(group, ParameterFile):
            continue
        allowed = group.allow_substs
        if not isinstance(allowed, bool):
            allowed = _typed_bool(context, normalize(allowed))
        if not allowed:
            continue
        source = group.param_file
        path = os.fspath(source) if isinstance(source, os.PathLike) else perform(context, source)
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
        _FRONTEND_LOCATION.append((group._file, group._line))  # its substitutions stand there
        try:
            parsed = parse_substitution(text)
        finally:
            _FRONTEND_LOCATION.pop()
        substituted = perform_substitutions(context, parsed)
        try:
            yaml.safe_load(substituted)
        except Exception:  # noqa: BLE001 - launch_ros's own rule: whatever yaml raises
            raise SubstitutionFailure("The substituted parameter file is not a valid yaml file") from None


class Parameter(Located):
    def __init__(self, name: SomeSubstitutionsType, value: object, *, value_type: object = None) -> None:
        super().__init__()
        self.name, self.value = name, value


def _flatten(
    group: Mapping[Any, Any], prefix: str | None, context: LaunchContext
) -> list[tuple[str, object]]:
    """A parameter dict, nested dicts joined with '.' (normalize_parameter_dict)."""
    out: list[tuple[str, object]] = []
    for key, value in group.items():
        name = perform(context, key) if not isinstance(key, str) else key
        if prefix:
            name = f"{prefix}.{name}"
        if isinstance(value, collections.abc.Mapping):
            out.extend(_flatten(value, name, context))
        else:
            out.append((name, value))
    return out


def _evaluate_parameters(
    context: LaunchContext, group: ParameterGroup, node: Located
) -> list[ParameterRecordDict]:
    """Node parameters: dicts of name → value, or parameter files; with how each was given."""
    out: list[ParameterRecordDict] = []
    if isinstance(group, collections.abc.Mapping):
        for name, value in _flatten(group, None, context):
            given = _value_form(value)
            text = _perform_value(context, value)
            out.append(
                {
                    "name": name,
                    "form": given,
                    "value_preview": str(text)[:PREVIEW_LENGTH],
                    "file": node._file,
                    "line": getattr(value, "_line", None) or node._line,
                }
            )
            if isinstance(text, str):
                _record_path(text, node, "parameter")
    elif isinstance(group, Parameter):
        text = _perform_value(context, group.value)
        out.append(
            {
                "name": perform(context, group.name),
                "form": _value_form(group.value),
                "value_preview": str(text)[:PREVIEW_LENGTH],
                "file": node._file,
                "line": node._line,
            }
        )
    else:
        source = group.param_file if isinstance(group, ParameterFile) else group
        path = perform(context, source) if not isinstance(source, (os.PathLike,)) else os.fspath(source)
        _record_path(path, node, "parameter file")
        out.append(
            {"name": None, "form": "file", "value_preview": path, "file": node._file, "line": node._line}
        )
    return out


def _check_parameter_value(context: LaunchContext, name: str, value: object) -> None:
    """launch_ros's typing of a parameter given as substitutions: the text is read as YAML and
    must give a scalar or a uniform list; otherwise the node does not start (the same error)."""
    import yaml

    if isinstance(value, ParameterValue):
        if value.value_type is not None or not _is_substitutions(value.value):
            return
        text = perform(context, value.value)
        if not text:
            return
        described = f"Failed to convert '{text}' using yaml rules"
        try:
            output = yaml.safe_load(text)
        except Exception as error:  # noqa: BLE001 - launch's own rule
            raise ValueError(f"{described}: yaml.safe_load() failed\n{error}") from None
        if not _allowed_value(output):
            raise ValueError(f"{described}: output type is not allowed, got {type(output)}")
        return
    if not _is_substitutions(value) or not _has_substitution(value):
        return
    text = perform(context, value) or "''"
    wrap = (
        "If the parameter is meant to be a string, try wrapping it in "
        "launch_ros.parameter_descriptions.ParameterValue(value, value_type=str)"
    )
    try:
        output = yaml.safe_load(text)
    except yaml.YAMLError:
        raise TypeError(f"Unable to parse the value of parameter {name} as yaml. {wrap}") from None
    if type(output) in (bool, int, float, str, bytes):
        return
    jazzy = _api_distro() != "humble"
    if isinstance(output, collections.abc.Sequence):
        if not _uniform(output):
            raise TypeError(
                "Expected a non-empty sequence, with items of uniform type. Allowed sequence "
                "item types are bool, int, float, str."
                + (f' Got inconsistent input for "{name}"' if jazzy else "")
            )
        return
    got = f'{type(output)} for "{name}". ' if jazzy else f"{type(output)}."
    raise TypeError(
        "Allowed value types are bytes, bool, int, float, str, Sequence[bool], Sequence[int], "
        f"Sequence[float], Sequence[str]. Got {got}{wrap}"
    )


def _api_distro() -> str:
    from pkgforge.launch import api

    return api.distro()


def _is_substitutions(value: object) -> TypeGuard[SomeSubstitutionsType]:
    if isinstance(value, (str, Substitution)):
        return True
    return (
        isinstance(value, (list, tuple))
        and bool(value)
        and all(isinstance(v, (str, Substitution)) for v in value)
    )


def _has_substitution(value: object) -> bool:
    if isinstance(value, Substitution):
        return True
    return isinstance(value, (list, tuple)) and any(isinstance(v, Substitution) for v in value)


def _uniform(sequence: Sequence[object]) -> bool:
    if not sequence or type(sequence[0]) not in (bool, int, float, str):
        return False
    return all(isinstance(item, type(sequence[0])) for item in sequence)


def _allowed_value(output: object) -> bool:
    """launch.utilities.type_utils: a scalar, or a list of one scalar type."""
    if not isinstance(output, list):
        return isinstance(output, (int, float, bool, str))
    member = next((type(x) for x in output if type(x) is not str), str)
    return member in (int, float, bool, str) and all(isinstance(x, member) for x in output)


def _value_form(value: object) -> ParameterForm:
    if isinstance(value, ParameterValue):
        typed = value.value_type is str
        return "typed-str" if typed else ("command-untyped" if _has_command(value.value) else "typed")
    if _has_command(value):
        return "command-untyped"
    return "plain"


def _has_command(value: object) -> bool:
    if isinstance(value, Command):
        return True
    if isinstance(value, (list, tuple)):
        return any(isinstance(v, Command) for v in value)
    return False


def _perform_value(context: LaunchContext, value: object) -> object:
    """A parameter's value as launch_ros evaluates it: a list with a Substitution among strs is
    one string (joined); a list of strs stays a list; a list of lists is a list of strings."""
    if isinstance(value, ParameterValue):
        value = value.value
    if isinstance(value, (str, Substitution)):
        return perform(context, value)
    if isinstance(value, (list, tuple)) and value:
        kinds = {type(v) for v in value}
        if any(isinstance(v, Substitution) for v in value) and all(
            isinstance(v, (str, Substitution)) for v in value
        ):
            return perform(context, list(value))
        if all(isinstance(v, (str, Substitution, list, tuple)) for v in value) and kinds - {str}:
            return [perform(context, v) for v in value]
    return value


class ComposableNode(Located):
    def __init__(
        self,
        *,
        package: SomeSubstitutionsType,
        plugin: SomeSubstitutionsType,
        name: SomeSubstitutionsType | None = None,
        namespace: SomeSubstitutionsType | None = None,
        parameters: Sequence[ParameterGroup] | None = None,
        remappings: Iterable[Remapping] | None = None,
        extra_arguments: Sequence[ParameterGroup] | None = None,
        condition: Condition | None = None,
    ) -> None:
        super().__init__()
        self.package, self.plugin = package, plugin
        self.parameters = list(parameters or [])
        self.condition = condition


class ComposableNodeContainer(Node):
    def __init__(
        self,
        *,
        name: SomeSubstitutionsType,
        namespace: SomeSubstitutionsType,
        composable_node_descriptions: Iterable[ComposableNode] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(name=name, namespace=namespace, **kwargs)
        self.descriptions = list(composable_node_descriptions or [])

    def visit(self, context: LaunchContext) -> None:
        super().visit(context)
        for description in self.descriptions:
            if description.condition is None or description.condition.evaluate(context):
                package = perform(context, description.package)
                RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)
                for group in description.parameters:
                    _evaluate_parameters(context, group, description)


class LoadComposableNodes(Action):
    def __init__(
        self,
        *,
        composable_node_descriptions: Iterable[ComposableNode],
        target_container: SomeSubstitutionsType | ComposableNodeContainer | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.descriptions = list(composable_node_descriptions)

    def visit(self, context: LaunchContext) -> None:
        for description in self.descriptions:
            package = perform(context, description.package)
            RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)


class PushRosNamespace(Action):
    def __init__(self, namespace: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.namespace = normalize(namespace)

    def visit(self, context: LaunchContext) -> None:
        pushed = perform_substitutions(context, self.namespace)
        previous = context.launch_configurations.get("ros_namespace", None)
        namespace = make_namespace_absolute(prefix_namespace(previous, pushed))
        if not _valid_namespace(namespace):
            raise SubstitutionFailure(
                "The resulting namespace is invalid: "
                f"[previous_namespace='{previous}', pushed_namespace='{pushed}']"
            )
        context.launch_configurations["ros_namespace"] = namespace


def _valid_namespace(namespace: str) -> bool:
    """rmw's namespace rules: absolute, [A-Za-z0-9_/] tokens not starting with a digit, no '//'."""
    import re

    if namespace == "/":
        return True
    return bool(re.fullmatch(r"(/[A-Za-z_][A-Za-z0-9_]*)+", namespace))


class SetParameter(Action):
    def __init__(self, name: SomeSubstitutionsType, value: object, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = name, value

    def visit(self, context: LaunchContext) -> None:
        name = perform(context, self.name)
        value = _perform_value(context, self.value)
        if _has_substitution(self.value):  # evaluate_parameter_dict: the text read as YAML
            import yaml

            _check_parameter_value(context, name, self.value)
            # text (a nested list with a substitution performs to a list: yaml's own error then)
            value = yaml.safe_load(typing.cast(str, value) or "''")
        context.launch_configurations.setdefault("global_params", []).append((name, value))


class SetRemap(Action):
    def __init__(self, src: SomeSubstitutionsType, dst: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.src, self.dst = normalize(src), normalize(dst)

    def visit(self, context: LaunchContext) -> None:
        src, dst = perform_substitutions(context, self.src), perform_substitutions(context, self.dst)
        # appended in place, as launch_ros does
        remaps = context.launch_configurations.get("ros_remaps", [])
        remaps.append((src, dst))
        context.launch_configurations["ros_remaps"] = remaps


class SetParametersFromFile(Action):
    def __init__(self, filename: SomeSubstitutionsType, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.filename = filename

    def visit(self, context: LaunchContext) -> None:
        path = perform(context, self.filename)
        _record_path(path, self, "SetParametersFromFile")
        context.launch_configurations.setdefault("global_params", []).append(path)


class RosTimerAction(TimerAction):
    pass


# --- names ROS has and pkgforge does not evaluate -------------------------------------------


def unsupported(name: str, bases: type | tuple[type, ...] = Action) -> type:
    """A real launch API name pkgforge records instead of evaluating: an action that does
    nothing, a substitution whose value is unknown (what uses it is skipped). Recorded where the
    real engine records it: an action when visited (its condition taken, in each evaluated
    branch), a substitution when performed, anything else when made."""
    bases = bases if isinstance(bases, tuple) else (bases,)
    visited = any(issubclass(b, (Action, Substitution)) for b in bases)

    # self: an instance of the class made below (its bases vary); the arguments: the real
    # constructor's (checked by api.py), only `condition` is read
    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        Located.__init__(self)
        self.condition = kwargs.get("condition")
        if not visited:
            RECORDER.add("unsupported", {"name": name}, self)

    def visit(self: Located, context: LaunchContext) -> None:
        RECORDER.add("unsupported", {"name": name}, self)

    def perform(self: Located, context: LaunchContext) -> str:
        RECORDER.add("unsupported", {"name": name}, self)
        raise Unresolved(f"<{name}>")

    return type(name, bases, {"__init__": __init__, "visit": visit, "perform": perform})


# launch_ros sets use_sim_time on the launch's own ROS node (a running rclpy node), not on
# the nodes it starts: nothing verify can do or check (the real engine records it the same way)
SetUseSimTime = unsupported("SetUseSimTime")


def load_description_function(path: FilePath, *args: Any, **kwargs: Any) -> LaunchDescription:
    # *args, **kwargs: the real loaders' other arguments (launch_file_path only is read)
    """launch's get_launch_description_from_*_launch_file(): the file's LaunchDescription."""
    from pkgforge.launch.evaluate import load_description

    return load_description(os.fspath(path))


def load_python_launch_file_as_module(python_launch_file_path: FilePath) -> ModuleType:
    """The launch file as a module, as launch loads it (generate_launch_description not called)."""
    from pkgforge.launch.evaluate import load_module

    module: ModuleType = load_module(os.fspath(python_launch_file_path))
    return module


# --- launch.utilities and friends -----------------------------------------------------------

# typing.Union, as launch.some_substitutions_type spells them (typing.get_args sees the same)
SomeSubstitutionsType = typing.Union[str, Substitution, typing.Iterable[str | Substitution]]  # noqa: UP007
SomeSubstitutionsType_types_tuple = (str, Substitution, collections.abc.Iterable)
SomeEntitiesType = typing.Union[LaunchDescriptionEntity, typing.Iterable[LaunchDescriptionEntity]]  # noqa: UP007
SomeEntitiesType_types_tuple = (LaunchDescriptionEntity, collections.abc.Iterable)
FilePath = typing.Union[str, "os.PathLike[str]"]


def isclassinstance(obj: object) -> bool:
    return hasattr(obj, "__class__")


def is_a(obj: object, entity_type: type) -> bool:
    return isclassinstance(obj) and issubclass(obj.__class__, entity_type)


def is_a_subclass(obj: object, entity_type: type) -> bool:
    return is_a(obj, entity_type) or (isinstance(obj, type) and issubclass(obj, entity_type))


def ensure_argument_type(
    argument: object, types: type | Sequence[type], argument_name: str, caller: str | None = None
) -> None:
    """launch.utilities.ensure_argument_type: a TypeError naming the argument."""
    kinds: Sequence[type] = types if isinstance(types, (list, tuple)) else [typing.cast(type, types)]
    if not any(
        isinstance(argument, t)
        or (isinstance(argument, type) and isinstance(t, type) and issubclass(argument, t))
        for t in kinds
    ):
        expected = ", ".join(f"'{t}'" for t in kinds)
        prefix = f"{caller}: " if caller else ""
        raise TypeError(
            f"{prefix}Expected '{argument_name}' to be one of [{expected}], "
            f"but got '{argument}' of type '{type(argument)}'"
        )


def normalize_to_list_of_entities(entities: Iterable[SomeEntitiesType]) -> list[LaunchDescriptionEntity]:
    out: list[Any] = []  # what the launch file gave; the visit skips what is not an entity
    for entity in entities:
        out.extend(entity if isinstance(entity, (list, tuple)) else [entity])
    return out


def get_logger(name: str | None = None) -> logging.Logger:
    return logging.getLogger("launch" if name is None else name)
