"""What a launch evaluation produces: one typed record format for both engines.

The worker (built-in engine or the real ROS launch libraries) fills a Recorder
with these records, serialises them with `as_dict`, and the parent
rebuilds them with `from_dict`; the checks read typed attributes. A key that
no record has raises at once (in the worker and in the parent): a renamed key
fails loudly instead of being read as missing.
"""

from __future__ import annotations

import dataclasses
import json
import os
import typing
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypedDict, TypeVar, cast, overload

from pkgforge.sandbox.protocol import LaunchRequest, LimitKind

if TYPE_CHECKING:
    from pkgforge.urdf.structure import RobotStructure

Status = Literal["ok", "load-error", "timeout", "crashed"]
Engine = Literal["builtin", "ros"]
NodeKind = Literal["node", "process"]
ParameterForm = Literal["plain", "typed", "typed-str", "command-untyped", "file"]
ErrorStage = Literal["load", "visit", "worker", "sandbox"]  # sandbox: the worker's guard (sandbox/worker.py)
RecordKind = Literal[
    "nodes",
    "packages",
    "paths",
    "includes",
    "commands",
    "conditions",
    "unsupported",
    "required",
    "errors",
    "executions",
]
Branch = dict[str, "str | None"]  # argument name -> value of one evaluation (None: declared without default)


# --- the JSON shape of the records, as they cross from the worker to the parent --------------
# One TypedDict per record class, key for key its fields (tests/test_launch_records.py holds
# them together). `total=False`: a key left out takes the record's default (from_dict), which is
# how the engines write them (`RECORDER.add("required", {"name": ...})`); `as_dict` writes every key.


class RecordDict(TypedDict, total=False):
    file: str | None
    line: int | None
    branch: Branch
    branches: list[str]


class ArgumentRecordDict(RecordDict, total=False):
    name: str
    default: str | None
    choices: list[str] | None
    boolean: bool
    values: list[str]


class ParameterRecordDict(RecordDict, total=False):
    name: str | None
    form: ParameterForm
    value_preview: str


class NodeRecordDict(RecordDict, total=False):
    kind: NodeKind
    package: str | None
    executable: str | None
    name: str | None
    namespace: str | None
    parameters: list[ParameterRecordDict]
    remappings: list[list[str]]
    arguments: list[str]
    ros_arguments: list[str]
    cmd: list[str] | None
    shell: bool


class PackageLookupRecordDict(RecordDict, total=False):
    name: str
    via: str
    found: bool | None


class ResolvedPathRecordDict(RecordDict, total=False):
    path: str
    via: str
    exists: bool


class IncludeRecordDict(RecordDict, total=False):
    path: str
    arguments: dict[str, str]
    exists: bool


class CommandRunRecordDict(RecordDict, total=False):
    command: list[str]
    text: str
    ok: bool
    message: str
    model: str | None
    mappings: dict[str, str]
    runtime_only: bool
    via: str | None
    robot: RobotStructure | None  # urdf/robot.py's model structure (its JSON, read by the checks)
    includes: list[str]
    stderr: str


class ConditionRecordDict(RecordDict, total=False):
    condition: str
    entity: str
    taken: bool


class UnsupportedRecordDict(RecordDict, total=False):
    name: str


class RequiredRecordDict(RecordDict, total=False):
    name: str
    skipped: str | None


class ErrorRecordDict(RecordDict, total=False):
    stage: ErrorStage
    type: str
    message: str
    entity: str | None
    package: str | None
    module: str | None
    program: str | None
    variable: str | None
    read_from: str | None
    read_before: str | None
    event_values: bool
    configuration: str | None
    deferred: str | None
    scoped_away: bool
    unevaluated_include: str | None
    limit: LimitKind | None


class ExecutionRecordDict(RecordDict, total=False):
    action: str
    cmd: list[str]
    name: str | None
    cwd: str | None
    env: list[list[str]] | None
    additional_env: list[list[str]]
    output: str | None
    respawn: bool
    failure: str | None


class StoppedBranchDict(TypedDict):
    """Where the branch the deadline stopped was running (`Branching.stopped`)."""

    branch: str
    file: str | None
    line: int | None


class BranchingDict(TypedDict):
    planned: int
    evaluated: int
    stopped: StoppedBranchDict | None
    limit: float | None


