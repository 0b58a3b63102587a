"""Importing this module imports every check module, so all checks are registered."""

from pkgforge.checks import build
from pkgforge.checks import files
from pkgforge.checks import install
from pkgforge.checks import launch
from pkgforge.checks import manifest
from pkgforge.checks import migrate
from pkgforge.checks import urdf as model
from pkgforge.checks import nodes
from pkgforge.checks import physics
from pkgforge.checks import rviz
from pkgforge.checks import sandbox
