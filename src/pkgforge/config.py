"""Which checks run: --select/--ignore, pkgforge.toml, and per-package overrides.

pkgforge.toml, at the workspace root or a package root:

    [verify]
    ignore = ["unused-exec-depend"]      # codes or names
    select = ["PF1", "PF2"]              # prefixes of codes work too
    distro = "jazzy"                     # or a list: the ROS 2 distros the package targets
    [verify.packages.rob_description]   # workspace file only
    ignore = ["folder-name-mismatch"]
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

from .checks.registry import all_checks
from .errors import PkgforgeError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

CONFIG_FILE = "pkgforge.toml"


@dataclass
class Selection:
    select: list[str] = field(default_factory=list)  # empty: every check
    ignore: list[str] = field(default_factory=list)

    def key(self) -> str:
        """The selection as text, for cache keys (with pkgforge's version, it decides the codes)."""
        return f"{sorted(self.select)}|{sorted(self.ignore)}"

    def codes(self) -> set[str]:
        checks = all_checks()
        chosen = {c.code for c in checks if not self.select or any(_matches(c, k) for k in self.select)}
        return {code for code in chosen
                if not any(_matches(c, k) for k in self.ignore for c in checks if c.code == code)}


def _matches(check, key: str) -> bool:
    key = key.strip()
    return check.name == key or check.code == key.upper() or \
        (key.upper().startswith("PF") and check.code.startswith(key.upper()))


def validate_keys(keys: list[str], where: str) -> None:
    if not keys:
        return
    checks = all_checks()
    for key in keys:
        if not any(_matches(c, key) for c in checks):
            raise PkgforgeError(f"{where}: no check is named or coded '{key}' (see `pkgforge checks`)")


@dataclass
class Config:
    """The workspace-level configuration, with each package's own on top."""

    cli: Selection = field(default_factory=Selection)
    workspace: dict = field(default_factory=dict)
    workspace_file: Path | None = None

    def for_package(self, name: str, package_path: Path) -> Selection:
        verify = self.workspace.get("verify", {})
        select = list(self.cli.select or verify.get("select", []))
        ignore = list(self.cli.ignore) + list(verify.get("ignore", []))
        ignore += list(verify.get("packages", {}).get(name, {}).get("ignore", []))
        own = package_path / CONFIG_FILE
        if own.is_file() and own != self.workspace_file:
            own_verify = read_config(own).get("verify", {})
            ignore += list(own_verify.get("ignore", []))
            if not self.cli.select and own_verify.get("select"):
                select = list(own_verify["select"])
        return Selection(select, ignore)

    def distro_for(self, package_path: Path):
        """[verify] distro of the package's pkgforge.toml, else the workspace's; None if neither."""
        own = package_path / CONFIG_FILE
        if own.is_file() and own != self.workspace_file:
            value = read_config(own).get("verify", {}).get("distro")
            if value:
                return value
        return self.workspace.get("verify", {}).get("distro")


def read_config(path: Path) -> dict:
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise PkgforgeError(f"{path}: cannot read: {exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise PkgforgeError(f"{path}: invalid TOML: {exc}") from exc
    verify = data.get("verify", {})
    if not isinstance(verify, dict):
        raise PkgforgeError(f"{path}: [verify] must be a table")
    for key in ("select", "ignore"):
        value = verify.get(key, [])
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise PkgforgeError(f"{path}: verify.{key} must be a list of check codes or names")
        validate_keys(value, f"{path}: verify.{key}")
    distro = verify.get("distro")
    if distro is not None:
        from .distros import DISTROS

        chosen = [distro] if isinstance(distro, str) else distro
        if not isinstance(chosen, list) or not chosen or \
                any(not isinstance(d, str) or d not in DISTROS for d in chosen):
            raise PkgforgeError(f"{path}: verify.distro must name active ROS 2 distros "
                                f"({', '.join(DISTROS)}), as a string or a list")
    for package, table in verify.get("packages", {}).items():
        validate_keys(list(table.get("ignore", [])), f"{path}: verify.packages.{package}.ignore")
    return data


def load_config(root: Path, cli: Selection) -> Config:
    validate_keys(cli.select + cli.ignore, "--select/--ignore")
    path = root / CONFIG_FILE
    if path.is_file():
        return Config(cli, read_config(path), path)
    return Config(cli)
