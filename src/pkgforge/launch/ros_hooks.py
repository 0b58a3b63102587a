"""What pkgforge puts into the real launch libraries: stand-ins and hooks that locate, load and record.

The real engine (ros_engine.py) imports the distro's launch and launch_ros once per worker;
before, rclpy and friends are stood in (no ROS graph, no middleware), and the libraries' own
functions are wrapped so that every object knows its launch file and line, every lookup and
path is recorded as the built-in engine records it, and a failure is marked with its cause.
The distro's libraries are untyped: their objects are `Any` here.
"""

from __future__ import annotations

import enum
import os
import re
import shlex
import sys
import types
from collections.abc import Callable
from typing import Any

from pkgforge.launch.builtin.launch.command import command_output
from pkgforge.launch.builtin.launch.errors import (
    FAILURE_CONFIGURATION,
    FAILURE_CONFIGURATION_AT,
    FAILURE_MARKS,
    FAILURE_PROGRAM,
    FAILURE_VARIABLE,
    MISSING_CONFIGURATION_TEXT,
    Unresolved,
    failure_mark,
    marked,
)
from pkgforge.launch.builtin.launch.launch_context import RECORDER, record_path
from pkgforge.launch.builtin.launch.substitution import joined
from pkgforge.launch.builtin.launch_ros.node import InvalidNodeNameException
from pkgforge.launch.builtin.launch_ros.node import validate_node_name as _validate_node_name
from pkgforge.launch.builtin.launch_ros.substitutions import executable_in_package, lookup_package
from pkgforge.launch.place import FRONTEND_LOCATION, LAUNCH_FILES, here
from pkgforge.launch.records import runs_at_verify_time

# substitutions whose value exists only at run time (the run's timestamped log folder): recorded
# as not evaluated, and what uses them skipped, as the built-in engine does
RUN_TIME_VALUES = ("LaunchLogDir",)

L = types.SimpleNamespace()  # the real libraries, once imported
# the context being visited; launch also performs substitutions in throw-away contexts to
# introspect included files (argument names), and those are not evaluations
_VISITING: Any = None  # a launch.LaunchContext


def _evaluating(context: Any) -> bool:
    return context is _VISITING


def visiting(context: Any) -> None:
    """The context ros_engine visits with now (None: none)."""
    global _VISITING
    _VISITING = context


# --- stand-ins for the compiled ROS packages launch_ros imports -------------------------------


def _module(name: str, **attributes: Any) -> Any:
    """A stand-in module (Any: its attributes are whatever launch_ros reads of the real one)."""
    module = types.ModuleType(name)
    module.__dict__.update(attributes)
    module.__dict__["__pkgforge_stand_in__"] = True
    sys.modules[name] = module
    return module


class _Constants:
    """A message class's constants: the real values, any other name an int."""

    def __init__(self, **values: int) -> None:
        self.__dict__.update(values)

    def __getattr__(self, name: str) -> int:
        if name.isupper():
            return 0
        raise AttributeError(name)

    def __call__(self, *args: Any, **kwargs: Any) -> types.SimpleNamespace:
        return types.SimpleNamespace(**kwargs)


class _Message:
    Request = types.SimpleNamespace
    Response = types.SimpleNamespace


_NAMESPACE = re.compile(r"^/([A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*)?$")


class InvalidNamespaceException(ValueError):
    pass


def _validate_namespace(namespace: str | None) -> bool:
    if not _NAMESPACE.match(namespace or ""):
        raise InvalidNamespaceException(f"Invalid namespace: '{namespace}'")
    return True


class _ParameterType(enum.IntEnum):
    NOT_SET = 0
    BOOL = 1
    INTEGER = 2
    DOUBLE = 3
    STRING = 4
    BYTE_ARRAY = 5
    BOOL_ARRAY = 6
    INTEGER_ARRAY = 7
    DOUBLE_ARRAY = 8
    STRING_ARRAY = 9

    def check(self, value: object) -> bool:
        kinds = {1: bool, 2: int, 3: float, 4: str}
        if self in kinds:
            return isinstance(value, kinds[self]) and not (self == 2 and isinstance(value, bool))
        if self == _ParameterType.NOT_SET:
            return value is None
        return isinstance(value, (list, tuple))


