"""ROS 2 packages that description and launch files commonly use.

On a machine without ROS, nothing else tells an undeclared real package
(missing-exec-depend) from a typo (unknown-package). A sourced ROS adds every
package of its prefixes; this list covers the usual ones without it.
"""

WELL_KNOWN = frozenset("""
ament_index_python ament_cmake ament_python launch launch_ros launch_xml launch_yaml ros2launch
robot_state_publisher joint_state_publisher joint_state_publisher_gui xacro urdf urdfdom kdl_parser
rviz2 rviz_common rviz_default_plugins rviz_rendering rviz_visual_testing_framework
urdf_tutorial urdf_launch tf2 tf2_ros tf2_tools rclcpp rclpy std_msgs sensor_msgs geometry_msgs nav_msgs
controller_manager ros2_control ros2_controllers joint_state_broadcaster joint_trajectory_controller
diff_drive_controller forward_command_controller gripper_controllers position_controllers
velocity_controllers effort_controllers hardware_interface transmission_interface
gazebo_ros gazebo_ros_pkgs gazebo_plugins gazebo_ros2_control ros_gz ros_gz_sim ros_gz_bridge
ros_gz_image ros_gz_interfaces gz_ros2_control ros_ign_gazebo ros_ign_bridge
nav2_bringup nav2_common nav2_map_server nav2_amcl nav2_lifecycle_manager nav2_rviz_plugins
slam_toolbox robot_localization teleop_twist_keyboard teleop_twist_joy joy twist_mux
moveit moveit_ros_move_group moveit_configs_utils moveit_ros_visualization moveit_servo
moveit_simple_controller_manager moveit_kinematics moveit_planners
image_transport camera_info_manager usb_cam realsense2_camera realsense2_description
velodyne_description robot_upstart topic_tools demo_nodes_cpp demo_nodes_py turtlesim
""".split())
