"""What a check reads: one package's model, the workspace, the install tree, the resolutions.

Checks never touch the file system themselves (tests/test_conventions.py holds them to it): what
they need of it is a fact of the context, looked up once per run (`CheckContext.files`), the way
catkin_lint's checks read what its on_init computed.
"""

from __future__ import annotations

import os
import re
from collections.abc import Collection
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar

from pkgforge.checks.facts import (
    FileFacts,
    command_line_words,
    environment_reads,
    ignored_under,
    launch_names,
    taken_on_distros,
)
from pkgforge.launch.records import Error as LaunchError
from pkgforge.launch.records import Include, LaunchFile, Resolution
from pkgforge.model.cmake import PYTHON_SITE
from pkgforge.model.manifest import EXPORT_TAGS
from pkgforge.model.package import PackageModel
from pkgforge.model.rviz import RvizConfig
from pkgforge.model.source import read_head, read_regular
from pkgforge.tree import InstallTree

if TYPE_CHECKING:
    from pkgforge.model.manifest import Dependency
    from pkgforge.model.references import Reference
    from pkgforge.model.ros_params import ParametersFile, Problem
    from pkgforge.robot_models import ModelResult
    from pkgforge.simulate import Outcome
    from pkgforge.urdf.meshes import MeshLookup

# an ImportError of a launch name (the built-in engine's message is ROS's own)
BUILTIN_IMPORT_ERROR = re.compile(r"cannot import name '(\w+)' from 'launch[\w.]*'")
# the distros whose own launch name lists the built-in engine has (launch/api_names.json)
GENERATED_LISTS = ("humble", "jazzy")
# pkgforge provides these in the launch worker; a missing submodule of one is a real error
STAND_IN_MODULES = {"launch", "launch_ros", "launch_xml", "launch_yaml", "ament_index_python"}

# why a launch file was not loaded (CheckContext.load_error_kind); None: it was
LoadErrorKind = Literal["load", "package", "xacro", "unevaluated", "newer-api", "environment", "unpredicted"]
# xacro's message for a file it could not open (an include of a package not installed here)
MISSING_FILE = re.compile(r"No such file or directory: \[?'?([^'\]\s]+)")
# the kinds whose launch file's literal references are checked statically instead
STATIC_KINDS: tuple[LoadErrorKind, ...] = ("unevaluated", "newer-api", "environment", "unpredicted")
# what may be a path in an error message or a command line: a word without quotes or brackets
PATH_WORD = re.compile(r"[^\s'\"\[\](),]+")
_T = TypeVar("_T")


# the text None standing in a path or a name for an unset variable (os.getenv('X') + '_robot')
NONE_TEXT = re.compile(r"(^|[/'\"])None([./_'\"-]|$)")

# simulators: they move a model's joints within its URDF limits, as ros2_control does the joints
# its <ros2_control> block names (MoveIt reads a velocity limit of 0 as no limit: robot_model.cpp's
# velocity_bounded_ = max_velocity_ > epsilon; RViz never reads it). A package declared is no use:
# mycobot_ros2 declares controller_manager in 15 packages and starts it nowhere
SIMULATOR_PREFIXES = ("gazebo", "gz_", "ros_gz", "ign_", "ros_ign", "webots")
# a simulator's own program, started by a launch file's ExecuteProcess
SIMULATOR_PROGRAMS = {"gazebo", "gzserver", "gz", "ign", "webots"}
# Gazebo Classic (ODE): every package of it is named gazebo_* (gz-sim's are gz_*, ros_gz_*, ign_*)
CLASSIC_PREFIXES = ("gazebo",)


def only_with(settings: list[str]) -> tuple[str, str | None]:
    """(a note for a message, the full text for its detail) saying which argument settings a
    finding holds under. One setting is named; several combinations ("a:=1 b:=2", "a:=1 b:=3")
    by the settings they all share and their count, the combinations themselves in the detail:
    eight combinations of eight arguments each make no line a person reads."""
    if len(settings) <= 1:
        return (f" (only with {settings[0]})" if settings else ""), None
    parsed = [dict(w.split(":=", 1) for w in setting.split() if ":=" in w) for setting in settings]
    shared = [f"{k}:={v}" for k, v in parsed[0].items() if all(p.get(k) == v for p in parsed[1:])]
    full = "only with " + ", ".join(settings)
    if shared and len(" ".join(shared)) <= 120:
        return f" (only with {' '.join(shared)}: {len(settings)} argument combinations)", full
    if len(full) <= 120:
        return f" ({full})", None
    return f" (only in {len(settings)} argument combinations, e.g. {settings[0][:80]})", full


