"""The launch API modules of the built-in engine, built from the real API's list of names.

Only inside the launch worker. `api_names.json` (generated from the real ros2/launch and
launch_ros sources by scripts/gen_launch_api.py) lists, per distro, every module of
launch, launch_xml, launch_yaml and launch_ros, the names each defines or imports, and
the signatures of their classes and functions. An import hook serves these modules:

- the module paths are the real ones, submodules included (`launch.substitutions.
  launch_configuration`, `launch.launch_context`), and importing one imports what the real
  one imports, so the same submodule attributes exist afterwards;
- a name pkgforge evaluates is its implementation in `builtin/` (the same object under
  every path, as in ROS); the real constructor's signature is enforced first, so a call ROS
  rejects raises the same TypeError;
- a real name pkgforge does not evaluate is a stand-in with the real signature that records
  `unsupported` (an info) and does nothing; evaluation goes on;
- a name the distro does not have is missing, so importing it is an ImportError as in ROS.

The distro is PKGFORGE_LAUNCH_DISTRO (humble, jazzy; kilted, lyrical and rolling use
jazzy's list); jazzy when unset or unknown.
"""

from __future__ import annotations

import builtins
import importlib
import importlib.abc
import importlib.util
import json
import sys
import types
import typing
from collections.abc import Callable, Sequence
from importlib.machinery import ModuleSpec
from pathlib import Path
from typing import Any, Literal, TypedDict

from pkgforge.launch import place
from pkgforge.launch.builtin import unsupported as unsupported_names
from pkgforge.launch.builtin.distro import distro
from pkgforge.launch.builtin.launch import (
    action,
    actions,
    conditions,
    errors,
    event_handlers,
    execute_process,
    include_launch_description,
    launch_context,
    launch_description,
    launch_description_sources,
    substitution,
    substitutions,
    utilities,
)
from pkgforge.launch.builtin.launch import command as command_substitution
from pkgforge.launch.builtin.launch_ros import actions as ros_actions
from pkgforge.launch.builtin.launch_ros import (
    composable_nodes,
    namespaces,
    node,
    parameter_descriptions,
)
from pkgforge.launch.builtin.launch_ros import substitutions as ros_substitutions

DATA = Path(__file__).resolve().parent / "api_names.json"
NO_DEFAULT = "<required>"
NOT_LITERAL = "<expression>"
TOP = ("launch", "launch_ros", "launch_xml", "launch_yaml")


# --- what pkgforge evaluates: the real name (where ROS defines it) → builtin's object ----------

_EVENT_CLASSES = ("launch.event.Event", "launch.events.", "launch_ros.events.")

