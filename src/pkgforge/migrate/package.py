"""`pkgforge migrate PATH`: read the ROS 1 package, convert it in memory, write it atomically."""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.model import ros1_names
from pkgforge.model.source import not_regular, read_regular
from pkgforge.urdf import XACRO_MODEL_SUFFIXES
from pkgforge.walk import WalkLimit, walk

if TYPE_CHECKING:
    from pkgforge.migrate.notes import Notes
    from pkgforge.migrate.roslaunch import Action, Token
    from pkgforge.scaffold.from_urdf import Reference
    from pkgforge.scaffold.package import CreatedPackage

SKIPPED_FOLDERS = {"build", "devel", "install", "log", "__pycache__"}
DEPENDENCY_TAGS = (
    "depend",
    "build_depend",
    "run_depend",
    "exec_depend",
    "build_export_depend",
    "buildtool_depend",
)


def _manifest(path: Path) -> tuple[Any, etree._Element]:
    """(catkin_pkg Package, lxml root) of a ROS 1 catkin package, or a located PkgforgeError.

    catkin_pkg has no type information: its Package is Any here."""
    from pkgforge.model.catkin import InvalidPackage, parse_package_string

    manifest = path / "package.xml"
    if not path.is_dir():
        raise PkgforgeError(f"{path}: no such folder; give the ROS 1 package folder (with package.xml)")
    if not os.path.lexists(manifest):
        raise PkgforgeError(
            f"{path}: no package.xml: not a catkin package; give the folder that holds package.xml"
        )
    try:
        data = read_regular(manifest)
    except OSError as exc:  # (a FIFO or a device: refused, never read)
        raise PkgforgeError(f"{manifest}: {exc.strerror} (nothing written)") from exc
    try:
        root = etree.fromstring(data, base_url=str(manifest))
        package = parse_package_string(data.decode("utf-8"), filename=str(manifest))
    except etree.XMLSyntaxError as exc:
        raise PkgforgeError(
            f"{manifest}:{exc.lineno}: not well-formed XML: {exc.msg} (nothing written)"
        ) from exc
    except InvalidPackage as exc:
        raise PkgforgeError(
            f"{manifest}:1: not a valid package.xml: {str(exc).splitlines()[0]} (nothing written)"
        ) from exc
    tools = [d.name for d in package.buildtool_depends]
    if "catkin" not in tools:
        line = next((e.sourceline for e in root.iter("buildtool_depend")), root.sourceline)
        found = f"its build tool is {', '.join(tools)}" if tools else "it has no <buildtool_depend>"
        raise PkgforgeError(
            f"{manifest}:{line}: not a catkin package ({found}, not catkin): migrate converts "
            "ROS 1 catkin packages (nothing written)"
        )
    return package, root


def _files(source: Path) -> list[str]:
    """The package's files to convert (the walk over the user's folder is pkgforge's one bounded walk:
    a folder it cannot read or a bound it hits stops the migration before anything is written)."""
    found: list[str] = []
    limits: list[WalkLimit] = []
    for folder, folders, names in walk(source, limits=limits):
        folders[:] = sorted(f for f in folders if not f.startswith(".") and f not in SKIPPED_FOLDERS)
        for name in sorted(names):
            relative = os.path.relpath(os.path.join(folder, name), source)
            if not name.startswith(".") and relative not in ("package.xml", "CMakeLists.txt"):
                _regular(os.path.join(folder, name))
                found.append(Path(relative).as_posix())
    if limits:
        limit = limits[0]
        raise PkgforgeError(
            f"{limit.path}: {limit.why}; {limit.hint or 'move it out of the package'} (nothing written)"
        )
    return found


def _copy_problems(source: Path, files: list[str]) -> list[str]:
    """Each of the package's files migrate would copy but does not, with why: migrate copies the
    package's own regular files, so a symbolic link must lead to one inside the package (never to
    a key or another package's file), and a FIFO or device is no file to copy."""
    from pkgforge.scaffold.from_urdf import copy_problem

    inside = [Path(os.path.realpath(source))]
    problems = []
    for relative in files:
        _, problem = copy_problem(source / relative, inside, None)
        if problem is not None:
            problems.append(f"{source / relative}: {problem}: not copied")
    return problems


