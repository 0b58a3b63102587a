"""launch.utilities that launch files use themselves: type checks, FilePath, the logger.

Real: launch/utilities/*.py, launch/logging.
"""

from __future__ import annotations

import logging
import os
import typing
from collections.abc import Sequence

FilePath = typing.Union[str, "os.PathLike[str]"]


def isclassinstance(obj: object) -> bool:
    return hasattr(obj, "__class__")


def is_a(obj: object, entity_type: type) -> bool:
    return isclassinstance(obj) and issubclass(obj.__class__, entity_type)


def is_a_subclass(obj: object, entity_type: type) -> bool:
    return is_a(obj, entity_type) or (isinstance(obj, type) and issubclass(obj, entity_type))


def ensure_argument_type(
    argument: object, types: type | Sequence[type], argument_name: str, caller: str | None = None
) -> None:
    """launch.utilities.ensure_argument_type: a TypeError naming the argument."""
    kinds: Sequence[type] = types if isinstance(types, (list, tuple)) else [typing.cast(type, types)]
    if not any(
        isinstance(argument, t)
        or (isinstance(argument, type) and isinstance(t, type) and issubclass(argument, t))
        for t in kinds
    ):
        expected = ", ".join(f"'{t}'" for t in kinds)
        prefix = f"{caller}: " if caller else ""
        raise TypeError(
            f"{prefix}Expected '{argument_name}' to be one of [{expected}], "
            f"but got '{argument}' of type '{type(argument)}'"
        )


def get_logger(name: str | None = None) -> logging.Logger:
    return logging.getLogger("launch" if name is None else name)
