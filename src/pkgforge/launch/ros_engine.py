"""The real engine: a ROS 2 distro's own `launch`, `launch_xml`, `launch_yaml` and `launch_ros`.

Runs only in the launch worker (`PKGFORGE_LAUNCH_ENGINE=ros`). The libraries are
imported once per worker. Each file is loaded as `ros2 launch` loads it (by the
loader its name says, with the locals its include would give it; a required
argument not given is recorded, not fatal) and its description is visited here, entity by entity, WITHOUT starting anything: the
actions that would start a process (ExecuteProcess, Node, ComposableNodeContainer,
LifecycleNode) have their substitutions performed and are recorded instead; no
ROS graph, no DDS, and nothing written outside a temporary folder (ROS_LOG_DIR
and the temporary parameter files live there). `Command` runs only xacro (in this
process, with the real xacro library); any other command is recorded as run-time
only. Where rclpy, lifecycle_msgs or composition_interfaces cannot be imported,
minimal stand-ins provide just what launch_ros touches at import and visit time.

The records are the built-in engine's (launch/records.py), with the same `via`
names, so the two engines can be compared record for record (tests/test_launch_oracle.py).
"""

from __future__ import annotations

import atexit
import enum
import os
import re
import shlex
import shutil
import sys
import tempfile
import types
from collections.abc import Callable, Iterable
from typing import Any

from pkgforge.build.toolchain import python_paths
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
    failure_text,
    marked,
)
from pkgforge.launch.builtin.launch.event_handlers import HandledEvent, handler_event
from pkgforge.launch.builtin.launch.execute_process import PREPARING
from pkgforge.launch.builtin.launch.include_launch_description import include_arguments
from pkgforge.launch.builtin.launch.launch_context import RECORDER, record_path
from pkgforge.launch.builtin.launch.substitution import joined
from pkgforge.launch.builtin.launch_ros.node import InvalidNodeNameException
from pkgforge.launch.builtin.launch_ros.node import validate_node_name as _validate_node_name
from pkgforge.launch.builtin.launch_ros.substitutions import executable_in_package, lookup_package
from pkgforge.launch.place import FRONTEND_LOCATION, LAUNCH_FILES, here
from pkgforge.launch.records import (
    PREVIEW_LENGTH,
    BranchBudget,
    ErrorRecordDict,
    ExecutionRecordDict,
    LaunchResultDict,
    NodeRecordDict,
    ParameterForm,
    ParameterRecordDict,
    Status,
    as_dict,
    evaluate_branches,
    runs_at_verify_time,
)

# The distro's launch libraries are untyped: their objects (entities, contexts, substitutions,
# parser elements) are `Any` here, and so are the methods this module puts on their classes.

MAX_DEPTH = 32
# actions whose execution needs a running launch service or a ROS graph (SetUseSimTime sets a
# parameter of the launch's own rclpy node): recorded, not executed, as the built-in engine does
NOT_EVALUATED = {"OpaqueCoroutine", "LifecycleTransition", "UnregisterEventHandler", "SetUseSimTime"}
# substitutions whose value exists only at run time (the run's timestamped log folder): recorded
# as not evaluated, and what uses them skipped, as the built-in engine does
RUN_TIME_VALUES = ("LaunchLogDir",)

L = types.SimpleNamespace()  # the real libraries, once imported
_SCRATCH: str | None = None
# the context being visited; launch also performs substitutions in throw-away contexts to
# introspect included files (argument names), and those are not evaluations
_VISITING: Any = None  # a launch.LaunchContext


def _evaluating(context: Any) -> bool:
    return context is _VISITING


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


def _install_stand_ins() -> list[str]:
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


def _yaml_with_lines(yaml_module: Any) -> types.SimpleNamespace:
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


def _xml_with_lines(et_module: Any) -> types.SimpleNamespace:
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


