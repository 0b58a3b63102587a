"""The shape of a robot model's structure and of a model's failure, as the model worker sends them.

urdf/robot.py builds these dicts in the worker (they cross the process boundary and the cache as
JSON); robot_models.py keeps them on a ModelResult; the checks, urdf/physics.py and view/ read them.
A TypedDict names every key once, so a renamed key is a type error on both sides, not a check
that silently finds nothing.
"""

from __future__ import annotations

from typing import Literal, TypedDict, final

from pkgforge.sandbox.protocol import ErrorRecord, WorkerRequest

# the worker's: ok | error | needs-arguments | too-large | load-error (a limit hit while parsing);
# the parent's: timeout | crashed (no reply), library (only macros: checked through the models
# that include it)
ModelStatus = Literal[
    "ok", "error", "needs-arguments", "too-large", "load-error", "timeout", "crashed", "library"
]
MeshKind = Literal["visual", "collision", "texture"]


class Origin(TypedDict):
    xyz: list[float]
    rpy: list[float]


class Geometry(TypedDict, total=False):
    """A visual's or collision's shape: `type` always; the others as the shape has them."""

    type: str  # box | cylinder | capsule | sphere | mesh | another tag (unknown shape)
    size: list[float] | None  # box
    radius: float | None  # cylinder, capsule, sphere
    length: float | None  # cylinder, capsule
    uri: str | None  # mesh
    scale: list[float]  # mesh


class Part(TypedDict):
    """One <visual> or <collision> of a link."""

    geometry: Geometry | None
    origin: Origin
    color: list[float] | None
    line: int | None


class Inertial(TypedDict):
    mass: float | None
    inertia: dict[str, float] | None  # ixx, ixy, ixz, iyy, iyz, izz
    origin: Origin
    line: int | None


class LinkDict(TypedDict):
    name: str | None
    file: str  # where a person edits it (the model or a file it includes)
    line: int | None
    inertial: Inertial | None
    visuals: list[Part]
    collisions: list[Part]


class Limit(TypedDict):
    lower: float | None
    upper: float | None
    velocity: float | None
    effort: float | None
    line: int | None


class JointDict(TypedDict):
    name: str | None
    type: str | None
    file: str
    line: int | None
    parent: str | None
    child: str | None
    origin: Origin
    axis: list[float] | None
    limit: Limit | None


class MeshDict(TypedDict):
    """A mesh (or texture) file a model references."""

    uri: str
    link: str | None  # None: a material's texture
    kind: MeshKind
    file: str
    line: int | None


class UrdfProblem(TypedDict):
    """What urdfdom refuses or drops (urdf/urdfdom.py): `effect` model | part | color | mimic."""

    effect: str
    message: str
    file: str
    line: int | None
    link: str | None  # the link whose part it drops (physics leaves that link's inertial alone)
    part: str | None  # inertial | visual | collision


class Ros1Tag(TypedDict):
    """An un-prefixed xacro tag (ROS 1's deprecated <macro>, <property> ...) ROS 2's xacro keeps as
    a plain element."""

    tag: str
    file: str
    line: int | None


class GazeboPlugin(TypedDict):
    """A <plugin> inside a URDF's <gazebo> (a model plugin, or a sensor's)."""

    filename: str
    name: str | None
    parameters: list[str]  # the text of its <parameters> elements (gz_ros2_control's controller YAML)
    file: str
    line: int | None


class ControlJoint(TypedDict):
    """A <joint> (or <gpio>/<sensor>: kind) of a <ros2_control> with its interfaces' names."""

    name: str | None
    kind: str  # joint | sensor | gpio
    command: list[str]
    state: list[str]
    file: str
    line: int | None


class ControlSystem(TypedDict):
    """A <ros2_control> element: its hardware plugin and what it controls."""

    name: str | None
    type: str | None
    plugin: str | None  # <hardware><plugin>'s text
    file: str
    line: int | None
    plugin_file: str
    plugin_line: int | None
    joints: list[ControlJoint]


class RobotStructure(TypedDict):
    root_tag: str | None  # "robot" for a URDF; anything else is the model's defect
    name: str | None
    links: list[LinkDict]
    joints: list[JointDict]
    meshes: list[MeshDict]
    urdfdom: list[UrdfProblem]
    ros1_tags: list[Ros1Tag]  # (set by process_model for the model's files; [] elsewhere)
    # joint name → what in the model moves it within its <limit>: "<ros2_control>" (its hardware
    # and controllers enforce the limits), or the Gazebo plugin that names it
    joint_users: dict[str, str]
    gazebo_plugins: list[GazeboPlugin]
    ros2_control: list[ControlSystem]


class Place(TypedDict):
    file: str
    line: int | None


class ModelError(TypedDict, total=False):
    """Why a model gave no structure: `message` and `line` always, the others as the failure has them."""

    message: str
    file: str
    line: int | None
    stage: Literal["xml", "xacro", "ros1-xacro"]  # ros1-xacro: un-prefixed xacro tags (urdf.ros1_xacro)
    hint: str
    argument: str | None  # needs-arguments: the (first) argument xacro asked for
    arguments: list[str]  # needs-arguments: the xacro:args with an empty default it needs
    declared: Place  # needs-arguments: where the first of them is declared
    type: str  # a worker limit hit inside xacro (MemoryError)
    limit: str  # a worker limit hit: time | cpu | memory | files


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
