"""`pkgforge new NAME --from-urdf FILE`: a CAD exporter's URDF (or xacro) and its meshes become a
package as `pkgforge new` makes it, the model in urdf/, every mesh and texture in meshes/.

Mesh URIs may be `package://OTHER/...` (OTHER found above the model, or in AMENT_PREFIX_PATH),
`file://` (also `file://$(find OTHER)/...`), absolute or relative to the model. Each is copied
with its sub-folders (below the folder all of them share), names and letter case kept, and its
URI rewritten to `package://NAME/meshes/...` (or `file://$(find NAME)/meshes/...`). Textures
that Collada and OBJ meshes name beside themselves come along. A mesh that cannot be found stops
it, naming the file and line, before anything is written (unless --force).

A model names paths, and pkgforge copies what it names into a package meant to be shared: so only
mesh and texture files (ASSET_SUFFIXES) are copied, and only from the model's package tree
(model_tree) or the folder of a package the URI names; symbolic links are followed first and the
rule holds for the file they lead to, which must be a regular file of a sane size (copy_problem).
Anything else is refused by name, at the model's file and line, like a mesh that cannot be found.
A copy keeps its source's permission bits, narrowed by the umask: never wider.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.urdf import XACRO_MODEL_SUFFIXES

if TYPE_CHECKING:
    from pkgforge.migrate.notes import Notes
    from pkgforge.scaffold.package import CreatedPackage

URI_STYLES = ("package", "find")
FIND = re.compile(r"\$\(find ([^)\s]+)\)")
XACRO_NS = "http://www.ros.org/wiki/xacro"

# What a URDF's consumers load from a <mesh> or <texture>: RViz (Ogre's .mesh, its own STL reader,
# Assimp for the rest) and Gazebo (gz-common: STL, Collada, OBJ, glTF/GLB, FBX), an OBJ's material
# library, and the images these name. Compared in lower case: SolidWorks writes .STL.
MESH_SUFFIXES = (".stl", ".dae", ".obj", ".ply", ".glb", ".gltf", ".3ds", ".fbx", ".mesh")
MATERIAL_SUFFIXES = (".mtl",)
TEXTURE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tga", ".bmp", ".tif", ".tiff", ".dds", ".ktx")
ASSET_SUFFIXES = MESH_SUFFIXES + MATERIAL_SUFFIXES + TEXTURE_SUFFIXES
INNER_SUFFIXES = MATERIAL_SUFFIXES + TEXTURE_SUFFIXES  # what a mesh may name beside itself
# Far above any robot's mesh (the largest real ones are tens of MB); every copy is held in memory
# until the package is written at once.
MAX_COPIED_BYTES = 256 << 20


@dataclass
class Reference:
    uri: str
    file: Path  # the model file that names it
    line: int | None  # None: lxml knows no line (never for a parsed file)
    kind: str  # mesh | texture | include | material library (a texture or library a mesh names)
    source: Path | None = None  # the file it resolves to
    problem: str | None = None
    refused: bool = False  # the file exists; problem says why pkgforge does not copy it
    root: Path | None = None  # the allowed folder its real path lies in (copy_problem)


def package_root(name: str, near: Path) -> Path | None:
    """The folder of package `name`: a folder above `near` whose package.xml names it, else
    share/<name> in AMENT_PREFIX_PATH (or <prefix>/<name> in ROS_PACKAGE_PATH)."""
    if not name or "/" in name or name in (".", ".."):
        return None  # not a package name: share/.. would be the prefix itself
    for folder in [near, *near.parents]:
        manifest = folder / "package.xml"
        if manifest.is_file():
            try:
                found = etree.parse(str(manifest)).findtext("name")
            except (etree.XMLSyntaxError, OSError):
                found = None
            if found is not None and found.strip() == name:
                return folder
            if folder.name == name:
                return folder
    for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
        if (Path(prefix) / "share" / name / "package.xml").is_file():
            return Path(prefix) / "share" / name
    for prefix in filter(None, os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep)):
        if (Path(prefix) / name / "package.xml").is_file():
            return Path(prefix) / name
    return None


def resolve(uri: str, model: Path) -> tuple[Path | None, str | None]:
    """(the path a URI names, which exists, None) or (None, why not)."""

    def find(match: re.Match[str]) -> str:
        root = package_root(match.group(1), model.parent)
        if root is None:
            raise LookupError(
                f"package '{match.group(1)}' is found neither above {model.name} nor in AMENT_PREFIX_PATH"
            )
        return str(root)

    try:
        text = FIND.sub(find, uri)
    except LookupError as exc:
        return None, str(exc)
    if "$(" in text or "${" in text:
        return (
            None,
            "it is computed by xacro (properties or arguments): write the path literally, or copy it by hand",
        )
    if text.startswith("package://"):
        name, _, rest = text[len("package://") :].partition("/")
        root = package_root(name, model.parent)
        if root is None:
            return None, f"package '{name}' is found neither above {model.name} nor in AMENT_PREFIX_PATH"
        path = root / rest
    elif text.startswith("file://"):
        path = Path(text[len("file://") :])
    elif "://" in text:
        return None, f"pkgforge cannot resolve {text.split('://')[0]}:// URIs"
    else:
        path = Path(text) if os.path.isabs(text) else model.parent / text
    if not path.exists():
        return None, f"no file {path}"
    return path, None  # what it is (a regular file, where) is copy_problem's to judge


def model_tree(model: Path) -> Path:
    """The folder of the package that holds the model: the nearest folder at or above the model's
    with a package.xml; for an exporter's folder without one, the folder the exporter wrote: the
    model's folder, or its parent when that is urdf/ (NAME/urdf/NAME.urdf beside NAME/meshes/)."""
    for folder in [model.parent, *model.parent.parents]:
        if (folder / "package.xml").is_file():
            return folder
    return model.parent.parent if model.parent.name == "urdf" else model.parent


