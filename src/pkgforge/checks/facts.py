"""The helpers that compute facts for a CheckContext (checks/context.py): the file-system facts
a run looks up once (FileFacts), the words of a command line a launch file builds, the variables a
Python launch file reads from its environment, which ROS distros a branch on $ROS_DISTRO is taken
on, the packages an ignore marker hides from colcon, and the names the launch API exports.

Like the context, and unlike the checks, this module reads the file system.
"""

from __future__ import annotations

import os
import shlex
from pathlib import Path
from typing import Any

from pkgforge.launch.records import Resolution
from pkgforge.model.source import parse_python, read_regular

# what colcon leaves in its own build/ and install/ folders (beside their COLCON_IGNORE)
COLCON_OUTPUT_MARKERS = frozenset({".built_by", ".colcon_install_layout"})
# launch arguments that the included launch file passes to a command through a shell (its
# ExecuteProcess(shell=True) joins them into one command line): ros_gz_sim's gz_sim.launch.py
# (gz_args, and the deprecated ign_args) and ros_ign_gazebo's ign_gazebo.launch.py (ign_args).
# The files are often not installed where pkgforge runs, so their use is known here.
COMMAND_LINE_ARGUMENTS = {
    "ros_gz_sim/launch/gz_sim.launch.py": frozenset({"gz_args", "ign_args"}),
    "ros_ign_gazebo/launch/ign_gazebo.launch.py": frozenset({"ign_args"}),
}


def command_line_words(resolution: Resolution, value: str) -> list[str] | None:
    """The words of `value` (a path a launch file resolved, with a space in it), file part first,
    when what uses it splits it as a command line: Command (shlex, as launch's Command does), a
    process started through a shell (ExecuteProcess(shell=True)), or a launch argument that the
    included file passes to such a process (ros_gz_sim's gz_args). None when nothing that uses it
    splits it: a Node's argument, a parameter or a plain process's cmd item is one word, and a
    file named so does not exist."""

    def split_by_consumer() -> bool:
        if any(value in command.text for command in resolution.commands):
            return True
        if any(
            node.kind == "process" and node.shell and any(value in part for part in node.cmd or [])
            for node in resolution.nodes
        ):
            return True
        for include in resolution.includes:
            named = COMMAND_LINE_ARGUMENTS.get("/".join(include.path.replace(os.sep, "/").split("/")[-3:]))
            if named and any(value in text for name, text in include.arguments.items() if name in named):
                return True
        return False

    if not split_by_consumer():
        return None
    try:
        words = shlex.split(value)
    except ValueError:  # an unclosed quote: the consumer fails on it too, as one bad word
        return None
    paths = [w for w in words if os.path.isabs(w)]
    if len(words) < 2 or not paths:
        return None
    return [paths[0], *(w for w in words if w != paths[0])]


class FileFacts:
    """The file-system facts the checks ask for, each looked up once per run: whether a path
    exists (is a file, a folder, a link), where a link points, a path's real location, the names
    a pattern matches. Every context of a run shares one (CheckContext.files)."""

    def __init__(self) -> None:
        self._memo: dict[tuple[str, str], Any] = {}

    def _once(self, kind: str, path: str | os.PathLike[str], compute: Any) -> Any:
        key = (kind, os.fspath(path))
        if key not in self._memo:
            self._memo[key] = compute(key[1])
        return self._memo[key]

    def exists(self, path: str | os.PathLike[str]) -> bool:
        return bool(self._once("exists", path, os.path.exists))

    def is_file(self, path: str | os.PathLike[str]) -> bool:
        return bool(self._once("file", path, os.path.isfile))

    def is_dir(self, path: str | os.PathLike[str]) -> bool:
        return bool(self._once("dir", path, os.path.isdir))

    def is_link(self, path: str | os.PathLike[str]) -> bool:
        return bool(self._once("link", path, os.path.islink))

    def link_target(self, path: str | os.PathLike[str]) -> str | None:
        """What a symbolic link points to (its text), None when it cannot be read."""

        def read(text: str) -> str | None:
            try:
                return os.readlink(text)
            except OSError:
                return None

        target: str | None = self._once("readlink", path, read)
        return target

    def lines(self, path: str | os.PathLike[str]) -> list[str]:
        """A text file's lines ([] when it cannot be read)."""

        def read(text: str) -> list[str]:
            try:
                return read_regular(text).decode("utf-8", errors="replace").splitlines()
            except OSError:  # (a FIFO or a device too: never read)
                return []

        found: list[str] = self._once("lines", path, read)
        return found

    def real(self, path: str | os.PathLike[str]) -> Path | None:
        """The path with its links resolved (Path.resolve), None when that fails."""

        def resolve(text: str) -> Path | None:
            try:
                return Path(text).resolve()
            except OSError:
                return None

        real: Path | None = self._once("real", path, resolve)
        return real

    def names(self, folder: Path, pattern: str) -> frozenset[str]:
        """The names of what `folder.glob(pattern)` finds."""
        found: frozenset[str] = self._once(
            f"glob:{pattern}", folder, lambda text: frozenset(p.name for p in Path(text).glob(pattern))
        )
        return found


