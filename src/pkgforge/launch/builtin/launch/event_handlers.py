"""launch.event_handlers and launch.events: what a handler's entities are visited with.

Real: launch/event_handler.py, launch/event_handlers/*.py, launch/events/*.py. verify starts
no process: a handler's entities are visited once, with a stand-in of the event they handle.
"""

from __future__ import annotations

import typing
from collections.abc import Callable
from typing import Any

from pkgforge.launch.builtin.launch.action import Action, LaunchDescriptionEntity, SomeEntitiesType
from pkgforge.launch.place import Located

# a handler's entities: what it starts, or a function of the event (known only at run time)
HandlerEntities = typing.Union["SomeEntitiesType", Callable[..., object], None]  # noqa: UP007


class BaseEventHandler(Located):
    # matcher: a predicate on launch's events (never seen at verify time); **_ignored: the rest
    # of the real handler's keyword arguments
    def __init__(
        self, *, matcher: Callable[[Any], bool] | None = None, handle_once: bool = False, **_ignored: Any
    ) -> None:
        super().__init__()
        self.entities: list[LaunchDescriptionEntity] = []


class EventHandler(BaseEventHandler):
    def __init__(
        self,
        *,
        matcher: Callable[[Any], bool] | None = None,
        entities: HandlerEntities = None,
        handle_once: bool = False,
        **_ignored: Any,
    ) -> None:
        super().__init__(matcher=matcher, handle_once=handle_once)
        self.entities = _as_entities(entities)


def _as_entities(entities: HandlerEntities) -> list[LaunchDescriptionEntity]:
    if entities is None or callable(entities):
        return []  # a function of the event: only known when the event happens
    if isinstance(entities, LaunchDescriptionEntity):
        return [entities]
    return [e for e in entities if isinstance(e, LaunchDescriptionEntity)]


class _OnEvent(EventHandler):
    HANDLERS = (
        "on_exit",
        "on_start",
        "on_completion",
        "on_stdin",
        "on_stdout",
        "on_stderr",
        "on_shutdown",
        "on_include",
        "on_event",
        "entities",
    )

    # the real handler's keyword arguments (on_exit=…, target_action=…): HANDLERS and the target
    # are read
    def __init__(self, **kwargs: Any) -> None:
        entities: list[LaunchDescriptionEntity] = []
        for key in self.HANDLERS:
            entities.extend(_as_entities(kwargs.get(key)))
        super().__init__()
        self.entities = entities
        target = kwargs.get("target_action", kwargs.get("target_lifecycle_node"))
        self.target_action = target if isinstance(target, Action) else None  # (not a matcher function)


class OnProcessExit(_OnEvent):
    pass


class OnProcessStart(_OnEvent):
    pass


class OnExecutionComplete(_OnEvent):
    pass


class OnProcessIO(_OnEvent):
    pass


class OnShutdown(_OnEvent):
    pass


class OnIncludeLaunchDescription(_OnEvent):
    pass


class OnActionEventBase(_OnEvent):
    pass


class OnStateTransition(_OnEvent):
    pass


def matcher(*args: Any, **kwargs: Any) -> Callable[[object], bool]:  # the real matcher's arguments
    """event_named, matches_action…: a predicate on events, which never come at verify time."""
    return lambda event: False


class HandledEvent:
    """The event launch puts in the context's locals (`event`) before it visits an event
    handler's entities (launch.event_handler.BaseEventHandler.handle), so that
    LocalSubstitution('event.reason') performs: no event happens at verify time, so this stands
    in for launch's event of the handler's kind (launch/events/, launch_ros's StateTransition),
    with its attributes; what only a run tells (a pid, an exit code, output) has a neutral value.
    Its class is named as launch's (an attribute it lacks: "'Shutdown' object has no attribute")."""

    def __init__(self, **attributes: object) -> None:
        self.__dict__.update(attributes)

    def __getattribute__(self, name: str) -> object:
        if not name.startswith("__"):
            EVENT_READ[0] = True  # an action failing after this may fail on the stand-in's values
        return object.__getattribute__(self, name)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} event (no event at verify time)>"


# whether the stand-in event was read since the current handler's entities began (deferred.handling)
EVENT_READ = [False]


_EVENT_CLASSES: dict[str, type[HandledEvent]] = {}


def _event(kind: str, **attributes: object) -> HandledEvent:
    cls = _EVENT_CLASSES.get(kind)
    if cls is None:
        cls = _EVENT_CLASSES[kind] = type(kind, (HandledEvent,), {})
    return cls(**attributes)


# the stand-in events whose handlers' entities are being visited (deferred.handling)
HANDLING: list[object] = []


def handler_event(handler: object, target: object = None) -> HandledEvent:
    """The event `handler` (launch's or pkgforge's, by its class's name) handles, standing in
    (both engines); `target`: the action it watches (target_action), None for any."""
    kinds = {cls.__name__ for cls in type(handler).__mro__}
    process: dict[str, object] = {
        "action": target,
        "execute_process_action": target,
        "process_name": "",
        "cmd": [],
        "cwd": None,
        "env": None,
        "pid": 0,
    }
    if "OnShutdown" in kinds:  # launch.events.Shutdown's defaults (a Shutdown action without reason)
        return _event("Shutdown", reason="reason not given", due_to_sigint=False)
    if "OnProcessStart" in kinds:
        return _event("ProcessStarted", **process)
    if "OnProcessExit" in kinds:
        return _event("ProcessExited", **process, returncode=0)
    if "OnProcessIO" in kinds:  # (a line of the process's standard output)
        fd = {"from_stdin": False, "from_stdout": True, "from_stderr": False}
        return _event("ProcessIO", **process, text=b"", **fd)
    if "OnExecutionComplete" in kinds:
        return _event("ExecutionComplete", action=target)
    if "OnIncludeLaunchDescription" in kinds:
        return _event("IncludeLaunchDescription", launch_description=None)
    if "OnStateTransition" in kinds:
        states = {"transition": "", "start_state": "", "goal_state": ""}
        return _event("StateTransition", action=target, msg=None, timestamp=0, **states)
    return _event("Event")  # a handler of its own matcher: which event, only the run tells


class InertEvent(Located):
    """An event class (Shutdown, ChangeState…): emitted at run time; nothing to check."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # the real event's arguments, unread
        super().__init__()
