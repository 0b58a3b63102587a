"""Which checks run: --select/--ignore, pkgforge.toml, and per-package overrides.

pkgforge.toml, at the workspace root or a package root:

    [verify]
    ignore = ["unused-exec-depend"]      # codes or names
    select = ["PF1", "PF2"]              # prefixes of codes work too
    distro = "jazzy"                     # or a list: the ROS 2 distros the package targets
    [verify.packages.rob_description]   # workspace file only
    ignore = ["folder-name-mismatch"]
    [verify.per-file-ignores]            # glob (from this file's folder) -> codes, prefixes or names
    "launch/legacy_*.py" = ["PF301"]     # a glob without / matches the file's name in any folder
    [severity]                           # per check: code, code prefix or name
    PF203 = "warning"                    # error, warning or info; a package's file wins
"""

from __future__ import annotations

import re
import sys
from collections.abc import Callable, Collection, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

from pkgforge.checks.registry import Check, all_checks
from pkgforge.diagnostics import PackageReport, Severity
from pkgforge.errors import PkgforgeError

CONFIG_FILE = "pkgforge.toml"


@dataclass
class Selection:
    select: list[str] = field(default_factory=list)  # empty: every check
    ignore: list[str] = field(default_factory=list)
    # [severity] of pkgforge.toml: check code, code prefix or name -> error, warning or info
    severity: dict[str, str] = field(default_factory=dict)
    # [verify.per-file-ignores]: (the folder of the pkgforge.toml, a glob, the checks it silences)
    per_file: list[tuple[Path, str, list[str]]] = field(default_factory=list)

    def key(self) -> str:
        """The selection as text, for cache keys (with pkgforge's version, it decides the codes
        and the severities a cached report holds)."""
        files = sorted((str(base), glob, sorted(keys)) for base, glob, keys in self.per_file)
        return f"{sorted(self.select)}|{sorted(self.ignore)}|{sorted(self.severity.items())}|{files}"

    def ignored_in(self, path: Path, check: Check) -> bool:
        """Whether [verify.per-file-ignores] silences `check` in the file at `path`."""
        for base, glob, keys in self.per_file:
            if any(_matches(check, key) for key in keys) and glob_matches(glob, path, base):
                return True
        return False

    def severity_of(self, check: Check) -> Severity | None:
        """The severity pkgforge.toml sets for this check: its code or name, else its longest
        matching code prefix; None: the check's own."""
        best: tuple[int, str] | None = None
        for key, level in self.severity.items():
            if not _matches(check, key):
                continue
            rank = (
                100
                if key.strip() in (check.code, check.name) or key.strip().upper() == check.code
                else len(key.strip())
            )
            if best is None or rank > best[0]:
                best = (rank, level)
        return Severity.parse(best[1]) if best else None

    def apply_severity(self, report: PackageReport) -> None:
        """Rewrite the severity of the report's diagnostics as [severity] says (exit code follows)."""
        if not self.severity:
            return
        from dataclasses import replace

        from pkgforge.checks.registry import REGISTRY

        changed = []
        for diagnostic in report.diagnostics:
            check = REGISTRY.get(diagnostic.code)
            level = self.severity_of(check) if check is not None else None
            changed.append(replace(diagnostic, severity=level) if level is not None else diagnostic)
        report.diagnostics = changed

    def codes(self) -> set[str]:
        checks = all_checks()
        chosen = {c.code for c in checks if not self.select or any(_matches(c, k) for k in self.select)}
        return {
            code
            for code in chosen
            if not any(_matches(c, k) for k in self.ignore for c in checks if c.code == code)
        }


def split_keys(values: Iterable[str]) -> list[str]:
    """--select/--ignore as given, once or more, each comma-separated: `--select PF1,PF2 --select PF3`
    (`pkgforge verify`, `pkgforge fix` and `colcon verify` alike)."""
    return [k.strip() for value in values for k in value.split(",") if k.strip()]


def _matches(check: Check, key: str) -> bool:
    key = key.strip()
    return (
        check.name == key
        or check.code == key.upper()
        or (key.upper().startswith("PF") and check.code.startswith(key.upper()))
    )


def validate_keys(keys: list[str], where: str) -> None:
    if not keys:
        return
    from pkgforge.checks.registry import close_checks

    checks = all_checks()
    for key in keys:
        if not any(_matches(c, key) for c in checks):
            close = close_checks(key)
            also = f" (did you mean {', '.join(close)}?)" if close else ""
            raise PkgforgeError(
                f"{where}: no check is named or coded '{key}'{also}; `pkgforge checks` lists them"
            )


def glob_matches(glob: str, path: Path, base: Path) -> bool:
    """Whether `path` matches `glob` written in a pkgforge.toml of the folder `base`: relative to
    `base` (`**` any folders, `*` and `?` within a name); a glob without / matches the file's
    name in any folder below `base`, as ruff's per-file-ignores and .gitignore read one."""
    import os
    import re

    try:
        relative = Path(os.path.relpath(path, base)).as_posix()
    except ValueError:  # (another drive)
        return False
    if relative == ".." or relative.startswith("../"):
        return False
    pattern = glob.strip().removeprefix("./")
    if "/" not in pattern.rstrip("/"):
        pattern = "**/" + pattern
    return re.fullmatch(_glob_regex(pattern.rstrip("/")), relative) is not None or (
        glob.endswith("/") and re.match(_glob_regex(pattern.rstrip("/")) + "/", relative) is not None
    )