def taken_on_distros(branch: str | None, distros: tuple[str, ...]) -> bool | None:
    """Whether a Python branch on $ROS_DISTRO ("if os.environ.get('ROS_DISTRO') == 'humble'",
    "else of if …") is taken on every target distro (True), on none (False); None when it
    tests something else, or holds on some only (every active distro when none is targeted)."""
    import ast

    from pkgforge.model.distros import DISTROS

    if not branch or "ROS_DISTRO" not in branch:
        return None
    negated = branch.startswith("else of if ")
    test = branch.removeprefix("else of if ").removeprefix("if ")
    try:
        node = ast.parse(test, mode="eval").body
    except SyntaxError:
        return None
    if not isinstance(node, ast.Compare) or len(node.ops) != 1:
        return None
    left, right = node.left, node.comparators[0]
    if isinstance(left, ast.Constant) and "ROS_DISTRO" in ast.unparse(right):
        left, right = right, left  # 'humble' == os.environ['ROS_DISTRO']
    if "ROS_DISTRO" not in ast.unparse(left):
        return None
    try:
        value = ast.literal_eval(right)
    except ValueError:
        return None
    kind = type(node.ops[0])
    if kind not in (ast.Eq, ast.NotEq, ast.In, ast.NotIn) or not isinstance(value, (str, tuple, list, set)):
        return None

    def holds(distro: str) -> bool:
        if kind is ast.Eq:
            return bool(distro == value)
        if kind is ast.NotEq:
            return bool(distro != value)
        inside = distro in value
        return inside if kind is ast.In else not inside

    taken = {holds(distro) != negated for distro in (distros or tuple(DISTROS))}
    return taken.pop() if len(taken) == 1 else None


def ignored_under(workspace_base: Path | None) -> tuple[dict[str, tuple[Path, Path]], frozenset[str]]:
    """The packages under `workspace_base` that an ignore marker keeps colcon from building: name →
    (folder, the marker file), the first folder of each name; and the files and folders read to
    find them (CheckContext.ignored_packages)."""
    from pkgforge.model.files import quick_name
    from pkgforge.walk import walk
    from pkgforge.workspace import BUILD_FILES, IGNORE_MARKERS

    found: dict[str, tuple[Path, Path]] = {}
    read: set[str] = set()
    if workspace_base is None:
        return found, frozenset()
    for folder, dirs, files in walk(workspace_base):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        marker = next((m for m in IGNORE_MARKERS if m in files), None)
        if marker is None:
            continue
        dirs[:] = []  # what is below is walked here, once
        if COLCON_OUTPUT_MARKERS & set(files):
            continue  # colcon's own build/ or install/ (its share/<pkg>/package.xml is no source)
        read.add(os.path.join(folder, marker))
        for inner, inner_dirs, inner_files in walk(folder):
            inner_dirs[:] = sorted(d for d in inner_dirs if not d.startswith("."))
            read.add(inner)  # (a folder's stamp changes when an entry is added to it)
            # a package as colcon would identify it without the marker: a manifest beside
            # a build file; colcon does not look inside a package
            if "package.xml" in inner_files and any(b in inner_files for b in BUILD_FILES):
                inner_dirs[:] = []
                read.add(os.path.join(inner, "package.xml"))
                found.setdefault(quick_name(Path(inner)), (Path(inner), Path(folder) / marker))
    return found, frozenset(read)


def environment_reads(source: Path) -> list[str]:
    """Names a Python launch file reads with os.environ['X'], os.getenv('X') or os.environ.get('X')
    without a default."""
    import ast

    try:
        text = read_regular(source).decode("utf-8", errors="replace")
        if "environ" not in text and "getenv" not in text:
            return []  # every form below names one of them: no parse needed
        tree = parse_python(text)
    except (OSError, SyntaxError, ValueError):
        return []
    names: list[str] = []
    for node in ast.walk(tree):
        key: ast.expr
        if isinstance(node, ast.Subscript) and ast.unparse(node.value) in ("os.environ", "environ"):
            key = node.slice
        elif (
            isinstance(node, ast.Call)
            and len(node.args) == 1
            and not node.keywords
            and ast.unparse(node.func) in ("os.getenv", "getenv", "os.environ.get", "environ.get")
        ):
            key = node.args[0]
        else:
            continue
        if isinstance(key, ast.Constant) and isinstance(key.value, str) and key.value not in names:
            names.append(key.value)
    return names


_names: set[str] | None = None
_homes: dict[str, str] | None = None


def launch_name_home(name: str) -> str | None:
    """The public launch module that exports `name` (FindPackageShare → launch_ros.substitutions),
    in the distros the built-in engine has lists of; None for a name none exports."""
    global _homes
    if _homes is None:
        import json

        data_file = Path(__file__).resolve().parent.parent / "launch" / "api_names.json"
        with open(data_file, encoding="utf-8") as handle:
            data = json.load(handle)["distros"]
        _homes = {}
        # the shortest module name first: launch_ros.substitutions, not .substitutions.find_package
        for lists in data.values():
            for module in sorted(lists["modules"], key=lambda m: (m.count("."), m)):
                for exported in lists["modules"][module].get("all") or []:
                    _homes.setdefault(exported, module)
    return _homes.get(name)


def launch_names() -> set[str]:
    """Every name of launch and launch_ros in the distros the built-in engine has lists of."""
    global _names
    if _names is None:
        import json

        data_file = Path(__file__).resolve().parent.parent / "launch" / "api_names.json"
        with open(data_file, encoding="utf-8") as handle:
            data = json.load(handle)["distros"]
        _names = {
            name
            for lists in data.values()
            for module in lists["modules"].values()
            for name in module.get("names", {})
        }
    return _names