IMPLEMENTED = {
    "launch.action.Action": "Action",
    "launch.condition.Condition": "Condition",
    "launch.event_handler.BaseEventHandler": "BaseEventHandler",
    "launch.event_handler.EventHandler": "EventHandler",
    "launch.invalid_launch_file_error.InvalidLaunchFileError": "InvalidLaunchFileError",
    "launch.launch_context.LaunchContext": "LaunchContext",
    "launch.launch_description.LaunchDescription": "LaunchDescription",
    "launch.launch_description_entity.LaunchDescriptionEntity": "LaunchDescriptionEntity",
    "launch.launch_description_source.LaunchDescriptionSource": "LaunchDescriptionSource",
    "launch.substitution.Substitution": "Substitution",
    "launch.some_substitutions_type.SomeSubstitutionsType": "SomeSubstitutionsType",
    "launch.some_substitutions_type.SomeSubstitutionsType_types_tuple": "SomeSubstitutionsType_types_tuple",
    "launch.some_entities_type.SomeEntitiesType": "SomeEntitiesType",
    "launch.some_entities_type.SomeEntitiesType_types_tuple": "SomeEntitiesType_types_tuple",
    "launch.some_actions_type.SomeActionsType": "SomeEntitiesType",
    "launch.some_actions_type.SomeActionsType_types_tuple": "SomeEntitiesType_types_tuple",
    "launch.utilities.typing_file_path.FilePath": "FilePath",
    # actions
    "launch.actions.append_environment_variable.AppendEnvironmentVariable": "AppendEnvironmentVariable",
    "launch.actions.declare_launch_argument.DeclareLaunchArgument": "DeclareLaunchArgument",
    "launch.actions.emit_event.EmitEvent": "EmitEvent",
    "launch.actions.execute_local.ExecuteLocal": "ExecuteLocal",
    "launch.actions.execute_process.ExecuteProcess": "ExecuteProcess",
    "launch.actions.group_action.GroupAction": "GroupAction",
    "launch.actions.include_launch_description.IncludeLaunchDescription": "IncludeLaunchDescription",
    "launch.actions.log_info.LogInfo": "LogInfo",
    "launch.actions.opaque_function.OpaqueFunction": "OpaqueFunction",
    "launch.actions.pop_environment.PopEnvironment": "PopEnvironment",
    "launch.actions.pop_launch_configurations.PopLaunchConfigurations": "PopLaunchConfigurations",
    "launch.actions.push_environment.PushEnvironment": "PushEnvironment",
    "launch.actions.push_launch_configurations.PushLaunchConfigurations": "PushLaunchConfigurations",
    "launch.actions.register_event_handler.RegisterEventHandler": "RegisterEventHandler",
    "launch.actions.reset_environment.ResetEnvironment": "ResetEnvironment",
    "launch.actions.reset_launch_configurations.ResetLaunchConfigurations": "ResetLaunchConfigurations",
    "launch.actions.set_environment_variable.SetEnvironmentVariable": "SetEnvironmentVariable",
    "launch.actions.set_launch_configuration.SetLaunchConfiguration": "SetLaunchConfiguration",
    "launch.actions.shutdown_action.Shutdown": "Shutdown",
    "launch.actions.timer_action.TimerAction": "TimerAction",
    "launch.actions.unset_environment_variable.UnsetEnvironmentVariable": "UnsetEnvironmentVariable",
    "launch.actions.unset_launch_configuration.UnsetLaunchConfiguration": "UnsetLaunchConfiguration",
    # conditions
    "launch.conditions.evaluate_condition_expression_impl.evaluate_condition_expression": "evaluate_condition_expression",
    "launch.conditions.evaluate_condition_expression_impl.VALID_TRUE_EXPRESSIONS": "VALID_TRUE_EXPRESSIONS",
    "launch.conditions.evaluate_condition_expression_impl.VALID_FALSE_EXPRESSIONS": "VALID_FALSE_EXPRESSIONS",
    "launch.conditions.if_condition.IfCondition": "IfCondition",
    "launch.conditions.unless_condition.UnlessCondition": "UnlessCondition",
    "launch.conditions.invalid_condition_expression_error.InvalidConditionExpressionError": "InvalidConditionExpressionError",
    "launch.conditions.launch_configuration_equals.LaunchConfigurationEquals": "LaunchConfigurationEquals",
    "launch.conditions.launch_configuration_not_equals.LaunchConfigurationNotEquals": "LaunchConfigurationNotEquals",
    # event handlers: their entities are visited
    "launch.event_handlers.on_action_event_base.OnActionEventBase": "OnActionEventBase",
    "launch.event_handlers.on_execution_complete.OnExecutionComplete": "OnExecutionComplete",
    "launch.event_handlers.on_include_launch_description.OnIncludeLaunchDescription": "OnIncludeLaunchDescription",
    "launch.event_handlers.on_process_exit.OnProcessExit": "OnProcessExit",
    "launch.event_handlers.on_process_io.OnProcessIO": "OnProcessIO",
    "launch.event_handlers.on_process_start.OnProcessStart": "OnProcessStart",
    "launch.event_handlers.on_shutdown.OnShutdown": "OnShutdown",
    "launch.event_handlers.event_named.event_named": "matcher",
    "launch.events.matchers.matches_action": "matcher",
    "launch.events.process.process_matchers.matches_executable": "matcher",
    "launch.events.process.process_matchers.matches_name": "matcher",
    "launch.events.process.process_matchers.matches_pid": "matcher",
    "launch_ros.events.lifecycle.lifecycle_node_matchers.matches_node_name": "matcher",
    "launch_ros.events.matchers.matches_node_name.matches_node_name": "matcher",
    "launch_ros.event_handlers.on_state_transition.OnStateTransition": "OnStateTransition",
    # sources and loading
    "launch.launch_description_sources.any_launch_description_source.AnyLaunchDescriptionSource": "AnyLaunchDescriptionSource",
    "launch.launch_description_sources.frontend_launch_description_source.FrontendLaunchDescriptionSource": "FrontendLaunchDescriptionSource",
    "launch.launch_description_sources.python_launch_description_source.PythonLaunchDescriptionSource": "PythonLaunchDescriptionSource",
    "launch.launch_description_sources.any_launch_file_utilities.get_launch_description_from_any_launch_file": "load_description_function",
    "launch.launch_description_sources.frontend_launch_file_utilities."
    "get_launch_description_from_frontend_launch_file": "load_description_function",
    "launch.launch_description_sources.python_launch_file_utilities."
    "get_launch_description_from_python_launch_file": "load_description_function",
    "launch.launch_description_sources.python_launch_file_utilities.load_python_launch_file_as_module": "load_python_launch_file_as_module",
    "launch.launch_description_sources.python_launch_file_utilities.InvalidPythonLaunchFileError": "InvalidPythonLaunchFileError",
    "launch.frontend.parser.InvalidFrontendLaunchFileError": "InvalidFrontendLaunchFileError",
    "launch_xml.launch_description_sources.xml_launch_description_source.XMLLaunchDescriptionSource": "XMLLaunchDescriptionSource",
    "launch_yaml.launch_description_sources.yaml_launch_description_source.YAMLLaunchDescriptionSource": "YAMLLaunchDescriptionSource",
    # substitutions
    "launch.substitutions.anon_name.AnonName": "AnonName",
    "launch.substitutions.boolean_substitution.AllSubstitution": "AllSubstitution",
    "launch.substitutions.boolean_substitution.AndSubstitution": "AndSubstitution",
    "launch.substitutions.boolean_substitution.AnySubstitution": "AnySubstitution",
    "launch.substitutions.boolean_substitution.NotSubstitution": "NotSubstitution",
    "launch.substitutions.boolean_substitution.OrSubstitution": "OrSubstitution",
    "launch.substitutions.command.Command": "Command",
    "launch.substitutions.environment_variable.EnvironmentVariable": "EnvironmentVariable",
    "launch.substitutions.equals_substitution.EqualsSubstitution": "EqualsSubstitution",
    "launch.substitutions.file_content.FileContent": "FileContent",
    "launch.substitutions.find_executable.FindExecutable": "FindExecutable",
    "launch.substitutions.if_else_substitution.IfElseSubstitution": "IfElseSubstitution",
    "launch.substitutions.launch_configuration.LaunchConfiguration": "LaunchConfiguration",
    "launch.substitutions.local_substitution.LocalSubstitution": "LocalSubstitution",
    "launch.substitutions.not_equals_substitution.NotEqualsSubstitution": "NotEqualsSubstitution",
    "launch.substitutions.path_join_substitution.PathJoinSubstitution": "PathJoinSubstitution",
    "launch.substitutions.python_expression.PythonExpression": "PythonExpression",
    "launch.substitutions.substitution_failure.SubstitutionFailure": "SubstitutionFailure",
    "launch.substitutions.text_substitution.TextSubstitution": "TextSubstitution",
    "launch.substitutions.this_launch_file.ThisLaunchFile": "ThisLaunchFile",
    "launch.substitutions.this_launch_file_dir.ThisLaunchFileDir": "ThisLaunchFileDir",
    # utilities
    "launch.utilities.class_tools_impl.is_a": "is_a",
    "launch.utilities.class_tools_impl.is_a_subclass": "is_a_subclass",
    "launch.utilities.class_tools_impl.isclassinstance": "isclassinstance",
    "launch.utilities.ensure_argument_type_impl.ensure_argument_type": "ensure_argument_type",
    "launch.utilities.normalize_to_list_of_entities_impl.normalize_to_list_of_entities": "normalize_to_list_of_entities",
    "launch.utilities.normalize_to_list_of_substitutions_impl.normalize_to_list_of_substitutions": "normalize",
    "launch.utilities.perform_substitutions_impl.perform_substitutions": "perform_substitutions",
    "launch.logging.get_logger": "get_logger",
    # launch_ros
    "launch_ros.actions.composable_node_container.ComposableNodeContainer": "ComposableNodeContainer",
    "launch_ros.actions.lifecycle_node.LifecycleNode": "LifecycleNode",
    "launch_ros.actions.load_composable_nodes.LoadComposableNodes": "LoadComposableNodes",
    "launch_ros.actions.node.Node": "Node",
    "launch_ros.actions.push_ros_namespace.PushROSNamespace": "PushRosNamespace",
    "launch_ros.actions.push_ros_namespace.PushRosNamespace": "PushRosNamespace",
    "launch_ros.actions.ros_timer.ROSTimer": "RosTimerAction",
    "launch_ros.actions.ros_timer.RosTimer": "RosTimerAction",
    "launch_ros.actions.set_parameter.SetParameter": "SetParameter",
    "launch_ros.actions.set_parameters_from_file.SetParametersFromFile": "SetParametersFromFile",
    "launch_ros.actions.set_remap.SetRemap": "SetRemap",
    "launch_ros.descriptions.composable_node.ComposableNode": "ComposableNode",
    "launch_ros.parameter_descriptions.Parameter": "Parameter",
    "launch_ros.parameter_descriptions.ParameterFile": "ParameterFile",
    "launch_ros.parameter_descriptions.ParameterValue": "ParameterValue",
    "launch_ros.substitutions.executable_in_package.ExecutableInPackage": "ExecutableInPackage",
    "launch_ros.substitutions.find_package.FindPackage": "FindPackage",
    "launch_ros.substitutions.find_package.FindPackagePrefix": "FindPackagePrefix",
    "launch_ros.substitutions.find_package.FindPackageShare": "FindPackageShare",
    "launch_ros.utilities.namespace_utils.is_namespace_absolute": "is_namespace_absolute",
    "launch_ros.utilities.namespace_utils.is_root_namespace": "is_root_namespace",
    "launch_ros.utilities.namespace_utils.make_namespace_absolute": "make_namespace_absolute",
    "launch_ros.utilities.namespace_utils.prefix_namespace": "prefix_namespace",
}

