"""InstallTree: the install space launch files are resolved against.

- predicted: the models' install layouts, materialised as a temporary prefix of
  symlinks with the ament index markers (fast; pre-commit);
- built: a real colcon build into a pkgforge-owned base (`--build`);
- existing: the user's own `colcon build` output, merged or isolated (`--install-base`).

The worker never sees the user's files through this tree: each is materialised
in a pkgforge-owned temporary folder (tmpfs /dev/shm when it has room), small
files copied, large meshes and images (over LINK_THRESHOLD) left as links that
the worker's guard (sandbox/guard.py) copies before any write through them. For
`--build` and `--install-base` the worker sees such a shadow of the install
base, never the install base itself; `locate` works on the shadow, `origin` and
`in_tree` map between the shadow and the user's paths.

Declared dependencies that are in none of these (robot_state_publisher, rviz2 …
on a machine without ROS) get a phantom prefix: an empty share folder and an
index marker, so lookups succeed as they would on the robot while pkgforge knows
that nothing under it can be checked.
"""

from __future__ import annotations

import os
import re
import stat
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from pkgforge.build.toolchain import TREE_PYTHONPATH, prepend_path, python_paths
from pkgforge.errors import PkgforgeError
from pkgforge.model.package import PackageModel
from pkgforge.model.source import read_regular
from pkgforge.walk import MAX_DEPTH, remove_tree

if TYPE_CHECKING:
    from pkgforge.workspace import Workspace

# what an entry of the tree is (inode, mode, size, mtime, ctime), to see whether a launch file changed
# it (ctime: no process can set it back, as `touch -d` sets mtime back)
Stamp = tuple[int, int, int, int, int]
INDEX = Path("share/ament_index/resource_index/packages")


