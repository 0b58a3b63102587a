"""What `pkgforge verify` was asked for (its options, and the launch engine they choose): the one
value every stage of verify/ reads, below all of them."""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.sandbox.processes import DEFAULT_WORKER_MEMORY
from pkgforge.verify.config import Selection

if TYPE_CHECKING:
    from pkgforge.launch.engines import LaunchEngine
    from pkgforge.robot_models import ModelResult
    from pkgforge.tree import InstallTree


@dataclass
class VerifyOptions:
    selection: Selection = field(default_factory=Selection)
    jobs: int | None = None
    strict: bool = False
    mode: str = "predicted"  # predicted | build | install-base
    install_base: Path | None = None
    launch_timeout: float = 10.0
    launch_arguments: dict[str, str] = field(default_factory=dict)
    use_cache: bool = True
    worker_memory: int | None = DEFAULT_WORKER_MEMORY  # bytes per launch worker; None: unlimited
    simulate: bool = False  # --simulate: each robot model's drop test in MuJoCo (simulate/)
    distro: str | None = (
        None  # --distro; else ROS_DISTRO, pkgforge.toml, CI file (distro_data.target_distros)
    )
    launch_engine: str = "auto"  # auto | ros | builtin
    ros_prefix: Path | None = None
    progress: bool = True  # status lines on a terminal (never elsewhere); --quiet: none
    _engine: LaunchEngine | None = field(default=None, repr=False, compare=False)
    # called with (tree, [ModelResult]) while the install tree is open (`view`, --artifacts)
    on_models: Callable[[InstallTree, list[ModelResult]], None] | None = field(
        default=None, repr=False, compare=False
    )

    def engine(self) -> LaunchEngine:
        """The launch engine these options choose (launch.engines.LaunchEngine), found once."""
        if self._engine is None:
            from pkgforge.launch.engines import choose

            self._engine = choose(self.launch_engine, self.ros_prefix, distro=self.distro)
        return self._engine

    def cache_key(self) -> str:
        engine = self.engine()
        return json.dumps(
            [
                self.mode,
                sorted(self.launch_arguments.items()),
                self.launch_timeout,
                self.distro,
                os.environ.get("ROS_DISTRO", ""),
                engine.name,
                engine.prefix,
                engine.distro,
                *(["simulate"] if self.simulate else []),
            ]
        )
