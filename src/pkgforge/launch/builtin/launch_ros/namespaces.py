"""launch_ros.utilities.namespace_utils: how namespaces are joined and made absolute."""

from __future__ import annotations

import typing


def is_root_namespace(ns: str) -> bool:
    return ns == "/"


def is_namespace_absolute(ns: str) -> bool:
    return ns.startswith("/")


@typing.overload
def prefix_namespace(base_ns: str, ns: str | None) -> str: ...
@typing.overload
def prefix_namespace(base_ns: str | None, ns: str) -> str: ...
@typing.overload
def prefix_namespace(base_ns: None, ns: None) -> None: ...
@typing.overload
def prefix_namespace(base_ns: str | None, ns: str | None) -> str | None: ...
def prefix_namespace(base_ns: str | None, ns: str | None) -> str | None:
    """launch_ros: ns under base_ns unless ns is absolute; trailing '/' stripped."""
    if ns is None:
        if base_ns is None:
            return None
        combined = base_ns
    elif not base_ns or is_namespace_absolute(ns):
        combined = ns
    else:
        combined = ("" if is_root_namespace(base_ns) else base_ns) + "/" + ns
    return combined if is_root_namespace(combined) else combined.rstrip("/")


@typing.overload
def make_namespace_absolute(ns: str) -> str: ...
@typing.overload
def make_namespace_absolute(ns: None) -> None: ...
@typing.overload
def make_namespace_absolute(ns: str | None) -> str | None: ...
def make_namespace_absolute(ns: str | None) -> str | None:
    if ns is None:
        return None
    return ns if is_namespace_absolute(ns) else "/" + ns
