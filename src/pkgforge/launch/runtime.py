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

import os
import shlex
import subprocess
import sys
from dataclasses import dataclass, field

# --- where a construct stands in the launch file --------------------------------------------

_LAUNCH_FILES: set[str] = set()  # files being evaluated; frames in them are "user" frames
_FRONTEND_LOCATION: list[tuple[str, int]] = []  # (file, line) while the XML/YAML frontend builds
_RUNNING_XACRO = False  # pkgforge's own xacro run (a Command), not the launch file's


def here() -> tuple[str | None, int | None]:
    """The launch file and line that constructed the object being created."""
    if _FRONTEND_LOCATION:
        return _FRONTEND_LOCATION[-1]
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_filename in _LAUNCH_FILES:
            return frame.f_code.co_filename, frame.f_lineno
        frame = frame.f_back
    return None, None


class Located:
    """Base of every stand-in object: remembers its launch file and line."""

    def __init__(self) -> None:
        self._file, self._line = here()


# --- errors ---------------------------------------------------------------------------------

class SubstitutionFailure(RuntimeError):
    pass


class InvalidLaunchFileError(Exception):
    pass


class PackageNotFoundError(KeyError):
    """ament_index_python's error, re-raised by FindPackageShare as in launch_ros."""


class Unresolved(Exception):
    """A launch configuration with no value: what depends on it is skipped, not guessed."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name


# --- the record -----------------------------------------------------------------------------

@dataclass
class Recorder:
    branch: dict = field(default_factory=dict)
    arguments: dict = field(default_factory=dict)  # name → {default, choices, file, line}
    nodes: list = field(default_factory=list)
    packages: list = field(default_factory=list)
    paths: list = field(default_factory=list)
    includes: list = field(default_factory=list)
    commands: list = field(default_factory=list)
    unsupported: list = field(default_factory=list)
    required: list = field(default_factory=list)
    errors: list = field(default_factory=list)
    command_cache: dict = field(default_factory=dict)

    def add(self, kind: str, item: dict, obj=None) -> None:
        item = dict(item)
        if obj is not None:
            item.setdefault("file", obj._file)
            item.setdefault("line", obj._line)
        item["branch"] = dict(self.branch)
        getattr(self, kind).append(item)


RECORDER = Recorder()


# --- context --------------------------------------------------------------------------------

class LaunchContext:
    def __init__(self, argv=None, noninteractive=True):
        self.launch_configurations: dict[str, str] = {}
        self.environment = dict(os.environ)
        self.locals = _Locals()
        self.argv = argv or []
        self.noninteractive = noninteractive
        self._stack: list[dict] = []
        self.current_file: str | None = None

    def perform_substitution(self, substitution) -> str:
        return substitution.perform(self)

    def extend_locals(self, values: dict) -> None:
        self.locals.__dict__.update(values)

    def get_locals_as_dict(self) -> dict:
        return dict(self.locals.__dict__)

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


def normalize(value) -> list:
    """str | Substitution | iterable of those → list of Substitutions (launch's rule)."""
    if value is None:
        return []
    if isinstance(value, (str, Substitution)):
        value = [value]
    out = []
    for item in value:
        if isinstance(item, str):
            out.append(TextSubstitution(text=item))
        elif isinstance(item, Substitution):
            out.append(item)
        elif isinstance(item, (int, float, bool)):
            out.append(TextSubstitution(text=str(item)))
        else:
            raise TypeError(f"expected str or Substitution, got {type(item).__name__}")
    return out


def perform(context: LaunchContext, value) -> str:
    """Concatenate the performed substitutions, as launch.utilities.perform_substitutions."""
    return "".join(s.perform(context) for s in normalize(value))


class TextSubstitution(Substitution):
    def __init__(self, *, text: str = ""):
        super().__init__()
        self.text = text

    def perform(self, context):
        return self.text


class LaunchConfiguration(Substitution):
    def __init__(self, variable_name, *, default=None):
        super().__init__()
        self.variable_name = variable_name
        self.default = default

    def perform(self, context):
        name = perform(context, self.variable_name)
        if name in context.launch_configurations:
            return context.launch_configurations[name]
        if self.default is not None:
            return perform(context, self.default)
        raise Unresolved(name)


class PathJoinSubstitution(Substitution):
    def __init__(self, substitutions):
        super().__init__()
        self.substitutions = list(substitutions)

    def perform(self, context):
        parts = [perform(context, part) for part in self.substitutions]
        result = os.path.join(*parts) if parts else ""
        _record_path(result, self, "PathJoinSubstitution")
        return result


class EnvironmentVariable(Substitution):
    def __init__(self, name, *, default_value=None):
        super().__init__()
        self.name = name
        self.default_value = default_value

    def perform(self, context):
        name = perform(context, self.name)
        value = context.environment.get(name)
        if value is None:
            if self.default_value is None:
                raise SubstitutionFailure(f"environment variable '{name}' does not exist")
            return perform(context, self.default_value)
        return value


class FindExecutable(Substitution):
    def __init__(self, *, name):
        super().__init__()
        self.name = name

    def perform(self, context):
        import shutil

        name = perform(context, self.name)
        found = shutil.which(name)
        if name == "xacro":
            RECORDER.add("packages", {"name": "xacro", "via": "FindExecutable"}, self)
        if found is None:
            raise SubstitutionFailure(f"executable '{name}' not found on the PATH")
        return found


class PythonExpression(Substitution):
    def __init__(self, expression, python_modules=("math",)):
        super().__init__()
        self.expression = expression
        self.python_modules = python_modules

    def perform(self, context):
        import importlib

        names = {m: importlib.import_module(m) for m in perform_list(context, self.python_modules)}
        if "math" in names:
            names.update(vars(names["math"]))
        return str(eval(perform(context, self.expression), {}, names))


def perform_list(context, values) -> list[str]:
    return [perform(context, v) if not isinstance(v, str) else v for v in values]


class Command(Substitution):
    def __init__(self, command, *, on_stderr="fail"):
        super().__init__()
        self.command = command
        self.on_stderr = on_stderr

    def perform(self, context):
        text = perform(context, self.command)
        words = shlex.split(text)
        if not words:
            raise SubstitutionFailure("empty command")
        key = tuple(words)
        if key not in RECORDER.command_cache:
            RECORDER.command_cache[key] = _run_command(words)
        ok, output, message, extra = RECORDER.command_cache[key]
        record = {"command": words, "ok": ok, "message": message, **extra}
        if os.path.basename(words[0]) == "xacro":
            RECORDER.add("packages", {"name": "xacro", "via": "Command xacro"}, self)
            for word in words[1:]:
                if ":=" not in word and not word.startswith("-"):
                    _record_path(word, self, "xacro input")
                    record["model"] = word
                    break
            record["mappings"] = dict(w.split(":=", 1) for w in words[1:] if ":=" in w)
        RECORDER.add("commands", record, self)
        if not ok:
            raise SubstitutionFailure(f"executed command failed. Command: {text}\n{message}")
        return output


def _run_command(words: list[str]) -> tuple[bool, str, str, dict]:
    """Run a Command; xacro runs in this process with the real xacro library."""
    if os.path.basename(words[0]) == "xacro":
        return _run_xacro(words[1:])
    try:
        done = subprocess.run(words, capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, "", str(exc), {}
    return done.returncode == 0, done.stdout, done.stderr.strip(), {}


def _run_xacro(args: list[str]) -> tuple[bool, str, str, dict]:
    """xacro with the real library; a success also yields the model's structure, so the
    model checks need not run xacro on it a second time."""
    import io

    import xacro

    process_file = getattr(xacro, "_pkgforge_real_process_file", xacro.process_file)
    files = [a for a in args if ":=" not in a and not a.startswith("-")]
    mappings = dict(a.split(":=", 1) for a in args if ":=" in a)
    if not files:
        return False, "", "xacro: no input file", {}
    stderr = io.StringIO()
    real_stderr, sys.stderr = sys.stderr, stderr
    global _RUNNING_XACRO
    _RUNNING_XACRO = True
    xacro.all_includes[:] = []
    try:
        document = process_file(files[0], mappings=mappings)
        output = document.toprettyxml(indent="  ")
        from ..robot import structure_of_output

        includes = sorted({os.path.abspath(f) for f in xacro.all_includes} - {os.path.abspath(files[0])})
        robot = structure_of_output(files[0], output, includes)
        return True, output, "", ({"robot": robot, "includes": includes} if robot else {})
    except BaseException as exc:  # xacro raises XacroException, IOError, SystemExit …
        message = getattr(exc, "msg", None) or str(exc) or type(exc).__name__
        extra = stderr.getvalue().strip()
        return False, "", f"{message}\n{extra}".strip(), {}
    finally:
        _RUNNING_XACRO = False
        sys.stderr = real_stderr


class ThisLaunchFileDir(Substitution):
    def perform(self, context):
        return os.path.dirname(context.current_file or "")


class ThisLaunchFile(Substitution):
    def perform(self, context):
        return context.current_file or ""


class AnonName(Substitution):
    def __init__(self, name):
        super().__init__()
        self.name = name

    def perform(self, context):
        return f"{perform(context, self.name)}_{os.getpid()}"


class LocalSubstitution(Substitution):
    def __init__(self, expression, description=None):
        super().__init__()
        self.expression = expression

    def perform(self, context):
        return str(eval(self.expression, {}, context.get_locals_as_dict()))


def _truth(text: str) -> bool:
    lowered = text.strip().lower()
    if lowered in ("true", "1"):
        return True
    if lowered in ("false", "0"):
        return False
    raise SubstitutionFailure(f"'{text}' is not a boolean (true, false, 1 or 0)")


class _Boolean(Substitution):
    def __init__(self, *values):
        super().__init__()
        self.values = values


class NotSubstitution(_Boolean):
    def perform(self, context):
        return str(not _truth(perform(context, self.values[0]))).lower()


class AndSubstitution(_Boolean):
    def perform(self, context):
        return str(all(_truth(perform(context, v)) for v in self.values)).lower()


class OrSubstitution(_Boolean):
    def perform(self, context):
        return str(any(_truth(perform(context, v)) for v in self.values)).lower()


class AllSubstitution(AndSubstitution):
    pass


class AnySubstitution(OrSubstitution):
    pass


class EqualsSubstitution(Substitution):
    def __init__(self, left, right):
        super().__init__()
        self.left, self.right = left, right

    def perform(self, context):
        return str(perform(context, self.left) == perform(context, self.right)).lower()


class NotEqualsSubstitution(EqualsSubstitution):
    def perform(self, context):
        return str(perform(context, self.left) != perform(context, self.right)).lower()


class IfElseSubstitution(Substitution):
    def __init__(self, condition, if_value="", else_value=""):
        super().__init__()
        self.condition, self.if_value, self.else_value = condition, if_value, else_value

    def perform(self, context):
        chosen = self.if_value if _truth(perform(context, self.condition)) else self.else_value
        return perform(context, chosen)


class FileContent(Substitution):
    def __init__(self, path):
        super().__init__()
        self.path = path

    def perform(self, context):
        path = perform(context, self.path)
        _record_path(path, self, "FileContent")
        with open(path, encoding="utf-8") as handle:
            return handle.read()


# launch_ros substitutions

def _share_directory(package: str) -> str:
    from ament_index_python.packages import get_package_share_directory

    return get_package_share_directory(package)


class FindPackageShare(Substitution):
    def __init__(self, package):
        super().__init__()
        self.package = package

    def perform(self, context):
        package = perform(context, self.package)
        RECORDER.add("packages", {"name": package, "via": type(self).__name__}, self)
        return self.find(package, context)

    def find(self, package: str, context: LaunchContext) -> str:
        return _share_directory(package)


class FindPackagePrefix(FindPackageShare):
    def find(self, package: str, context: LaunchContext) -> str:
        from ament_index_python.packages import get_package_prefix

        return get_package_prefix(package)


class FindPackage(FindPackagePrefix):
    pass


class FindPackageFile(FindPackageShare):
    def __init__(self, package, file_path):
        super().__init__(package)
        self.file_path = file_path

    def find(self, package: str, context: LaunchContext) -> str:
        path = os.path.join(_share_directory(package), perform(context, self.file_path))
        _record_path(path, self, "FindPackageFile")
        return path


class ExecutableInPackage(Substitution):
    def __init__(self, executable, package):
        super().__init__()
        self.executable, self.package = executable, package

    def perform(self, context):
        package = perform(context, self.package)
        RECORDER.add("packages", {"name": package, "via": "ExecutableInPackage"}, self)
        from ament_index_python.packages import get_package_prefix

        return os.path.join(get_package_prefix(package), "lib", package, perform(context, self.executable))


def _record_path(path: str, obj, via: str) -> None:
    if path and os.path.isabs(path):
        RECORDER.add("paths", {"path": path, "via": via, "exists": os.path.exists(path)}, obj)


# --- conditions -----------------------------------------------------------------------------

class Condition(Located):
    def __init__(self, *, predicate=None):
        super().__init__()
        self.predicate = predicate

    def evaluate(self, context) -> bool:
        return bool(self.predicate(context)) if self.predicate else True


class IfCondition(Condition):
    def __init__(self, predicate_expression):
        super().__init__()
        self.expression = predicate_expression

    def evaluate(self, context):
        return _truth(perform(context, self.expression))


class UnlessCondition(IfCondition):
    def evaluate(self, context):
        return not super().evaluate(context)


class LaunchConfigurationEquals(Condition):
    def __init__(self, launch_configuration_name, expected_value):
        super().__init__()
        self.name, self.expected = launch_configuration_name, expected_value

    def evaluate(self, context):
        value = context.launch_configurations.get(self.name)
        expected = None if self.expected is None else perform(context, self.expected)
        return value == expected


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    def evaluate(self, context):
        return not super().evaluate(context)


def evaluate_condition_expression(context, expression) -> bool:
    return _truth(perform(context, expression))


# --- entities -------------------------------------------------------------------------------

class LaunchDescriptionEntity(Located):
    def visit(self, context) -> list | None:
        return None

    def describe_sub_entities(self):
        return []


class Action(LaunchDescriptionEntity):
    def __init__(self, *, condition=None, **_ignored):
        super().__init__()
        self.condition = condition


class LaunchDescription(LaunchDescriptionEntity):
    def __init__(self, initial_entities=None, *, deprecated_reason=None):
        super().__init__()
        self.entities = list(initial_entities or [])

    def add_action(self, action) -> None:
        self.entities.append(action)

    def add_entity(self, entity) -> None:
        self.entities.append(entity)

    def visit(self, context):
        return list(self.entities)

    def get_launch_arguments(self, conditional_inclusion=False):
        return [e for e in self.entities if isinstance(e, DeclareLaunchArgument)]


class DeclareLaunchArgument(Action):
    def __init__(self, name, *, default_value=None, description=None, choices=None, **kwargs):
        super().__init__(**kwargs)
        self.name = name
        self.default_value = default_value
        self.description = description
        self.choices = list(choices) if choices is not None else None

    def visit(self, context):
        default = None
        if self.default_value is not None:
            try:
                default = perform(context, self.default_value)
            except Unresolved:
                default = None
        RECORDER.arguments.setdefault(self.name, {
            "name": self.name, "default": default, "choices": self.choices,
            "file": self._file, "line": self._line,
            "boolean": default is not None and default.lower() in ("true", "false"),
        })
        if self.name not in context.launch_configurations:
            if self.default_value is None:
                RECORDER.add("required", {"name": self.name}, self)
                return None
            context.launch_configurations[self.name] = perform(context, self.default_value)
        value = context.launch_configurations[self.name]
        if self.choices is not None and value not in self.choices:
            raise SubstitutionFailure(
                f"argument '{self.name}' has value '{value}', not one of {self.choices}")
        return None


class SetLaunchConfiguration(Action):
    def __init__(self, name, value, **kwargs):
        super().__init__(**kwargs)
        self.name, self.value = name, value

    def visit(self, context):
        context.launch_configurations[perform(context, self.name)] = perform(context, self.value)


class UnsetLaunchConfiguration(Action):
    def __init__(self, name, **kwargs):
        super().__init__(**kwargs)
        self.name = name

    def visit(self, context):
        context.launch_configurations.pop(perform(context, self.name), None)


class GroupAction(Action):
    def __init__(self, actions, *, scoped=True, forwarding=True, launch_configurations=None, **kwargs):
        super().__init__(**kwargs)
        self.actions = list(actions)
        self.scoped = scoped
        self.launch_configurations = launch_configurations or {}

    def visit(self, context):
        entities = []
        if self.scoped:
            entities.append(PushLaunchConfigurations())
        for key, value in self.launch_configurations.items():
            entities.append(SetLaunchConfiguration(key, value))
        entities.extend(self.actions)
        if self.scoped:
            entities.append(PopLaunchConfigurations())
        return entities


class PushLaunchConfigurations(Action):
    def visit(self, context):
        context._push()


class PopLaunchConfigurations(Action):
    def visit(self, context):
        context._pop()


class ResetLaunchConfigurations(Action):
    def __init__(self, launch_configurations=None, **kwargs):
        super().__init__(**kwargs)
        self.keep = launch_configurations or {}

    def visit(self, context):
        context.launch_configurations = {perform(context, k): perform(context, v) for k, v in self.keep.items()}


class OpaqueFunction(Action):
    def __init__(self, *, function, args=None, kwargs=None, **rest):
        super().__init__(**rest)
        self.function, self.args, self.kwargs = function, args or [], kwargs or {}

    def visit(self, context):
        return self.function(context, *self.args, **self.kwargs)


class SetEnvironmentVariable(Action):
    def __init__(self, name, value, **kwargs):
        super().__init__(**kwargs)
        self.name, self.value = name, value

    def visit(self, context):
        name, value = perform(context, self.name), perform(context, self.value)
        context.environment[name] = value
        os.environ[name] = value


class AppendEnvironmentVariable(SetEnvironmentVariable):
    def __init__(self, name, value, *, prepend=False, separator=os.pathsep, **kwargs):
        super().__init__(name, value, **kwargs)
        self.prepend, self.separator = prepend, separator

    def visit(self, context):
        name, value = perform(context, self.name), perform(context, self.value)
        current = context.environment.get(name)
        if current:
            value = f"{value}{self.separator}{current}" if self.prepend else f"{current}{self.separator}{value}"
        context.environment[name] = value
        os.environ[name] = value


class UnsetEnvironmentVariable(Action):
    def __init__(self, name, **kwargs):
        super().__init__(**kwargs)
        self.name = name

    def visit(self, context):
        context.environment.pop(perform(context, self.name), None)


class LogInfo(Action):
    def __init__(self, *, msg="", **kwargs):
        super().__init__(**kwargs)
        self.msg = msg


class TimerAction(Action):
    def __init__(self, *, period, actions, cancel_on_shutdown=True, **kwargs):
        super().__init__(**kwargs)
        self.actions = list(actions)

    def visit(self, context):
        return list(self.actions)


class RegisterEventHandler(Action):
    def __init__(self, event_handler, **kwargs):
        super().__init__(**kwargs)
        self.event_handler = event_handler

    def visit(self, context):
        # the handler's entities may run: check them like any other
        return list(getattr(self.event_handler, "entities", []))


class EventHandler(Located):
    def __init__(self, *, matcher=None, entities=None, **_ignored):
        super().__init__()
        self.entities = _as_entities(entities)


def _as_entities(entities) -> list:
    if entities is None or callable(entities):
        return []
    if isinstance(entities, LaunchDescriptionEntity):
        return [entities]
    return [e for e in entities if isinstance(e, LaunchDescriptionEntity)]


class _OnEvent(EventHandler):
    def __init__(self, *, target_action=None, **kwargs):
        entities = None
        for key in ("on_exit", "on_start", "on_completion", "on_stdout", "on_stderr",
                    "on_shutdown", "entities", "on_include"):
            if kwargs.get(key) is not None:
                entities = kwargs[key]
        super().__init__(entities=entities)


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


class ExecuteProcess(Action):
    def __init__(self, *, cmd, name=None, cwd=None, env=None, additional_env=None, **kwargs):
        super().__init__(**kwargs)
        self.cmd = cmd

    def visit(self, context):
        RECORDER.add("nodes", {"kind": "process", "cmd": [perform(context, part) for part in self.cmd]}, self)


class ExecuteLocal(ExecuteProcess):
    def __init__(self, *, process_description=None, **kwargs):
        super().__init__(cmd=[], **kwargs)


class Shutdown(Action):
    pass


class EmitEvent(Action):
    def __init__(self, *, event=None, **kwargs):
        super().__init__(**kwargs)


# --- launch file sources and includes -------------------------------------------------------

class LaunchDescriptionSource(Located):
    kind: str | None = None

    def __init__(self, launch_file_path=None, *args, **kwargs):
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
    def __init__(self, launch_description_source, *, launch_arguments=None, **kwargs):
        super().__init__(**kwargs)
        if not isinstance(launch_description_source, LaunchDescriptionSource):
            launch_description_source = AnyLaunchDescriptionSource(launch_description_source)
        self.source = launch_description_source
        self.launch_arguments = list(launch_arguments or [])

    def visit(self, context):
        location = self.source.location
        path = perform(context, location) if location is not None else ""
        arguments = {perform(context, k): perform(context, v) for k, v in self.launch_arguments}
        exists = os.path.isfile(path)
        RECORDER.add("includes", {"path": path, "arguments": arguments, "exists": exists}, self)
        _record_path(path, self, "IncludeLaunchDescription")
        if not exists or _phantom(path):
            return None
        context.launch_configurations.update(arguments)
        from .evaluate import load_description  # noqa: PLC0415  (evaluate imports this module)

        description = load_description(path, self.source.kind)
        previous = context.current_file
        context.current_file = path
        return [description, _RestoreFile(previous)]


class ScopedIncludeLaunchDescription(IncludeLaunchDescription):
    pass


class _RestoreFile(LaunchDescriptionEntity):
    def __init__(self, previous):
        super().__init__()
        self.previous = previous

    def visit(self, context):
        context.current_file = self.previous


def _phantom(path: str) -> bool:
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    return bool(phantom) and os.path.abspath(path).startswith(phantom + os.sep)


# --- launch_ros actions ---------------------------------------------------------------------

class Node(ExecuteProcess):
    def __init__(self, *, executable=None, package=None, name=None, namespace=None,
                 exec_name=None, parameters=None, remappings=None, ros_arguments=None,
                 arguments=None, node_executable=None, node_name=None, node_namespace=None,
                 **kwargs):
        kwargs.pop("cmd", None)
        super().__init__(cmd=[], **kwargs)
        self.package = package
        self.executable = executable if executable is not None else node_executable
        self.node_name = name if name is not None else node_name
        self.namespace = namespace if namespace is not None else node_namespace
        self.parameters = list(parameters or [])
        self.remappings = list(remappings or [])
        self.arguments = list(arguments or [])
        self.ros_arguments = list(ros_arguments or [])

    def record(self, context) -> dict:
        package = perform(context, self.package) if self.package is not None else None
        arguments = []
        for argument in self.arguments:
            text = perform(context, argument)
            arguments.append(text)
            _record_path(text, self, "Node arguments")
        parameters = []
        for group in self.parameters:
            parameters.extend(_evaluate_parameters(context, group, self))
        return {
            "kind": "node", "package": package,
            "executable": perform(context, self.executable) if self.executable is not None else None,
            "name": perform(context, self.node_name) if self.node_name is not None else None,
            "namespace": perform(context, self.namespace) if self.namespace is not None else None,
            "arguments": arguments, "parameters": parameters,
            "remappings": [[perform(context, a), perform(context, b)] for a, b in self.remappings],
        }

    def visit(self, context):
        record = self.record(context)
        if record["package"]:
            RECORDER.add("packages", {"name": record["package"], "via": "Node package"}, self)
        RECORDER.add("nodes", record, self)


class LifecycleNode(Node):
    pass


class ParameterValue(Located):
    def __init__(self, value, *, value_type=None):
        super().__init__()
        self.value, self.value_type = value, value_type


class ParameterFile(Located):
    def __init__(self, param_file, *, allow_substs=False):
        super().__init__()
        self.param_file = param_file


class Parameter(Located):
    def __init__(self, name, value, *, value_type=None):
        super().__init__()
        self.name, self.value = name, value


def _evaluate_parameters(context, group, node) -> list[dict]:
    """Node parameters: dicts of name → value, or parameter files; with how each was given."""
    out = []
    if isinstance(group, dict):
        for key, value in group.items():
            name = perform(context, key) if not isinstance(key, str) else key
            given = _value_form(value)
            text = _perform_value(context, value)
            out.append({"name": name, "form": given, "value_preview": str(text)[:200],
                        "file": node._file, "line": getattr(value, "_line", None) or node._line})
            if isinstance(text, str):
                _record_path(text, node, "parameter")
    else:
        source = group.param_file if isinstance(group, ParameterFile) else group
        path = perform(context, source) if not isinstance(source, (os.PathLike,)) else os.fspath(source)
        _record_path(path, node, "parameter file")
        out.append({"name": None, "form": "file", "value_preview": path, "file": node._file, "line": node._line})
    return out


def _value_form(value) -> str:
    if isinstance(value, ParameterValue):
        typed = value.value_type is str
        return "typed-str" if typed else ("command-untyped" if _has_command(value.value) else "typed")
    if _has_command(value):
        return "command-untyped"
    return "plain"


def _has_command(value) -> bool:
    if isinstance(value, Command):
        return True
    if isinstance(value, (list, tuple)):
        return any(isinstance(v, Command) for v in value)
    return False


def _perform_value(context, value):
    if isinstance(value, ParameterValue):
        value = value.value
    if isinstance(value, (str, Substitution)) or (isinstance(value, (list, tuple)) and value and
                                                  all(isinstance(v, (str, Substitution)) for v in value)):
        return perform(context, value)
    return value


class ComposableNode(Located):
    def __init__(self, *, package, plugin, name=None, namespace=None, parameters=None,
                 remappings=None, extra_arguments=None, condition=None):
        super().__init__()
        self.package, self.plugin = package, plugin
        self.parameters = list(parameters or [])
        self.condition = condition


class ComposableNodeContainer(Node):
    def __init__(self, *, name, namespace, composable_node_descriptions=None, **kwargs):
        super().__init__(name=name, namespace=namespace, **kwargs)
        self.descriptions = list(composable_node_descriptions or [])

    def visit(self, context):
        super().visit(context)
        for description in self.descriptions:
            if description.condition is None or description.condition.evaluate(context):
                package = perform(context, description.package)
                RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)
                for group in description.parameters:
                    _evaluate_parameters(context, group, description)


class LoadComposableNodes(Action):
    def __init__(self, *, composable_node_descriptions, target_container=None, **kwargs):
        super().__init__(**kwargs)
        self.descriptions = list(composable_node_descriptions)

    def visit(self, context):
        for description in self.descriptions:
            package = perform(context, description.package)
            RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)