# the built-in engine's modules, laid out as launch and launch_ros lay theirs out; an
# implementation above is found by its name in the one that defines it
IMPLEMENTATIONS = (
    place,
    errors,
    launch_context,
    substitution,
    conditions,
    substitutions,
    command_substitution,
    action,
    launch_description,
    actions,
    event_handlers,
    execute_process,
    launch_description_sources,
    include_launch_description,
    utilities,
    unsupported_names,
    ros_substitutions,
    namespaces,
    node,
    parameter_descriptions,
    composable_nodes,
    ros_actions,
)


def implementation(name: str) -> Any:
    """The built-in engine's object of that name (IMPLEMENTED's values)."""
    for module in IMPLEMENTATIONS:
        if name in vars(module):
            return vars(module)[name]
    raise LookupError(f"no built-in implementation named {name}")


# --- the list of names ----------------------------------------------------------------------

ParamKind = Literal[
    "POSITIONAL_ONLY", "POSITIONAL_OR_KEYWORD", "VAR_POSITIONAL", "KEYWORD_ONLY", "VAR_KEYWORD"
]
# One parameter of a real signature: (name, inspect.Parameter kind name, default as written
# in the source or NO_DEFAULT); JSON arrays of three, only ever unpacked or indexed.
Param = tuple[str, ParamKind, object]
EntryKind = Literal["alias", "module", "external", "external-module", "class", "function", "value"]


