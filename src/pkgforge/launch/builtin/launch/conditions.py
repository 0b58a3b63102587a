"""launch.conditions: If/UnlessCondition, LaunchConfiguration(Not)Equals and the expressions they accept.

Real: launch/condition.py, launch/conditions/*.py (true/1, false/0, nothing else).
"""

from __future__ import annotations

from collections.abc import Callable

from pkgforge.launch.builtin.launch.errors import SubstitutionFailure
from pkgforge.launch.builtin.launch.launch_context import LaunchContext
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType, perform
from pkgforge.launch.place import Located


class InvalidConditionExpressionError(SubstitutionFailure):
    def __init__(
        self,
        expression: str,
        expression_substitutions: object = None,
        valid_expressions: list[str] | None = None,
    ) -> None:
        valid = valid_expressions or VALID_TRUE_EXPRESSIONS + VALID_FALSE_EXPRESSIONS
        super().__init__(f"Unexpected condition expression '{expression}', expected one of: {valid}")


def _truth(text: str) -> bool:
    """A condition's expression (evaluate_condition_expression): true/1, false/0, nothing else."""
    lowered = text.strip().lower()
    if lowered in VALID_TRUE_EXPRESSIONS:
        return True
    if lowered in VALID_FALSE_EXPRESSIONS:
        return False
    raise InvalidConditionExpressionError(lowered)


VALID_TRUE_EXPRESSIONS = ["true", "1"]
VALID_FALSE_EXPRESSIONS = ["false", "0"]


class Condition(Located):
    def __init__(self, *, predicate: Callable[[LaunchContext], bool] | None = None) -> None:
        super().__init__()
        self.predicate = predicate

    def evaluate(self, context: LaunchContext) -> bool:
        return bool(self.predicate(context)) if self.predicate else True


class IfCondition(Condition):
    def __init__(self, predicate_expression: SomeSubstitutionsType) -> None:
        super().__init__()
        self.expression = predicate_expression

    def evaluate(self, context: LaunchContext) -> bool:
        return _truth(perform(context, self.expression))


class UnlessCondition(IfCondition):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


class LaunchConfigurationEquals(Condition):
    def __init__(self, launch_configuration_name: str, expected_value: SomeSubstitutionsType | None) -> None:
        super().__init__()
        self.name, self.expected = launch_configuration_name, expected_value

    def evaluate(self, context: LaunchContext) -> bool:
        value = context.launch_configurations.get(self.name)
        expected = None if self.expected is None else perform(context, self.expected)
        return value == expected


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


def evaluate_condition_expression(context: LaunchContext, expression: SomeSubstitutionsType) -> bool:
    return _truth(perform(context, expression))
