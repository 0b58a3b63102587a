"""Issue 35, "Output" 17: a launch file ros2 launch cannot decode is an error (launch-load-error) at
the line of its first byte that is not UTF-8, through both launch engines; one it loads is not.

What the real libraries do (launch and launch_xml of humble and jazzy, under Python 3.10 to 3.12):
- a Python launch file is loaded by importlib's SourceFileLoader (load_python_launch_file_as_module):
  its bytes are compiled as UTF-8 (PEP 263) unless a coding line says otherwise, and the compiler
  decodes comments leniently, so a Latin-1 byte in a comment loads and one in a string is a
  SyntaxError at its line; a UTF-16 file's NUL bytes are refused (no line);
- an XML or YAML launch file is opened as text, `open(file, 'r')` (launch.frontend.Parser.load),
  UTF-8 in the UTF-8 locale ROS 2 requires, strictly: a byte that is not UTF-8 is a
  UnicodeDecodeError before any parser sees it, whatever a BOM or an XML declaration says (a UTF-16
  file with or without both, a Latin-1 file declaring encoding="ISO-8859-1"). A UTF-8 file that
  declares ISO-8859-1 loads: expat reads each UTF-8 byte as a Latin-1 character.
"""

from __future__ import annotations

import pytest
from conftest import new_package, run_pkgforge, verify_report
from ros_prefix import DISTROS, make_prefix

PY = (
    "from launch import LaunchDescription\n"
    "from launch.actions import DeclareLaunchArgument\n"
    "\n"
    "# {comment}\n"
    "def generate_launch_description():\n"
    "    return LaunchDescription([DeclareLaunchArgument('who', default_value='{value}')])\n"
)
XML = '<launch>\n  <!-- {comment} -->\n  <arg name="who" default="{value}"/>\n</launch>\n'
YAML = "launch:\n- arg: {{name: who, default: '{value}'}}\n"
DECLARED = '<?xml version="1.0" encoding="{}"?>\n'

# file name → (its bytes, the line of launch-load-error or None: ros2 launch loads it)
VARIANTS: dict[str, tuple[bytes, int | None]] = {
    "py_latin1_comment.launch.py": (PY.format(comment="café", value="x").encode("latin-1"), None),
    "py_latin1_string.launch.py": (PY.format(comment="", value="café").encode("latin-1"), 6),
    "py_latin1_coding.launch.py": (
        ("# -*- coding: latin-1 -*-\n" + PY.format(comment="", value="café")).encode("latin-1"),
        None,
    ),
    "py_utf16.launch.py": (PY.format(comment="", value="x").encode("utf-16"), 1),
    "py_utf8_bom.launch.py": (b"\xef\xbb\xbf" + PY.format(comment="café", value="café").encode(), None),
    "xml_utf16_bom_declared.launch.xml": (
        (DECLARED.format("UTF-16") + XML.format(comment="x", value="café")).encode("utf-16"),
        1,
    ),
    "xml_utf16_bom.launch.xml": (XML.format(comment="x", value="café").encode("utf-16"), 1),
    # no BOM: its ASCII is UTF-8 (with NULs); the first byte that is not is é's, on line 3
    "xml_utf16le.launch.xml": (XML.format(comment="x", value="café").encode("utf-16-le"), 3),
    # Latin-1 declared: the é in the comment (line 3) is refused before XML is parsed
    "xml_latin1_declared.launch.xml": (
        (DECLARED.format("ISO-8859-1") + XML.format(comment="café", value="x")).encode("latin-1"),
        3,
    ),
    "xml_latin1.launch.xml": (XML.format(comment="x", value="café").encode("latin-1"), 3),
    "xml_utf8_declared_latin1.launch.xml": (
        (DECLARED.format("ISO-8859-1") + XML.format(comment="café", value="café")).encode(),
        None,
    ),
    "xml_utf8_bom.launch.xml": (b"\xef\xbb\xbf" + XML.format(comment="café", value="café").encode(), None),
    "yaml_latin1.launch.yaml": (YAML.format(value="café").encode("latin-1"), 2),
    "yaml_utf16.launch.yaml": (YAML.format(value="x").encode("utf-16"), 1),
    "yaml_utf8_bom.launch.yaml": (b"\xef\xbb\xbf" + YAML.format(value="café").encode(), None),
}
PACKAGE = "enc_description"


