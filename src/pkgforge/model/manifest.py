"""package.xml: catkin_pkg for what it means, lxml for where each element stands."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from pkgforge.model.catkin import InvalidPackage, parse_package_string
from pkgforge.model.source import SourceFile

DEPENDENCY_TAGS = (
    "depend",
    "build_depend",
    "buildtool_depend",
    "build_export_depend",
    "buildtool_export_depend",
    "exec_depend",
    "run_depend",
    "test_depend",
    "doc_depend",
)
# what satisfies a run-time need (REP 149: <depend> is build + build_export + exec)
RUN_TAGS = ("depend", "exec_depend", "run_depend")
# what an installed package brings along (a binary's Depends; rosdep installs them with it)
EXPORT_TAGS = (*RUN_TAGS, "build_export_depend", "buildtool_export_depend")
# catkin_pkg refuses <depend>X</depend> beside a specific tag for X (colcon then skips the package)
REDUNDANT_GENERIC = "is redundant with"
GENERIC_OVERLAPS = {"build_depend", "build_export_depend", "exec_depend"}


# a variable in a REP 149 condition, as catkin_pkg's condition grammar reads it
CONDITION_VARIABLE = re.compile(r"\$([A-Za-z0-9_]+)")
# one comparison of a condition with a variable on either side: its variable in group 1 or 2
_OPERAND = r"(?:\"[^\"]*\"|'[^']*'|[A-Za-z0-9_.\-]+)"
UNKNOWN_COMPARISON = re.compile(
    rf"\$([A-Za-z0-9_]+)\s*(?:==|!=|>=|<=|>|<)\s*{_OPERAND}|{_OPERAND}\s*(?:==|!=|>=|<=|>|<)\s*\$([A-Za-z0-9_]+)"
)


@dataclass(frozen=True)
class Dependency:
    name: str
    tag: str
    line: int
    condition: str | None = None  # REP 149 condition="$ROS_VERSION == 2", evaluated as catkin_pkg does

    def holds_on_every(self, distros: tuple[str, ...]) -> bool:
        """Whether the dependency counts on each of `distros` (`active` asks: on any of them). With
        no target distro, a condition on $ROS_DISTRO holds nowhere for sure."""
        if not self.condition:
            return True
        known = {"ROS_VERSION", "ROS_PYTHON_VERSION", "ROS_DISTRO"}
        # a comparison on a variable of the user's own build ($BUILD_TYPE == hardware) may be
        # false: it is made false, and what still holds then holds for sure (conditions join
        # comparisons with and/or only, so a false one never makes the whole true)
        condition = UNKNOWN_COMPARISON.sub(
            lambda m: m.group(0) if (m.group(1) or m.group(2)) in known else "$ROS_VERSION == pkgforge_never",
            self.condition,
        )
        if set(CONDITION_VARIABLE.findall(condition)) - known:
            return False  # (a variable in a form not compared: not for sure)
        sure = Dependency(self.name, self.tag, self.line, condition)
        if "ROS_DISTRO" not in condition:
            return sure.active(())  # ($ROS_VERSION == 2: the same on every distro)
        return bool(distros) and all(sure.active((distro,)) for distro in distros)

    def active(self, distros: tuple[str, ...] = ()) -> bool:
        """Whether the dependency counts on ROS 2 (for any of `distros`; every distro when empty)."""
        if not self.condition:
            return True
        from catkin_pkg.condition import evaluate_condition

        context = {"ROS_VERSION": "2", "ROS_PYTHON_VERSION": "3"}
        if set(CONDITION_VARIABLE.findall(self.condition)) - {*context, "ROS_DISTRO"}:
            # a variable of the user's own build set-up (panther's $HUSARION_ROS_BUILD_TYPE): colcon
            # and rosdep read it from the environment of the build, which verify cannot know
            return True
        try:
            if "ROS_DISTRO" in self.condition and not distros:
                return True  # a condition on the distro, with no target distro: it may hold
            if "ROS_DISTRO" not in self.condition:
                return bool(evaluate_condition(self.condition, context))
            return any(evaluate_condition(self.condition, {**context, "ROS_DISTRO": d}) for d in distros)
        except (ValueError, TypeError):
            return True  # catkin_pkg rejects the manifest; manifest-invalid says so


@dataclass
class Manifest:
    path: Path
    name: str | None = None
    name_line: int | None = None
    format: int | None = None
    root_line: int = 1
    build_type: str | None = None
    build_type_line: int | None = None
    export_line: int | None = None
    metapackage: bool = False  # <export><metapackage/>: its dependencies are its content
    dependencies: list[Dependency] = field(default_factory=list)
    # (message, line) for manifest-invalid
    problems: list[tuple[str, int | None]] = field(default_factory=list)
    element_lines: dict[str, int] = field(default_factory=dict)  # first line of each tag
    # the target distros of this verify (conditions on $ROS_DISTRO are evaluated for them)
    distros: tuple[str, ...] = ()

    @property
    def valid(self) -> bool:
        return not self.problems and self.name is not None

    def active_dependencies(self) -> list[Dependency]:
        """The dependencies whose condition holds on ROS 2 (and the target distros)."""
        return [d for d in self.dependencies if d.active(self.distros)]

    def run_dependencies(self) -> set[str]:
        return {d.name for d in self.active_dependencies() if d.tag in RUN_TAGS}

    def build_dependencies(self) -> set[str]:
        return {
            d.name
            for d in self.active_dependencies()
            if d.tag in ("depend", "build_depend", "buildtool_depend")
        }

    def declared(self) -> set[str]:
        return {d.name for d in self.active_dependencies()}

    def last_dependency_line(self) -> int | None:
        lines = [d.line for d in self.dependencies]
        return max(lines) if lines else self.export_line


def load_manifest(source: SourceFile, parsed_package: object = None, *, validate: bool = True) -> Manifest:
    """Build the Manifest; `parsed_package` is catkin_pkg's result when colcon already parsed it;
    `validate=False`: its elements only, no catkin_pkg validation (another package's dependencies)."""
    manifest = Manifest(source.path)
    if source.text is None:
        manifest.problems.append((f"package.xml: {source.problem}", source.problem_line))
        return manifest
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, remove_comments=True, remove_pis=True, huge_tree=False
    )
    try:
        root = etree.fromstring(source.text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as exc:
        manifest.problems.append((f"package.xml is not well-formed XML: {exc.msg}", exc.lineno))
        return manifest
    manifest.root_line = root.sourceline or 1
    if root.tag != "package":
        manifest.problems.append((f"the root element is <{root.tag!s}>, not <package>", root.sourceline))
        return manifest
    try:
        manifest.format = int(root.get("format", "1"))
    except ValueError:
        manifest.problems.append((f'format="{root.get("format")}" is not a number', root.sourceline))
    for element in root:
        if isinstance(element.tag, str):
            manifest.element_lines.setdefault(element.tag, element.sourceline or 1)  # lxml: 1 at least
    name_element = root.find("name")
    if name_element is not None:
        manifest.name = (name_element.text or "").strip()
        manifest.name_line = name_element.sourceline
    for element in root:
        if isinstance(element.tag, str) and element.tag in DEPENDENCY_TAGS:
            manifest.dependencies.append(
                Dependency(
                    (element.text or "").strip(),
                    element.tag,
                    element.sourceline or 1,
                    element.get("condition"),
                )
            )
    export = root.find("export")
    if export is not None:
        manifest.export_line = export.sourceline
        manifest.metapackage = export.find("metapackage") is not None
        build_type = export.find("build_type")
        if build_type is not None:
            manifest.build_type = (build_type.text or "").strip()
            manifest.build_type_line = build_type.sourceline

    if parsed_package is None and validate:
        _validate_with_catkin_pkg(manifest, source.text)
    return manifest


def _validate_with_catkin_pkg(manifest: Manifest, text: str) -> None:
    try:
        parse_package_string(text, filename=str(manifest.path), warnings=[])
    except InvalidPackage as exc:
        for message in _catkin_messages(exc):
            if REDUNDANT_GENERIC in message:
                continue  # reported, with its line, by duplicate-dependency
            manifest.problems.append((message, _line_for(manifest, message)))
    except (AssertionError, ValueError, TypeError) as exc:  # catkin_pkg asserts on some inputs
        manifest.problems.append((f"catkin_pkg cannot read it: {exc}", manifest.root_line))


def _catkin_messages(exc: InvalidPackage) -> list[str]:
    text = str(exc)
    text = re.sub(r"^Error\(s\) in package '[^']*':\s*", "", text)
    text = re.sub(r"^Error\(s\) in [^:]*:\s*", "", text)
    messages = [line.strip().removeprefix("- ") for line in text.splitlines()]
    return [m for m in messages if m and m != "Error(s):"] or [text]


def _line_for(manifest: Manifest, message: str) -> int:
    """The line of the element a catkin_pkg message is about, else the <package> line."""
    lowered = message.lower()
    for tag in ("maintainer", "license", "version", "description", "author", "url", "name"):
        if tag in lowered and tag in manifest.element_lines:
            return manifest.element_lines[tag]
    for dependency in manifest.dependencies:
        if f'"{dependency.name}"' in message or f"'{dependency.name}'" in message:
            return dependency.line
    return manifest.root_line