class Method(TypedDict):
    kind: Literal["method", "property", "classmethod", "staticmethod"]
    signature: list[Param]


class Entry(TypedDict, total=False):
    """One name of a module: what `kind` says, with the keys that kind has."""

    kind: EntryKind
    target: str  # alias: the dotted name it re-exports
    module: str  # module, external, external-module: the module's dotted name
    attr: str  # external: the name in that module
    bases: list[str]  # class: dotted names of its bases
    methods: dict[str, Method]  # class
    signature: list[Param]  # function
    line: int  # class, function, value: where the real source defines it


class ModuleInfo(TypedDict, total=False):
    names: dict[str, Entry]
    imports: list[str]  # the modules the real one imports
    all: list[str] | None
    package: bool
    submodules: list[str]


class Frontend(TypedDict):
    actions: dict[str, str]  # XML/YAML tag → the real class's dotted name
    substitutions: dict[str, str]  # $(name …) → the real class's dotted name


class DistroData(TypedDict):
    sources: str
    frontend: Frontend
    modules: dict[str, ModuleInfo]


# a call's (args, kwargs), checked against a real constructor (raises the TypeError ROS raises)
Validator = Callable[[tuple[Any, ...], dict[str, Any]], None]

# each distro's list, read once: the fork server reads its own distro's ahead, and a worker it
# forks for a package of another target distro (PKGFORGE_LAUNCH_DISTRO) reads that one
_data: dict[str, DistroData] = {}
# what each canonical name stands for: a built-in class or function, a stand-in, typing.Any
_objects: dict[str, Any] = {}