@dataclass
class InstallTree:
    kind: str  # predicted | built | existing
    prefixes: list[Path]
    phantom: Path | None = None
    packages: dict[str, Path] = field(default_factory=dict)  # package → prefix holding it
    phantom_packages: set[str] = field(default_factory=set)
    # workspace packages (share names) whose install pkgforge cannot predict → where (file, line):
    # their share folder stands in for what they install with their source mirrored (predicted tree)
    unpredicted: dict[str, tuple[Path, int | None]] = field(default_factory=dict)
    # packages of an AMENT_PREFIX_PATH the user already has (a sourced ROS) → their prefix
    system_packages: dict[str, Path] = field(default_factory=dict)
    _temporary: tempfile.TemporaryDirectory[str] | None = None
    root: Path | None = None  # pkgforge's temporary folder: the only place the worker may write
    shadows: dict[str, str] = field(default_factory=dict)  # shadow prefix → the user's prefix
    copied: dict[str, str] = field(default_factory=dict)  # file in the tree → the user's file it copies
    _plan: _Plan | None = None  # how the tree was made, to restore what a launch file changed
    _stamps: dict[str, Stamp] = field(default_factory=dict)
    sealed: int = 0  # time (ns) the tree was complete: entries older than it are pkgforge's
    # the install base the user's own launch would see in place of the tree's `install` folder:
    # theirs (--install-base), pkgforge's build in their workspace (--build), or colcon's default
    # <workspace>/install (predicted); None: not known
    user_install: Path | None = None

    def share(self, package: str) -> Path | None:
        """The package's share folder in the tree (workspace packages)."""
        prefix = self.packages.get(package)
        return prefix / "share" / package if prefix else None

    def installed_share(self, package: str) -> Path | None:
        """The share folder in the tree, else in a prefix the user already has."""
        prefix = self.packages.get(package) or self.system_packages.get(package)
        return prefix / "share" / package if prefix else None

    def locate(self, path: str) -> tuple[str, str, Path] | None:
        """(package, path inside its share folder, prefix) for a path in the tree, else None."""
        real = os.path.normpath(path)
        for prefix in [*self.prefixes, *([self.phantom] if self.phantom else [])]:
            share = str(prefix / "share") + os.sep
            if real.startswith(share):
                package, _, rest = real[len(share) :].partition(os.sep)
                return package, rest.replace(os.sep, "/"), prefix
        return None

    def origin(self, path: str) -> str:
        """The user's file a path of the tree stands for (itself, resolved, when none)."""
        normal = os.path.normpath(path)
        source = self.copied.get(normal)
        if source is not None:
            return os.path.realpath(source)
        for shadow, user in self.shadows.items():
            if normal.startswith(shadow + os.sep):
                return os.path.realpath(user + normal[len(shadow) :])
        return os.path.realpath(path)

    def as_users(self, text: str) -> str:
        """Text (a command line, a path) with every path into the tree's install folder written as
        the user's own install base would give it: what their launch would see, spaces included."""
        if self.user_install is None or self.root is None:
            return text
        install = str(self.root / "install")
        return re.sub(re.escape(install) + r"(?![^/\s'\"])", lambda _: str(self.user_install), text)

    def in_tree(self, path: str) -> str:
        """A path in the user's install base → the same path in the tree the worker sees."""
        normal = os.path.normpath(path)
        for shadow, user in self.shadows.items():
            if normal == user or normal.startswith(user + os.sep):
                return shadow + normal[len(user) :]
        return path

    def is_phantom(self, path: str) -> bool:
        return self.phantom is not None and os.path.normpath(path).startswith(str(self.phantom) + os.sep)

    def environment(self, base: dict[str, str] | None = None) -> dict[str, str]:
        env = dict(os.environ if base is None else base)
        value = env.get("AMENT_PREFIX_PATH", "")
        if self.phantom is not None:
            value = value + (os.pathsep if value else "") + str(self.phantom)
        for prefix in reversed(self.prefixes):
            value = prepend_path(str(prefix), value)
        env["AMENT_PREFIX_PATH"] = value
        # what sourcing the tree's setup script adds: its Python packages (a launch file's import
        # of a workspace package's module), first; a launch worker puts them on sys.path
        own = [folder for prefix in self.prefixes for folder in python_paths(str(prefix))]
        if own:
            python = env.get("PYTHONPATH", "")
            for folder in reversed(own):
                python = prepend_path(folder, python)
            env["PYTHONPATH"] = python
            env[TREE_PYTHONPATH] = os.pathsep.join(own)
        if self.phantom is not None:
            env["PKGFORGE_PHANTOM_PREFIX"] = str(self.phantom)
        if self.root is not None:
            env["PKGFORGE_SANDBOX"] = str(self.root)  # the worker's guard allows writes only here
            # and refuses changes to what is installed there, as made (sandbox/guard.py)
            env["PKGFORGE_SANDBOX_SEALED"] = str(self.sealed)
        return env

    def restore(self) -> int:
        """Undo what launch files changed in the tree (they may write to their share folder), so
        the checks after them read the user's files; → how many entries were put back."""
        if self._plan is None or self.root is None:
            return 0
        changed = self._plan.restore(self.root, self._stamps)
        if changed:
            self._stamps = self._plan.stamps(self.root)
            self.sealed = time.time_ns()
        return changed

    def close(self) -> None:
        if self._temporary is not None:
            try:
                self._temporary.cleanup()
            except (OSError, RecursionError):  # what a launch file left: nested, or made unreadable
                remove_tree(self._temporary.name)
            self._temporary = None


def _index(prefixes: list[Path]) -> dict[str, Path]:
    found: dict[str, Path] = {}
    for prefix in prefixes:
        folder = prefix / INDEX
        if folder.is_dir():
            for marker in sorted(folder.iterdir()):
                found.setdefault(marker.name, prefix)
    return found


def _user_prefixes() -> list[Path]:
    return [Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]


def _add_phantoms(tree: InstallTree, models: list[PackageModel], root: Path) -> None:
    tree.system_packages = _index(_user_prefixes())
    available = set(tree.packages) | set(tree.system_packages)
    wanted = {
        dep.name
        for model in models
        for dep in model.manifest.dependencies
        if dep.tag not in ("test_depend", "doc_depend")
    }
    missing = sorted(name for name in wanted - available if name)
    if not missing:
        return
    tree.phantom = root / "phantom"
    for name in missing:
        (tree.phantom / "share" / name).mkdir(parents=True, exist_ok=True)
        (tree.phantom / INDEX).mkdir(parents=True, exist_ok=True)
        (tree.phantom / INDEX / name).touch()
    tree.phantom_packages = set(missing)


