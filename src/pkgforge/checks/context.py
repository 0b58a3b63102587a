"""What a check reads: one package's model, the workspace, the install tree, the resolutions."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from pkgforge.model.package import PackageModel

# an ImportError of a launch name (the built-in engine's message is ROS's own)
BUILTIN_IMPORT_ERROR = re.compile(r"cannot import name '(\w+)' from 'launch[\w.]*'")
# the distros whose own launch name lists the built-in engine has (launch/api_names.json)
GENERATED_LISTS = ("humble", "jazzy")
# pkgforge provides these in the launch worker; a missing submodule of one is a real error
STAND_IN_MODULES = {"launch", "launch_ros", "launch_xml", "launch_yaml", "ament_index_python"}


@dataclass
class CheckContext:
    model: PackageModel
    # every package of the workspace being verified: name → folder
    workspace: dict[str, Path] = field(default_factory=dict)
    # the models of the verified packages, by the name their share folder has
    models: dict[str, PackageModel] = field(default_factory=dict)
    tree: object | None = None  # trees.InstallTree, when launch files were resolved
    resolutions: list = field(default_factory=list)  # launch.resolve.Resolution of this package
    ros1_launch_files: list = field(default_factory=list)
    model_results: list = field(default_factory=list)  # models.ModelResult of this package
    rviz_configs: list = field(default_factory=list)  # rviz.RvizConfig of this package's own files
    rviz_launches: list = field(default_factory=list)  # (RvizConfig, LaunchFile) a launch passes with -d
    distros: tuple = ()  # the ROS 2 distros the package targets; empty: every active distro
    install_base: Path | None = None  # --install-base, when verifying against one
    # one dict for every context of a run (the workspace and the tree are the same for each):
    # the package-name sets built once per run, not once per package
    shared: dict = field(default_factory=dict)

    def relative(self, path: Path) -> str:
        try:
            return str(path.relative_to(self.model.path))
        except ValueError:
            return str(path)

    # --- packages -----------------------------------------------------------------------------

    def model_for_share(self, package: str) -> PackageModel | None:
        if package in (self.model.share_name, self.model.name):
            return self.model
        return self.models.get(package)

    def tree_packages(self) -> set[str]:
        """Packages a lookup finds: in the tree, declared (phantom), or already installed."""
        if self.tree is None:
            return set()
        return set(self.tree.packages) | set(self.tree.phantom_packages) | set(self.tree.system_packages)

    def installed_packages(self) -> frozenset[str]:
        """Packages the tree holds or finds already installed (built once per run, not per call)."""
        if self.tree is None:
            return frozenset()
        if "installed" not in self.shared:
            self.shared["installed"] = frozenset(set(self.tree.packages) | set(self.tree.system_packages))
        return self.shared["installed"]

    def real_packages(self) -> set[str]:
        """Every name known to be a ROS package here: the workspace's, the tree's, and those
        released for the target distros (any active distro when there is no target)."""
        from pkgforge.model.distro_data import released_set

        key = ("real", self.distros)
        if key not in self.shared:
            # a name declared somewhere (a phantom in the tree) but released only for other distros
            # is package-not-in-distro's, not a real package here
            foreign = released_set(()) - released_set(self.distros)
            self.shared[key] = frozenset(
                set(self.workspace) | (self.tree_packages() - foreign) | released_set(self.distros)
            )
        return self.shared[key]

    def known_packages(self) -> set[str]:
        """Names that are no typo: real packages, released in any distro, or declared here."""
        from pkgforge.model.distro_data import released_set

        key = ("known", self.distros)
        if key not in self.shared:
            self.shared[key] = self.real_packages() | released_set(())
        known, declared = self.shared[key], self.model.manifest.declared()
        return known if declared <= known else known | declared

    # --- locations ----------------------------------------------------------------------------

    def own_source(self, installed: str) -> Path | None:
        """The source of an installed file of this package (a model, an include), else None."""
        from pkgforge.launch.resolve import source_of

        return source_of(Path(installed), self.tree, self.model) if self.tree is not None else None

    def source_position(self, resolution, item_file: str | None, line: int | None):
        """(source path, line) of a construct, or None when it stands in another package's file."""
        launch = resolution.launch
        if item_file is None or item_file == str(launch.installed):
            return (launch.source or launch.installed), line
        source = self.own_source(item_file)
        return (source, line) if source is not None else None

    def file_exists_for_rviz(self, reference: str) -> bool:
        """A Description File as RViz reads it: an absolute path, or package://."""
        if reference.startswith("package://") and self.tree is not None:
            from pkgforge.urdf.meshes import resolve_uri

            return resolve_uri(reference, self.tree).status in ("found", "unchecked")
        return os.path.isfile(reference)

    def static_line(self, path: Path, package: str, relative: str, near: int | None = None) -> int | None:
        """The line where the file names package/relative literally, if it does (the one
        nearest `near` when it does on several lines)."""
        lines = [
            r.line
            for r in self.model.references
            if r.path == path and r.package == package and r.relative == relative
        ]
        if not lines:
            return None
        return min(lines, key=lambda n: (abs(n - near), n)) if near is not None else lines[0]

    # --- launch results -----------------------------------------------------------------------

    def load_error_kind(self, resolution) -> str | None:
        """None (loaded), or why not: load | package | xacro | unevaluated."""
        if resolution.status == "ok":
            return None
        error = resolution.error
        if resolution.status != "load-error" or error is None:
            return "load"
        if error.type == "PackageNotFoundError":
            return "package"
        if error.type == "XacroException":
            return "xacro"
        module = (error.module or "").split(".")[0]
        if (
            error.type == "ModuleNotFoundError"
            and module
            and module not in STAND_IN_MODULES
            and (module in self.model.manifest.declared() or module in self.tree_packages())
        ):
            return "unevaluated"
        if self.newer_launch_name(resolution) is not None:
            return "newer-api"
        if error.type == "KeyError" and self.unset_environment(resolution):
            return "environment"
        return "load"

    def unset_environment(self, resolution) -> list[str]:
        """Environment variables the launch file reads without a default and that are not set
        here, when its loading failed on one (os.environ['X'] → KeyError) or a path it resolved
        has the text None from one (os.getenv('X'))."""
        source = resolution.launch.source
        if source is None or source.suffix != ".py":
            return []
        unset = [n for n in _environment_reads(source) if n not in os.environ]
        error = resolution.error
        if resolution.status == "load-error" and error is not None and error.type == "KeyError":
            key = re.search(r"'([^']+)'", str(error.message or ""))
            return [key.group(1)] if key and key.group(1) in unset else []
        return unset

    def newer_launch_name(self, resolution) -> str | None:
        """The launch API name the built-in engine lacks where its list is only the nearest older
        distro's and no list has it (a name new in Kilted or later, e.g. PathSubstitution, is real
        there; a typo looks the same): None where the ImportError is ROS's."""
        from pkgforge.model.distro_data import active_distros

        error = resolution.error
        found = BUILTIN_IMPORT_ERROR.search(str(error.message or "")) if error is not None else None
        if error is None or error.type != "ImportError" or found is None or resolution.engine != "builtin":
            return None
        later = any(d not in GENERATED_LISTS for d in self.distros or active_distros())
        if not later or found.group(1) in _launch_names():
            return None  # the target's own list, or a real name imported from the wrong module
        return found.group(1)

    def static_fallback(self) -> dict[Path, list]:
        """Static references of the launch files that could not be evaluated here."""
        out: dict[Path, list] = {}
        for resolution in self.resolutions:
            if self.load_error_kind(resolution) in ("unevaluated", "newer-api") and resolution.launch.source:
                out[resolution.launch.source] = [
                    r for r in self.model.references if r.path == resolution.launch.source
                ]
        return out

    def folders_reported_uninstalled(self) -> set[str]:
        """Own top-level folders a launch file or a model's mesh resolves into but the tree lacks."""
        folders = set()
        if self.tree is None:
            return folders
        own = (self.model.share_name, self.model.name)
        for result in self.model_results:
            for mesh in (result.robot or {}).get("meshes", []):
                uri = mesh["uri"]
                if uri.startswith("package://"):
                    package, _, relative = uri[len("package://") :].partition("/")
                    if (
                        package in own
                        and os.path.isfile(self.model.path / relative)
                        and self.tree.share(package) is not None
                        and not os.path.exists(self.tree.share(package) / relative)
                    ):
                        folders.add(relative.split("/")[0])
        for resolution in self.resolutions:
            for item in resolution.paths:
                if item.exists:
                    continue
                located = self.tree.locate(item.path)
                if (
                    located
                    and located[0] in (self.model.share_name, self.model.name)
                    and os.path.exists(self.model.path / located[1])
                ):
                    folders.add(located[1].split("/")[0])
        return folders


