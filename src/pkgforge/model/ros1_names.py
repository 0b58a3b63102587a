"""Every ROS 1 → ROS 2 name pkgforge knows, in one place.

Packages (package.xml, launch files), node executables, and RViz 1 display classes. The
checks read it (package-not-in-distro and unknown-package PACKAGES through
distro_data.replacement, rviz-ros1-config RVIZ_CLASSES); `pkgforge migrate` reads all of it. It
lives in model, below both, so that no check imports a command.
"""

from __future__ import annotations

# ROS 1 names, renamed packages and Gazebo Classic → what a ROS 2 package uses instead, and why.
# Consulted by the checks only for a name not released for the target distro.
PACKAGES: dict[str, tuple[str, str]] = {
    # ROS 1 packages with a ROS 2 successor
    "rviz": ("rviz2", "rviz is ROS 1; ROS 2 has rviz2"),
    "roslaunch": ("ros2launch", "roslaunch is ROS 1; ROS 2 launches with ros2launch (launch, launch_ros)"),
    "rospy": ("rclpy", "rospy is ROS 1; ROS 2 has rclpy"),
    "roscpp": ("rclcpp", "roscpp is ROS 1; ROS 2 has rclcpp"),
    "actionlib": ("rclcpp_action", "actionlib is ROS 1; ROS 2 has actions in rclcpp_action/rclpy"),
    "actionlib_msgs": ("action_msgs", "actionlib_msgs is ROS 1; ROS 2 has action_msgs"),
    "catkin": ("ament_cmake", "catkin is ROS 1; ROS 2 builds with ament_cmake"),
    "rosbag": ("rosbag2", "rosbag is ROS 1; ROS 2 has rosbag2"),
    "roslib": ("ament_index_python", "roslib is ROS 1; ROS 2 finds packages with ament_index_python"),
    "rospack": ("ament_index_python", "rospack is ROS 1; ROS 2 finds packages with ament_index_python"),
    "tf": ("tf2_ros", "tf is ROS 1; ROS 2 has tf2_ros"),
    "message_generation": ("rosidl_default_generators", "message_generation is ROS 1"),
    "message_runtime": ("rosidl_default_runtime", "message_runtime is ROS 1"),
    "gazebo_ros_control": ("gz_ros2_control", "gazebo_ros_control is ROS 1 (Gazebo Classic)"),
    "joint_state_controller": ("joint_state_broadcaster", "joint_state_controller is ROS 1"),
    # Gazebo Classic is gone after Humble; Gazebo (gz) replaces it
    "gazebo": ("ros_gz_sim", "Gazebo Classic (gazebo) is not a ROS 2 package; use Gazebo with ros_gz_sim"),
    "gazebo_ros": (
        "ros_gz_sim",
        "Gazebo Classic (gazebo_ros) is released for Humble only; use Gazebo with ros_gz_sim",
    ),
    "gazebo_plugins": ("ros_gz_sim", "Gazebo Classic plugins are released for Humble only"),
    "gazebo_ros_pkgs": ("ros_gz", "Gazebo Classic is released for Humble only; use ros_gz"),
    "gazebo_ros2_control": ("gz_ros2_control", "Gazebo Classic is released for Humble only"),
    "ros_ign_gazebo": ("ros_gz_sim", "ros_ign_* was renamed ros_gz_*"),
    "ros_ign_bridge": ("ros_gz_bridge", "ros_ign_* was renamed ros_gz_*"),
    "ros_ign": ("ros_gz", "ros_ign_* was renamed ros_gz_*"),
    "ign_ros2_control": ("gz_ros2_control", "ign_ros2_control was renamed gz_ros2_control"),
}

# ROS 1 dependencies a migrated description package drops: the build tool and the launcher
# (ament_cmake, launch and launch_ros are declared from what the new files use).
DROPPED_DEPENDENCIES = frozenset({"catkin", "roslaunch", "rospy", "roscpp", "rosbag", "roslib", "rospack"})
# dependencies that stand for Gazebo Classic: ros_gz_sim with --gazebo, else dropped
GAZEBO_DEPENDENCIES = frozenset(
    {
        "gazebo",
        "gazebo_ros",
        "gazebo_plugins",
        "gazebo_ros_pkgs",
        "gazebo_ros_control",
        "hector_gazebo_plugins",
    }
)