def package_folders(uri: str, model: Path) -> list[Path]:
    """The real folders of the packages a URI names ($(find OTHER), package://OTHER), which files
    may be copied from. A package in an install tree built with --symlink-install links each file
    back to its source folder: the folder its package.xml leads to is the package's too."""
    names = [match.group(1) for match in FIND.finditer(uri)]
    if uri.startswith("package://"):
        names.append(uri[len("package://") :].partition("/")[0])
    folders: list[Path] = []
    for name in names:
        root = package_root(name, model.parent)
        if root is not None:
            folders += [Path(os.path.realpath(root)), Path(os.path.realpath(root / "package.xml")).parent]
    return list(dict.fromkeys(folders))


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


FILE_TYPES = {
    stat.S_IFDIR: "a folder",
    stat.S_IFIFO: "a FIFO",
    stat.S_IFSOCK: "a socket",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
}


def copy_problem(
    path: Path, roots: Sequence[Path], suffixes: Sequence[str] | None
) -> tuple[Path | None, str | None]:
    """(the folder of `roots` the file lies in, None), or (None, why pkgforge does not copy it).

    Symbolic links are followed first: the rule holds for the file they lead to. `roots` are
    real paths; `suffixes` None: any name (a xacro file an include names)."""
    real = Path(os.path.realpath(path))
    linked = real != Path(os.path.normpath(os.path.abspath(path)))
    what = f"it leads to {real} (a symbolic link)," if linked else f"{real} is"
    if suffixes is not None:
        kinds = f"not a mesh or texture file (pkgforge copies only {' '.join(suffixes)} files)"
        if path.suffix.lower() not in suffixes:
            return None, kinds
        if real.suffix.lower() not in suffixes:
            return None, f"{what} {kinds}"
    root = next((folder for folder in roots if _inside(real, folder)), None)
    if root is None:
        return None, f"{what} outside {' and '.join(str(r) for r in roots)}"
    try:
        status = os.stat(real)
    except OSError as exc:
        return None, f"cannot read {real}: {exc.strerror}"
    if not stat.S_ISREG(status.st_mode):
        return None, f"{what} not a regular file ({FILE_TYPES.get(stat.S_IFMT(status.st_mode), 'special')})"
    if status.st_size > MAX_COPIED_BYTES:
        return None, (
            f"{real} is {status.st_size >> 20} MiB, over the {MAX_COPIED_BYTES >> 20} MiB pkgforge "
            "copies: copy it by hand"
        )
    if not os.access(real, os.R_OK):
        return None, f"cannot read {real}: permission denied"
    return root, None


