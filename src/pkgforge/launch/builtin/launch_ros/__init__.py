"""The built-in engine's `launch_ros`: package lookups, nodes, parameters, composable nodes, ROS actions."""
