"""setup.py evaluated as setuptools and colcon evaluate it, in the sandbox (user code).

colcon-python-setup-py reads an ament_python package's metadata by running, in the package's
folder, `distutils.core.run_setup('setup.py', script_args=('--dry-run',), stop_after='config')`
with setuptools imported first: setup.py runs whole, its setup() call builds setuptools'
Distribution from the keyword arguments and setup.cfg, and stops there, before any command.
`run_setup_py` does the same in a request's fresh, confined process (sandbox/worker.py), so what
a helper function with glob, os.walk or a list comprehension computes is what pkgforge predicts.
Two differences, both so that evaluating never changes anything: setup_requires is not fetched
(setuptools would install eggs before calling setup()), and the process may write nowhere but
its own folder (the sandbox's Landlock and guard): a setup.py that writes fails, at its line.

The parent (`apply_setup_reply`) turns the values into the package's SetupPyModel and install
layout; when setup.py fails, the static reader's (setup_py.py) model stays, with the failure.
"""

from __future__ import annotations

import os
import sys
import traceback
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pkgforge.sandbox.protocol import DataFilesItem, ErrorRecord, SetupReply, SetupValues

if TYPE_CHECKING:
    from pkgforge.model.package import PackageModel

SCRIPT = "setup.py"  # the name colcon runs it by (its __file__), in its own folder


class NotSetupValue(ValueError):
    """A value setup() got that setuptools would refuse when it installs (not text, not a list)."""


# --- in the sandbox: run it ------------------------------------------------------------------


def run_setup_py(path: str) -> SetupReply:
    """The values setup.py's setup() call gets, as colcon's run_setup(stop_after='config') reads
    them; or the error that stopped it, at setup.py's line. Runs in a request's own process."""
    folder = os.path.dirname(os.path.abspath(path))
    os.chdir(folder)  # its globs and relative paths are the package's, as under colcon
    sys.path.insert(0, folder)  # `python -c` in that folder: the package's own modules import
    sys.argv = [SCRIPT]
    try:
        import importlib

        setuptools: Any = importlib.import_module("setuptools")
        # fetching setup_requires would install eggs (network, writes) before setup() runs
        setuptools._install_setup_requires = lambda attrs: None
        # (setuptools' own distutils, since setuptools came first: colcon's order)
        run_setup: Any = importlib.import_module("distutils.core").run_setup
        distribution = run_setup(SCRIPT, script_args=("--dry-run",), stop_after="config")
        return {"status": "ok", "values": _values(distribution)}
    except NotSetupValue as error:
        return {"status": "error", "error": _record(path, error, located=False)}
    except (Exception, KeyboardInterrupt) as error:  # noqa: BLE001 - setup.py's own, at its line
        # (the sandbox's time limits are other BaseExceptions: the worker reports them)
        return {"status": "error", "error": _record(path, error)}


def _record(path: str, error: BaseException, *, located: bool = True) -> ErrorRecord:
    """The error at setup.py's deepest line in its traceback (run_setup execs the file's text,
    so its frames are '<string>' with the script's globals)."""
    line = None
    if located:
        for frame, number in traceback.walk_tb(error.__traceback__):
            if frame.f_code.co_filename == "<string>" and frame.f_globals.get("__file__") == SCRIPT:
                line = number
    message = " ".join(str(error).split()) or type(error).__name__
    kind = "" if isinstance(error, NotSetupValue) else type(error).__name__  # (its words say all)
    return {"stage": "setup", "type": kind, "message": message, "file": path, "line": line}


def _values(distribution: Any) -> SetupValues:
    metadata = getattr(distribution, "metadata", None)
    name = getattr(metadata, "name", None)
    return {
        "name": name if isinstance(name, str) else None,
        "data_files": _data_files(getattr(distribution, "data_files", None)),
        "packages": _names(getattr(distribution, "packages", None), "packages"),
        "py_modules": _names(getattr(distribution, "py_modules", None), "py_modules"),
        "package_data": _mapping_of_lists(getattr(distribution, "package_data", None), "package_data"),
        "package_dir": _mapping_of_text(getattr(distribution, "package_dir", None)),
        "entry_points": _entry_points(getattr(distribution, "entry_points", None)),
    }


def _text(value: object, what: str) -> str:
    if isinstance(value, (str, os.PathLike)):
        text = os.fspath(value)
        if isinstance(text, str):
            return text
    raise NotSetupValue(f"setup() got {what} that is {type(value).__name__} {value!r:.80}, not a path")


