"""Physical checks of robot models: masses, inertias, joint limits and axes, mesh units.

They read the numbers robot.py already extracted from the xacro run verify
makes anyway; the only file they open is a mesh (once per file and run, for
its bounds and triangle count). Duplicate names, several roots and links not
connected are urdf-invalid's (PF401).
"""

from __future__ import annotations

import statistics
from collections.abc import Callable, Iterator
from pathlib import Path

from pkgforge.checks.context import CheckContext
from pkgforge.checks.model_positions import model_item_position
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding, Group, Severity
from pkgforge.model.simulation import GAZEBO_HARDWARE
from pkgforge.robot_models import ModelResult
from pkgforge.urdf import physics
from pkgforge.urdf.meshes import resolve_uri
from pkgforge.urdf.structure import Geometry, LinkDict, Part, RobotStructure

MESH_SCALE_RATIO = 100.0  # a mesh this many times bigger (or smaller) than the rest: a unit mistake
COLLISION_TRIANGLES = 20_000  # above this, a collision mesh slows every contact computation
MOVING = ("revolute", "prismatic")
# an inertia this many times that of a solid box of the link's mass filling its collision bounds
# (or that many times smaller): no body of that mass and size has it. Mass kept inside the bounds
# gives at most 3 times the solid box's (all of it in the corners); kg·mm² written as kg·m² is 1e6
INERTIA_RATIO = 100.0
# MuJoCo's mjMINVAL: below it MuJoCo refuses a moving body ("mass and inertia of moving bodies
# must be larger than mjMINVAL"); DART (gz-sim's engine) computes NaN from such a body and aborts
# (gz-physics#851, a mass of 1e-300)
ENGINE_MINIMUM = 1e-15


def _robots(ctx: CheckContext) -> Iterator[tuple[ModelResult, RobotStructure]]:
    for result in ctx.model_results:
        robot = result.robot
        if result.status == "ok" and robot and robot.get("root_tag") == "robot" and robot.get("links"):
            yield result, robot


def _unparsed_inertials(robot: RobotStructure) -> set[str | None]:
    """The links whose <inertial> urdfdom cannot read (urdf-part-dropped names why): no mass or
    inertia of theirs is checked here (one cause, one finding)."""
    return {p.get("link") for p in robot.get("urdfdom", []) if p.get("part") == "inertial"}


def _parts_dropped(robot: RobotStructure) -> set[str | None]:
    """The links urdfdom stops reading partway (urdf-part-dropped): what they collide with is
    not what the file says."""
    return {p.get("link") for p in robot.get("urdfdom", []) if p.get("part")}


def _links_that_move(robot: RobotStructure) -> set[str]:
    """The links a non-fixed joint moves (a massless frame is fine only on a fixed joint)."""
    return {
        child
        for j in robot.get("joints", [])
        if j.get("type") != "fixed" and (child := j.get("child")) is not None
    }


def _carrying_inertia(robot: RobotStructure) -> set[str]:
    """The links with a link below them (through any joints) whose inertia is not all zero: a
    joint moving such a link moves that inertia too, so a point mass there is no singular body."""
    with_inertia: set[str | None] = set()
    for link in robot["links"]:
        inertial = link.get("inertial")
        inertia = inertial.get("inertia") if inertial is not None else None
        if inertia is not None and any(physics.principal_moments(inertia)):
            with_inertia.add(link["name"])
    children: dict[str, list[str]] = {}
    for joint in robot.get("joints", []):
        parent, child = joint.get("parent"), joint.get("child")
        if parent is not None and child is not None:
            children.setdefault(parent, []).append(child)
    carrying: set[str] = set()
    for link in robot["links"]:
        own = link["name"]
        if own is None:
            continue
        seen, todo = set(), list(children.get(own, []))
        while todo:
            name = todo.pop()
            if name in seen:
                continue  # (a loop in a broken model: each link once)
            seen.add(name)
            if name in with_inertia:
                carrying.add(own)
                break
            todo.extend(children.get(name, []))
    return carrying


def _root(robot: RobotStructure) -> str | None:
    children = {joint.get("child") for joint in robot.get("joints", [])}
    return next((link["name"] for link in robot["links"] if link["name"] not in children), None)