# (package, executable) in ROS 1 → in ROS 2, for nodes whose name changed
EXECUTABLES: dict[tuple[str, str], tuple[str, str]] = {
    ("robot_state_publisher", "state_publisher"): ("robot_state_publisher", "robot_state_publisher"),
    ("rviz", "rviz"): ("rviz2", "rviz2"),
    ("tf", "static_transform_publisher"): ("tf2_ros", "static_transform_publisher"),
    # ROS 1 navigation's nodes → Navigation2's (a node's package, not a replacement verify suggests:
    # Navigation2 is released for some distros only)
    ("map_server", "map_server"): ("nav2_map_server", "map_server"),
    ("amcl", "amcl"): ("nav2_amcl", "amcl"),
    ("joint_state_publisher", "joint_state_publisher_gui"): (
        "joint_state_publisher_gui",
        "joint_state_publisher_gui",
    ),
}
# ROS 1 command-line tools started as nodes: ROS 2 has them as `ros2 ...` commands, not nodes
COMMAND_NODES: dict[str, str] = {
    "rostopic": "ros2 topic",
    "rosservice": "ros2 service",
    "rosparam": "ros2 param",
    "rosbag": "ros2 bag",
}
# Gazebo Classic's spawner → Gazebo's (with --gazebo)
GAZEBO_SPAWNER = ("gazebo_ros", "spawn_model")
GZ_SPAWNER = ("ros_gz_sim", "create")
# Gazebo Classic's world launch files (gazebo_ros/launch/*.launch) → ros_gz_sim's
GAZEBO_WORLD_LAUNCH = ("gazebo_ros", ("empty_world.launch",))
GZ_WORLD_LAUNCH = ("ros_gz_sim", "launch/gz_sim.launch.py")
# spawn_model option → ros_gz_sim create option (None: no equivalent, dropped)
SPAWN_OPTIONS: dict[str, str | None] = {
    "-file": "-file",
    "-param": "-topic",
    "-model": "-name",
    "-x": "-x",
    "-y": "-y",
    "-z": "-z",
    "-R": "-R",
    "-P": "-P",
    "-Y": "-Y",
    "-urdf": None,
    "-sdf": None,
    "-unpause": None,
    "-wait": None,
    "-gazebo_namespace": None,
    "-reference_frame": None,
    "-robot_namespace": None,
    "-J": None,
}

# ros_control's controller names → ros2_control's (ros2_controllers), in a spawner's arguments: ROS 1's
# joint_state_controller/JointStateController is ROS 2's joint_state_broadcaster/JointStateBroadcaster,
# and the name ROS 2 configurations give it
CONTROLLER_NAMES: dict[str, str] = {"joint_state_controller": "joint_state_broadcaster"}
CONTROLLER_SPAWNER = ("controller_manager", "spawner")
# ROS 1 spawner option → ROS 2 spawner option (humble and later); None: no equivalent, dropped
SPAWNER_OPTIONS: dict[str, str | None] = {
    "--stopped": "--inactive",
    "--timeout": "--controller-manager-timeout",
    "--namespace": "-n",
    "--shutdown-timeout": None,
    "--wait-for": None,
}
SPAWNER_FLAGS = ("--stopped",)  # options that take no value

# RViz 1 class → RViz 2 class (displays, panels, tools, views): rviz2's own (rviz_common's panel and
# display factories, rviz_default_plugins' plugins_description.xml)
RVIZ_CLASSES: dict[str, str] = {
    **{
        f"rviz/{name}": f"rviz_common/{name}"
        for name in ("Displays", "Selection", "Tool Properties", "Views", "Time", "Help", "Group")
    },
    "rviz/WrenchStamped": "rviz_default_plugins/Wrench",
    **{
        f"rviz/{name}": f"rviz_default_plugins/{name}"
        for name in (
            "Axes",
            "Camera",
            "DepthCloud",
            "Effort",
            "FluidPressure",
            "Grid",
            "GridCells",
            "Illuminance",
            "Image",
            "InteractiveMarkers",
            "LaserScan",
            "Map",
            "Marker",
            "MarkerArray",
            "Odometry",
            "Path",
            "PointCloud",
            "PointCloud2",
            "PointStamped",
            "Polygon",
            "Pose",
            "PoseArray",
            "PoseWithCovariance",
            "Range",
            "RelativeHumidity",
            "RobotModel",
            "TF",
            "Temperature",
            "AccelStamped",
            "TwistStamped",
            "Wrench",
            # tools
            "Interact",
            "MoveCamera",
            "Select",
            "FocusCamera",
            "Measure",
            "SetInitialPose",
            "SetGoal",
            "PublishPoint",
            # views
            "Orbit",
            "XYOrbit",
            "FPS",
            "ThirdPersonFollower",
            "TopDownOrtho",
        )
    },
}


