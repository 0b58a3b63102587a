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
    {"gazebo", "gazebo_ros", "gazebo_plugins", "gazebo_ros_pkgs", "gazebo_ros_control"}
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
    """A Gazebo Classic ROS plugin (libgazebo_ros_*.so): gone with ROS 1 and Gazebo Classic."""
    return filename.startswith("libgazebo_ros")
