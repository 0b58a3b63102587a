"""What CAD exporters write, in their real shapes (facts from their templates, written here):

- SolidWorks (ros/solidworks_urdf_exporter, 1.6): a catkin package named after the assembly,
  format 2, `<author>TODO</author>` and `<maintainer email="TODO@email.com" />`, CRLF line ends,
  one attribute per line (XmlWriter NewLineOnAttributes), meshes/<link>.STL (names may hold spaces),
  config/joint_names_<name>.yaml, urdf/<name>.csv, export.log, launch/display.launch (textfile,
  joint_state_publisher_gui, rviz -d urdf.rviz, which it never writes) and launch/gazebo.launch
  (empty_world, tf_footprint_base, spawn_model -file, rostopic fake_joint_calibration).
- fusion2urdf (syuntoku14): <robot>_description from catkin_create_pkg's templates, urdf/<robot>.xacro
  including materials.xacro, <robot>.trans and <robot>.gazebo through $(find), meshes/*.stl at
  scale 0.001, launch/display.launch (use_gui, rviz required="true"), gazebo.launch (global
  robot_description, spawn_model -param, empty_world paused), controller.launch (global rosparam,
  a spawner in the robot's namespace with joint_state_controller, robot_state_publisher with no
  description), controller.yaml and urdf.rviz in launch/.
- onshape-to-robot: robot.urdf beside assets/, meshes as package://assets/<part>.stl (no package).
"""

from __future__ import annotations

from pathlib import Path

from pkgforge.scaffold.stl import binary_stl, box_triangles

SW_LINKS = ("base_link", "Fing 1", "Thumb")


def _stl(path: Path, size: float = 0.05) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(binary_stl(box_triangles((size, size, size)), header=path.stem))


def _crlf(text: str) -> bytes:
    return text.replace("\n", "\r\n").encode()


def sw_urdf(name: str, package: str, trailing: str = "") -> str:
    """The SolidWorks exporter's URDF: one attribute per line, each mesh named twice."""
    parts = [
        '<?xml version="1.0" encoding="utf-8"?>',
        "<!-- This URDF was automatically created by SolidWorks to URDF Exporter! Originally created by "
        "Stephen Brawner (brawner@gmail.com) ",
        "     Commit Version: 1.6.0-4-g7f85cfe  Build Version: 1.6.7995.38578",
        "     For more information, please see http://wiki.ros.org/sw_urdf_exporter -->",
        "<robot",
        f'  name="{name}">',
    ]
    for link in SW_LINKS:
        parts.append(f"""  <link
    name="{link}">
    <inertial>
      <origin
        xyz="0 0 0.02"
        rpy="0 0 0" />
      <mass
        value="0.2" />
      <inertia
        ixx="0.0001"
        ixy="0"
        ixz="0"
        iyy="0.0001"
        iyz="0"
        izz="0.0001" />
    </inertial>
    <visual>
      <origin
        xyz="0 0 0"
        rpy="0 0 0" />
      <geometry>
        <mesh
          filename="package://{package}/meshes/{link}.STL" />
      </geometry>
      <material
        name="">
        <color
          rgba="0.79 0.82 0.93 1" />
      </material>
    </visual>
    <collision>
      <origin
        xyz="0 0 0"
        rpy="0 0 0" />
      <geometry>
        <mesh
          filename="package://{package}/meshes/{link}.STL" />
      </geometry>
    </collision>
  </link>""")
    for parent, child in zip(SW_LINKS, SW_LINKS[1:], strict=False):
        parts.append(f"""  <joint
    name="{child}"
    type="revolute">
    <origin
      xyz="0 0 0.05"
      rpy="0 0 0" />
    <parent
      link="{parent}" />
    <child
      link="{child}" />
    <axis
      xyz="0 0 1" />
    <limit
      lower="-1"
      upper="1"
      effort="1"
      velocity="1" />
  </joint>""")
    parts.append("</robot>")
    return "\n".join(parts) + trailing + "\n"


TRANSMISSION = """
<transmission name="trans_Thumb">
  <type>transmission_interface/SimpleTransmission</type>
  <joint name="Thumb">
    <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
  </joint>
  <actuator name="Thumb_motor">
    <mechanicalReduction>1</mechanicalReduction>
  </actuator>
</transmission>"""

