"""Per-package results cached by the content of everything their checks read.

An entry is valid while the package's files, the files outside it that its
verification read (another package's xacro include or mesh, an installed file),
the selected checks and options, and the workspace's package names and declared
dependencies are all unchanged. A file's fingerprint is its content and its
permission bits (a `chmod 000` changes what verify can read); content digests
are memoized by (size, mtime, ctime, mode), as git's index does, so an
unchanged file is not read again. Results that depend on the machine's state
(a timeout, a crashed worker, a limit hit) are never stored (verify/pipeline.py). Entries are written
to a temporary file and renamed: two runs at once never see half an entry, and
the folder is safe to delete.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path
from stat import S_ISDIR
from typing import TYPE_CHECKING, Any

from pkgforge import __version__
from pkgforge.diagnostics import Diagnostic, PackageReport, Severity
from pkgforge.model.files import manifest_text, quick_name
from pkgforge.model.source import NotRegularFile, open_regular
from pkgforge.workspace import IGNORE_MARKERS

if TYPE_CHECKING:
    from pkgforge.checks.context import CheckContext

# 4: a model failing on its own for want of its empty-default xacro:args is PF406, no longer PF308
# 5: stop 23's answers (PF305/PF304/PF308 warnings off the defaults, PF311 for what this machine
#    lacks, nested templates and .repos repositories known, True/False branches, SDF through xacro)
# 6: PF110 (two workspace packages with one name); the workspace key holds such names' folders
# 7: a launch file's load failure after a package not found, or after reading a declared package
#    not installed here, is that lookup's (PF304/PF305) or PF311, not PF301; PF304's hint names
#    an ignored folder holding the package; stop 25's audit of real workspaces: PF109 warnings for
#    what a declared package brings along, PF108/PF306/PF402/PF305 false errors; folder digests
# 8: a second reader's corrections of 7 (PF306 read as-is, PF108 repos and conditions, PF109
#    doc_depend, PF305 cycles through every workspace package), PF107 rosdep keys and wrappers
# 9: ten new repositories: PF605 velocity 0 a warning, PF302 under an unevaluated rule a warning,
#    PF109 through workspace packages' exports, an unset variable's None is PF317, .rosinstall
# 10: a second reader's corrections of 9: manifests read with conditions and without comments,
#    the workspace key holds each package's dependency elements, PF302 only for rules that may
#    install files there, an unset variable's None a warning (PF301/PF304)
# 11: an OpaqueFunction reading a package not installed here is PF311; build_export_depend counts
#    for PF305; what loading records holds for every argument setting (no "only with" note)
# 12: a second reader's corrections of 11 (the ros engine's reloads, an action's own reads, other
#    packages' conditions for the target distros, a manifest's dependencies whatever its defects,
#    a rule at the prefix root), an empty model file, an RViz config no launch file opens
# 13: an action stopped by the guard is no PF301; 'gazebo' a rosdep key on humble; PF305 for what a
#    declared package brings along a warning
# 14: a second reader's corrections of 13: a link under a condition brings nothing along unless it
#    holds on every target distro, the cycle first, reads while loading and by the OpaqueFunction
#    an action came from count, an RViz config's displays stay errors, a blank model file
# 15: only an action's own reads and its OpaqueFunction ancestors' excuse its failure (PF311); a
#    read while loading makes it a PF301 warning; a $ROS_VERSION-only condition holds everywhere
# 16: an included file's loading reads count as loading reads; a condition on a variable of the
#    user's own build brings nothing along for sure
# 17: ... unless joined by `or` with a comparison that holds on ROS 2 (only such comparisons made false)
# 18: a file another launch file of the package includes with arguments, failing only on its own: a
#    PF301 warning
# 19: setup.py's Python packages in the predicted tree and on the workers' path; a file stopped by an
#    unset variable checked statically
# 20: the exports table (model/data/exports.json, not in the key) covers navigation2, rviz, moveit2,
#    ros2_controllers, ros_gz, xacro, ...; packages colcon ignores left out of it
# 21: PF305 for a use only with argument settings other than the defaults a warning
# 22: an own xacro.process_file() failing on a declared package not installed here: PF407, not PF301
# 23: PF107 not for a dependency that brings along an undeclared use
# 24: a CI matrix whose rows name several branches (moveit2_tutorials' deploy.yml) gives no target distro
# 25: a package name ending in "_" a PF102 warning
# 26: PF602 a warning for a point mass on a moving link with inertia below it
# 27: a use in a Python if/else branch of a file checked statically: PF305/PF108 warnings
# 28: a file an includer checked statically names, failing on its own: a PF301 warning
# 29: a workspace module's own missing import leaves the file unevaluated; package_data and dotted
#    py_modules in the tree; PF107 counts what evaluation saw used
# 30: a matrix branch key counts as this repository's only when its checkout reads it or the triggers name it
# 31: PF305 off-default uses a warning only for viewers (rviz2, rqt, jsp_gui)
# 32: MoveIt no longer makes a zero velocity an error; a point mass an error where Gazebo Classic is used
# 33: FindExecutable's program not on PATH is PF311, EnvironmentVariable's variable not set PF317
#    (both engines; errors record `variable`); an event handler's entities see `event` in the locals
# 34: a launch file's xacro.process_file(pathlib.Path) recorded as with a str
# 35: PF306 silent when robot_state_publisher gets the same plain file on its command line
# 36: PF305 for a package declared only as test_depend a warning; PF304's hint names building from source
# 37: a model finding in another package's included file at the include's line
# 38: a PathJoinSubstitution's path that is only part of a name a substitution list builds: that name
# 39: a find_package() only an optional find_package() not installed lets run: a PF109 warning
# 40: FindExecutable of a program a sourced ROS does not put on PATH stays PF301
# 41: a system library's CMake name gates nothing (PF109); test_depend-only uses a warning only in test packages
# 42: a full stop after a joined path ends its name; the include line named by package and path
# 43: an event handler's action failing on the stand-in event's empty values: PF311 (error records event_values)
# 44: a statically checked use under condition= says so in PF305's message
# 45: a statically checked branch on $ROS_DISTRO evaluated for the target distros
# 46: event_values only after the stand-in event was read; rviz2, rqt, gazebo on PATH; a system library no
#    declared key names gates; a dot inside a joined suffix; include lines with comments
# 47: choices given as one str are that word (launch tests membership by substring)
# 48: an XML or YAML launch file that is not UTF-8 is refused (launch reads it as UTF-8 text), at its
#    first such byte; a Python one's NUL byte located; file-not-read leaves out what launch-load-error says;
#    FIFOs and devices are never read (PF101/PF204/PF901/PF405 say what they are; a mesh link
#    to one is no "case differs"), YAML read within bounds (nesting, aliases), a deep xacro says so
# 49: with 48, setup.py run as colcon reads it when its text does not give its install; a package whose
#    install is still unknown is its source in the tree (PF319 for lookups it lacks); command lines split
#    as their consumer splits them (process records carry `shell`)
# 50: launch configurations not set are errors (PF320, Error.configuration); executions recorded; timers'
#    and handlers' entities visited after the description, with its final configurations
# 51: with 50, RViz 1 configs, ROS 1's bare xacro tags, what urdfdom refuses or drops, nested packages,
#    dependencies released nowhere (issue 28 classes 3, 6, 7, 8)
# 52: with 51, a launch file that does not load is read statically (its packages and its literal
#    paths, for every file read statically); robot_state_publisher with no description (PF321);
#    parameter files (PF322) and ros_gz_bridge configs (PF323) read; node records keep
#    SetParametersFromFile's files
# 53: with 52, a report says under which distro's launch API the built-in engine evaluated its launch
#    files, and where that distro came from; action-ros-ci's target-ros2-distro is a CI distro (issue 30)
# 54: with 53, diagnostics carry `detail` (messages one line of at most 300 characters), findings of one cause
#    grouped per file, per-file-ignores in the selection's key, no path of pkgforge's tree reported
# 55: with 54, model structures carry their Gazebo plugins and <ros2_control> systems (issue 31)
# 56: with 55, Gazebo worlds and SDF models read, --simulate's outcomes, inertia against geometry (issue 31)
# 57: with 56, a message over 300 characters keeps its beginning and its end; PF320's deferred note shorter
# 58: with 57, no spawner-controller-unknown while every controller configuration is unreadable
# 59: with 58, the displays of an RViz 1 config are no missing-exec-depend
# 60: with 59, SDF messages no longer repeat the file the location names
CACHE_FORMAT = 64
DEPENDENCY = re.compile(r"<(depend|\w+_depend)([^>]*)>\s*([^<\s]+)\s*<")
COMMENT = re.compile(r"<!--.*?-->", re.S)


def _atomic_write(path: Path, text: str) -> None:
    import tempfile  # (here: an unchanged re-run writes nothing)

    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            out.write(text)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


class ResultCache:
    def __init__(self, folder: Path, options_key: str):
        self.folder = folder
        self.options_key = options_key
        self.index_path = folder / "digests.json"
        try:
            self.index = json.loads(self.index_path.read_text())
        except (OSError, ValueError):
            self.index = {}
        self.changed = False
        # package folder → (files outside it that its valid entry read, its codes): loaded or stored
        self.answered: dict[Path, tuple[list[str], set[str]]] = {}
        self.stamps: dict[str, FileStamp] = {}  # path → its stamp when its digest was taken

    # --- digests ------------------------------------------------------------------------------

    def digest(self, path: str) -> str | None:
        """sha256 of a file's content (a folder's: its entries' names) and its mode (None when
        missing), memoized by size, mtime, ctime and mode; an unreadable file's fingerprint is its
        mode alone."""
        try:
            stat = os.stat(path)
        except OSError as error:
            self.stamps[path] = [error.errno]
            return None
        mode = f"{stat.st_mode & 0o7777:o}"
        stamp: FileStamp = [stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns, stat.st_mode]
        self.stamps[path] = stamp  # as _stamp() gives it: the workspace entry's record of the file
        known = self.index.get(path)
        if known and len(known) == 5 and known[:4] == stamp:
            return f"{known[4]}:{mode}"
        digest = hashlib.sha256()
        try:
            if S_ISDIR(stat.st_mode):  # a folder's names: an entry added below it shows
                digest.update(os.fsencode("\0".join(sorted(os.listdir(path)))))
            else:  # a FIFO or a device is never read (it blocks, or never ends): its type is its content
                with open(open_regular(path)[0], "rb", closefd=True) as handle:
                    for block in iter(lambda: handle.read(1 << 20), b""):
                        digest.update(block)
        except NotRegularFile:
            return f"special:{stat.st_mode:o}:{stat.st_rdev}"
        except OSError:
            return f"unreadable:{mode}"
        self.index[path] = [*stamp, digest.hexdigest()]
        self.changed = True
        return f"{digest.hexdigest()}:{mode}"

    def package_key(self, folder: Path, files: list[str], selection: str, workspace_key: str) -> str:
        key = hashlib.sha256()
        for part in (__version__, str(CACHE_FORMAT), self.options_key, workspace_key, selection):
            key.update(part.encode() + b"\0")
        prefix = str(folder).rstrip(os.sep) + os.sep  # (str(folder / relative), without a Path per file)
        for relative in files:
            # fsencode: a file name's bytes as they are, UTF-8 or not (a str's encode() refuses those)
            key.update(
                os.fsencode(relative) + b"\0" + (self.digest(prefix + relative) or "-").encode() + b"\0"
            )
        return key.hexdigest()

    # --- entries ------------------------------------------------------------------------------

    def _entry_path(self, folder: Path) -> Path:
        return self.folder / f"{hashlib.sha1(os.fsencode(folder)).hexdigest()}.json"

    def load(self, folder: Path, key: str) -> tuple[PackageReport, set[str]] | None:
        """(report, codes of the checks that ran) when the entry is still valid."""
        try:
            entry = json.loads(self._entry_path(folder).read_text())
        except (OSError, ValueError):
            return None
        if entry.get("key") != key:
            return None
        for path, digest in entry.get("externals", []):
            if self.digest(path) != digest:
                return None
        self.answered[folder] = (
            [path for path, _ in entry.get("externals", [])],
            set(entry.get("codes", [])),
        )
        return _report_from(entry["report"]), set(entry.get("codes", []))

    def store(
        self, folder: Path, key: str, report: PackageReport, externals: set[str], codes: set[str]
    ) -> None:
        entry = {
            "key": key,
            "externals": sorted([p, self.digest(p)] for p in externals),
            "codes": sorted(codes),
            "report": _report_to(report),
        }
        _atomic_write(self._entry_path(folder), json.dumps(entry))
        self.answered[folder] = (sorted(externals), set(codes))

    def save_index(self) -> None:
        if self.changed:
            _atomic_write(self.index_path, json.dumps(self.index))


# --- the whole workspace at once ------------------------------------------------------------
#
# An unchanged re-run of a whole workspace would compute every package's key (walk, digests,
# package.xml, target distros, config) and read every entry. The workspace entry holds the
# whole answer under one fingerprint of everything those keys read: every file under the
# discovery base with its (size, mtime, ctime, mode), the memo rule of the digests above (ctime
# cannot be set back, so an edit that keeps the size and restores the mtime still changes it),
# the CI files above the base (the target distros), the options, the configuration, and the
# stamps of every file outside the workspace that a package's entry read. Any difference, even
# one the per-package keys would not see, only sends the run to the per-package lookup.

WORKSPACE_ENTRY = "workspace.whole"  # (not *.json: one file, not a package's entry)
PRUNED = (".git",)  # never read by verify, and large
# a file's (size, mtime ns, ctime ns, mode), or [errno] when it cannot be stat'ed
FileStamp = list[int | None]
MAX_STAMPED = 100_000  # more files: no workspace entry (the per-package lookup as before)


def _stamp(path: str) -> FileStamp:
    try:
        stat = os.stat(path)
    except OSError as error:
        return [error.errno]
    return [stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns, stat.st_mode]


def tree_stamps(base: str) -> list[list[Any]] | None:
    """Every folder and file under base (sorted; links read, not followed; `.git` and folders
    with an ignore marker not entered) with each file's stamp; None when too many files."""
    out: list[list[Any]] = []  # [folder, name, what …]: JSON for the fingerprint
    stack = [base]
    cut = len(base.rstrip(os.sep)) + 1
    while stack:
        folder = stack.pop()
        relative = folder[cut:]
        try:
            with os.scandir(folder) as found:
                entries = sorted(found, key=lambda e: e.name)
        except OSError as error:
            out.append([relative, "unreadable", error.errno])
            continue
        if folder != base and any(e.name in IGNORE_MARKERS for e in entries):
            out.append([relative, "ignored", [e.name for e in entries if e.name in IGNORE_MARKERS]])
            continue
        below = []
        for entry in entries:
            name = entry.name
            try:
                if entry.is_dir(follow_symlinks=False):
                    if name in PRUNED:
                        out.append([relative, name, "pruned"])
                    else:
                        below.append(entry.path)
                    continue
                if entry.is_symlink():
                    out.append([relative, name, "link", os.readlink(entry.path), _stamp(entry.path)])
                    continue
                stat = entry.stat(follow_symlinks=False)
            except OSError as error:
                out.append([relative, name, "error", error.errno])
                continue
            out.append([relative, name, stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns, stat.st_mode])
        if len(out) > MAX_STAMPED:
            return None
        out.append([relative, "folders", [os.path.basename(b) for b in below]])
        stack.extend(reversed(below))
    return out


