"""Where the URIs of a model that `new --from-urdf` (and migrate) imports lead: package:// and
$(find) URIs to a package above the model or in AMENT_PREFIX_PATH, or to the folder an exporter
wrote; file:// and plain paths as written."""

from __future__ import annotations

import os
import re
from pathlib import Path

from lxml import etree

FIND = re.compile(r"\$\(find ([^)\s]+)\)")


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


def exporter_folder(name: str, rest: str, model: Path, found: dict[str, Path] | None = None) -> Path | None:
    """The folder a `package://NAME/REST` that names no package means, as the exporter wrote it, or
    None: the package folder around the model when REST is there (a SolidWorks export named
    package://<model>-URDF/meshes/... in a package of another name), else the folder NAME beside
    the model (onshape-to-robot's package://assets/..., which pybullet and MuJoCo read so). One
    NAME means one folder: the first that holds a file the model names (`found` remembers it)."""
    if name in ("", ".", ".."):
        return None  # no name a package or an exporter's folder has
    if found is not None and name in found:
        return found[name] if (found[name] / rest).exists() else None
    tree = model_tree(model)
    for folder in (tree, model.parent / name, tree / name):
        if rest and (folder / rest).exists():
            if found is not None:
                found[name] = folder
            return folder
    return None


def resolve(uri: str, model: Path, found: dict[str, Path] | None = None) -> tuple[Path | None, str | None]:
    """(the path a URI names, which exists, None) or (None, why not). A package:// URI naming no
    package is read in the exporter's folder (exporter_folder), which `found` records."""

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
        root = package_root(name, model.parent) or exporter_folder(name, rest, model, found)
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


# what xacro computes in a URI: a property or an argument, any substitution but $(find)
COMPUTED = re.compile(r"\$\{|\$\((?!find )")


def static_folder(uri: str) -> str | None:
    """The literal folder a computed URI starts with (package://P/meshes/ of
    package://P/meshes/${name}.stl), or None when it is not computed or has no literal folder."""
    match = COMPUTED.search(uri)
    if match is None:
        return None
    head = uri[: match.start()]
    cut = head.rfind("/")
    return head[: cut + 1] if cut > 0 and not COMPUTED.search(head[: cut + 1]) else None


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
