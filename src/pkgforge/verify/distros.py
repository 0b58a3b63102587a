"""The ROS 2 distros a verified package targets, and so the launch engine its launch files run in."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.verify.config import Config
from pkgforge.workspace import Workspace

if TYPE_CHECKING:
    from pkgforge.launch.engines import LaunchEngine
    from pkgforge.launch.records import LaunchFile
    from pkgforge.model.package import PackageModel
    from pkgforge.verify.pipeline import VerifyOptions


def package_distros(
    folder: Path, workspace: Workspace, config: Config, options: VerifyOptions
) -> tuple[str, ...]:
    """The ROS 2 distros a package targets (empty: every active distro)."""
    from pkgforge.model.distro_data import target_distros

    return target_distros(folder, workspace.root.resolve(), options.distro, config.distro_for(folder))[0]


NEWEST_LTS_SOURCE = "the newest LTS"


def launch_distro(
    folder: Path, workspace: Workspace, config: Config, options: VerifyOptions
) -> tuple[str, str]:
    """(the distro whose launch API the built-in engine follows for a package's launch files,
    where it came from): its target distro as the checks see it (--distro, ROS_DISTRO, pkgforge.toml
    [verify] distro, the CI files), the oldest of several (a name that one lacks fails there: a
    humble CI job cannot import EqualsSubstitution), else the newest LTS."""
    from pkgforge.model.distro_data import target_distros
    from pkgforge.model.distros import NEWEST_LTS

    distros, source = target_distros(
        folder, workspace.root.resolve(), options.distro, config.distro_for(folder)
    )
    return (distros[0], source) if distros else (NEWEST_LTS, NEWEST_LTS_SOURCE)


def by_launch_engine(
    launch_files: list[LaunchFile],
    packages: list[PackageModel],
    launch_distros: dict[Path, tuple[str, str]],
    options: VerifyOptions,
) -> list[tuple[LaunchEngine, list[LaunchFile]]]:
    """The launch files in groups, each with the engine that evaluates it: the real engine takes
    them all; the built-in one follows each package's target distro (launch_distro), so a humble
    package's file that imports EqualsSubstitution fails as it does on humble."""
    engine = options.engine()
    if engine.name != "builtin":
        return [(engine, launch_files)]
    from pkgforge.launch.engines import builtin

    folders = {model.name: model.path for model in packages}
    groups: dict[str, list[LaunchFile]] = {}
    for launch in launch_files:
        chosen = launch_distros.get(folders.get(launch.package) or Path())
        groups.setdefault(chosen[0] if chosen else engine.distro or "", []).append(launch)
    return [
        (engine if distro == engine.distro else builtin(distro or None), group)
        for distro, group in groups.items()
    ]
