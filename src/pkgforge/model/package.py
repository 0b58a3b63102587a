"""PackageModel: one package read once (manifest, build files, install layout, references)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.model.cmake import CMakeModel, load_cmake
from pkgforge.model.files import SKIPPED_DIRS
from pkgforge.model.files import walk_files as _walk_files
from pkgforge.model.layout import InstallLayout, layout_from_cmake, layout_from_setup_py
from pkgforge.model.manifest import Manifest, load_manifest
from pkgforge.model.references import Reference, launch_kind, scan
from pkgforge.model.setup_py import SetupPyModel, load_setup_py
from pkgforge.model.source import SourceFile, read_source
from pkgforge.walk import WalkLimit

# Top-level folders that hold run-time resources by convention.
RESOURCE_FOLDERS = (
    "launch",
    "urdf",
    "meshes",
    "rviz",
    "config",
    "worlds",
    "models",
    "maps",
    "params",
    "description",
    "robots",
    "xacro",
    "sdf",
)
SCANNED_SUFFIXES = (".xacro", ".urdf", ".rviz", ".sdf")


@dataclass
class PackageModel:
    name: str  # package.xml <name>, else the folder name
    path: Path
    build_type: str  # ament_cmake | ament_python | cmake | catkin | ...
    manifest: Manifest
    cmake: CMakeModel | None = None
    setup_py: SetupPyModel | None = None
    layout: InstallLayout = field(default_factory=InstallLayout)
    files: list[Path] = field(default_factory=list)  # every file, relative to path
    references: list[Reference] = field(default_factory=list)
    sources: dict[Path, SourceFile] = field(default_factory=dict)  # every file read
    skipped: list[SourceFile] = field(default_factory=list)  # too large or unreadable
    # where a walk of the package (or of its installed share folder) stopped: folder-not-walked
    walk_limits: list[WalkLimit] = field(default_factory=list)
    # folders inside it with their own package.xml (not walked: colcon does not look inside a package)
    nested_packages: list[Path] = field(default_factory=list)

    @property
    def share_name(self) -> str:
        """The folder under share/ the build installs to (CMake's PROJECT_NAME)."""
        if self.cmake is not None and isinstance(self.cmake.project_name, str):
            return self.cmake.project_name
        return self.name

    def top_level_folders(self) -> dict[str, list[Path]]:
        """Top-level folder → its files (relative to the package)."""
        folders: dict[str, list[Path]] = {}
        for relative in self.files:
            if len(relative.parts) > 1:
                folders.setdefault(relative.parts[0], []).append(relative)
        return folders

    def launch_files(self) -> list[Path]:
        return [
            self.path / f for f in self.files if launch_kind(self.path / f) and f.parts[0] not in SKIPPED_DIRS
        ]

    def unpredicted(self) -> tuple[Path, int | None] | None:
        """Where the install of a setup.py package into its share folder cannot be predicted
        (setup.py unreadable, or data_files that neither its text nor running it gave): (file,
        line), else None. Such a share folder is unknown, never empty. (A CMake package's rule
        pkgforge cannot evaluate keeps its own handling: a file it may install is a warning.)"""
        layout, setup_py = self.layout, self.setup_py
        if setup_py is None:
            return None
        if not layout.known:
            return setup_py.source.path, setup_py.syntax_error[0] if setup_py.syntax_error else None
        share = f"share/{self.share_name}"
        for path, line, destination in layout.may_install:
            if (
                destination is None
                or destination in ("", "share")
                or (destination + "/").startswith(share + "/")
            ):
                return path, line
        return None

    def suppressed(self, path: Path, line: int | None, keys: set[str]) -> bool:
        source = self.sources.get(path)
        if source is None or line is None:
            return False
        return bool(source.suppressions.get(line, set()) & keys)


def _is_scanned(relative: Path) -> bool:
    if relative.parts[0] in SKIPPED_DIRS:
        return False
    name = relative.name
    if name.endswith(SCANNED_SUFFIXES) or name.endswith(".urdf.xml"):
        return True
    if name.endswith((".py", ".yaml", ".yml")) and relative.parts[0] not in ("test", "tests"):
        return True  # imports; controller and plugin types
    return launch_kind(relative) is not None


def load_package(
    path: Path, *, colcon_type: str | None = None, parsed_by_colcon: bool = False
) -> PackageModel:
    path = path.resolve()
    manifest_source = read_source(path / "package.xml")
    manifest = load_manifest(manifest_source, parsed_package=True if parsed_by_colcon else None)
    build_type = manifest.build_type or (colcon_type or "").removeprefix("ros.") or "unknown"
    model = PackageModel(name=manifest.name or path.name, path=path, build_type=build_type, manifest=manifest)
    model.sources[manifest_source.path] = manifest_source
    model.files = _walk_files(path, model.walk_limits, model.nested_packages)

    if (path / "CMakeLists.txt").exists() and build_type not in ("ament_python",):
        model.cmake = load_cmake(path)
        for source in model.cmake.files:
            model.sources[source.path] = source
        model.layout = layout_from_cmake(model.cmake, path, model.share_name)
    elif (path / "setup.py").exists():
        source = read_source(path / "setup.py")
        model.sources[source.path] = source
        model.setup_py = load_setup_py(source, path)
        model.layout = layout_from_setup_py(model.setup_py, path)

    for relative in model.files:
        if not _is_scanned(relative):
            continue
        source = read_source(path / relative)
        model.sources[source.path] = source
        if source.text is None:
            model.skipped.append(source)
            continue
        model.references.extend(scan(source))
    # large files pkgforge would otherwise read later (models, meshes) are noted too
    return model
