"""`pkgforge migrate`: a ROS 1 catkin description package → a ROS 2 ament_cmake package.

model/ros1_names.py holds every ROS 1 → ROS 2 name (packages, executables, RViz classes; the
checks read it too); roslaunch.py reads ROS 1 launch XML (lxml, with lines) into plain actions;
emit.py writes them as a ROS 2 launch file (py, xml, yaml); rviz1.py converts RViz configs;
package.py puts it together.
"""