def setup(prefix: str | None) -> None:
    """Import the distro's launch libraries (once) and hook what records and locates."""
    global _SCRATCH
    if getattr(L, "launch", None) is not None:
        return
    # in the parent's scratch folder (it removes it however this worker ends), else in TMPDIR
    base = os.environ.get("PKGFORGE_SCRATCH")
    _SCRATCH = tempfile.mkdtemp(prefix="pkgforge-ros-", dir=base if base and os.path.isdir(base) else None)
    atexit.register(shutil.rmtree, _SCRATCH, True)
    os.environ["ROS_LOG_DIR"] = os.path.join(_SCRATCH, "log")
    os.environ.setdefault("ROS_HOME", os.path.join(_SCRATCH, "ros_home"))
    tempfile.tempdir = os.path.join(_SCRATCH, "tmp")
    os.makedirs(tempfile.tempdir, exist_ok=True)
    if prefix:
        for folder in reversed(python_paths(prefix)):
            if folder not in sys.path:
                sys.path.insert(0, folder)
    from pkgforge.launch.engines import SYSTEM_PYTHON

    if os.path.isdir(SYSTEM_PYTHON) and SYSTEM_PYTHON not in sys.path:
        sys.path.append(SYSTEM_PYTHON)  # lark, osrf_pycommon as Debian's ROS packages install them
    L.stand_ins = _install_stand_ins()
    import xml.etree.ElementTree as ET

    import launch
    import launch.frontend
    import launch.launch_description_sources
    import launch.logging
    import launch.substitutions
    import launch.utilities
    import launch_ros
    import launch_ros.actions
    import launch_ros.descriptions
    import launch_ros.substitutions
    import launch_xml  # noqa: F401
    import launch_xml.parser
    import launch_yaml  # noqa: F401
    import launch_yaml.parser
    import yaml

    try:
        launch.logging.launch_config.log_dir = os.environ["ROS_LOG_DIR"]
    except Exception:  # noqa: BLE001 - an older launch: ROS_LOG_DIR alone decides
        pass
    launch_xml.parser.ET = _xml_with_lines(ET)
    launch_yaml.parser.yaml = _yaml_with_lines(yaml)
    L.launch, L.launch_ros = launch, launch_ros
    L.perform = _hook_perform_substitutions(launch.utilities.perform_substitutions)
    L.normalize = launch.utilities.normalize_to_list_of_substitutions
    _hook_locations()
    _hook_loaders()
    _hook_substitutions()
    _memoize_substitution_grammar()
    _fast_parameter_files(yaml)


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


def _fast_parameter_files(yaml_module: Any) -> None:
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


def _memoize_substitution_grammar() -> None:
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


def _hook_locations() -> None:
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


def _hook_loaders() -> None:
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


def _hook_perform_substitutions(real: Callable[[Any, Any], str]) -> Callable[[Any, Any], str]:
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


def _hook_substitutions() -> None:
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


# --- visiting -----------------------------------------------------------------------------


def _text(context: Any, value: Any) -> str | None:
    if value is None:
        return None
    return _perform(context, value)


def _perform(context: Any, value: Any) -> str:
    """A value that is there (a str, a substitution or a list of them) performed."""
    text: str = L.perform(context, L.normalize(value))
    return text


def _has_command(value: Any) -> bool:
    Command = L.launch.substitutions.Command
    if isinstance(value, Command):
        return True
    if isinstance(value, (list, tuple)):
        return any(_has_command(v) for v in value)
    return False


def _value_form(value: Any) -> ParameterForm:
    ParameterValue = L.launch_ros.parameter_descriptions.ParameterValue
    if isinstance(value, ParameterValue):
        if value.value_type is str:
            return "typed-str"
        return "command-untyped" if _has_command(value.value) else "typed"
    return "command-untyped" if _has_command(value) else "plain"


