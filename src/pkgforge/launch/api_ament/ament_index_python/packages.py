"""Package lookups over the ament index, as ament_index_python.packages."""

import os
import pathlib

from ament_index_python.resources import get_resources, get_search_paths, has_resource


class PackageNotFoundError(KeyError):
    pass


def get_packages_with_prefixes():
    return get_resources("packages")


def get_package_prefix(package_name):
    prefix = has_resource("packages", package_name)
    if prefix is None:
        raise PackageNotFoundError(f"package '{package_name}' not found, searching: {get_search_paths()}")
    return prefix


def get_package_share_directory(package_name, print_warning=True):
    return os.path.join(get_package_prefix(package_name), "share", package_name)


def get_package_share_path(package_name, print_warning=True):
    return pathlib.Path(get_package_share_directory(package_name))
