"""The ament resource index over AMENT_PREFIX_PATH."""

from __future__ import annotations

import os

# where get_search_paths lives in the real package (the type checker reads the real one's)
from ament_index_python.search_paths import get_search_paths

RESOURCE_INDEX = os.path.join("share", "ament_index", "resource_index")


def get_resources(resource_type: str) -> dict[str, str]:
    found: dict[str, str] = {}
    for prefix in get_search_paths():
        folder = os.path.join(prefix, RESOURCE_INDEX, resource_type)
        if os.path.isdir(folder):
            for name in os.listdir(folder):
                if not name.startswith(".") and name not in found:
                    found[name] = prefix
    return found


def has_resource(resource_type: str, resource_name: str) -> str | None:
    for prefix in get_search_paths():
        if os.path.isfile(os.path.join(prefix, RESOURCE_INDEX, resource_type, resource_name)):
            return prefix
    return None


def get_resource(resource_type: str, resource_name: str) -> tuple[str, str]:
    prefix = has_resource(resource_type, resource_name)
    if prefix is None:
        raise LookupError(f"Could not find the resource '{resource_name}' of type '{resource_type}'")
    with open(os.path.join(prefix, RESOURCE_INDEX, resource_type, resource_name)) as handle:
        return handle.read(), prefix