SW_DISPLAY = """<launch>
  <arg
    name="model" />
  <param
    name="robot_description"
    textfile="$(find {name})/urdf/{name}.urdf" />
  <node
    name="joint_state_publisher_gui"
    pkg="joint_state_publisher_gui"
    type="joint_state_publisher_gui" />
  <node
    name="robot_state_publisher"
    pkg="robot_state_publisher"
    type="robot_state_publisher" />
  <node
    name="rviz"
    pkg="rviz"
    type="rviz"
    args="-d $(find {name})/urdf.rviz" />
</launch>"""

SW_GAZEBO = """<launch>
  <include
    file="$(find gazebo_ros)/launch/empty_world.launch" />
  <node
    name="tf_footprint_base"
    pkg="tf"
    type="static_transform_publisher"
    args="0 0 0 0 0 0 base_link base_footprint 40" />
  <node
    name="spawn_model"
    pkg="gazebo_ros"
    type="spawn_model"
    args="-file $(find {name})/urdf/{name}.urdf -urdf -model {name}"
    output="screen" />
  <node
    name="fake_joint_calibration"
    pkg="rostopic"
    type="rostopic"
    args="pub /calibrated std_msgs/Bool true" />
</launch>"""


def sw_export(folder: Path, name: str = "GripperPrototype", *, meshes_as: str | None = None) -> Path:
    """The SolidWorks exporter's package `name` (the assembly's name). `meshes_as`: the name its URIs
    give the package instead (package://<assembly>-URDF/meshes/... in a package of another name)."""
    package = folder / name
    for sub in ("launch", "urdf", "config", "textures", "meshes"):
        (package / sub).mkdir(parents=True)
    (package / "package.xml").write_text(f"""<package format="2">
  <name>{name}</name>
  <version>1.0.0</version>
  <description>
    <p>URDF Description package for {name}</p>
    <p>This package contains configuration data, 3D models and launch files
for {name} robot</p>
  </description>
  <author>TODO</author>
  <maintainer email="TODO@email.com" />
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <depend>roslaunch</depend>
  <depend>robot_state_publisher</depend>
  <depend>rviz</depend>
  <depend>joint_state_publisher_gui</depend>
  <depend>gazebo</depend>
  <export>
    <architecture_independent />
  </export>
</package>""")
    (package / "CMakeLists.txt").write_bytes(
        _crlf(
            f"cmake_minimum_required(VERSION 2.8.3)\n\nproject({name})\n\nfind_package(catkin REQUIRED)\n\n"
            "catkin_package()\n\nfind_package(roslaunch)\n\nforeach(dir config launch meshes urdf)\n"
            "\tinstall(DIRECTORY ${dir}/\n\t\tDESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/${dir})\n"
            "endforeach(dir)\n"
        )
    )
    (package / "launch/display.launch").write_bytes(_crlf(SW_DISPLAY.format(name=name)))
    (package / "launch/gazebo.launch").write_bytes(_crlf(SW_GAZEBO.format(name=name)))
    (package / f"config/joint_names_{name}.yaml").write_text(
        "controller_joint_names: ['', 'Fing 1', 'Thumb', ]\n"
    )
    uri = meshes_as or name
    (package / f"urdf/{name}.urdf").write_bytes(_crlf(sw_urdf(name, uri)))
    (package / f"urdf/{name}.csv").write_bytes(
        _crlf(f"Link Name,Mesh Filename\nbase_link,package://{uri}/meshes/base_link.STL\n")
    )
    for link in SW_LINKS:
        _stl(package / "meshes" / f"{link}.STL")
    (package / "export.log").write_text("2025-03-25 01:27:16,364 INFO  Logger.cs: 70 - Logging commencing\n")
    return package