class PushRosNamespace(Action):
    def __init__(self, namespace, **kwargs):
        super().__init__(**kwargs)
        self.namespace = namespace


class SetParameter(Action):
    def __init__(self, name, value, **kwargs):
        super().__init__(**kwargs)
        self.name, self.value = name, value


class SetRemap(Action):
    def __init__(self, src, dst, **kwargs):
        super().__init__(**kwargs)


class SetUseSimTime(Action):
    def __init__(self, value, **kwargs):
        super().__init__(**kwargs)


class SetParametersFromFile(Action):
    def __init__(self, filename, **kwargs):
        super().__init__(**kwargs)
        self.filename = filename

    def visit(self, context):
        _record_path(perform(context, self.filename), self, "SetParametersFromFile")


class RosTimerAction(TimerAction):
    pass


# --- names ROS has and pkgforge does not evaluate -------------------------------------------

def unsupported(name: str, base: type = Action) -> type:
    """A real launch API name pkgforge records instead of evaluating."""

    def __init__(self, *args, **kwargs):
        base.__init__(self)
        RECORDER.add("unsupported", {"name": name}, self)

    def visit(self, context):
        return None

    def perform(self, context):
        raise Unresolved(f"<{name}>")

    return type(name, (base,), {"__init__": __init__, "visit": visit, "perform": perform})


def load_description_function(path, *args, **kwargs):
    """launch's get_launch_description_from_*_launch_file(): the file's LaunchDescription."""
    from .evaluate import load_description

    return load_description(os.fspath(path))