class _Parameter:
    Type = _ParameterType

    def __init__(self, name: str, type_: _ParameterType | None = None, value: object = None) -> None:
        self.name, self.type_, self.value = name, type_, value


def install_stand_ins() -> list[str]:
    """Stand-ins for what cannot be imported; the names of those provided."""
    provided: list[str] = []
    try:
        import rclpy  # noqa: F401
        import rclpy.executors  # noqa: F401
        import rclpy.parameter  # noqa: F401
        import rclpy.validate_namespace  # noqa: F401
        import rclpy.validate_node_name  # noqa: F401
    except Exception:  # noqa: BLE001 - a ROS for another Python: its extension modules do not load
        for name in [n for n in sys.modules if n == "rclpy" or n.startswith("rclpy.")]:
            del sys.modules[name]
        rclpy = _module("rclpy", ok=lambda: False, init=lambda *a, **k: None, shutdown=lambda *a, **k: None)
        rclpy.executors = _module("rclpy.executors", SingleThreadedExecutor=object)
        rclpy.parameter = _module("rclpy.parameter", Parameter=_Parameter)
        rclpy.validate_namespace = _module("rclpy.validate_namespace", validate_namespace=_validate_namespace)
        rclpy.validate_node_name = _module("rclpy.validate_node_name", validate_node_name=_validate_node_name)
        rclpy.logging = _module("rclpy.logging", get_logging_directory=lambda: os.environ["ROS_LOG_DIR"])
        rclpy.exceptions = _module(
            "rclpy.exceptions",
            InvalidNamespaceException=InvalidNamespaceException,
            InvalidNodeNameException=InvalidNodeNameException,
        )
        rclpy.node = _module("rclpy.node", Node=object)
        provided.append("rclpy")
    try:
        import lifecycle_msgs.msg  # noqa: F401
        import lifecycle_msgs.srv  # noqa: F401
    except Exception:  # noqa: BLE001
        state = _Constants(
            PRIMARY_STATE_UNKNOWN=0,
            PRIMARY_STATE_UNCONFIGURED=1,
            PRIMARY_STATE_INACTIVE=2,
            PRIMARY_STATE_ACTIVE=3,
            PRIMARY_STATE_FINALIZED=4,
            TRANSITION_STATE_CONFIGURING=10,
            TRANSITION_STATE_CLEANINGUP=11,
            TRANSITION_STATE_SHUTTINGDOWN=12,
            TRANSITION_STATE_ACTIVATING=13,
            TRANSITION_STATE_DEACTIVATING=14,
            TRANSITION_STATE_ERRORPROCESSING=15,
        )
        transition = _Constants(
            TRANSITION_CREATE=0,
            TRANSITION_CONFIGURE=1,
            TRANSITION_CLEANUP=2,
            TRANSITION_ACTIVATE=3,
            TRANSITION_DEACTIVATE=4,
            TRANSITION_UNCONFIGURED_SHUTDOWN=5,
            TRANSITION_INACTIVE_SHUTDOWN=6,
            TRANSITION_ACTIVE_SHUTDOWN=7,
            TRANSITION_DESTROY=8,
        )
        package: Any = _module("lifecycle_msgs")
        package.msg = _module(
            "lifecycle_msgs.msg", State=state, Transition=transition, TransitionEvent=_Constants()
        )
        package.srv = _module("lifecycle_msgs.srv", ChangeState=_Message, GetState=_Message)
        provided.append("lifecycle_msgs")
    try:
        import composition_interfaces.srv  # noqa: F401
    except Exception:  # noqa: BLE001
        package = _module("composition_interfaces")
        package.srv = _module(
            "composition_interfaces.srv", LoadNode=_Message, UnloadNode=_Message, ListNodes=_Message
        )
        provided.append("composition_interfaces")
    return provided


# --- setting up the libraries, once per worker ------------------------------------------------


class _LineDict(dict[Any, Any]):
    line: int | None = None


