"""ROS 1 packages in the SolidWorks exporter's shape, and bare URDFs, written by the tests."""

from __future__ import annotations

from pathlib import Path

from pkgforge.scaffold.stl import binary_stl, box_triangles

LINKS = ("base_link", "link1", "link2")


def urdf(name: str, mesh_uri) -> str:
    """Three links on two revolute joints, each with an STL visual and collision (mesh_uri(link))."""
    parts = [f'<?xml version="1.0" encoding="utf-8"?>\n<robot name="{name}">']
    for link in LINKS:
        parts.append(f'''  <link name="{link}">
    <inertial>
      <origin xyz="0 0 0.05" rpy="0 0 0"/>
      <mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <visual>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <geometry>
        <mesh filename="{mesh_uri(link)}"/>
      </geometry>
      <material name="">
        <color rgba="0.79 0.82 0.93 1"/>
      </material>
    </visual>
    <collision>
      <geometry>
        <mesh filename="{mesh_uri(link)}"/>
      </geometry>
    </collision>
  </link>''')
    for index, (parent, child) in enumerate(zip(LINKS, LINKS[1:], strict=False), start=1):
        parts.append(f'''  <joint name="joint{index}" type="revolute">
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <parent link="{parent}"/>
    <child link="{child}"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1.57" upper="1.57" effort="10" velocity="1"/>
  </joint>''')
    parts.append("</robot>\n")
    return "\n".join(parts)


