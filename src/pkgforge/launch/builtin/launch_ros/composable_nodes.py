"""launch_ros's composable nodes: ComposableNode, ComposableNodeContainer, LoadComposableNodes.

Real: launch_ros/descriptions/composable_node.py, launch_ros/actions/composable_node_container.py,
load_composable_nodes.py.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from pkgforge.launch.builtin.launch.action import Action
from pkgforge.launch.builtin.launch.conditions import Condition
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType, perform
from pkgforge.launch.builtin.launch_ros.node import Node, Remapping
from pkgforge.launch.builtin.launch_ros.parameter_descriptions import ParameterGroup, _evaluate_parameters
from pkgforge.launch.place import Located


class ComposableNode(Located):
    def __init__(
        self,
        *,
        package: SomeSubstitutionsType,
        plugin: SomeSubstitutionsType,
        name: SomeSubstitutionsType | None = None,
        namespace: SomeSubstitutionsType | None = None,
        parameters: Sequence[ParameterGroup] | None = None,
        remappings: Iterable[Remapping] | None = None,
        extra_arguments: Sequence[ParameterGroup] | None = None,
        condition: Condition | None = None,
    ) -> None:
        super().__init__()
        self.package, self.plugin = package, plugin
        self.parameters = list(parameters or [])
        self.condition = condition


class ComposableNodeContainer(Node):
    def __init__(
        self,
        *,
        name: SomeSubstitutionsType,
        namespace: SomeSubstitutionsType,
        composable_node_descriptions: Iterable[ComposableNode] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(name=name, namespace=namespace, **kwargs)
        self.descriptions = list(composable_node_descriptions or [])

    def visit(self, context: LaunchContext) -> None:
        super().visit(context)
        for description in self.descriptions:
            if description.condition is None or description.condition.evaluate(context):
                package = perform(context, description.package)
                RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)
                for group in description.parameters:
                    _evaluate_parameters(context, group, description)


class LoadComposableNodes(Action):
    def __init__(
        self,
        *,
        composable_node_descriptions: Iterable[ComposableNode],
        target_container: SomeSubstitutionsType | ComposableNodeContainer | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.descriptions = list(composable_node_descriptions)

    def visit(self, context: LaunchContext) -> None:
        for description in self.descriptions:
            package = perform(context, description.package)
            RECORDER.add("packages", {"name": package, "via": "ComposableNode"}, description)
