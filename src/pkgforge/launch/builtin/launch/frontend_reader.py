"""The XML and YAML reader, as the Python API reaches it without importing it.

launch finds its front-end parsers (launch_xml, launch_yaml) through entry points, so no
action imports them. Here the reader, pkgforge.launch.frontend, builds on every action of
this package and registers itself when imported (evaluate imports it before any launch file
is read). The Python API needs it twice: an XML or YAML file included or loaded
(launch_description_sources.load_description) and a parameter file's `$(...)` performed
(launch_ros's ParameterFile with allow_substs).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pkgforge.launch.builtin.launch.launch_description import LaunchDescription
from pkgforge.launch.builtin.launch.substitution import Substitution


@dataclass(frozen=True)
class FrontendReader:
    parse_file: Callable[[str, str], LaunchDescription]  # (path, "xml" | "yaml")
    parse_substitution: Callable[[str], list[Substitution]]  # `a$(var x)b` → its substitutions


_REGISTERED: list[FrontendReader] = []


def register(reader: FrontendReader) -> None:
    _REGISTERED[:] = [reader]


def reader() -> FrontendReader:
    """The registered reader (pkgforge.launch.frontend, imported with evaluate)."""
    if not _REGISTERED:
        raise RuntimeError("pkgforge.launch.frontend was not imported: no XML/YAML reader registered")
    return _REGISTERED[0]
