"""launch.actions that set things when visited: arguments, configurations, groups, environment, timers...

Real: launch/actions/*.py, but for ExecuteProcess (execute_process.py here) and
IncludeLaunchDescription (include_launch_description.py).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.errors import Unresolved
from pkgforge.launch.builtin.launch.event_handlers import BaseEventHandler
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    Substitution,
    normalize,
    perform,
    perform_substitutions,
)
from pkgforge.launch.builtin.launch.substitutions import _typed_bool


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
        # what its execute performs; its actions run when the period has passed (deferred.defer)
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


class Shutdown(Action):
    pass


class EmitEvent(Action):
    def __init__(self, *, event: object = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