def _distro_data() -> DistroData:
    name = distro()
    if name not in _data:
        with open(DATA, encoding="utf-8") as handle:
            data: DistroData = json.load(handle)["distros"][name]
        _data[name] = data
    return _data[name]


def modules() -> dict[str, ModuleInfo]:
    return _distro_data()["modules"]


def frontend() -> Frontend:
    """{"actions": {tag: real class}, "substitutions": {name: real class}} of the XML/YAML front end."""
    return _distro_data()["frontend"]


def _split(target: str) -> tuple[str, str]:
    module, _, name = target.rpartition(".")
    return module, name


def _definition(target: str, depth: int = 0) -> tuple[str, Entry] | None:
    """(canonical name, entry) of what target names, following re-exports; None if unknown."""
    module, name = _split(target)
    entry = modules().get(module, {}).get("names", {}).get(name)
    if entry is None or depth > 20:
        return None
    if entry["kind"] == "alias":
        if entry["target"] in modules():
            return entry["target"], {"kind": "module", "module": entry["target"]}
        return _definition(entry["target"], depth + 1)
    return target, entry


def resolve(target: str) -> Any:
    """The object a real dotted name stands for here (cached: one object for every path).

    Any: a module, a class, a function or a typing construct, used by the launch file (and
    the front end) as the real API's object would be, dynamically."""
    found = _definition(target)
    if found is None:
        if target in modules():
            return importlib.import_module(target)
        raise LookupError(target)
    canonical, entry = found
    if entry["kind"] == "module":
        return importlib.import_module(entry.get("module", canonical))
    if canonical in _objects:
        return _objects[canonical]
    kind = entry["kind"]
    value: Any
    if kind == "external":
        return getattr(importlib.import_module(entry["module"]), entry["attr"])
    if kind == "external-module":
        return importlib.import_module(entry["module"])
    if canonical in IMPLEMENTED:
        value = implementation(IMPLEMENTED[canonical])
        if isinstance(value, type) and kind == "class":
            _enforce_signature(value, canonical, entry)
    elif kind == "class" and canonical.startswith(_EVENT_CLASSES):
        value = _inert_class(canonical, entry)
    elif kind == "class":
        value = _stand_in_class(canonical, entry)
    elif kind == "function":
        value = _stand_in_function(canonical, entry)
    else:
        value = typing.Any  # a type alias or constant pkgforge has no use for
    _objects[canonical] = value
    return value


# --- signatures -----------------------------------------------------------------------------


