"""Gazebo worlds and SDF models a package installs (.sdf, .world): well formed for the SDF version
they declare, their <include> and <mesh> URIs found, and the resource path Gazebo needs to find
the package's own models set by the package.

Where the rules come from: sdformat's parser (an <sdf version> root whose version it has a
description of; the file converted to sdformat's newest version before it is read), gz-common's URI lookup (model://NAME is
NAME's folder on GZ_SIM_RESOURCE_PATH, IGN_GAZEBO_RESOURCE_PATH on Fortress, GAZEBO_MODEL_PATH on
Gazebo Classic), and gazebosim/ros_gz's ros_gz_sim/launch/gz_sim.launch.py.in on its humble
(0.244.14 and later) and jazzy branches: it appends each package's <export><gazebo_ros
gazebo_model_path=.../> (${prefix}: its share folder) to GZ_SIM_RESOURCE_PATH (and
IGN_GAZEBO_RESOURCE_PATH), as gazebo_ros's gazebo_ros_paths.py does for Classic; neither adds a
package's share folder by itself.
"""

from __future__ import annotations

import functools
import posixpath
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlparse

from lxml import etree

from pkgforge.checks.context import CheckContext
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Severity

SDF_SUFFIXES = (".sdf", ".world")
# the SDF versions sdformat has descriptions of (sdf/1.0 ... sdf/1.12)
SDF_VERSIONS = frozenset(f"1.{minor}" for minor in range(13))
# the variables Gazebo finds models and meshes by (gz-sim, Fortress, Classic)
RESOURCE_VARIABLES = ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH")
# models Gazebo Classic installs itself (gazebo11's models/): worlds include them everywhere
GAZEBO_MODELS = frozenset({"sun", "ground_plane"})
# a home folder: a path into one exists on its author's machine only
HOME = re.compile(r"^/(home|Users)/[^/]+/|^/root/")
READ_LIMIT = 1 << 20  # text_head's: a longer file is not read whole, not checked
SHOWN = 120  # characters of a URI or a value a message quotes


def _shown(text: str) -> str:
    return text if len(text) <= SHOWN else text[: SHOWN - 3] + "..."


@dataclass(frozen=True)
class SdfFile:
    source: Path  # the user's file
    installed: str  # its path in the package's share folder ("worlds/yard.sdf")
    text: str


def _installed_sdf(ctx: CheckContext) -> Iterator[SdfFile]:
    """The package's SDF files its install rules put in its share folder."""
    layout = ctx.model.layout
    if not layout.known:
        return
    share = f"share/{ctx.model.share_name}/"
    for destination, installed in sorted(layout.files.items()):
        if (
            installed.source is None
            or not destination.endswith(SDF_SUFFIXES)
            or not destination.startswith(share)
        ):
            continue
        text = ctx.text_head(str(installed.source))
        if text and len(text) < READ_LIMIT:
            yield SdfFile(installed.source, destination[len(share) :], text)


# the three SDF checks run one after the other on a package's files: each file parsed once, not
# three times (a world of thousands of lines), the last few kept (read only)
@functools.lru_cache(maxsize=8)
def _parse(sdf: SdfFile) -> etree._Element | etree.XMLSyntaxError:
    try:
        return etree.fromstring(sdf.text.encode("utf-8"), _parser(recover=False))
    except etree.XMLSyntaxError as error:
        return _as_tinyxml2_reads(sdf.text, error)


def _parser(recover: bool) -> etree.XMLParser:
    return etree.XMLParser(
        remove_comments=True,
        remove_pis=True,
        resolve_entities=False,
        no_network=True,
        huge_tree=False,
        recover=recover,
    )


