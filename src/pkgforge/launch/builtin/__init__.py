"""The built-in launch engine: pkgforge's own ROS 2 launch API, the one description packages use.

It runs only inside the launch worker subprocess. Objects record where the launch file
constructed them; evaluation visits a LaunchDescription the way `ros2 launch` would
(arguments, conditions, includes, OpaqueFunction) but, instead of starting processes, records
nodes, looked-up packages, resolved paths and commands into a Recorder. Semantics follow
ros2/launch: a list of substitutions concatenates, Command splits with shlex, a missing launch
configuration is an error, conditions accept true/false/1/0 only.

Laid out as the real packages: `launch/` and `launch_ros/` hold one module per concept group
of launch and launch_ros (docs/launch-builtin.md maps them), so a difference the oracle finds
points at one small file. Below them: `place` (where a construct stands in its launch file) and
`distro` (which distro's API this stands for); `unsupported` makes a real name not evaluated.
"""