def _value_preview(context: Any, value: Any) -> Any:
    """The value's text (its substitutions performed), else the value as given (a number, a list)."""
    ParameterValue = L.launch_ros.parameter_descriptions.ParameterValue
    Substitution = L.launch.Substitution
    if isinstance(value, ParameterValue):
        value = value.value
    if isinstance(value, (str, Substitution)) or (
        isinstance(value, (list, tuple)) and value and all(isinstance(v, (str, Substitution)) for v in value)
    ):
        return L.perform(context, L.normalize(value))
    return value


def _parameters(context: Any, groups: Iterable[Any], owner: Any) -> list[ParameterRecordDict]:
    ParameterFile = L.launch_ros.parameter_descriptions.ParameterFile
    out: list[ParameterRecordDict] = []
    for group in groups:
        if isinstance(group, dict):
            for key, value in group.items():
                name = key if isinstance(key, str) else _text(context, key)
                form = _value_form(value)
                text = _value_preview(context, value)
                out.append(
                    {
                        "name": name,
                        "form": form,
                        "value_preview": str(text)[:PREVIEW_LENGTH],
                        "file": owner._file,
                        "line": getattr(value, "_line", None) or owner._line,
                    }
                )
                if isinstance(text, str):
                    record_path(text, owner, "parameter")
        else:
            source = group.param_file if isinstance(group, ParameterFile) else group
            path = os.fspath(source) if isinstance(source, os.PathLike) else _perform(context, source)
            record_path(path, owner, "parameter file")
            out.append(
                {
                    "name": None,
                    "form": "file",
                    "value_preview": path,
                    "file": owner._file,
                    "line": owner._line,
                }
            )
    return out


def _record_node(node: Any, context: Any) -> None:
    """Node, LifecycleNode, ComposableNodeContainer: their substitutions performed, nothing started."""
    package = _text(context, node._Node__package)
    if package:
        RECORDER.add("packages", {"name": package, "via": "Node package"}, node)
    arguments: list[str] = []
    for argument in node._pkgforge_arguments:
        text = _perform(context, argument)
        arguments.append(text)
        record_path(text, node, "Node arguments")
    # SetParameter's global parameters, which launch_ros gives every node in scope
    parameters: list[ParameterRecordDict] = [
        {
            "name": group[0],
            "form": "plain",
            "value_preview": str(group[1])[:PREVIEW_LENGTH],
            "file": node._file,
            "line": node._line,
        }
        for group in context.launch_configurations.get("global_params") or []
        if isinstance(group, tuple)
    ]
    parameters += _parameters(context, node._pkgforge_parameters, node)
    record: NodeRecordDict = {
        "kind": "node",
        "package": package,
        "executable": _text(context, node._Node__node_executable),
        "arguments": arguments,
        "parameters": parameters,
    }
    try:
        node._perform_substitutions(context)  # the real name, namespace, parameter and remapping rules
    except Exception:
        # recorded as written, and the failure (a bad name, a parameter launch_ros refuses) reported
        RECORDER.add(
            "nodes",
            {
                **record,
                "name": _text(context, node._Node__node_name),
                "namespace": _text(context, node._Node__node_namespace),
                "remappings": [
                    [_perform(context, a), _perform(context, b)] for a, b in node._Node__remappings or []
                ],
            },
            node,
        )
        raise
    name = node._Node__expanded_node_name
    namespace = node.expanded_node_namespace
    RECORDER.add(
        "nodes",
        {
            **record,
            "name": None if name == node.UNSPECIFIED_NODE_NAME else name,
            "namespace": None if namespace == node.UNSPECIFIED_NODE_NAMESPACE else namespace,
            "remappings": [[a, b] for a, b in (node.expanded_remapping_rules or [])],
        },
        node,
    )


def _record_composable(descriptions: Iterable[Any], context: Any) -> None:
    for description in descriptions:
        condition = description.condition()
        if condition is not None and not condition.evaluate(context):
            continue
        package = _perform(context, description.package)
        RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)
        _parameters(context, _raw_parameters(description), description)


def _raw_parameters(description: Any) -> list[Any]:
    return list(getattr(description, "_pkgforge_parameters", None) or [])