def yaml_with_lines(yaml_module: Any) -> types.SimpleNamespace:
    class Loader(yaml_module.SafeLoader):  # type: ignore[misc]  # (the module given is untyped)
        pass

    def construct_map(loader: Any, node: Any) -> Any:
        data = _LineDict()
        data.line = node.start_mark.line + 1
        yield data
        data.update(loader.construct_mapping(node))
        for key_node, value_node in node.value:
            value = loader.constructed_objects.get(value_node)
            if isinstance(value, _LineDict):
                value.line = key_node.start_mark.line + 1  # the tag's line, as `- node:` is written

    Loader.add_constructor("tag:yaml.org,2002:map", construct_map)
    shim = types.SimpleNamespace(
        **{k: getattr(yaml_module, k) for k in dir(yaml_module) if not k.startswith("__")}
    )
    shim.safe_load = lambda stream: _bounded_load(stream, Loader)
    return shim


def _bounded_load(stream: Any, loader: Any) -> Any:
    """yaml.load(stream, Loader=loader) through pkgforge's YAML reader: an alias bomb or 50,000
    nested brackets end as a located YAMLError, not a walk of 10**11 nodes or a RecursionError."""
    from pkgforge.model.yamlnodes import load

    text = stream if isinstance(stream, (str, bytes)) else stream.read()
    return load(text.decode("utf-8") if isinstance(text, bytes) else text, loader)


def xml_with_lines(et_module: Any) -> types.SimpleNamespace:
    """xml.etree's parse through lxml: the same element API, with each element's source line."""
    from lxml import etree

    parser = etree.XMLParser(remove_comments=True, remove_pis=True)
    shim = types.SimpleNamespace(
        **{k: getattr(et_module, k) for k in dir(et_module) if not k.startswith("__")}
    )
    shim.parse = lambda source, *a, **k: etree.parse(source, parser)
    return shim


def _entity_line(entity: Any) -> int | None:
    for attribute in ("_Entity__xml_element", "_Entity__element"):
        element = getattr(entity, attribute, None)
        if element is not None:
            return getattr(element, "sourceline", None) or getattr(element, "line", None)
    return None


class _MemoParser:
    """launch's substitution grammar parser, each distinct string parsed once per worker: the
    tree is only read by the transformer, which builds fresh substitutions from it every time."""

    def __init__(self, parser: Any) -> None:
        self.parser = parser
        self.trees: dict[str, Any] = {}

    def parse(self, text: str, *args: Any, **kwargs: Any) -> Any:
        if args or kwargs:
            return self.parser.parse(text, *args, **kwargs)
        if text not in self.trees:
            self.trees[text] = self.parser.parse(text)
        return self.trees[text]

    def __getattr__(self, name: str) -> Any:
        return getattr(self.parser, name)


def fast_parameter_files(yaml_module: Any) -> None:
    """launch_ros dumps a node's parameters to a temporary file with PyYAML's pure-Python
    dumper; libyaml's writes the same document, several times faster (the file is removed)."""
    import launch_ros.actions.node as node_module

    dumper = getattr(yaml_module, "CDumper", None)  # the C twin of yaml.dump's default Dumper
    if dumper is None or not _dumps_with(node_module, yaml_module):
        return
    shim = types.SimpleNamespace(
        **{k: getattr(yaml_module, k) for k in dir(yaml_module) if not k.startswith("__")}
    )

    def dump(data: Any, stream: Any = None, **kwargs: Any) -> Any:
        return yaml_module.dump(data, stream, Dumper=dumper, **kwargs)

    shim.dump = dump
    node_module.yaml = shim


def _dumps_with(node_module: Any, yaml_module: Any) -> bool:
    """Whether launch_ros's node module dumps parameters with this yaml module."""
    return getattr(node_module, "yaml", None) is yaml_module


def memoize_substitution_grammar() -> None:
    """Every file is loaded again for each evaluated branch; the Earley parse of its
    substitution strings is most of a front-end file's cost."""
    try:
        from launch.frontend import parse_substitution as module

        if getattr(module, "_parser", None) is None:
            with open(module.get_grammar_path()) as handle:
                module._parser = module.Lark(handle, start="template")
        if not isinstance(module._parser, _MemoParser):
            module._parser = _MemoParser(module._parser)
    except Exception:  # noqa: BLE001 - another launch layout: parsed as launch parses it
        pass