def admit(reference: Reference, roots: Sequence[Path], suffixes: Sequence[str] | None) -> None:
    """Apply copy_problem's rule to a resolved reference: a refused one has no source."""
    assert reference.source is not None
    reference.root, problem = copy_problem(reference.source, list(dict.fromkeys(roots)), suffixes)
    if problem is not None:
        reference.source, reference.problem, reference.refused = None, problem, True


def model_references(model: Path, root: etree._Element) -> list[Reference]:
    """The meshes, textures and xacro includes a parsed model names, with their lines."""
    found: list[Reference] = []
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        tag = etree.QName(element).localname
        filename = element.get("filename")
        if filename is None:
            continue
        if tag == "mesh":
            found.append(Reference(filename, model, element.sourceline or 0, "mesh"))
        elif tag == "texture":
            found.append(Reference(filename, model, element.sourceline or 0, "texture"))
        elif tag == "include" and etree.QName(element).namespace == XACRO_NS:
            found.append(Reference(filename, model, element.sourceline or 0, "include"))
    return found


def parse_model(path: Path) -> etree._Element:
    """The root element of a URDF or xacro file; a located PkgforgeError when it cannot be read."""
    try:
        # external entities are never read: a model's <!ENTITY x SYSTEM "file:///..."> would put
        # another file's text in a path, and so in a message (lxml before 5 resolves them)
        parser = etree.XMLParser(remove_comments=False, resolve_entities=False, no_network=True)
        return etree.parse(str(path), parser).getroot()
    except etree.XMLSyntaxError as exc:
        raise PkgforgeError(
            f"{path}:{exc.lineno}: not well-formed XML: {exc.msg}; fix the model (nothing written)"
        ) from exc
    except OSError as exc:
        raise PkgforgeError(f"{path}: cannot read it: {exc.strerror}") from exc


def named_files(mesh: Path) -> list[tuple[str, Path, int, str]]:
    """(name as written, path, line, kind) of each file a mesh names beside itself: a Collada
    <image>'s <init_from>, an OBJ's mtllib, an OBJ or MTL's map_*."""
    named: list[tuple[str, int, str]] = []
    suffix = mesh.suffix.lower()
    try:
        if suffix == ".dae":
            parser = etree.XMLParser(huge_tree=True, resolve_entities=False, no_network=True)
            root = etree.parse(str(mesh), parser).getroot()
            named = [
                (e.text.strip(), e.sourceline or 0, "texture")
                for e in root.iter("{*}init_from")
                if e.text
                and (parent := e.getparent()) is not None
                and etree.QName(parent).localname == "image"
            ]
        elif suffix in (".obj", ".mtl"):
            for number, text in enumerate(mesh.read_text(errors="replace").splitlines(), start=1):
                words = text.split()
                if words and (words[0] == "mtllib" or words[0].startswith("map_")) and len(words) > 1:
                    named.append(
                        (words[-1], number, "material library" if words[0] == "mtllib" else "texture")
                    )
    except (etree.XMLSyntaxError, OSError):
        return []
    files: list[tuple[str, Path, int, str]] = []
    for name, line, kind in named:
        written = name[len("file://") :] if name.startswith("file://") else name
        files.append((name, Path(written) if os.path.isabs(written) else mesh.parent / written, line, kind))
    return files


