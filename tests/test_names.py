import pytest

from pkgforge.model.names import rep144_advice, rep144_problem


@pytest.mark.parametrize("name", ["rob_description", "a", "robot2", "x_y_z", "r2d2_description"])
def test_valid_names(name):
    assert rep144_problem(name) is None


@pytest.mark.parametrize(
    "name, reason",
    [
        ("Rob", "upper-case"),
        ("rob-desc", "'-'"),
        ("1rob", "starts with a digit"),
        ("rob__d", "double underscore"),
        ("../x", "is a path"),
        ("", "empty"),
        ("rob.d", "characters other than"),
        ("_rob", "characters other than"),
    ],
)
def test_invalid_names_say_why(name, reason):
    assert reason in rep144_problem(name)


@pytest.mark.parametrize(
    "name, suggestion",
    [
        ("Bad-Name", "bad_name"),  # the hint once said 'bad-name', itself invalid
        ("Rob", "rob"),
        ("rob-desc", "rob_desc"),
        # what CAD exporters take from the assembly (migrate's default name)
        ("BellPepperGripperPrototype", "bell_pepper_gripper_prototype"),
        ("er20-1780", "er20_1780"),
        ("Arm_Assembly_URDF.SLDASM", "arm_assembly_urdf_sldasm"),
        ("ROS_rover_urdf_description", "ros_rover_urdf_description"),
        ("Rob__X", "rob_x"),
    ],
)
def test_the_suggested_name_is_valid(name, suggestion):
    assert f"(try '{suggestion}')" in rep144_problem(name)
    assert rep144_problem(suggestion) is None


def test_no_suggestion_when_no_simple_fix_is_valid():
    assert "try" not in rep144_problem("1Rob")
    assert "try" not in rep144_problem("7260501-000000-001 TB6-R5-RevA1-URDF")


def test_a_trailing_underscore_is_advice_not_a_rep144_violation():
    # REP 144's mandatory rules say nothing of a trailing '_'; catkin_pkg and colcon take it
    # (ros2_learning's composition_): verify warns, `new` refuses
    assert rep144_problem("composition_") is None
    assert rep144_advice("composition_") == "'composition_' ends with '_'"
    assert rep144_advice("rob") is None and rep144_advice("Rob_") is None