# --- materialising a tree ------------------------------------------------------------------

# A file up to this size is copied into the tree. Over it, a mesh or image (LINKED_SUFFIXES)
# stays a link to the user's file, which the worker's guard replaces by a copy before any
# write through it. Text files (launch, URDF, xacro, YAML, RViz) are always copied: they are
# what launch files write to, and they are small. 1 MiB: the scaffold's and most tutorial
# meshes are far below it, copying 1 MiB on tmpfs costs well under a millisecond, and the
# real robots' meshes that are above it (tens of MB) would make every verify copy hundreds of MB.
LINK_THRESHOLD = 1 << 20
LINKED_SUFFIXES = frozenset(
    {
        ".stl",
        ".dae",
        ".obj",
        ".ply",
        ".glb",
        ".gltf",
        ".3ds",
        ".fbx",
        ".blend",
        ".mesh",
        ".ogre",
        ".png",
        ".jpg",
        ".jpeg",
        ".tif",
        ".tiff",
        ".bmp",
        ".pgm",
        ".ppm",
        ".tga",
        ".dds",
        ".ktx",
        ".exr",
        ".hdr",
        ".so",
        ".a",
        ".bin",
        ".db3",
        ".mcap",
        ".bag",
        ".pcd",
        ".bt",
        ".ot",
    }
)
SHM = "/dev/shm"
SHM_MARGIN = 32 << 20  # leave this much of tmpfs free
# a shadow of an install base copies at most this many files, this deep; past it, links
SHADOW_MAX_FILES = 100_000
# Folders are mirrored this deep below the install base, links past it (links out of the shadow are
# never walked). The walks over a tree start at a share folder (install/share/<pkg>, or
# install/<pkg>/share/<pkg> isolated) or one folder below it (share/<pkg>/urdf): the deepest top is
# 4 below the install base, and a walk must meet its own bound (walk.MAX_DEPTH) inside real folders
# to report it (PF903) as it does over the user's own tree.
DEEPEST_WALK_TOP = 4
SHADOW_MAX_DEPTH = MAX_DEPTH + DEEPEST_WALK_TOP
# a mirrored folder's path (below the tree's root) stays this short, so that the shadow's own paths
# (its root is longer than most install bases') are never too long for the system (PATH_MAX 4096)
SHADOW_MAX_PATH = 3584
PREFIX = "pkgforge-tree-"


def _fast_folder(needed: int) -> str | None:
    """/dev/shm when it is a writable, executable tmpfs with room to spare, else None (the temp dir)."""
    try:
        info = os.statvfs(SHM)
    except OSError:
        return None
    if info.f_flag & (os.ST_RDONLY | os.ST_NOEXEC) or not os.access(SHM, os.W_OK | os.X_OK):
        return None
    return SHM if info.f_bavail * info.f_frsize >= 2 * needed + SHM_MARGIN else None


def _sweep(folder: str) -> None:
    """Remove trees of pkgforge runs that were killed before they could (tmpfs holds them in memory)."""

    try:
        names = [n for n in os.listdir(folder) if n.startswith(PREFIX)]
    except OSError:
        return
    for name in names:
        pid = name[len(PREFIX) :].split("-", 1)[0]
        if not pid.isdigit() or int(pid) == os.getpid() or os.path.exists(f"/proc/{pid}"):
            continue
        path = os.path.join(folder, name)
        try:
            if os.stat(path).st_uid == os.getuid():
                remove_tree(path)
        except OSError:
            pass