def inner_references(assets: list[Reference], tree: Path) -> list[Reference]:
    """The textures and material libraries the copied meshes name, under the model's rule: each
    must be one, in the model's package tree or in the folder the mesh naming it was copied from.
    One that does not exist is left out as before (exporters leave stale absolute paths behind;
    the mesh shows without it)."""
    found: list[Reference] = []
    seen: set[Path] = set()
    queue = [(r.source, r.root) for r in assets if r.source is not None and r.root is not None]
    while queue:
        mesh, home = queue.pop(0)
        if Path(os.path.realpath(mesh)) in seen:
            continue  # a library naming itself, or one mesh named twice
        seen.add(Path(os.path.realpath(mesh)))
        for name, path, line, kind in named_files(mesh):
            if not path.exists():
                continue
            reference = Reference(name, Path(os.path.normpath(mesh)), line, kind, source=path)
            admit(reference, [tree, home], INNER_SUFFIXES)
            found.append(reference)
            if reference.source is not None and reference.root is not None:
                queue.append((reference.source, reference.root))
    return found


def _read_copy(path: Path) -> tuple[bytes, int]:
    """A copied file's bytes and the permission bits its copy may have: the source's, never wider
    (a key readable by its owner only stays so), no execute bits (nothing here is run)."""
    try:
        return path.read_bytes(), path.stat().st_mode & 0o666
    except OSError as exc:
        raise PkgforgeError(f"{path}: cannot read it: {exc.strerror} (nothing written)") from exc


def _line_replace(text: str, line: int | None, old: str, new: str) -> str:
    lines = text.split("\n")
    for index in range((line or 1) - 1, len(lines)):  # an attribute may sit below its element's first line
        if old in lines[index]:
            lines[index] = lines[index].replace(f'"{old}"', f'"{new}"').replace(f"'{old}'", f"'{new}'")
            return "\n".join(lines)
    return text


def root_link(root: etree._Element) -> str | None:
    links = [e.get("name") for e in root.iter("link") if e.get("name")]
    children = {child.get("link") for e in root.iter("joint") if (child := e.find("child")) is not None}
    roots = [link for link in links if link not in children]
    return roots[0] if len(roots) == 1 else None


ROBOT_START_TAG = re.compile(r"""<robot\b(?:[^>"']|"[^"]*"|'[^']*')*>""")


def massless_root(text: str, root: etree._Element, path: Path, notes: Notes | None = None) -> str:
    """The model with a massless root link when its root link has an <inertial>.

    KDL ignores a root link's inertia and robot_state_publisher warns (PF604 root-link-inertia);
    exporters put one on base_link. KDL's own advice is a link without inertia above it, joined by
    a fixed joint: that is added right after <robot>, named <root>_root, so no frame the package
    already publishes (base_footprint, world) changes. The RViz Fixed Frame stays the old root."""
    name = root_link(root)
    link = next((e for e in root if e.tag == "link" and e.get("name") == name), None)  # not in a macro
    if name is None or link is None or link.find("inertial") is None:
        return text
    names = {e.get("name") for e in root.iter("link", "joint")}
    new = f"{name}_root"
    while new in names or f"{new}_joint" in names:
        new += "_"
    start = sum(len(line) + 1 for line in text.split("\n")[: (root.sourceline or 1) - 1])
    tag = ROBOT_START_TAG.search(text, start)
    if tag is None:
        return text
    added = (
        f"\n  <!-- added by pkgforge: KDL ignores the inertia of a root link; {name} now hangs below "
        f'this massless link -->\n  <link name="{new}"/>\n  <joint name="{new}_joint" type="fixed">\n'
        f'    <parent link="{new}"/>\n    <child link="{name}"/>\n  </joint>'
    )
    if notes is not None:
        notes.add(
            "migrate-changed",
            f"root link {name} has an inertia, which KDL ignores: link {new} added as "
            "the root, joined to it by a fixed joint",
            path,
            link.sourceline,
        )
    return text[: tag.end()] + added + text[tag.end() :]


