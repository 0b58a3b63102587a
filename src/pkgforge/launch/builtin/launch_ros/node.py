"""launch_ros.actions.Node and LifecycleNode: a node recorded (package, executable, name...), not started.

Real: launch_ros/actions/node.py, lifecycle_node.py; rclpy's validate_node_name.
"""

from __future__ import annotations

import collections.abc
import re
from collections.abc import Iterable, Sequence
from typing import Any

from pkgforge.launch.builtin.launch.errors import failure_text
from pkgforge.launch.builtin.launch.execute_process import ExecuteProcess, execute_process
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext, record_path
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType, perform
from pkgforge.launch.builtin.launch_ros.namespaces import make_namespace_absolute, prefix_namespace
from pkgforge.launch.builtin.launch_ros.parameter_descriptions import (
    ParameterGroup,
    _allowed_parameter_files,
    _check_parameter_value,
    _evaluate_parameters,
    _flatten,
)
from pkgforge.launch.builtin.launch_ros.substitutions import ExecutableInPackage
from pkgforge.launch.records import PREVIEW_LENGTH, NodeRecordDict, ParameterRecordDict

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
            record_path(text, self, "Node arguments")
        namespace = perform(context, self.namespace) if self.namespace is not None else None
        namespace = make_namespace_absolute(
            prefix_namespace(context.launch_configurations.get("ros_namespace"), namespace)
        )
        parameters: list[ParameterRecordDict] = []
        for group in context.launch_configurations.get("global_params") or []:
            # SetParameter's (name, value), SetParametersFromFile's file: launch_ros gives each node
            # in scope every one (a `-p` or a `--params-file`)
            given: ParameterRecordDict = (
                {"name": group[0], "form": "plain", "value_preview": str(group[1])[:PREVIEW_LENGTH]}
                if isinstance(group, tuple)
                else {"name": None, "form": "file", "value_preview": str(group)}
            )
            parameters.append({**given, "file": self._file, "line": self._line})
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
            "ros_arguments": [perform(context, argument) for argument in self.ros_arguments],
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