def _regular(path: str) -> None:
    """A located PkgforgeError for a FIFO or a device (or a link to one) among the files to convert
    and copy: reading it would block, or never end."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return  # a dangling link: its read says so, as before
    if not stat.S_ISREG(mode):
        refusal = not_regular(path, mode)
        raise PkgforgeError(f"{path}: {refusal.strerror}; move it out of the package (nothing written)")


def _is_ros1_launch(relative: str) -> bool:
    return relative.endswith(".launch")


def _models(
    source: Path, files: list[str], notes: Notes
) -> tuple[dict[str, etree._Element], set[str], str | None, list[Reference]]:
    """Each model parsed (by relative path), the links of all, the root link of the first .urdf,
    and the meshes that are missing."""
    from pkgforge.scaffold.from_urdf import model_references, parse_model, resolve, root_link

    roots: dict[str, etree._Element] = {}
    links: set[str] = set()
    first_root: str | None = None
    missing: list[Reference] = []
    for relative in files:
        if not relative.endswith(XACRO_MODEL_SUFFIXES):
            continue
        path = source / relative
        root = roots[relative] = parse_model(path)
        links |= {name for e in root.iter("link") if (name := e.get("name"))}
        if first_root is None and relative.endswith(".urdf"):
            first_root = root_link(root)
        for reference in model_references(path, root):
            if (
                reference.kind in ("mesh", "texture")
                and "$(" not in reference.uri
                and "${" not in reference.uri
            ):
                found, problem = resolve(reference.uri, path)
                if found is not None and not found.is_file():
                    found, problem = None, f"no file {found}"  # a folder, a FIFO: no mesh
                if found is None:
                    reference.problem = problem
                    missing.append(reference)
        for element in root.iter("plugin"):
            if ros1_names.is_gazebo_classic_plugin(element.get("filename", "")):
                notes.add(
                    "migrate-gazebo-classic",
                    f"Gazebo Classic plugin {element.get('filename')} is kept as "
                    "written; it does not load in Gazebo (gz)",
                    path,
                    element.sourceline,
                )
    return roots, links, first_root, missing


def migrate(
    source: Path,
    destination: Path | None,
    *,
    launch_format: str,
    distro: str | None,
    gazebo: bool,
    notes_factory: Callable[[str], Notes],
) -> tuple[CreatedPackage, Notes, Path]:
    from pkgforge.migrate.emit import to_python, to_xml, to_yaml, used_packages
    from pkgforge.migrate.roslaunch import Reader
    from pkgforge.migrate.rviz1 import convert as convert_rviz
    from pkgforge.model.distro_data import load
    from pkgforge.scaffold.from_urdf import massless_root, missing_message
    from pkgforge.scaffold.package import create_package, make_spec, render_files

    source = source.absolute()
    package, manifest_root = _manifest(source)
    name = package.name
    notes = notes_factory(name)
    files = _files(source)
    refused = _copy_problems(source, files)
    if refused:
        raise PkgforgeError(
            *refused,
            f"{len(refused)} file(s) of the package cannot be copied: nothing written; replace each "
            "link that leads out of the package by the file it names, or move the file out of the package",
        )
    models, links, root, missing = _models(source, files, notes)
    if missing:
        raise PkgforgeError(*missing_message(missing, force=False))
    base = make_spec(
        name,
        distro=distro,
        launch_format=launch_format,
        maintainer_name=package.maintainers[0].name if package.maintainers else None,
        maintainer_email=package.maintainers[0].email if package.maintainers else None,
    )

    # where things go: ROS 1 launch files get their ROS 2 name; an RViz config at the top moves to rviz/
    moved: dict[str, str] = {}
    for relative in files:
        if _is_ros1_launch(relative):
            moved[relative] = relative.rsplit(".", 1)[0] + f".launch.{launch_format}"
        elif relative.endswith(".rviz") and "/" not in relative:
            moved[relative] = f"rviz/{relative}"

    def rename_launch(parts: list[Token]) -> list[Token]:
        return _rewrite(parts, name, moved, foreign_launch=".launch.py")  # other packages' ROS 2 launch files

    output: dict[str, bytes] = {}
    # each file's permission bits: its source's, never wider; a file copied as it is keeps its
    # execute bits (a script), a converted one has none
    modes: dict[str, int] = {}
    used: set[str] = set()
    generated_rviz: dict[str, int | None] = {}
    for relative in files:
        path = source / relative
        modes[moved.get(relative, relative)] = path.stat().st_mode & 0o666
        if relative in moved and _is_ros1_launch(relative):
            reader = Reader(path, name, notes, gazebo=gazebo, rename_launch=rename_launch)
            converted = reader.read()
            _rewrite_all(converted.actions, name, moved, source, generated_rviz, notes, path)
            used |= used_packages(converted.actions)
            if launch_format == "py":
                text = to_python(converted.actions, relative)
            elif launch_format == "xml":
                text = to_xml(converted.actions, relative, param_type=base.distro.frontend_param_type)
            else:
                text = to_yaml(converted.actions, relative, param_type=base.distro.frontend_param_type)
            output[moved[relative]] = text.encode("utf-8")
            notes.add("migrate-changed", f"{relative} → {moved[relative]}", path, None)
        elif relative.endswith(".rviz"):
            try:
                text = path.read_text(encoding="utf-8")
            except UnicodeDecodeError as exc:
                raise PkgforgeError(f"{path}: not a text file: not an RViz config (nothing written)") from exc
            output[moved.get(relative, relative)] = convert_rviz(text, path, notes, links, root).encode(
                "utf-8"
            )
        elif relative in models and etree.QName(models[relative]).localname == "robot":
            output[relative] = massless_root(
                path.read_text(encoding="utf-8"), models[relative], path, notes
            ).encode("utf-8")
        else:
            output[relative] = path.read_bytes()
            modes[relative] = path.stat().st_mode & 0o777

    # exec_depends: what the launch files use, and the old ones that still mean something
    data = load()
    target = base.distro.name
    depends = (used - {name}) | {"launch", "launch_ros"}
    depends |= (
        {"launch_xml"} if launch_format == "xml" else {"launch_yaml"} if launch_format == "yaml" else set()
    )
    if "rviz2" in depends:
        depends.add("rviz_default_plugins")
    for element in manifest_root.iter(*DEPENDENCY_TAGS):
        dependency = (element.text or "").strip()
        if not dependency or dependency == name:
            continue
        if dependency in ros1_names.DROPPED_DEPENDENCIES:
            notes.add(
                "migrate-dependency-dropped",
                f"<{element.tag!s}>{dependency}</{element.tag!s}> is ROS 1 only: not carried over",
                source / "package.xml",
                element.sourceline,
            )
        elif dependency in ros1_names.GAZEBO_DEPENDENCIES:
            if gazebo:
                depends.add("ros_gz_sim")
                notes.add(
                    "migrate-renamed",
                    f"{dependency} → ros_gz_sim",
                    source / "package.xml",
                    element.sourceline,
                )
            else:
                notes.add(
                    "migrate-dependency-dropped",
                    f"<{element.tag!s}>{dependency}</{element.tag!s}>: Gazebo Classic, "
                    "not carried over (--gazebo uses ros_gz_sim)",
                    source / "package.xml",
                    element.sourceline,
                )
        elif (replacement := ros1_names.package(dependency)) and not data.released(dependency, target):
            better = replacement[0]
            depends.add(better)
            notes.add(
                "migrate-renamed", f"{dependency} → {better}", source / "package.xml", element.sourceline
            )
        else:
            depends.add(dependency)

    for rviz in generated_rviz:
        spec_for_rviz = make_spec(name, distro=target, fixed_frame=root or "base_link")
        output[rviz] = render_files(spec_for_rviz)["rviz/display.rviz"]
        modes.pop(rviz, None)
    folders = tuple(sorted({r.split("/", 1)[0] for r in output if "/" in r}))
    launch_files = tuple(sorted(r for r in output if r.startswith("launch/") and ".launch." in r))
    spec = make_spec(
        name,
        distro=target,
        launch_format=launch_format,
        maintainer_name=base.maintainer_name,
        maintainer_email=base.maintainer_email,
        license=package.licenses[0] if package.licenses else "TODO",
        description=package.description.strip() or "",
        model_name=None,
        fixed_frame=root or "base_link",
        resource_folders=folders,
        extra_exec_depends=tuple(sorted(depends)),
        launch_files=launch_files or ("launch",),
        maintainers=tuple((m.name, m.email) for m in package.maintainers),
        licenses=tuple(package.licenses),
        version=package.version,
        authors=tuple((a.name, a.email) for a in package.authors),
        urls=tuple((u.type or "", u.url) for u in package.urls),
    )
    rendered = render_files(spec)
    output["package.xml"] = rendered["package.xml"]
    output["CMakeLists.txt"] = rendered["CMakeLists.txt"]
    notes.add(
        "migrate-changed",
        "package.xml: format 3, ament_cmake, exec_depends from what the launch files use",
        source / "package.xml",
        1,
    )
    if (source / "CMakeLists.txt").is_file():
        notes.add(
            "migrate-changed",
            f"CMakeLists.txt: ament_cmake, install(DIRECTORY {' '.join(folders)} "
            "DESTINATION share/${PROJECT_NAME})",
            source / "CMakeLists.txt",
            1,
        )

    parent = (destination or source.parent).absolute()
    folder = name
    if destination is None and (parent / name).exists():
        folder = f"{name}_ros2"  # beside the source, which usually has the package's name
    if (parent / folder).exists() or (parent / folder).is_symlink():
        raise PkgforgeError(
            f"{parent / folder} already exists: migrate never overwrites; give another "
            "--destination (nothing written)"
        )
    created = create_package(spec, parent, files=output, folder=folder, modes=modes)
    return created, notes, source


def _rewrite(parts: list[Token], name: str, moved: dict[str, str], foreign_launch: str) -> list[Token]:
    """$(find NAME)/old → $(find NAME)/new for a moved file; other packages' .launch → ROS 2 name."""
    from pkgforge.migrate.roslaunch import Token

    out = list(parts)
    for index in range(len(out) - 1):
        if out[index][0] == "find" and out[index + 1][0] == "text":
            rest = out[index + 1][1]
            relative = rest.lstrip("/")
            if out[index][1] == name:
                for old, new in moved.items():
                    if relative == old or relative.startswith(old + " "):
                        out[index + 1] = Token("text", "/" + new + relative[len(old) :])
            elif relative.endswith(".launch"):
                out[index + 1] = Token("text", rest[: -len(".launch")] + foreign_launch)
    return out