@dataclass
class Imported:
    files: dict[str, bytes]  # urdf/... and meshes/..., relative to the package folder
    model_name: str
    root_link: str | None
    meshes: int
    missing: list[Reference]  # not found, or refused (Reference.refused)
    modes: dict[str, int]  # each file's permission bits: its source's, never wider


def _read_models(
    model: Path, tree: Path
) -> tuple[dict[Path, str], list[Reference], dict[Path, etree._Element]]:
    """The model and the xacro files it includes (each with its name in urdf/ and its parsed
    root) and every reference they hold, resolved and admitted.

    A file a model names may lie in the model's package tree, in a package the URI names, or in
    the folder the naming (included) file was admitted from: a package's own xacro names its
    meshes relative to itself."""
    models: dict[Path, str] = {}  # model file → its name in urdf/
    homes = {model: tree}  # model file → the allowed folder it lies in
    references: list[Reference] = []
    queue = [model]
    roots: dict[Path, etree._Element] = {}
    while queue:
        current = queue.pop(0)
        if current in models:
            continue
        models[current] = (
            current.name if current.name not in models.values() else f"{current.parent.name}_{current.name}"
        )
        root = parse_model(current)
        roots[current] = root
        for reference in model_references(current, root):
            reference.source, reference.problem = resolve(reference.uri, current)
            if reference.source is not None:
                allowed = [tree, homes[current], *package_folders(reference.uri, current)]
                admit(reference, allowed, None if reference.kind == "include" else ASSET_SUFFIXES)
            references.append(reference)
            if reference.kind == "include" and reference.source is not None and reference.root is not None:
                queue.append(reference.source)
                homes.setdefault(reference.source, reference.root)
    return models, references, roots


def import_model(
    name: str, model: Path, *, uri_style: str = "package", notes: Notes | None = None
) -> Imported:
    """Read the model (and the xacro files it includes), find every mesh and texture, and say
    what the new package's urdf/ and meshes/ hold."""
    model = model.absolute()
    if not model.is_file():
        raise PkgforgeError(f"{model}: no such file; give the .urdf or .urdf.xacro to import")
    if not model.name.lower().endswith(XACRO_MODEL_SUFFIXES):
        raise PkgforgeError(f"{model}: not a .urdf or .urdf.xacro file")
    tree = Path(os.path.realpath(model_tree(model)))
    models, references, roots = _read_models(model, tree)
    if etree.QName(roots[model]).localname != "robot":
        raise PkgforgeError(
            f"{model}:{roots[model].sourceline}: the root element is "
            f"<{etree.QName(roots[model]).localname}>, not <robot>: not a URDF"
        )
    assets = [r for r in references if r.kind != "include" and r.source is not None]
    inner = inner_references(assets, tree)
    missing = [r for r in [*references, *inner] if r.problem is not None]
    files_to_copy = sorted(
        {Path(os.path.realpath(r.source)) for r in [*assets, *inner] if r.source is not None}
    )
    common = Path(os.path.commonpath([str(f.parent) for f in files_to_copy])) if files_to_copy else None
    placed = {f: Path(os.path.relpath(f, common)).as_posix() for f in files_to_copy}
    files: dict[str, bytes] = {}
    modes: dict[str, int] = {}
    for source, relative in placed.items():
        files[f"meshes/{relative}"], modes[f"meshes/{relative}"] = _read_copy(source)
    for current, file_name in models.items():
        text = current.read_text(encoding="utf-8")
        for reference in references:
            if reference.file != current or reference.source is None:
                continue
            if reference.kind == "include":
                new = f"$(find {name})/urdf/{models[reference.source]}"
            else:
                relative = placed[Path(os.path.realpath(reference.source))]
                new = (
                    f"package://{name}/meshes/{relative}"
                    if uri_style == "package"
                    else f"file://$(find {name})/meshes/{relative}"
                )
            if new != reference.uri:
                text = _line_replace(text, reference.line, reference.uri, new)
        if current == model:
            text = massless_root(text, roots[current], current, notes)
        files[f"urdf/{file_name}"] = text.encode("utf-8")
        modes[f"urdf/{file_name}"] = current.stat().st_mode & 0o666
        if notes is not None:
            from pkgforge.model.ros1_names import is_gazebo_classic_plugin

            for element in roots[current].iter("plugin"):
                if is_gazebo_classic_plugin(element.get("filename", "")):
                    notes.add(
                        "migrate-gazebo-classic",
                        f"Gazebo Classic plugin {element.get('filename')} "
                        "is kept as written; it does not load in Gazebo (gz)",
                        current,
                        element.sourceline,
                    )
    return Imported(
        files,
        models[model],
        root_link(roots[model]),
        len({os.path.realpath(r.source) for r in assets if r.kind == "mesh" and r.source is not None}),
        missing,
        modes,
    )