class RecordsDict(TypedDict, total=False):
    """Everything one evaluation recorded (`Recorder.dump`)."""

    arguments: list[ArgumentRecordDict]
    nodes: list[NodeRecordDict]
    packages: list[PackageLookupRecordDict]
    paths: list[ResolvedPathRecordDict]
    includes: list[IncludeRecordDict]
    commands: list[CommandRunRecordDict]
    conditions: list[ConditionRecordDict]
    unsupported: list[UnsupportedRecordDict]
    required: list[RequiredRecordDict]
    errors: list[ErrorRecordDict]
    executions: list[ExecutionRecordDict]


class _StatusDict(TypedDict):
    status: Status  # the one key every reply has


class LaunchResultDict(RecordsDict, _StatusDict, total=False):
    """One launch file's reply, worker to parent (one JSON line; resolve.py's own when the worker
    timed out or crashed): `resolution_from_reply` turns it into a Resolution."""

    error: ErrorRecordDict | None  # why it did not load (status != ok)
    files: list[str]  # every launch file evaluated (includes too)
    engine: Engine
    distro: str | None
    branching: BranchingDict
    request: LaunchRequest  # the worker's echo of the request it answered
    token: str  # the request's token (sandbox/protocol.Envelope): the parent checks and drops it


@dataclass
class Record:
    """Where a construct stands (file, line) and under which argument values it was seen."""

    file: str | None = None
    line: int | None = None
    branch: Branch = field(default_factory=dict)  # the worker's: one evaluation's values
    branches: list[str] = field(default_factory=list)  # the parent's: every evaluation that saw it


@dataclass
class Argument(Record):
    name: str = ""
    default: str | None = None
    choices: list[str] | None = None
    boolean: bool = False
    values: list[str] = field(default_factory=list)  # the values evaluated (choices, true/false)


# what a record keeps of a parameter's value (Parameter.value_preview)
PREVIEW_LENGTH = 200


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
    # ros_arguments=, launch_ros's own `--ros-args` part of the command line (ros_args= in XML)
    ros_arguments: list[str] = field(default_factory=list)
    cmd: list[str] | None = None  # a plain process (ExecuteProcess)
    shell: bool = False  # ExecuteProcess(shell=True): a shell splits its joined cmd into words


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
    stage: ErrorStage = "visit"
    type: str = ""
    message: str = ""
    entity: str | None = None
    package: str | None = None  # PackageNotFoundError: which package
    module: str | None = None  # ModuleNotFoundError: which module
    # a program the file runs by name (subprocess's FileNotFoundError) or finds on PATH
    # (FindExecutable's SubstitutionFailure) that this machine lacks
    program: str | None = None
    variable: str | None = None  # EnvironmentVariable's SubstitutionFailure: the variable not set
    # a declared package not installed here whose (empty) share folder the loading file read:
    # what failed after is that read's consequence (on the user's machine the files are there)
    read_from: str | None = None
    # an action's failure after loading read such a package's files (not the action itself):
    # maybe a consequence of that read, maybe the action's own defect
    read_before: str | None = None
    # an event handler's action failed on what only the run gives the event (event.cmd,
    # event.action.process_details): the stand-in event's empty values, not the file's defect
    event_values: bool = False
    # a LaunchConfiguration with no default that nothing declared or set when it was performed
    # (launch's SubstitutionFailure "launch configuration 'x' does not exist"): its name; the
    # record stands at the substitution's line (builtin.launch.errors.missing_configuration)
    configuration: str | None = None
    # what the failing action ran after, as launch runs it once the description is done: the
    # TimerAction or the event handler (OnProcessExit...) it is in, else None
    deferred: str | None = None
    # the configuration existed where that timer or handler stands, and a scoped GroupAction
    # (or an include in one) took it away before it ran (ros2/launch#825)
    scoped_away: bool = False
    # a launch file included before the failing action that could not be evaluated here (its
    # package not installed, or it failed): it may declare the configuration, as launch lets an
    # included file's declarations stand after the include; None: none
    unevaluated_include: str | None = None
    limit: LimitKind | None = None  # a worker limit hit (never cached)


@dataclass
class Execution(Record):
    """What executing an action performs before it would start its process (launch's
    ExecuteLocal.prepare and launch_ros's Node._perform_substitutions): what the process would
    be given, or the failure that stops the launch there. One per action that executes."""

    action: str = ""  # ExecuteProcess, Node, LifecycleNode, ComposableNodeContainer
    # the command: the launch-prefix's words, then the action's own command (a node's executable,
    # arguments and ros_arguments, with its name's remapping); launch_ros's own additions (the
    # namespace, parameter files in temporary folders, remappings) left out
    cmd: list[str] = field(default_factory=list)
    name: str | None = None  # the process's label (exec_name, name, or the executable's), no counter
    cwd: str | None = None
    env: list[list[str]] | None = None  # env= given: the whole environment; None: the context's
    additional_env: list[list[str]] = field(default_factory=list)
    output: str | None = None  # None: a dict of outputs (not performed)
    respawn: bool = False
    failure: str | None = None  # "Type: message" of what stopped it; None: it would start


