"""Robot models: which to process, the one xacro runner, URDF structure, mesh files and physical numbers."""

# a robot model pkgforge runs xacro on (a plain URDF is processed the same; .urdf.xacro ends in .xacro)
XACRO_MODEL_SUFFIXES = (".urdf", ".xacro")
# a robot model in any format: what a launch file's node argument or a package:// / $(find) reference
# names as a model (SDF is a model too, though pkgforge does not process it)
ANY_MODEL_SUFFIXES = (*XACRO_MODEL_SUFFIXES, ".sdf")
# MoveIt's semantic description: <robot> at its root too, but groups and poses, no links: no URDF
# (c3pzero_moveit_config/config/c3pzero.srdf.xacro)
SEMANTIC_SUFFIXES = (".srdf", ".srdf.xacro")
