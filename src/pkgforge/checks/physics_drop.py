"""verify --simulate's drop test, as findings: a model MuJoCo refuses, one that does not come to
rest, collisions that overlap at the zero pose."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from pkgforge.checks.context import CheckContext
from pkgforge.checks.model_positions import model_item_position, model_source_position
from pkgforge.checks.physics import ENGINE_MINIMUM, _robots
from pkgforge.checks.registry import register
from pkgforge.diagnostics import Finding
from pkgforge.robot_models import ModelResult
from pkgforge.simulate import Outcome, Problem
from pkgforge.simulate.drop import ANGULAR_SPEED, LINEAR_SPEED
from pkgforge.urdf import physics
from pkgforge.urdf.structure import RobotStructure


def _drop_tests(ctx: CheckContext) -> Iterator[tuple[ModelResult, RobotStructure, Outcome]]:
    """(model, its structure, its drop test) for each model verify --simulate tested."""
    for result, robot in _robots(ctx):
        outcome = ctx.simulations.get(result.installed)
        if outcome is not None:
            yield result, robot, outcome


def _named_item(robot: RobotStructure, problem: Problem) -> Mapping[str, Any] | None:
    """The joint or link (in that order) a drop test's problem names, None when it names none."""
    for joint in robot.get("joints", []):
        if problem.joint is not None and joint["name"] == problem.joint:
            return joint
    for name in problem.links:
        for link in robot["links"]:
            if link["name"] == name:
                return link
        for joint in robot.get("joints", []):  # (MuJoCo's message may name a joint element)
            if joint["name"] == name:
                return joint
    return None


def _drop_position(
    ctx: CheckContext, result: ModelResult, robot: RobotStructure, problem: Problem
) -> tuple[Path, int | None]:
    item = _named_item(robot, problem)
    if item is None:
        return model_source_position(ctx, result, None, None)
    return model_item_position(ctx, result, item)


def _mass_said(robot: RobotStructure, problem: Problem) -> bool:
    """Whether MuJoCo's refusal names a link whose mass or inertia mass-not-positive,
    inertia-invalid or mass-below-engine-minimum already report (one cause, one finding)."""
    for link in robot["links"]:
        inertial = link.get("inertial")
        if link["name"] not in problem.links or inertial is None:
            continue
        inertia = inertial.get("inertia")
        moments = physics.principal_moments(inertia) if inertia else [0.0]
        if not (inertial.get("mass") or 0) >= ENGINE_MINIMUM or moments[0] < ENGINE_MINIMUM:
            return True
    return False


@register(
    "PF612",
    "simulation-refused",
    "warning",
    area="physics",
    bad='<link name="elbow_frame"/>  <!-- between two revolute joints: no mass, no inertia -->',
    good='<link name="elbow_frame"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>',
    summary="verify --simulate: MuJoCo refuses the model, or the drop test could not run",
    explanation="With --simulate each robot model is loaded with MuJoCo's URDF importer (PyPI "
    "mujoco, the `simulate` extra) in a separate process limited in memory, CPU and time. What "
    "MuJoCo refuses (a link a joint moves without mass or inertia, a mesh it cannot use) is named "
    "at the link or joint its message names. A warning: other simulators accept some of it.",
    hint="give the named link a mass and inertia of its own (or fix it to its parent); for a mesh "
    "MuJoCo cannot read, use an STL or OBJ collision mesh",
)
def simulation_refused(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot, outcome in _drop_tests(ctx):
        if outcome.error is not None:
            yield Finding(
                f"drop test not run: {outcome.error}", *model_source_position(ctx, result, None, None)
            )
        for problem in outcome.problems:
            if problem.kind == "refused" and not _mass_said(robot, problem):
                yield Finding(
                    f"MuJoCo refuses the model: {problem.message}"
                    + (f" (link '{problem.links[0]}')" if problem.links else ""),
                    *_drop_position(ctx, result, robot, problem),
                )


@register(
    "PF613",
    "simulation-unstable",
    "error",
    area="physics",
    bad='<inertial><origin xyz="0.00001 0 0"/><mass value="1"/><inertia ixx="1e-10" iyy="1e-10" izz="1e-10" ixy="0" ixz="0" iyz="0"/></inertial>',
    good='<inertial><origin xyz="0.05 0 0"/><mass value="1"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>',
    summary="verify --simulate: the model falling limp under gravity reaches non-finite state or "
    f"absurd speeds (over {LINEAR_SPEED:g} m/s or {ANGULAR_SPEED:g} rad/s) within 2 s",
    explanation="The drop test (MuJoCo, base fixed, joints limp, gravity on, 2 s at MuJoCo's "
    "default 2 ms step) is what a simulator does with the model before any controller acts: "
    "a link that spins up or a state that turns NaN there explodes in Gazebo too. The cause is "
    "almost always an inertia far too small for the link's mass and centre of mass.",
    hint="give the named link the inertia of its shape and mass (its centre of mass where the material is)",
)
def simulation_unstable(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot, outcome in _drop_tests(ctx):
        for problem in outcome.problems:
            if problem.kind == "unstable":
                named = (
                    f"joint '{problem.joint}'"
                    if problem.joint
                    else f"link '{problem.links[0]}'"
                    if problem.links
                    else "the model"
                )
                yield Finding(
                    f"{named}, falling limp under gravity, {problem.message}",
                    *_drop_position(ctx, result, robot, problem),
                )


@register(
    "PF614",
    "collision-overlap-at-zero",
    "warning",
    area="physics",
    bad='<joint name="elbow" type="revolute"><parent link="arm"/><child link="forearm"/>\n'
    '  <origin xyz="0 0 -0.2"/>  <!-- forearm folded into the base -->',
    good='<joint name="elbow" type="revolute"><parent link="arm"/><child link="forearm"/>\n  <origin xyz="0 0 0.3"/>',
    summary="verify --simulate: collision shapes of links not joined to each other overlap at the zero pose",
    explanation="At the pose every joint at 0 (where simulators spawn the robot), the collision "
    "shapes of two links that no joint joins (MuJoCo ignores parent and child) lie more than 10 mm "
    "inside each other: the simulator pushes them apart at the first step and the robot jumps. "
    "Meshes count as their convex hulls (as MuJoCo's collisions see them; COLLADA as their bounding box).",
    hint="move the collision shapes apart (smaller or split shapes), or disable the pair's "
    "collisions in the simulator",
)
def collision_overlap_at_zero(ctx: CheckContext) -> Iterator[Finding]:
    for result, robot, outcome in _drop_tests(ctx):
        for problem in outcome.problems:
            if problem.kind == "overlap" and len(problem.links) == 2:
                # named at the link further down the tree (the one a joint brings into the other)
                depth = _depths(robot)
                deeper = sorted(problem.links, key=lambda name: -depth.get(name, 0))
                yield Finding(
                    f"collision shapes of links '{deeper[0]}' and '{deeper[1]}' overlap at the zero "
                    f"pose ({problem.message})",
                    *_drop_position(ctx, result, robot, Problem(problem.kind, problem.message, deeper)),
                )


def _depths(robot: RobotStructure) -> dict[str | None, int]:
    """Each link's number of joints from the root."""
    parent = {j.get("child"): j.get("parent") for j in robot.get("joints", [])}
    depths: dict[str | None, int] = {}
    for link in robot["links"]:
        name, steps, seen = link["name"], 0, set()
        while name in parent and name not in seen:  # (a loop in a broken model: stops)
            seen.add(name)
            name, steps = parent[name], steps + 1
        depths[link["name"]] = steps
    return depths