def _init_entry(canonical: str, entry: Entry, depth: int = 0) -> tuple[str, list[Param], list[str]] | None:
    """(class name, __init__ signature, canonical bases) of the nearest class defining __init__."""
    if "__init__" in entry.get("methods", {}):
        return canonical, entry["methods"]["__init__"]["signature"], entry.get("bases", [])
    for base in entry.get("bases", []):
        found = _definition(base)
        if found and found[1]["kind"] == "class" and depth < 20:
            result = _init_entry(found[0], found[1], depth + 1)
            if result:
                return result
    return None


def _checker(qualname: str, signature: Sequence[Param]) -> Callable[..., dict[str, Any]]:
    """A function with the real parameters: calling it raises CPython's own TypeError.

    It returns what its **kwargs caught (what the real class passes on to its base)."""
    names: list[str] = []
    defaults: dict[str, None] = {}
    positional_only_done = not any(kind == "POSITIONAL_ONLY" for _, kind, _ in signature)
    star_done = False
    var_keyword = None
    for index, (name, kind, default) in enumerate(signature):
        text = name
        if kind == "VAR_POSITIONAL":
            text, star_done = f"*{name}", True
        elif kind == "VAR_KEYWORD":
            text, var_keyword = f"**{name}", name
        elif kind == "KEYWORD_ONLY" and not star_done:
            names.append("*")
            star_done = True
        if kind not in ("VAR_POSITIONAL", "VAR_KEYWORD") and default != NO_DEFAULT:
            defaults[f"_d{index}"] = None
            text = f"{name}=_d{index}"
        if not positional_only_done and kind != "POSITIONAL_ONLY":
            names.append("/")
            positional_only_done = True
        names.append(text)
    body = f"return {var_keyword}" if var_keyword else "return {}"
    namespace: dict[str, Any] = dict(defaults)
    short = qualname.rsplit(".", 1)[-1]
    exec(f"def {short}({', '.join(names)}):\n    {body}\n", namespace)  # noqa: S102 - parameters only
    function: Callable[..., dict[str, Any]] = namespace[short]
    function.__qualname__ = qualname
    return function


def _enforce_signature(cls: type, canonical: str, entry: Entry) -> None:
    """Calls of cls are checked against the real constructor (and what its **kwargs reach)."""
    found = _init_entry(canonical, entry)
    if found is None or "_pkgforge_check" in cls.__dict__:
        return
    owner, signature, bases = found
    name = canonical.rsplit(".", 1)[-1]
    check = _checker(f"{name}.__init__", signature)
    chain: list[tuple[str, list[Param]]] = []
    for base in bases:
        definition = _definition(base)
        while definition is not None and definition[1]["kind"] == "class":
            init = _init_entry(*definition)
            if init is None:
                break
            chain.append((init[0].rsplit(".", 1)[-1], init[1]))
            if not any(kind == "VAR_KEYWORD" for _, kind, _ in init[1]) or not init[2]:
                break
            definition = _definition(init[2][0])
        break

    def validate(args: tuple[Any, ...], kwargs: dict[str, Any]) -> None:
        rest = check(None, *args, **kwargs)
        for base_name, base_signature in chain:
            if not rest:
                break
            accepted = {
                n for n, kind, _ in base_signature if kind in ("POSITIONAL_OR_KEYWORD", "KEYWORD_ONLY")
            }
            takes_more = any(kind == "VAR_KEYWORD" for _, kind, _ in base_signature)
            for key in rest:
                if key not in accepted and not takes_more:
                    raise TypeError(f"{base_name}.__init__() got an unexpected keyword argument '{key}'")
            rest = {k: v for k, v in rest.items() if k not in accepted}

    checker: Validator = validate
    # on any class exposed under a real name (exceptions too); place.Located calls it
    setattr(cls, "_pkgforge_check", staticmethod(checker))  # noqa: B010


# --- stand-ins for what is not evaluated ----------------------------------------------------


