"""Which robot models to process, and their results (plain data from the worker).

A model is processed when a launch file feeds it to xacro (with that launch's
xacro arguments), and every top-level .urdf/.xacro installed in a urdf/,
description/ or robots/ folder that no other file includes is processed on
its own: the model a person opens in RViz by hand is checked too.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from .launch.resolve import run_requests, source_of
from .model.package import PackageModel
from .trees import InstallTree
from .walk import walk

MODEL_FOLDERS = ("urdf", "description", "robots", "xacro")
MODEL_SUFFIXES = (".urdf", ".xacro", ".urdf.xacro")
INCLUDE = re.compile(r"<xacro:include[^>]*?filename\s*=\s*[\"']([^\"']+)[\"']")


@dataclass
class ModelResult:
    package: str  # the verified package that uses or installs the model
    installed: Path
    source: Path | None
    mappings: dict
    origins: list[dict] = field(default_factory=list)  # launch lines that feed it to xacro
    status: str = "ok"  # ok | error | needs-arguments | too-large | timeout | crashed | library
    error: dict | None = None
    robot: dict | None = None
    includes: list[str] = field(default_factory=list)

    @property
    def links(self) -> set[str]:
        return {link["name"] for link in (self.robot or {}).get("links", [])}


def _installed_models(tree: InstallTree, model: PackageModel) -> list[Path]:
    share = tree.share(model.share_name)
    if share is None:
        return []
    candidates, included = [], set()
    for folder in MODEL_FOLDERS:
        for root, dirs, files in walk(share / folder, follow_links=True, inside=(model.path,),
                                      limits=model.walk_limits):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(MODEL_SUFFIXES):
                    path = Path(root) / name
                    candidates.append(path)
                    try:
                        if path.stat().st_size < 2 * 2**20:
                            # a file including itself is still top-level (and broken)
                            included |= {os.path.basename(m) for m in INCLUDE.findall(
                                path.read_text(errors="replace"))} - {name}
                    except OSError:
                        continue
    return [path for path in candidates if path.name not in included]


def collect(tree: InstallTree, models: list[PackageModel], resolutions: dict[str, list]) -> list[ModelResult]:
    jobs: dict[tuple, ModelResult] = {}
    by_name = {m.name: m for m in models}
    for package, package_resolutions in resolutions.items():
        owner = by_name.get(package)
        for resolution in package_resolutions:
            for command in resolution.commands:
                model_path = command.model
                if not model_path or not os.path.isfile(model_path) or tree.is_phantom(model_path):
                    continue
                key = (package, os.path.normpath(model_path), tuple(sorted(command.mappings.items())))
                if key not in jobs:
                    jobs[key] = ModelResult(package, Path(key[1]), source_of(Path(key[1]), tree, owner),
                                            dict(command.mappings))
                if command.robot and jobs[key].robot is None:
                    # the launch's own xacro run already gave the structure
                    jobs[key].robot, jobs[key].includes = command.robot, list(command.includes)
                jobs[key].origins.append({"launch": resolution.launch, "file": command.file,
                                          "line": command.line})
    fed = {key[:2] for key in jobs}  # (package, model) a launch file feeds to xacro
    for model in models:
        for path in _installed_models(tree, model):
            key = (model.name, os.path.normpath(path), ())
            if key[:2] not in fed:
                fed.add(key[:2])
                jobs[key] = ModelResult(model.name, path, source_of(path, tree, model), {})
    return list(jobs.values())


def process(results: list[ModelResult], tree: InstallTree, *, jobs: int, timeout: float,
            on_done=None, limits=None, zygote=None) -> list[ModelResult]:
    """Run xacro on the models whose structure no launch file's xacro run already gave."""
    pending = [r for r in results if r.robot is None]
    requests = [{"model": str(r.installed), "mappings": r.mappings} for r in pending]
    for result, reply in zip(pending, run_requests(requests, tree, jobs=jobs, timeout=timeout, on_done=on_done,
                                                    limits=limits, zygote=zygote)):
        result.status = reply.get("status", "crashed")
        result.error = reply.get("error")
        result.robot = reply.get("robot")
        result.includes = reply.get("includes", [])
        if result.status == "ok" and not result.origins and not result.links:
            result.status = "library"  # only macros and properties: checked through its includers
        if result.status == "needs-arguments" and result.origins:
            result.status = "error"  # a launch file gave it no value either
    for result in results:
        if result not in pending and not result.links and not result.origins:
            result.status = "library"
    return results