# what sdformat's XML reader (tinyxml2) reads although XML forbids it: it ends a comment at the
# first "-->" ("--" inside is text: gz_ros2_control's own demo worlds have it), an attribute value
# at its quote ("<" inside), keeps an entity it does not know as text, and knows no namespaces (a
# world Gazebo saved has its models' custom <surface_props:material> without their xmlns)
TINYXML2_READS = frozenset(
    {
        etree.ErrorTypes.NS_ERR_UNDEFINED_NAMESPACE,
        etree.ErrorTypes.ERR_HYPHEN_IN_COMMENT,
        etree.ErrorTypes.ERR_LT_IN_ATTRIBUTE,
        etree.ErrorTypes.ERR_UNDECLARED_ENTITY,
        etree.ErrorTypes.WAR_UNDECLARED_ENTITY,
    }
)


def _as_tinyxml2_reads(text: str, error: etree.XMLSyntaxError) -> etree._Element | etree.XMLSyntaxError:
    """The document as sdformat reads it when each of libxml2's complaints is one tinyxml2 does
    not make, else the first complaint it makes too."""
    parser = _parser(recover=True)
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError:
        return error
    refused = [entry for entry in parser.error_log if entry.type not in TINYXML2_READS]
    if refused:
        first = refused[0]
        return etree.XMLSyntaxError(first.message.strip(), first.type, first.line, first.column)
    return error if root is None else root


def _version(text: str | None) -> tuple[int, int] | None:
    match = re.fullmatch(r"\s*(\d+)\.(\d+)\s*", text or "")
    return (int(match.group(1)), int(match.group(2))) if match else None


@register(
    "PF420",
    "sdf-invalid",
    "error",
    area="model",
    bad='<!-- worlds/yard.sdf -->\n<world name="yard">  <!-- no <sdf version=...> around it -->',
    good='<!-- worlds/yard.sdf -->\n<sdf version="1.9">\n  <world name="yard">',
    summary="an installed SDF world or model is not XML or has no <sdf version=...> root with a "
    "version sdformat knows",
    explanation="sdformat (Gazebo's parser, every version) refuses a file that is not XML or whose "
    "root is not <sdf> with a version it has a description of (1.0 to 1.12): Gazebo loads no world. "
    "(sdformat converts an older file to its own newest version and reads it against that "
    "version's description: an attribute newer than the declared version is read, not refused.) "
    "No automatic fix: the version a file is written for is the author's knowledge (an <sdf> "
    "wrapper with a guessed version makes sdformat read elements of another version against the "
    "wrong description), and broken XML has no one repair.",
    hint='declare the SDF version the file is written for, e.g. <sdf version="1.9">',
)
def sdf_invalid(ctx: CheckContext) -> Iterator[Finding]:
    for sdf in _installed_sdf(ctx):
        root = _parse(sdf)
        if isinstance(root, etree.XMLSyntaxError):
            message = (str(root).splitlines() or ["not well formed"])[0][:200]
            yield Finding(
                f"not an XML file: {message}",
                sdf.source,
                root.lineno or None,
                hint="fix the XML at that line (every element closed, attribute values quoted)",
            )
            continue
        if root.tag != "sdf" or _version(root.get("version")) is None:
            yield Finding(
                f"root <{etree.QName(root).localname}>"
                + (
                    f" version={_shown(root.get('version') or '')!r}"
                    if root.get("version") is not None
                    else " without a version"
                )
                + ", not <sdf version=...>: sdformat refuses the file",
                sdf.source,
                root.sourceline,
            )
            continue
        declared = root.get("version", "").strip()
        if declared not in SDF_VERSIONS:
            yield Finding(
                f"SDF version {_shown(declared)} is none sdformat has (1.0 to 1.12)",
                sdf.source,
                root.sourceline,
                hint='declare the version the file is written for, e.g. version="1.9"',
            )
            continue


@dataclass(frozen=True)
class _Uri:
    text: str
    line: int | None
    include: bool  # an <include>'s (else a <mesh>'s)


