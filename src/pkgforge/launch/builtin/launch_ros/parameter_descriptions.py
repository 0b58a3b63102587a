"""launch_ros.parameter_descriptions: a node's parameters evaluated and checked as launch_ros does.

Real: launch_ros/parameter_descriptions.py, launch_ros/utilities/evaluate_parameters.py,
to_parameters_list.py.
"""

from __future__ import annotations

import collections.abc
import os
import typing
from collections.abc import Mapping, Sequence
from typing import Any, TypeGuard

from pkgforge.launch.builtin.distro import distro
from pkgforge.launch.builtin.launch.command import Command
from pkgforge.launch.builtin.launch.errors import SubstitutionFailure
from pkgforge.launch.builtin.launch.frontend_reader import reader
from pkgforge.launch.builtin.launch.launch_context import LaunchContext, record_path
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    Substitution,
    normalize,
    perform,
    perform_substitutions,
)
from pkgforge.launch.builtin.launch.substitutions import _typed_bool
from pkgforge.launch.place import FRONTEND_LOCATION, Located
from pkgforge.launch.records import PREVIEW_LENGTH, ParameterForm, ParameterRecordDict

# one item of a node's `parameters`: a dict of name → value (keys str or substitutions, values
# any YAML value or substitutions: the launch file's own data), a Parameter, or a parameter file
ParameterGroup = typing.Union[  # noqa: UP007
    Mapping[Any, Any], "Parameter", "ParameterFile", "SomeSubstitutionsType", "os.PathLike[str]"
]


class ParameterValue(Located):
    # value: any YAML value or substitutions; value_type: a type or typing construct (List[str])
    def __init__(self, value: object, *, value_type: object = None) -> None:
        super().__init__()
        self.value, self.value_type = value, value_type


class ParameterFile(Located):
    def __init__(
        self,
        param_file: SomeSubstitutionsType | os.PathLike[str],
        *,
        allow_substs: bool | SomeSubstitutionsType = False,
    ) -> None:
        super().__init__()
        self.param_file = param_file
        self.allow_substs = allow_substs


def _allowed_parameter_files(context: LaunchContext, groups: Sequence[ParameterGroup]) -> None:
    """launch_ros's ParameterFile.evaluate with allow_substs: the file's text is read, its
    substitutions ($(var x)...) performed and the result read as YAML; what fails stops the
    node (a configuration it names that is not set: at the ParameterFile's line)."""
    import yaml

    parse_substitution = reader().parse_substitution
    for group in groups:
        if not isinstance(group, ParameterFile):
            continue
        allowed = group.allow_substs
        if not isinstance(allowed, bool):
            allowed = _typed_bool(context, normalize(allowed))
        if not allowed:
            continue
        source = group.param_file
        path = os.fspath(source) if isinstance(source, os.PathLike) else perform(context, source)
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
        FRONTEND_LOCATION.append((group._file, group._line))  # its substitutions stand there
        try:
            parsed = parse_substitution(text)
        finally:
            FRONTEND_LOCATION.pop()
        substituted = perform_substitutions(context, parsed)
        try:
            yaml.safe_load(substituted)
        except Exception:  # noqa: BLE001 - launch_ros's own rule: whatever yaml raises
            raise SubstitutionFailure("The substituted parameter file is not a valid yaml file") from None


class Parameter(Located):
    def __init__(self, name: SomeSubstitutionsType, value: object, *, value_type: object = None) -> None:
        super().__init__()
        self.name, self.value = name, value


def _flatten(
    group: Mapping[Any, Any], prefix: str | None, context: LaunchContext
) -> list[tuple[str, object]]:
    """A parameter dict, nested dicts joined with '.' (normalize_parameter_dict)."""
    out: list[tuple[str, object]] = []
    for key, value in group.items():
        name = perform(context, key) if not isinstance(key, str) else key
        if prefix:
            name = f"{prefix}.{name}"
        if isinstance(value, collections.abc.Mapping):
            out.extend(_flatten(value, name, context))
        else:
            out.append((name, value))
    return out


def _evaluate_parameters(
    context: LaunchContext, group: ParameterGroup, node: Located
) -> list[ParameterRecordDict]:
    """Node parameters: dicts of name → value, or parameter files; with how each was given."""
    out: list[ParameterRecordDict] = []
    if isinstance(group, collections.abc.Mapping):
        for name, value in _flatten(group, None, context):
            given = _value_form(value)
            text = _perform_value(context, value)
            out.append(
                {
                    "name": name,
                    "form": given,
                    "value_preview": str(text)[:PREVIEW_LENGTH],
                    "file": node._file,
                    "line": getattr(value, "_line", None) or node._line,
                }
            )
            if isinstance(text, str):
                record_path(text, node, "parameter")
    elif isinstance(group, Parameter):
        text = _perform_value(context, group.value)
        out.append(
            {
                "name": perform(context, group.name),
                "form": _value_form(group.value),
                "value_preview": str(text)[:PREVIEW_LENGTH],
                "file": node._file,
                "line": node._line,
            }
        )
    else:
        source = group.param_file if isinstance(group, ParameterFile) else group
        path = perform(context, source) if not isinstance(source, (os.PathLike,)) else os.fspath(source)
        record_path(path, node, "parameter file")
        out.append(
            {"name": None, "form": "file", "value_preview": path, "file": node._file, "line": node._line}
        )
    return out