def _bases(entry: Entry) -> tuple[type, ...]:
    out: list[type] = []
    for base in entry.get("bases", []):
        builtin = getattr(builtins, base, None)
        if isinstance(builtin, type):
            out.append(builtin)
            continue
        try:
            value = resolve(base)
        except (LookupError, ImportError, AttributeError):
            continue
        if isinstance(value, type) and value not in out:
            out.append(value)
    return tuple(out)


def _stand_in_class(canonical: str, entry: Entry) -> type:
    name = canonical.rsplit(".", 1)[-1]
    bases = _bases(entry) or (place.Located,)
    if any(issubclass(b, BaseException) for b in bases):
        return type(name, bases, {"__module__": canonical.rsplit(".", 1)[0]})
    if not any(issubclass(b, place.Located) for b in bases):
        bases = bases + (place.Located,)
    try:
        cls = unsupported_names.unsupported(name, bases)
    except TypeError:  # an impossible MRO of stand-ins: the plainest stand-in will do
        cls = unsupported_names.unsupported(
            name, (action.Action,) if "Action" in str(entry.get("bases")) else (substitution.Substitution,)
        )
    cls.__module__ = canonical.rsplit(".", 1)[0]
    _enforce_signature(cls, canonical, entry)
    return cls


def _inert_class(canonical: str, entry: Entry) -> type:
    """An event (Shutdown, ChangeState…): built to be emitted at run time, nothing to check."""
    name = canonical.rsplit(".", 1)[-1]
    cls = type(name, (event_handlers.InertEvent,), {"__module__": canonical.rsplit(".", 1)[0]})
    _enforce_signature(cls, canonical, entry)
    return cls


def _stand_in_function(canonical: str, entry: Entry) -> Callable[..., None]:
    name = canonical.rsplit(".", 1)[-1]
    check = _checker(name, entry["signature"])

    def stand_in(*args: Any, **kwargs: Any) -> None:  # whatever the launch file passes
        check(*args, **kwargs)
        file, line = place.here()
        launch_context.RECORDER.add("unsupported", {"name": name, "file": file, "line": line})
        return None

    stand_in.__name__ = stand_in.__qualname__ = name
    stand_in.__module__ = canonical.rsplit(".", 1)[0]
    return stand_in


# --- the import hook ------------------------------------------------------------------------


class _Loader(importlib.abc.Loader):
    def create_module(self, spec: ModuleSpec) -> types.ModuleType | None:
        return None

    def exec_module(self, module: types.ModuleType) -> None:
        name = module.__name__
        info = modules()[name]
        module.__file__ = f"<pkgforge launch API ({distro()})>/{name.replace('.', '/')}.py"

        def __getattr__(attribute: str) -> Any:
            # names are resolved when first used (PEP 562): importing launch stays cheap
            if attribute in info["names"]:
                try:
                    value = resolve(f"{name}.{attribute}")
                except (ImportError, LookupError) as error:
                    raise AttributeError(f"module {name!r} has no attribute {attribute!r}") from error
                setattr(module, attribute, value)
                return value
            raise AttributeError(f"module {name!r} has no attribute {attribute!r}")

        def __dir__() -> list[str]:
            return sorted(set(module.__dict__) | set(info["names"]))

        # PEP 562 module hooks and __all__: a module's attributes, set by name
        module.__dict__.update(__getattr__=__getattr__, __dir__=__dir__)
        exported = info.get("all")
        if exported is not None:
            module.__dict__["__all__"] = list(exported)
        for imported in info["imports"]:  # what the real module imports: the same submodules exist
            importlib.import_module(imported)


class _Finder(importlib.abc.MetaPathFinder):
    loader = _Loader()

    def find_spec(
        self, fullname: str, path: Sequence[str] | None = None, target: types.ModuleType | None = None
    ) -> ModuleSpec | None:
        if fullname.split(".")[0] not in TOP:
            return None
        info = modules().get(fullname)
        if info is None:
            return None  # not a module of this distro: ModuleNotFoundError, as in ROS
        return importlib.util.spec_from_loader(fullname, self.loader, is_package=info["package"])


def install() -> None:
    """Serve launch, launch_ros, launch_xml and launch_yaml from the list (first on sys.meta_path)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.insert(0, _Finder())