def _plain_folder() -> str | None:
    """The temporary folder, or the first usable one whose path has no whitespace: the tree's paths
    go into command lines that launch splits at spaces, where the user's own would not be split."""
    default = tempfile.gettempdir()
    if not any(c.isspace() for c in default):
        return None
    for folder in ("/tmp", "/var/tmp", SHM):
        if (
            not any(c.isspace() for c in folder)
            and os.path.isdir(folder)
            and os.access(folder, os.W_OK | os.X_OK)
        ):
            return folder
    return None  # nowhere better: the tree's own spaces may then show as splits


def _temporary(needed: int) -> tuple[tempfile.TemporaryDirectory[str], Path]:
    folder = _fast_folder(needed)
    if folder is not None:
        _sweep(folder)
    else:
        folder = _plain_folder()
    temporary = tempfile.TemporaryDirectory(prefix=f"{PREFIX}{os.getpid()}-", dir=folder)
    return temporary, Path(os.path.realpath(temporary.name))


def _linked(name: str, size: int) -> bool:
    return size > LINK_THRESHOLD and os.path.splitext(name)[1].lower() in LINKED_SUFFIXES


def _copy(source: str, target: str, info: os.stat_result) -> bool:
    """Copy a regular file (False: it is not one, or unreadable); the copy is the tree's, writable."""
    try:
        handle = os.open(source, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)  # a FIFO must not block
    except OSError:
        return False
    try:
        if not stat.S_ISREG(os.fstat(handle).st_mode):
            return False
        out = os.open(
            target, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, (info.st_mode & 0o777) | 0o600
        )
        try:
            while os.sendfile(out, handle, None, 1 << 24):
                pass
        finally:
            os.close(out)
        return True
    except OSError:
        return False
    finally:
        os.close(handle)


class _Plan:
    """Folders, files and links to create under a root not chosen yet (its size decides where)."""

    def __init__(self) -> None:
        self.folders: set[str] = set()
        self.files: dict[str, tuple[str | None, os.stat_result | None]] = {}  # target → (source, stat)
        self.links: dict[str, str] = {}  # target → link text
        self.bytes = 0

    def folder(self, relative: str) -> None:
        while relative and relative not in self.folders:
            self.folders.add(relative)
            relative = os.path.dirname(relative)

    def file(self, relative: str, source: str | None, info: os.stat_result | None = None) -> None:
        if relative in self.files or relative in self.links:
            return
        self.folder(os.path.dirname(relative))
        if source is not None and info is None:
            try:
                info = os.stat(source)
            except OSError:
                info = None
        if info is not None and stat.S_ISREG(info.st_mode) and not _linked(relative, info.st_size):
            self.bytes += info.st_size
        self.files[relative] = (source, info)

    def link(self, relative: str, text: str) -> None:
        if relative not in self.files:
            self.folder(os.path.dirname(relative))
            self.links[relative] = text

    def build(self, root: Path) -> dict[str, str]:
        """Create everything under root; → {file in the tree: the user's file it stands for}."""
        base = str(root)
        for folder in sorted(self.folders):  # a parent sorts before its children
            os.mkdir(os.path.join(base, folder))
        origins = {}
        for relative, (source, _) in self.files.items():
            self._place(base, relative)
            if source is not None:
                origins[os.path.join(base, relative)] = source
        for relative in self.links:
            self._place(base, relative)
        return origins

    def _place(self, base: str, relative: str) -> None:
        target = os.path.join(base, relative)
        if relative in self.links:
            os.symlink(self.links[relative], target)
            return
        source, info = self.files[relative]
        if source is None:
            os.close(os.open(target, os.O_WRONLY | os.O_CREAT | os.O_CLOEXEC, 0o644))
        elif info is None:  # missing or a dangling link: missing here too, and a write lands here
            os.symlink(os.path.join(base, ".missing", relative), target)
        elif (
            not stat.S_ISREG(info.st_mode)
            or _linked(relative, info.st_size)
            or not _copy(source, target, info)
        ):
            os.symlink(os.path.realpath(source), target)

    def stamps(self, root: Path) -> dict[str, Stamp]:
        """What each created entry is now, to see later whether a launch file changed it."""
        base = str(root)
        out: dict[str, Stamp] = {}
        for relative in [*self.files, *self.links]:
            try:
                info = os.lstat(os.path.join(base, relative))
            except OSError:
                continue
            out[relative] = (info.st_ino, info.st_mode, info.st_size, info.st_mtime_ns, info.st_ctime_ns)
        return out

    def restore(self, root: Path, stamps: dict[str, Stamp]) -> int:
        """Put back every entry a launch file changed or removed; → how many."""

        base = str(root)
        changed = 0
        for relative, stamp in stamps.items():
            target = os.path.join(base, relative)
            try:
                info = os.lstat(target)
                if (info.st_ino, info.st_mode, info.st_size, info.st_mtime_ns, info.st_ctime_ns) == stamp:
                    continue
                if stat.S_ISDIR(info.st_mode):
                    remove_tree(target)
                else:
                    os.unlink(target)
            except FileNotFoundError:
                pass
            os.makedirs(os.path.dirname(target), exist_ok=True)
            self._place(base, relative)
            changed += 1
        return changed