def _locate(cls: Any) -> None:
    """Every instance of cls (and its subclasses) remembers the launch file line that made it:
    set in __new__, which runs once whatever the __init__ chain does."""
    if cls.__dict__.get("_pkgforge_located"):
        return
    real_new = cls.__new__

    def __new__(klass: Any, *args: Any, **kwargs: Any) -> Any:
        instance = real_new(klass) if real_new is object.__new__ else real_new(klass, *args, **kwargs)
        try:
            instance._file, instance._line = here()
        except AttributeError:  # __slots__: no location
            pass
        return instance

    cls.__new__ = staticmethod(__new__)
    cls._pkgforge_located = True


def hook_locations() -> None:
    launch, launch_ros = L.launch, L.launch_ros
    from launch.event_handler import BaseEventHandler

    bases = [
        launch.LaunchDescriptionEntity,
        launch.Substitution,
        launch.Condition,
        launch.LaunchDescriptionSource,
        BaseEventHandler,
        launch_ros.descriptions.ComposableNode,
        launch_ros.parameter_descriptions.ParameterValue,
        launch_ros.parameter_descriptions.ParameterFile,
    ]
    for base in bases:
        _locate(base)
    node_init = launch_ros.actions.Node.__init__

    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        self._pkgforge_parameters = list(kwargs.get("parameters") or [])
        self._pkgforge_arguments = list(kwargs.get("arguments") or [])
        self._pkgforge_ros_arguments = list(kwargs.get("ros_arguments") or [])
        node_init(self, *args, **kwargs)
        # the command as the node gives it to ExecuteProcess, before _perform_substitutions adds to it
        self._pkgforge_own_cmd = len(self.cmd)

    launch_ros.actions.Node.__init__ = __init__
    composable_init = launch_ros.descriptions.ComposableNode.__init__

    def composable(self: Any, *args: Any, **kwargs: Any) -> None:
        self._pkgforge_parameters = list(kwargs.get("parameters") or [])
        composable_init(self, *args, **kwargs)

    launch_ros.descriptions.ComposableNode.__init__ = composable
    parse_action = launch.frontend.Parser.parse_action

    def located_parse_action(self: Any, entity: Any) -> Any:
        file = FRONTEND_LOCATION[-1][0] if FRONTEND_LOCATION else None
        line = _entity_line(entity)
        FRONTEND_LOCATION.append((file, line))
        try:
            action = parse_action(self, entity)
        except Exception as error:
            # the innermost element that failed: ROS's own front end does not say where
            if getattr(error, "_pkgforge_location", None) is None and line is not None:
                try:
                    error.__dict__["_pkgforge_location"] = (file, line)  # read by _load_error
                except AttributeError:
                    pass
            raise
        finally:
            FRONTEND_LOCATION.pop()
        if hasattr(action, "__dict__"):  # the element's line, whatever its children set last
            action._file, action._line = file, line
        return action

    launch.frontend.Parser.parse_action = located_parse_action
    import launch_xml.entity
    import launch_yaml.entity

    for entity_class in (launch_xml.entity.Entity, launch_yaml.entity.Entity):
        _locate_attributes(entity_class)


def _locate_attributes(entity_class: Any) -> None:
    """A substitution parsed from an element's attribute stands on that element's line
    (a <param>'s value on the <param>, not on its <node>)."""
    get_attr = entity_class.get_attr

    def located_get_attr(self: Any, *args: Any, **kwargs: Any) -> Any:
        line = _entity_line(self)
        if FRONTEND_LOCATION and line is not None:
            FRONTEND_LOCATION[-1] = (FRONTEND_LOCATION[-1][0], line)
        return get_attr(self, *args, **kwargs)

    entity_class.get_attr = located_get_attr


