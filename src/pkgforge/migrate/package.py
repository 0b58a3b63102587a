"""`pkgforge migrate PATH`: read the ROS 1 package, convert it in memory, write it atomically.

What CAD exporters write is the normal case, not bad input: an assembly's name as package name
(a valid one is chosen and every reference to the old one follows), a manifest without a
maintainer's name (filled in), a model with content after </robot> (read as ROS 1 did), URIs
naming the exporter's folder instead of a package (read in that folder). Models and meshes are
copied byte for byte but for the references that follow a new name.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.migrate.converted import Converted
from pkgforge.migrate.models import Models, is_ros1_launch, read_models
from pkgforge.model import ros1_names
from pkgforge.model.source import not_regular
from pkgforge.walk import WalkLimit, walk

if TYPE_CHECKING:
    from pkgforge.migrate.manifest import Ros1Manifest
    from pkgforge.migrate.roslaunch import Action, Reader
    from pkgforge.migrate.tokens import Token
    from pkgforge.scaffold.notes import Notes
    from pkgforge.scaffold.package import CreatedPackage, PackageSpec

SKIPPED_FOLDERS = {"build", "devel", "install", "log", "__pycache__"}
DEPENDENCY_TAGS = (
    "depend",
    "build_depend",
    "run_depend",
    "exec_depend",
    "build_export_depend",
    "buildtool_depend",
)
# at most this many line numbers in a note (a message is one line)
SHOWN_LINES = 8


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


def _is_asset(relative: str) -> bool:
    from pkgforge.scaffold.from_urdf import ASSET_SUFFIXES

    return relative.lower().endswith(ASSET_SUFFIXES)


def _is_text(data: bytes) -> bool:
    """A file whose references a rename rewrites: text (a model, a config), never a binary one."""
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return b"\0" not in data


def _lines(items: list[int]) -> str:
    distinct = sorted(set(items))
    shown = ", ".join(map(str, distinct[:SHOWN_LINES]))
    return f"line {shown}" + (" …" if len(distinct) > SHOWN_LINES else "")


@dataclass
class Renames:
    """Where references to the package go: its old name (and the folders exporters name as if they
    were packages) → the new package. Keys and values are URI prefixes, as bytes."""

    old: str
    new: str
    prefixes: dict[str, str] = field(default_factory=dict)
    names: dict[str, str] = field(default_factory=dict)  # package names in launch files

    @classmethod
    def of(cls, old: str, new: str) -> Renames:
        renames = cls(old, new)
        if old != new:
            renames.names[old] = new
            renames.prefixes.update(
                {
                    f"package://{old}/": f"package://{new}/",
                    f"$(find {old})": f"$(find {new})",
                    f"$(find-pkg-share {old})": f"$(find-pkg-share {new})",
                }
            )
        return renames

    def folder(self, name: str, relative: str) -> None:
        """package://NAME/ names no package but the folder `relative` of this package."""
        self.prefixes[f"package://{name}/"] = f"package://{self.new}/" + (
            "" if relative == "." else relative + "/"
        )

    def pattern(self) -> re.Pattern[bytes] | None:
        if not self.prefixes:
            return None
        keys = sorted(self.prefixes, key=len, reverse=True)
        return re.compile(b"|".join(re.escape(k.encode()) for k in keys))

    def apply(self, data: bytes) -> tuple[bytes, list[int]]:
        """The bytes with every reference rewritten, and the line of each rewrite."""
        pattern = self.pattern()
        if pattern is None:
            return data, []
        lines = [data.count(b"\n", 0, m.start()) + 1 for m in pattern.finditer(data)]
        return pattern.sub(lambda m: self.prefixes[m.group(0).decode()].encode(), data), lines

    def text(self, value: str) -> str:
        data, _ = self.apply(value.encode("utf-8", "surrogateescape"))
        return data.decode("utf-8", "surrogateescape")

    def note(self, notes: Notes, path: Path, lines: list[int]) -> None:
        if lines:
            olds = sorted(
                k.removeprefix("package://").rstrip("/") for k in self.prefixes if k.startswith("package://")
            )
            notes.add(
                "migrate-generated",
                f"{len(lines)} reference(s) to {' and '.join(olds)} rewritten to package {self.new} "
                f"(package://, $(find); {_lines(lines)})",
                path,
                lines[0],
            )