def _uris(root: etree._Element) -> Iterator[_Uri]:
    """The <uri> of each <include> and <mesh>."""
    for element in root.iter("uri"):
        parent = element.getparent()
        if parent is not None and parent.tag in ("include", "mesh") and (element.text or "").strip():
            yield _Uri((element.text or "").strip(), element.sourceline, parent.tag == "include")


def _model_roots(ctx: CheckContext) -> dict[Path, str]:
    """Folders a model://NAME may stand in, each with the package that installs it: every
    workspace package's share/<package>/models, and what its <gazebo_ros gazebo_model_path>
    exports name."""
    tree = ctx.tree
    roots: dict[Path, str] = {}
    if tree is None:
        return roots
    for package in tree.packages:
        share = tree.share(package)
        if share is None:
            continue
        roots[share / "models"] = package
        for path in _exported_paths(ctx, package, share):
            roots.setdefault(path, package)
    return roots


def _exported_paths(ctx: CheckContext, package: str, share: Path) -> list[Path]:
    """The folders a package's <export><gazebo_ros gazebo_model_path|gazebo_media_path> names."""
    model = ctx.model_for_share(package)
    source = model.sources.get(model.path / "package.xml") if model is not None else None
    if source is None or source.text is None:
        return []
    try:
        root = etree.fromstring(
            source.text.encode("utf-8"), etree.XMLParser(resolve_entities=False, no_network=True)
        )
    except etree.XMLSyntaxError:
        return []
    paths = []
    for element in root.iterfind("export/gazebo_ros"):
        for name in ("gazebo_model_path", "gazebo_media_path"):
            value = element.get(name)
            if value:
                for part in value.split(":"):
                    if part.strip():
                        paths.append(Path(posixpath.normpath(part.strip().replace("${prefix}", str(share)))))
    return paths


@register(
    "PF421",
    "sdf-uri-unresolved",
    "error",
    area="model",
    bad="<include><uri>file:///home/ada/models/crate</uri></include>",
    good="<include><uri>model://crate</uri></include>  <!-- models/crate installed -->",
    summary="an installed SDF's <include> or <mesh> URI names a file or model that is not there, "
    "or an absolute path into someone's home folder",
    explanation="Gazebo finds model://NAME in a folder NAME on its resource path, package://PKG/... in "
    "PKG's share folder, and a relative URI beside the SDF file; a path into /home/<someone> exists "
    "on its author's machine only. Not found, Gazebo loads the world without the model (or the "
    "mesh) or stops. A model:// no folder of the workspace has may come from the user's own "
    "resource path or Gazebo's model database: a warning. `pkgforge fix` rewrites a path into a "
    "home folder whose model or mesh the package itself installs: a path whose end is in its "
    "installed models folder (a model folder NAME, an SDF file or a mesh in it) as model://NAME[/...], "
    "another mesh of its share folder as package://PKG/... (unsafe: Gazebo finds it only with the "
    "folder holding share/PKG on its resource path). The model:// rewrite is safe when the models "
    "folder is on Gazebo's resource path, else unsafe: with --unsafe-fixes PF422's fix puts it there.",
    fix="safe",
    hint="install the model folder (install(DIRECTORY models ...)) and refer to it as model://NAME, "
    "or to a file of a package as package://PKG/path",
)
def sdf_uri_unresolved(ctx: CheckContext) -> Iterator[Finding]:
    tree = ctx.tree
    if tree is None:
        return
    share = tree.share(ctx.model.share_name)
    roots = _model_roots(ctx)
    for sdf in _installed_sdf(ctx):
        root = _parse(sdf)
        if isinstance(root, etree.XMLSyntaxError) or share is None:
            continue
        here = (share / sdf.installed).parent
        for uri in _uris(root):
            message = _unresolved(ctx, uri, here, roots)
            if message is not None:
                text, severity = message
                yield Finding(
                    f"{_shown(uri.text)}{text}",
                    sdf.source,
                    uri.line,
                    severity=severity,
                    fix=_home_replacement(ctx, uri, share, roots),
                )


