"""InstallTree: the install space launch files are resolved against.

- predicted: the models' install layouts, materialised as a temporary prefix of
  symlinks with the ament index markers (fast; pre-commit);
- built: a real colcon build into a pkgforge-owned base (`--build`);
- existing: the user's own `colcon build` output, merged or isolated (`--install-base`).

Declared dependencies that are in none of these (robot_state_publisher, rviz2 …
on a machine without ROS) get a phantom prefix: an empty share folder and an
index marker, so lookups succeed as they would on the robot while pkgforge knows
that nothing under it can be checked.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from .errors import PkgforgeError
from .model.package import PackageModel
from .toolchain import prepend_path

INDEX = Path("share/ament_index/resource_index/packages")


@dataclass
class InstallTree:
    kind: str  # predicted | built | existing
    prefixes: list[Path]
    phantom: Path | None = None
    packages: dict[str, Path] = field(default_factory=dict)  # package → prefix holding it
    phantom_packages: set[str] = field(default_factory=set)
    # packages of an AMENT_PREFIX_PATH the user already has (a sourced ROS) → their prefix
    system_packages: dict[str, Path] = field(default_factory=dict)
    _temporary: tempfile.TemporaryDirectory | None = None

    def share(self, package: str) -> Path | None:
        """The package's share folder in the tree (workspace packages)."""
        prefix = self.packages.get(package)
        return prefix / "share" / package if prefix else None

    def installed_share(self, package: str) -> Path | None:
        """The share folder in the tree, else in a prefix the user already has."""
        prefix = self.packages.get(package) or self.system_packages.get(package)
        return prefix / "share" / package if prefix else None

    def locate(self, path: str) -> tuple[str, str, Path] | None:
        """(package, path inside its share folder, prefix) for a path in the tree, else None."""
        real = os.path.normpath(path)
        for prefix in [*self.prefixes, *([self.phantom] if self.phantom else [])]:
            share = str(prefix / "share") + os.sep
            if real.startswith(share):
                package, _, rest = real[len(share):].partition(os.sep)
                return package, rest.replace(os.sep, "/"), prefix
        return None

    def is_phantom(self, path: str) -> bool:
        return self.phantom is not None and os.path.normpath(path).startswith(str(self.phantom) + os.sep)

    def environment(self, base: dict[str, str] | None = None) -> dict[str, str]:
        env = dict(os.environ if base is None else base)
        value = env.get("AMENT_PREFIX_PATH", "")
        if self.phantom is not None:
            value = value + (os.pathsep if value else "") + str(self.phantom)
        for prefix in reversed(self.prefixes):
            value = prepend_path(str(prefix), value)
        env["AMENT_PREFIX_PATH"] = value
        if self.phantom is not None:
            env["PKGFORGE_PHANTOM_PREFIX"] = str(self.phantom)
        return env

    def close(self) -> None:
        if self._temporary is not None:
            self._temporary.cleanup()
            self._temporary = None


def _index(prefixes: list[Path]) -> dict[str, Path]:
    found: dict[str, Path] = {}
    for prefix in prefixes:
        folder = prefix / INDEX
        if folder.is_dir():
            for marker in sorted(folder.iterdir()):
                found.setdefault(marker.name, prefix)
    return found


def _user_prefixes() -> list[Path]:
    return [Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]


def _add_phantoms(tree: InstallTree, models: list[PackageModel], root: Path) -> None:
    tree.system_packages = _index(_user_prefixes())
    available = set(tree.packages) | set(tree.system_packages)
    wanted = {dep.name for model in models for dep in model.manifest.dependencies
              if dep.tag not in ("test_depend", "doc_depend")}
    missing = sorted(name for name in wanted - available if name)
    if not missing:
        return
    tree.phantom = root / "phantom"
    for name in missing:
        (tree.phantom / "share" / name).mkdir(parents=True, exist_ok=True)
        (tree.phantom / INDEX).mkdir(parents=True, exist_ok=True)
        (tree.phantom / INDEX / name).touch()
    tree.phantom_packages = set(missing)


def predicted_tree(models: list[PackageModel]) -> InstallTree:
    temporary = tempfile.TemporaryDirectory(prefix="pkgforge-tree-")
    root = Path(temporary.name)
    prefix = root / "install"
    prefix.mkdir()
    for model in models:
        for destination, installed in model.layout.files.items():
            target = prefix / destination
            target.parent.mkdir(parents=True, exist_ok=True)
            if target.exists() or target.is_symlink():
                continue
            if installed.source is None:
                target.touch()
            else:
                target.symlink_to(installed.source)
    tree = InstallTree("predicted", [prefix], _temporary=temporary)
    tree.packages = _index(tree.prefixes)
    _add_phantoms(tree, models, root)
    return tree


def existing_tree(install_base: Path, models: list[PackageModel]) -> InstallTree:
    install_base = install_base.resolve()
    if not install_base.is_dir():
        raise PkgforgeError(f"--install-base {install_base} is not a folder (run colcon build first)")
    marker = install_base / ".colcon_install_layout"
    layout = marker.read_text().strip() if marker.is_file() else None
    if layout == "isolated" or (layout is None and not (install_base / INDEX).is_dir()):
        prefixes = sorted(p for p in install_base.iterdir() if (p / INDEX).is_dir())
    else:
        prefixes = [install_base]
    if not prefixes:
        raise PkgforgeError(f"--install-base {install_base} holds no ament index: is it a colcon install folder?")
    tree = InstallTree("existing", prefixes)
    tree.packages = _index(prefixes)
    temporary = tempfile.TemporaryDirectory(prefix="pkgforge-tree-")
    tree._temporary = temporary
    _add_phantoms(tree, models, Path(temporary.name))
    return tree


def built_tree(workspace, models: list[PackageModel], *, out=None) -> InstallTree:
    from .build import BuildOptions, run_build

    base = workspace.root / "build" / "pkgforge-verify"
    options = BuildOptions(build_base=base / "build", install_base=base / "install", log_base=base / "log",
                           continue_on_error=True)
    run_build(workspace, options, out=out, colcon_output_to_stderr=True, quiet_failures=True)
    tree = existing_tree(options.install_base, models)
    tree.kind = "built"
    return tree