def predicted_tree(models: list[PackageModel], user_install: Path | None = None) -> InstallTree:
    """The tree colcon would install; `user_install`: where (colcon's default <workspace>/install)."""
    plan = _Plan()
    plan.folder("install")
    unpredicted = {}
    for model in models:
        for destination, installed in model.layout.files.items():
            plan.file(
                os.path.normpath(os.path.join("install", destination)),
                None if installed.source is None else str(installed.source),
            )
        where = model.unpredicted()
        if where is not None:
            unpredicted[model.share_name] = where
            _plan_source_mirror(plan, model)
    tree = _materialised("predicted", plan, models, user_install, lambda root: {str(root / "install"): None})
    tree.unpredicted = unpredicted
    return tree


# a package's own build files and what is no run-time resource: never mirrored into its share folder
NOT_MIRRORED = frozenset({"setup.py", "setup.cfg", "CMakeLists.txt", "package.xml"})


def _plan_source_mirror(plan: _Plan, model: PackageModel) -> None:
    """A package whose install cannot be predicted is unknown, not empty: its share folder holds
    its source files where they are in the source (share/<pkg>/urdf/a.xacro for urdf/a.xacro),
    beside what is predicted, and its ament index marker. Its own launch files and models are then
    evaluated against its source, and other packages' lookups into it find what it has; what they
    do not find is not known to be missing (the checks say so: unpredicted-lookup)."""
    share = os.path.join("install", "share", model.share_name)
    plan.file(os.path.join("install", str(INDEX), model.share_name), None)
    for relative in model.files:
        parts = relative.parts
        if (len(parts) == 1 and relative.name in NOT_MIRRORED) or any(p.startswith(".") for p in parts):
            continue
        plan.file(os.path.join(share, *parts), str(model.path / relative))


def _materialised(
    mode: str,
    plan: _Plan,
    models: list[PackageModel],
    user_install: Path | None,
    prefixes_in: Callable[[Path], dict[str, str | None]],
) -> InstallTree:
    """The tree `plan` builds in pkgforge's temporary folder, indexed, with the models' packages
    it lacks stood in. `prefixes_in(root)`: each prefix of the tree, and the user's folder it
    shadows (None: a prefix of pkgforge's own). Nothing of it stays when this fails."""
    temporary, root = _temporary(plan.bytes)
    try:
        copied = plan.build(root)
        prefixes = prefixes_in(root)
        shadows = {prefix: user for prefix, user in prefixes.items() if user is not None}
        tree = InstallTree(
            mode,
            [Path(p) for p in prefixes],
            _temporary=temporary,
            root=root,
            shadows=shadows,
            copied=copied,
            _plan=plan,
            _stamps=plan.stamps(root),
            sealed=time.time_ns(),
            user_install=user_install,
        )
        tree.packages = _index(tree.prefixes)
        _add_phantoms(tree, models, root)
    except BaseException:
        temporary.cleanup()
        raise
    return tree