def _package_name(manifest: Ros1Manifest, requested: str | None) -> tuple[str, str | None]:
    """(the ROS 2 package's name, why it differs from the source's or None): --name, else the
    source's when valid, else the valid name REP 144's message suggests."""
    from pkgforge.model.names import REP144_RULE, rep144_advice, rep144_problem, suggested_name

    old = manifest.name
    if requested is not None:
        problem = rep144_problem(requested) or rep144_advice(requested)
        if problem:
            raise PkgforgeError(f"invalid --name: {problem}; {REP144_RULE}")
        return requested, "--name" if requested != old else None
    problem = rep144_problem(old) or rep144_advice(old)
    if problem is None:
        return old, None
    new = suggested_name(old)
    if new is None:
        raise PkgforgeError(
            f"{manifest.path}:{manifest.name_line}: package name: {problem}, and no valid name is near "
            "it: give the ROS 2 package's name with --name (nothing written)"
        )
    return new, f"{problem.split(' (try')[0]}, which REP 144 forbids"


def migrate(
    source: Path,
    destination: Path | None,
    *,
    launch_format: str,
    distro: str | None,
    gazebo: bool,
    notes_factory: Callable[[str], Notes],
    name: str | None = None,
    maintainer_name: str | None = None,
    maintainer_email: str | None = None,
    add_root_link: bool = False,
    check_launch: bool = True,
    record_distro: bool = False,
) -> tuple[CreatedPackage, Notes, Path]:
    from pkgforge.migrate.check import unloadable
    from pkgforge.migrate.manifest import maintainers, read_manifest, version
    from pkgforge.scaffold.from_urdf import missing_message
    from pkgforge.scaffold.package import make_spec, render_files

    source = source.absolute()
    manifest = read_manifest(source)
    new_name, why = _package_name(manifest, name)
    notes = notes_factory(new_name)
    renames = Renames.of(manifest.name, new_name)
    if why is not None:
        notes.add(
            "migrate-generated",
            f"package name '{manifest.name}' → '{new_name}' ({why}); package://, $(find) and project() follow",
            manifest.path,
            manifest.name_line,
        )
    files = _files(source)
    refused = _copy_problems(source, files)
    if refused:
        raise PkgforgeError(
            *refused,
            f"{len(refused)} file(s) of the package cannot be copied: nothing written; replace each "
            "link that leads out of the package by the file it names, or move the file out of the package",
        )
    models = read_models(source, files, notes)
    if models.missing:
        raise PkgforgeError(*missing_message(models.missing, force=False))
    for folder_name, folder in models.found.items():
        renames.folder(folder_name, os.path.relpath(folder, source))
        _note_folder(notes, models, folder_name, folder)
    people = maintainers(manifest, maintainer_name, maintainer_email, notes)
    base = make_spec(
        new_name,
        distro=distro,
        launch_format=launch_format,
        maintainer_name=people[0][0],
        maintainer_email=people[0][1],
    )
    target = base.distro.name
    converted = _convert_files(source, files, models, renames, notes, target, launch_format, gazebo)
    if add_root_link:
        from pkgforge.scaffold.from_urdf import decode, encode, massless_root

        for relative, model in models.read.items():
            if etree.QName(model.root).localname == "robot":
                text = decode(converted.output[relative])
                converted.output[relative] = encode(massless_root(text, model.root, model.path, notes))
    for rviz in converted.generated_rviz:
        rviz_spec = make_spec(new_name, distro=target, fixed_frame=models.root or "base_link")
        converted.output[rviz] = render_files(rviz_spec)["rviz/display.rviz"]
        converted.modes.pop(rviz, None)
    declared = _dependencies(manifest, new_name, target, gazebo, notes) | converted.depends
    package_version = version(manifest, notes)

    def spec_for(launch_files: tuple[str, ...]) -> PackageSpec:
        used = set().union(*(converted.uses[f] for f in launch_files)) if launch_files else set()
        depends = (used - {new_name}) | declared
        if launch_files:
            depends |= {"launch", "launch_ros"}
        if "rviz2" in depends:
            depends.add("rviz_default_plugins")
        return make_spec(
            new_name,
            distro=target,
            launch_format=launch_format,
            maintainer_name=people[0][0],
            maintainer_email=people[0][1],
            license=manifest.licenses[0] if manifest.licenses else "TODO",
            fixed_frame=models.root or "base_link",
            resource_folders=tuple(sorted({r.split("/", 1)[0] for r in converted.output if "/" in r})),
            extra_exec_depends=tuple(sorted(depends)),
            launch_files=launch_files or ("launch",),
            maintainers=people,
            licenses=tuple(manifest.licenses),
            version=package_version,
            authors=tuple((a.name, a.email) for a in manifest.authors),
            urls=tuple(manifest.urls),
            description_xml=manifest.description_xml,
            record_distro=record_distro,
        )

    leave_out: set[str] = set()
    converted.emit(leave_out, new_name, launch_format, base.distro, notes)
    for _ in range(3):  # what is left out may leave an include in another file without its file
        if not (check_launch and converted.uses):
            break
        failing = unloadable(spec_for(tuple(sorted(converted.uses))), converted.output, converted.modes)
        if not failing:
            break
        for relative, reason in failing.items():
            notes.add(
                "migrate-dropped",
                f"{relative} not written: {reason}",
                converted.launch_sources[relative],
                None,
            )
        leave_out |= set(failing)
        converted.emit(leave_out, new_name, launch_format, base.distro, notes)
    for written in sorted(converted.uses):
        notes.add(
            "migrate-changed",
            f"{converted.launch_names[written]} → {written}",
            converted.launch_sources[written],
            None,
        )
    spec = spec_for(tuple(sorted(converted.uses)))
    rendered = render_files(spec)
    converted.output["package.xml"] = rendered["package.xml"]
    converted.output["CMakeLists.txt"] = rendered["CMakeLists.txt"]
    if "pkgforge.toml" in rendered:  # --distro given: verify and fix target it, as after new --distro
        converted.output["pkgforge.toml"] = rendered["pkgforge.toml"]
    notes.add(
        "migrate-changed",
        "package.xml: format 3, ament_cmake, exec_depends from what the launch files use",
        manifest.path,
        1,
    )
    if (source / "CMakeLists.txt").is_file():
        project = f"project({new_name}), " if new_name != manifest.name else ""
        notes.add(
            "migrate-changed",
            f"CMakeLists.txt: ament_cmake, {project}install(DIRECTORY {' '.join(spec.folders)} "
            "DESTINATION share/${PROJECT_NAME})",
            source / "CMakeLists.txt",
            1,
        )
    return _write(spec, converted, source, destination), notes, source