def _glob_regex(glob: str) -> str:
    import re

    out, index = [], 0
    while index < len(glob):
        if glob.startswith("**/", index):
            out.append("(?:.*/)?")
            index += 3
        elif glob.startswith("**", index):
            out.append(".*")
            index += 2
        elif glob[index] == "*":
            out.append("[^/]*")
            index += 1
        elif glob[index] == "?":
            out.append("[^/]")
            index += 1
        elif glob[index] == "[" and "]" in glob[index + 2 :]:
            end = glob.index("]", index + 2)
            body = glob[index + 1 : end]
            out.append("[" + ("^" + body[1:] if body.startswith("!") else body).replace("\\", "\\\\") + "]")
            index = end + 1
        else:
            out.append(re.escape(glob[index]))
            index += 1
    return "".join(out)


@dataclass
class Config:
    """The workspace-level configuration, with each package's own on top."""

    cli: Selection = field(default_factory=Selection)
    workspace: dict[str, Any] = field(default_factory=dict)  # pkgforge.toml as read (validated)
    workspace_file: Path | None = None

    def for_package(self, name: str, package_path: Path) -> Selection:
        verify = self.workspace.get("verify", {})
        select = list(self.cli.select or verify.get("select", []))
        ignore = list(self.cli.ignore) + list(verify.get("ignore", []))
        ignore += list(verify.get("packages", {}).get(name, {}).get("ignore", []))
        severity = {key: str(level).lower() for key, level in self.workspace.get("severity", {}).items()}
        per_file = _per_file(verify, self.workspace_file)
        own = package_path / CONFIG_FILE
        if own.is_file() and own != self.workspace_file:
            own_config = read_config(own)
            own_verify = own_config.get("verify", {})
            ignore += list(own_verify.get("ignore", []))
            if not self.cli.select and own_verify.get("select"):
                select = list(own_verify["select"])
            severity.update(
                {key: str(level).lower() for key, level in own_config.get("severity", {}).items()}
            )
            per_file += _per_file(own_verify, own)
        return Selection(select, ignore, severity, per_file)

    def distro_for(self, package_path: Path) -> str | list[str] | None:
        """[verify] distro of the package's pkgforge.toml, else the workspace's; None if neither."""
        own = package_path / CONFIG_FILE
        value: str | list[str] | None
        if own.is_file() and own != self.workspace_file:
            value = read_config(own).get("verify", {}).get("distro")
            if value:
                return value
        value = self.workspace.get("verify", {}).get("distro")
        return value


def _per_file(verify: dict[str, Any], file: Path | None) -> list[tuple[Path, str, list[str]]]:
    """[verify.per-file-ignores] of a pkgforge.toml: its globs are read from its own folder."""
    table = verify.get("per-file-ignores", {})
    if not table or file is None:
        return []
    return [(file.parent.resolve(), glob, list(keys)) for glob, keys in table.items()]


# What pkgforge.toml may hold: a key not here (a misspelling) is an error, not silently ignored.
# A value is checked by the function at its key; a dict is a table of known keys; PACKAGES is
# a table whose keys are package names, each a table of PACKAGE_KEYS.
def _strings(value: object) -> bool:
    return isinstance(value, list) and all(isinstance(v, str) for v in value)


def _distros(value: object) -> bool:
    return isinstance(value, str) or (isinstance(value, list) and all(isinstance(v, str) for v in value))


SEVERITIES = ("error", "warning", "info")
# a key's rule: a table of known keys, a table of the user's keys (Entries), or (test, what it must be)
Rule = Union[dict[str, "Rule"], "Entries", tuple[Callable[[Any], bool], str]]


@dataclass(frozen=True)
class Entries:
    """A table whose keys are the user's (package names, checks); each value follows `each`."""

    each: Rule  # a table's schema (dict) or (test, what it must be)
    key_is_check: bool = False  # each key must name a check (code, code prefix or name)


SCHEMA: dict[str, Rule] = {
    "verify": {
        "select": (_strings, "a list of check codes, code prefixes or names"),
        "ignore": (_strings, "a list of check codes, code prefixes or names"),
        "distro": (_distros, "a ROS 2 distro name, or a list of them"),
        "packages": Entries({"ignore": (_strings, "a list of check codes or names")}),  # workspace file only
        # glob -> the checks silenced in the files it matches
        "per-file-ignores": Entries((_strings, "a list of check codes, code prefixes or names")),
    },
    # check code, code prefix or name = "error" | "warning" | "info"
    "severity": Entries(
        (
            lambda level: isinstance(level, str) and level.lower() in SEVERITIES,
            f"one of {', '.join(map(repr, SEVERITIES))}",
        ),
        key_is_check=True,
    ),
}