KINDS: dict[RecordKind, type[Record]] = {
    "nodes": Node,
    "packages": PackageLookup,
    "paths": ResolvedPath,
    "includes": Include,
    "commands": CommandRun,
    "conditions": Condition,
    "unsupported": Unsupported,
    "required": Required,
    "errors": Error,
    "executions": Execution,
}
ITEM_KINDS: tuple[RecordKind, ...] = tuple(KINDS)


class RecordKeyError(KeyError):
    """A record built from a key no record of that kind has."""


_FIELD_NAMES: dict[type[Record], frozenset[str]] = {}
R = TypeVar("R", bound=Record)


def _field_names(cls: type[Record]) -> frozenset[str]:
    names = _FIELD_NAMES.get(cls)
    if names is None:
        names = _FIELD_NAMES[cls] = frozenset(f.name for f in dataclasses.fields(cls))
    return names


def from_dict(cls: type[R], data: Mapping[str, Any]) -> R:
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


@overload
def as_dict(record: Argument) -> ArgumentRecordDict: ...
@overload
def as_dict(record: Parameter) -> ParameterRecordDict: ...
@overload
def as_dict(record: Node) -> NodeRecordDict: ...
@overload
def as_dict(record: PackageLookup) -> PackageLookupRecordDict: ...
@overload
def as_dict(record: ResolvedPath) -> ResolvedPathRecordDict: ...
@overload
def as_dict(record: Include) -> IncludeRecordDict: ...
@overload
def as_dict(record: CommandRun) -> CommandRunRecordDict: ...
@overload
def as_dict(record: Condition) -> ConditionRecordDict: ...
@overload
def as_dict(record: Unsupported) -> UnsupportedRecordDict: ...
@overload
def as_dict(record: Required) -> RequiredRecordDict: ...
@overload
def as_dict(record: Error) -> ErrorRecordDict: ...
@overload
def as_dict(record: Execution) -> ExecutionRecordDict: ...
@overload
def as_dict(record: Record) -> RecordDict: ...
def as_dict(record: Record) -> RecordDict:
    """The record as plain data, for serialising at once: what dataclasses.asdict gives, but
    sharing the record's values instead of deep-copying them (a CommandRun's robot structure
    is large, and every record is dumped in the worker and identified in the parent)."""
    # the TypedDict of each class lists its fields (tests/test_launch_records.py holds them together)
    return cast(RecordDict, {f.name: _plain(getattr(record, f.name)) for f in dataclasses.fields(record)})


def _plain(value: object) -> object:
    if isinstance(value, Record):
        return as_dict(value)
    if isinstance(value, (list, tuple)) and any(isinstance(v, Record) for v in value):
        return type(value)(_plain(v) for v in value)
    return value


def identity(record: Record) -> str:
    """The record without its branch: equal records from several evaluations merge."""
    data = dict(as_dict(record))
    data.pop("branch"), data.pop("branches")
    return json.dumps(data, sort_keys=True, default=str)


class _Arguments(dict[str, Argument]):
    """name → Argument; a dict given (the built-in engine's) becomes an Argument."""

    def setdefault(self, key: str, default: Argument | ArgumentRecordDict) -> Argument:
        if key not in self:
            self[key] = default
        return self[key]

    def __setitem__(self, key: str, value: Argument | ArgumentRecordDict) -> None:
        super().__setitem__(key, value if isinstance(value, Argument) else from_dict(Argument, value))