def _data_files(value: object) -> list[DataFilesItem] | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise NotSetupValue(f"setup() got data_files that are {type(value).__name__}, not a list")
    out: list[DataFilesItem] = []
    for number, entry in enumerate(value, start=1):
        if isinstance(entry, (str, os.PathLike)):
            out.append(_text(entry, f"data_files entry {number}"))
            continue
        try:
            destination, files = entry
        except (TypeError, ValueError):
            raise NotSetupValue(
                f"setup() got data_files entry {number} that is not (destination, [files])"
            ) from None
        if isinstance(files, (str, bytes)) or not isinstance(files, Iterable):
            raise NotSetupValue(
                f"data_files entry {number}: its files are {type(files).__name__}, not a list"
            )
        out.append(
            [
                _text(destination, f"the destination of data_files entry {number}"),
                [_text(f, f"a file of data_files entry {number}") for f in files],
            ]
        )
    return out


def _names(value: object, what: str) -> list[str] | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise NotSetupValue(f"setup() got {what} that are {type(value).__name__}, not a list")
    return [_text(v, f"an entry of {what}") for v in value]


def _mapping_of_lists(value: object, what: str) -> dict[str, list[str]] | None:
    if not isinstance(value, Mapping):
        return None
    out: dict[str, list[str]] = {}
    for key, items in value.items():
        if isinstance(items, str):
            items = [items]
        out[str(key)] = _names(items, what) or []
    return out


def _mapping_of_text(value: object) -> dict[str, str] | None:
    if not isinstance(value, Mapping):
        return None
    return {str(k): os.fspath(v) for k, v in value.items() if isinstance(v, (str, os.PathLike))}


def _entry_points(value: object) -> dict[str, list[str]] | None:
    """entry_points as setuptools takes them: {group: [lines] or text}, or one INI text."""
    if isinstance(value, str):
        groups: dict[str, list[str]] = {}
        group = None
        for line in (raw.strip() for raw in value.splitlines()):
            if line.startswith("[") and line.endswith("]"):
                group = line[1:-1].strip()
                groups.setdefault(group, [])
            elif line and not line.startswith(("#", ";")) and group is not None:
                groups[group].append(line)
        return groups
    if not isinstance(value, Mapping):
        return None
    out: dict[str, list[str]] = {}
    for key, lines in value.items():
        if isinstance(lines, str):
            lines = [line.strip() for line in lines.splitlines() if line.strip()]
        if isinstance(lines, Iterable):
            out[str(key)] = [str(line) for line in lines]
    return out


# --- in the parent: what it means for the package ----------------------------------------------


def needs_evaluation(model: PackageModel) -> bool:
    """Whether the static reader left part of setup.py unread: only those run (the literal ones,
    most packages, keep the fast path)."""
    setup_py = model.setup_py
    return (
        setup_py is not None
        and setup_py.syntax_error is None
        and setup_py.has_setup_call
        and setup_py.evaluation_error is None  # (run once: a failure stays the answer)
        and bool(setup_py.unknown or setup_py.partial)
    )


def apply_setup_reply(model: PackageModel, reply: Mapping[str, Any]) -> None:
    """The evaluated values as the package's setup.py model and install layout; on a failure the
    static model stays, with the failure (install-rule-unevaluated says it at its line)."""
    from pkgforge.model.layout import layout_from_setup_py
    from pkgforge.model.setup_py import evaluated_model

    setup_py = model.setup_py
    if setup_py is None:
        return
    if reply.get("status") == "ok" and isinstance(reply.get("values"), dict):
        try:
            model.setup_py = evaluated_model(setup_py, reply["values"], model.path)
        except (TypeError, ValueError, AttributeError) as shape:  # a reply of another shape
            setup_py.evaluation_error = (None, f"{type(shape).__name__}: {shape}")
            return
        model.layout = layout_from_setup_py(model.setup_py, model.path)
        return
    error = reply.get("error") or {}
    line = error.get("line") if isinstance(error.get("line"), int) else None
    kind, message = str(error.get("type") or ""), str(error.get("message") or "")
    if error.get("limit") or reply.get("status") in ("timeout", "crashed") or message.startswith(kind):
        why = message or kind or "no result"  # (the limit's own words; a crash's cause)
    else:
        why = f"{kind}: {message}" if message else kind
    setup_py.evaluation_error = (line, why)
    if error.get("limit") or reply.get("status") in ("timeout", "crashed"):
        setup_py.evaluation_unstable = True


def evaluation_request(model: PackageModel) -> str:
    """The setup.py a SetupRequest names."""
    return str(Path(model.path) / SCRIPT)