def workspace_fingerprint(base: Path, above: list[Path], options_key: str, config_key: str) -> str | None:
    """The fingerprint of what a whole-workspace run read (see above); `above`: the folders from
    base's parent up to the workspace root, whose CI files say which distros are targeted."""
    from pkgforge.model.distro_data import CI_FILES, CI_FOLDER

    stamps = tree_stamps(str(base))
    if stamps is None:
        return None
    outside: list[list[Any]] = []  # [path, its stamp or errno]
    for folder in above:
        outside += [[str(folder / name), _stamp(str(folder / name))] for name in CI_FILES]
        workflows = folder / CI_FOLDER
        try:
            names = sorted(os.listdir(workflows))
        except OSError as error:
            outside.append([str(workflows), error.errno])
            continue
        outside += [[str(workflows / name), _stamp(str(workflows / name))] for name in names]
    whole = json.dumps([__version__, CACHE_FORMAT, options_key, config_key, str(base), outside, stamps])
    return hashlib.sha256(whole.encode()).hexdigest()


def load_workspace(folder: Path, fingerprint: str) -> tuple[list[PackageReport], set[str]] | None:
    """The whole workspace's reports and codes when its entry's fingerprint and every outside file's
    stamp are unchanged."""
    try:
        entry = json.loads((folder / WORKSPACE_ENTRY).read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(entry, dict) or entry.get("fingerprint") != fingerprint:
        return None
    for path, stamp in entry.get("externals", []):
        if _stamp(path) != stamp:
            return None
    return [_report_from(r) for r in entry["reports"]], set(entry["codes"])


def store_workspace(
    folder: Path,
    fingerprint: str,
    reports: list[PackageReport],
    codes: set[str],
    externals: dict[str, FileStamp],
) -> None:
    """`externals`: each outside file's stamp when its digest was taken (a later edit is not hidden)."""
    entry = {
        "fingerprint": fingerprint,
        "externals": [[p, externals[p]] for p in sorted(externals)],
        "codes": sorted(codes),
        "reports": [_report_to(r) for r in reports],
    }
    _atomic_write(folder / WORKSPACE_ENTRY, json.dumps(entry))


def workspace_key(folders: list[Path], texts: dict[Path, str | None] | None = None) -> str:
    """The names and declared dependencies of every package: what lookups depend on (and the
    folders of a name two packages have). `texts`: the package.xml texts already read (None:
    unreadable), by folder."""
    folders_by_name: dict[str, list[str]] = {}
    # each package's dependency elements as written (kind, attributes such as a condition, name):
    # which package declares what, and how, is read by checks of other packages (what a declared
    # package brings along, PF109; a dependency cycle, PF305; MoveIt or a simulator used, PF605)
    dependencies: dict[str, list[tuple[str, str, str]]] = {}
    for folder in folders:
        text = texts[folder] if texts is not None and folder in texts else manifest_text(folder)
        if text is None:
            continue
        name = quick_name(folder, text)
        folders_by_name.setdefault(name, []).append(str(folder))
        elements = DEPENDENCY.findall(COMMENT.sub("", text))
        dependencies.setdefault(name, []).extend(
            (kind, " ".join(attributes.split()), what) for kind, attributes, what in elements
        )
    # a name two folders hold (package-name-duplicate, and which copy the tree holds): those folders
    twice = sorted((name, sorted(where)) for name, where in folders_by_name.items() if len(where) > 1)
    written = sorted((name, sorted(elements)) for name, elements in dependencies.items())
    return hashlib.sha256(json.dumps([sorted(folders_by_name), written, twice]).encode()).hexdigest()


BUILD_FILES = ("package.xml", "CMakeLists.txt", "setup.py", "setup.cfg")


def externals(context: CheckContext) -> set[str]:
    """Files outside the package that its verification depended on (real paths).

    A path into another workspace package depends on that package's build
    files too: fixing its install rules changes what exists in the tree.
    """
    tree = context.tree
    found: set[str] = set()
    for resolution in context.resolutions:
        found.update(item.path for item in resolution.paths)
        found.update(item.path for item in resolution.includes)
        found.update(c.model for c in resolution.commands if c.model)
    for result in context.model_results:
        found.add(str(result.installed))
        found.update(result.includes)
        for mesh in result.robot["meshes"] if result.robot and tree is not None else []:
            lookup = context.mesh(mesh["uri"], result.installed)  # the checks' own lookup
            if lookup.path is not None:
                found.add(str(lookup.path))
    found.update(context.read_elsewhere)
    own = str(context.model.path) + os.sep
    temporary = [str(p) + os.sep for p in (tree.prefixes if tree is not None else [])]
    if tree is not None and tree.root is not None:
        temporary.append(str(tree.root) + os.sep)
    out: set[str] = set()
    for path in found:
        located = tree.locate(path) if tree is not None else None
        if located is not None:
            package = located[0]
            if (
                tree is not None
                and tree.is_phantom(path)
                or package in (context.model.name, context.model.share_name)
            ):
                continue
            other = context.models.get(package)
            if other is not None:
                out.update(str(other.path / name) for name in BUILD_FILES)
        real = tree.origin(path) if tree is not None else os.path.realpath(path)  # a copy → the user's file
        if not real.startswith(own) and not any(real.startswith(t) for t in temporary):
            out.add(real)
    return out


def _report_to(report: PackageReport) -> dict[str, Any]:
    return {
        "name": report.name,
        "path": str(report.path),
        "build_type": report.build_type,
        "launch_distro": list(report.launch_distro) if report.launch_distro else None,
        "diagnostics": [
            {**d.__dict__, "path": str(d.path), "severity": d.severity.label, "group": None}
            for d in report.diagnostics
        ],
    }


def _report_from(data: dict[str, Any]) -> PackageReport:
    report = PackageReport(data["name"], Path(data["path"]), data["build_type"])
    launch_distro = data.get("launch_distro")
    report.launch_distro = (str(launch_distro[0]), str(launch_distro[1])) if launch_distro else None
    for d in data["diagnostics"]:
        report.diagnostics.append(
            Diagnostic(**{**d, "path": Path(d["path"]), "severity": Severity.parse(d["severity"])})
        )
    return report
