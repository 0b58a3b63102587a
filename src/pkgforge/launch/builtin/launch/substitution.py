"""launch.Substitution and TextSubstitution, and how substitutions are normalized, performed and joined.

Real: launch/substitution.py, launch/substitutions/text_substitution.py,
launch/some_substitutions_type.py, launch/utilities/normalize_to_list_of_substitutions_impl.py
and perform_substitutions_impl.py.
"""

from __future__ import annotations

import collections.abc
import os
import typing
from collections.abc import Callable, Iterable
from typing import TypeGuard, TypeVar

from pkgforge.launch.builtin.launch.launch_context import MISSING_PACKAGE_ROOT, RECORDER, LaunchContext
from pkgforge.launch.place import Located


class Substitution(Located):
    def perform(self, context: LaunchContext) -> str:  # pragma: no cover - overridden
        raise NotImplementedError

    def describe(self) -> str:
        return type(self).__name__


def normalize(subs: SomeSubstitutionsType) -> list[Substitution]:
    """launch.utilities.normalize_to_list_of_substitutions: str | Substitution | iterable of
    those → list of Substitutions; anything else raises the TypeError ROS raises (iterating
    a bool or an int fails, an item of another type is refused)."""
    if isinstance(subs, str):
        return [TextSubstitution(text=subs)]
    if isinstance(subs, Substitution):
        return [subs]
    out: list[Substitution] = []
    for item in subs:
        if isinstance(item, Substitution):
            out.append(item)
        elif isinstance(item, str):
            out.append(TextSubstitution(text=item))
        else:
            raise TypeError(
                f"Failed to normalize given item of type '{type(item)}', when only "
                "'str' or 'launch.Substitution' were expected."
            )
    return out


def perform(context: LaunchContext, value: SomeSubstitutionsType | None) -> str:
    """Concatenate the performed substitutions (None → ''): pkgforge's own shorthand."""
    if value is None:
        return ""
    return joined(normalize(value), lambda s: s.perform(context))


def perform_substitutions(context: LaunchContext, subs: Iterable[Substitution]) -> str:
    """launch.utilities.perform_substitutions (a list of Substitutions)."""
    return joined(subs, context.perform_substitution)


_Part = TypeVar("_Part")
# what goes on naming one file: a path performed right before one of these is only the start of
# the name the list builds (`[PathJoinSubstitution([share, 'xacro', model]), '.urdf.xacro']`)
_NAME_CHARACTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-/")
JOINED_VIA = "PathJoinSubstitution and the text joined to it"


def joined(parts: Iterable[_Part], perform_one: Callable[[_Part], str]) -> str:
    """A list of substitutions performed and concatenated, as launch does it (both engines: the
    real engine's perform_substitutions calls this too). A path a PathJoinSubstitution recorded
    that is only part of one name in the result (text goes on right after it, or comes right
    before it) names no file of its own: launch gives the whole name to whoever reads it (Command
    joins before it splits). Its record becomes that whole name when that is an absolute path
    (so a typo in the suffix is still a missing file), and is dropped when it is not."""
    texts: list[str] = []
    own: list[tuple[int, int]] = []  # (the part, its PathJoinSubstitution's record)
    complete = False
    try:
        for part in parts:
            mark = len(RECORDER.paths)
            text = perform_one(part)
            for k in range(len(RECORDER.paths) - 1, mark - 1, -1):
                record = RECORDER.paths[k]
                if record.path == text and record.via in ("PathJoinSubstitution", JOINED_VIA):
                    own.append((len(texts), k))
                    break
            texts.append(text)
        complete = True
    finally:  # a part that fails: the names the parts before it began are not known whole
        if own:
            _whole_names(texts, own, complete)
    return "".join(texts)


def _whole_names(texts: list[str], own: list[tuple[int, int]], complete: bool) -> None:
    """`joined`'s records of paths that are only part of a name: each that name, or dropped."""
    result = "".join(texts)
    gone: list[int] = []
    for index, k in own:
        start = sum(len(t) for t in texts[:index])
        end = start + len(texts[index])
        # text before it makes it the end of a name unless that is a separator, name:= or file://
        goes_on = start > 0 and result[start - 1] != "/" and result[start - 1] in _NAME_CHARACTERS
        # a separator after it, or nothing (when no part after it failed)
        ends = (end < len(result) and result[end] not in _NAME_CHARACTERS) or (
            end == len(result) and complete
        )
        if not goes_on and ends:
            continue  # the whole name
        while goes_on and start and result[start - 1] in _NAME_CHARACTERS:
            start -= 1
        own_end = end
        while end < len(result) and result[end] in _NAME_CHARACTERS:
            end += 1
        if set(result[own_end:end]) == {"."}:
            end = own_end  # a sentence's full stop or ellipsis ('Loading ', path, '.'): no part of a name
        if end == own_end and not goes_on and (end < len(result) or complete):
            continue  # only punctuation after it: the whole name
        name = result[start:end]
        if end == len(result) and not complete:
            gone.append(k)  # the part after it failed: where the name ends is not known
        elif os.path.isabs(name) and not name.startswith(MISSING_PACKAGE_ROOT):
            record = RECORDER.paths[k]
            record.path, record.via, record.exists = name, JOINED_VIA, os.path.exists(name)
        else:
            gone.append(k)
    for k in sorted(gone, reverse=True):
        del RECORDER.paths[k]


def _stringify_default(default: object) -> list[Substitution]:
    """LaunchConfiguration's default: items that are not str or Substitution become str()."""
    items = default if isinstance(default, collections.abc.Iterable) else (default,)
    return normalize([i if isinstance(i, (str, Substitution)) else str(i) for i in items])


def _substitution_items(value: object) -> TypeGuard[Iterable[str | Substitution]]:
    """strs and Substitutions, at least one Substitution (launch takes len() of any iterable)."""
    return (
        isinstance(value, collections.abc.Iterable)
        and not isinstance(value, str)
        and len(typing.cast(collections.abc.Sized, value)) > 0
        and all(isinstance(v, (str, Substitution)) for v in value)
        and any(isinstance(v, Substitution) for v in value)
    )


def _plain_text(value: object) -> SomeSubstitutionsType:
    """EqualsSubstitution's operand: None → '', a bool → 'true'/'false', else str()."""
    if isinstance(value, Substitution) or _substitution_items(value):
        return value
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(value).lower()
    return str(value)


class TextSubstitution(Substitution):
    def __init__(self, *, text: str = "") -> None:
        super().__init__()
        self.text = text

    def perform(self, context: LaunchContext) -> str:
        return self.text


# typing.Union, as launch.some_substitutions_type spells them (typing.get_args sees the same)
SomeSubstitutionsType = typing.Union[str, Substitution, typing.Iterable[str | Substitution]]  # noqa: UP007
SomeSubstitutionsType_types_tuple = (str, Substitution, collections.abc.Iterable)
