"""Package lookups over the ament index, as ament_index_python.packages."""

from __future__ import annotations

import os
import pathlib

from ament_index_python.resources import get_resources, has_resource
from ament_index_python.search_paths import get_search_paths


class PackageNotFoundError(KeyError):
    pass


def get_packages_with_prefixes() -> dict[str, str]:
    return get_resources("packages")


def get_package_prefix(package_name: str) -> str:
    prefix = has_resource("packages", package_name)
    if not prefix:  # None here, False in the real index (its typing is what mypy reads)
        raise PackageNotFoundError(f"package '{package_name}' not found, searching: {get_search_paths()}")
    return prefix


def get_package_share_directory(package_name: str, print_warning: bool = True) -> str:
    return os.path.join(get_package_prefix(package_name), "share", package_name)


def get_package_share_path(package_name: str, print_warning: bool = True) -> pathlib.Path:
    return pathlib.Path(get_package_share_directory(package_name))
