"""The messages between pkgforge and its launch worker (sandbox/worker.py): one JSON object per line.

The parent (launch/resolve.py) writes a request per launch file, robot model or setup.py on the worker's
stdin and reads one reply per request from its stdout; the worker's limits come once, as JSON in
PKGFORGE_WORKER_LIMITS. These TypedDicts are that protocol: what json.dumps writes and
json.loads gives back, so the values are plain JSON (lists, str, int, float, None).
"""

from __future__ import annotations

from typing import Literal, TypedDict, final

from pkgforge.urdf.structure import ModelStatus, RobotStructure

# A launch file's reply is launch/records.LaunchResultDict (the records' own JSON shape, defined
# beside the records); a model's is ModelReply below. Both statuses are defined once, where their
# replies are made: launch/records.Status, urdf/structure.ModelStatus.

# the worker limit a breach hit (worker._limit_message): never cached by the parent
LimitKind = Literal["time", "cpu", "memory", "files"]


class WorkerLimits(TypedDict, total=False):
    """PKGFORGE_WORKER_LIMITS: the limits the worker sets on itself before any user code runs."""

    timeout: float | None  # seconds of wall and CPU time per request
    memory: int | None  # bytes of address space; None: no limit
    parent: int  # the parent's pid: the worker dies with it


class Confinement(TypedDict):
    """What confines each process that evaluates a request (sandbox/confinement.py): the
    coordinator's first line to the parent, {"hello": Confinement}, and verify's JSON summary."""

    landlock: int  # the Landlock ABI each process restricts itself with; 0: none (writes not kernel-enforced)
    signals: bool  # Landlock scopes signals and abstract sockets to the process's own tree (ABI 6)
    view: bool  # a user and mount namespace where all but pkgforge's temporary folders is read-only
    pid: bool  # a PID namespace of its own: nothing outside can be seen or signalled; one kill ends all
    network: bool  # no network (a namespace of its own in the view; else Landlock's TCP rights, ABI 4)
    sockets: bool  # no new Unix socket (seccomp): no agent reachable by its socket's path
    guard: bool  # the Python guard (an audit hook) reports refused writes and signals at their line
    why: list[str]  # what the kernel did not allow, and why


@final  # no other keys: `"model" in request` tells the kinds apart
class GuardRecord(TypedDict, total=False):
    """A write or signal the guard (sandbox/guard.py) refused, or an installed file it saw changed:
    a JSON line of its log, then an error of the reply (worker._refusals)."""

    kind: str  # refused | installed
    pid: int  # the process that tried
    operation: str  # "write", "delete", "send signal 15 to" …
    path: str
    file: str | None  # where the launch file (or the start of its child) was running
    line: int | None
    child: bool  # a process the launch file started did it


@final  # no other keys: `"model" in request` tells the kinds apart
class LaunchRequest(TypedDict):
    """Evaluate one installed launch file with these launch arguments."""

    file: str
    arguments: dict[str, str]


@final  # no other keys: `"model" in request` tells the kinds apart
class ModelRequest(TypedDict):
    """Run xacro on one installed robot model with these xacro arguments (mappings)."""

    model: str
    mappings: dict[str, str]


@final  # no other keys: `"setup" in request` tells the kinds apart
class SetupRequest(TypedDict):
    """Run one package's setup.py as colcon reads its metadata (model/setup_eval.py): setuptools'
    own setup(), stopped once its configuration is read, before any command runs."""

    setup: str


WorkerRequest = LaunchRequest | ModelRequest | SetupRequest


class Envelope(TypedDict):
    """A request line to the coordinator: the request, and a token the reply must carry back.
    The token never reaches the process that evaluates the request (the coordinator reads it after
    forking that process), so a line that process forges on any channel cannot carry it."""

    request: WorkerRequest
    token: str


class Hello(TypedDict):
    """The coordinator's first line: what confines the processes it will fork."""

    hello: Confinement


class Declared(TypedDict):
    """Where a xacro:arg is declared."""

    file: str
    line: int | None


class ErrorRecord(TypedDict, total=False):
    """A reply's error (and each entity error of a launch reply: launch/records.Error as_dict)."""

    message: str
    file: str | None
    line: int | None
    stage: str  # xml | xacro | load | visit | worker | sandbox
    type: str  # the exception's class name (TimeLimit, MemoryError, RefusedWrite …)
    limit: LimitKind  # a worker limit hit
    hint: str
    argument: str | None  # needs-arguments: the first xacro:arg the model needs
    arguments: list[str]  # every xacro:arg it needs
    declared: Declared
    # launch/records.Error's other fields, when the record is one
    entity: str | None
    package: str | None
    module: str | None
    branch: dict[str, str]
    branches: list[str]


@final
class ModelReply(TypedDict, total=False):
    """urdf/robot.process_model's answer: the robot's structure, or why there is none."""

    status: ModelStatus
    error: ErrorRecord | None
    errors: list[ErrorRecord]  # what the guard refused while answering (none for models)
    includes: list[str]  # the files the model included (absolute paths)
    robot: RobotStructure  # the structure: links, joints, meshes (urdf/robot._structure)
    request: WorkerRequest  # the request it answers (the coordinator adds it)
    token: str  # the request's token (the coordinator adds it; the parent checks and drops it)


# one data_files entry as setup() got it: [destination, [file, ...]], or a lone file (installed
# into the prefix itself, as distutils' install_data does)
DataFilesItem = list[str | list[str]] | str


class SetupValues(TypedDict, total=False):
    """What setup() was given (after setup.cfg, as setuptools merges it), as plain JSON."""

    name: str | None
    data_files: list[DataFilesItem] | None
    packages: list[str] | None
    py_modules: list[str] | None
    package_data: dict[str, list[str]] | None
    package_dir: dict[str, str] | None
    entry_points: dict[str, list[str]] | None


@final
class SetupReply(TypedDict, total=False):
    """model/setup_eval.run_setup_py's answer: the values setup() got, or where setup.py failed."""

    status: Literal["ok", "error", "load-error", "timeout", "crashed"]
    error: ErrorRecord | None
    errors: list[ErrorRecord]  # (none: what the guard refuses, setup.py's own failure says)
    values: SetupValues
    request: WorkerRequest  # the request it answers (the coordinator adds it)
    token: str  # the request's token (the coordinator adds it; the parent checks and drops it)


# --- the fork server (sandbox/zygote.py): JSON over its Unix socket ---------------------------------


class ForkRequest(TypedDict):
    """Fork a worker with this environment (its stdin and stdout come with it, SCM_RIGHTS)."""

    env: dict[str, str]


@final
class Forked(TypedDict):
    """The worker forked: its pid."""

    pid: int


@final
class Exited(TypedDict):
    """A worker of the server ended: its exit status (negative: the signal)."""

    exit: int
    code: int


ForkReply = Forked | Exited