def _handle(action: Any, context: Any, depth: int) -> Iterable[Any] | None:
    """The entities an action yields, recording what would start instead of starting it."""
    launch, launch_ros = L.launch, L.launch_ros
    name = type(action).__name__
    if name in NOT_EVALUATED:
        RECORDER.add("unsupported", {"name": name}, action)
        return None
    if isinstance(action, launch.actions.IncludeLaunchDescription):
        return _include(action, context, depth)
    if isinstance(action, launch.actions.DeclareLaunchArgument):
        return _declare(action, context)
    if isinstance(action, launch_ros.actions.Node):
        _execute(action, context, lambda: _record_node(action, context))
        if isinstance(action, launch_ros.actions.ComposableNodeContainer):
            _record_composable(action._ComposableNodeContainer__composable_node_descriptions or [], context)
        return None
    if isinstance(action, launch_ros.actions.LoadComposableNodes):
        _record_composable(action._LoadComposableNodes__composable_node_descriptions or [], context)
        return None
    if isinstance(action, launch.actions.ExecuteProcess):
        cmd = [L.perform(context, part) for part in action.process_description.cmd]
        shell = bool(getattr(action, "shell", False))  # (ExecuteLocal's, since humble)
        RECORDER.add("nodes", {"kind": "process", "cmd": cmd, "shell": shell}, action)
        _execute(action, context)
        return None
    if isinstance(action, launch.actions.TimerAction):
        # what its execute performs; its actions are visited when the description is done
        from launch.utilities.type_utils import perform_typed_substitution

        perform_typed_substitution(context, action._TimerAction__cancel_on_shutdown, bool)
        return list(action.actions)
    if isinstance(action, launch.actions.RegisterEventHandler):
        out: list[Any] = []
        for _, entities in action.describe_conditional_sub_entities():
            out.extend(e for e in entities if isinstance(e, launch.LaunchDescriptionEntity))
        return out + _shutdown_entities(action.event_handler)
    if name == "SetParametersFromFile":
        record_path(
            _text(context, action._SetParametersFromFile__param_file), action, "SetParametersFromFile"
        )
    children: Iterable[Any] | None = action.execute(context)
    return children


def _execute(action: Any, context: Any, before: Callable[[], None] | None = None) -> None:
    """What the action's execute performs before it would start its process, by the real
    methods (launch_ros's Node._perform_substitutions in `before`, then ExecuteLocal.prepare and
    the output), recorded as its execution (builtin execute_process.execute_process is the built-in engine's);
    a failure is recorded there too, and raised as launch raises it. Nothing is started."""
    try:
        if before is not None:
            before()
        PREPARING[0] = True
        try:
            record = _prepared(action, context)
        finally:
            PREPARING[0] = False
    except Exception as error:
        RECORDER.add("executions", {"action": type(action).__name__, "failure": failure_text(error)}, action)
        raise
    RECORDER.add("executions", record, action)


def _prepared(action: Any, context: Any) -> ExecutionRecordDict:
    description = action.process_description
    node = isinstance(action, L.launch_ros.actions.Node)
    context._push_locals()
    try:
        if node:  # what Node.execute puts in the locals for the command's `__node:=`
            specific: dict[str, str] = {}
            if action._Node__node_name is not None:
                specific["name"] = f"__node:={action._Node__expanded_node_name}"
            if action.expanded_node_namespace != "":
                specific["ns"] = f"__ns:={action.expanded_node_namespace}"
            context.extend_locals({"ros_specific_arguments": specific})
        action.prepare(context)
        output = action._ExecuteLocal__output
        text = None if isinstance(output, dict) else L.perform(context, output)
    finally:
        context._pop_locals()
    final: list[str] = list(description.final_cmd)
    # what _perform_substitutions added (namespace, parameter files, remappings) left out
    added = len(description.cmd) - action._pkgforge_own_cmd if node else 0
    env = description.final_env if description.env is not None else None
    additional = {
        L.perform(context, key): L.perform(context, value) for key, value in description.additional_env or []
    }
    return {
        "action": type(action).__name__,
        "cmd": final[: len(final) - added],
        "name": description.final_name.rsplit("-", 1)[0],
        "cwd": description.final_cwd,
        "env": None if env is None else [[k, v] for k, v in env.items()],
        "additional_env": [[k, v] for k, v in additional.items()],
        "output": text,
        "respawn": bool(action._ExecuteLocal__respawn),
    }


