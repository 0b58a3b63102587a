"""Mesh URIs resolved in the install tree, and mesh files checked to be what they claim.

Readability is judged from headers and sizes (binary STL: 84 bytes + 50 per
triangle; ASCII STL: `solid` … `facet`; COLLADA: an XML root <COLLADA>; OBJ:
vertex lines), not with a mesh library: that costs a numpy import on every
run to learn what the first kilobytes tell.
"""

from __future__ import annotations

import os
import posixpath
import stat
import struct
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlparse

from pkgforge.model.source import NotRegularFile, read_head
from pkgforge.tree import InstallTree

READ_LIMIT = 1 << 20


@dataclass(frozen=True)
class MeshLookup:
    status: str  # found | missing | case | unchecked | escapes | unknown-package | unsupported
    path: Path | None = None
    package: str | None = None
    relative: str | None = None
    real_name: str | None = None  # for case: the name on disk


def resolve_uri(uri: str, tree: InstallTree, base: Path | None = None) -> MeshLookup:
    if uri.startswith("package://"):
        package, _, relative = uri[len("package://") :].partition("/")
        relative = unquote(relative)
        normal = posixpath.normpath(relative)
        if normal.startswith("..") or normal.startswith("/"):
            return MeshLookup("escapes", None, package, relative)
        if package in tree.phantom_packages:
            return MeshLookup("unchecked", None, package, normal)
        share = tree.installed_share(package)
        if share is None:
            return MeshLookup("unknown-package", None, package, normal)
        return _unless_unpredicted(_check(share / normal, package, normal), tree, package)
    if uri.startswith("file://"):
        path = Path(unquote(urlparse(uri).path))
        located = tree.locate(str(path)) if tree.is_phantom(str(path)) else None
        if located is not None and located[0] in tree.phantom_packages:
            # file://$(find zed_msgs)/meshes/zed.stl: a declared package not installed here, as
            # its package:// URI would be (zed-ros2-wrapper's zed_descr.urdf.xacro)
            return MeshLookup("unchecked", None, located[0], located[1])
        located = tree.locate(str(path))
        return _unless_unpredicted(_check(path, None, None), tree, located[0] if located else None)
    if "://" in uri:
        return MeshLookup("unsupported")
    if base is not None:  # a relative path: relative to the model file, as urdfdom does
        return _check(base.parent / uri, None, None)
    return MeshLookup("unsupported")


def _unless_unpredicted(lookup: MeshLookup, tree: InstallTree, package: str | None) -> MeshLookup:
    """A mesh missing from the share folder of a package whose install pkgforge cannot predict is
    not known to be missing (its real install may have it): unchecked."""
    if lookup.status == "missing" and package is not None and package in tree.unpredicted:
        return MeshLookup("unchecked", lookup.path, package, lookup.relative)
    return lookup


def _check(path: Path, package: str | None, relative: str | None) -> MeshLookup:
    try:
        is_folder = stat.S_ISDIR(os.stat(path).st_mode)
    except OSError:
        is_folder = True  # nothing there (or a dangling link): look for another case of the name
    if not is_folder:  # a file, or a FIFO or device standing in one's place (unreadable says which)
        return MeshLookup("found", path, package, relative)
    parent = path.parent
    if parent.is_dir():
        wanted = path.name.lower()
        for entry in os.listdir(parent):
            if entry.lower() == wanted and entry != path.name:
                return MeshLookup("case", path, package, relative, entry)
    return MeshLookup("missing", path, package, relative)


def unreadable(path: Path) -> str | None:
    """Why the mesh file is not a readable mesh of its kind, or None when it is."""
    suffix = path.suffix.lower()
    try:
        head, size = read_head(path, READ_LIMIT)
    except NotRegularFile as error:
        return str(error.strerror)
    except OSError as error:
        return f"cannot read it: {error.strerror}"
    if size == 0:
        return "the file is empty"
    if suffix == ".stl":
        return _stl_problem(head, size)
    if suffix == ".dae":
        text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
        if not text.startswith(b"<"):
            return "a .dae file must be COLLADA XML; this does not start with '<'"
        if b"<COLLADA" not in head[:4096]:
            return "no <COLLADA> root element in the first 4 kB"
        return None
    if suffix == ".obj":
        if b"\nv " not in b"\n" + head and not head.startswith(b"v "):
            return "an OBJ file needs vertex lines ('v x y z'); none in the first MB"
        return None
    return None  # other formats (.glb, .ply, textures) are passed to their loaders unchecked


def _stl_problem(head: bytes, size: int) -> str | None:
    if len(head) >= 84:
        (count,) = struct.unpack_from("<I", head, 80)
        if 84 + 50 * count == size:
            return None  # a binary STL, whatever its header says
    if head.lstrip().lower().startswith(b"solid"):
        if b"facet" in head or size > READ_LIMIT:
            return None
        return "an ASCII STL with no 'facet' in it"
    if len(head) < 84:
        return f"{size} bytes is too short for an STL (a binary STL has an 84-byte header)"
    (count,) = struct.unpack_from("<I", head, 80)
    return (
        f"binary STL header says {count} triangles ({84 + 50 * count} bytes), "
        f"but the file has {size} bytes: truncated or not an STL"
    )
