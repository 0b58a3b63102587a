"""launch.actions.IncludeLaunchDescription: another launch file followed, with its arguments.

Real: launch/actions/include_launch_description.py.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from typing import Any

from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext, record_path
from pkgforge.launch.builtin.launch.launch_description_sources import (
    AnyLaunchDescriptionSource,
    LaunchDescriptionSource,
    load_description,
)
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType, perform


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
        record_path(path, self, "IncludeLaunchDescription")
        if not exists or _phantom(path):
            RECORDER.unfollowed.append(path)
            return None
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