@register(
    "PF601",
    "mass-not-positive",
    "error",
    area="physics",
    bad='<inertial><mass value="0"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>',
    good='<inertial><mass value="1.2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>',
    summary="a link's <inertial> has a mass that is zero, negative or not a number",
    explanation="Physics engines divide by the mass: Gazebo refuses the model or the link "
    "accelerates without bound. (Mass 0 with a zero inertia on a link fixed to its "
    "parent is a plain frame and passes.)",
    hint="give the link its real mass in kilograms (> 0), or remove <inertial> from a link "
    "that only carries a frame",
)
def mass_not_positive(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        moving = _links_that_move(robot)
        unparsed = _unparsed_inertials(robot)
        for link in robot["links"]:
            inertial = link.get("inertial")
            if inertial is None or (inertial.get("mass") or 0) > 0 or link["name"] in unparsed:
                continue
            # mass 0 and no inertia on a link fixed to its parent: a frame (tool0, imu) that
            # physics engines merge into the parent; a common and harmless idiom
            frame = inertial.get("mass") == 0 and not any((inertial.get("inertia") or {}).values())
            if not (frame and link["name"] not in moving):
                yield Finding(
                    f"link '{link['name']}' has mass {inertial.get('mass')}",
                    *model_item_position(ctx, result, link, inertial.get("line")),
                    group=Group(
                        "mass",
                        f"{link['name']} ({inertial.get('mass')})",
                        "{count} links have a mass that is zero, negative or not a number: {items}",
                    ),
                )


@register(
    "PF602",
    "inertia-invalid",
    "error",
    area="physics",
    bad='<inertia ixx="0.001" iyy="0.001" izz="0.02" ixy="0" ixz="0" iyz="0"/>  <!-- 0.02 > 0.001 + 0.001 -->',
    good='<inertia ixx="0.0077" iyy="0.0077" izz="0.0004" ixy="0" ixz="0" iyz="0"/>',
    summary="a link's inertia tensor is not positive definite or breaks the triangle inequality",
    explanation="No rigid body has such an inertia: simulators reject it or the link spins and "
    "explodes (every principal moment must be > 0 and each at most the sum of the "
    "other two). An inertia all zero is a point mass: none on a fixed frame, a warning on a "
    "link that moves with an inertia below it (gz-sim takes it), an error where the workspace uses "
    "Gazebo Classic (ODE refuses it).",
    hint="compute the inertia from the link's shape and mass (CAD export, or the box/cylinder formulas)",
)
def inertia_invalid(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        moving = _links_that_move(robot)
        carried = _carrying_inertia(robot)
        unparsed = _unparsed_inertials(robot)
        for link in robot["links"]:
            inertial = link.get("inertial")
            inertia = inertial.get("inertia") if inertial is not None else None
            if inertial is None or inertia is None or not (inertial.get("mass") or 0) > 0:
                continue
            if link["name"] in unparsed:
                continue
            moments = physics.principal_moments(inertia)
            scale = max(abs(m) for m in moments) or 1.0
            tolerance = 1e-9 * scale
            shown = ", ".join(f"{m:.4g}" for m in moments)
            # all zero: a point mass, fine on a frame fixed to its parent (sensor frames, tool0)
            point = not any(moments)
            if point and link["name"] in moving and link["name"] in carried and not ctx.uses_gazebo_classic():
                # gz-sim takes it (MassMatrix3: moments near positive, triangle inequality holds)
                # and the child below carries the joint (gz_ros2_control's ackermann steering
                # knuckles); ODE (Gazebo Classic) refuses a moving body without inertia
                yield Finding(
                    f"link '{link['name']}': a point mass (inertia all zero) on a joint that moves",
                    *model_item_position(ctx, result, link, inertial.get("line")),
                    severity=Severity.WARNING,
                    hint="give it the inertia of its shape; Gazebo Classic (ODE) needs one, gz-sim and "
                    "KDL do not",
                    group=Group(
                        "point",
                        str(link["name"]),
                        "{count} links are point masses (inertia all zero) on joints that move: {items}",
                    ),
                )
            elif moments[0] < -tolerance or moments[0] <= 0 and not point or point and link["name"] in moving:
                yield Finding(
                    f"link '{link['name']}': inertia not positive definite (principal moments {shown})",
                    *model_item_position(ctx, result, link, inertial.get("line")),
                    group=Group(
                        "definite",
                        f"{link['name']} ({shown})",
                        "{count} links have an inertia that is not positive definite (principal "
                        "moments): {items}",
                    ),
                )
            elif moments[2] > moments[0] + moments[1] + tolerance:
                yield Finding(
                    f"link '{link['name']}': principal moments {shown} break the triangle "
                    f"inequality ({moments[2]:.4g} > {moments[0]:.4g} + {moments[1]:.4g})",
                    *model_item_position(ctx, result, link, inertial.get("line")),
                    group=Group(
                        "triangle",
                        f"{link['name']} ({moments[2]:.4g} > {moments[0]:.4g} + {moments[1]:.4g})",
                        "{count} links have principal moments that break the triangle inequality: {items}",
                    ),
                )


@register(
    "PF603",
    "collision-without-inertial",
    "warning",
    area="physics",
    bad='<link name="arm">\n  <collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>\n</link>',
    good='<link name="arm">\n  <collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>\n  <inertial><mass value="1"/><inertia ixx="0.0077" iyy="0.0077" izz="0.0004" ixy="0" ixz="0" iyz="0"/></inertial>\n</link>',
    summary="a link has collision geometry but no <inertial>",
    explanation="Gazebo drops links without inertia (and their collisions with them): the part "
    "the model shows does not collide.",
    hint="add an <inertial> with the link's mass and inertia",
)
def collision_without_inertial(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        root = _root(robot)
        dropped = _parts_dropped(robot)
        for link in robot["links"]:
            if link["name"] in dropped:
                continue
            if link.get("collisions") and link.get("inertial") is None and link["name"] != root:
                yield Finding(
                    f"link '{link['name']}' has {len(link['collisions'])} collision shape(s) and "
                    "no <inertial>",
                    *model_item_position(ctx, result, link),
                    group=Group(
                        "no-inertial",
                        str(link["name"]),
                        "{count} links have collision shapes and no <inertial>: {items}",
                    ),
                )


@register(
    "PF604",
    "root-link-inertia",
    "warning",
    area="physics",
    bad='<link name="base_link">  <!-- the root -->\n  <inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>\n</link>',
    good='<link name="base_footprint"/>\n<joint name="base_joint" type="fixed"><parent link="base_footprint"/><child link="base_link"/></joint>',
    summary="the root link has an <inertial>",
    explanation="KDL cannot give the root link an inertia: robot_state_publisher warns on every "
    "start and the mass is lost to dynamics solvers.",
    hint="add a massless root link (e.g. base_footprint or base) joined to this one by a fixed joint",
)
def root_link_inertia(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        root = _root(robot)
        link = next((each for each in robot["links"] if each["name"] == root), None)
        inertial = link.get("inertial") if link is not None else None
        if link is not None and inertial is not None and robot.get("joints"):
            yield Finding(
                f"root link '{root}' has an inertia, which KDL ignores",
                *model_item_position(ctx, result, link, inertial.get("line")),
            )


@register(
    "PF605",
    "joint-limit-invalid",
    "error",
    area="physics",
    bad='<limit lower="1.57" upper="-1.57" velocity="0" effort="10"/>',
    good='<limit lower="-1.57" upper="1.57" velocity="1.0" effort="10"/>',
    summary="a revolute or prismatic joint's <limit> is missing, reversed (lower > upper), or has "
    "zero or negative velocity or effort",
    explanation="urdfdom refuses a revolute or prismatic joint without <limit>; reversed limits "
    "leave no allowed position (errors). Simulators and ros2_control hold a joint to its velocity "
    "and effort limits: at 0 it cannot move. RViz and the state publishers never read them, MoveIt "
    'reads a zero velocity as no limit, and exporters write 0 by default: velocity="0" or '
    'effort="0" is an error only where something of the workspace enforces it (a <ros2_control> '
    "block or a Gazebo plugin of the model naming the joint, a launch file that feeds the model to "
    "a simulator), a warning that says who would elsewhere. ros2_control's joint limiters clamp the "
    'effort command only: effort="0" is held by a <ros2_control> joint that commands effort or '
    "that Gazebo's hardware simulates, not by a position-controlled arm on real or mock hardware "
    '(ROS-Industrial writes effort="0"). The joints of one model with the same defect are one '
    "diagnostic.",
    hint="give <limit lower=... upper=... velocity=... effort=...> with lower <= upper and "
    "velocity, effort > 0",
)
def joint_limit_invalid(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        simulator = ctx.simulator_feeding(result)
        users = robot.get("joint_users") or {}
        for joint in robot.get("joints", []):
            if joint.get("type") not in MOVING:
                continue
            limit = joint.get("limit")
            where = model_item_position(ctx, result, joint, limit.get("line") if limit else None)
            name = f"{joint['type']} joint '{joint['name']}'"
            if limit is None:
                yield Finding(
                    f"{name} has no <limit>: urdfdom refuses the whole model (robot_state_publisher "
                    "exits at start and RViz shows no robot)",
                    *where,
                    group=Group(
                        "no-limit",
                        str(joint["name"]),
                        "{count} revolute or prismatic joints have no <limit>: urdfdom refuses the whole "
                        "model (robot_state_publisher exits at start, RViz shows no robot): {items}",
                    ),
                )
                continue
            lower, upper = limit.get("lower") or 0.0, limit.get("upper") or 0.0
            if lower > upper:
                yield Finding(
                    f"{name}: lower limit {lower:g} > upper limit {upper:g}",
                    *where,
                    hint="swap lower and upper",
                    group=Group(
                        "reversed",
                        f"{joint['name']} ({lower:g} > {upper:g})",
                        "{count} joints have a lower limit above their upper limit: {items}",
                    ),
                )
            if limit.get("velocity") is None or limit.get("effort") is None:
                continue  # absent or not a number: urdfdom refuses the model (urdf-invalid says so)
            enforcer = users.get(str(joint["name"])) or simulator
            for what, value in (("velocity", limit["velocity"]), ("effort", limit["effort"])):
                if value is not None and not value > 0:  # (NaN too)
                    held = (
                        _effort_enforcer(robot, str(joint["name"]), enforcer, simulator)
                        if what == "effort"
                        else enforcer
                    )
                    yield _limit_zero(what, value, str(joint["name"]), name, held, where)


def _effort_enforcer(
    robot: RobotStructure, joint: str, enforcer: str | None, simulator: str | None
) -> str | None:
    """What holds a joint to its effort limit. A <ros2_control> block does where it commands the
    joint's effort or where Gazebo's hardware simulates it; ros2_control's joint limiters clamp
    the effort command only (a position- or velocity-commanded joint on real or mock hardware
    never reads effort=: abb_ros2's IRB 4600 joints, effort="0" as ROS-Industrial writes it)."""
    if enforcer != "<ros2_control>":
        return enforcer
    for system in robot.get("ros2_control") or []:
        simulated = (system["plugin"] or "") in GAZEBO_HARDWARE.values()
        for control in system["joints"]:
            if control["name"] == joint and (simulated or "effort" in control["command"]):
                return enforcer
    return simulator


def _limit_zero(
    what: str, value: float, joint: str, name: str, enforcer: str | None, where: tuple[Path, int | None]
) -> Finding:
    """velocity="0" (effort="0") on a joint: an error where something of the workspace holds the
    joint to it (it cannot move there), else a warning that says who would. SolidWorks' URDF
    exporter writes velocity="0": urdfdom, robot_state_publisher, joint_state_publisher and RViz
    accept and never read it (mycobot_ros2's 259 joints), and MoveIt reads 0 as no limit (roarm);
    ROS-Industrial arms (KUKA, FANUC) declare effort="0" on purpose, position controlled."""
    written = f'{what}="{value:g}"'
    if enforcer is not None:
        return Finding(
            f"{name}: {written}, and {enforcer} holds the joint to it: the joint cannot move",
            *where,
            hint=f"set {what}= to the joint's real maximum (> 0)",
            group=Group(
                f"{written}|{enforcer}",
                joint,
                f"{{count}} joints have {written}, and {enforcer} holds them to it (they cannot move): {{items}}",
            ),
        )
    readers = (
        "MoveIt reads 0 as no limit and RViz ignores it"
        if what == "velocity"
        else "MoveIt and RViz never read it"
    )
    nobody = f"nothing here enforces it: {readers}"
    return Finding(
        f"{name}: {written} ({nobody}; a simulator or ros2_control would stop the joint)",
        *where,
        severity=Severity.WARNING,
        hint=f"set {what}= to the joint's real maximum (> 0) before a simulator or ros2_control moves it",
        group=Group(
            written,
            joint,
            f"{{count}} joints have {written} ({nobody}; a simulator or ros2_control would stop them): {{items}}",
        ),
    )


@register(
    "PF606",
    "continuous-joint-limits",
    "warning",
    area="physics",
    bad='<joint name="wheel" type="continuous">\n  <limit lower="-3.14" upper="3.14" velocity="5" effort="2"/>\n</joint>',
    good='<joint name="wheel" type="continuous">\n  <limit velocity="5" effort="2"/>\n</joint>',
    summary="a continuous joint has position limits",
    explanation="A continuous joint turns without end: urdfdom ignores its lower/upper, so the "
    "limits the author meant are not applied anywhere.",
    hint="make it a revolute joint to keep the limits, or drop lower/upper",
)
def continuous_joint_limits(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        for joint in robot.get("joints", []):
            limit = joint.get("limit")
            lower, upper = (limit.get("lower"), limit.get("upper")) if limit else (None, None)
            if joint.get("type") == "continuous" and (lower or upper):
                yield Finding(
                    f"continuous joint '{joint['name']}' has lower={lower} upper={upper}, which are ignored",
                    *model_item_position(ctx, result, joint, limit.get("line") if limit else None),
                    group=Group(
                        "continuous",
                        str(joint["name"]),
                        "{count} continuous joints have lower/upper limits, which are ignored: {items}",
                    ),
                )


@register(
    "PF607",
    "joint-axis-zero",
    "error",
    area="physics",
    bad='<axis xyz="0 0 0"/>',
    good='<axis xyz="0 0 1"/>',
    summary="a joint's axis is the zero vector",
    explanation="A zero axis gives the joint no direction of motion: urdfdom refuses it and "
    "the joint cannot move.",
    hint="give <axis xyz=...> a unit vector, e.g. 0 0 1",
)
def joint_axis_zero(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        for joint in robot.get("joints", []):
            axis = joint.get("axis")
            if joint.get("type") not in ("fixed", "floating") and axis is not None and not any(axis):
                yield Finding(
                    f"joint '{joint['name']}' has axis {' '.join(f'{a:g}' for a in axis)}",
                    *model_item_position(ctx, result, joint),
                    group=Group(
                        "axis", str(joint["name"]), "{count} joints have the zero vector as axis: {items}"
                    ),
                )


def _collision_bounds(
    link: LinkDict, resolve: Callable[[str], Path | None]
) -> tuple[float, float, float] | None:
    """The size (x, y, z) of the box around the link's collision shapes in the link's frame,
    None when it has none or one whose size is not known (a mesh not found or not read)."""
    points: list[physics.Vec3] = []
    identity: physics.Pose = (((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0))
    for part in link.get("collisions", []):
        box = physics.local_box(part.get("geometry"), resolve)
        if box is None:
            return None
        pose = physics.compose(identity, part.get("origin") or {"xyz": [0.0] * 3, "rpy": [0.0] * 3})
        points += [physics.apply(pose, corner) for corner in physics.box_corners(box)]
    if not points:
        return None
    x, y, z = (max(p[i] for p in points) - min(p[i] for p in points) for i in range(3))
    return x, y, z


@register(
    "PF610",
    "inertia-implausible",
    "error",
    area="physics",
    bad='<inertial><mass value="1.0"/><inertia ixx="7700" iyy="7700" izz="400" ixy="0" ixz="0" iyz="0"/></inertial>\n'
    '<collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>  <!-- kg·mm² -->',
    good='<inertial><mass value="1.0"/><inertia ixx="0.0077" iyy="0.0077" izz="0.0004" ixy="0" ixz="0" iyz="0"/></inertial>\n'
    '<collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>',
    summary=f"a link's inertia is more than {INERTIA_RATIO:g} times that of a solid box of its mass "
    "filling its collision geometry's bounds (or that many times smaller)",
    explanation="The sum of the principal moments is compared with a solid box's, m(a²+b²+c²)/6, "
    "a, b, c the bounds of the link's collision shapes (meshes with their scale): mass kept inside "
    "those bounds gives at most 3 times it, so a link 100 times above it was computed in other "
    "units, typically kg·mm² written as kg·m² (1e6 times too big: the link barely turns in a "
    "simulator). 100 times below it (a placeholder 1e-6 on a big link) is a warning: simulators "
    "take it, but the link spins up at the least torque and the solver grows unstable.",
    hint="compute the inertia in kg·m² from the link's shape and mass (a CAD export in kg·mm²: divide by 1e6)",
)
def inertia_implausible(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        resolve = _resolver(ctx, result)
        unparsed = _unparsed_inertials(robot)
        rescaled = {uri for uri, _, _, _ in _scale_suspects(robot, resolve)}
        for link in robot["links"]:
            inertial = link.get("inertial")
            inertia = inertial.get("inertia") if inertial is not None else None
            mass = (inertial.get("mass") or 0) if inertial is not None else 0
            if inertial is None or inertia is None or not mass >= ENGINE_MINIMUM or link["name"] in unparsed:
                continue  # (a mass below what engines take: mass-below-engine-minimum's)
            if any((p.get("geometry") or {}).get("uri") in rescaled for p in link.get("collisions", [])):
                continue  # a mesh in the wrong unit: mesh-scale-suspect says so, the bounds are wrong
            moments = physics.principal_moments(inertia)
            size = _collision_bounds(link, resolve)
            if size is None or moments[0] <= 0 or moments[2] > moments[0] + moments[1]:
                continue  # no shape to compare with, or no inertia of a body (inertia-invalid's)
            solid = mass * sum(s * s for s in size) / 6
            if not solid > 0:
                continue
            ratio = sum(moments) / solid
            if 1 / INERTIA_RATIO <= ratio <= INERTIA_RATIO:
                continue
            bounds = " x ".join(f"{s:.3g}" for s in size)
            units = " (kg·mm² written as kg·m²?)" if ratio > 1e4 else ""
            yield Finding(
                f"link '{link['name']}': inertia (moments summing to {sum(moments):.3g} kg·m²) is "
                + (f"{ratio:.3g} times" if ratio > 1 else f"1/{1 / ratio:.3g} of")
                + f" that of a solid {mass:.3g} kg box filling its {bounds} m collision bounds{units}",
                *model_item_position(ctx, result, link, inertial.get("line")),
                severity=None if ratio > 1 else Severity.WARNING,
            )


@register(
    "PF611",
    "mass-below-engine-minimum",
    "error",
    area="physics",
    bad='<inertial><mass value="1e-20"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/></inertial>',
    good='<inertial><mass value="0.01"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/></inertial>',
    summary=f"a link a joint moves has a mass or a principal moment of inertia above 0 but below {ENGINE_MINIMUM:g}",
    explanation="MuJoCo refuses the model ('mass and inertia of moving bodies must be larger than "
    "mjMINVAL', 1e-15); DART, gz-sim's physics engine, computes NaN from such a body and aborts "
    "(gz-physics#851). A link fixed to its parent is merged into it and passes.",
    hint="give the link its real mass and inertia (a few grams and the inertia of its shape "
    "for a light part), or fix it to its parent",
)
def mass_below_engine_minimum(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        moving = _links_that_move(robot)
        unparsed = _unparsed_inertials(robot)
        for link in robot["links"]:
            inertial = link.get("inertial")
            if inertial is None or link["name"] not in moving or link["name"] in unparsed:
                continue
            mass = inertial.get("mass") or 0
            inertia = inertial.get("inertia")
            moments = physics.principal_moments(inertia) if inertia else []
            if not mass > 0 or moments and not moments[0] > 0:
                continue  # mass-not-positive's, inertia-invalid's
            tiny = [
                f"{what} {value:.3g}"
                for what, value in (("mass", mass), *(("principal moment", m) for m in moments[:1]))
                if value < ENGINE_MINIMUM
            ]
            if tiny:
                yield Finding(
                    f"link '{link['name']}' (moved by a joint) has {' and '.join(tiny)}, below the "
                    f"{ENGINE_MINIMUM:g} MuJoCo and DART need",
                    *model_item_position(ctx, result, link, inertial.get("line")),
                )


def _resolver(ctx: CheckContext, result: ModelResult) -> Callable[[str], Path | None]:
    def resolve(uri: str) -> Path | None:
        lookup = resolve_uri(uri, ctx.tree, result.installed) if ctx.tree is not None else None
        return lookup.path if lookup is not None and lookup.status == "found" else None

    return resolve


def _sizes(
    robot: RobotStructure, resolve: Callable[[str], Path | None]
) -> Iterator[tuple[LinkDict, Part, str, float]]:
    """(link, part, kind, extent) for every shape with a size, meshes with their scale applied."""
    for link in robot["links"]:
        for kind, parts in (("visuals", link.get("visuals", [])), ("collisions", link.get("collisions", []))):
            for part in parts:
                box = physics.local_box(part.get("geometry"), resolve)
                if box is not None:
                    low, high = box
                    yield link, part, kind, max(h - lo for lo, h in zip(low, high, strict=False))


def _shape(part: Part) -> str | None:
    """The type of a part's geometry (box, mesh …), None when it has none."""
    geometry = part["geometry"]
    return geometry.get("type") if geometry else None


@register(
    "PF608",
    "mesh-scale-suspect",
    "warning",
    area="physics",
    bad='<mesh filename="package://rob_description/meshes/arm.stl"/>  <!-- exported in mm -->',
    good='<mesh filename="package://rob_description/meshes/arm.stl" scale="0.001 0.001 0.001"/>',
    summary="a mesh is about 1000 times bigger (or smaller) than the rest of the model",
    explanation="A CAD export in millimetres read as metres makes the robot 1000x too big: RViz "
    "shows a giant or nothing, and collisions and inertias are wrong.",
    hint='add scale="0.001 0.001 0.001" to the <mesh>, or export the mesh in metres',
)
def mesh_scale_suspect(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        for uri, link, part, (kind, extent, ratio, typical) in _scale_suspects(robot, _resolver(ctx, result)):
            factor = "0.001" if ratio > 1 else "1000"
            yield Finding(
                f"{uri} ({kind[:-1]} of link '{link['name']}') is {extent:.3g} m across, "
                f"{ratio:.3g} times the model's typical size of {typical:.3g} m: a unit mistake?",
                *model_item_position(ctx, result, link, part.get("line")),
                hint=f'add scale="{factor} {factor} {factor}" to the <mesh>, or export it in metres',
            )


def _scale_suspects(
    robot: RobotStructure, resolve: Callable[[str], Path | None]
) -> Iterator[tuple[str | None, LinkDict, Part, tuple[str, float, float, float]]]:
    """(uri, link, part, (kind, extent, ratio to the typical size, typical size)) of each mesh
    about 1000 times bigger or smaller than the rest of the model, once per (uri, kind)."""
    sizes = [s for s in _sizes(robot, resolve) if s[3] > 0]
    meshes = [s for s in sizes if _shape(s[1]) == "mesh"]
    if not meshes:
        return
    reference = [s[3] for s in sizes if _shape(s[1]) != "mesh"]
    reference += [
        sum(v * v for v in j["origin"]["xyz"]) ** 0.5
        for j in robot.get("joints", [])
        if j.get("origin") and any(j["origin"]["xyz"])
    ]
    if not reference:  # only meshes: compare each with the others
        reference = [s[3] for s in meshes]
    typical = statistics.median(reference)
    seen = set()
    for link, part, kind, extent in meshes:
        geometry = part["geometry"]
        uri = geometry["uri"] if geometry else None
        ratio = extent / typical
        if (uri, kind) in seen or 1 / MESH_SCALE_RATIO <= ratio <= MESH_SCALE_RATIO:
            continue
        seen.add((uri, kind))
        yield uri, link, part, (kind, extent, ratio, typical)


@register(
    "PF609",
    "collision-mesh-heavy",
    "warning",
    area="physics",
    bad='<collision><geometry><mesh filename="package://rob_description/meshes/arm_visual.dae"/></geometry></collision>',
    good='<collision><geometry><mesh filename="package://rob_description/meshes/arm_convex.stl"/></geometry></collision>',
    summary=f"a collision mesh has more than {COLLISION_TRIANGLES} triangles",
    explanation="Collision checking (Gazebo, MoveIt) costs per triangle: a detailed visual mesh "
    "used as collision geometry makes simulation and planning slow.",
    hint="use a simplified or convex mesh (or primitives) as <collision> geometry",
)
def collision_mesh_heavy(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot in _robots(ctx):
        resolve = _resolver(ctx, result)
        seen = set()
        for link in robot["links"]:
            for part in link.get("collisions", []):
                geometry: Geometry = part.get("geometry") or {}
                uri = geometry.get("uri")
                path = resolve(uri) if geometry.get("type") == "mesh" and uri else None
                info = physics.mesh_info(str(path)) if path else None
                if info is not None and info.triangles > COLLISION_TRIANGLES and uri not in seen:
                    seen.add(uri)
                    yield Finding(
                        f"{uri} (collision of link '{link['name']}') has {info.triangles} triangles",
                        *model_item_position(ctx, result, link, part.get("line")),
                        group=Group(
                            "heavy",
                            f"{uri} ({info.triangles})",
                            f"{{count}} collision meshes have more than {COLLISION_TRIANGLES} triangles: {{items}}",
                        ),
                    )
