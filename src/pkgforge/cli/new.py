"""`pkgforge new`: a robot description package written from the templates, or around a CAD export."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, finish_with_verify, main
from pkgforge.cli.options import (
    add_root_link_option,
    destination_option,
    distro_option,
    launch_format_option,
    maintainer_options,
    path_option,
)
from pkgforge.errors import PkgforgeError
from pkgforge.scaffold.kinds import BUILD_TYPES, CI_SYSTEMS

if TYPE_CHECKING:
    from pkgforge.scaffold.notes import Notes


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("name", required=False)
@distro_option
@click.option(
    "--build-type",
    type=click.Choice(BUILD_TYPES),
    default="ament_cmake",
    show_default=True,
    help="Package build type.",
)
@launch_format_option("Format of launch/display.launch.*.")
@destination_option("Folder to create the package in [default: ./src in a workspace root, else .].")
@maintainer_options()
@click.option(
    "--license",
    "license_",
    default="Apache-2.0",
    show_default=True,
    help="License identifier for package.xml.",
)
@click.option("--description", default="", help="package.xml description.")
@click.option(
    "--force",
    count=True,
    help="Write into an existing package folder: add missing generated files; files that "
    "differ from what pkgforge writes are listed and refused unless given twice "
    "(--force --force). Other files stay.",
)
@click.option(
    "--ci",
    type=click.Choice(CI_SYSTEMS),
    multiple=True,
    help="Add a CI workflow that builds and verifies the package on ros:<distro>. Repeatable.",
)
@path_option(
    "--from-urdf",
    "from_urdf",
    kind="file",
    metavar="FILE",
    help="Bring in this .urdf/.urdf.xacro (a CAD export) with every mesh and "
    "texture it names, instead of the example robot; then verify.",
)
@click.option(
    "--mesh-uri",
    type=click.Choice(["package", "find"]),
    default="package",
    show_default=True,
    help="With --from-urdf: rewrite mesh URIs as package://NAME/meshes/... or "
    "file://$(find NAME)/meshes/....",
)
@add_root_link_option(
    "With --from-urdf: add a massless root link above a root link with an inertia, which KDL "
    "ignores (PF604); models are otherwise copied byte for byte."
)
@click.option(
    "--sim",
    type=click.Choice(["gz"]),
    default=None,
    help="Add what Gazebo and ros2_control need for the target distro: worlds/empty.sdf, "
    "launch/sim.launch.py (ros_gz_sim, the clock bridge, the spawners), <ros2_control> with "
    "gz_ros2_control (ign_ros2_control on humble) and config/controllers.yaml.",
)
def new(
    name: str | None,
    distro: str,
    build_type: str,
    launch_format: str,
    destination: Path | None,
    maintainer_name: str | None,
    maintainer_email: str | None,
    license_: str,
    description: str,
    force: int,
    ci: tuple[str, ...],
    from_urdf: Path | None,
    mesh_uri: str,
    add_root_link: bool,
    sim: str | None,
) -> None:
    """Create a robot description package NAME that builds and shows in RViz2 (with --from-urdf,
    NAME defaults to the model's package name, made valid)."""
    from pkgforge.scaffold.package import create_package, default_destination, make_spec

    name_note = None
    if name is None:
        if from_urdf is None:
            raise click.UsageError("Missing argument 'NAME' (it may be left out with --from-urdf only).")
        from pkgforge.scaffold.from_urdf import default_name

        try:
            name, name_note = default_name(from_urdf)
        except PkgforgeError as error:
            fail(error)

    options: dict[str, Any] = dict(  # make_spec's keyword arguments
        name=name,
        distro=distro,
        build_type=build_type,
        launch_format=launch_format,
        maintainer_name=maintainer_name,
        maintainer_email=maintainer_email,
        license=license_,
        description=description,
        ci=tuple(dict.fromkeys(ci)),
        # the distro given on the command line is recorded in the package (pkgforge.toml)
        record_distro=click.get_current_context().get_parameter_source("distro")
        == click.core.ParameterSource.COMMANDLINE,
    )
    if sim is not None:
        if from_urdf is not None:
            fail(
                PkgforgeError(
                    "--sim gz writes the example robot's ros2_control and controllers: not with --from-urdf"
                )
            )
        options["sim"] = sim
    notes: Notes | None = None
    try:
        if from_urdf is not None:
            from pkgforge.scaffold.from_urdf import new_from_urdf

            created, notes, imported = new_from_urdf(
                options,
                from_urdf,
                destination or default_destination(Path.cwd()),
                force=force,
                uri_style=mesh_uri,
                add_root_link=add_root_link,
                name_note=name_note,
            )
            spec = make_spec(**options)
        else:
            spec = make_spec(**options)
            created = create_package(spec, destination or default_destination(Path.cwd()), force=force)
    except PkgforgeError as error:
        fail(error)
    shown = os.path.relpath(created.path)
    click.echo(f"created {spec.build_type} package '{spec.name}' for ROS 2 {spec.distro.name} in {shown}/")
    for relative in created.files:
        mark = (
            " (replaced)"
            if relative in created.overwritten
            else " (unchanged)"
            if relative in created.unchanged
            else ""
        )
        click.echo(f"  {relative}{mark}")
    from pkgforge.workspace import locate

    # the workspace the package landed in: `pkgforge build` run here would look elsewhere
    root = locate(created.path).root
    build = "pkgforge build" if root == Path.cwd().resolve() else f"pkgforge build {os.path.relpath(root)}"
    install = "install" if root == Path.cwd().resolve() else os.path.relpath(root / "install")
    steps = [
        (build, "# colcon build into install/"),
        (f"pkgforge verify {shown}", ""),
        (f"source {install}/setup.bash", "# the built package on this shell's paths (after ROS 2's own)"),
        (f"ros2 launch {spec.name} display.launch.{spec.launch_format}", ""),
    ]
    width = max(len(command) for command, comment in steps if comment) + 2
    click.echo("next:")
    for command, comment in steps:
        click.echo(f"  {command:<{width}}{comment}".rstrip())
    if notes is not None:
        click.echo(
            f"imported {from_urdf} with {imported.meshes} mesh(es); {len(imported.files)} file(s) "
            "in urdf/ and meshes/"
        )
        finish_with_verify(created.path, notes, spec.distro.name)
