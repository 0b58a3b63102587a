"""Checks of RViz configs: installed ones, and those a launch file passes to rviz2 with -d."""

from __future__ import annotations

from collections.abc import Iterator

from pkgforge.checks.context import CheckContext
from pkgforge.checks.files import read_problem_hint
from pkgforge.checks.registry import register
from pkgforge.checks.urdf import link_names, root_link
from pkgforge.diagnostics import Finding
from pkgforge.model.ros1_names import RVIZ_CLASSES
from pkgforge.model.rviz import ROBOT_MODEL

# frames another node (localization, odometry) publishes; fine when no link has the name
EXTERNAL_FRAMES = ("map", "odom", "world", "earth")


@register(
    "PF501",
    "rviz-invalid",
    "error",
    area="rviz",
    bad=("# rviz/display.rviz\nVisualization Manager: [unclosed"),
    good="# rviz/display.rviz: saved again from RViz (File > Save Config As)",
    summary="an RViz config is not YAML, or not an RViz config",
    explanation="rviz2 falls back to an empty default layout: no robot, no TF.",
    hint="save the config again from RViz (File > Save Config As)",
)
def rviz_invalid(ctx: CheckContext) -> Iterator[Finding]:
    for config in ctx.rviz_configs:
        if config.error:
            yield Finding(
                f"{config.path.name}: {config.error}",
                config.path,
                config.error_line,
                hint=read_problem_hint(config.error),
            )


@register(
    "PF502",
    "rviz-no-description",
    "error",
    area="rviz",
    fix="safe",
    bad=(
        "# rviz/display.rviz\n"
        "- Class: rviz_default_plugins/RobotModel\n"
        "  Description Source: Topic\n"
        "  Description Topic:\n"
        '    Value: ""'
    ),
    good=(
        "# rviz/display.rviz\n"
        "- Class: rviz_default_plugins/RobotModel\n"
        "  Description Source: Topic\n"
        "  Description Topic:\n"
        "    Value: /robot_description"
    ),
    summary="a RobotModel display has no description to show",
    explanation="No error anywhere, TF fine, and RViz shows no robot until someone sets "
    "Description Topic by hand (user story 5).",
    hint="set Description Source: Topic and Description Topic: /robot_description",
)
def rviz_no_description(ctx: CheckContext) -> Iterator[Finding]:
    for config in ctx.rviz_configs:
        for display in config.displays:
            if display["class"] != ROBOT_MODEL or not display["enabled"]:
                continue
            if display["source"] == "File":
                file = display["file"] or ""
                if not file or not ctx.file_exists_for_rviz(file):
                    yield Finding(
                        f"RobotModel '{display['name']}' reads Description File '{file}', which does not "
                        "exist",
                        config.path,
                        display["file_line"] or display["line"],
                        fix={"display_line": display["line"]},
                    )
            elif not (display["topic"] or "").strip():
                yield Finding(
                    f"RobotModel '{display['name']}' has no Description Topic: RViz shows no robot",
                    config.path,
                    display["topic_line"] or display["line"],
                    fix={"display_line": display["line"]},
                )


@register(
    "PF503",
    "rviz-fixed-frame-unknown",
    "warning",
    area="rviz",
    fix="unsafe",
    bad=("# rviz/display.rviz (the model's links: base_link, arm)\nGlobal Options:\n  Fixed Frame: map"),
    good=("# rviz/display.rviz\nGlobal Options:\n  Fixed Frame: base_link"),
    summary="the Fixed Frame is not a link of the model the same launch file publishes",
    explanation="RViz shows 'Fixed Frame [x] does not exist' and draws nothing relative to it.",
    hint="set Fixed Frame to a link of the model, e.g. its root link",
)
def rviz_fixed_frame_unknown(ctx: CheckContext) -> Iterator[Finding]:
    for config, launch in ctx.rviz_launches:
        frame = config.fixed_frame
        links = link_names(ctx, launch)
        if not frame or links is None or frame in links:
            continue
        if frame in EXTERNAL_FRAMES:
            continue
        root = root_link(ctx, launch)
        example = root or sorted(links, key=str)[0]
        yield Finding(
            f"Fixed Frame '{frame}' is not a link of the model {launch.installed.name} publishes",
            config.path,
            config.fixed_frame_line,
            hint=f"use a link of the model (its root is {example}); frames such as map, odom or world that "
            "another node publishes are accepted when no link has the name",
            fix={"frame": root} if root else None,
        )


# classes an RViz 1 config message names before "and N more", the robot's own displays first
SHOWN_CLASSES = 4
ROBOT_DISPLAYS = ("rviz/RobotModel", "rviz/TF")


@register(
    "PF504",
    "rviz-ros1-config",
    "error",
    area="rviz",
    fix="unsafe",
    bad=("# rviz/display.rviz\n- Class: rviz/RobotModel\n  Robot Description: robot_description"),
    good=(
        "# rviz/display.rviz\n"
        "- Class: rviz_default_plugins/RobotModel\n"
        "  Description Source: Topic\n"
        "  Description Topic:\n"
        "    Value: /robot_description"
    ),
    summary="an RViz config is in RViz 1's format (rviz/RobotModel, rviz/TF, Robot Description:)",
    explanation="rviz2 knows none of RViz 1's classes: each display, panel, tool and view named "
    "rviz/... shows 'could not be loaded', so a ROS 1 config that rviz2 is started with shows no "
    "robot and no TF. RViz 2's RobotModel reads the model from a topic (Description Topic "
    "/robot_description), not from the robot_description parameter (Robot Description:). "
    "`pkgforge fix --unsafe-fixes` converts the whole file as `pkgforge migrate` does (it rewrites "
    "the file: comments and the window layout are not kept).",
    hint="convert it: `pkgforge fix --unsafe-fixes` (or open it in rviz2, add the displays again "
    "and save it)",
)
def rviz_ros1_config(ctx: CheckContext) -> Iterator[Finding]:
    for config in ctx.rviz_configs:
        if config.error or not config.ros1_classes:
            continue
        names: list[str] = []
        # the robot's own displays first: what the user misses
        classes = sorted(config.ros1_classes, key=lambda item: item[0] not in ROBOT_DISPLAYS)
        for klass, _ in classes:
            renamed = RVIZ_CLASSES.get(klass)
            shown = f"{klass} → {renamed}" if renamed else f"{klass} (no RViz 2 class)"
            if shown not in names:
                names.append(shown)
        more = len(names) - SHOWN_CLASSES
        listed = ", ".join(names[:SHOWN_CLASSES]) + (f" and {more} more" if more > 0 else "")
        robot = next((line for klass, line in classes if klass == "rviz/RobotModel"), None)
        effect = "it shows no robot" if robot else "those fail to load"
        yield Finding(
            f"{config.path.name} is an RViz 1 config: rviz2 loads none of its rviz/ classes "
            f"({listed}); {effect}",
            config.path,
            robot or config.ros1_classes[0][1],
        )