FUSION_XACRO = """<?xml version="1.0" ?>
<robot name="{robot}" xmlns:xacro="http://www.ros.org/wiki/xacro">

<xacro:include filename="$(find {package})/urdf/materials.xacro" />
<xacro:include filename="$(find {package})/urdf/{robot}.trans" />
<xacro:include filename="$(find {package})/urdf/{robot}.gazebo" />
<link name="base_link">
  <inertial>
    <origin rpy="0 0 0" xyz="0.04 0.004 -0.03"/>
    <mass value="0.44"/>
    <inertia ixx="0.000128" ixy="2e-06" ixz="-0.0" iyy="0.00046" iyz="0.0" izz="0.000341"/>
  </inertial>
  <visual>
    <origin rpy="0 0 0" xyz="0 0 0"/>
    <geometry>
      <mesh filename="package://{package}/meshes/base_link.stl"
        scale="0.001 0.001 0.001"/>
    </geometry>
    <material name="silver"/>
  </visual>
  <collision>
    <origin rpy="0 0 0" xyz="0 0 0"/>
    <geometry>
      <mesh filename="package://{package}/meshes/base_link.stl"
        scale="0.001 0.001 0.001"/>
    </geometry>
  </collision>
</link>

<link name="arm_1">
  <inertial>
    <origin rpy="0 0 0" xyz="0.005 0.0 -0.0014"/>
    <mass value="0.0155"/>
    <inertia ixx="1e-06" ixy="0.0" ixz="-0.0" iyy="1e-06" iyz="0.0" izz="2e-06"/>
  </inertial>
  <visual>
    <origin rpy="0 0 0" xyz="-0.0 -0.005 0.06"/>
    <geometry>
      <mesh filename="package://{package}/meshes/arm_1.stl" scale="0.001 0.001 0.001"/>
    </geometry>
    <material name="silver"/>
  </visual>
  <collision>
    <origin rpy="0 0 0" xyz="-0.0 -0.005 0.06"/>
    <geometry>
      <mesh filename="package://{package}/meshes/arm_1.stl" scale="0.001 0.001 0.001"/>
    </geometry>
  </collision>
</link>

<joint name="Rev1" type="continuous">
  <origin rpy="0 0 0" xyz="0.0 0.005 -0.06"/>
  <parent link="base_link"/>
  <child link="arm_1"/>
  <axis xyz="-0.0 1.0 0.0"/>
</joint>

</robot>
"""

FUSION_TRANS = """<?xml version="1.0" ?>
<robot name="{robot}" xmlns:xacro="http://www.ros.org/wiki/xacro" >

<transmission name="Rev1_tran">
  <type>transmission_interface/SimpleTransmission</type>
  <joint name="Rev1">
    <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
  </joint>
  <actuator name="Rev1_actr">
    <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
    <mechanicalReduction>1</mechanicalReduction>
  </actuator>
</transmission>

</robot>
"""

FUSION_GAZEBO = """<?xml version="1.0" ?>
<robot name="{robot}" xmlns:xacro="http://www.ros.org/wiki/xacro" >

<xacro:property name="body_color" value="Gazebo/Silver" />

<gazebo>
  <plugin filename="libgazebo_ros_control.so" name="control"/>
</gazebo>
<gazebo reference="base_link">
  <material>${{body_color}}</material>
  <mu1>0.2</mu1>
  <mu2>0.2</mu2>
  <selfCollide>true</selfCollide>
  <gravity>true</gravity>
</gazebo>

</robot>
"""

FUSION_MATERIALS = """<?xml version="1.0" ?>
<robot name="{robot}" xmlns:xacro="http://www.ros.org/wiki/xacro" >

<material name="silver">
  <color rgba="0.700 0.700 0.700 1.000"/>
</material>

</robot>
"""

FUSION_DISPLAY = """<launch>
  <arg default="$(find {package})/urdf/{robot}.xacro" name="model"/>
  <arg default="true" name="gui"/>
  <arg default="$(find {package})/launch/urdf.rviz" name="rvizconfig"/>
  <param command="$(find xacro)/xacro $(arg model)" name="robot_description"/>
  <param name="use_gui" value="$(arg gui)"/>
  <node name="joint_state_publisher" pkg="joint_state_publisher" type="joint_state_publisher"/>
  <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher"/>
  <node args="-d $(arg rvizconfig)" name="rviz" pkg="rviz" required="true" type="rviz"/>
</launch>
"""

FUSION_GAZEBO_LAUNCH = """<launch>
  <param command="$(find xacro)/xacro $(find {package})/urdf/{robot}.xacro" name="robot_description"/>
  <node args="-param robot_description -urdf -model {robot}" name="spawn_urdf" pkg="gazebo_ros" type="spawn_model"/>
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="paused" value="true"/>
    <arg name="use_sim_time" value="true"/>
    <arg name="gui" value="true"/>
    <arg name="headless" value="false"/>
    <arg name="debug" value="false"/>
  </include>
</launch>
"""

FUSION_CONTROLLER = """<launch>

<rosparam file="$(find {package})/launch/controller.yaml" command="load"/>
<node args="Rev1_position_controller joint_state_controller " name="controller_spawner" ns="{robot}" output="screen" pkg="controller_manager" respawn="false" type="spawner"/>
<node name="robot_state_publisher" output="screen" pkg="robot_state_publisher" respawn="false" type="robot_state_publisher">
  <remap from="/joint_states" to="/{robot}/joint_states"/>
</node>

</launch>"""

