"""launch_ros.actions that set what the nodes after them get: a namespace, parameters, remappings.

Real: launch_ros/actions/push_ros_namespace.py, set_parameter.py, set_remap.py,
set_parameters_from_file.py, ros_timer.py, set_use_sim_time.py.
"""

from __future__ import annotations

import re
import typing
from typing import Any

from pkgforge.launch.builtin.launch.action import Action
from pkgforge.launch.builtin.launch.actions import TimerAction
from pkgforge.launch.builtin.launch.errors import SubstitutionFailure
from pkgforge.launch.builtin.launch.launch_context import LaunchContext, record_path
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    normalize,
    perform,
    perform_substitutions,
)
from pkgforge.launch.builtin.launch_ros.namespaces import make_namespace_absolute, prefix_namespace
from pkgforge.launch.builtin.launch_ros.parameter_descriptions import (
    _check_parameter_value,
    _has_substitution,
    _perform_value,
)
from pkgforge.launch.builtin.unsupported import unsupported


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
        record_path(path, self, "SetParametersFromFile")
        context.launch_configurations.setdefault("global_params", []).append(path)


class RosTimerAction(TimerAction):
    pass


# launch_ros sets use_sim_time on the launch's own ROS node (a running rclpy node), not on
# the nodes it starts: nothing verify can do or check (the real engine records it the same way)
SetUseSimTime = unsupported("SetUseSimTime")