def _write(spec: PackageSpec, converted: Converted, source: Path, destination: Path | None) -> CreatedPackage:
    """Write the package into DESTINATION/NAME (default: beside the source, NAME_ros2 when NAME is
    taken there, as the source usually is), never over an existing folder."""
    from pkgforge.scaffold.package import create_package

    parent = (destination or source.parent).absolute()
    folder = spec.name
    if destination is None and (parent / folder).exists():
        folder = f"{spec.name}_ros2"  # beside the source, which usually has the package's name
    if (parent / folder).exists() or (parent / folder).is_symlink():
        raise PkgforgeError(
            f"{parent / folder} already exists: migrate never overwrites; give another "
            "--destination (nothing written)"
        )
    return create_package(spec, parent, files=converted.output, folder=folder, modes=converted.modes)


def _note_folder(notes: Notes, models: Models, name: str, folder: Path) -> None:
    from pkgforge.scaffold.from_urdf import folder_message, model_references

    for model in models.read.values():
        first = next(
            (
                r
                for r in model_references(model.path, model.root, model.text)
                if r.uri.startswith(f"package://{name}/")
            ),
            None,
        )
        if first is not None:
            notes.add("migrate-generated", folder_message(name, folder, model.path), model.path, first.line)
            return


def _convert_files(
    source: Path,
    files: list[str],
    models: Models,
    renames: Renames,
    notes: Notes,
    target: str,
    launch_format: str,
    gazebo: bool,
) -> Converted:
    """Every file of the package, converted (launch files, RViz configs) or copied (the rest, with
    each reference to a renamed package rewritten and reported)."""
    from pkgforge.migrate.roslaunch import Reader
    from pkgforge.migrate.rviz1 import convert as convert_rviz
    from pkgforge.model.distros import DISTROS

    distro = DISTROS[target]
    # where things go: ROS 1 launch files get their ROS 2 name; an RViz config at the top moves to rviz/
    moved: dict[str, str] = {}
    for relative in files:
        if is_ros1_launch(relative):
            moved[relative] = relative.rsplit(".", 1)[0] + f".launch.{launch_format}"
        elif relative.endswith(".rviz") and "/" not in relative:
            moved[relative] = f"rviz/{relative}"
    own = {renames.old, renames.new}

    def rename_launch(parts: list[Token]) -> list[Token]:
        return _rewrite(parts, own, moved, foreign_launch=".launch.py")  # other packages' ROS 2 launch files

    def reader(path: Path, into: Notes, description: list[Token] | None) -> Reader:
        return Reader(
            path,
            renames.new,
            into,
            gazebo=gazebo,
            rename_launch=rename_launch,
            distro=distro,
            launch_format=launch_format,
            package_description=description,
            content=renames.apply(path.read_bytes())[0],
        )

    description = _package_description(
        [source / r for r in files if is_ros1_launch(r)],
        renames,
        lambda path: reader(path, type(notes)(renames.new), None),
    )
    converted = Converted()
    for relative in files:
        path = source / relative
        # each file's permission bits: its source's, never wider; a file copied as it is keeps its
        # execute bits (a script), a converted one has none
        converted.modes[moved.get(relative, relative)] = path.stat().st_mode & 0o666
        data = path.read_bytes()
        if relative in moved and is_ros1_launch(relative):
            _, lines = renames.apply(data)
            renames.note(notes, path, lines)
            launch = reader(path, notes, description).read()
            _rename_tokens(launch.actions, renames)
            _rewrite_all(launch.actions, renames.new, moved, source, converted.generated_rviz, notes, path)
            converted.launches[moved[relative]] = launch
            converted.launch_sources[moved[relative]] = path
            converted.launch_names[moved[relative]] = relative
        elif relative.endswith(".rviz"):
            renamed, lines = renames.apply(data)
            renames.note(notes, path, lines)
            try:
                text = renamed.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise PkgforgeError(f"{path}: not a text file: not an RViz config (nothing written)") from exc
            converted.output[moved.get(relative, relative)] = convert_rviz(
                text, path, notes, models.links, models.root
            ).encode("utf-8")
        else:
            if not _is_asset(relative) and _is_text(data):
                data, lines = renames.apply(data)
                renames.note(notes, path, lines)
            converted.output[relative] = data
            converted.modes[relative] = path.stat().st_mode & 0o777
    parameter_files: set[str] = set()  # own YAML files a node's <rosparam file> loads
    for launch in converted.launches.values():
        parameter_files |= _parameter_files(launch.actions, renames.new)
    for relative in sorted(parameter_files):
        if relative in converted.output:
            converted.output[relative] = _as_ros2_parameters(
                converted.output[relative], source / relative, notes
            )
    from pkgforge.migrate.gazebo import convert_package, strip_package

    if gazebo:
        convert_package(converted, models, source, renames.new, target, notes)
    else:
        strip_package(converted, models, source, notes)
    return converted