def write_meshes(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for link in LINKS:
        (folder / f"{link}.STL").write_bytes(binary_stl(box_triangles((0.05, 0.05, 0.1)), header=link))


DISPLAY = """<launch>
  <arg name="model" />
  <arg name="gui" default="False" />
  <param name="robot_description" textfile="$(find {name})/urdf/{name}.urdf" />
  <param name="use_gui" value="$(arg gui)" />
  <node name="joint_state_publisher" pkg="joint_state_publisher" type="joint_state_publisher" />
  <node name="robot_state_publisher" pkg="robot_state_publisher" type="state_publisher" />
  <node name="rviz" pkg="rviz" type="rviz" args="-d $(find {name})/urdf.rviz" />
</launch>
"""

XACRO_DISPLAY = """<launch>
  <param name="robot_description" command="$(find xacro)/xacro --inorder '$(find {name})/urdf/{name}.urdf'" />
  <node name="joint_state_publisher_gui" pkg="joint_state_publisher_gui" type="joint_state_publisher_gui" />
  <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher" />
  <node name="rviz" pkg="rviz" type="rviz" args="-d $(find {name})/urdf.rviz" required="true" />
</launch>
"""

GAZEBO = """<launch>
  <include file="$(find gazebo_ros)/launch/empty_world.launch" />
  <node name="tf_footprint_base" pkg="tf" type="static_transform_publisher" args="0 0 0 0 0 0 base_link base_footprint 40" />
  <node name="spawn_model" pkg="gazebo_ros" type="spawn_model" args="-file $(find {name})/urdf/{name}.urdf -urdf -model {name}" output="screen" />
  <node name="fake_joint_calibration" pkg="rostopic" type="rostopic" args="pub /calibrated std_msgs/Bool true" />
</launch>
"""

RVIZ1 = """Panels:
  - Class: rviz/Displays
    Name: Displays
  - Class: rviz/Views
    Name: Views
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz/Grid
      Enabled: true
      Name: Grid
      Value: true
    - Alpha: 1
      Class: rviz/RobotModel
      Enabled: true
      Name: RobotModel
      Robot Description: robot_description
      Value: true
    - Class: rviz/TF
      Enabled: true
      Name: TF
      Value: true
    - Class: jsk_rviz_plugin/OverlayText
      Enabled: true
      Name: Overlay
      Value: true
  Enabled: true
  Global Options:
    Background Color: 48; 48; 48
    Fixed Frame: base_link
    Frame Rate: 30
  Name: root
  Tools:
    - Class: rviz/Interact
    - Class: rviz/MoveCamera
  Views:
    Current:
      Class: rviz/Orbit
      Distance: 1.5
      Name: Current View
    Saved: ~
Window Geometry:
  Height: 800
  QMainWindow State: 000000ff00000000fd
  Width: 1200
"""


def ros1_package(folder: Path, name: str, *, format_: int = 2) -> Path:
    """The SolidWorks exporter's catkin package, with an RViz 1 config and an xacro display launch."""
    package = folder / name
    (package / "launch").mkdir(parents=True)
    (package / "urdf").mkdir()
    (package / "config").mkdir()
    (package / "textures").mkdir()
    run = "run_depend" if format_ == 1 else "exec_depend"
    (package / "package.xml").write_text(f"""<?xml version="1.0"?>
<package format="{format_}">
  <name>{name}</name>
  <version>1.0.0</version>
  <description>URDF Description package for {name}</description>
  <author email="me@email.com">TODO</author>
  <maintainer email="me@email.com">Exporter User</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <{"build_depend" if format_ == 1 else "depend"}>roslaunch</{"build_depend" if format_ == 1 else "depend"}>
  <{run}>robot_state_publisher</{run}>
  <{run}>rviz</{run}>
  <{run}>joint_state_publisher</{run}>
  <{run}>gazebo</{run}>
  <export>
    <architecture_independent />
  </export>
</package>
""")
    (package / "CMakeLists.txt").write_text(f"""cmake_minimum_required(VERSION 2.8.3)
project({name})
find_package(catkin REQUIRED)
catkin_package()
find_package(roslaunch)
foreach(dir config launch meshes urdf)
  install(DIRECTORY ${{dir}}/
    DESTINATION ${{CATKIN_PACKAGE_SHARE_DESTINATION}}/${{dir}})
endforeach(dir)
""")
    (package / "launch" / "display.launch").write_text(DISPLAY.format(name=name))
    (package / "launch" / "display_xacro.launch").write_text(XACRO_DISPLAY.format(name=name))
    (package / "launch" / "gazebo.launch").write_text(GAZEBO.format(name=name))
    (package / "config" / f"joint_names_{name}.yaml").write_text(
        "controller_joint_names: ['', 'joint1', 'joint2', ]\n"
    )
    (package / "urdf.rviz").write_text(RVIZ1)
    (package / "urdf" / f"{name}.urdf").write_text(
        urdf(name, lambda link: f"package://{name}/meshes/{link}.STL")
    )
    (package / "urdf" / f"{name}.csv").write_text("Link Name,Center of Mass X\nbase_link,0\n")
    write_meshes(package / "meshes")
    (package / "textures" / "README").write_text("textures of the exported parts\n")
    return package


def bare_urdf(folder: Path, name: str = "arm") -> Path:
    """A bare URDF in urdf/ with meshes by relative path in ../meshes/ (no package around it)."""
    (folder / "urdf").mkdir(parents=True)
    write_meshes(folder / "meshes")
    model = folder / "urdf" / f"{name}.urdf"
    model.write_text(urdf(name, lambda link: f"../meshes/{link}.STL"))
    return model


def _inertial(mass: float) -> str:
    return f"""    <inertial>
      <mass value="{mass}"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>"""


def _wheel(side: str, y: float) -> str:
    return f"""  <link name="{side}_wheel">
{_inertial(0.5)}
    <visual><geometry><cylinder radius="0.05" length="0.02"/></geometry></visual>
    <collision><geometry><cylinder radius="0.05" length="0.02"/></geometry></collision>
  </link>
  <joint name="{side}_wheel_joint" type="continuous">
    <parent link="base_link"/>
    <child link="{side}_wheel"/>
    <origin xyz="0 {y} 0" rpy="-1.5708 0 0"/>
    <axis xyz="0 0 1"/>
  </joint>"""


GAZEBO_MODEL = """<?xml version="1.0"?>
<robot name="{name}" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <link name="base_footprint"/>
  <joint name="base_joint" type="fixed">
    <parent link="base_footprint"/>
    <child link="base_link"/>
    <origin xyz="0 0 0.05"/>
  </joint>
  <link name="base_link">
{base_inertial}
    <visual><geometry><box size="0.3 0.2 0.05"/></geometry></visual>
    <collision><geometry><box size="0.3 0.2 0.05"/></geometry></collision>
  </link>
{left}
{right}
  <link name="arm_link">
{arm_inertial}
    <visual><geometry><box size="0.02 0.02 0.2"/></geometry></visual>
    <collision><geometry><box size="0.02 0.02 0.2"/></geometry></collision>
  </link>
  <joint name="arm_joint" type="revolute">
    <parent link="base_link"/>
    <child link="arm_link"/>
    <origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1.57" upper="1.57" effort="10" velocity="1"/>
  </joint>
  <link name="camera_link">
{camera_inertial}
  </link>
  <joint name="camera_joint" type="fixed">
    <parent link="base_link"/>
    <child link="camera_link"/>
    <origin xyz="0.15 0 0.05"/>
  </joint>

  <transmission name="arm_transmission">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="arm_joint">
      <hardwareInterface>hardware_interface/PositionJointInterface</hardwareInterface>
    </joint>
    <actuator name="arm_motor">
      <mechanicalReduction>1</mechanicalReduction>
    </actuator>
  </transmission>

  <gazebo>
    <plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">
      <robotNamespace>/</robotNamespace>
    </plugin>
  </gazebo>

  <gazebo>
    <plugin name="differential_drive_controller" filename="libgazebo_ros_diff_drive.so">
      <leftJoint>left_wheel_joint</leftJoint>
      <rightJoint>right_wheel_joint</rightJoint>
      <wheelSeparation>0.25</wheelSeparation>
      <wheelDiameter>0.1</wheelDiameter>
      <commandTopic>cmd_vel</commandTopic>
      <odometryTopic>odom</odometryTopic>
      <odometryFrame>odom</odometryFrame>
      <robotBaseFrame>base_footprint</robotBaseFrame>
      <publishOdomTF>true</publishOdomTF>
      <wheelTorque>20</wheelTorque>
    </plugin>
  </gazebo>

  <gazebo reference="camera_link">
    <sensor type="camera" name="camera">
      <update_rate>30</update_rate>
      <camera>
        <horizontal_fov>1.3962634</horizontal_fov>
        <image><width>640</width><height>480</height><format>R8G8B8</format></image>
        <clip><near>0.02</near><far>300</far></clip>
      </camera>
      <plugin name="camera_controller" filename="libgazebo_ros_camera.so">
        <cameraName>camera</cameraName>
        <frameName>camera_link</frameName>
      </plugin>
    </sensor>
  </gazebo>
</robot>
"""

GAZEBO_CONTROLLERS = """joint_state_controller:
  type: joint_state_controller/JointStateController
  publish_rate: 50

arm_controller:
  type: position_controllers/JointTrajectoryController
  joints:
    - arm_joint
  constraints:
    goal_time: 0.6
"""

GAZEBO_LAUNCH = """<launch>
  <param name="robot_description" command="$(find xacro)/xacro $(find {name})/urdf/{name}.urdf.xacro" />
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="paused" value="false"/>
  </include>
  <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher" />
  <node name="spawn_model" pkg="gazebo_ros" type="spawn_model" args="-urdf -param robot_description -model {name}" output="screen" />
  <rosparam file="$(find {name})/config/controllers.yaml" command="load"/>
  <node name="controller_spawner" pkg="controller_manager" type="spawner" args="joint_state_controller arm_controller" output="screen"/>
</launch>
"""


def ros1_gazebo_package(folder: Path, name: str) -> Path:
    """A ROS 1 package simulated in Gazebo Classic: a two-wheel base (libgazebo_ros_diff_drive.so),
    an arm joint with a transmission (gazebo_ros_control), a camera with its plugin, the
    controllers YAML a launch file loads with <rosparam> for the spawner, empty_world.launch and
    spawn_model."""
    package = folder / name
    for sub in ("launch", "urdf", "config"):
        (package / sub).mkdir(parents=True)
    (package / "package.xml").write_text(f"""<?xml version="1.0"?>
<package format="2">
  <name>{name}</name>
  <version>0.1.0</version>
  <description>A ROS 1 robot simulated in Gazebo Classic</description>
  <maintainer email="me@email.com">Sim User</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <exec_depend>robot_state_publisher</exec_depend>
  <exec_depend>xacro</exec_depend>
  <exec_depend>gazebo_ros</exec_depend>
  <exec_depend>gazebo_ros_control</exec_depend>
  <exec_depend>controller_manager</exec_depend>
</package>
""")
    (package / "CMakeLists.txt").write_text(
        f"cmake_minimum_required(VERSION 3.0.2)\nproject({name})\nfind_package(catkin REQUIRED)\ncatkin_package()\n"
    )
    (package / "urdf" / f"{name}.urdf.xacro").write_text(
        GAZEBO_MODEL.format(
            name=name,
            base_inertial=_inertial(3.0).replace("\n", "\n"),
            arm_inertial=_inertial(0.2),
            camera_inertial=_inertial(0.05),
            left=_wheel("left", 0.125),
            right=_wheel("right", -0.125),
        )
    )
    (package / "config" / "controllers.yaml").write_text(GAZEBO_CONTROLLERS)
    (package / "launch" / "gazebo.launch").write_text(GAZEBO_LAUNCH.format(name=name))
    return package