def _shutdown_entities(handler: Any) -> list[Any]:
    """OnShutdown(on_shutdown=[...])'s entities, which its describe() leaves out: launch keeps them
    in a function of its own that returns them whatever the event (humble's lambda, gen_handler
    from Iron on); called as launch calls it on shutdown. A function of the file's own is only
    known when the event happens (as in the built-in engine)."""
    function = getattr(handler, "_OnShutdown__on_shutdown", None)
    if function is None or getattr(function, "__module__", None) != "launch.event_handlers.on_shutdown":
        return []
    entities = function(None, None)  # (it reads neither the event nor the context)
    entities = entities if isinstance(entities, Iterable) else [entities]
    return [e for e in entities if isinstance(e, L.launch.LaunchDescriptionEntity)]


def _handled_event(action: Any) -> HandledEvent:
    """The event a RegisterEventHandler's handler handles (builtin event_handlers.handler_event), with the action
    it watches: launch keeps that in the handler's private attributes."""
    handler = action.event_handler
    target = getattr(handler, "_OnActionEventBase__action_matcher", None)
    target = getattr(handler, "_OnStateTransition__target_lifecycle_node", target)
    return handler_event(handler, target if isinstance(target, L.launch.Action) else None)


def _declare(action: Any, context: Any) -> Iterable[Any] | None:
    default: str | None = None
    if action.default_value is not None:
        try:
            default = L.perform(context, action.default_value)
        except Exception:  # noqa: BLE001 - a default that needs a value not given: no default shown
            default = None
    RECORDER.arguments.setdefault(
        action.name,
        {
            "name": action.name,
            "default": default,
            # (choices=('wxai') is a str: one word, as the built-in engine takes it)
            "choices": ([action.choices] if isinstance(action.choices, str) else list(action.choices))
            if action.choices
            else None,
            "file": action._file,
            "line": action._line,
            "boolean": default is not None and default.lower() in ("true", "false"),
        },
    )
    if action.name not in context.launch_configurations and action.default_value is None:
        RECORDER.add("required", {"name": action.name}, action)
        return None
    children: Iterable[Any] | None = action.execute(context)
    return children


def _phantom(path: str) -> bool:
    phantom = os.environ.get("PKGFORGE_PHANTOM_PREFIX")
    if not phantom:
        return False
    return os.path.abspath(path).startswith(phantom + os.sep)


def _include(action: Any, context: Any, depth: int) -> Iterable[Any] | None:
    source = action.launch_description_source
    path = L.perform(context, source._LaunchDescriptionSource__location)
    arguments = include_arguments(context, action.launch_arguments, _perform)
    exists = os.path.isfile(path)
    RECORDER.add("includes", {"path": path, "arguments": arguments, "exists": exists}, action)
    record_path(path, action, "IncludeLaunchDescription")
    if not exists or _phantom(path):
        RECORDER.unfollowed.append(path)
        return None
    LAUNCH_FILES.add(path)
    children: Iterable[Any] | None = action.execute(context)
    return children