def _parameter_files(actions: list[Action], name: str) -> set[str]:
    """The package's own files (relative paths) a node's <rosparam command="load" file=...> loads."""
    from pkgforge.migrate.roslaunch import Group, Node
    from pkgforge.migrate.tokens import Token

    found: set[str] = set()
    for action in actions:
        if isinstance(action, Group):
            found |= _parameter_files(action.actions, name)
        elif isinstance(action, Node):
            for param in action.params:
                value = param.value
                if (
                    param.kind == "file"
                    and len(value) == 2
                    and value[0] == Token("find", name)
                    and value[1][0] == "text"
                ):
                    found.add(value[1][1].lstrip("/"))
    return found


def _as_ros2_parameters(content: bytes, path: Path, notes: Notes) -> bytes:
    """A ROS 1 rosparam file a node loads, as a ROS 2 parameters file: rcl reads only
    `<node name or /**>: ros__parameters: ...` (the file's own parameters as they were, under
    /**: the one node the launch file gives it to). A file already laid out so, or one with
    document markers (several documents, directives), stays as it is."""
    text = content.decode("utf-8", errors="replace")
    lines = text.splitlines(keepends=True)
    if "ros__parameters" in text or any(line.startswith(("---", "...", "%")) for line in lines):
        return content
    indented = "".join(f"    {line}" if line.strip() else line for line in lines)
    notes.add(
        "migrate-changed",
        f"{path.name}: its parameters now under /**: ros__parameters:, as a ROS 2 node reads a parameters file",
        path,
        1,
    )
    return f"/**:\n  ros__parameters:\n{indented}".encode()