def package(name: str) -> tuple[str, str] | None:
    """(ROS 2 package, why) for a ROS 1 or renamed package, else None."""
    return PACKAGES.get(name)


def executable(package_name: str, executable_name: str) -> tuple[str, str]:
    """The ROS 2 (package, executable) of a ROS 1 node; unchanged when ROS 2 kept the names."""
    if (package_name, executable_name) in EXECUTABLES:
        return EXECUTABLES[(package_name, executable_name)]
    renamed = PACKAGES.get(package_name)
    if renamed and package_name in ("rviz",):
        return renamed[0], renamed[0]
    return package_name, executable_name


def is_gazebo_classic_plugin(filename: str) -> bool:
    """A Gazebo Classic ROS plugin (gazebo_plugins' libgazebo_ros_*.so, hector_gazebo_plugins'
    libhector_gazebo_ros_*.so, as mir_description's IMU): gone with ROS 1 and Gazebo Classic."""
    return filename.startswith(("libgazebo_ros", "libhector_gazebo_ros"))


# ros_control's hardware interfaces (a <transmission>'s <hardwareInterface>, with or without the
# hardware_interface/ prefix) → the ros2_control command interface a Gazebo system exports
HARDWARE_INTERFACES: dict[str, str] = {
    "EffortJointInterface": "effort",
    "PositionJointInterface": "position",
    "VelocityJointInterface": "velocity",
}
# gazebo_ros_control's plugin (ROS 1): ros2_control in Gazebo replaces it (migrate --gazebo)
GAZEBO_ROS_CONTROL = "libgazebo_ros_control.so"
# ros_control's controller types (ROS 1) → ros2_controllers' (ROS 2): (type, the command interface
# it claims or None). A type missing
# here has no ROS 2 equivalent (effort_controllers/JointPositionController: a PID on effort).
# The interface is the joint_trajectory_controller's command_interfaces.
CONTROLLER_TYPES: dict[str, tuple[str, str | None]] = {
    "joint_state_controller/JointStateController": ("joint_state_broadcaster/JointStateBroadcaster", None),
    "position_controllers/JointTrajectoryController": (
        "joint_trajectory_controller/JointTrajectoryController",
        "position",
    ),
    "velocity_controllers/JointTrajectoryController": (
        "joint_trajectory_controller/JointTrajectoryController",
        "velocity",
    ),
    "effort_controllers/JointTrajectoryController": (
        "joint_trajectory_controller/JointTrajectoryController",
        "effort",
    ),
    "position_controllers/JointGroupPositionController": (
        "position_controllers/JointGroupPositionController",
        None,
    ),
    "velocity_controllers/JointGroupVelocityController": (
        "velocity_controllers/JointGroupVelocityController",
        None,
    ),
    "effort_controllers/JointGroupEffortController": ("effort_controllers/JointGroupEffortController", None),
    # a single joint's forwarding controller: ROS 2's group controller with one joint
    "position_controllers/JointPositionController": (
        "position_controllers/JointGroupPositionController",
        None,
    ),
    "velocity_controllers/JointVelocityController": (
        "velocity_controllers/JointGroupVelocityController",
        None,
    ),
    "effort_controllers/JointEffortController": ("effort_controllers/JointGroupEffortController", None),
    "diff_drive_controller/DiffDriveController": ("diff_drive_controller/DiffDriveController", None),
    "position_controllers/GripperActionController": ("position_controllers/GripperActionController", None),
    "effort_controllers/GripperActionController": ("effort_controllers/GripperActionController", None),
}
# ROS 1 diff_drive_controller parameters → ROS 2's (ros2_controllers' diff_drive_controller
# parameter YAML, humble and jazzy); a parameter missing here and not in DIFF_DRIVE_KEPT is left out
DIFF_DRIVE_RENAMED = {"left_wheel": "left_wheel_names", "right_wheel": "right_wheel_names"}
DIFF_DRIVE_KEPT = frozenset(
    {
        "wheel_separation",
        "wheel_radius",
        "wheel_separation_multiplier",
        "left_wheel_radius_multiplier",
        "right_wheel_radius_multiplier",
        "base_frame_id",
        "odom_frame_id",
        "enable_odom_tf",
        "cmd_vel_timeout",
        "publish_rate",
        "pose_covariance_diagonal",
        "twist_covariance_diagonal",
        "open_loop",
        "velocity_rolling_window_size",
        "publish_limited_velocity",
        "linear",
        "angular",
    }
)
# ROS 1 joint_trajectory_controller parameters ROS 2's has under the same name
TRAJECTORY_KEPT = frozenset({"constraints", "gains"})