@dataclass
class Recorder:
    """What one launch file's evaluation saw; `add(kind, item, obj)` records one item."""

    branch: Mapping[str, str | None] = field(default_factory=dict)
    arguments: _Arguments = field(default_factory=_Arguments)
    nodes: list[Node] = field(default_factory=list)
    packages: list[PackageLookup] = field(default_factory=list)
    paths: list[ResolvedPath] = field(default_factory=list)
    includes: list[Include] = field(default_factory=list)
    commands: list[CommandRun] = field(default_factory=list)
    conditions: list[Condition] = field(default_factory=list)
    unsupported: list[Unsupported] = field(default_factory=list)
    required: list[Required] = field(default_factory=list)
    errors: list[Error] = field(default_factory=list)
    executions: list[Execution] = field(default_factory=list)
    # a Command run once per evaluation: its words -> (ok, output, message, extra record fields)
    command_cache: dict[tuple[str, ...], tuple[bool, str, str, CommandRunRecordDict]] = field(
        default_factory=dict
    )
    # package -> its prefix, or the lookup's error (a file asks ~9 times)
    prefix_cache: dict[str, str | BaseException] = field(default_factory=dict)
    # paths in the empty stand-in of a package not found, or in the phantom share folder of one
    # not installed here, that the file opened or listed (not sent: what a load failure came from)
    stand_in_reads: list[str] = field(default_factory=list)
    load_reads: int = 0  # how many of those loading the file made (they count for every action)
    # the current visit's uses of launch configurations not set (not sent: settled into required
    # or errors records when the visit is done)
    unset_uses: list[UnsetUse] = field(default_factory=list)
    # the current visit's includes not followed (not installed here, or failed): what they
    # would have declared is not known (not sent)
    unfollowed: list[str] = field(default_factory=list)
    # the configurations actions that failed in the current visit would have set (not sent)
    failed_sets: set[str] = field(default_factory=set)

    # one signature per kind: the item's keys are checked against that record's TypedDict
    @overload
    def add(self, kind: Literal["nodes"], item: NodeRecordDict, obj: object = None) -> Node: ...
    @overload
    def add(
        self, kind: Literal["packages"], item: PackageLookupRecordDict, obj: object = None
    ) -> PackageLookup: ...
    @overload
    def add(
        self, kind: Literal["paths"], item: ResolvedPathRecordDict, obj: object = None
    ) -> ResolvedPath: ...
    @overload
    def add(self, kind: Literal["includes"], item: IncludeRecordDict, obj: object = None) -> Include: ...
    @overload
    def add(
        self, kind: Literal["commands"], item: CommandRunRecordDict, obj: object = None
    ) -> CommandRun: ...
    @overload
    def add(
        self, kind: Literal["conditions"], item: ConditionRecordDict, obj: object = None
    ) -> Condition: ...
    @overload
    def add(
        self, kind: Literal["unsupported"], item: UnsupportedRecordDict, obj: object = None
    ) -> Unsupported: ...
    @overload
    def add(self, kind: Literal["required"], item: RequiredRecordDict, obj: object = None) -> Required: ...
    @overload
    def add(self, kind: Literal["errors"], item: ErrorRecordDict, obj: object = None) -> Error: ...
    @overload
    def add(
        self, kind: Literal["executions"], item: ExecutionRecordDict, obj: object = None
    ) -> Execution: ...
    def add(self, kind: RecordKind, item: Mapping[str, Any], obj: object = None) -> Record:
        data = dict(item)
        if obj is not None:
            data.setdefault("file", getattr(obj, "_file", None))
            data.setdefault("line", getattr(obj, "_line", None))
        data.setdefault("branch", dict(self.branch))
        record = from_dict(KINDS[kind], data)
        records: list[Record] = getattr(self, kind)
        records.append(record)
        return record

    def reset(self) -> None:
        """Empty again, in place: the engines and the worker hold this one recorder."""
        fresh = Recorder()
        for f in dataclasses.fields(self):
            setattr(self, f.name, getattr(fresh, f.name))

    def dump(self) -> RecordsDict:
        out: RecordsDict = {}
        self.dump_into(out)
        return out

    def dump_into(self, out: RecordsDict) -> None:
        """Every record as plain data, into `out` (a reply: LaunchResultDict)."""
        out["arguments"] = [as_dict(a) for a in self.arguments.values()]
        out["nodes"] = [as_dict(r) for r in self.nodes]
        out["packages"] = [as_dict(r) for r in self.packages]
        out["paths"] = [as_dict(r) for r in self.paths]
        out["includes"] = [as_dict(r) for r in self.includes]
        out["commands"] = [as_dict(r) for r in self.commands]
        out["conditions"] = [as_dict(r) for r in self.conditions]
        out["unsupported"] = [as_dict(r) for r in self.unsupported]
        out["required"] = [as_dict(r) for r in self.required]
        out["errors"] = [as_dict(r) for r in self.errors]
        out["executions"] = [as_dict(r) for r in self.executions]