def visit(
    entity: Any,
    context: Any,
    depth: int = 0,
    in_handler: bool = False,
    ancestors: tuple[tuple[int, int], ...] = (),
    loading: tuple[tuple[int, int], ...] = (),
) -> None:
    """Visit one entity; `ancestors` and `loading`: the stand-in reads of the OpaqueFunctions and
    the included files' loading it came from (evaluate.visit's, the same rule)."""
    launch = L.launch
    if depth > MAX_DEPTH:
        RECORDER.add(
            "errors",
            {
                "stage": "visit",
                "type": "RecursionError",
                "message": f"launch files include each other more than {MAX_DEPTH} deep",
                "file": None,
                "line": None,
            },
        )
        return
    start = len(RECORDER.stand_in_reads)  # (what this entity reads from here on is its own)
    try:
        if isinstance(entity, launch.Action):
            condition = entity.condition
            if condition is not None:
                taken = bool(condition.evaluate(context))
                RECORDER.add(
                    "conditions",
                    {"condition": type(condition).__name__, "entity": type(entity).__name__, "taken": taken},
                    entity,
                )
                if not taken:
                    return
            from pkgforge.launch.evaluate import executed

            executed(entity)
            children = _handle(entity, context, depth)
        else:
            children = entity.visit(context)
    except Exception as error:  # noqa: BLE001 - every failure is a finding, none a crash
        from pkgforge.launch.evaluate import RUNS_ON_THE_EVENT, record_visit_failure

        if not (in_handler and type(entity).__name__ in RUNS_ON_THE_EVENT):
            record_visit_failure(entity, error, [*ancestors, (start, None)], list(loading))
        return
    from pkgforge.launch.evaluate import child_spans, defer

    spans = child_spans(entity, start, ancestors, loading)
    if isinstance(entity, launch.actions.TimerAction) and children:
        # its actions run when the period has passed, once the description is done
        defer(context, list(children), "TimerAction", None, depth + 1, in_handler, spans)
    elif isinstance(entity, launch.actions.RegisterEventHandler) and children:
        # as launch visits them when the event comes
        kind = type(entity.event_handler).__name__
        defer(context, list(children), kind, _handled_event(entity), depth + 1, True, spans)
    else:
        for child in children or []:
            visit(child, context, depth + 1, in_handler, *spans)


# --- one file -----------------------------------------------------------------------------


def evaluate(
    path: str, overrides: dict[str, str], distro: str | None, budget: BranchBudget | None = None
) -> LaunchResultDict:
    """Resolve one launch file with the real libraries; the result is plain data (JSON). `budget`
    (records.BranchBudget): how long the argument combinations past the defaults may run."""
    path_before = list(sys.path)  # what the file adds is its own (as the built-in engine keeps it)
    try:
        return _evaluate(path, overrides, distro, budget)
    finally:
        sys.path[:] = path_before


def _evaluate(
    path: str, overrides: dict[str, str], distro: str | None, budget: BranchBudget | None
) -> LaunchResultDict:
    from pkgforge.launch import evaluate as builtin

    builtin._watch_xacro()
    # the launch file's own ament_index lookups, recorded (and a package not found here standing
    # in as an empty one) as the built-in engine does; launch_ros's own lookups are left alone
    builtin._watch_ament()
    builtin._watch_stand_in_reads()
    RECORDER.reset()
    LAUNCH_FILES.clear()
    LAUNCH_FILES.add(path)
    environment = dict(os.environ)
    launch = L.launch
    try:
        try:
            first = _load(path)  # a file that does not load is a load error, as in `ros2 launch`
        except BaseException as error:  # noqa: BLE001 - SystemExit and friends included
            return _result("load-error", _load_error(path, error), distro)
        RECORDER.load_reads = len(RECORDER.stand_in_reads)

        def run(values: dict[str, str], label: dict[str, str]) -> None:
            global _VISITING
            nonlocal first
            context = launch.LaunchContext(noninteractive=True)
            for key, value in {**overrides, **values}.items():
                context.launch_configurations[key] = value
            # what IncludeLaunchDescription gives the file `ros2 launch` includes, without its
            # refusal of a required argument not given: that is recorded, what needs it skipped
            context.extend_locals(
                {"current_launch_file_path": path, "current_launch_file_directory": os.path.dirname(path)}
            )
            # a fresh description for each evaluation: included sources cache what they loaded
            if first is not None:
                description = first
            else:
                # what loading records holds for every setting, as the first load's records do
                # (records.evaluate_branches): not this branch's alone
                RECORDER.branch = {}
                description = _load(path)
            first = None
            RECORDER.branch = label
            _VISITING = context
            try:
                declared_from = builtin.begin_visit()
                visit(description, context)

                def run_one(item: builtin.Deferred) -> None:
                    for entity in item.entities:
                        visit(entity, context, item.depth, item.in_handler, *item.spans)

                builtin.run_deferred(context, run_one)
                builtin.settle_unset_uses(declared_from)
            finally:
                _VISITING = None
                _clean_scratch()

        branching = evaluate_branches(RECORDER, path, overrides, run, budget)
        result = _result("ok", None, distro)
        result["branching"] = branching.as_reply()
        return result
    finally:
        os.environ.clear()
        os.environ.update(environment)
        _clean_scratch()


