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
from pkgforge.scaffold.model_uris import COMPUTED, model_tree, package_folders, resolve, static_folder
from pkgforge.urdf import XACRO_MODEL_SUFFIXES
from pkgforge.walk import WalkLimit, walk

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes
    from pkgforge.scaffold.package import CreatedPackage

URI_STYLES = ("package", "find")
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
    # a URI xacro computes below a literal folder (package://P/meshes/${name}.stl): that folder as
    # written (package://P/meshes/) and found; every mesh and texture in it comes along
    static: str | None = None
    folder: Path | None = None


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


URI_PREFIXES = ("package://", "$(find ", "file://")


def model_references(
    model: Path, root: etree._Element, text: str | None = None, *, values: bool = False
) -> list[Reference]:
    """The meshes, textures and xacro includes a parsed model names, each at the line of its
    filename (given the text: libxml2 gives an element the line its start tag ends on). `values`:
    also every other attribute holding a URI (a xacro property's package://P/meshes/, a macro's
    default), kind "value": what xacro computes a mesh's filename from."""
    lines = text.split("\n") if text is not None else None
    found: list[Reference] = []
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        tag = etree.QName(element).localname
        for attribute, value in element.items():
            kind = None
            if attribute == "filename" and tag in ("mesh", "texture"):
                kind = tag
            elif attribute == "filename" and tag == "include" and etree.QName(element).namespace == XACRO_NS:
                kind = "include"
            elif values and value.strip().startswith(URI_PREFIXES):
                kind = "value"
            if kind is not None:
                line = value_line(lines, element.sourceline or 0, value) if lines else element.sourceline or 0
                found.append(Reference(value, model, line, kind))
    return found


def _escaped(value: str) -> str:
    return value.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;")


def value_line(lines: list[str], end: int, value: str) -> int:
    """The line of an attribute value in an element whose start tag ends on line `end`."""
    for index in range(min(end, len(lines)) - 1, max(end - 64, 0) - 1, -1):
        if value in lines[index] or _escaped(value) in lines[index]:
            return index + 1
    return end


class ModelUnreadable(PkgforgeError):
    """A model that cannot be read: where and why, for a caller that goes on without it."""

    def __init__(self, path: Path, line: int | None, why: str, advice: str) -> None:
        super().__init__(f"{path}{f':{line}' if line else ''}: {why}{advice}")
        self.path, self.line, self.why = path, line, why


@dataclass
class ModelFile:
    """A model file as read: its bytes, text (undecodable bytes kept as they are), root element,
    and the line of content after the root element, which ROS 1's TinyXML and urdfdom's tinyxml2
    read past (a <transmission> pasted after </robot>)."""

    path: Path
    data: bytes
    root: etree._Element
    trailing_line: int | None = None

    @property
    def text(self) -> str:
        return decode(self.data)


def decode(data: bytes) -> str:
    """A model's bytes as text, byte for byte: no newline translation (CRLF stays CRLF), and bytes
    that are not UTF-8 kept as they are (encode() gives them back)."""
    return data.decode("utf-8", "surrogateescape")


def encode(text: str) -> bytes:
    return text.encode("utf-8", "surrogateescape")


def read_model(path: Path) -> ModelFile:
    """The model file; a located PkgforgeError when it cannot be read. Content after the root
    element is read as ROS 1's tools did: the root element, the rest left alone (trailing_line)."""
    from pkgforge.model.source import read_regular

    try:
        data = read_regular(path)  # a FIFO or a device is refused, never read
    except OSError as exc:
        raise ModelUnreadable(path, None, f"cannot read it: {exc.strerror}", "") from exc
    # external entities are never read: a model's <!ENTITY x SYSTEM "file:///..."> would put
    # another file's text in a path, and so in a message (lxml before 5 resolves them)
    parser = etree.XMLParser(remove_comments=False, resolve_entities=False, no_network=True)
    try:
        return ModelFile(path, data, etree.fromstring(data, parser, base_url=str(path)))
    except etree.XMLSyntaxError as exc:
        if exc.code != etree.ErrorTypes.ERR_DOCUMENT_END:
            raise ModelUnreadable(
                path, exc.lineno, f"not well-formed XML: {exc.msg}", "; fix the model (nothing written)"
            ) from exc
        trailing = exc.lineno
    recovering = etree.XMLParser(remove_comments=False, resolve_entities=False, no_network=True, recover=True)
    return ModelFile(path, data, etree.fromstring(data, recovering, base_url=str(path)), trailing)