FUSION_CONTROLLER_YAML = """{robot}_controller:
  # Publish all joint states -----------------------------------
  joint_state_controller:
    type: joint_state_controller/JointStateController
    publish_rate: 50

  # Position Controllers --------------------------------------
  Rev1_position_controller:
    type: effort_controllers/JointPositionController
    joint: Rev1
    pid: {{p: 100.0, i: 0.01, d: 10.0}}
"""

FUSION_RVIZ = """Panels:
  - Class: rviz/Displays
    Name: Displays
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz/Grid
      Enabled: true
      Name: Grid
      Value: true
    - Class: rviz/RobotModel
      Enabled: true
      Name: RobotModel
      Robot Description: robot_description
      Value: true
  Enabled: true
  Global Options:
    Fixed Frame: base_link
  Name: root
"""


def fusion_export(folder: Path, robot: str = "Arm_2") -> Path:
    """fusion2urdf's package <robot>_description."""
    name = f"{robot}_description"
    package = folder / name
    for sub in ("launch", "urdf", "meshes"):
        (package / sub).mkdir(parents=True)
    (package / "package.xml").write_text(f"""<?xml version="1.0"?>
<package format="2">
  <name>{name}</name>
  <version>0.0.0</version>
<description>The {name} package</description>

  <!-- One maintainer tag required, multiple allowed, one person per tag -->
  <!-- Example:  -->
  <!-- <maintainer email="jane.doe@example.com">Jane Doe</maintainer> -->
  <maintainer email="syuntoku14@todo.todo">syuntoku14</maintainer>

  <license>TODO</license>

  <buildtool_depend>catkin</buildtool_depend>
  <build_depend>rospy</build_depend>
  <build_export_depend>rospy</build_export_depend>
  <exec_depend>rospy</exec_depend>

  <export>
  </export>
</package>
""")
    (package / "CMakeLists.txt").write_text(
        f"cmake_minimum_required(VERSION 2.8.3)\nproject({name})\n\n"
        "## Find catkin macros and libraries\nfind_package(catkin REQUIRED COMPONENTS\n  rospy\n)\n\ncatkin_package()\n"
    )
    values = {"robot": robot, "package": name}
    (package / f"urdf/{robot}.xacro").write_text(FUSION_XACRO.format(**values))
    (package / f"urdf/{robot}.trans").write_text(FUSION_TRANS.format(**values))
    (package / f"urdf/{robot}.gazebo").write_text(FUSION_GAZEBO.format(**values))
    (package / "urdf/materials.xacro").write_text(FUSION_MATERIALS.format(**values))
    (package / "launch/display.launch").write_text(FUSION_DISPLAY.format(**values))
    (package / "launch/gazebo.launch").write_text(FUSION_GAZEBO_LAUNCH.format(**values))
    (package / "launch/controller.launch").write_text(FUSION_CONTROLLER.format(**values))
    (package / "launch/controller.yaml").write_text(FUSION_CONTROLLER_YAML.format(**values))
    (package / "launch/urdf.rviz").write_text(FUSION_RVIZ)
    for part in ("base_link", "arm_1"):
        _stl(package / "meshes" / f"{part}.stl", 50.0)  # millimetres: the model scales by 0.001
    return package


def onshape_export(folder: Path) -> Path:
    """onshape-to-robot's output without package_name: robot.urdf, meshes as package://assets/."""
    folder.mkdir(parents=True)
    parts = [
        '<?xml version="1.0" ?>',
        "<!-- Generated using onshape-to-robot -->",
        '<robot name="two_wheels">',
    ]
    for link in ("body", "wheel"):
        parts.append(f"""    <!-- Link {link} -->
    <link name="{link}">
        <inertial>
            <origin xyz="0 0 0" rpy="0 0 0"/>
            <mass value="0.3"/>
            <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.0003"/>
        </inertial>
        <visual>
            <origin xyz="0 0 0" rpy="0 -0 0"/>
            <geometry>
                <mesh filename="package://assets/{link}.stl"/>
            </geometry>
        </visual>
        <collision>
            <origin xyz="0 0 0" rpy="0 -0 0"/>
            <geometry>
                <mesh filename="package://assets/{link}.stl"/>
            </geometry>
        </collision>
    </link>""")
        _stl(folder / "assets" / f"{link}.stl")
    parts.append("""    <joint name="wheel_joint" type="continuous">
        <origin xyz="0 0 0.05" rpy="0 0 0"/>
        <parent link="body"/>
        <child link="wheel"/>
        <axis xyz="0 0 1"/>
    </joint>
</robot>""")
    (folder / "robot.urdf").write_text("\n".join(parts) + "\n")
    (folder / "config.json").write_text('{"output_format": "urdf"}\n')
    return folder / "robot.urdf"