def _home_path(uri: str) -> list[str] | None:
    """The parts of a file:// URI's or an absolute path's path when it is in a home folder."""
    parsed = urlparse(uri)
    if parsed.scheme not in ("file", ""):
        return None
    path = unquote(parsed.path if parsed.scheme else uri)
    if not HOME.match(path):
        return None
    return [part for part in posixpath.normpath(path).split("/") if part]


def _home_replacement(
    ctx: CheckContext, found: _Uri, share: Path, roots: dict[Path, str]
) -> dict[str, Any] | None:
    """The fix data of a home-folder URI whose target the package itself installs: the URI Gazebo
    finds it by, and whether that is unsafe (see PF421's explanation); None when there is none."""
    parts = _home_path(found.text)
    if not parts:
        return None
    target = _home_target(ctx, found, parts, share, roots)
    return {"uri": found.text, **target} if target else {"uri": found.text}


def _home_target(
    ctx: CheckContext, found: _Uri, parts: list[str], share: Path, roots: dict[Path, str]
) -> dict[str, Any] | None:
    own = ctx.model.share_name
    on_path = _on_resource_path(ctx)
    # the longest end of the path that is in a models folder of the package: model://NAME[/...]
    # (sdformat's <include> takes a model folder or an SDF file, gz-common a mesh, both found by
    # model:// in the folders of the resource path)
    for start in range(1, len(parts)):
        inside = "/".join(parts[start:])
        for root, package in roots.items():
            if package == own and root != share and ctx.files.exists(root / inside):
                return {"replacement": f"model://{inside}", "unsafe": root not in on_path}
    if found.include:
        return None
    # another mesh of the package's share folder: package://PKG/...
    for start in range(1, len(parts) - 1):
        relative = "/".join(parts[start:])
        if ctx.files.exists(share / relative) and not ctx.files.is_dir(share / relative):
            return {"replacement": f"package://{own}/{relative}", "unsafe": True}
    return None


def _on_resource_path(ctx: CheckContext) -> set[Path]:
    """The model folders Gazebo finds models in: what packages export (gazebo_model_path), every
    one when a hook or launch file of the workspace names a resource variable."""
    roots = _model_roots(ctx)
    if _sets_resource_path(ctx):
        return set(roots)
    tree = ctx.tree
    if tree is None:
        return set()
    return {
        path
        for package in tree.packages
        if (s := tree.share(package))
        for path in _exported_paths(ctx, package, s)
    }


def _unresolved(
    ctx: CheckContext, found: _Uri, here: Path, roots: dict[Path, str]
) -> tuple[str, Severity | None] | None:
    """What is wrong with one URI (the message after the URI, and its severity when not the
    check's), None when it is found or not Gazebo's to find here."""
    files = ctx.files
    uri = found.text
    parsed = urlparse(uri)
    if parsed.scheme in ("file", "") and (path := unquote(parsed.path if parsed.scheme else uri)).startswith(
        "/"
    ):
        if HOME.match(path):
            return (
                " is a path in a home folder: only its author's machine has it (install the model, use model://NAME)",
                None,
            )
        return None  # a system path (/usr/share/...): the target machine's
    if parsed.scheme == "model":
        # (model:///NAME/...: gz-common and Gazebo Classic join the rest to each resource path)
        name, _, rest = unquote(parsed.netloc + parsed.path).lstrip("/").partition("/")
        if name in ("", ".", "..") or ".." in rest.split("/"):
            return ": not a model name and a path inside it (model://NAME/...)", None
        folders = [root / name for root in roots if files.is_dir(root / name)]
        if not folders:
            if name in GAZEBO_MODELS:
                return None
            return (
                f": no models folder of the workspace has a model '{_shown(name)}' (Gazebo looks on "
                "its resource path and in its online model database only)",
                Severity.WARNING,
            )
        if rest and not any(files.exists(folder / rest) for folder in folders):
            return f": model '{name}' has no {_shown(rest)}", None
        return None
    if parsed.scheme == "package":
        tree = ctx.tree
        share = tree.share(parsed.netloc) if tree is not None else None
        if share is None:
            return None  # not a workspace package: installed elsewhere, or the manifest checks'
        relative = posixpath.normpath(unquote(parsed.path).lstrip("/") or ".")
        if relative.startswith(".."):
            return f": climbs out of package {parsed.netloc}'s share folder", None
        if relative != "." and not files.exists(share / relative):
            return f": package {parsed.netloc} installs no {_shown(relative)}", None
        return None
    if not parsed.scheme and uri and not files.exists(here / unquote(uri)):
        if found.include:  # sdformat looks for an include's bare name on the resource path too
            return ": not beside the SDF file (Gazebo looks on its resource path too)", Severity.WARNING
        return ": no such file beside the SDF file", None
    return None