def what_became(reference: Reference) -> str:
    """'not found: why' or 'not copied: why', as a message line says it."""
    return f"{'not copied' if reference.refused else 'not found'}: {reference.problem}"


def missing_message(missing: list[Reference], *, force: bool = True) -> list[str]:
    """The lines of the error: one per file not found or refused, then what to do
    (PkgforgeError(*lines))."""
    lines = [f"{r.file}:{r.line}: {r.kind} '{r.uri}' {what_became(r)}" for r in missing]
    if any(r.refused for r in missing):
        advice = (
            f"{len(missing)} file(s) the model names cannot be imported: nothing written; pkgforge "
            "copies only mesh and texture files, from the model's package tree and the packages the "
            "model names: copy them there"
        )
    else:
        advice = (
            f"{len(missing)} file(s) the model names cannot be found: nothing written; "
            "copy them where the model says"
        )
    return [*lines, advice + (", or pass --force to write the package without them" if force else "")]


def new_from_urdf(
    spec_options: dict[str, Any],
    model: Path,
    destination: Path,
    *,
    force: int = 0,
    uri_style: str = "package",
) -> tuple[CreatedPackage, Notes, Imported]:
    """Write the package; returns (CreatedPackage, Notes, Imported). `spec_options`: make_spec's."""
    from pkgforge.migrate.notes import Notes
    from pkgforge.scaffold.package import create_package, make_spec, render_files

    name = spec_options["name"]
    make_spec(**spec_options)  # a bad name or option fails before the model is read
    notes = Notes(name)
    imported = import_model(name, model, uri_style=uri_style, notes=notes)
    if imported.missing and not force:
        raise PkgforgeError(*missing_message(imported.missing))
    for reference in imported.missing:
        notes.add(
            "migrate-dropped",
            f"{reference.kind} '{reference.uri}' {'not copied' if reference.refused else 'not found'} "
            f"({reference.problem}); "
            "the package was written without it (--force)",
            reference.file,
            reference.line,
        )
    frame = imported.root_link
    if frame is None:
        frame = "base_link"
        notes.add(
            "migrate-generated",
            "the model's root link is not written literally (xacro macros): the "
            "RViz Fixed Frame is base_link",
            model,
        )
    has_meshes = any(k.startswith("meshes/") for k in imported.files)
    spec = make_spec(
        **spec_options,
        model_name=imported.model_name,
        fixed_frame=frame,
        resource_folders=("launch", "meshes", "rviz", "urdf") if has_meshes else ("launch", "rviz", "urdf"),
    )
    files = render_files(spec)
    for generated in ("urdf/macros.xacro", spec.mesh_file, spec.model_file):
        files.pop(generated, None)
    files.update(imported.files)
    created = create_package(spec, destination, force=force, files=files, modes=imported.modes)
    return created, notes, imported
