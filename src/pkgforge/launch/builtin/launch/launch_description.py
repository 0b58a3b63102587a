"""launch.LaunchDescription: the entities a launch file returns, and the arguments it declares."""

from __future__ import annotations

from collections.abc import Iterable

from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity
from pkgforge.launch.builtin.launch.actions import DeclareLaunchArgument
from pkgforge.launch.builtin.launch.launch_context import LaunchContext


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