def parse_model(path: Path) -> etree._Element:
    """The root element of a URDF or xacro file; a located PkgforgeError when it cannot be read."""
    return read_model(path).root


def trailing_message(model: ModelFile) -> str:
    return (
        f"content after </{etree.QName(model.root).localname}>: ROS 1's parser read the first element "
        "and went on; xacro refuses it; kept as written"
    )


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


def replace_values(text: str, mapping: dict[str, str]) -> str:
    """Every quoted attribute value `old` of mapping → `new`, in one pass over the whole file: one
    URI always means the same file in one model, so each of its uses (a visual's and a collision's)
    is rewritten, wherever its element's lines are. Values written with entities (&amp;) too."""
    variants = {**{_escaped(k): _escaped(v) for k, v in mapping.items()}, **mapping}
    if not variants:
        return text
    pattern = re.compile(
        r"([\"'])(" + "|".join(map(re.escape, sorted(variants, key=len, reverse=True))) + r")\1"
    )
    return pattern.sub(lambda m: m.group(1) + variants[m.group(2)] + m.group(1), text)


def _unrewritten(text: str, path: Path, mapping: dict[str, str]) -> list[str]:
    """The values of the rewritten model that still name an old place (an attribute the text
    writes in a way pkgforge did not find): each would be a mesh the new package cannot resolve."""
    if not mapping:
        return []
    parser = etree.XMLParser(remove_comments=True, resolve_entities=False, no_network=True, recover=True)
    root = etree.fromstring(encode(text), parser, base_url=str(path))
    left = mapping.keys() - set(mapping.values())
    return sorted(
        {value for e in root.iter() if isinstance(e.tag, str) for value in e.values() if value in left}
    )


def root_link(root: etree._Element) -> str | None:
    links = [e.get("name") for e in root.iter("link") if e.get("name")]
    children = {child.get("link") for e in root.iter("joint") if (child := e.find("child")) is not None}
    roots = [link for link in links if link not in children]
    return roots[0] if len(roots) == 1 else None


ROBOT_START_TAG = re.compile(r"""<robot\b(?:[^>"']|"[^"]*"|'[^']*')*>""")


