"""The ament resource index over AMENT_PREFIX_PATH."""

import os

RESOURCE_INDEX = os.path.join("share", "ament_index", "resource_index")


def get_search_paths():
    return [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p and os.path.exists(p)]


def get_resources(resource_type):
    found = {}
    for prefix in get_search_paths():
        folder = os.path.join(prefix, RESOURCE_INDEX, resource_type)
        if os.path.isdir(folder):
            for name in os.listdir(folder):
                if not name.startswith(".") and name not in found:
                    found[name] = prefix
    return found


def has_resource(resource_type, resource_name):
    for prefix in get_search_paths():
        if os.path.isfile(os.path.join(prefix, RESOURCE_INDEX, resource_type, resource_name)):
            return prefix
    return None


def get_resource(resource_type, resource_name):
    prefix = has_resource(resource_type, resource_name)
    if prefix is None:
        raise LookupError(f"Could not find the resource '{resource_name}' of type '{resource_type}'")
    with open(os.path.join(prefix, RESOURCE_INDEX, resource_type, resource_name)) as handle:
        return handle.read(), prefix
