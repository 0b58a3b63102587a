"""What `pkgforge migrate` and `pkgforge new --from-urdf` changed or could not convert.

These are reported by the commands themselves (no check function reads a verify context),
each at the file and line of the source it is about, with the same codes every time.
"""

from __future__ import annotations

from pkgforge.checks.registry import register

register(
    "PF801",
    "migrate-dropped",
    "warning",
    area="migrate",
    bad='<!-- launch/display.launch (ROS 1) -->\n<machine name="arm" address="10.0.0.2"/>',
    good="# launch/display.launch.py (ROS 2): no <machine>; run the node on that host instead",
    summary="a ROS 1 launch or RViz construct has no ROS 2 equivalent and was left out",
    explanation="ROS 2 launch has no global parameters, machines or $(eval) in ROS 1's syntax; "
    "RViz 2 has no plugin of that class. The converted file works without it, but "
    "whatever it did is not done.",
    hint="port it by hand if the package needs it (a node parameter, a ROS 2 plugin)",
)(None)

register(
    "PF802",
    "migrate-gazebo-classic",
    "warning",
    area="migrate",
    bad='<!-- launch/gazebo.launch (ROS 1) -->\n<node pkg="gazebo_ros" type="spawn_model" name="spawn"\n      args="-urdf -param robot_description -model arm"/>',
    good='# pkgforge migrate --gazebo\nNode(package="ros_gz_sim", executable="create",\n     arguments=["-topic", "robot_description", "-name", "arm"])',
    summary="Gazebo Classic (ROS 1) is used: left out and reported",
    explanation="Gazebo Classic and its ROS 1 plugins (gazebo_ros, spawn_model, libgazebo_ros_*.so) "
    "do not exist after Humble, and ROS 1's plugins load in no Gazebo of a ROS 2 distro; Gazebo (gz) "
    "with ros_gz_sim replaces them. Without --gazebo the launch actions and the models' plugins are "
    "left out (`new --from-urdf` keeps a model's as written: verify reports them, PF701). With "
    "--gazebo, what has no gz equivalent pkgforge can write is left out and said so: a Classic "
    "plugin (a sensor's: the <sensor> stays), a ros_control controller type ros2_controllers lacks "
    "on the target distro, a transmission's hardware interface no Gazebo system commands, a "
    "controller file of another package.",
    hint="migrate with --gazebo to start Gazebo with ros_gz_sim and spawn with `ros_gz_sim create`; "
    "replace libgazebo_ros_*.so plugins by gz-sim systems (gz_ros2_control)",
)(None)

register(
    "PF803",
    "migrate-renamed",
    "info",
    area="migrate",
    bad='<node pkg="robot_state_publisher" type="state_publisher" name="rsp"/>',
    good='Node(package="robot_state_publisher", executable="robot_state_publisher")',
    summary="a ROS 1 package, executable or RViz class was renamed to its ROS 2 name",
    explanation="ROS 2 renamed some of what a description package uses: state_publisher is "
    "robot_state_publisher, rviz is rviz2, tf is tf2_ros, RViz displays live in "
    "rviz_default_plugins, Gazebo Classic's spawner is ros_gz_sim's create.",
    hint="nothing to do: said so that every change is visible",
)(None)

register(
    "PF804",
    "migrate-dependency-dropped",
    "info",
    area="migrate",
    bad="<!-- package.xml (ROS 1) -->\n<buildtool_depend>catkin</buildtool_depend>",
    good="<!-- package.xml (ROS 2) -->\n<buildtool_depend>ament_cmake</buildtool_depend>",
    summary="a ROS 1-only dependency was not carried over to package.xml",
    explanation="catkin and roslaunch are ROS 1's build tool and launcher: ament_cmake, launch "
    "and launch_ros take their place, declared from what the new files use.",
    hint="nothing to do: said so that every change is visible",
)(None)

register(
    "PF805",
    "migrate-generated",
    "info",
    area="migrate",
    bad='<node pkg="rviz" type="rviz" name="rviz" args="-d $(find arm)/urdf.rviz"/>\n<!-- the package has no urdf.rviz -->',
    good="# rviz/urdf.rviz generated, Fixed Frame = the model's root link",
    summary="a file or name the package needs was made by pkgforge, or a reference rewritten to fit it",
    explanation="A launch file referred to an RViz config the source does not have, or the RViz "
    "Fixed Frame is not a link of the model; the converted package gets a config "
    "that shows the model, with the model's root link as Fixed Frame. A package name that breaks "
    "REP 144 (the assembly's name a CAD exporter took) gets the valid name close to it, and every "
    "package:// and $(find) naming the old one (or an exporter's folder named as a package) is "
    "rewritten, each file with the lines it was rewritten at.",
    hint="open it in RViz 2 and save your own layout over it; give --name to choose the package's name",
)(None)

register(
    "PF806",
    "migrate-changed",
    "info",
    area="migrate",
    bad='<param name="robot_description" textfile="$(find arm)/urdf/arm.urdf"/>',
    good='Node(package="robot_state_publisher", executable="robot_state_publisher",\n     parameters=[{"robot_description": ParameterValue(\n         Command(["xacro ", PathJoinSubstitution([FindPackageShare("arm"), "urdf", "arm.urdf"])]),\n         value_type=str)}])',
    summary="a launch construct or a manifest entry was converted to its ROS 2 form",
    explanation="robot_description becomes a string parameter of robot_state_publisher (never an "
    "argument of joint_state_publisher), the xacro output of the model; $(find) "
    'becomes $(find-pkg-share); use_gui chooses joint_state_publisher_gui; required="true" '
    "becomes on_exit=Shutdown(); files move to folders that are installed. A maintainer without a "
    'name (an exporter\'s <maintainer email="TODO@email.com" />) is filled in from '
    "--maintainer-name/--maintainer-email or git config.",
    hint="nothing to do: said so that every change is visible",
)(None)

register(
    "PF807",
    "migrate-source-defect",
    "warning",
    area="migrate",
    bad='<!-- urdf/arm.urdf -->\n<robot name="arm">\n  ...\n</robot>\n<transmission name="tran1">...</transmission>',
    good='<robot name="arm">\n  ...\n  <transmission name="tran1">...</transmission>\n</robot>',
    summary="a file of the source has a defect ROS 1 tolerated: it is copied as written",
    explanation="ROS 1's URDF parser (TinyXML) read the first element of a file and ignored what "
    "follows it, and a model no launch file used was never read at all. pkgforge copies such a "
    "file byte for byte and reads it as ROS 1 did, so the migration goes on; xacro, which ROS 2 "
    "launch files run on a model, refuses content after the root element.",
    hint="move the content into the root element (or delete it), or fix the file so it is well-formed XML",
)(None)
