"""`pkgforge migrate`: a ROS 1 catkin description package converted to ROS 2, then verified."""

from __future__ import annotations

import os
from pathlib import Path

import click

from pkgforge.cli.app import CONTEXT_SETTINGS, fail, finish_with_verify, main
from pkgforge.cli.options import (
    add_root_link_option,
    destination_option,
    distro_option,
    launch_format_option,
    maintainer_options,
)
from pkgforge.errors import PkgforgeError


@main.command(context_settings=CONTEXT_SETTINGS)
@click.argument("path", type=click.Path(path_type=Path))
@destination_option(
    "Folder to create the ROS 2 package in [default: beside PATH, as NAME, or NAME_ros2 "
    "when NAME exists]. Never overwritten."
)
@launch_format_option("Format of the converted launch files.")
@distro_option
@click.option(
    "--gazebo",
    is_flag=True,
    help="Convert Gazebo Classic (gazebo_ros empty_world.launch, spawn_model) to Gazebo with "
    "ros_gz_sim instead of leaving it out.",
)
@click.option(
    "--name",
    default=None,
    help="Name of the ROS 2 package [default: the source's; when that breaks REP 144 (an exporter's "
    "Arm_2_description), the valid name close to it]. Every package://, $(find) follows.",
)
@maintainer_options("For a maintainer without one ")
@add_root_link_option(
    "Add a massless root link above a root link with an inertia, which KDL ignores (PF604); "
    "models are otherwise copied byte for byte."
)
def migrate(
    path: Path,
    destination: Path | None,
    launch_format: str,
    distro: str,
    gazebo: bool,
    name: str | None,
    maintainer_name: str | None,
    maintainer_email: str | None,
    add_root_link: bool,
) -> None:
    """Convert the ROS 1 catkin description package at PATH to a ROS 2 package; then verify it."""
    from pkgforge.migrate.package import migrate as run_migrate
    from pkgforge.scaffold.notes import Notes

    try:
        created, notes, source = run_migrate(
            path,
            destination,
            launch_format=launch_format,
            distro=distro,
            gazebo=gazebo,
            notes_factory=Notes,
            name=name,
            maintainer_name=maintainer_name,
            maintainer_email=maintainer_email,
            add_root_link=add_root_link,
            # the distro given on the command line is recorded in the package (pkgforge.toml)
            record_distro=click.get_current_context().get_parameter_source("distro")
            == click.core.ParameterSource.COMMANDLINE,
        )
    except PkgforgeError as error:
        fail(error)
    click.echo(f"migrated {os.path.relpath(source)} to ROS 2 {distro} in {os.path.relpath(created.path)}/")
    for relative in created.files:
        click.echo(f"  {relative}")
    finish_with_verify(created.path, notes, distro)