def _environment_reads(source: Path) -> list[str]:
    """Names a Python launch file reads with os.environ['X'], os.getenv('X') or os.environ.get('X')
    without a default."""
    import ast

    try:
        text = source.read_text(encoding="utf-8", errors="replace")
        if "environ" not in text and "getenv" not in text:
            return []  # every form below names one of them: no parse needed
        tree = ast.parse(text)
    except (OSError, SyntaxError, ValueError):
        return []
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Subscript) and ast.unparse(node.value) in ("os.environ", "environ"):
            key = node.slice
        elif (
            isinstance(node, ast.Call)
            and len(node.args) == 1
            and not node.keywords
            and ast.unparse(node.func) in ("os.getenv", "getenv", "os.environ.get", "environ.get")
        ):
            key = node.args[0]
        else:
            continue
        if isinstance(key, ast.Constant) and isinstance(key.value, str) and key.value not in names:
            names.append(key.value)
    return names


_names: set | None = None


def _launch_names() -> set[str]:
    """Every name of launch and launch_ros in the distros the built-in engine has lists of."""
    global _names
    if _names is None:
        import json

        data_file = Path(__file__).resolve().parent.parent / "launch" / "api_names.json"
        with open(data_file, encoding="utf-8") as handle:
            data = json.load(handle)["distros"]
        _names = {
            name
            for lists in data.values()
            for module in lists["modules"].values()
            for name in module.get("names", {})
        }
    return _names