@dataclass
class CheckContext:
    model: PackageModel
    # every package of the workspace being verified: name → folder
    workspace: dict[str, Path] = field(default_factory=dict)
    # the models of the verified packages, by the name their share folder has
    models: dict[str, PackageModel] = field(default_factory=dict)
    tree: InstallTree | None = None  # when launch files were resolved
    resolutions: list[Resolution] = field(default_factory=list)  # this package's launch files
    ros1_launch_files: list[LaunchFile] = field(default_factory=list)
    model_results: list[ModelResult] = field(default_factory=list)  # this package's robot models
    rviz_configs: list[RvizConfig] = field(default_factory=list)  # this package's own RViz files
    # (RvizConfig, LaunchFile) a launch passes with -d
    rviz_launches: list[tuple[RvizConfig, LaunchFile]] = field(default_factory=list)
    distros: tuple[str, ...] = ()  # the ROS 2 distros the package targets; empty: every active distro
    install_base: Path | None = None  # --install-base, when verifying against one
    workspace_base: Path | None = None  # the folder the workspace's packages are found under
    # the other folders of the workspace whose package has this one's name (colcon build refuses it)
    namesakes: tuple[Path, ...] = ()
    # another of those is what the install tree holds: this one's launch files and models are unchecked
    shadowed: bool = False
    # one dict for every context of a run (the workspace and the tree are the same for each):
    # the package-name sets and file-system facts built once per run, not once per package
    shared: dict[Any, Any] = field(default_factory=dict)
    # files outside the workspace's packages whose content this package's checks used (the cache
    # stamps them: verify/cache.py externals)
    read_elsewhere: set[str] = field(default_factory=set)
    # verify --simulate: each robot model's drop test in MuJoCo, by the model's installed file
    simulations: dict[Path, Outcome] = field(default_factory=dict)

    def _shared(self, key: object, compute: Any) -> Any:
        if key not in self.shared:
            self.shared[key] = compute()
        return self.shared[key]

    @property
    def files(self) -> FileFacts:
        """The file-system facts of this run (one FileFacts for every context sharing `shared`)."""
        facts: FileFacts = self._shared("files", FileFacts)
        return facts

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
        tree = self.tree
        installed: frozenset[str] = self._shared(
            "installed", lambda: frozenset(set(tree.packages) | set(tree.system_packages))
        )
        return installed

    def real_packages(self) -> frozenset[str]:
        """Every name known to be a ROS package here: the workspace's, the tree's, and those
        released for the target distros (any active distro when there is no target)."""
        from pkgforge.model.distro_data import released_set

        def compute() -> frozenset[str]:
            # a name declared somewhere (a phantom in the tree) but released only for other distros
            # is package-not-in-distro's, not a real package here
            foreign = released_set(()) - released_set(self.distros)
            return frozenset(
                set(self.workspace) | (self.tree_packages() - foreign) | released_set(self.distros)
            )

        real: frozenset[str] = self._shared(("real", self.distros), compute)
        return real

    def known_packages(self) -> frozenset[str]:
        """Names that are no typo: real packages, released in any distro, or declared here."""
        from pkgforge.model.distro_data import released_set

        known: frozenset[str] = self._shared(
            ("known", self.distros), lambda: self.real_packages() | released_set(())
        )
        declared = self.model.manifest.declared() | self.source_repositories()
        return known if declared <= known else known | declared

    def source_repositories(self) -> frozenset[str]:
        """Repositories the workspace's vcs .repos files bring in from source (in a package's folder,
        or beside the packages): rosbot_ros builds rosbot_hardware_interfaces from one for humble,
        where it is not released. Their packages are the workspace's once imported."""

        def compute() -> frozenset[str]:
            import yaml

            from pkgforge.model.files import vcs_repos_files
            from pkgforge.model.yamlnodes import load as load_yaml

            names: set[str] = set()
            for path in vcs_repos_files([self.model.path, *self.workspace.values()], self.workspace_base):
                try:
                    data = load_yaml(read_regular(path).decode("utf-8", errors="replace"))
                except (OSError, yaml.YAMLError):  # (past the loader's bounds: a YAMLError too)
                    continue
                repositories = data.get("repositories") if isinstance(data, dict) else None
                if isinstance(repositories, dict):
                    names.update(str(name).rsplit("/", 1)[-1] for name in repositories)
                    # and the repository's own name (src/ur_driver: url .../Universal_Robots_ROS2_Driver.git)
                    for spec in repositories.values():
                        url = str(spec.get("url") or "") if isinstance(spec, dict) else ""
                        if url.strip().rstrip("/"):
                            names.add(url.strip().rstrip("/").removesuffix(".git").rsplit("/", 1)[-1])
                for entry in data if isinstance(data, list) else []:
                    # .rosinstall: - git: {local-name: robotis_controller_msgs, uri: ...ROBOTIS-Framework-msgs.git}
                    for spec in entry.values() if isinstance(entry, dict) else []:
                        if isinstance(spec, dict):
                            for key in ("local-name", "uri"):
                                value = str(spec.get(key) or "").strip().rstrip("/").removesuffix(".git")
                                if value:
                                    names.add(value.rsplit("/", 1)[-1])
            return frozenset(names)

        found: frozenset[str] = self._shared("repositories", compute)
        return found

    def nested_packages(self) -> dict[str, Path]:
        """The packages inside this one's folders (each with its own package.xml), name → folder:
        colcon does not look inside a package, so they are templates or data the package ships
        (clearpath's project_bringup inside clearpath_customization); their own files name them."""
        model = self.model

        def compute() -> dict[str, Path]:
            from pkgforge.model.files import quick_name

            return {quick_name(model.path / folder): model.path / folder for folder in model.nested_packages}

        found: dict[str, Path] = self._shared(("nested", str(model.path)), compute)
        return found

    def text_head(self, path: str) -> str:
        """The first MiB of a text file ('' when it cannot be read), read once per run."""

        def compute() -> str:
            try:
                return read_head(path, 1 << 20)[0].decode("utf-8", errors="replace")
            except OSError:  # (a FIFO or a device too: never read)
                return ""

        head: str = self._shared(("head", path), compute)
        return head

    def yaml_file(self, path: str) -> str | None:
        """A YAML file a launch file hands a node (a parameters file, a bridge config), read once
        per run: its text, None when it cannot be read (missing, unreadable, past the reading
        limit, not UTF-8). A file outside this package is stamped for the cache."""
        from pkgforge.model.source import read_source

        if not path or not os.path.isabs(path):
            return None  # (a relative path is the started node's, from its own folder)
        text: str | None = self._shared(("yaml-file", path), lambda: read_source(Path(path)).text)
        if self.own_source(path) is None:
            self.read_elsewhere.add(path)
        return text

    def parameters_file(self, path: str) -> ParametersFile | None:
        """A parameters file (--params-file) as rcl reads it; None when it cannot be read."""
        from pkgforge.model.ros_params import ParametersFile, read_parameters

        text = self.yaml_file(path)
        if text is None:
            return None
        if "$(" in text:
            # ParameterFile(..., allow_substs=True): what rcl reads is the text with the
            # substitutions made (launch_ros writes it to a file of its own); not judged here
            return ParametersFile(judged=False)
        found: ParametersFile = self._shared(("parameters-file", text), lambda: read_parameters(text))
        return found

    def bridge_config(self, path: str) -> list[Problem] | None:
        """What ros_gz_bridge refuses in a config_file; None when it cannot be read."""
        from pkgforge.model.ros_params import read_bridge_config

        text = self.yaml_file(path)
        if text is None:
            return None
        found: list[Problem] = self._shared(("bridge-config", text), lambda: read_bridge_config(text))
        return found

    def depends_on(self, start: str, goal: str) -> bool:
        """Whether workspace package `start` depends on `goal` through the declared dependencies
        of workspace packages (any tag but doc_depend: colcon orders by all of them), so that a
        dependency of `goal` on `start` would be a cycle colcon refuses to order."""
        edges: dict[str, set[str]] = self._shared(("dependency-edges", self.distros), self._dependency_edges)
        seen, todo = {start}, [start]
        while todo:
            for name in edges.get(todo.pop(), ()):
                if name == goal:
                    return True
                if name not in seen:
                    seen.add(name)
                    todo.append(name)
        return False

    def simulator_feeding(self, result: ModelResult) -> str | None:
        """What runs a simulator in a launch file that feeds this model to xacro (it simulates
        the model's joints within their limits), as a message names it; None: none does."""
        for origin in result.origins:
            resolution = next((r for r in self.resolutions if r.launch == origin["launch"]), None)
            if resolution is None:
                continue
            for node in resolution.nodes:
                program = os.path.basename(node.cmd[0]) if node.cmd else None
                if (node.package or "").startswith(SIMULATOR_PREFIXES) or program in SIMULATOR_PROGRAMS:
                    name = resolution.launch.source or resolution.launch.installed
                    what = f"{node.package} {node.executable}" if node.package else program
                    return f"{Path(name).name}'s simulator ({what})"
            for lookup in resolution.packages:
                if lookup.name.startswith(SIMULATOR_PREFIXES) and lookup.name not in ("gazebo_msgs",):
                    name = resolution.launch.source or resolution.launch.installed
                    return f"{Path(name).name}'s simulator ({lookup.name})"
        return None

    def uses_gazebo_classic(self) -> bool:
        """Whether a package of the workspace declares a Gazebo Classic package (gazebo_ros, ...)."""
        return self._workspace_declares(CLASSIC_PREFIXES)

    def _workspace_declares(self, prefixes: tuple[str, ...]) -> bool:
        edges: dict[str, set[str]] = self._shared(("dependency-edges", self.distros), self._dependency_edges)
        return any(name.startswith(prefixes) for names in edges.values() for name in names)

    def brought_along(self, name: str, tags: tuple[str, ...]) -> str | None:
        """The dependency package.xml declares with one of `tags` (holding on every target
        distro) whose install brings `name` along, in every target distro: through the
        workspace's own manifests and the core packages' table (model/exports.py)."""
        from pkgforge.model.exports import brought_by

        declared = {
            d.name
            for d in self.model.manifest.active_dependencies()
            if d.tag in tags and d.holds_on_every(self.distros)
        }
        return brought_by(name, declared, self.distros, self.workspace_exports())

    def workspace_exports(self) -> dict[str, set[str]]:
        """Workspace package name → what its install brings along (its <depend>, <exec_depend>,
        <build_export_depend>, <buildtool_export_depend>), conditions evaluated."""

        def compute() -> dict[str, set[str]]:
            # (an export under a condition may hold on some target distros only: it brings
            # nothing along for sure, and a lowered error must hold on every one)
            return {
                name: {
                    d.name for d in dependencies if d.tag in EXPORT_TAGS and d.holds_on_every(self.distros)
                }
                for name, dependencies in self._workspace_dependencies().items()
            }

        found: dict[str, set[str]] = self._shared(("workspace-exports", self.distros), compute)
        return found

    def _workspace_dependencies(self) -> dict[str, list[Dependency]]:
        """Every workspace package's active dependencies (their conditions evaluated for the
        target distros, comments being no elements): the loaded models', and the other folders'
        manifests read here, so a package verified alone sees what the workspace run sees."""

        def compute() -> dict[str, list[Dependency]]:
            from pkgforge.model.manifest import load_manifest
            from pkgforge.model.source import read_source

            # (the dependencies as parsed whatever catkin_pkg's validation says of the rest of the
            # manifest, their conditions evaluated for this package's target distros)
            out: dict[str, list[Dependency]] = {}
            for model in [*self.models.values(), self.model]:
                out.setdefault(model.name, [d for d in model.manifest.dependencies if d.active(self.distros)])
            for name, folder in self.workspace.items():
                if name not in out:
                    # (its dependencies only: catkin_pkg's validation is that package's own run's)
                    manifest = load_manifest(read_source(folder / "package.xml"), validate=False)
                    out[name] = [d for d in manifest.dependencies if d.active(self.distros)]
            return out

        found: dict[str, list[Dependency]] = self._shared(("workspace-dependencies", self.distros), compute)
        return found

    def _dependency_edges(self) -> dict[str, set[str]]:
        """Workspace package name → the names its package.xml declares (doc_depend left out)."""
        return {
            name: {d.name for d in dependencies if d.tag != "doc_depend"}
            for name, dependencies in self._workspace_dependencies().items()
        }

    def ignored_packages(self) -> dict[str, tuple[Path, Path]]:
        """The packages in the workspace's folders that an ignore marker (COLCON_IGNORE,
        AMENT_IGNORE, CATKIN_IGNORE) keeps colcon from building: name → (folder, the marker
        file), the first folder of each name. doosan-robot2's moveit_config_m1013, looked up by
        another package's launch file, is in no workspace colcon sees while its folder is right
        there. Walked once per run, and only when a lookup found no package."""
        found, read = self._shared(
            ("ignored", str(self.workspace_base)), lambda: ignored_under(self.workspace_base)
        )
        # the hint depends on them: a cached answer must not outlive a change to them
        self.read_elsewhere.update(read)
        result: dict[str, tuple[Path, Path]] = found
        return result

    def install_base_packages(self) -> Collection[str]:
        """Packages the install base (--install-base) holds: the tree's, else those its ament index
        names (a merged or an isolated install)."""
        if self.tree is not None:
            return self.tree.packages  # (a mapping: membership without a copy per package)
        if self.install_base is None:
            return frozenset()
        from pkgforge.tree import INDEX

        base = Path(self.install_base)
        return self.files.names(base / INDEX, "*") | self.files.names(base, f"*/{INDEX}/*")

    # --- locations ----------------------------------------------------------------------------

    def own_source(self, installed: str) -> Path | None:
        """The source of an installed file of this package (a model, an include), else None."""
        from pkgforge.launch.resolve import source_of

        return source_of(Path(installed), self.tree, self.model) if self.tree is not None else None

    def model_files_read(self) -> set[Path] | None:
        """The package's own files some processed robot model reads (the model, its includes);
        None when one failed (what it would have included is not known)."""
        if not self.model_results:
            return None  # no model of its own: its model files are for other packages to include
        read: set[Path] = set()
        for result in self.model_results:
            if result.status != "ok":
                return None
            for installed in [str(result.installed), *result.includes]:
                source = self.own_source(installed)
                if source is not None:
                    read.add(source)
            if result.source is not None:
                read.add(result.source)
        return read

    def file_part(self, resolution: Resolution, path: str) -> str:
        """The path a launch file resolved, or its file part when what uses it splits it as a
        command line (command_line_words): the file that must exist."""
        if not any(c.isspace() for c in path):
            return path
        words = command_line_words(resolution, path)
        return words[0] if words else path

    def unpredicted_file(self, text: str | None) -> tuple[str, str] | None:
        """(package, path in its share folder) when `text` (a path, an error message) names a file
        the predicted tree does not have, in the share folder of a workspace package whose install
        pkgforge cannot predict (tree.unpredicted): whether the real install has it is not known."""
        tree = self.tree
        if not text or tree is None or not tree.unpredicted:
            return None

        def compute() -> tuple[str, str] | None:
            for word in PATH_WORD.findall(text):
                if not (word.startswith("share/") or "/share/" in word):
                    continue
                # xacro names a file relative to the prefix it searched
                paths = [word] if os.path.isabs(word) else [str(prefix / word) for prefix in tree.prefixes]
                for path in paths:
                    located = tree.locate(path)
                    if located is not None and located[0] in tree.unpredicted and not self.files.exists(path):
                        return located[0], located[1]
            return None

        found: tuple[str, str] | None = self._shared(("unpredicted", text), compute)
        return found

    def unpredicted_where(self, package: str) -> str:
        """Where a package's install stops being predicted: 'setup.py:4', for messages."""
        where = self.tree.unpredicted.get(package) if self.tree is not None else None
        if where is None:
            return package
        path, line = where
        return f"{path.name}:{line}" if line else path.name

    def absent_include(self, message: str | None) -> tuple[str, str] | None:
        """(package, file) when xacro failed only because it includes a file of a package that
        is declared but not installed here (its share folder an empty stand-in): ROS has the file."""
        found = MISSING_FILE.search(str(message or ""))
        tree = self.tree
        if found is None or tree is None or tree.phantom is None:
            return None
        path = found.group(1)
        if not os.path.isabs(path):  # xacro names it relative to the stand-ins' prefix
            path = str(tree.phantom / path)
        located = tree.locate(path) if tree.is_phantom(path) else None
        if located is None or located[0] not in tree.phantom_packages:
            return None
        return located[0], located[1]

    def source_position(
        self, resolution: Resolution, item_file: str | None, line: int | None
    ) -> tuple[Path, int | None] | None:
        """(source path, line) of a construct, or None when it stands in another package's file."""
        launch = resolution.launch
        if item_file is None or item_file == str(launch.installed):
            return (launch.source or launch.installed), line
        source = self.own_source(item_file)
        return (source, line) if source is not None else None

    def mesh(self, uri: str, model_file: Path) -> MeshLookup:
        """A mesh URI resolved in the tree (a relative one next to the model file), once per run:
        every mesh check reads the same lookup."""
        from pkgforge.urdf.meshes import resolve_uri

        tree = self.tree
        if tree is None:
            raise ValueError("mesh URIs are resolved in an install tree; this context has none")
        lookup: MeshLookup = self._shared(
            ("mesh", uri, model_file), lambda: resolve_uri(uri, tree, model_file)
        )
        return lookup

    def mesh_problem(self, path: Path) -> str | None:
        """Why a mesh file is not a readable mesh of its kind (urdf.meshes.unreadable), None if it is."""
        from pkgforge.urdf.meshes import unreadable

        problem: str | None = self._shared(("mesh-problem", path), lambda: unreadable(path))
        return problem

    def file_exists_for_rviz(self, reference: str) -> bool:
        """A Description File as RViz reads it: an absolute path, or package://."""
        if reference.startswith("package://") and self.tree is not None:
            from pkgforge.urdf.meshes import resolve_uri

            tree = self.tree
            lookup: MeshLookup = self._shared(("mesh", reference, None), lambda: resolve_uri(reference, tree))
            return lookup.status in ("found", "unchecked")
        return self.files.is_file(reference)

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

    def load_error_kind(self, resolution: Resolution) -> LoadErrorKind | None:
        """None (loaded), or why not."""
        if resolution.status == "ok":
            return None
        error = resolution.error
        if resolution.status != "load-error" or error is None:
            return "load"
        if error.type == "PackageNotFoundError":
            return "package"
        if self.unpredicted_file(error.message) is not None:
            return "unpredicted"  # a file of a package whose install is not known: not its fault
        if error.type == "XacroException":
            return "xacro"
        if self.package_not_installed_here(error) or error.program or error.read_from:
            # (error.program: a program it runs or finds at load, by name, that this machine lacks)
            return "unevaluated"
        if self.newer_launch_name(resolution) is not None:
            return "newer-api"
        if (error.type == "KeyError" or self.unset_variable(error)) and self.unset_environment(resolution):
            return "environment"
        return "load"

    def package_not_installed_here(self, error: LaunchError) -> bool:
        """Whether an error is the import of a ROS package's module that is not installed on this
        machine: declared or not (an undeclared one is missing-exec-depend's), on the user's
        machine it may well be installed, so the failure here is not the launch file's."""
        # the module's own name, or the package whose folder the file put on sys.path for it
        module = error.package or (error.module or "").split(".")[0]
        declared = self.model.manifest.declared()
        # a Python library the package declares by its rosdep key (usb_cam: python3-pydantic)
        keys = {f"python3-{name}" for name in (module.lower(), module.lower().replace("_", "-"))}
        return (
            error.type == "ModuleNotFoundError"
            and bool(module)
            and module not in STAND_IN_MODULES
            and (
                module in declared
                or bool(keys & declared)
                or module in self.tree_packages()
                or module in self.real_packages()
                or self.through_workspace_module(error)
            )
        )

    def through_workspace_module(self, error: LaunchError) -> bool:
        """Whether a module was not found by the import of a workspace package's Python module
        (at the launch file's line that imports it): that module's own imports, which its
        package declares and rosdep installs on the user's machine (audit_helpers' `import cv2`)."""
        source = self.own_source(error.file) if error.file else None
        if source is None or error.line is None:
            return False
        imported = {
            r.package
            for r in self.model.references
            if r.via == "import" and r.path == source and r.line == error.line
        }
        missing = (error.module or "").split(".")[0]
        return bool(imported & self.workspace_python_modules()) and missing not in imported

    def workspace_python_modules(self) -> frozenset[str]:
        """The top-level Python modules the verified packages install (setup.py's packages=,
        ament_python_install_package): what the tree puts on a launch file's sys.path."""

        def compute() -> frozenset[str]:
            prefix = PYTHON_SITE + "/"
            return frozenset(
                destination[len(prefix) :].split("/")[0].removesuffix(".py")
                for model in [self.model, *self.models.values()]
                for destination in model.layout.files
                if destination.startswith(prefix)
            )

        modules: frozenset[str] = self._shared("workspace-python-modules", compute)
        return modules

    def none_from_unset(self, resolution: Resolution, text: str) -> list[str]:
        """The unset variables the file reads when `text` (a name, a path, an error message) has
        the text None in it where a name was built ('urdf/None_robot.xacro', 'None_moveit'):
        os.getenv('DOBOT_TYPE') may have given it. Not proven (a dict.get() may have too), so
        what is said of it is a warning that names the variables, not silence."""
        return self.unset_environment(resolution) if NONE_TEXT.search(text) else []

    def unset_environment(self, resolution: Resolution) -> list[str]:
        """Environment variables the launch file reads without a default and that are not set
        here, when its loading failed on one (os.environ['X'] → KeyError) or a path it resolved
        has the text None from one (os.getenv('X'))."""
        source = resolution.launch.source
        if source is None or source.suffix != ".py":
            return []
        reads: list[str] = self._shared(("environment-reads", source), lambda: environment_reads(source))
        unset = [n for n in reads if n not in os.environ]
        error = resolution.error
        if resolution.status == "load-error" and error is not None:
            variable = self.unset_variable(error)  # EnvironmentVariable('X') performed while loading
            if variable is not None:
                return [variable]
            if error.type == "KeyError":
                key = re.search(r"'([^']+)'", str(error.message or ""))
                return [key.group(1)] if key and key.group(1) in unset else []
        return unset

    @staticmethod
    def unset_variable(error: LaunchError) -> str | None:
        """The environment variable an EnvironmentVariable substitution without a default failed
        on, when it is not set here either (`EnvironmentVariable('USER')`: the user's shell sets
        it); None for any other failure, and for a variable set here that the file unset itself."""
        if error.variable and error.variable not in os.environ:
            return error.variable
        return None

    def variable_unset_here(self, message: str | None) -> bool:
        """Whether a KeyError's message names an environment variable one of this package's launch
        files reads without a default and that is not set here (the robot's own setup sets it)."""
        key = re.search(r"'([^']+)'", str(message or ""))
        return key is not None and any(key.group(1) in self.unset_environment(r) for r in self.resolutions)

    def newer_launch_name(self, resolution: Resolution) -> str | None:
        """The launch API name the built-in engine lacks where its list is only the nearest older
        distro's and no list has it (a name new in Kilted or later, e.g. PathSubstitution, is real
        there; a typo looks the same): None where the ImportError is ROS's."""
        from pkgforge.model.distro_data import active_distros

        error = resolution.error
        found = BUILTIN_IMPORT_ERROR.search(str(error.message or "")) if error is not None else None
        if error is None or error.type != "ImportError" or found is None or resolution.engine != "builtin":
            return None
        later = any(d not in GENERATED_LISTS for d in self.distros or active_distros())
        if not later or found.group(1) in launch_names():
            return None  # the target's own list, or a real name imported from the wrong module
        return found.group(1)

    def static_fallback(self) -> dict[Path, list[Reference]]:
        """Static references of the launch files that could not be evaluated here, or did not
        load (a use in a branch on $ROS_DISTRO that no target distro takes left out)."""
        out: dict[Path, list[Reference]] = {}
        for resolution in self.resolutions:
            # (a file stopped by an unset environment variable: what it names literally is still its own)
            if resolution.launch.source and self.read_statically(resolution):
                out[resolution.launch.source] = [
                    r
                    for r in self.model.references
                    if r.path == resolution.launch.source
                    and self.branch_on_distros(r.python_branch) is not False
                ]
        return out

    def read_statically(self, resolution: Resolution) -> bool:
        """Whether what a launch file names literally is checked statically: it could not be
        evaluated here (STATIC_KINDS), or it did not load (an ImportError, a NameError, a
        SyntaxError, an exception before generate_launch_description returned: `ros2 launch`
        fails the same way, and its packages and files are still its own). Not a file that only
        fails launched alone, which another launch file of the package includes and evaluates."""
        kind = self.load_error_kind(resolution)
        if kind in STATIC_KINDS:
            return True
        return kind is not None and self.included_and_loaded(resolution) is None

    def failed_to_load(self, source: Path) -> Resolution | None:
        """The resolution of the launch file `source` when it did not load (read statically for
        that reason, not because this machine lacks what it needs): its static findings say so."""
        return next(
            (
                r
                for r in self.resolutions
                if r.launch.source == source
                and self.load_error_kind(r) not in (None, *STATIC_KINDS)
                and self.included_and_loaded(r) is None
            ),
            None,
        )

    def included_and_loaded(self, resolution: Resolution) -> tuple[Resolution, Include] | None:
        """(includer, include) when another launch file of the package includes this one with a
        launch argument it does not declare and evaluates it without an error there: a file made
        to be included (xarm's _robot_on_mbot_gazebo.launch.py, given moveit_config_dump by its
        includer) that fails only when launched on its own."""
        installed = str(resolution.launch.installed)
        # what the file declares: an includer's value for one of those is one more setting, which its
        # own branches cover (robot.launch.py's use_sim_time:=true through sim.launch.py is no reason
        # to excuse its failure with the default false); only a value it does not declare is the
        # includer's to give (xarm's moveit_config_dump, read with LaunchConfiguration(..., default=''))
        declared = {argument.name for argument in resolution.arguments}
        for other in self.resolutions:
            if other is resolution or other.status != "ok" or installed not in other.files:
                continue
            include = next(
                (i for i in other.includes if i.path == installed and set(i.arguments) - declared), None
            )
            if include is None:
                continue
            includer_file = str(other.launch.installed)
            if any(
                item.file == installed or (item.file in (None, includer_file) and item.line == include.line)
                for item in other.errors
            ):
                continue  # it fails there too (in the file, or at the include): an error, said there
            return other, include
        return None

    def branch_on_distros(self, branch: str | None) -> bool | None:
        """Whether a Python branch on $ROS_DISTRO ("if os.environ.get('ROS_DISTRO') == 'humble'",
        "else of if …") is taken on every target distro (True), on none (False); None when it
        tests something else, or holds on some only (every active distro when none is targeted)."""
        return taken_on_distros(branch, self.distros)

    def folders_reported_uninstalled(self) -> set[str]:
        """Own top-level folders a launch file or a model's mesh resolves into but the tree lacks."""
        folders: set[str] = set()
        if self.tree is None:
            return folders
        own = (self.model.share_name, self.model.name)
        for result in self.model_results:
            for mesh in result.robot["meshes"] if result.robot else []:
                uri = mesh["uri"]
                if uri.startswith("package://"):
                    package, _, relative = uri[len("package://") :].partition("/")
                    share = self.tree.share(package)
                    if (
                        package in own
                        and self.files.is_file(self.model.path / relative)
                        and share is not None
                        and not self.files.exists(share / relative)
                    ):
                        folders.add(relative.split("/")[0])
        for resolution in self.resolutions:
            for item in resolution.paths:
                if item.exists:
                    continue
                located = self.tree.locate(self.file_part(resolution, item.path))
                if (
                    located
                    and located[0] in (self.model.share_name, self.model.name)
                    and self.files.exists(self.model.path / located[1])
                ):
                    folders.add(located[1].split("/")[0])
        return folders
