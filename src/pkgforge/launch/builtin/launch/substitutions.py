"""launch.substitutions but Command: configurations, paths, environment, expressions, booleans, files.

Real: launch/substitutions/*.py (Command is command.py here: it runs programs).
"""

from __future__ import annotations

import collections.abc
import os
from collections.abc import Iterable
from typing import Any

from pkgforge.launch.builtin.distro import distro
from pkgforge.launch.builtin.launch.errors import (
    FAILURE_PROGRAM,
    FAILURE_VARIABLE,
    MissingConfiguration,
    SubstitutionFailure,
    Unresolved,
    marked,
)
from pkgforge.launch.builtin.launch.launch_context import (
    MISSING_PACKAGE_ROOT,
    RECORDER,
    LaunchContext,
    record_path,
)
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    Substitution,
    _plain_text,
    _stringify_default,
    normalize,
    perform,
    perform_substitutions,
)
from pkgforge.launch.builtin.launch.utilities import ensure_argument_type


class LaunchConfiguration(Substitution):
    def __init__(self, variable_name: SomeSubstitutionsType, *, default: object = None) -> None:
        super().__init__()
        self.variable_name = normalize(variable_name)
        self.default = None if default is None else _stringify_default(default)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.variable_name)
        if name in context.launch_configurations:
            value: str = context.launch_configurations[name]
            return value
        if self.default is not None:
            return perform(context, self.default)
        raise MissingConfiguration(name, (self._file, self._line))


class PathJoinSubstitution(Substitution):
    def __init__(self, substitutions: Iterable[SomeSubstitutionsType]) -> None:
        super().__init__()
        self.substitutions = list(substitutions)

    def perform(self, context: LaunchContext) -> str:
        parts = [perform(context, part) for part in self.substitutions]
        result = os.path.join(*parts) if parts else ""
        record_path(result, self, "PathJoinSubstitution")
        return result


class EnvironmentVariable(Substitution):
    def __init__(
        self, name: SomeSubstitutionsType, *, default_value: SomeSubstitutionsType | None = None
    ) -> None:
        super().__init__()
        self.name = name
        self.default_value = default_value

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        value = context.environment.get(name)
        if value is None:
            if self.default_value is None:
                failure = SubstitutionFailure(f"environment variable '{name}' does not exist")
                raise marked(failure, FAILURE_VARIABLE, name)
            return perform(context, self.default_value)
        return value


class FindExecutable(Substitution):
    def __init__(self, *, name: SomeSubstitutionsType) -> None:
        super().__init__()
        self.name = name

    def perform(self, context: LaunchContext) -> str:
        import shutil

        name = perform(context, self.name)
        found = shutil.which(name)
        if name == "xacro":
            RECORDER.add("packages", {"name": "xacro", "via": "FindExecutable"}, self)
        if found is None:
            failure = SubstitutionFailure(f"executable '{name}' not found on the PATH")
            raise marked(failure, FAILURE_PROGRAM, name)
        return found


class PythonExpression(Substitution):
    def __init__(
        self,
        expression: SomeSubstitutionsType,
        python_modules: SomeSubstitutionsType = ["math"],  # noqa: B006 - launch's default
    ) -> None:
        super().__init__()
        ensure_argument_type(
            expression, (str, Substitution, collections.abc.Iterable), "expression", "PythonExpression"
        )
        ensure_argument_type(
            python_modules,
            (str, Substitution, collections.abc.Iterable),
            "python_modules",
            "PythonExpression",
        )
        self.expression = normalize(expression)
        self.python_modules = normalize(python_modules)

    def perform(self, context: LaunchContext) -> str:
        import importlib

        names: dict[str, Any] = {}  # what the expression may name: modules and math's functions
        for sub in self.python_modules:
            module = importlib.import_module(context.perform_substitution(sub))
            if module.__name__ == "math":
                names.update(vars(module))
            names[module.__name__] = module
        return str(eval(perform_substitutions(context, self.expression), {}, names))


class ThisLaunchFileDir(Substitution):
    def perform(self, context: LaunchContext) -> str:
        return os.path.dirname(context.current_file or "")


class ThisLaunchFile(Substitution):
    def perform(self, context: LaunchContext) -> str:
        return context.current_file or ""


class AnonName(Substitution):
    def __init__(self, name: SomeSubstitutionsType) -> None:
        super().__init__()
        self.name = name

    def perform(self, context: LaunchContext) -> str:
        return f"{perform(context, self.name)}_{os.getpid()}"


class LocalSubstitution(Substitution):
    def __init__(self, expression: str, description: str | None = None) -> None:
        super().__init__()
        self.expression = expression

    def perform(self, context: LaunchContext) -> str:
        # the value as it is, as launch returns it (an int such as event.returncode fails where
        # the substitutions are joined, as in ROS)
        value: str = eval(self.expression, {}, context.get_locals_as_dict())
        return value