def massless_root(text: str, root: etree._Element, path: Path, notes: Notes | None = None) -> str:
    """The model with a massless root link when its root link has an <inertial> (--add-root-link).

    KDL ignores a root link's inertia and robot_state_publisher warns (PF604 root-link-inertia);
    exporters put one on base_link. KDL's own advice is a link without inertia above it, joined by
    a fixed joint: that is added right after <robot>, named <root>_root, so no frame the package
    already publishes (base_footprint, world) changes. The RViz Fixed Frame stays the old root.
    The file's line endings are kept (a CRLF export stays CRLF)."""
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
    eol = "\r\n" if "\r\n" in text else "\n"
    added = eol.join(
        [
            "",
            f"  <!-- added by pkgforge (add-root-link): KDL ignores the inertia of a root link; {name} "
            "now hangs below this massless link -->",
            f'  <link name="{new}"/>',
            f'  <joint name="{new}_joint" type="fixed">',
            f'    <parent link="{new}"/>',
            f'    <child link="{name}"/>',
            "  </joint>",
        ]
    )
    if notes is not None:
        notes.add(
            "migrate-changed",
            f"root link {name} has an inertia, which KDL ignores: link {new} added as "
            "the root, joined to it by a fixed joint (--add-root-link)",
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


# the most files a folder a model computes mesh names in may bring along
MAX_FOLDER_FILES = 10_000


def _admit_folder(
    reference: Reference, current: Path, tree: Path, home: Path, found: dict[str, Path]
) -> None:
    """A URI computed below a literal folder (Reference.static): find the folder, which must lie in
    the model's tree, the naming file's home or the package the URI names."""
    assert reference.static is not None
    folder, problem = resolve(reference.static, current, found)
    if folder is not None and not folder.is_dir():
        folder, problem = None, f"{folder} is not a folder"
    if folder is None:
        reference.problem = problem
        return
    real = Path(os.path.realpath(folder))
    roots = list(dict.fromkeys([tree, home, *package_folders(reference.static, current)]))
    reference.root = next((r for r in roots if _inside(real, r)), None)
    if reference.root is None:
        reference.problem, reference.refused = f"{real} is outside {' and '.join(map(str, roots))}", True
    else:
        reference.folder = folder


def _read_models(
    model: Path, tree: Path, found: dict[str, Path]
) -> tuple[dict[Path, str], list[Reference], dict[Path, ModelFile]]:
    """The model and the xacro files it includes (each with its name in urdf/ and as read) and every
    reference they hold, resolved and admitted.

    A file a model names may lie in the model's package tree, in a package the URI names, or in
    the folder the naming (included) file was admitted from: a package's own xacro names its
    meshes relative to itself. A URI xacro computes below a literal folder brings the folder's
    meshes and textures; any other attribute holding a URI (a property's value) that names a mesh
    or a folder of meshes brings them too; one that names nothing is left alone."""
    models: dict[Path, str] = {}  # model file → its name in urdf/
    homes = {model: tree}  # model file → the allowed folder it lies in
    references: list[Reference] = []
    queue = [model]
    files: dict[Path, ModelFile] = {}
    while queue:
        current = queue.pop(0)
        if current in models:
            continue
        models[current] = (
            current.name if current.name not in models.values() else f"{current.parent.name}_{current.name}"
        )
        read = files[current] = read_model(current)
        for reference in model_references(current, read.root, read.text, values=True):
            computed = COMPUTED.search(reference.uri) is not None
            folder_value = reference.kind == "value" and reference.uri.rstrip().endswith("/")
            if (computed and reference.kind != "include") or folder_value:
                reference.static = reference.uri if folder_value else static_folder(reference.uri)
                if reference.static is None:
                    if reference.kind != "value":
                        reference.problem = resolve(reference.uri, current)[1]
                        references.append(reference)
                    continue
                _admit_folder(reference, current, tree, homes[current], found)
                if reference.kind == "value" and reference.folder is None:
                    continue  # a value naming no folder here: not pkgforge's to bring
                references.append(reference)
                continue
            reference.source, reference.problem = resolve(reference.uri, current, found)
            if reference.kind == "value" and (
                reference.source is None or not reference.uri.lower().endswith(ASSET_SUFFIXES)
            ):
                continue  # a value that names no mesh or texture: left as written
            if reference.source is not None:
                allowed = [tree, homes[current], *package_folders(reference.uri, current)]
                admit(reference, allowed, None if reference.kind == "include" else ASSET_SUFFIXES)
            references.append(reference)
            if reference.kind == "include" and reference.source is not None and reference.root is not None:
                queue.append(reference.source)
                homes.setdefault(reference.source, reference.root)
    return models, references, files


def folder_assets(folders: list[Reference], tree: Path) -> list[Reference]:
    """The meshes and textures in each folder a model computes names in (what xacro may name there),
    each admitted as a mesh the model names."""
    found: list[Reference] = []
    seen: set[Path] = set()
    for reference in folders:
        if reference.folder is None or reference.root is None:
            continue
        limits: list[WalkLimit] = []
        for folder, subfolders, names in walk(reference.folder, limits=limits, max_files=MAX_FOLDER_FILES):
            subfolders[:] = sorted(f for f in subfolders if not f.startswith("."))
            for name in sorted(names):
                path = Path(folder) / name
                if name.startswith(".") or not name.lower().endswith(ASSET_SUFFIXES) or path in seen:
                    continue
                seen.add(path)
                uri = (reference.static or "") + path.relative_to(reference.folder).as_posix()
                asset = Reference(uri, reference.file, reference.line, "mesh", source=path)
                admit(asset, [tree, reference.root], ASSET_SUFFIXES)
                found.append(asset)
        if limits:
            reference.problem = f"{limits[0].path}: {limits[0].why}"
    return found


def _new_uri(name: str, relative: str, uri_style: str) -> str:
    return (
        f"package://{name}/meshes/{relative}"
        if uri_style == "package"
        else f"file://$(find {name})/meshes/{relative}"
    )


def _rewrites(
    name: str,
    current: Path,
    references: list[Reference],
    models: dict[Path, str],
    placed: dict[Path, str],
    common: Path | None,
    uri_style: str,
) -> dict[str, str]:
    """Each URI of `current` that changes → what it becomes in the new package."""
    mapping: dict[str, str] = {}
    for reference in references:
        if reference.file != current or reference.problem is not None:
            continue
        if reference.kind == "include" and reference.source is not None:
            new = f"$(find {name})/urdf/{models[reference.source]}"
        elif reference.source is not None:
            new = _new_uri(name, placed[Path(os.path.realpath(reference.source))], uri_style)
        elif reference.folder is not None and reference.static is not None and common is not None:
            relative = os.path.relpath(os.path.realpath(reference.folder), common)
            if relative.startswith(".."):
                continue  # a folder with no mesh in it: nothing of it was copied
            folder = "" if relative == "." else Path(relative).as_posix() + "/"
            new = _new_uri(name, folder, uri_style) + reference.uri[len(reference.static) :]
        else:
            continue
        if new != reference.uri:
            mapping[reference.uri] = new
    return mapping


def import_model(
    name: str,
    model: Path,
    *,
    uri_style: str = "package",
    notes: Notes | None = None,
    add_root_link: bool = False,
) -> Imported:
    """Read the model (and the xacro files it includes), find every mesh and texture, and say
    what the new package's urdf/ and meshes/ hold. Models are copied byte for byte but for the
    URIs that name what was copied (and --add-root-link's link)."""
    model = model.absolute()
    if not model.is_file():
        raise PkgforgeError(f"{model}: no such file; give the .urdf or .urdf.xacro to import")
    if not model.name.lower().endswith(XACRO_MODEL_SUFFIXES):
        raise PkgforgeError(f"{model}: not a .urdf or .urdf.xacro file")
    tree = Path(os.path.realpath(model_tree(model)))
    found: dict[str, Path] = {}
    models, references, read = _read_models(model, tree, found)
    top = read[model].root
    if etree.QName(top).localname != "robot":
        raise PkgforgeError(
            f"{model}:{top.sourceline}: the root element is <{etree.QName(top).localname}>, not <robot>: not a URDF"
        )
    if notes is not None:
        _note_read(notes, read, references, found)
    assets = [r for r in references if r.kind != "include" and r.source is not None]
    assets += folder_assets([r for r in references if r.folder is not None], tree)
    inner = inner_references(assets, tree)
    if any(r.kind == "value" and r.folder is not None for r in references):
        # a filename computed whole (${mesh_path}base.stl) from a property naming a folder that
        # came along: the property is rewritten, so xacro computes a name in the new package
        references = [
            r for r in references if not (r.problem and r.static is None and COMPUTED.search(r.uri))
        ]
    missing = [r for r in [*references, *assets, *inner] if r.problem is not None]
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
        mapping = _rewrites(name, current, references, models, placed, common, uri_style)
        text = replace_values(read[current].text, mapping)
        left = _unrewritten(text, current, mapping)
        if left:  # never a package whose meshes resolve in the source only
            raise PkgforgeError(
                f"{current}: pkgforge could not rewrite {len(left)} URI(s) ({left[0]} …): nothing written; "
                "please report it"
            )
        if current == model and add_root_link:
            text = massless_root(text, read[current].root, current, notes)
        files[f"urdf/{file_name}"] = encode(text)
        modes[f"urdf/{file_name}"] = current.stat().st_mode & 0o666
    return Imported(
        files,
        models[model],
        root_link(top),
        len({os.path.realpath(r.source) for r in assets if r.kind == "mesh" and r.source is not None}),
        missing,
        modes,
    )


def _note_read(
    notes: Notes, read: dict[Path, ModelFile], references: list[Reference], found: dict[str, Path]
) -> None:
    """What the import reads differently from a strict XML parser or a ROS 2 package lookup."""
    from pkgforge.model.ros1_names import is_gazebo_classic_plugin

    for current, model in read.items():
        if model.trailing_line is not None:
            notes.add("migrate-source-defect", trailing_message(model), current, model.trailing_line)
        for element in model.root.iter("plugin"):
            if is_gazebo_classic_plugin(element.get("filename", "")):
                notes.add(
                    "migrate-gazebo-classic",
                    f"Gazebo Classic plugin {element.get('filename')} "
                    "is kept as written; it does not load in Gazebo (gz)",
                    current,
                    element.sourceline,
                )
    for package, folder in found.items():
        first = next(r for r in references if r.uri.startswith(f"package://{package}/"))
        notes.add("migrate-generated", folder_message(package, folder, first.file), first.file, first.line)


def folder_message(package: str, folder: Path, model: Path) -> str:
    where = "the package folder around" if folder == model_tree(model) else "the folder beside"
    return (
        f"package://{package}/ names no package: read as {Path(os.path.normpath(folder)).name}/, {where} "
        f"{model.name}, where the exporter put what it names"
    )


def default_name(model: Path) -> tuple[str, str]:
    """(the name `new --from-urdf` gives the package when NAME is left out, how it was chosen): the
    name of the model's package (its package.xml), else of the exporter's folder, made valid when it
    breaks REP 144 (an exporter's Arm_2_description → arm_2_description)."""
    from pkgforge.model.names import rep144_advice, rep144_problem, suggested_name

    tree = model_tree(model.absolute())
    name, what = tree.name, f"the folder {tree.name}"
    if (tree / "package.xml").is_file():
        try:
            named = (etree.parse(str(tree / "package.xml")).findtext("name") or "").strip()
        except (etree.XMLSyntaxError, OSError):
            named = ""
        if named:
            name, what = named, f"the name of its package {named}"
    if rep144_problem(name) is None and rep144_advice(name) is None:
        return name, f"the package is named {name}: {what} (give NAME to choose another)"
    valid = suggested_name(name)
    if valid is None:
        raise PkgforgeError(
            f"{model}: {what} is no valid package name and none is near it: give the package's NAME"
        )
    return (
        valid,
        f"the package is named {valid}: {what}, made valid for REP 144 (give NAME to choose another)",
    )


def what_became(reference: Reference) -> str:
    """'not found: why' or 'not copied: why', as a message line says it."""
    return f"{'not copied' if reference.refused else 'not found'}: {reference.problem}"


def missing_message(missing: list[Reference], *, force: bool = True) -> list[str]:
    """One line per file the model names and pkgforge cannot bring (a mesh a visual and a collision
    both name is one line, with the other lines it is named at), then what to do
    (PkgforgeError(*lines))."""
    groups: dict[tuple[Path, str, str, str], list[Reference]] = {}
    for reference in missing:
        key = (reference.file, reference.kind, reference.uri, what_became(reference))
        groups.setdefault(key, []).append(reference)
    lines = []
    for (file, kind, uri, became), uses in groups.items():
        also = sorted({u.line or 0 for u in uses[1:] if u.line != uses[0].line})
        more = f" (also line {', '.join(map(str, also))})" if also else ""
        lines.append(f"{file}:{uses[0].line}: {kind} '{uri}' {became}{more}")
    if any(r.refused for r in missing):
        advice = (
            f"{len(groups)} file(s) the model names cannot be imported: nothing written; pkgforge "
            "copies only mesh and texture files, from the model's package tree and the packages the "
            "model names: copy them there"
        )
    else:
        advice = (
            f"{len(groups)} file(s) the model names cannot be found: nothing written; "
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
    add_root_link: bool = False,
    name_note: str | None = None,
) -> tuple[CreatedPackage, Notes, Imported]:
    """Write the package; returns (CreatedPackage, Notes, Imported). `spec_options`: make_spec's.
    `name_note`: how the name was chosen when the command line gave none (default_name)."""
    from pkgforge.scaffold.notes import Notes
    from pkgforge.scaffold.package import create_package, make_spec, render_files

    name = spec_options["name"]
    make_spec(**spec_options)  # a bad name or option fails before the model is read
    notes = Notes(name)
    if name_note is not None:
        notes.add("migrate-generated", name_note, model.absolute(), None)
    imported = import_model(name, model, uri_style=uri_style, notes=notes, add_root_link=add_root_link)
    if imported.missing and not force:
        raise PkgforgeError(*missing_message(imported.missing))
    seen: set[tuple[Path, str]] = set()
    for reference in imported.missing:
        if (reference.file, reference.uri) in seen:
            continue  # one line per file, not per use
        seen.add((reference.file, reference.uri))
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
