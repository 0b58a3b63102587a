"""The migrated package in memory (`Converted`): its files, their modes, and what each launch file
uses; the launch files written from their actions. What migrate/package reads into it and what
migrate/gazebo converts in it both use it, so it stands below both.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pkgforge.migrate.roslaunch import Action, LaunchFile
    from pkgforge.model.distros import Distro
    from pkgforge.scaffold.notes import Notes


@dataclass
class Converted:
    """The migrated package in memory: its files, their modes, and what each launch file uses."""

    output: dict[str, bytes] = field(default_factory=dict)
    modes: dict[str, int] = field(default_factory=dict)
    uses: dict[str, set[str]] = field(default_factory=dict)  # written launch file → packages it uses
    launches: dict[str, LaunchFile] = field(default_factory=dict)  # ROS 2 launch file → its actions
    launch_sources: dict[str, Path] = field(default_factory=dict)  # ROS 2 launch file → the ROS 1 file
    launch_names: dict[str, str] = field(default_factory=dict)  # ROS 2 launch file → ROS 1's, relative
    generated_rviz: dict[str, int | None] = field(default_factory=dict)
    depends: set[str] = field(
        default_factory=set
    )  # what the converted files need beyond the launch files' uses

    def emit(self, leave_out: set[str], name: str, launch_format: str, distro: Distro, notes: Notes) -> None:
        """Write the launch files in output, but for those in leave_out and those that come to start
        nothing (a Gazebo Classic file without --gazebo); an include of a file not written is left
        out of the file including it."""
        from pkgforge.migrate.emit import to_python, to_xml, to_yaml, used_packages

        written = set(self.launches) - leave_out
        changed = True
        while changed:
            changed = False
            for relative in sorted(written):
                launch, path = self.launches[relative], self.launch_sources[relative]
                for include in _includes_of(launch.actions, name, set(self.launches) - written):
                    notes.add(
                        "migrate-dropped",
                        f"include of {include[1]} left out: it is not written",
                        path,
                        include[0],
                    )
                if not launch.runs_anything():
                    notes.add(
                        "migrate-dropped",
                        f"{relative} not written: nothing in it starts in ROS 2",
                        path,
                        None,
                    )
                    written.discard(relative)
                    changed = True
        self.uses = {}
        for relative, launch in self.launches.items():
            self.output.pop(relative, None)
            if relative not in written:
                continue
            source = os.path.relpath(
                self.launch_sources[relative].as_posix(),
                self.launch_sources[relative].parents[len(Path(relative).parts) - 1],
            )
            if launch_format == "py":
                text = to_python(launch.actions, source)
            elif launch_format == "xml":
                text = to_xml(launch.actions, source, distro=distro)
            else:
                text = to_yaml(launch.actions, source, distro=distro)
            self.output[relative] = text.encode("utf-8")
            self.uses[relative] = used_packages(launch.actions)


def _includes_of(actions: list[Action], name: str, gone: set[str]) -> list[tuple[int | None, str]]:
    """Take out each include of one of the package's launch files in `gone`: (its line, the file)."""
    from pkgforge.migrate.roslaunch import Group, Include
    from pkgforge.migrate.tokens import Token

    taken: list[tuple[int | None, str]] = []
    for action in list(actions):
        if isinstance(action, Group):
            taken += _includes_of(action.actions, name, gone)
        elif isinstance(action, Include) and len(action.path) == 2 and action.path[0] == Token("find", name):
            relative = action.path[1][1].lstrip("/")
            if relative in gone:
                actions.remove(action)
                taken.append((action.line, relative))
    return taken