KEY = r"""(?:"[^"]*"|'[^']*'|[A-Za-z0-9_\-]+)"""  # a TOML key: quoted or bare


def key_line(text: str, dotted: str) -> int | None:
    """The line that sets `dotted` (a.b.c) in TOML text: its `[a.b]` header or its `c = ...`."""
    import re

    def parts(name: str) -> list[str]:
        return [p.strip().strip('"').strip("'") for p in re.findall(r'"[^"]*"|\'[^\']*\'|[^.]+', name)]

    want = parts(dotted)
    table: list[str] = []
    for number, line in enumerate(text.splitlines(), start=1):
        header = re.match(r"\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$", line)
        if header:
            table = parts(header.group(1))
            if table == want:
                return number
            continue
        assignment = re.match(rf"\s*({KEY}(?:\s*\.\s*{KEY})*)\s*=", line)
        if assignment and table + parts(assignment.group(1)) == want:
            return number
    return None


def _at(text: str, dotted: str) -> str:
    line = key_line(text, dotted)
    return f":{line}" if line else ""


def _problem(path: Path, text: str, dotted: str, what: str) -> PkgforgeError:
    return PkgforgeError(f"{path}{_at(text, dotted)}: {what}")


def _unknown(path: Path, text: str, dotted: str, known: Collection[str]) -> PkgforgeError:
    import difflib

    name = dotted.rpartition(".")[2]
    close = difflib.get_close_matches(name, list(known), n=1)
    also = f"did you mean '{close[0]}'? " if close else ""
    return _problem(path, text, dotted, f"unknown key '{dotted}' ({also}known here: {', '.join(known)})")


def validate(data: dict[str, Any], path: Path, text: str) -> None:
    """Every key known and of the right type: exit 2 naming the key, the file and its line."""

    def value(item: Any, rule: Rule, dotted: str) -> None:
        if isinstance(rule, (dict, Entries)) and not isinstance(item, dict):
            raise _problem(path, text, dotted, f"'{dotted}' must be a table ([{dotted}])")
        if isinstance(rule, dict):
            for key, own in item.items():
                if key not in rule:
                    raise _unknown(path, text, f"{dotted}.{key}".lstrip("."), rule)
                value(own, rule[key], f"{dotted}.{key}".lstrip("."))
        elif isinstance(rule, Entries):
            for key, own in item.items():
                # a key that is no bare TOML key (a glob of per-file-ignores: "launch/*.py") quoted
                # as written, so that its line is found
                named = f"{dotted}.{key}" if re.fullmatch(r"[A-Za-z0-9_-]+", key) else f'{dotted}."{key}"'
                if rule.key_is_check:
                    validate_keys([key], f"{path}{_at(text, named)}: {named}")
                value(own, rule.each, named)
        else:
            test, expected = rule
            if not test(item):
                raise _problem(path, text, dotted, f"'{dotted}' must be {expected}, not {item!r}")

    value(data, SCHEMA, "")


def read_config(path: Path) -> dict[str, Any]:
    if sys.version_info >= (3, 11):  # (imported here: a workspace without pkgforge.toml never needs it)
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib  # type: ignore[import-not-found,unused-ignore]  # 3.10's backport: absent where mypy runs

    from pkgforge.model.source import read_regular

    try:  # (a FIFO or a device: refused, never read)
        text = read_regular(path).decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise PkgforgeError(f"{path}: cannot read: {exc}") from exc
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        where = str(exc).replace(
            "(at end of document)", f"(at end of document, line {max(1, len(text.splitlines()))})"
        )
        raise PkgforgeError(f"{path}: invalid TOML: {where}; fix the syntax at that line") from exc
    validate(data, path, text)
    verify = data.get("verify", {})
    for key in ("select", "ignore"):
        validate_keys(verify.get(key, []), f"{path}{_at(text, 'verify.' + key)}: verify.{key}")
    distro = verify.get("distro")
    if distro is not None:
        from pkgforge.model.distros import DISTROS

        chosen = [distro] if isinstance(distro, str) else distro
        if not chosen or any(d not in DISTROS for d in chosen):
            raise PkgforgeError(
                f"{path}{_at(text, 'verify.distro')}: verify.distro must name active ROS 2 "
                f"distros ({', '.join(DISTROS)}), as a string or a list"
            )
    for package, table in verify.get("packages", {}).items():
        validate_keys(list(table.get("ignore", [])), f"{path}: verify.packages.{package}.ignore")
    for glob, keys in verify.get("per-file-ignores", {}).items():
        dotted = f'verify.per-file-ignores."{glob}"'
        validate_keys(list(keys), f"{path}{_at(text, dotted)}: {dotted}")
    return data


def load_config(root: Path, cli: Selection) -> Config:
    validate_keys(cli.select + cli.ignore, "--select/--ignore")
    path = root / CONFIG_FILE
    if path.is_file():
        return Config(cli, read_config(path), path)
    return Config(cli)
