"""`pkgforge new`: options → a PackageSpec → rendered files → moved into place atomically."""

from __future__ import annotations

import getpass
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jinja2

from pkgforge import DISTRIBUTION, __version__
from pkgforge.errors import PkgforgeError
from pkgforge.model.catkin import InvalidPackage, parse_package_string
from pkgforge.model.distros import DISTROS, Distro, default_distro
from pkgforge.model.names import REP144_RULE, rep144_advice, rep144_problem
from pkgforge.model.simulation import gz_names
from pkgforge.model.source import FileTooLarge, read_regular
from pkgforge.scaffold.kinds import BUILD_TYPES, CI_SYSTEMS, LAUNCH_FORMATS
from pkgforge.scaffold.stl import binary_stl, box_triangles

# catkin_pkg's own rule, so a bad address fails here, not later in CMake
EMAIL_PATTERN = re.compile(
    r"^[-a-zA-Z0-9_%+]+(\.[-a-zA-Z0-9_%+]+)*@[-a-zA-Z0-9%]+(\.[-a-zA-Z0-9%]+)*\.[a-zA-Z]{2,}$"
)

# What the generated launch file starts or looks up, hence what must be an
# exec_depend (user story 6). rviz_default_plugins provides the RViz displays.
BASE_EXEC_DEPENDS = (
    "joint_state_publisher",
    "joint_state_publisher_gui",
    "robot_state_publisher",
    "rviz2",
    "rviz_default_plugins",
    "xacro",
)
LAUNCH_FORMAT_DEPENDS = {
    "py": ("launch", "launch_ros"),
    "xml": ("launch", "launch_ros", "launch_xml"),
    "yaml": ("launch", "launch_ros", "launch_yaml"),
}

# `new --sim gz`: what sim.launch.py starts and the controllers it spawns (+ the distro's
# gz_ros2_control or ign_ros2_control), and the folders of the world and the controllers
SIM_EXEC_DEPENDS = (
    "controller_manager",
    "joint_state_broadcaster",
    "joint_trajectory_controller",
    "ros_gz_bridge",
    "ros_gz_sim",
)
SIM_FOLDERS = ("config", "worlds")

# The mesh the scaffold writes: a 4 cm x 4 cm x 30 cm arm segment.
ARM_MESH_SIZE = (0.04, 0.04, 0.3)


@dataclass(frozen=True)
class PackageSpec:
    """Everything that decides what `pkgforge new` writes."""

    name: str
    distro: Distro
    build_type: str = "ament_cmake"
    launch_format: str = "py"
    maintainer_name: str = "todo"
    maintainer_email: str = "todo@todo.todo"
    license: str = "Apache-2.0"
    description: str = ""
    version: str = "0.0.0"
    ci: tuple[str, ...] = field(default=())
    # `new --distro` given: pkgforge.toml records it, so verify and fix target that distro
    record_distro: bool = False
    # an existing robot brought in (`new --from-urdf`, `migrate`): its model file (in urdf/),
    # the RViz Fixed Frame, the folders it has, more exec_depends and the people of its manifest
    model_name: str | None = None
    fixed_frame: str = "base_link"
    resource_folders: tuple[str, ...] | None = None
    extra_exec_depends: tuple[str, ...] = ()
    launch_files: tuple[str, ...] = ()
    maintainers: tuple[tuple[str, str], ...] = ()
    licenses: tuple[str, ...] = ()
    authors: tuple[tuple[str, str | None], ...] = ()
    urls: tuple[tuple[str, str], ...] = ()
    # migrate: the source's <description> content as XML (its <p>s kept), written as it is
    description_xml: str | None = None
    sim: str | None = None  # "gz": a Gazebo world, a spawn launch file, ros2_control and controllers

    @property
    def folders(self) -> tuple[str, ...]:
        """Resource folders the package gets; each one is installed to share/<name>/."""
        folders = self.resource_folders or ("launch", "meshes", "rviz", "urdf")
        return tuple(sorted({*folders, *SIM_FOLDERS})) if self.sim else folders

    @property
    def gz(self) -> dict[str, str]:
        """The names the distro's Gazebo and its ros2_control plugin answer to (gz_names)."""
        return gz_names(self.distro.name)

    @property
    def exec_depends(self) -> list[str]:
        if self.launch_files:  # migrated: what its launch files use, no more
            return sorted(set(self.extra_exec_depends))
        return sorted(
            set(BASE_EXEC_DEPENDS)
            | set(LAUNCH_FORMAT_DEPENDS[self.launch_format])
            | set(self.extra_exec_depends)
            | (set(SIM_EXEC_DEPENDS) | {self.gz["control"]} if self.sim else set())
        )

    @property
    def launch_file(self) -> str:
        return f"launch/display.launch.{self.launch_format}"

    @property
    def launch_comment(self) -> str:
        return ", ".join(self.launch_files or (self.launch_file,))

    @property
    def all_maintainers(self) -> tuple[tuple[str, str], ...]:
        return self.maintainers or ((self.maintainer_name, self.maintainer_email),)

    @property
    def all_licenses(self) -> tuple[str, ...]:
        return self.licenses or (self.license,)

    @property
    def model_file(self) -> str:
        return f"urdf/{self.model_name or self.name + '.urdf.xacro'}"

    @property
    def mesh_file(self) -> str:
        return "meshes/arm.stl"

    def template_context(self) -> dict[str, Any]:
        return {
            "spec": self,
            "name": self.name,
            "distro": self.distro,
            # what generated CI files install: this distribution, pinned to the version that wrote them
            "pkgforge_requirement": f"{DISTRIBUTION}=={__version__}",
            "description": self.description
            or f"Robot description of {self.name}: URDF/xacro model, meshes, launch files and RViz configuration.",
        }


