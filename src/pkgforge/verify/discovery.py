"""The packages of a verify run: colcon's discovery, a quick walk beside it, and one model per
package, loaded in forked processes while discovery runs (verify.forked)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.model.files import quick_name
from pkgforge.workspace import IGNORE_MARKERS, Workspace, discover

if TYPE_CHECKING:
    from pkgforge.model.package import PackageModel
    from pkgforge.model.rviz import RvizConfig


# Below this many packages, starting worker processes costs more than it saves.
PARALLEL_THRESHOLD = 16


@dataclass(frozen=True)
class PackageTarget:
    path: Path
    name: str
    colcon_type: str | None
    parsed_by_colcon: bool


def package_folders(base: Path) -> list[Path]:
    """Folders with a package.xml under base, honouring the ignore markers as colcon does."""
    from pkgforge.walk import walk

    found = []
    # below a resolved top, the walk (which enters no linked folder) yields real paths already
    for current, dirs, files in walk(Path(base).resolve()):
        if any(marker in files for marker in IGNORE_MARKERS):
            dirs[:] = []
            continue
        if "package.xml" in files:
            found.append(Path(current))
            dirs[:] = []
            continue
        dirs[:] = [d for d in dirs if not d.startswith(".")]
    return found


def find_targets(workspace: Workspace) -> list[PackageTarget]:
    """Every ROS package of the workspace: colcon's discovery decides, and folders whose
    package.xml colcon rejected are added, so their problems are reported, not skipped."""
    targets = []
    for descriptor in discover(workspace.base_path, augment=False, ros_only=True):  # names and types only
        path = Path(descriptor.path).resolve()
        if not (path / "package.xml").exists():
            continue  # a plain CMake or Python package: not a ROS package
        targets.append(
            PackageTarget(
                path, descriptor.name, str(descriptor.type), str(descriptor.type).startswith("ros.")
            )
        )
    known = {t.path for t in targets}
    for path in package_folders(workspace.base_path):
        if path not in known:
            targets.append(PackageTarget(path, quick_name(path), None, False))
    return sorted(targets, key=lambda t: (t.name, str(t.path)))


def _load(target: PackageTarget) -> PackageModel:
    from pkgforge.model.package import load_package

    return load_package(target.path, colcon_type=target.colcon_type, parsed_by_colcon=target.parsed_by_colcon)


def _load_folder(folder: Path) -> PackageModel:
    """A package folder's model, in a model loader. catkin_pkg is not run on its manifest here:
    colcon's discovery runs it beside the loaders (its ROS extension parses every package.xml),
    and a package it could not parse is loaded again after, with catkin_pkg's messages."""
    model = _load(PackageTarget(folder, folder.name, None, True))
    # read here, where loading just parsed the same texts (yamlnodes' memo)
    model.rviz_read = {source: read for source, read in rviz_files(model)}  # type: ignore[attr-defined]
    return model


def rviz_files(
    model: PackageModel, known: dict[Path, RvizConfig] | None = None
) -> Iterator[tuple[Path, RvizConfig]]:
    """(source, RvizConfig) of each RViz config the package installs; `known`: those read already."""
    from pkgforge.model.rviz import read_rviz

    for destination, installed in model.layout.files.items():
        if destination.endswith(".rviz") and installed.source is not None:
            source = installed.source
            yield source, known[source] if known and source in known else read_rviz(source)


def load_models(workspace: Workspace, jobs: int) -> tuple[list[PackageTarget], dict[Path, PackageModel]]:
    """Models of every package; with several cores, loaded while colcon's discovery runs.

    Discovery and loading each take about half of a run on their own, so a
    quick walk hands the folders to workers first; colcon's answer then decides
    which models count, and what it found that the walk did not is loaded after.
    """
    guessed = package_folders(workspace.base_path)
    if jobs <= 1 or len(guessed) < PARALLEL_THRESHOLD:
        targets = find_targets(workspace)
        return targets, {t.path: _load(t) for t in targets}
    # imported here, before the fork, so that the loaders inherit them: this process needs them
    # anyway to unpickle the models, and each loader importing them again cost ~0.16 CPU s
    import pkgforge.model.package
    import pkgforge.model.rviz  # noqa: F401
    from pkgforge.verify.forked import Forked, slices

    # as many loaders as cores: this process's discovery (colcon's ROS extension alone) ends long
    # before the loading. A loader that cannot be forked, or dies, leaves its models to this
    # process, below (verify/forked.py)
    loaders = Forked(_load_folder, guessed, slices(len(guessed), max(1, jobs)))
    try:
        targets = find_targets(workspace)
        answers = loaders.answers()
    finally:
        loaders.stop()
    loaded = {model.path: model for answer in answers if answer is not None for model in answer}
    models = {}
    for target in targets:
        model = loaded.get(target.path)
        if model is None or model.name != target.name or not target.parsed_by_colcon:
            model = _load(target)
        elif target.colcon_type and model.manifest.build_type is None:
            model.build_type = target.colcon_type.removeprefix("ros.")
        models[target.path] = model
    return targets, models


# --- checks ---------------------------------------------------------------------------------


def load_one_package(
    workspace: Workspace,
) -> tuple[list[PackageTarget], dict[Path, PackageModel], dict[str, Path], Namesakes]:
    """One package of a workspace (pre-commit): it, the workspace packages it declares, every
    package's name, and the other folders holding a package of its name.

    The other packages matter only by name, which a walk reads cheaply; colcon
    identifies just this folder.
    """
    if workspace.package_path is None:
        raise ValueError("load_one_package: the workspace is no single package")
    folder = workspace.package_path.resolve()
    named = [(quick_name(p), p) for p in package_folders(workspace.base_path)]
    everything = dict(named)
    from pkgforge.workspace import identify_folder

    descriptor = identify_folder(folder)
    if descriptor is not None and (folder / "package.xml").exists():
        targets = [PackageTarget(folder, descriptor.name, str(descriptor.type), True)]
    else:
        targets = [t for t in find_targets(Workspace(workspace.root, folder)) if t.path == folder]
    if not targets:
        return [], {}, everything, {}
    namesakes = namesakes_of([(name, p) for name, p in named if p != folder] + [(targets[0].name, folder)])
    everything[targets[0].name] = folder  # its own name is itself, whatever other copy the walk met
    models = {folder: _load(targets[0])}
    todo = [models[folder]]
    while todo:
        for dependency in todo.pop().manifest.declared():
            path = everything.get(dependency)
            if path is not None and path not in models:
                models[path] = _load(PackageTarget(path, dependency, None, False))
                todo.append(models[path])
    return targets, models, everything, {folder: namesakes[folder]} if folder in namesakes else {}


def first_of_each(models: Iterable[PackageModel], attribute: str) -> dict[str, PackageModel]:
    """The first model of each value of `attribute` (name, share_name), in the models' order:
    the copy of a name the install tree holds, and what every lookup of that name reads (PF110)."""
    first: dict[str, PackageModel] = {}
    for model in models:
        first.setdefault(getattr(model, attribute), model)
    return first


# a package folder → the other folders of the workspace whose package has the same name
Namesakes = dict[Path, tuple[Path, ...]]


def namesakes_of(named: list[tuple[str, Path]]) -> Namesakes:
    """For each (name, folder) whose name another folder has too: the other folders, sorted."""
    folders: dict[str, list[Path]] = {}
    for name, folder in named:
        folders.setdefault(name, []).append(folder)
    return {
        folder: tuple(sorted(other for other in same if other != folder))
        for same in folders.values()
        if len(same) > 1
        for folder in same
    }