def _rewrite_all(
    actions: list[Action],
    name: str,
    moved: dict[str, str],
    source: Path,
    generated: dict[str, int | None],
    notes: Notes,
    path: Path,
) -> None:
    """References to moved files follow them; an RViz config the source lacks is generated in rviz/."""
    from pkgforge.migrate.roslaunch import Arg, Group, Node, Token

    for action in actions:
        if isinstance(action, Arg) and action.default:
            action.default = _rewrite(action.default, name, moved, ".launch.py")
        elif isinstance(action, Group):
            _rewrite_all(action.actions, name, moved, source, generated, notes, path)
        elif isinstance(action, Node):
            action.arguments = [_rewrite(w, name, moved, ".launch.py") for w in action.arguments]
            if action.package == "rviz2":
                for index, word in enumerate(action.arguments):
                    if (
                        len(word) == 2
                        and word[0] == Token("find", name)
                        and word[1][0] == "text"
                        and word[1][1].endswith(".rviz")
                    ):
                        relative = word[1][1].lstrip("/")
                        if not (source / relative).is_file() and relative not in moved.values():
                            new = f"rviz/{Path(relative).name}"
                            generated[new] = action.line
                            action.arguments[index] = [Token("find", name), Token("text", "/" + new)]
                            notes.add(
                                "migrate-generated",
                                f"{relative} (the -d config of rviz) is not in the source: "
                                f"{new} made, showing the model on /robot_description",
                                path,
                                action.line,
                            )