def _package_description(
    launch_files: list[Path], renames: Renames, reader: Callable[[Path], Reader]
) -> list[Token] | None:
    """The model the package's launch files describe the robot with (an argument's default filled
    in), when they agree on one: what ROS 1's global robot_description was for a launch file that
    only read it (fusion2urdf's controller.launch starts robot_state_publisher without one)."""
    from pkgforge.migrate.emit import frontend
    from pkgforge.migrate.roslaunch import Arg

    found: dict[str, list[Token]] = {}
    for path in launch_files:
        launch = reader(path).read()
        if launch.description:
            _rename_tokens([Arg("", launch.description, None, None)], renames)
            found.setdefault(re.sub(r"[\'\"\s]", "", frontend(launch.description)), launch.description)
    return next(iter(found.values())) if len(found) == 1 else None


def _rename_tokens(actions: list[Action], renames: Renames) -> None:
    """$(find OLD) → $(find NEW), a node of package OLD → NEW, package://OLD/ in a value → NEW."""
    from pkgforge.migrate.roslaunch import nodes, token_lists
    from pkgforge.migrate.tokens import Token

    if not renames.prefixes:
        return
    for parts in token_lists(actions):
        for index, part in enumerate(parts):
            if part[0] == "find" and part[1] in renames.names:
                parts[index] = Token("find", renames.names[part[1]])
            elif part[0] == "text" and "package://" in part[1]:
                parts[index] = Token("text", renames.text(part[1]))
    for node in nodes(actions):
        node.package = renames.names.get(node.package, node.package)


def _dependencies(manifest: Ros1Manifest, name: str, target: str, gazebo: bool, notes: Notes) -> set[str]:
    """The source's dependencies that still mean something in ROS 2 (what the launch files use is
    added to them): ROS 1's build tool and launcher dropped, renamed packages renamed."""
    from pkgforge.model.distro_data import load

    data = load()
    depends: set[str] = set()

    def note(message: str, element: etree._Element, kind: str = "migrate-dependency-dropped") -> None:
        notes.add(kind, message, manifest.path, element.sourceline)

    for element in manifest.root.iter(*DEPENDENCY_TAGS):
        dependency = (element.text or "").strip()
        if not dependency or dependency in (name, manifest.name):
            continue
        if dependency in ros1_names.DROPPED_DEPENDENCIES:
            note(f"<{element.tag!s}>{dependency}</{element.tag!s}> is ROS 1 only: not carried over", element)
        elif dependency in ros1_names.GAZEBO_DEPENDENCIES:
            if gazebo:
                depends.add("ros_gz_sim")
                note(f"{dependency} → ros_gz_sim", element, "migrate-renamed")
            else:
                note(
                    f"<{element.tag!s}>{dependency}</{element.tag!s}>: Gazebo Classic, "
                    "not carried over (--gazebo uses ros_gz_sim)",
                    element,
                )
        elif (replacement := ros1_names.package(dependency)) and not data.released(dependency, target):
            depends.add(replacement[0])
            note(f"{dependency} → {replacement[0]}", element, "migrate-renamed")
        else:
            depends.add(dependency)
    return depends


def _rewrite(parts: list[Token], own: set[str], moved: dict[str, str], foreign_launch: str) -> list[Token]:
    """$(find NAME)/old → $(find NAME)/new for a moved file (NAME: the package, by its old or new
    name); other packages' .launch → their ROS 2 name."""
    from pkgforge.migrate.tokens import Token

    out = list(parts)
    for index in range(len(out) - 1):
        if out[index][0] == "find" and out[index + 1][0] == "text":
            rest = out[index + 1][1]
            relative = rest.lstrip("/")
            if out[index][1] in own:
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
    from pkgforge.migrate.roslaunch import Arg, Group, Node
    from pkgforge.migrate.tokens import Token

    for action in actions:
        if isinstance(action, Arg) and action.default:
            action.default = _rewrite(action.default, {name}, moved, ".launch.py")
        elif isinstance(action, Group):
            _rewrite_all(action.actions, name, moved, source, generated, notes, path)
        elif isinstance(action, Node):
            action.arguments = [_rewrite(w, {name}, moved, ".launch.py") for w in action.arguments]
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
