"""Launch files in a package's source that its install rules leave out.

`ros2 launch` cannot find them, but they are the package's own code: they are evaluated from
the source tree (their lookups still resolve in the install tree), so what they reference is
checked too; launch-not-installed says once that they are not installed.
"""

from __future__ import annotations

from pkgforge.launch.records import LaunchFile
from pkgforge.launch.resolve import _is_launch_file
from pkgforge.model.package import PackageModel

SKIPPED = {"test", "tests", "build", "install", "log", "__pycache__"}


def source_only(models: list[PackageModel], found: list[LaunchFile]) -> list[LaunchFile]:
    """The launch files of `models` that no install rule installs (none when a rule is unreadable)."""
    known = {launch.source for launch in found if launch.source is not None}
    out = []
    for model in models:
        if not model.layout.known or model.layout.unknown:
            continue  # a rule pkgforge cannot read may install them
        installed = model.layout.installed_sources()
        for relative in model.launch_files():
            relative = relative.relative_to(model.path)
            path = model.path / relative
            if any(p in SKIPPED or p.startswith(".") for p in relative.parts) or path.name.startswith(
                "test_"
            ):
                continue
            if path in installed or path in known or not _is_launch_file(path):
                continue
            out.append(LaunchFile(model.name, path, path))
    return out


def is_uninstalled(launch: LaunchFile) -> bool:
    return launch.source is not None and launch.installed == launch.source