def _typed_bool(context: LaunchContext, subs: Iterable[Substitution]) -> bool:
    """perform_typed_substitution(..., bool): '1'/'0', else YAML's booleans (yes, on, True…)."""
    import yaml

    text = perform_substitutions(context, subs)
    # '1'/'0' are booleans from Iron on; humble's launch reads them as YAML integers (refused)
    value = text if distro() == "humble" else {"1": "true", "0": "false"}.get(text, text)
    try:
        output = yaml.safe_load(value) if value else value
    except yaml.YAMLError as error:
        raise SubstitutionFailure(  # noqa: B904 - launch raises it inside the except, with the YAML error as context
            f"Failed to convert '{value}' to '{bool}': yaml.safe_load() failed\n{error}"
        )
    if isinstance(output, bool):
        return output
    raise SubstitutionFailure(f"Cannot convert value '{value}' to '{bool}'")


class NotSubstitution(Substitution):
    def __init__(self, value: SomeSubstitutionsType) -> None:
        super().__init__()
        self.value = normalize(value)

    def perform(self, context: LaunchContext) -> str:
        return str(not _typed_bool(context, self.value)).lower()


class AndSubstitution(Substitution):
    def __init__(self, left: SomeSubstitutionsType, right: SomeSubstitutionsType) -> None:
        super().__init__()
        self.left, self.right = normalize(left), normalize(right)

    def perform(self, context: LaunchContext) -> str:
        left, right = _typed_bool(context, self.left), _typed_bool(context, self.right)
        return str(left and right).lower()


class OrSubstitution(AndSubstitution):
    def perform(self, context: LaunchContext) -> str:
        left, right = _typed_bool(context, self.left), _typed_bool(context, self.right)
        return str(left or right).lower()


class AllSubstitution(Substitution):
    def __init__(self, *args: SomeSubstitutionsType) -> None:
        super().__init__()
        self.args = [normalize(a) for a in args]

    def perform(self, context: LaunchContext) -> str:
        return str(all([_typed_bool(context, a) for a in self.args])).lower()


class AnySubstitution(AllSubstitution):
    def perform(self, context: LaunchContext) -> str:
        return str(any([_typed_bool(context, a) for a in self.args])).lower()


def _str_is_bool(text: str) -> bool:
    return isinstance(text, str) and text.lower() in ("true", "false", "1", "0")


def _str_is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


class EqualsSubstitution(Substitution):
    """Typed as in launch: booleans compare as booleans (True equals 1), numbers as numbers
    (1 equals 1.0), anything else as text."""

    def __init__(self, left: object, right: object) -> None:  # any value: see _plain_text
        super().__init__()
        self.left, self.right = normalize(_plain_text(left)), normalize(_plain_text(right))

    def _equal(self, context: LaunchContext) -> bool:
        import math

        left = perform_substitutions(context, self.left)
        right = perform_substitutions(context, self.right)
        if _str_is_bool(left) and _str_is_bool(right):
            return (left.lower() in ("true", "1")) == (right.lower() in ("true", "1"))
        if _str_is_float(left) and _str_is_float(right):
            return math.isclose(float(left), float(right))
        return left == right

    def perform(self, context: LaunchContext) -> str:
        return str(self._equal(context)).lower()


class NotEqualsSubstitution(EqualsSubstitution):
    def perform(self, context: LaunchContext) -> str:
        return str(not self._equal(context)).lower()


class IfElseSubstitution(Substitution):
    def __init__(
        self,
        condition: SomeSubstitutionsType,
        if_value: SomeSubstitutionsType = "",
        else_value: SomeSubstitutionsType = "",
    ) -> None:
        super().__init__()
        if if_value == else_value == "":
            raise RuntimeError("One of if_value and else_value must be specified")
        self.condition = normalize(condition)
        self.if_value, self.else_value = normalize(if_value), normalize(else_value)

    def perform(self, context: LaunchContext) -> str:
        chosen = self.if_value if _typed_bool(context, self.condition) else self.else_value
        return perform_substitutions(context, chosen)


class FileContent(Substitution):
    def __init__(self, path: SomeSubstitutionsType) -> None:
        super().__init__()
        self.path = normalize(path)

    def perform(self, context: LaunchContext) -> str:
        path = perform_substitutions(context, self.path)
        record_path(path, self, "FileContent")
        if path.startswith(MISSING_PACKAGE_ROOT):
            raise Unresolved(f"<a file of a package not found: {path}>")
        try:
            with open(path, encoding="utf-8") as handle:
                return handle.read()
        except FileNotFoundError:
            raise SubstitutionFailure(f"File not found: {path}") from None