def git_config(key: str) -> str | None:
    try:
        result = subprocess.run(["git", "config", "--get", key], capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    value = result.stdout.strip()
    return value if result.returncode == 0 and value else None


def default_maintainer() -> tuple[str, str]:
    """Maintainer from git config, falling back like `ros2 pkg create` does."""
    user = getpass.getuser() or "todo"
    name = git_config("user.name") or user
    email = git_config("user.email") or f"{user}@todo.todo"
    return name, email


def default_destination(cwd: Path) -> Path:
    """`./src` in a workspace root (a folder with src/), else the current folder."""
    return cwd / "src" if (cwd / "src").is_dir() else cwd


def make_spec(
    name: str,
    *,
    distro: str | None = None,
    build_type: str = "ament_cmake",
    launch_format: str = "py",
    maintainer_name: str | None = None,
    maintainer_email: str | None = None,
    license: str = "Apache-2.0",
    description: str = "",
    ci: tuple[str, ...] = (),
    **more: Any,  # PackageSpec's other fields
) -> PackageSpec:
    """Validate options into a PackageSpec; bad input raises PkgforgeError."""
    problem = rep144_problem(name) or rep144_advice(name)
    if problem:
        raise PkgforgeError(f"invalid package name: {problem}; {REP144_RULE}")
    distro = distro or default_distro()  # ROS_DISTRO when set, else the newest LTS
    if distro not in DISTROS:
        raise PkgforgeError(f"unknown distro '{distro}'; choose one of {', '.join(DISTROS)}")
    for value, allowed, what in (
        (build_type, BUILD_TYPES, "build type"),
        (launch_format, LAUNCH_FORMATS, "launch format"),
        *((system, CI_SYSTEMS, "CI system") for system in ci),
    ):
        if value not in allowed:
            raise PkgforgeError(f"unknown {what} '{value}'; choose one of {', '.join(allowed)}")
    default_name, default_email = default_maintainer()
    email = maintainer_email or default_email
    if not EMAIL_PATTERN.match(email):
        raise PkgforgeError(
            f"invalid maintainer e-mail '{email}': package.xml needs an address like "
            "name@example.com (set --maintainer-email or `git config user.email`)"
        )
    maint_name = (maintainer_name or default_name).strip()
    if not maint_name:
        raise PkgforgeError("the maintainer name is empty: set --maintainer-name")
    if not license.strip():
        raise PkgforgeError("the license is empty: set --license (e.g. Apache-2.0)")
    return PackageSpec(
        name=name,
        distro=DISTROS[distro],
        build_type=build_type,
        launch_format=launch_format,
        maintainer_name=maint_name,
        maintainer_email=email,
        license=license.strip(),
        description=description.strip(),
        ci=tuple(ci),
        **more,
    )


def _environment() -> jinja2.Environment:
    env = jinja2.Environment(
        # the templates are package data of pkgforge.scaffold, read through importlib.resources
        loader=jinja2.PackageLoader("pkgforge.scaffold", "templates"),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    # a Python literal for setup.py, quoted and escaped
    env.filters["py"] = repr
    return env


def render_files(spec: PackageSpec) -> dict[str, bytes]:
    """Every file of the new package, by path relative to the package folder."""
    env = _environment()
    ctx = spec.template_context()

    def render(template: str) -> bytes:
        return env.get_template(f"package/{template}").render(ctx).encode("utf-8")

    files: dict[str, bytes] = {
        "package.xml": render("package.xml.j2"),
        spec.launch_file: render(f"launch/display.launch.{spec.launch_format}.j2"),
        spec.model_file: render("urdf/model.urdf.xacro.j2"),
        "urdf/macros.xacro": render("urdf/macros.xacro.j2"),
        "rviz/display.rviz": render("rviz/display.rviz.j2"),
        spec.mesh_file: binary_stl(box_triangles(ARM_MESH_SIZE), header=f"{spec.name} arm"),
    }
    if spec.build_type == "ament_cmake":
        files["CMakeLists.txt"] = render("CMakeLists.txt.j2")
    else:
        files["setup.py"] = render("setup.py.j2")
        files["setup.cfg"] = render("setup.cfg.j2")
        files[f"resource/{spec.name}"] = b""
    if spec.sim:
        files["launch/sim.launch.py"] = render("launch/sim.launch.py.j2")
        files["config/controllers.yaml"] = render("config/controllers.yaml.j2")
        files["worlds/empty.sdf"] = render("worlds/empty.sdf.j2")
    for system in spec.ci:
        path = {"github": ".github/workflows/pkgforge.yml", "gitlab": ".gitlab-ci.yml"}[system]
        files[path] = render(f"ci/{system}.yml.j2")
    if spec.record_distro:
        files["pkgforge.toml"] = render("pkgforge.toml.j2")
    _validate_manifest(files["package.xml"])
    return files


def _validate_manifest(manifest: bytes) -> None:
    """A template bug must never reach the user's disk as a broken package.xml."""
    try:
        parse_package_string(manifest.decode("utf-8"))
    except InvalidPackage as exc:  # pragma: no cover - guards the templates
        raise PkgforgeError(f"pkgforge rendered an invalid package.xml: {exc}") from exc


@dataclass
class CreatedPackage:
    path: Path
    files: list[str]
    overwritten: list[str]  # replaced: their content differed
    unchanged: list[str] = field(default_factory=list)  # already exactly what pkgforge writes


# The longest name pkgforge writes is the staging folder `.NAME.pkgforge-XXXXXXXX`
# (NAME + 19); most file systems allow 255 bytes per name.
MAX_NAME_LENGTH = 200


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _write_new(path: Path, content: bytes, mode: int) -> None:
    """Create `path` with `mode` narrowed by the umask from its first byte on: a private file's
    copy is never readable by others, not even for a moment."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode & 0o777)
    with os.fdopen(descriptor, "wb") as out:
        out.write(content)


def _symlink_out(target: Path, relative: str) -> Path | None:
    """The first existing symlink on target/relative (target included) whose real path leaves
    target's folder: writing there would land outside the destination."""
    inside = os.path.realpath(target.parent if target.is_symlink() else target)
    path = target
    for part in ("", *Path(relative).parts):
        path = path / part if part else path
        if path.is_symlink():
            real = os.path.realpath(path)
            if path == target or not (real == inside or real.startswith(inside + os.sep)):
                return path
        elif not path.exists():
            return None
    return None


def create_package(
    spec: PackageSpec,
    destination: Path,
    *,
    force: int = 0,
    files: dict[str, bytes] | None = None,
    folder: str | None = None,
    modes: Mapping[str, int] | None = None,
) -> CreatedPackage:
    """Render into a temporary folder beside the target, then move into place.

    Without `force` an existing target is refused and left untouched. With
    `force` (once) missing files are added, files already holding exactly what
    pkgforge writes stay, and a generated file the user edited is refused, all
    listed before anything is written; with `force` twice edited files are
    replaced too. The user's other files in the folder always stay. Nothing is
    ever written through a symbolic link that leads out of the target folder.
    Folders and files get the modes the umask gives (like mkdir and touch); a file in `modes`
    (one copied from the user's) gets at most the permission bits given there: a copy of a
    file only its owner may read stays so (like cp).
    """
    if len(spec.name) > MAX_NAME_LENGTH:
        raise PkgforgeError(
            f"the name is {len(spec.name)} characters long; files named after it would pass "
            f"the file system's 255-byte limit: use at most {MAX_NAME_LENGTH}"
        )
    destination = destination.absolute()
    target = destination / (folder or spec.name)
    if (target.exists() or target.is_symlink()) and not force:
        raise PkgforgeError(
            f"{target} already exists; pkgforge does not touch it without --force "
            "(which adds the missing generated files and keeps any others)"
        )
    if target.is_symlink():
        raise PkgforgeError(
            f"{target} is a symbolic link (to {os.path.realpath(target)}): pkgforge does not "
            "write through it; give the real folder with --destination"
        )
    if target.exists() and not target.is_dir():
        raise PkgforgeError(f"{target} exists and is not a folder")
    files = render_files(spec) if files is None else files
    overwritten: list[str] = []
    unchanged: list[str] = []
    if target.exists():
        for relative in sorted(files):
            link = _symlink_out(target, relative)
            if link is not None:
                raise PkgforgeError(
                    f"{link} is a symbolic link to {os.path.realpath(link)}, outside {target}: "
                    f"pkgforge does not write {relative} through it (nothing written)"
                )
            final = target / relative
            if final.is_dir() and not final.is_symlink():
                raise PkgforgeError(f"{final} is a folder where pkgforge writes a file (nothing written)")
            if final.exists() or final.is_symlink():
                try:  # (a FIFO or a device: refused, never read)
                    same = not final.is_symlink() and read_regular(final) == files[relative]
                except FileTooLarge:
                    same = False  # (no template is 8 MB)
                except OSError as exc:
                    raise PkgforgeError(f"cannot read {final}: {exc.strerror}") from exc
                (unchanged if same else overwritten).append(relative)
        if overwritten and force < 2:
            raise PkgforgeError(  # one line each (a name's own newline is escaped)
                f"--force would replace {len(overwritten)} file(s) in {target} that differ from what "
                "pkgforge writes now (edited, or generated with other options):",
                *(f"  {relative}" for relative in overwritten),
                "nothing was written; pass --force twice to replace them, or move them away first",
            )
    mask = _umask()
    try:
        destination.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{spec.name}.pkgforge-", dir=destination))
    except OSError as exc:
        raise PkgforgeError(
            f"cannot create the package in {destination}: {exc.strerror} "
            "(choose a folder you can write to with --destination)"
        ) from exc
    try:
        os.chmod(staging, 0o777 & ~mask)  # mkdtemp makes it 0700; it becomes the package folder
        for relative, content in files.items():
            path = staging / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            _write_new(path, content, (modes or {}).get(relative, 0o666))
        if not target.exists():
            os.rename(staging, target)
            return CreatedPackage(target, sorted(files), [])
        for relative in sorted(files):
            if relative in unchanged:
                continue
            final = target / relative
            final.parent.mkdir(parents=True, exist_ok=True)
            os.replace(staging / relative, final)
        return CreatedPackage(target, sorted(files), overwritten, unchanged)
    except OSError as exc:
        raise PkgforgeError(f"cannot write the package to {target}: {exc.strerror or exc}") from exc
    finally:
        shutil.rmtree(staging, ignore_errors=True)
