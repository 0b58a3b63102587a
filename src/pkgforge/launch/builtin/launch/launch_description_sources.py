"""launch.launch_description_sources: the file an include names, read into its LaunchDescription.

Real: launch/launch_description_source.py, launch/launch_description_sources/*.py
(python_launch_file_utilities: a Python file loaded as a module; an XML or YAML file through
frontend_reader).
"""

from __future__ import annotations

import importlib.util
import itertools
import os
from types import ModuleType
from typing import Any

from pkgforge.launch.builtin.launch.errors import InvalidLaunchFileError
from pkgforge.launch.builtin.launch.frontend_reader import reader
from pkgforge.launch.builtin.launch.launch_description import LaunchDescription
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType
from pkgforge.launch.builtin.launch.utilities import FilePath
from pkgforge.launch.place import LAUNCH_FILES, Located
from pkgforge.model.references import launch_format


class LaunchDescriptionSource(Located):
    kind: str | None = None

    # the real sources' other arguments (method, launch_description…) are not read
    def __init__(
        self, launch_file_path: SomeSubstitutionsType | None = None, *args: Any, **kwargs: Any
    ) -> None:
        super().__init__()
        self.location = launch_file_path


class PythonLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "py"


class AnyLaunchDescriptionSource(LaunchDescriptionSource):
    kind = None


class FrontendLaunchDescriptionSource(LaunchDescriptionSource):
    kind = None


class XMLLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "xml"


class YAMLLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "yaml"


def load_description_function(path: FilePath, *args: Any, **kwargs: Any) -> LaunchDescription:
    # *args, **kwargs: the real loaders' other arguments (launch_file_path only is read)
    """launch's get_launch_description_from_*_launch_file(): the file's LaunchDescription."""
    return load_description(os.fspath(path))


def load_python_launch_file_as_module(python_launch_file_path: FilePath) -> ModuleType:
    """The launch file as a module, as launch loads it (generate_launch_description not called)."""
    return load_module(os.fspath(python_launch_file_path))


_module_counter = itertools.count()


def load_module(path: str) -> ModuleType:
    """A Python launch file as a module (launch's load_python_launch_file_as_module)."""
    LAUNCH_FILES.add(path)
    spec = importlib.util.spec_from_file_location(f"pkgforge_launch_{next(_module_counter)}", path)
    if spec is None or spec.loader is None:  # a name importlib knows no loader for
        raise ImportError(f"cannot load {path} as a Python module")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_description(path: str, kind: str | None = None) -> LaunchDescription:
    """The launch file's LaunchDescription: a Python file's generate_launch_description(), an
    XML or YAML file read by the front end."""
    kind = kind or launch_format(path)
    LAUNCH_FILES.add(path)
    if kind == "py":
        module = load_module(path)
        function = getattr(module, "generate_launch_description", None)
        if function is None:
            raise InvalidLaunchFileError(f"{os.path.basename(path)} has no generate_launch_description()")
        description: object = function()
        if not isinstance(description, LaunchDescription):
            raise InvalidLaunchFileError(
                f"generate_launch_description() returned {type(description).__name__}, not a LaunchDescription"
            )
        return description
    return reader().parse_file(path, kind)
