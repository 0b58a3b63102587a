"""launch.Action and LaunchDescriptionEntity: what a launch description holds, and how a list of them is made.

Real: launch/action.py, launch/launch_description_entity.py, launch/some_entities_type.py,
launch/utilities/normalize_to_list_of_entities_impl.py.
"""

from __future__ import annotations

import collections.abc
import typing
from collections.abc import Iterable
from typing import Any

from pkgforge.launch.builtin.launch.conditions import Condition
from pkgforge.launch.builtin.launch.launch_context import LaunchContext
from pkgforge.launch.place import Located


class LaunchDescriptionEntity(Located):
    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None

    def describe_sub_entities(self) -> list[LaunchDescriptionEntity]:
        return []


class Action(LaunchDescriptionEntity):
    # the other keyword arguments of launch's Action (and its subclasses'), not evaluated
    def __init__(self, *, condition: Condition | None = None, **_ignored: Any) -> None:
        super().__init__()
        self.condition = condition


SomeEntitiesType = typing.Union[LaunchDescriptionEntity, typing.Iterable[LaunchDescriptionEntity]]  # noqa: UP007
SomeEntitiesType_types_tuple = (LaunchDescriptionEntity, collections.abc.Iterable)


def normalize_to_list_of_entities(entities: Iterable[SomeEntitiesType]) -> list[LaunchDescriptionEntity]:
    out: list[Any] = []  # what the launch file gave; the visit skips what is not an entity
    for entity in entities:
        out.extend(entity if isinstance(entity, (list, tuple)) else [entity])
    return out
