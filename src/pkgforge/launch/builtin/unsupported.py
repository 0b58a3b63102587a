"""A real launch API name pkgforge records instead of evaluating (api.py and the front end make them)."""

from __future__ import annotations

from typing import Any

from pkgforge.launch.builtin.launch.action import Action
from pkgforge.launch.builtin.launch.errors import Unresolved
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.substitution import Substitution
from pkgforge.launch.place import Located


def unsupported(name: str, bases: type | tuple[type, ...] = Action) -> type:
    """A real launch API name pkgforge records instead of evaluating: an action that does
    nothing, a substitution whose value is unknown (what uses it is skipped). Recorded where the
    real engine records it: an action when visited (its condition taken, in each evaluated
    branch), a substitution when performed, anything else when made."""
    bases = bases if isinstance(bases, tuple) else (bases,)
    visited = any(issubclass(b, (Action, Substitution)) for b in bases)

    # self: an instance of the class made below (its bases vary); the arguments: the real
    # constructor's (checked by api.py), only `condition` is read
    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        Located.__init__(self)
        self.condition = kwargs.get("condition")
        if not visited:
            RECORDER.add("unsupported", {"name": name}, self)

    def visit(self: Located, context: LaunchContext) -> None:
        RECORDER.add("unsupported", {"name": name}, self)

    def perform(self: Located, context: LaunchContext) -> str:
        RECORDER.add("unsupported", {"name": name}, self)
        raise Unresolved(f"<{name}>")

    return type(name, bases, {"__init__": __init__, "visit": visit, "perform": perform})
