"""What a launch evaluation produces: one typed record format for both engines.

The worker (built-in engine or the real ROS launch libraries) fills a Recorder
with these records, serialises them with `as_dict`, and the parent
rebuilds them with `from_dict`; the checks read typed attributes. A key that
no record has raises at once (in the worker and in the parent): a renamed key
fails loudly instead of being read as missing.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:
    from pkgforge.urdf.structure import RobotStructure

Status = Literal["ok", "load-error", "timeout", "crashed"]
Engine = Literal["builtin", "ros"]
NodeKind = Literal["node", "process"]
ParameterForm = Literal["plain", "typed", "typed-str", "command-untyped", "file"]


@dataclass
class Record:
    """Where a construct stands (file, line) and under which argument values it was seen."""

    file: str | None = None
    line: int | None = None
    branch: dict[str, str] = field(default_factory=dict)  # the worker's: one evaluation's values
    branches: list[str] = field(default_factory=list)  # the parent's: every evaluation that saw it


@dataclass
class Argument(Record):
    name: str = ""
    default: str | None = None
    choices: list[str] | None = None
    boolean: bool = False
    values: list[str] = field(default_factory=list)  # the values evaluated (choices, true/false)


@dataclass
class Parameter(Record):
    name: str | None = None  # None: a parameter file
    form: ParameterForm = "plain"
    value_preview: str = ""


@dataclass
class Node(Record):
    kind: NodeKind = "node"
    package: str | None = None
    executable: str | None = None
    name: str | None = None
    namespace: str | None = None
    parameters: list[Parameter] = field(default_factory=list)
    remappings: list[list[str]] = field(default_factory=list)
    arguments: list[str] = field(default_factory=list)
    cmd: list[str] | None = None  # a plain process (ExecuteProcess)


@dataclass
class PackageLookup(Record):
    name: str = ""
    via: str = ""
    found: bool | None = None  # None: not asked (the tree decides)


@dataclass
class ResolvedPath(Record):
    path: str = ""
    via: str = ""
    exists: bool = False


@dataclass
class Include(Record):
    path: str = ""
    arguments: dict[str, str] = field(default_factory=dict)
    exists: bool = False


@dataclass
class CommandRun(Record):
    command: list[str] = field(default_factory=list)
    text: str = ""  # the one line Command joined before splitting it (shell-like) into `command`
    ok: bool = True
    message: str = ""
    model: str | None = None  # the xacro input
    mappings: dict[str, str] = field(default_factory=dict)  # xacro name:=value
    runtime_only: bool = False  # a run-time query, not executed at verify time
    via: str | None = None
    robot: RobotStructure | None = None  # the model's structure, from the launch's own xacro run
    includes: list[str] = field(default_factory=list)
    stderr: str = ""  # what the command wrote to stderr (Command's on_stderr rule)


@dataclass
class Condition(Record):
    condition: str = ""  # IfCondition, UnlessCondition, ...
    entity: str = ""  # what it guards
    taken: bool = True


@dataclass
class Unsupported(Record):
    name: str = ""


@dataclass
class Required(Record):
    name: str = ""
    skipped: str | None = None  # the entity skipped for want of it; None: the declaration


@dataclass
class Error(Record):
    stage: str = "visit"  # load | visit | worker
    type: str = ""
    message: str = ""
    entity: str | None = None
    package: str | None = None  # PackageNotFoundError: which package
    module: str | None = None  # ModuleNotFoundError: which module
    limit: str | None = None  # a worker limit hit: time | cpu | memory | files (never cached)


KINDS: dict[str, type[Record]] = {
    "nodes": Node,
    "packages": PackageLookup,
    "paths": ResolvedPath,
    "includes": Include,
    "commands": CommandRun,
    "conditions": Condition,
    "unsupported": Unsupported,
    "required": Required,
    "errors": Error,
}
ITEM_KINDS = tuple(KINDS)


class RecordKeyError(KeyError):
    """A record built from a key no record of that kind has."""


_FIELD_NAMES: dict[type, frozenset[str]] = {}


def _field_names(cls: type) -> frozenset[str]:
    names = _FIELD_NAMES.get(cls)
    if names is None:
        names = _FIELD_NAMES[cls] = frozenset(f.name for f in dataclasses.fields(cls))
    return names


def from_dict(cls: type, data: dict):
    """A record from plain data; an unknown key raises RecordKeyError."""
    names = _field_names(cls)
    unknown = set(data) - names
    if unknown:
        raise RecordKeyError(f"{cls.__name__} has no field {', '.join(sorted(unknown))}")
    values = dict(data)
    if cls is Node and values.get("parameters"):
        values["parameters"] = [
            p if isinstance(p, Parameter) else from_dict(Parameter, p) for p in values["parameters"]
        ]
    return cls(**values)


def as_dict(record) -> dict:
    """The record as plain data, for serialising at once: what dataclasses.asdict gives, but
    sharing the record's values instead of deep-copying them (a CommandRun's robot structure
    is large, and every record is dumped in the worker and identified in the parent)."""
    return {f.name: _plain(getattr(record, f.name)) for f in dataclasses.fields(record)}


def _plain(value):
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return as_dict(value)
    if isinstance(value, (list, tuple)) and any(dataclasses.is_dataclass(v) for v in value):
        return type(value)(_plain(v) for v in value)
    return value


def identity(record: Record) -> str:
    """The record without its branch: equal records from several evaluations merge."""
    data = as_dict(record)
    data.pop("branch"), data.pop("branches")
    return json.dumps(data, sort_keys=True, default=str)


class _Arguments(dict):
    """name → Argument; a dict given (the built-in engine's) becomes an Argument."""

    def setdefault(self, key, default=None):
        if key not in self:
            self[key] = default
        return self[key]

    def __setitem__(self, key, value):
        super().__setitem__(key, value if isinstance(value, Argument) else from_dict(Argument, value))


@dataclass
class Recorder:
    """What one launch file's evaluation saw; `add(kind, item, obj)` records one item."""

    branch: dict = field(default_factory=dict)
    arguments: dict = field(default_factory=_Arguments)
    nodes: list = field(default_factory=list)
    packages: list = field(default_factory=list)
    paths: list = field(default_factory=list)
    includes: list = field(default_factory=list)
    commands: list = field(default_factory=list)
    conditions: list = field(default_factory=list)
    unsupported: list = field(default_factory=list)
    required: list = field(default_factory=list)
    errors: list = field(default_factory=list)
    command_cache: dict = field(default_factory=dict)

    def add(self, kind: str, item: dict, obj=None) -> Record:
        item = dict(item)
        if obj is not None:
            item.setdefault("file", getattr(obj, "_file", None))
            item.setdefault("line", getattr(obj, "_line", None))
        item.setdefault("branch", dict(self.branch))
        record = from_dict(KINDS[kind], item)
        getattr(self, kind).append(record)
        return record

    def dump(self) -> dict:
        out = {"arguments": [as_dict(a) for a in self.arguments.values()]}
        for kind in ITEM_KINDS:
            out[kind] = [as_dict(r) for r in getattr(self, kind)]
        return out


@dataclass(frozen=True)
class LaunchFile:
    package: str
    installed: Path
    source: Path | None


@dataclass
class Resolution:
    """One launch file resolved; records de-duplicated across branches."""

    launch: LaunchFile
    status: Status
    error: Error | None = None
    arguments: list[Argument] = field(default_factory=list)
    nodes: list[Node] = field(default_factory=list)
    packages: list[PackageLookup] = field(default_factory=list)
    paths: list[ResolvedPath] = field(default_factory=list)
    includes: list[Include] = field(default_factory=list)
    commands: list[CommandRun] = field(default_factory=list)
    conditions: list[Condition] = field(default_factory=list)
    unsupported: list[Unsupported] = field(default_factory=list)
    required: list[Required] = field(default_factory=list)
    errors: list[Error] = field(default_factory=list)
    files: list[str] = field(default_factory=list)  # every launch file evaluated (includes too)
    branches: int = 1
    branch_names: list[str] = field(default_factory=list)
    engine: Engine = "builtin"
    distro: str | None = None
    branching: Branching = field(default_factory=lambda: Branching())  # combinations evaluated in time

    @property
    def unevaluated(self) -> int:
        """Argument combinations not evaluated because the time limit came first (machine-dependent)."""
        return self.branching.planned - self.branching.evaluated if self.status == "ok" else 0


STATUSES = ("ok", "load-error", "timeout", "crashed")


def resolution_from_reply(launch: LaunchFile, reply: dict) -> Resolution:
    """The parent's side: the worker's plain data back into records, merged across branches."""
    status = reply.get("status", "crashed")
    if status not in STATUSES:
        raise ValueError(f"unknown launch status {status!r}")
    error = reply.get("error")
    resolution = Resolution(
        launch,
        status,
        from_dict(Error, error) if error else None,
        [from_dict(Argument, a) for a in reply.get("arguments", [])],
        files=list(reply.get("files", [])),
        engine=reply.get("engine", "builtin"),
        distro=reply.get("distro"),
    )
    if isinstance(reply.get("branching"), dict):
        resolution.branching = Branching(**reply["branching"])
    labels = set()
    for kind, cls in KINDS.items():
        merged: dict[str, Record] = {}
        for data in reply.get(kind, []):
            record = from_dict(cls, data)
            label = " ".join(f"{k}:={v}" for k, v in sorted(record.branch.items()))
            labels.add(label)
            entry = merged.setdefault(identity(record), record)
            if label not in entry.branches:
                entry.branches.append(label)
        setattr(resolution, kind, list(merged.values()))
    resolution.branch_names = sorted(b for b in labels if b)
    resolution.branches = max(1, len(resolution.branch_names))
    return resolution


# --- which commands run at verify time: ONE decision for both engines ----------------------

# programs whose output is a pure function of the files named on their command line
PURE_COMMANDS = ("xacro", "cat")


def runs_at_verify_time(words: list[str]) -> bool:
    """Whether a `Command` is a pure function of files, so verify runs it (issue 10, item 4):
    xacro, and `cat` of regular files (a device, a fifo or a folder is not a file's content).
    Any other command (`ros2 param get`, a script) is run-time only: recorded, never run.
    Both engines' `Command.perform` decide through this function alone."""
    if not words or os.path.basename(words[0]) not in PURE_COMMANDS:
        return False
    if os.path.basename(words[0]) == "cat":
        operands = [w for w in words[1:] if not w.startswith("-") or w == "-"]
        # a file that does not exist is cat's own failure, as in ROS; stdin and devices are not files
        return bool(operands) and all(
            w != "-" and (not os.path.exists(w) or os.path.isfile(w)) for w in operands
        )
    return True


MAX_BRANCHES = 16


@dataclass
class BranchBudget:
    """How long a request's extra branches may run (the worker's, per request). The defaults are
    evaluated under the full time limit; a file whose defaults finish is never an error because
    its other argument combinations did not fit: they run only until `deadline` (time.monotonic),
    `limit(seconds)` brings the wall-time alarm forward to it, and a branch the alarm (or the CPU
    limit) stops, raising one of `stops`, is dropped whole and counted as not evaluated."""

    deadline: float
    stops: tuple  # the exceptions the worker's limits raise in a launch file
    limit: Callable[[float], None]  # the wall-time alarm no later than that many seconds from now
    release: Callable[[], None]  # the limits off again (the parent's own limit bounds the rest)


@dataclass
class Branching:
    """How many argument combinations a file has (the defaults included) and how many were evaluated;
    where the branch that ran out of time was stopped."""

    planned: int = 1
    evaluated: int = 1
    stopped: dict | None = None  # {"file", "line", "branch"}: the branch stopped at the deadline
    limit: float | None = None  # the time limit (s) the worker had

    def as_reply(self) -> dict:
        return dataclasses.asdict(self)


def _mark(recorder) -> tuple:
    return list(recorder.arguments), {kind: len(getattr(recorder, kind)) for kind in ITEM_KINDS}


def _forget(recorder, mark: tuple) -> None:
    """What a stopped branch recorded goes: a half-visited branch is no evaluation."""
    names, lengths = mark
    for name in [n for n in recorder.arguments if n not in names]:
        del recorder.arguments[name]
    for kind, length in lengths.items():
        del getattr(recorder, kind)[length:]


def evaluate_branches(
    recorder, path: str, overrides: dict[str, str], run, budget: BranchBudget | None = None
) -> Branching:
    """Visit once with the defaults, then once per other value of every argument of `path` that has
    choices or a true/false default (at most MAX_BRANCHES), while `budget` lasts. Both engines
    branch through this one function, so their records can only differ in what a visit records,
    never in which visits run. `run(values, label)` performs one visit."""
    run({}, {})
    varying = [
        a
        for a in recorder.arguments.values()
        if a.name not in overrides and a.file == path and (a.choices or a.boolean)
    ]
    if not varying:
        return Branching()
    defaults = {a.name: a.default for a in varying}
    for kind in ITEM_KINDS:
        for item in getattr(recorder, kind):
            if not item.branch:
                item.branch = dict(defaults)
    domains = [a.choices or ["true", "false"] for a in varying]
    for argument, domain in zip(varying, domains, strict=False):
        argument.values = list(domain)
    names = [a.name for a in varying]
    assignments = [
        dict(zip(names, values, strict=False))
        for values in itertools.islice(itertools.product(*domains), MAX_BRANCHES)
    ]
    assignments = [
        a for a in assignments if not all(a[n].lower() == (defaults[n] or "").lower() for n in names)
    ]
    result = Branching(planned=1 + len(assignments))
    if budget is None:
        for assignment in assignments:
            run(assignment, assignment)
        result.evaluated = result.planned
        return result
    current = None
    try:  # the deadline may come between two branches too: then nothing is running, nothing is lost
        try:
            for assignment in assignments:
                left = budget.deadline - time.monotonic()
                if left <= 0:
                    break
                current, mark = assignment, _mark(recorder)
                budget.limit(left)
                run(assignment, assignment)
                current = None
                result.evaluated += 1
        except budget.stops as stop:
            if current is not None:
                _forget(recorder, mark)
                result.stopped = {
                    "branch": " ".join(f"{k}:={v}" for k, v in sorted(current.items())),
                    **_where_stopped(stop),
                }
        finally:
            budget.release()
    except budget.stops:
        budget.release()
    return result


def _where_stopped(error: BaseException) -> dict:
    """The launch file's line a stopped branch was running (the deepest frame in a launch file)."""
    import traceback

    from pkgforge.launch.runtime import _LAUNCH_FILES

    frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename in _LAUNCH_FILES]
    return (
        {"file": frames[-1].filename, "line": frames[-1].lineno} if frames else {"file": None, "line": None}
    )