@register(
    "PF422",
    "gazebo-resource-path-unset",
    "error",
    area="model",
    bad="<export>\n  <build_type>ament_cmake</build_type>\n</export>  <!-- worlds include model://crate from models/ -->",
    good='<export>\n  <build_type>ament_cmake</build_type>\n  <gazebo_ros gazebo_model_path="${prefix}/models"/>\n</export>',
    summary="an installed SDF includes model://NAME from a workspace package's models folder that "
    "nothing puts on Gazebo's resource path",
    explanation="Gazebo finds model://NAME only in folders of GZ_SIM_RESOURCE_PATH (gz-sim; "
    "IGN_GAZEBO_RESOURCE_PATH on Fortress) or GAZEBO_MODEL_PATH (Classic). ros_gz_sim's "
    "gz_sim.launch.py (humble 0.244.14 and later, jazzy) and gazebo_ros's gazebo.launch.py add "
    'what a package exports with <export><gazebo_ros gazebo_model_path="${prefix}/models"/>; '
    "neither adds a share folder by itself. An environment hook of the package or a launch file "
    "of the workspace naming one of those variables counts too (read as text). `pkgforge fix` "
    "gives an ament_cmake package's own models folder an environment hook (hooks/gz_resource_path.dsv.in, "
    "named in ament_environment_hooks() before ament_package(), as ros_gz_sim_demos does) prepending "
    "share/<package>/models to IGN_GAZEBO_RESOURCE_PATH (humble: Fortress), GZ_SIM_RESOURCE_PATH "
    "(jazzy and later) or GAZEBO_MODEL_PATH (a humble package depending on gazebo_ros: Classic): a safe fix, the path is set for whoever sources the workspace, whichever way "
    "Gazebo is started.",
    fix="safe",
    hint='add <gazebo_ros gazebo_model_path="${prefix}/models"/> to package.xml\'s <export>, or an '
    "environment hook that appends share/<package>/models to GZ_SIM_RESOURCE_PATH",
)
def gazebo_resource_path_unset(ctx: CheckContext) -> Iterator[Finding]:
    tree = ctx.tree
    if tree is None:
        return
    roots = _model_roots(ctx)
    exported = _on_resource_path(ctx)
    for sdf in _installed_sdf(ctx):
        root = _parse(sdf)
        if isinstance(root, etree.XMLSyntaxError):
            continue
        for uri in _uris(root):
            parsed = urlparse(uri.text)
            if parsed.scheme != "model":
                continue
            name = unquote(parsed.netloc + parsed.path).lstrip("/").partition("/")[0]
            found = [folder for folder in roots if ctx.files.is_dir(folder / name)]
            if not found or any(folder in exported for folder in found) or _sets_resource_path(ctx):
                continue
            package = roots[found[0]]
            yield Finding(
                f"model://{name} is in share/{package}/{found[0].name}, which nothing "
                f"puts on Gazebo's resource path (no <gazebo_ros gazebo_model_path> export, hook or "
                "launch file setting GZ_SIM_RESOURCE_PATH)",
                sdf.source,
                uri.line,
                fix=_hook_fix_data(ctx, package, found[0]),
            )
            return  # once per package: one export fixes every model of the folder


