"""`pkgforge new NAME --from-urdf FILE`: a CAD exporter's URDF (or xacro) and its meshes become a
package as `pkgforge new` makes it, the model in urdf/, every mesh and texture in meshes/.

Mesh URIs may be `package://OTHER/...` (OTHER found above the model, or in AMENT_PREFIX_PATH),
`file://` (also `file://$(find OTHER)/...`), absolute or relative to the model. Each is copied
with its sub-folders (below the folder all of them share), names and letter case kept, and its
URI rewritten to `package://NAME/meshes/...` (or `file://$(find NAME)/meshes/...`). Textures
that Collada and OBJ meshes name beside themselves come along. A mesh that cannot be found stops
it, naming the file and line, before anything is written (unless --force).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.urdf import XACRO_MODEL_SUFFIXES

if TYPE_CHECKING:
    from pkgforge.migrate.notes import Notes
    from pkgforge.scaffold.package import CreatedPackage

if TYPE_CHECKING:
    from pkgforge.migrate.notes import Notes

URI_STYLES = ("package", "find")
FIND = re.compile(r"\$\(find ([^)\s]+)\)")
XACRO_NS = "http://www.ros.org/wiki/xacro"


@dataclass
class Reference:
    uri: str
    file: Path  # the model file that names it
    line: int | None  # None: lxml knows no line (never for a parsed file)
    kind: str  # mesh | texture | include | inner (a texture a mesh names)
    source: Path | None = None  # the file it resolves to
    problem: str | None = None


def package_root(name: str, near: Path) -> Path | None:
    """The folder of package `name`: a folder above `near` whose package.xml names it, else
    share/<name> in AMENT_PREFIX_PATH (or <prefix>/<name> in ROS_PACKAGE_PATH)."""
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
    """(the file a URI names, None) or (None, why not)."""

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
    if not path.is_file():
        return None, f"no file {path}"
    return path, None


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
        return etree.parse(str(path), etree.XMLParser(remove_comments=False)).getroot()
    except etree.XMLSyntaxError as exc:
        raise PkgforgeError(
            f"{path}:{exc.lineno}: not well-formed XML: {exc.msg}; fix the model (nothing written)"
        ) from exc
    except OSError as exc:
        raise PkgforgeError(f"{path}: cannot read it: {exc.strerror}") from exc


def inner_files(mesh: Path) -> list[Path]:
    """Files a mesh names beside itself: Collada <init_from> images, OBJ mtllib and its maps."""
    names: list[str] = []
    suffix = mesh.suffix.lower()
    try:
        if suffix == ".dae":
            root = etree.parse(str(mesh), etree.XMLParser(huge_tree=True)).getroot()
            names = [
                e.text.strip()
                for e in root.iter("{*}init_from")
                if e.text
                and (parent := e.getparent()) is not None
                and etree.QName(parent).localname == "image"
            ]
        elif suffix in (".obj", ".mtl"):
            for line in mesh.read_text(errors="replace").splitlines():
                words = line.split()
                if words and (words[0] == "mtllib" or words[0].startswith("map_")) and len(words) > 1:
                    names.append(words[-1])
    except (etree.XMLSyntaxError, OSError):
        return []
    files = []
    for name in names:
        name = name[len("file://") :] if name.startswith("file://") else name
        path = (mesh.parent / name) if not os.path.isabs(name) else Path(name)
        if path.is_file():
            files.append(path)
            files.extend(inner_files(path) if path.suffix.lower() == ".mtl" else [])
    return files


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
    missing: list[Reference]


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
    models: dict[Path, str] = {}  # model file → its name in urdf/
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
            references.append(reference)
            if reference.kind == "include" and reference.source is not None:
                queue.append(reference.source)
    if etree.QName(roots[model]).localname != "robot":
        raise PkgforgeError(
            f"{model}:{roots[model].sourceline}: the root element is "
            f"<{etree.QName(roots[model]).localname}>, not <robot>: not a URDF"
        )
    missing = [r for r in references if r.problem is not None]
    assets = [r for r in references if r.kind != "include" and r.source is not None]
    sources = [r.source for r in assets if r.source is not None]
    inner = {f for source in sources for f in inner_files(source)}
    files_to_copy = sorted({source.resolve() for source in sources} | {f.resolve() for f in inner})
    common = Path(os.path.commonpath([str(f.parent) for f in files_to_copy])) if files_to_copy else None
    placed = {f: Path(os.path.relpath(f, common)).as_posix() for f in files_to_copy}
    files: dict[str, bytes] = {f"meshes/{relative}": f.read_bytes() for f, relative in placed.items()}
    for current, file_name in models.items():
        text = current.read_text(encoding="utf-8")
        for reference in references:
            if reference.file != current or reference.source is None:
                continue
            if reference.kind == "include":
                new = f"$(find {name})/urdf/{models[reference.source]}"
            else:
                relative = placed[reference.source.resolve()]
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
        if notes is not None:
            from pkgforge.migrate.table import is_gazebo_classic_plugin

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
        len({r.source.resolve() for r in assets if r.kind == "mesh" and r.source is not None}),
        missing,
    )


def missing_message(missing: list[Reference], *, force: bool = True) -> list[str]:
    """The lines of the error: one per file not found, then what to do (PkgforgeError(*lines))."""
    lines = [f"{r.file}:{r.line}: {r.kind} '{r.uri}' not found: {r.problem}" for r in missing]
    return [
        *lines,
        f"{len(missing)} file(s) the model names cannot be found: nothing written; "
        "copy them where the model says"
        + (", or pass --force to write the package without them" if force else ""),
    ]


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
            f"{reference.kind} '{reference.uri}' not found ({reference.problem}); "
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
    created = create_package(spec, destination, force=force, files=files)
    return created, notes, imported