@pytest.fixture(scope="module")
def reports(tmp_path_factory) -> dict:
    """engine (builtin, or the real libraries of a distro) → the JSON report of the workspace."""
    workspace = tmp_path_factory.mktemp("encodings")
    (workspace / "src").mkdir()
    launch = new_package(workspace, PACKAGE) / "launch"
    for name, (data, _line) in VARIANTS.items():
        (launch / name).write_bytes(data)
    out = {
        "builtin": verify_report(workspace, "--no-cache", "--distro", "jazzy", "--launch-engine", "builtin")
    }
    base = tmp_path_factory.mktemp("ros")
    for distro in DISTROS:
        prefix, reason = make_prefix(distro, base)
        if prefix is not None:
            out[distro] = verify_report(
                workspace, "--no-cache", "--distro", distro, "--launch-engine", "ros", "--ros-prefix", prefix
            )
        else:
            print(f"real launch engine not compared: {reason}")
    return out


def _of(report: dict, name: str) -> list[dict]:
    return [d for d in report["diagnostics"] if d["path"] == f"src/{PACKAGE}/launch/{name}"]


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_a_launch_file_ros2_launch_cannot_decode_is_an_error_at_its_byte(reports, name):
    status, report = reports["builtin"]
    assert status == 1
    line = VARIANTS[name][1]
    found = [(d["code"], d["severity"], d["line"]) for d in _of(report, name)]
    if line is None:  # ros2 launch loads it: no error (a file Python reads past its comment: an info)
        assert all(severity != "error" for _code, severity, _line in found), found
        if name in ("py_latin1_comment.launch.py", "py_latin1_coding.launch.py"):
            assert [(code, severity) for code, severity, _line in found] == [("PF901", "info")]
    else:  # the error alone: file-not-read does not say the same bytes again
        assert found == [("PF301", "error", line)]
        (diagnostic,) = _of(report, name)
        assert diagnostic["hint"].startswith("save the file as UTF-8"), diagnostic


def test_the_message_is_launchs_own_decoding_error(reports):
    (diagnostic,) = _of(reports["builtin"][1], "xml_latin1_declared.launch.xml")
    position = VARIANTS["xml_latin1_declared.launch.xml"][0].index(b"\xe9")
    assert diagnostic["message"] == (
        f"loading xml_latin1_declared.launch.xml failed: UnicodeDecodeError: 'utf-8' codec can't "
        f"decode byte 0xe9 in position {position}: invalid continuation byte"
    )
    assert diagnostic["hint"] == (
        "save the file as UTF-8: ros2 launch reads XML and YAML launch files as UTF-8, whatever a "
        "BOM or an encoding declaration says"
    )
    (diagnostic,) = _of(reports["builtin"][1], "py_latin1_string.launch.py")
    assert diagnostic["message"].startswith(
        "loading py_latin1_string.launch.py failed: SyntaxError: (unicode error) 'utf-8' codec can't decode byte 0xe9"
    )
    assert "# -*- coding: latin-1 -*-" in diagnostic["hint"]


@pytest.mark.parametrize("distro", DISTROS)
def test_the_real_launch_libraries_agree(reports, distro):
    if distro not in reports:
        pytest.skip(f"no real ROS 2 launch library for {distro}")
    status, real = reports[distro]
    assert real["launch"] == {"engine": "ros", "distro": distro}

    def shown(report: dict) -> list[tuple]:
        return sorted(
            (d["code"], d["severity"], d["path"], d["line"], d["message"], d["hint"])
            for name in VARIANTS
            for d in _of(report, name)
        )

    assert shown(real) == shown(reports["builtin"][1])


def test_verify_exits_1_on_a_file_ros2_launch_refuses(tmp_path):
    """The campaign's case: a UTF-16 XML launch file was an info and exit 0."""
    (tmp_path / "src").mkdir()
    launch = new_package(tmp_path, PACKAGE, "--launch-format", "xml") / "launch"
    name, (data, line) = "xml_utf16_bom_declared.launch.xml", VARIANTS["xml_utf16_bom_declared.launch.xml"]
    (launch / name).write_bytes(data)
    result = run_pkgforge("verify", "--no-cache", cwd=tmp_path)
    assert result.returncode == 1, result.stdout
    assert f"src/{PACKAGE}/launch/{name}:{line}: PF301 [error] loading {name} failed: UnicodeDecodeError" in (
        result.stdout
    )