def hook_loaders() -> None:
    """Every launch file loaded (top level or included) joins the files whose frames are user code."""
    from launch.launch_description_sources import frontend_launch_file_utilities as frontend
    from launch.launch_description_sources import python_launch_file_utilities as python

    real_python = python.get_launch_description_from_python_launch_file
    real_frontend = frontend.get_launch_description_from_frontend_launch_file

    def from_python(path: Any, *args: Any, **kwargs: Any) -> Any:
        LAUNCH_FILES.add(os.fspath(path))
        return real_python(path, *args, **kwargs)

    def from_frontend(path: Any, *args: Any, **kwargs: Any) -> Any:
        LAUNCH_FILES.add(os.fspath(path))
        FRONTEND_LOCATION.append((os.fspath(path), None))
        try:
            return real_frontend(path, *args, **kwargs)
        finally:
            FRONTEND_LOCATION.pop()

    real_module = python.load_python_launch_file_as_module

    def as_module(
        path: Any, *args: Any, **kwargs: Any
    ) -> Any:  # a launch file loaded by another one: user code too
        LAUNCH_FILES.add(os.fspath(path))
        return real_module(path, *args, **kwargs)

    replacements: dict[Any, Callable[..., Any]] = {
        real_python: from_python,
        real_frontend: from_frontend,
        real_module: as_module,
    }
    for name, module in list(sys.modules.items()):
        if name.split(".")[0] in ("launch", "launch_xml", "launch_yaml", "launch_ros") and module is not None:
            for attribute, value in list(vars(module).items()):
                if callable(value) and value in replacements:
                    setattr(module, attribute, replacements[value])


def hook_perform_substitutions(real: Callable[[Any, Any], str]) -> Callable[[Any, Any], str]:
    """launch's perform_substitutions, every module's name for it: in the visit, the built-in
    engine's concatenation (builtin substitution.joined), so a path that is only part of a name the list
    builds is recorded as that whole name in both engines."""

    def perform_substitutions(context: Any, subs: Any) -> str:
        if not _evaluating(context):
            return real(context, subs)
        return joined(subs, context.perform_substitution)

    for name, module in list(sys.modules.items()):
        if name.split(".")[0] in ("launch", "launch_xml", "launch_yaml", "launch_ros") and module is not None:
            if getattr(module, "perform_substitutions", None) is real:
                module.__dict__["perform_substitutions"] = perform_substitutions
    return perform_substitutions


def hook_substitutions() -> None:
    subs, ros_subs = L.launch.substitutions, L.launch_ros.substitutions

    def wrap(
        cls: Any,
        after: Callable[[Any, Any, str], object] | None = None,
        before: Callable[[Any, Any], object] | None = None,
    ) -> None:
        real = cls.perform

        def perform(self: Any, context: Any) -> Any:
            if before is not None and _evaluating(context):
                before(self, context)
            result = real(self, context)
            if after is not None and _evaluating(context):
                after(self, context, result)
            return result

        cls.perform = perform

    wrap(subs.PathJoinSubstitution, after=lambda s, c, r: record_path(r, s, "PathJoinSubstitution"))
    if hasattr(subs, "FileContent"):
        wrap(subs.FileContent, before=lambda s, c: record_path(L.perform(c, s.path), s, "FileContent"))

    def find_executable(self: Any, context: Any) -> None:
        if L.perform(context, self.name) == "xacro":
            RECORDER.add("packages", {"name": "xacro", "via": "FindExecutable"}, self)

    wrap(subs.FindExecutable, before=find_executable)
    _mark_missing_configuration(subs.LaunchConfiguration)
    _locate_parameter_file_substitutions(L.launch_ros.parameter_descriptions.ParameterFile)
    _mark_failure(subs.FindExecutable, FAILURE_PROGRAM)
    _mark_failure(subs.EnvironmentVariable, FAILURE_VARIABLE)

    real_perform = ros_subs.FindPackage.perform

    def find_perform(self: Any, context: Any) -> Any:
        if not _evaluating(context):
            return real_perform(self, context)
        self._pkgforge_performing = True
        try:
            return real_perform(self, context)
        finally:
            self._pkgforge_performing = False

    ros_subs.FindPackage.perform = find_perform
    for cls, kind in ((ros_subs.FindPackageShare, "share"), (ros_subs.FindPackagePrefix, "prefix")):
        _find(cls, kind)
    if hasattr(ros_subs, "ExecutableInPackage"):
        real_executable = ros_subs.ExecutableInPackage.perform

        def executable_perform(self: Any, context: Any) -> Any:
            """as the built-in engine (builtin launch_ros/substitutions.executable_in_package): a package not found here
            stands in as an empty one; an executable not built yet is no failure"""
            if not _evaluating(context):
                return real_executable(self, context)
            return executable_in_package(
                self, L.perform(context, self.executable), L.perform(context, self.package)
            )

        ros_subs.ExecutableInPackage.perform = executable_perform
    subs.Command.perform = _command_perform
    for name in RUN_TIME_VALUES:
        if hasattr(subs, name):
            getattr(subs, name).perform = _run_time_value(name)