@dataclass
class UnsetUse:
    """A LaunchConfiguration with no default performed where no value is set (launch's
    SubstitutionFailure): an error unless the visit declares it as a launch argument without a
    default (verify has no value for it then, and records it as required). Which one is known
    once the visit is done: a declaration may come after the use (deferred.settle_unset_uses)."""

    name: str
    entity: str  # the action that failed
    entity_at: tuple[str | None, int | None]
    at: tuple[str | None, int | None]  # the substitution's place (the entity's when not known)
    deferred: str | None = None  # Error.deferred
    scoped_away: bool = False  # Error.scoped_away
    unevaluated_include: str | None = None  # Error.unevaluated_include
    # an action before it that would have set it failed: a consequence of that failure
    after_failed_set: bool = False


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
    executions: list[Execution] = field(default_factory=list)
    files: list[str] = field(default_factory=list)  # every launch file evaluated (includes too)
    branches: int = 1
    branch_names: list[str] = field(default_factory=list)
    engine: Engine = "builtin"
    distro: str | None = None
    branching: Branching = field(default_factory=lambda: Branching())  # combinations evaluated in time

    def off_default(self, item: Record) -> list[str]:
        """The branches `item` was seen in when the visit with every argument at its default is not
        one of them (a record of other settings only); else [] (seen with the defaults, or no
        branching). The defaults visit's label is made as _merged makes every label."""
        branches = [b for b in item.branches if b]
        varying = sorted((a for a in self.arguments if a.values), key=lambda a: a.name)
        if not branches or not varying or "" in item.branches:  # "": recorded while loading
            return []
        defaults = " ".join(f"{a.name}:={a.default}" for a in varying)
        return [] if defaults in branches else branches

    @property
    def unevaluated(self) -> int:
        """Argument combinations not evaluated because the time limit came first (machine-dependent)."""
        return self.branching.planned - self.branching.evaluated if self.status == "ok" else 0


STATUSES: tuple[Status, ...] = typing.get_args(Status)


def resolution_from_reply(launch: LaunchFile, reply: LaunchResultDict) -> Resolution:
    """The parent's side: the worker's plain data back into records, merged across branches."""
    status = reply.get("status", "crashed")
    if status not in STATUSES:  # JSON: whatever the worker wrote
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
    branching = reply.get("branching")
    if isinstance(branching, dict):
        resolution.branching = Branching(**branching)
    labels: set[str] = set()
    resolution.nodes = _merged(Node, reply.get("nodes", []), labels)
    resolution.packages = _merged(PackageLookup, reply.get("packages", []), labels)
    resolution.paths = _merged(ResolvedPath, reply.get("paths", []), labels)
    resolution.includes = _merged(Include, reply.get("includes", []), labels)
    resolution.commands = _merged(CommandRun, reply.get("commands", []), labels)
    resolution.conditions = _merged(Condition, reply.get("conditions", []), labels)
    resolution.unsupported = _merged(Unsupported, reply.get("unsupported", []), labels)
    resolution.required = _merged(Required, reply.get("required", []), labels)
    resolution.errors = _merged(Error, reply.get("errors", []), labels)
    resolution.executions = _merged(Execution, reply.get("executions", []), labels)
    resolution.branch_names = sorted(b for b in labels if b)
    resolution.branches = max(1, len(resolution.branch_names))
    return resolution


def _merged(cls: type[R], items: Iterable[RecordDict], labels: set[str]) -> list[R]:
    """One kind's records, equal ones from several branches merged (each keeps its branches'
    labels); every label seen is added to `labels`."""
    merged: dict[str, R] = {}
    for data in items:
        record = from_dict(cls, data)
        label = " ".join(f"{k}:={v}" for k, v in sorted(record.branch.items()))
        labels.add(label)
        entry = merged.setdefault(identity(record), record)
        if label not in entry.branches:
            entry.branches.append(label)
    return list(merged.values())


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


@dataclass
class Branching:
    """How many argument combinations a file has (the defaults included) and how many were evaluated;
    where the branch that ran out of time was stopped."""

    planned: int = 1
    evaluated: int = 1
    stopped: StoppedBranchDict | None = None  # the branch stopped at the deadline
    limit: float | None = None  # the time limit (s) the worker had

    def as_reply(self) -> BranchingDict:
        return {
            "planned": self.planned,
            "evaluated": self.evaluated,
            "stopped": None if self.stopped is None else self.stopped.copy(),
            "limit": self.limit,
        }