def _check_parameter_value(context: LaunchContext, name: str, value: object) -> None:
    """launch_ros's typing of a parameter given as substitutions: the text is read as YAML and
    must give a scalar or a uniform list; otherwise the node does not start (the same error)."""
    import yaml

    if isinstance(value, ParameterValue):
        if value.value_type is not None or not _is_substitutions(value.value):
            return
        text = perform(context, value.value)
        if not text:
            return
        described = f"Failed to convert '{text}' using yaml rules"
        try:
            output = yaml.safe_load(text)
        except Exception as error:  # noqa: BLE001 - launch's own rule
            raise ValueError(f"{described}: yaml.safe_load() failed\n{error}") from None
        if not _allowed_value(output):
            raise ValueError(f"{described}: output type is not allowed, got {type(output)}")
        return
    if not _is_substitutions(value) or not _has_substitution(value):
        return
    text = perform(context, value) or "''"
    wrap = (
        "If the parameter is meant to be a string, try wrapping it in "
        "launch_ros.parameter_descriptions.ParameterValue(value, value_type=str)"
    )
    try:
        output = yaml.safe_load(text)
    except yaml.YAMLError:
        raise TypeError(f"Unable to parse the value of parameter {name} as yaml. {wrap}") from None
    if type(output) in (bool, int, float, str, bytes):
        return
    jazzy = distro() != "humble"
    if isinstance(output, collections.abc.Sequence):
        if not _uniform(output):
            raise TypeError(
                "Expected a non-empty sequence, with items of uniform type. Allowed sequence "
                "item types are bool, int, float, str."
                + (f' Got inconsistent input for "{name}"' if jazzy else "")
            )
        return
    got = f'{type(output)} for "{name}". ' if jazzy else f"{type(output)}."
    raise TypeError(
        "Allowed value types are bytes, bool, int, float, str, Sequence[bool], Sequence[int], "
        f"Sequence[float], Sequence[str]. Got {got}{wrap}"
    )


def _is_substitutions(value: object) -> TypeGuard[SomeSubstitutionsType]:
    if isinstance(value, (str, Substitution)):
        return True
    return (
        isinstance(value, (list, tuple))
        and bool(value)
        and all(isinstance(v, (str, Substitution)) for v in value)
    )


def _has_substitution(value: object) -> bool:
    if isinstance(value, Substitution):
        return True
    return isinstance(value, (list, tuple)) and any(isinstance(v, Substitution) for v in value)


def _uniform(sequence: Sequence[object]) -> bool:
    if not sequence or type(sequence[0]) not in (bool, int, float, str):
        return False
    return all(isinstance(item, type(sequence[0])) for item in sequence)


def _allowed_value(output: object) -> bool:
    """launch.utilities.type_utils: a scalar, or a list of one scalar type."""
    if not isinstance(output, list):
        return isinstance(output, (int, float, bool, str))
    member = next((type(x) for x in output if type(x) is not str), str)
    return member in (int, float, bool, str) and all(isinstance(x, member) for x in output)


def _value_form(value: object) -> ParameterForm:
    if isinstance(value, ParameterValue):
        typed = value.value_type is str
        return "typed-str" if typed else ("command-untyped" if _has_command(value.value) else "typed")
    if _has_command(value):
        return "command-untyped"
    return "plain"


def _has_command(value: object) -> bool:
    if isinstance(value, Command):
        return True
    if isinstance(value, (list, tuple)):
        return any(isinstance(v, Command) for v in value)
    return False


def _perform_value(context: LaunchContext, value: object) -> object:
    """A parameter's value as launch_ros evaluates it: a list with a Substitution among strs is
    one string (joined); a list of strs stays a list; a list of lists is a list of strings."""
    if isinstance(value, ParameterValue):
        value = value.value
    if isinstance(value, (str, Substitution)):
        return perform(context, value)
    if isinstance(value, (list, tuple)) and value:
        kinds = {type(v) for v in value}
        if any(isinstance(v, Substitution) for v in value) and all(
            isinstance(v, (str, Substitution)) for v in value
        ):
            return perform(context, list(value))
        if all(isinstance(v, (str, Substitution, list, tuple)) for v in value) and kinds - {str}:
            return [perform(context, v) for v in value]
    return value