def _plan_shadow(plan: _Plan, source: Path, relative: str) -> None:
    """Mirror the folder `source` at `relative`: no walk through a link cycle, bounded in files
    and depth (past the bounds, a link to the user's folder, which the guard protects)."""
    top = os.path.realpath(source)
    seen: set[tuple[int, int]] = set()
    stack = [(str(source), relative, 0)]
    count = 0
    info: os.stat_result | None
    while stack:
        folder, here, depth = stack.pop()
        try:
            info = os.stat(folder)
        except OSError:
            continue
        if (info.st_dev, info.st_ino) in seen:
            plan.link(here, os.path.realpath(folder))  # a second way into a folder already mirrored
            continue
        seen.add((info.st_dev, info.st_ino))
        plan.folder(here)
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for entry in entries:
            target = os.path.join(here, entry.name)
            try:
                is_dir = entry.is_dir()  # follows links
            except OSError:
                is_dir = False
            if is_dir:
                real = os.path.realpath(entry.path)
                if entry.is_symlink() and (real == top or real.startswith(top + os.sep)):
                    parent = os.path.realpath(folder)
                    if parent == real or parent.startswith(real + os.sep):
                        continue  # a link to a folder holding it (`self -> .`): a cycle, left out
                    # another folder of the install base: the same link inside the shadow
                    inside = os.path.join(relative, os.path.relpath(real, top))
                    plan.link(target, os.path.relpath(inside, os.path.dirname(target)))
                elif entry.is_symlink():
                    # a link out of the install base stays a link: the walks decide whether to follow it
                    # (into the package's own source, for --symlink-install; never elsewhere), and the
                    # worker's guard refuses writes through it
                    plan.link(target, real)
                elif depth >= SHADOW_MAX_DEPTH or count >= SHADOW_MAX_FILES or len(target) > SHADOW_MAX_PATH:
                    plan.link(target, real)
                else:
                    stack.append((entry.path, target, depth + 1))
                continue
            count += 1
            if count > SHADOW_MAX_FILES:
                plan.link(target, os.path.realpath(entry.path))
                continue
            try:
                info = entry.stat()
            except OSError:
                info = None
            if info is not None and not stat.S_ISREG(info.st_mode):
                continue  # a pipe, socket or device: nothing a launch file resolves
            plan.file(target, entry.path, info)


def existing_tree(install_base: Path, models: list[PackageModel]) -> InstallTree:
    install_base = install_base.resolve()
    if not install_base.is_dir():
        raise PkgforgeError(f"--install-base {install_base} is not a folder (run colcon build first)")
    try:  # (colcon writes it; a FIFO or a device in its place is refused, never read)
        layout: str | None = (
            read_regular(install_base / ".colcon_install_layout").decode(errors="replace").strip()
        )
    except OSError:
        layout = None
    if layout == "isolated" or (layout is None and not (install_base / INDEX).is_dir()):
        prefixes = sorted(p for p in install_base.iterdir() if (p / INDEX).is_dir())
    else:
        prefixes = [install_base]
    if not prefixes:
        raise PkgforgeError(
            f"--install-base {install_base} holds no ament index: is it a colcon install folder?"
        )
    plan = _Plan()
    _plan_shadow(plan, install_base, "install")
    return _materialised(
        "existing",
        plan,
        models,
        install_base,
        lambda root: {
            os.path.normpath(root / "install" / p.relative_to(install_base)): str(p) for p in prefixes
        },
    )


def built_tree(workspace: Workspace, models: list[PackageModel], *, out: TextIO | None = None) -> InstallTree:
    from pkgforge.build.colcon import BuildOptions, run_build

    base = workspace.root / "build" / "pkgforge-verify"
    options = BuildOptions(
        build_base=base / "build",
        install_base=base / "install",
        log_base=base / "log",
        continue_on_error=True,
    )
    run_build(workspace, options, out=out, colcon_output_to_stderr=True, quiet_failures=True)
    tree = existing_tree(options.install_base, models)
    tree.kind = "built"
    tree.user_install = workspace.root / "install"  # where the user's own colcon build installs
    return tree