def _hook_fix_data(ctx: CheckContext, package: str, folder: Path) -> dict[str, Any] | None:
    """What PF422's fix needs: the package's folder and the variables of its target distros; None
    for another package's folder or an exported one (that package's own finding fixes it)."""
    if package != ctx.model.share_name or folder.name != "models" or ctx.tree is None:
        return None
    if folder != (ctx.tree.share(package) or Path("/nonexistent")) / "models":
        return None
    return {
        "package": str(ctx.model.path),
        "build_type": ctx.model.build_type,
        "variables": resource_variables(ctx.distros, _gazebos(ctx)),
    }


# what a package depends on to run each Gazebo (gazebo_ros_pkgs for Classic; ros_gz, and
# ros_ign on humble, for gz-sim and Fortress)
CLASSIC_PACKAGES = frozenset({"gazebo_ros", "gazebo_ros_pkgs", "gazebo_plugins", "gazebo_ros2_control"})
GZ_PACKAGES = frozenset(
    {
        "ros_gz",
        "ros_gz_sim",
        "ros_gz_bridge",
        "ros_ign",
        "ros_ign_gazebo",
        "gz_ros2_control",
        "ign_ros2_control",
    }
)


def _gazebos(ctx: CheckContext) -> tuple[bool, bool]:
    """(whether the package depends on Gazebo Classic's ROS packages, on gz-sim's)."""
    names = {d.name for d in ctx.model.manifest.dependencies if d.active()}
    return bool(names & CLASSIC_PACKAGES), bool(names & GZ_PACKAGES)


def resource_variables(distros: tuple[str, ...], gazebos: tuple[bool, bool] = (False, True)) -> list[str]:
    """The variables the package's Gazebo reads its resource path from: Gazebo Classic
    GAZEBO_MODEL_PATH (a humble package depending on gazebo_ros); Fortress (humble)
    IGN_GAZEBO_RESOURCE_PATH (ign-gazebo6's Util.hh; its later releases read GZ_SIM_RESOURCE_PATH
    too, its first did not); gz-sim 8 and later GZ_SIM_RESOURCE_PATH only (gz-sim8's Util.hh).
    No target: both gz variables. A package depending on neither Gazebo's ROS packages: gz-sim."""
    from pkgforge.model.simulation import gz_names

    classic, gz = gazebos
    humble = not distros or "humble" in distros
    out: list[str] = []
    if gz or not classic or not humble:
        # (no target: both gz variables, the newest's first)
        for distro in sorted(distros or ("jazzy", "humble"), key=lambda d: d == "humble"):
            variable = gz_names(distro)["resource"]
            if variable not in out:
                out.append(variable)
    if classic and humble:
        out.append("GAZEBO_MODEL_PATH")
    return out


def _sets_resource_path(ctx: CheckContext) -> bool:
    """Whether a file of the workspace's packages that may set the environment (a hook, a CMake
    file, a launch file) names one of Gazebo's resource variables."""

    def compute() -> bool:
        for model in [ctx.model, *ctx.models.values()]:
            for relative in model.files:
                name = relative.name
                candidate = (
                    name.endswith(
                        (
                            ".dsv",
                            ".dsv.in",
                            ".sh",
                            ".sh.in",
                            ".bash",
                            ".zsh",
                            ".cmake",
                            ".in",
                            ".py",
                            ".xml",
                            ".yaml",
                        )
                    )
                    or name == "CMakeLists.txt"
                )
                if candidate and name != "package.xml":
                    text = ctx.text_head(str(model.path / relative))
                    if any(variable in text for variable in RESOURCE_VARIABLES):
                        return True
        return False

    found: bool = ctx._shared("gazebo-resource-variables", compute)
    return found
