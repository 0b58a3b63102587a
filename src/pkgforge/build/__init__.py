"""`pkgforge build`: the real colcon + ament_cmake, with or without ROS."""
