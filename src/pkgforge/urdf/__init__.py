"""Robot models: which to process, the one xacro runner, URDF structure, mesh files and physical numbers."""
