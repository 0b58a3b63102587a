"""launch.LaunchContext, and the Recorder every built-in construct writes what it does to.

Real: launch/launch_context.py. RECORDER, MISSING_PACKAGE_ROOT and record_path are pkgforge's:
what one evaluation records, and where a package not found here stands in.
"""

from __future__ import annotations

import os
from typing import Any, Protocol

from pkgforge.launch.records import Recorder

# what one evaluation in this worker records: every construct adds to it (evaluate reads it out)
RECORDER = Recorder()


class Performed(Protocol):
    """A Substitution, as the context performs it (substitution.py builds on this module)."""

    def perform(self, context: LaunchContext) -> str: ...


class LaunchContext:
    def __init__(self, *, argv: list[str] | None = None, noninteractive: bool = False) -> None:
        # name → value; str, except what launch_ros keeps there too: "global_params" (a list of
        # (name, value) and parameter file paths) and "ros_remaps" (a list of (src, dst))
        self.launch_configurations: dict[str, Any] = {}
        self.environment = dict(os.environ)
        self._initial_environment = dict(os.environ)
        self._environment_stack: list[dict[str, str]] = []
        self.locals = _Locals()
        self._locals_stack: list[dict[str, Any]] = []
        self.argv = argv or []
        self.noninteractive = noninteractive
        self._stack: list[dict[str, Any]] = []
        self.current_file: str | None = None

    def perform_substitution(self, substitution: Performed) -> str:
        return substitution.perform(self)

    def extend_locals(self, values: dict[str, Any]) -> None:  # any objects an action shares
        self.locals.__dict__.update(values)

    def get_locals_as_dict(self) -> dict[str, Any]:
        return dict(self.locals.__dict__)

    def _push_locals(self) -> None:  # launch's own, around an event handler's entities
        self._locals_stack.append(dict(self.locals.__dict__))

    def _pop_locals(self) -> None:
        self.locals.__dict__.clear()
        self.locals.__dict__.update(self._locals_stack.pop())

    def _push(self) -> None:
        self._stack.append(dict(self.launch_configurations))

    def _pop(self) -> None:
        self.launch_configurations = self._stack.pop()


class _Locals:
    pass


MISSING_PACKAGE_ROOT = "/nonexistent-pkgforge-missing-package"


def record_path(path: object, obj: object, via: str) -> None:
    """An absolute path the launch file resolves, recorded (both engines); none under a package
    not found here (that lookup is reported already)."""
    if isinstance(path, str) and path and os.path.isabs(path) and not path.startswith(MISSING_PACKAGE_ROOT):
        RECORDER.add("paths", {"path": path, "via": via, "exists": os.path.exists(path)}, obj)
