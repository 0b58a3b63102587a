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
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterable
from typing import Any

from pkgforge.build.toolchain import python_paths
from pkgforge.launch.branches import BranchBudget, evaluate_branches
from pkgforge.launch.builtin.launch.errors import (
    failure_text,
)
from pkgforge.launch.builtin.launch.event_handlers import HandledEvent, handler_event
from pkgforge.launch.builtin.launch.execute_process import PREPARING
from pkgforge.launch.builtin.launch.include_launch_description import include_arguments
from pkgforge.launch.builtin.launch.launch_context import RECORDER, record_path
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
from pkgforge.launch.place import LAUNCH_FILES
from pkgforge.launch.records import (
    PREVIEW_LENGTH,
    ErrorRecordDict,
    ExecutionRecordDict,
    LaunchResultDict,
    NodeRecordDict,
    ParameterForm,
    ParameterRecordDict,
    Status,
    as_dict,
)
from pkgforge.launch.ros_hooks import (
    L,
    fast_parameter_files,
    hook_loaders,
    hook_locations,
    hook_perform_substitutions,
    hook_substitutions,
    install_stand_ins,
    memoize_substitution_grammar,
    visiting,
    xml_with_lines,
    yaml_with_lines,
)
from pkgforge.launch.watch import watch_ament, watch_stand_in_reads, watch_xacro

# The distro's launch libraries are untyped: their objects (entities, contexts, substitutions,
# parser elements) are `Any` here, and so are the methods this module puts on their classes.

MAX_DEPTH = 32
# actions whose execution needs a running launch service or a ROS graph (SetUseSimTime sets a
# parameter of the launch's own rclpy node): recorded, not executed, as the built-in engine does
NOT_EVALUATED = {"OpaqueCoroutine", "LifecycleTransition", "UnregisterEventHandler", "SetUseSimTime"}
_SCRATCH: str | None = None


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
    L.stand_ins = install_stand_ins()
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
    launch_xml.parser.ET = xml_with_lines(ET)
    launch_yaml.parser.yaml = yaml_with_lines(yaml)
    L.launch, L.launch_ros = launch, launch_ros
    L.perform = hook_perform_substitutions(launch.utilities.perform_substitutions)
    L.normalize = launch.utilities.normalize_to_list_of_substitutions
    hook_locations()
    hook_loaders()
    hook_substitutions()
    memoize_substitution_grammar()
    fast_parameter_files(yaml)


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
    # SetParameter's global parameters and SetParametersFromFile's files, which launch_ros gives
    # every node in scope (a `-p` or a `--params-file` each)
    parameters: list[ParameterRecordDict] = [
        {
            "name": group[0],
            "form": "plain",
            "value_preview": str(group[1])[:PREVIEW_LENGTH],
            "file": node._file,
            "line": node._line,
        }
        if isinstance(group, tuple)
        else {
            "name": None,
            "form": "file",
            "value_preview": str(group),
            "file": node._file,
            "line": node._line,
        }
        for group in context.launch_configurations.get("global_params") or []
    ]
    parameters += _parameters(context, node._pkgforge_parameters, node)
    record: NodeRecordDict = {
        "kind": "node",
        "package": package,
        "executable": _text(context, node._Node__node_executable),
        "arguments": arguments,
        "ros_arguments": [_perform(context, a) for a in getattr(node, "_pkgforge_ros_arguments", [])],
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
        # (launch_ros keeps the file as _input_file, humble and jazzy alike)
        record_path(_text(context, action._input_file), action, "SetParametersFromFile")
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
            executed(entity)
            children = _handle(entity, context, depth)
        else:
            children = entity.visit(context)
    except Exception as error:  # noqa: BLE001 - every failure is a finding, none a crash
        if not (in_handler and type(entity).__name__ in RUNS_ON_THE_EVENT):
            record_visit_failure(entity, error, [*ancestors, (start, None)], list(loading))
        return
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
    (branches.BranchBudget): how long the argument combinations past the defaults may run."""
    path_before = list(sys.path)  # what the file adds is its own (as the built-in engine keeps it)
    try:
        return _evaluate(path, overrides, distro, budget)
    finally:
        sys.path[:] = path_before


def _evaluate(
    path: str, overrides: dict[str, str], distro: str | None, budget: BranchBudget | None
) -> LaunchResultDict:
    watch_xacro()
    # the launch file's own ament_index lookups, recorded (and a package not found here standing
    # in as an empty one) as the built-in engine does; launch_ros's own lookups are left alone
    watch_ament()
    watch_stand_in_reads()
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
                # (branches.evaluate_branches): not this branch's alone
                RECORDER.branch = {}
                description = _load(path)
            first = None
            RECORDER.branch = label
            visiting(context)
            try:
                declared_from = begin_visit()
                visit(description, context)

                def run_one(item: Deferred) -> None:
                    for entity in item.entities:
                        visit(entity, context, item.depth, item.in_handler, *item.spans)

                run_deferred(context, run_one)
                settle_unset_uses(declared_from)
            finally:
                visiting(None)
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
    cause = getattr(error, "orig_exc", None) if type(error).__name__ == "VisitError" else None
    refusal = _undecodable(path, error)
    if refusal is not None:
        error = refusal
    record = error_record(path, cause if isinstance(cause, Exception) else error, "load")
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
