"""Importing this module imports every check module, so all checks are registered."""

# imported for their effect: each module registers its checks with the registry
from pkgforge.checks import (  # noqa: F401
    build,
    controllers,
    files,
    install,
    launch,
    launch_depends,
    launch_evaluation,
    launch_load,
    launch_paths,
    manifest,
    migrate,
    nodes,
    physics,
    physics_drop,
    rviz,
    sandbox,
    sdf,
    simulation,
    urdf,
)
