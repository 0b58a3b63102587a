"""The Python formatter a repository keeps its launch files in (black, ruff format), run on a fixed file.

A fix edits as little as it can, but a wrapped call (`ParameterValue(Command(...),
value_type=str)`) can make a line longer than the repository's formatter allows, and
its CI's `black --check` or `ruff format --check` then fails on the fixed file. Where
the repository configures one of them, and the file as read is exactly what that
formatter makes of it, the fixed text is put through the same formatter: the file
stays stable under it. A file the formatter would change anyway, a formatter that is
not installed or fails: the fixed text as the fix made it.

Which formatter: the nearest configuration between the file and its repository's root
(the first folder above it with .git), as the formatters find theirs:
`.pre-commit-config.yaml` hooks `ruff-format` or `black`; `pyproject.toml`'s
`[tool.black]` or `[tool.ruff]`; a `ruff.toml` or `.ruff.toml`.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

TIMEOUT = 20.0  # seconds for one run of the formatter
CONFIG_FILES = (".pre-commit-config.yaml", "pyproject.toml", "ruff.toml", ".ruff.toml")


def configured(path: Path) -> str | None:
    """black or ruff: the formatter the repository holding `path` configures; None: none."""
    folder = path.parent
    while True:
        for name in CONFIG_FILES:
            chosen = _from_config(folder / name)
            if chosen is not None:
                return chosen
        if (folder / ".git").exists() or folder.parent == folder:
            return None
        folder = folder.parent


def _from_config(config: Path) -> str | None:
    try:
        text = config.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    if config.name == ".pre-commit-config.yaml":
        return _pre_commit_hook(text)
    if config.name != "pyproject.toml":
        return "ruff"
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib  # type: ignore[import-not-found,unused-ignore]

    try:
        tool = tomllib.loads(text).get("tool", {})
    except tomllib.TOMLDecodeError:
        return None
    if not isinstance(tool, dict):
        return None
    return "black" if "black" in tool else "ruff" if "ruff" in tool else None


def _pre_commit_hook(text: str) -> str | None:
    import yaml

    try:
        document = yaml.safe_load(text)
    except yaml.YAMLError:
        return None
    repos = document.get("repos") if isinstance(document, dict) else None
    for repo in repos if isinstance(repos, list) else []:
        hooks = repo.get("hooks") if isinstance(repo, dict) else None
        for hook in hooks if isinstance(hooks, list) else []:
            name = hook.get("id") if isinstance(hook, dict) else None
            if name == "ruff-format":
                return "ruff"
            if name == "black":
                return "black"
    return None


def _command(formatter: str, path: Path) -> list[str] | None:
    """The command that formats standard input as the file `path` (its configuration found from there)."""
    program = shutil.which(formatter) or shutil.which(formatter, path=os.path.dirname(sys.executable))
    if program is None:
        return None
    if formatter == "ruff":
        return [program, "format", "--quiet", "--stdin-filename", str(path), "-"]
    return [program, "--quiet", "--stdin-filename", str(path), "-"]


def _run(command: list[str], text: str, folder: Path) -> str | None:
    try:
        done = subprocess.run(
            command, input=text, capture_output=True, text=True, timeout=TIMEOUT, cwd=folder, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout if done.returncode == 0 else None


def keep_formatted(path: Path, before: str, after: str) -> str:
    """`after` (the fixed text of the Python file `path`) as the repository's formatter writes it,
    when `before` (the text as read) is already what it writes; else `after` unchanged."""
    formatter = configured(path)
    command = _command(formatter, path) if formatter is not None else None
    if command is None or _run(command, before, path.parent) != before:
        return after
    formatted = _run(command, after, path.parent)
    return formatted if formatted is not None else after
