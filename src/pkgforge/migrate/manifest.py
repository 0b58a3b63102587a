"""A ROS 1 package.xml as CAD exporters write it, read for what the ROS 2 manifest needs.

Read with lxml, not catkin_pkg: catkin_pkg refuses (or warns on the terminal about) what the
exporters write by default: the assembly's name as package name (`Arm_Assembly_URDF.SLDASM`),
`<maintainer email="TODO@email.com" />` with no name, format 1. migrate gives the package a valid
name and fills in the maintainer, so these are no reason to refuse the package.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from pkgforge.errors import PkgforgeError
from pkgforge.model.source import read_regular

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes

VERSION = re.compile(r"^\d+\.\d+\.\d+$")


@dataclass(frozen=True)
class Person:
    name: str
    email: str | None
    line: int | None


@dataclass
class Ros1Manifest:
    path: Path
    root: etree._Element
    name: str
    name_line: int | None
    version: str
    description_xml: str
    maintainers: list[Person] = field(default_factory=list)
    authors: list[Person] = field(default_factory=list)
    licenses: list[str] = field(default_factory=list)
    urls: list[tuple[str, str]] = field(default_factory=list)
    buildtools: list[str] = field(default_factory=list)


def _people(root: etree._Element, tag: str) -> list[Person]:
    return [Person((e.text or "").strip(), e.get("email"), e.sourceline) for e in root.findall(tag)]


def inner_xml(element: etree._Element | None) -> str:
    """The content of an element as XML (a description's <p>s and text), without the element."""
    if element is None:
        return ""
    text = etree.tostring(element, encoding="unicode", with_tail=False)
    if text.endswith("/>") and text.count("<") == 1:
        return ""
    return text[text.index(">") + 1 : text.rindex("</")].strip()


def read_manifest(folder: Path) -> Ros1Manifest:
    """The package.xml of a ROS 1 catkin package (any format), or a located PkgforgeError."""
    manifest = folder / "package.xml"
    if not folder.is_dir():
        raise PkgforgeError(f"{folder}: no such folder; give the ROS 1 package folder (with package.xml)")
    if not os.path.lexists(manifest):
        raise PkgforgeError(
            f"{folder}: no package.xml: not a catkin package; give the folder that holds package.xml"
        )
    try:
        data = read_regular(manifest)  # (a FIFO or a device: refused, never read)
    except OSError as exc:
        raise PkgforgeError(f"{manifest}: {exc.strerror} (nothing written)") from exc
    parser = etree.XMLParser(resolve_entities=False, no_network=True)
    try:
        root = etree.fromstring(data, parser, base_url=str(manifest))
    except etree.XMLSyntaxError as exc:
        raise PkgforgeError(
            f"{manifest}:{exc.lineno}: not well-formed XML: {exc.msg} (nothing written)"
        ) from exc
    if root.tag != "package":
        raise PkgforgeError(
            f"{manifest}:{root.sourceline}: the root element is <{root.tag!s}>, not <package>: "
            "not a package.xml (nothing written)"
        )
    name_element = root.find("name")
    name = (name_element.text or "").strip() if name_element is not None else ""
    if not name:
        raise PkgforgeError(
            f"{manifest}:{root.sourceline}: no <name>: give the package a name (nothing written)"
        )
    buildtools = [(e.text or "").strip() for e in root.findall("buildtool_depend")]
    if "catkin" not in buildtools:
        line = next((e.sourceline for e in root.iter("buildtool_depend")), root.sourceline)
        found = f"its build tool is {', '.join(buildtools)}" if buildtools else "it has no <buildtool_depend>"
        raise PkgforgeError(
            f"{manifest}:{line}: not a catkin package ({found}, not catkin): migrate converts "
            "ROS 1 catkin packages (nothing written)"
        )
    return Ros1Manifest(
        path=manifest,
        root=root,
        name=name,
        name_line=name_element.sourceline if name_element is not None else root.sourceline,
        version=(root.findtext("version") or "").strip(),
        description_xml=inner_xml(root.find("description")),
        maintainers=_people(root, "maintainer"),
        authors=[p for p in _people(root, "author") if p.name],
        licenses=[t for e in root.findall("license") if (t := (e.text or "").strip())],
        urls=[(e.get("type") or "", t) for e in root.findall("url") if (t := (e.text or "").strip())],
        buildtools=buildtools,
    )


def maintainers(
    manifest: Ros1Manifest, name_option: str | None, email_option: str | None, notes: Notes
) -> tuple[tuple[str, str], ...]:
    """The maintainers of the ROS 2 manifest: the source's, each missing name or e-mail filled in
    from --maintainer-name/--maintainer-email or git config (as `new` does), reported. A maintainer
    with no name is the exporter's stand-in (`<maintainer email="TODO@email.com" />`): its e-mail
    gives way to --maintainer-email."""
    from pkgforge.scaffold.package import EMAIL_PATTERN, default_maintainer, git_config

    default_name, default_email = default_maintainer()
    name_from = (
        "--maintainer-name"
        if name_option
        else "git config user.name"
        if git_config("user.name")
        else "login name"
    )
    email_from = (
        "--maintainer-email"
        if email_option
        else "git config user.email"
        if git_config("user.email")
        else "login name"
    )
    people = list(manifest.maintainers) or [Person("", None, None)]
    out: list[tuple[str, str]] = []
    for person in people:
        name, email, filled = person.name, person.email or "", []
        if not name:
            # the exporter's stand-in (<maintainer email="TODO@email.com" />): a maintainer to fill in
            name = name_option or default_name
            filled.append(f"name from {name_from}")
            if (email_option or git_config("user.email")) and email != (email_option or default_email):
                email = email_option or default_email
                filled.append(f"e-mail from {email_from}")
        if not EMAIL_PATTERN.match(email):
            email = email_option or default_email
            filled.append(f"e-mail from {email_from}")
        if filled:
            was = (
                f'<maintainer email="{person.email}"/> has no name'
                if manifest.maintainers and not person.name
                else "<maintainer> without an e-mail"
                if manifest.maintainers
                else "no <maintainer>"
            )
            notes.add(
                "migrate-changed",
                f"package.xml: {was}: {name} <{email}> ({', '.join(filled)})",
                manifest.path,
                person.line or manifest.name_line,
            )
        out.append((name, email))
    return tuple(dict.fromkeys(out))


def version(manifest: Ros1Manifest, notes: Notes) -> str:
    """The package's version, which a ROS 2 manifest needs as MAJOR.MINOR.PATCH."""
    if VERSION.match(manifest.version):
        return manifest.version
    element = manifest.root.find("version")
    notes.add(
        "migrate-changed",
        f"package.xml: version '{manifest.version}' is not MAJOR.MINOR.PATCH: 0.0.0",
        manifest.path,
        element.sourceline if element is not None else manifest.name_line,
    )
    return "0.0.0"