def _mark_failure(cls: Any, mark: str) -> None:
    """cls's SubstitutionFailure carries the name it looked up, as the built-in engine's does
    (builtin errors.marked): FindExecutable's program not on PATH, EnvironmentVariable's variable not set
    (launch says the former as the list of substitutions, not the name)."""
    real = cls.perform

    def perform(self: Any, context: Any) -> Any:
        name = L.perform(context, self.name)  # (a failure of the name's own substitutions is theirs)
        try:
            return real(self, context)
        except L.launch.substitutions.SubstitutionFailure as error:
            if getattr(self, "default_value", None) is None:  # (a default's failure is the default's)
                marked(error, mark, name)
            raise

    cls.perform = perform


def _mark_missing_configuration(cls: Any) -> None:
    """launch's failure of a LaunchConfiguration not set carries its name and the
    substitution's place, as the built-in engine's does (builtin errors.missing_configuration): the
    innermost one, where a configuration's name or default uses another."""
    real = cls.perform

    def perform(self: Any, context: Any) -> Any:
        try:
            return real(self, context)
        except L.launch.substitutions.SubstitutionFailure as error:
            unset = MISSING_CONFIGURATION_TEXT.search(str(error))
            if unset is not None and all(failure_mark(error, m) is None for m in FAILURE_MARKS):
                setattr(error, FAILURE_CONFIGURATION, unset.group(1))
                setattr(
                    error,
                    FAILURE_CONFIGURATION_AT,
                    (getattr(self, "_file", None), getattr(self, "_line", None)),
                )
            raise

    cls.perform = perform


def _locate_parameter_file_substitutions(cls: Any) -> None:
    """A parameter file read with allow_substs: the substitutions launch_ros parses from its text
    stand at the ParameterFile's place (the built-in engine's launch_ros/parameter_descriptions._allowed_parameter_files)."""
    real = cls.evaluate

    def evaluate(self: Any, context: Any) -> Any:
        FRONTEND_LOCATION.append((getattr(self, "_file", None), getattr(self, "_line", None)))
        try:
            return real(self, context)
        finally:
            FRONTEND_LOCATION.pop()

    cls.evaluate = evaluate


def _run_time_value(name: str) -> Callable[[Any, Any], str]:
    def perform(self: Any, context: Any) -> str:
        if _evaluating(context):
            RECORDER.add("unsupported", {"name": name}, self)
        raise Unresolved(f"<{name}>")

    return perform


def _find(cls: Any, kind: str) -> None:
    """FindPackageShare/FindPackagePrefix's lookup, as the built-in engine does it
    (builtin launch_ros/substitutions.lookup_package): recorded, and a package not found here reported and standing in as
    an empty one, so the node using it and every later use in the file are still checked
    (issue 10, item 4). Performed in the visit: at the substitution's place; called by the launch
    file itself (`FindPackageShare('p').find('p')`): at that call's place; anything else (launch
    introspecting in a throw-away context) is the real lookup."""
    real = cls.find

    def find(self: Any, package_name: str) -> Any:
        if getattr(self, "_pkgforge_performing", False):
            return lookup_package(package_name, cls.__name__, self, kind)
        if sys._getframe(1).f_code.co_filename in LAUNCH_FILES:
            return lookup_package(package_name, cls.__name__, here(), kind)
        return real(self, package_name)

    cls.find = find


def _command_perform(self: Any, context: Any) -> str:
    """Command as the built-in engine performs it (builtin command.command_output, one policy for both):
    what is a pure function of files runs here (xacro with the real library); any other command
    is recorded as run-time only."""
    text = L.perform(context, self.command)
    on_stderr = L.perform(context, self.on_stderr) if hasattr(self, "on_stderr") else "fail"
    if not _evaluating(context):
        # launch performing substitutions in a throw-away context: nothing runs, nothing recorded
        if runs_at_verify_time(shlex.split(text)):
            raise L.launch.substitutions.SubstitutionFailure("not evaluated outside the launch file's visit")
        return ""
    output: str = command_output(self, text, on_stderr, L.launch.substitutions.SubstitutionFailure)
    return output