def _result(status: Status, error: ErrorRecordDict | None, distro: str | None) -> LaunchResultDict:
    result: LaunchResultDict = {"status": status, "error": error}
    RECORDER.dump_into(result)
    result["files"] = sorted(LAUNCH_FILES)
    result["engine"], result["distro"] = "ros", distro
    return result


def _load_error(path: str, error: BaseException) -> ErrorRecordDict:
    """A file ROS refuses to load: ROS's own exception, at the element that failed in a front-end
    file (lark wraps a substitution's error in a VisitError; the error itself is what is said)."""
    from pkgforge.launch import evaluate as builtin

    cause = getattr(error, "orig_exc", None) if type(error).__name__ == "VisitError" else None
    refusal = _undecodable(path, error)
    if refusal is not None:
        error = refusal
    record = builtin._error_record(path, cause if isinstance(cause, Exception) else error, "load")
    located = getattr(error, "_pkgforge_location", None)
    if located is not None and record.get("line") is None:
        record["file"], record["line"] = located[0] or path, located[1]
    return record


def _undecodable(path: str, error: BaseException) -> BaseException | None:
    """launch's refusal of a front-end file that is not UTF-8 (an InvalidFrontendLaunchFileError
    of each parser's UnicodeDecodeError) as the built-in engine says it: the decoding error, at
    the line of the first byte that is not UTF-8 (frontend.decoded). None: another error."""
    from pkgforge.launch.frontend import FrontendError, decoded

    errors = [error, *(getattr(error, "_likely_errors", None) or [])]  # (InvalidLaunchFileError's)
    if path.endswith(".py") or not any(isinstance(e, UnicodeDecodeError) for e in errors):
        return None
    try:
        with open(path, "rb") as handle:
            decoded(handle.read())
    except FrontendError as refusal:
        return refusal
    except OSError:
        return None
    return None  # the file is UTF-8: a decoding error of something it read


def _load(path: str) -> Any:  # a launch.LaunchDescription
    """The file's LaunchDescription, loaded by the loader its name says (as `ros2 launch` tries
    first), so that its own exception, with its line, is what a load error reports."""
    sources = L.launch.launch_description_sources
    if path.endswith(".py"):
        return sources.get_launch_description_from_python_launch_file(path)
    if path.endswith((".xml", ".yaml", ".yml")):
        return sources.get_launch_description_from_frontend_launch_file(path)
    return sources.get_launch_description_from_any_launch_file(path)


def _clean_scratch() -> None:
    """Temporary parameter files and logs go, after every evaluation."""
    scratch = tempfile.tempdir  # setup() put it in _SCRATCH
    if _SCRATCH is None or scratch is None:
        return
    shutil.rmtree(scratch, ignore_errors=True)  # the log folder stays: launch keeps its file open
    os.makedirs(scratch, exist_ok=True)


def error_reply(path: str, message: str, distro: str | None) -> LaunchResultDict:
    """The reply for every file when the distro's libraries cannot be imported."""
    from pkgforge.launch.records import Error

    error = Error(stage="worker", type="RosEngineError", message=message, file=path)
    return {"status": "load-error", "error": as_dict(error), "engine": "ros", "distro": distro}
