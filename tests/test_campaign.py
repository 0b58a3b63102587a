"""The bad-input campaign: hundreds of broken packages, verified in every mode that applies.

Broken inputs are made from the fixtures and from packages made by `pkgforge new`:
truncations and byte flips of every file kind, wrong encodings, a BOM, CRLF, huge and
empty files, links (dangling, cycles, out of the tree), permissions, deep nesting,
hostile launch files and xacro. Many broken packages share one workspace, so a few
verify runs cover them all. For every run: no traceback, exit status 0 or 1, no hang
(each case under 15 s: a run gets 15 s per case it holds), nothing of the workspace
changed (hashed before and after), every diagnostic names a file, and the JUnit report written
beside it (--junit-xml) is well-formed XML with no control character in it (issue 35: a file's name
may hold any). A launch file whose bytes are not UTF-8 gets what the real decoders say of it
(`launch_verdict`): an error where ros2 launch refuses it, at the line of its first such byte.

Byte-level mutations are drawn from a Random that Hypothesis draws (derandomized, so CI sees the same
inputs; no shrinking: a failing batch is split case by case instead).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from conftest import FIXTURES, MAINTAINER, run_command, run_pkgforge

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, Phase, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from test_sandbox import fingerprint  # noqa: E402

PER_CASE_SECONDS = 15
LAUNCH_TIMEOUT = "4"
# the bases every broken package is cloned from: name in its files → how it is made
BASES = {
    "cbasepy": ["--launch-format", "py"],
    "cbasexml": ["--launch-format", "xml"],
    "cbaseyaml": ["--launch-format", "yaml", "--distro", "humble"],
    "cbasepython": ["--build-type", "ament_python", "--launch-format", "xml"],
    "rob_description": "seed000/rob_description",
    "small_turtle": "seed001/small_turtle",
}
KINDS = {  # file kind → how to recognise it
    "package.xml": lambda p: p.name == "package.xml",
    "CMakeLists.txt": lambda p: p.name == "CMakeLists.txt",
    "setup.py": lambda p: p.name == "setup.py",
    "launch.py": lambda p: p.name.endswith(".launch.py"),
    "launch.xml": lambda p: p.name.endswith(".launch.xml"),
    "launch.yaml": lambda p: p.name.endswith(".launch.yaml"),
    "urdf": lambda p: p.suffix in (".urdf", ".xacro"),
    "rviz": lambda p: p.suffix == ".rviz",
    "stl": lambda p: p.suffix.lower() == ".stl",
}
TEXT_KINDS = [k for k in KINDS if k != "stl"]


@dataclass
class Case:
    name: str  # the package's name (and folder)
    base: str
    what: str  # what is broken, for a failure's message
    installable: bool = True  # its build files intact: `colcon build` still builds it
    # a diagnostic the report must hold: (code, severity, path as reported, line)
    expect: list[tuple[str, str, str, int | None]] = field(default_factory=list)


# --- the bases ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def bases(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("bases")
    (folder / "src").mkdir()
    for name, how in BASES.items():
        if isinstance(how, str):
            shutil.copytree(FIXTURES / how, folder / "src" / name)
        else:
            result = run_pkgforge("new", name, *MAINTAINER, *how, cwd=folder)
            assert result.returncode == 0, result.stderr
    return folder / "src"


def clone(bases: Path, base: str, src: Path, name: str) -> Path:
    """A copy of a base package under a new name (in file names and contents)."""
    target = src / name
    for root, _dirs, files in os.walk(bases / base):
        relative = os.path.relpath(root, bases / base).replace(base, name)
        (target / relative).mkdir(parents=True, exist_ok=True)
        for file in files:
            data = (Path(root) / file).read_bytes().replace(base.encode(), name.encode())
            (target / relative / file.replace(base, name)).write_bytes(data)
    return target


def files_of(package: Path, kind: str) -> list[Path]:
    return sorted(p for p in package.rglob("*") if p.is_file() and not p.is_symlink() and KINDS[kind](p))


# --- mutations ----------------------------------------------------------------------------------


def truncate(path: Path, fraction: float) -> str:
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * fraction)])
    return f"truncated to {fraction:.0%}"


def flip(path: Path, positions: list[int], values: list[int]) -> str:
    data = bytearray(path.read_bytes())
    if not data:
        return "flip of an empty file"
    for position, value in zip(positions, values, strict=False):
        data[position % len(data)] ^= value or 1
    path.write_bytes(bytes(data))
    return f"{len(positions)} bytes flipped"


def reencode(path: Path, encoding: str) -> str:
    text = path.read_bytes().decode("utf-8", errors="replace")
    text = text.replace("<description>", "<description>Müller ☃ ", 1).replace("# ", "# é ", 1)
    path.write_bytes(text.encode(encoding, errors="replace"))
    return f"encoded as {encoding}"


def latin1_text(path: Path) -> str:
    """A Latin-1 é in the first quoted value (a Python string, an XML attribute, a YAML value), where
    Python, unlike in a comment, does not skip it."""
    text = path.read_bytes().decode("utf-8", errors="replace")
    for quote in ("='", '="', ": "):
        if quote in text:
            text = text.replace(quote, quote + "é", 1)
            break
    path.write_bytes(text.encode("latin-1", errors="replace"))
    return "a Latin-1 é in a value"


def launch_verdict(path: Path) -> tuple[str, str, int | None] | None:
    """What ros2 launch makes of a launch file's bytes, by the real decoders (test_launch_encodings.py
    says why): (code, severity, line) verify must report, None when the bytes are UTF-8. Python
    compiles a .py file (comments decoded leniently, a coding line honoured); launch reads an XML or
    YAML file as UTF-8 text, strictly."""
    data = path.read_bytes()
    try:
        data.decode("utf-8")
        return None
    except UnicodeDecodeError as error:
        first = data.count(b"\n", 0, error.start) + 1
    if not path.name.endswith(".py"):
        return ("PF301", "error", first)
    try:
        compile(data, str(path), "exec", dont_inherit=True)
    except SyntaxError as error:
        if error.lineno is None:  # a NUL byte (UTF-16): located at the first one
            return ("PF301", "error", data.count(b"\n", 0, data.find(b"\0")) + 1)
        return ("PF301", "error", error.lineno)
    except ValueError:  # a NUL byte, as Python 3.10 says it
        return ("PF301", "error", data.count(b"\n", 0, data.find(b"\0")) + 1)
    return ("PF901", "info", first)  # Python loads it (a comment's bytes): pkgforge does not read it


def bom(path: Path) -> str:
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    return "UTF-8 BOM"


def crlf(path: Path) -> str:
    path.write_bytes(path.read_bytes().replace(b"\r\n", b"\n").replace(b"\n", b"\r\n"))
    return "CRLF"


def empty(path: Path) -> str:
    path.write_bytes(b"")
    return "empty"


def huge(path: Path) -> str:
    data = path.read_bytes()
    if path.suffix.lower() == ".stl":
        path.write_bytes(data[:80] + (10**7).to_bytes(4, "little") + b"\0" * (9 * 2**20))
    elif path.suffix == ".py":
        path.write_bytes(data + b"# padding\n" * 600_000)
    else:
        path.write_bytes(data + b"<!-- " + b"x" * (9 * 2**20) + b" -->\n")
    return "huge"


def replace(path: Path, make) -> None:
    """path (a file, or nothing yet) replaced by what make(path) creates there."""
    if path.exists() or path.is_symlink():
        path.unlink()
    make(path)


# a YAML "billion laughs": 12 lines of anchors, each alias ten of the one before (10**12 nodes)
ALIAS_BOMB = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"] + [
    f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 12)
]

BYTE_MUTATIONS = ("truncate", "truncate", "flip", "flip", "latin-1", "utf-16", "bom", "crlf", "empty")
LAUNCH_KINDS = ("launch.py", "launch.xml", "launch.yaml")
# re-encodings whose launch files get what the real decoders say (launch_verdict)
ENCODINGS = ("latin-1", "utf-16", "latin-1 text")

# hostile launch files: (file name, content); each lives in one package of its own
HOSTILE_LAUNCH = {
    "loop.launch.py": "def generate_launch_description():\n    while True:\n        pass\n",
    "exit.launch.py": "import sys\ndef generate_launch_description():\n    sys.exit(3)\n",
    "osexit.launch.py": "import os\ndef generate_launch_description():\n    os._exit(0)\n",
    "recursion.launch.py": "def f():\n    return f()\ndef generate_launch_description():\n    return f()\n",
    "baseexc.launch.py": "def generate_launch_description():\n    raise KeyboardInterrupt\n",
    "returns.launch.py": "def generate_launch_description():\n    return 42\n",
    "nofunction.launch.py": "x = 1\n",
    "kill.launch.py": (
        "import os, signal\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n    os.kill(os.getppid(), signal.SIGTERM)\n"
        "    return LaunchDescription([])\n"
    ),
    "writes.launch.py": (
        "import os\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    open(os.path.join(os.path.dirname(__file__), '..', 'package.xml'), 'w').write('')\n"
        "    return LaunchDescription([])\n"
    ),
    "prints.launch.py": (
        "import sys, os\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    print('{\"status\": \"ok\"}'); os.write(1, b'garbage\\n'); sys.stderr.write('x')\n"
        "    return LaunchDescription([])\n"
    ),
    "self.launch.py": (
        "import os\nfrom launch import LaunchDescription\n"
        "from launch.actions import IncludeLaunchDescription\n"
        "from launch.launch_description_sources import PythonLaunchDescriptionSource\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([IncludeLaunchDescription(PythonLaunchDescriptionSource(__file__))])\n"
    ),
    "laughs.launch.xml": (
        '<?xml version="1.0"?>\n<!DOCTYPE l [<!ENTITY a "aaaaaaaaaa">'
        '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">'
        '<!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;"><!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;">'
        '<!ENTITY f "&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;"><!ENTITY g "&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;">]>\n'
        '<launch><arg name="x" default="&g;"/></launch>\n'
    ),
    "external.launch.xml": (
        '<?xml version="1.0"?>\n<!DOCTYPE l [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        '<launch><arg name="x" default="&x;"/></launch>\n'
    ),
    "self.launch.xml": ('<launch><include file="$(find-pkg-share NAME)/launch/self.launch.xml"/></launch>\n'),
    "anchors.launch.yaml": (
        "launch:\n- arg: &a {name: x, default: y}\n- arg: *a\n- let: {name: z, value: [*a, *a, *a, *a]}\n"
    ),
    "notalist.launch.yaml": "launch: 7\n",
    # what steps around a Python guard (issue 35): only the kernel stops these
    "shellwrite.launch.py": (
        "import os\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    os.system('echo x >> SRC/package.xml; chmod 600 SRC/CMakeLists.txt; touch SRC/made.txt')\n"
        "    return LaunchDescription([])\n"
    ),
    "unguarded.launch.py": (
        "import subprocess, sys\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    subprocess.run([sys.executable, '-I', '-c', \"open('SRC/package.xml', 'a').write('x')\"])\n"
        "    return LaunchDescription([])\n"
    ),
    "libc.launch.py": (
        "import ctypes, os\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    libc = ctypes.CDLL(None)\n"
        "    fd = libc.open(b'SRC/package.xml', os.O_WRONLY | os.O_TRUNC)\n"
        "    return LaunchDescription([])\n"
    ),
    "forged.launch.py": (
        "import os\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    for fd in range(3, 64):\n"
        "        try:\n"
        '            os.write(fd, b\'{"status": "ok"}\\n\')\n'
        "        except OSError:\n"
        "            pass\n"
        "    raise RuntimeError('fails after forging')\n"
    ),
    "sleepers.launch.py": (
        "import os, time\nfrom launch import LaunchDescription\n"
        "def generate_launch_description():\n"
        "    for _ in range(4):\n"
        "        if os.fork() == 0:\n"
        "            os.setsid()\n"
        "            time.sleep(60)\n"
        "            os._exit(0)\n"
        "    return LaunchDescription([])\n"
    ),
    "tabs.launch.yaml": "launch:\n\t- arg: {name: x}\n",
    # issue 28: files that do not load, read statically (a wrong import; syntax errors everywhere)
    "wrong_import.launch.py": (
        "from launch import LaunchDescription\nfrom launch.substitutions import FindPackageShare\n"
        "from launch_ros.actions import Node\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([Node(package='NAME_typo', executable=os.path.join("
        "FindPackageShare('NAME'), 'urdf', '..', '..', '..', 'etc', 'passwd'))])\n"
    ),
    "syntax_deep.launch.py": "x = " + "(" * 5000 + "\n",
    "syntax_everywhere.launch.py": "def (:\n" * 40 + "FindPackageShare('nowhere_pkg')\n",
    # YAML the reader bounds (issue 35): aliases expanding to 10**12 nodes, 50,000 levels, an alias
    # inside the collection it names
    "bomb.launch.yaml": "launch:\n- let:\n    name: laughs\n    value:\n"
    + "".join(f"      {line}\n" for line in ALIAS_BOMB),
    "deep.launch.yaml": "launch:\n- let:\n    name: deep\n    value: " + "[" * 50_000 + "]" * 50_000 + "\n",
    "selfalias.launch.yaml": "launch:\n- let: &l\n    name: x\n    value: [*l]\n",
}
# hostile parameter files (issue 28): each given to a node and to ros_gz_bridge as its config
HOSTILE_PARAMS = {
    "deep.yaml": "n:\n  ros__parameters:\n    a: " + "[" * 3000 + "]" * 3000 + "\n",
    "deepmap.yaml": "n:\n  ros__parameters:\n    a: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n",
    "laughs.yaml": "n:\n  ros__parameters:\n    a0: &a0 {x: 1}\n"
    + "".join(
        f"    a{i}: &a{i} {{" + ", ".join(f"k{j}: *a{i - 1}" for j in range(10)) + "}\n" for i in range(1, 9)
    ),
    "binary.yaml": "n:\n  ros__parameters:\n    a: \x00\x01\n",
    "complexkey.yaml": "? [a, b]\n: {ros__parameters: {x: 1}}\n",
    "multidoc.yaml": "a:\n  ros__parameters: {x: 1}\n---\nb: 2\n---\n- c\n",
    "pytag.yaml": "!!python/object/apply:os.system ['touch /tmp/pwned']\n",
    "bignumbers.yaml": "n:\n  ros__parameters:\n    a: [1, 99999999999999999999999, 1e999, 0x1p3, nan]\n",
    "tabs.yaml": "n:\n\tros__parameters:\n\t\ta: 1\n",
}
# hostile RViz configs: (file name, content), in the package's rviz/ folder
HOSTILE_RVIZ = {
    "bomb.rviz": "Visualization Manager:\n  Class: ''\n  Laughs:\n"
    + "".join(f"    {line}\n" for line in ALIAS_BOMB),
    # issue 28, class 1: configurations not set where it is hard to say where (a name made of one,
    # a timer or a handler that holds itself: what runs after the description never ends)
    "confignested.launch.py": (
        "from launch import LaunchDescription\nfrom launch.actions import LogInfo\n"
        "from launch.substitutions import LaunchConfiguration as C\n"
        "def generate_launch_description():\n"
        "    return LaunchDescription([LogInfo(msg=C(C(C('x')), default=C('y')))])\n"
    ),
    "configtimerloop.launch.py": (
        "from launch import LaunchDescription\nfrom launch.actions import TimerAction, LogInfo\n"
        "from launch.substitutions import LaunchConfiguration\n"
        "def generate_launch_description():\n"
        "    t = TimerAction(period=0.0, actions=[LogInfo(msg=LaunchConfiguration('x'))])\n"
        "    t.actions.append(t)\n"
        "    return LaunchDescription([t])\n"
    ),
    "confighandlerloop.launch.py": (
        "from launch import LaunchDescription\nfrom launch.actions import RegisterEventHandler, LogInfo\n"
        "from launch.event_handlers import OnShutdown\nfrom launch.substitutions import LaunchConfiguration\n"
        "def generate_launch_description():\n"
        "    entities = [LogInfo(msg=LaunchConfiguration('x'))]\n"
        "    handler = RegisterEventHandler(OnShutdown(on_shutdown=entities))\n"
        "    entities.append(handler)\n"
        "    return LaunchDescription([handler])\n"
    ),
    "confignames.launch.xml": (
        '<launch><let name="$(var a)" value="1"/><node pkg="$(var pkg)" exec="x"/>'
        '<timer period="$(var period)"><log message="$(var m)"/></timer></launch>\n'
    ),
}
# hostile models: (file name, content)
HOSTILE_XACRO = {
    "selfinclude.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        '<xacro:include filename="$(find NAME)/urdf/selfinclude.urdf.xacro"/></robot>\n'
    ),
    "recursive.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        '<xacro:macro name="m"><xacro:m/></xacro:macro><xacro:m/></robot>\n'
    ),
    "eval.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        "<link name=\"${__import__('os').remove('SRC/package.xml') or 'l'}\"/></robot>\n"
    ),
    "bigloop.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        '<xacro:property name="n" value="${10**10}"/>'
        "<link name=\"${'x' * 1000}\"/></robot>\n"
    ),
    "laughs.urdf": (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa">'
        '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">'
        '<!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;"><!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;">]>'
        '<robot name="r"><link name="&e;"/></robot>\n'
    ),
    "notxml.urdf": "\x00\x01\x02 not xml at all",
    "escape.urdf.xacro": (  # xacro's eval escaped to Popen: a shell, no Python guard
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        "<link name=\"${[c for c in python.vars(python.type)['__subclasses__'](python.type(0).mro()[-1]) "
        "if 'Popen' in python.repr(c)][0]('echo x >> SRC/package.xml', shell=True).wait() and 'l'}\"/></robot>\n"
    ),
    "deep.urdf.xacro": (  # 100,000 nested elements: xacro recurses once per level (issue 35)
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
        + "<g>" * 100_000
        + "</g>" * 100_000
        + "</robot>\n"
    ),
    # ROS 1's bare xacro tags, nested and in odd places (issue 28 class 3)
    "ros1tags.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r"><property name="x" value="1"/>'
        '<macro name="m" params="p"><link name="${p}"/><macro name="n"/></macro>'
        '<if value="${x}"><include filename="nowhere.xacro"/><arg name="a"/><link name="l"/></if>'
        '<unless value="1"><link name="u"/></unless><xacro:m p="a"/><link name="r0"/></robot>\n'
    ),
    # what urdfdom refuses or drops, all at once (issue 28 class 7)
    "urdfdom.urdf": (
        '<robot><material name="m"/><material name="m"><color rgba="nan 1 1 1 1 1"/></material>'
        "<material><texture/></material>"
        '<link name="a"><inertial><origin xyz="inf 0 0"/></inertial><visual><geometry/></visual></link>'
        '<link name="b"><visual><origin xyz="1e 0x10 1,5" rpy=""/><geometry><capsule/></geometry>'
        '<material name="m"><color rgba="-1 2 3"/><texture filename=""/></material></visual>'
        '<visual><geometry><mesh scale="1 1"/></geometry><material/></visual>'
        '<collision><geometry><box size="     "/></geometry></collision></link>'
        '<link name="c"><visual><geometry><sphere radius="r"/></geometry></visual></link>'
        '<joint name="j" type="weird"><parent link="a"/><child link="b"/></joint>'
        '<joint type="revolute"><parent link="a"/><child link="c"/><mimic joint="j"/><limit effort=""/></joint>'
        '<joint name="k" type="continuous"><parent link="b"/><child link="c"/><mimic joint="k"/>'
        '<mimic/><dynamics/><safety_controller/><calibration rising="x"/><axis xyz="0 0 0 0"/></joint>'
        "</robot>\n"
    ),
    # what CAD exporters write (issue 29): content after the root, a package:// naming the
    # exporter's folder, a mesh start tag over two lines
    "trailing.urdf": '<robot name="r"><link name="l"/></robot>\n<transmission name="t"><type>x</type></transmission>\n',
    "exporterfolder.urdf": (
        '<robot name="r"><link name="l"><visual><geometry>'
        '<mesh filename="package://Some-URDF/meshes/x.STL"\n scale="1 1 1"/></geometry></visual></link></robot>\n'
    ),
    # simulation and control tags at their oddest (issue 31): nameless, empty, repeated, nested in
    # conditionals, plugin names of every family, parameters files that are no file or not YAML
    "control.urdf.xacro": (
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r"><link name="a"/><link name="b"/>'
        '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>'
        '<ros2_control><hardware><plugin/></hardware><joint/><joint name=""><command_interface/></joint>'
        '<gpio name="g"/><sensor name="s"/></ros2_control>'
        '<ros2_control name="x" type="system"><hardware><plugin>  </plugin><plugin>a/b/c</plugin></hardware>'
        '<joint name="j"><state_interface name="\u00e9"/></joint><joint name="j"/></ros2_control>'
        '<xacro:if value="1"><ros2_control name="y"><hardware><plugin>gz_ros2_control/GazeboSimSystem'
        '</plugin></hardware><joint name="nowhere"/></ros2_control></xacro:if>'
        '<gazebo><plugin/><plugin filename=""/><plugin filename="/abs/libgazebo_ros_camera.so"/>'
        '<plugin filename="libgz-sim99-x-system.so"/><plugin filename="ignition-gazebo--system"/>'
        '<plugin filename="gz_ros2_control-system"><parameters>/etc/passwd</parameters>'
        "<parameters>$(find NAME)/urdf/control.urdf.xacro</parameters><parameters>/nowhere.yaml</parameters>"
        '<parameters/></plugin><plugin filename="' + "x" * 5000 + '"/></gazebo>'
        "</robot>\n"
    ),
    # Gazebo worlds and SDF models (issue 31 item 4): entities, URIs that climb out, odd versions
    "laughs.sdf": (
        '<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY a "aaaaaaaaaa">'
        '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>'
        '<sdf version="&c;"><world name="&c;"><include><uri>model://&c;</uri></include></world></sdf>\n'
    ),
    "climb.world": (
        '<sdf version="1.x"><world name="w"><include><uri>model://../../../../etc</uri></include>'
        "<include><uri>package://NAME/../../../../etc/passwd</uri></include>"
        "<include><uri>file:///home/</uri></include><include><uri>model://</uri></include>"
        "<model name='m'><link name='l'><visual name='v'><geometry><mesh><uri>%00/dev/zero</uri>"
        "</mesh></geometry></visual></link></model><include><uri>\u00e9</uri></include>"
        '<pose relative_to="" degrees="maybe"/></world></sdf>\n'
    ),
    # home-folder URIs PF421's fix reads back to the package's own files (issue 31 fixes): climbing,
    # escaped, endless, a file for a folder, a link's name
    "homes.world": (
        '<sdf version="1.9"><world name="w"><include><uri>file:///home/a/../../etc/passwd</uri></include>'
        "<include><uri>file:///home/a/%2e%2e/%2e%2e/etc</uri></include>"
        "<include><uri>/home/a/" + "deep/" * 400 + "urdf</uri></include>"
        "<include><uri>/home/a/ws/src/NAME/urdf/</uri></include><include><uri>/root/.</uri></include>"
        "<include><uri>file:///home/a/NAME/package.xml</uri></include>"
        "<include><uri><![CDATA[/home/a/NAME/urdf]]></uri></include>"
        "<model name='m'><link name='l'><visual name='v'><geometry><mesh><uri>/home/a/ws/src/NAME/urdf/"
        + "x" * 300
        + ".stl</uri></mesh></geometry></visual></link></model></world></sdf>\n"
    ),
}

# hostile setup.py files (issue 34): each computes its data_files (a helper the static reader cannot
# evaluate), so verify runs it, sandboxed, as colcon reads it; the line below goes before setup()
HOSTILE_SETUP = {
    "loop": "while True:\n    pass",
    "exit": "import sys\nsys.exit(3)",
    "osexit": "os._exit(0)",
    "recursion": "def f():\n    return f()\nf()",
    "baseexc": "raise KeyboardInterrupt",
    "kill": "import signal\nos.kill(os.getppid(), signal.SIGTERM)",
    "writes": "open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'package.xml'), 'w').write('')",
    "removes": "os.remove(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'package.xml'))",
    "prints": "print('{\"status\": \"ok\"}')\nos.write(1, b'garbage\\n')",
    "memory": "hog = bytearray(1 << 40)",
    "sleeper": "import subprocess\nsubprocess.Popen(['sleep', '600'])",
    "forks": "if os.fork() == 0:\n    while True:\n        pass",
    "baddata": "share_files = lambda: [(1, 2), 'x', None]",
    "nosetup": "raise SystemExit(0)",
}
SETUP_TEMPLATE = """import os
from setuptools import setup

package_name = 'NAME'


def share_files():
    out = [('share/ament_index/resource_index/packages', ['resource/' + package_name])]
    for folder in ('launch', 'urdf', 'meshes', 'rviz'):
        for root, _, files in os.walk(folder):
            out.append((os.path.join('share', package_name, root), [os.path.join(root, f) for f in files]))
    return out


HOSTILE

setup(name=package_name, version='0.0.0', packages=[],
      data_files=[('share/' + package_name, ['package.xml'])] + share_files())
"""


def structural(package: Path, what: str, outside: Path) -> None:
    """Links, permissions, nesting: one kind of damage to the package."""
    meshes = package / "meshes"
    meshes.mkdir(exist_ok=True)
    if what == "dangling link":
        (meshes / "gone.stl").symlink_to(package / "nowhere.stl")
    elif what == "link cycle":
        (meshes / "self").symlink_to(".")
    elif what == "link loop":
        (meshes / "a").symlink_to("b")
        (meshes / "b").symlink_to("a")
    elif what == "link out of the tree":
        (meshes / "outside").symlink_to(outside)
    elif what == "link to a system file":
        (meshes / "passwd.stl").symlink_to("/etc/passwd")
    elif what == "mesh replaced by a link out":
        mesh = next(iter(sorted(meshes.glob("*.[sS][tT][lL]"))), meshes / "m.stl")
        if mesh.exists():
            mesh.unlink()
        mesh.symlink_to(outside / "mesh.stl")
    elif what == "urdf folder is a link up":
        shutil.rmtree(package / "urdf", ignore_errors=True)
        (package / "urdf").symlink_to("..")
    elif what == "unreadable mesh":
        for mesh in meshes.glob("*.[sS][tT][lL]"):
            mesh.chmod(0)
    elif what == "unreadable urdf folder":
        (package / "urdf").chmod(0)
    elif what == "unreadable launch file":
        for launch in (package / "launch").glob("*"):
            launch.chmod(0)
    elif what == "read-only package":
        for path in sorted(package.rglob("*"), reverse=True):
            path.chmod(0o555 if path.is_dir() else 0o444)
    elif what == "deep nesting":
        deep = meshes
        for _ in range(400):
            deep = deep / "d"
        deep.mkdir(parents=True)
        (deep / "deep.stl").write_bytes(b"solid x\nendsolid x\n")
    elif what == "many files":
        many = meshes / "many"
        many.mkdir()
        for i in range(3000):
            (many / f"{i}.stl").write_bytes(b"")
    elif what == "fifo":
        os.mkfifo(meshes / "pipe.stl")
    elif what == "launch folder is a file":
        shutil.rmtree(package / "launch", ignore_errors=True)
        (package / "launch").write_text("not a folder")
    elif what == "space and unicode in names":
        (meshes / "with space ☃.stl").write_bytes(b"solid x\nendsolid x\n")
    elif what == "rejected manifest and a setup.py that cannot run":
        manifest = package / "package.xml"
        manifest.write_text(re.sub(r"<name>[^<]*</name>", "", manifest.read_text()))
        setup_py = package / "setup.py"
        rest = setup_py.read_text() if setup_py.is_file() else "from setuptools import setup\nsetup()\n"
        setup_py.write_text("import pkgforge_campaign_not_installed\n" + rest)
    elif what in HOSTILE_NAMES:
        # a launch file that fails to load (so reports name it) and a mesh, named so
        launch_name, content, mesh = HOSTILE_NAMES[what]
        (package / "launch").mkdir(exist_ok=True)
        (package / "launch" / launch_name).write_text(content)
        (meshes / mesh).write_bytes(b"solid x\nendsolid x\n")
    elif what.endswith(" is a FIFO"):  # package.xml, CMakeLists.txt (issue 35: a read blocks for ever)
        replace(package / what.split()[0], os.mkfifo)
    elif " linked to /dev/" in what:  # a read never ends (issue 35)
        kind, device = what.split(" linked to ")
        folder = {"package.xml": package, "launch file": package / "launch", "mesh": meshes}[kind]
        pattern = {"package.xml": "package.xml", "launch file": "*.launch.*", "mesh": "*.[sS][tT][lL]"}[kind]
        target = next(
            iter(sorted(folder.glob(pattern))),
            folder / "x.launch.py" if kind == "launch file" else meshes / "m.stl",
        )
        replace(target, lambda path: os.symlink(device, path))
    elif what == "nested package":  # a package.xml inside the package (issue 28 class 6)
        inner = package / "inner" / "nested_pkg"
        inner.mkdir(parents=True)
        (inner / "package.xml").write_text('<package format="3"><name>nested_pkg</name><name>twice</name>')
    elif what == "rviz 1 config":  # ROS 1's classes, a group in a group, a class that is no string
        (package / "rviz").mkdir(exist_ok=True)
        (package / "rviz" / "ros1.rviz").write_text(
            "Panels:\n  - Class: rviz/Displays\nVisualization Manager:\n  Displays:\n"
            "    - Class: rviz/Group\n      Displays:\n        - Class: rviz/Group\n          Displays:\n"
            "            - Class: rviz/RobotModel\n              Robot Description: robot_description\n"
            "        - Class: [rviz/TF]\n        - Class: rviz/\n  Views: {Current: {Class: rviz/Orbit}}\n"
        )
    else:
        raise AssertionError(what)


# file names a report prints (issue 35): what → (launch file, its content, mesh); each file fails to load
HOSTILE_NAMES = {
    "escape sequence in a name": (
        "title\x1b]0;pwned\x07.launch.py",
        "def generate_launch_description(:\n",
        "clear\x1b[2J.stl",
    ),
    "newline in a name": (
        "x\n::error file=README.md,line=1::forged.launch.py",
        "def generate_launch_description(:\n",
        "line\nbreak.stl",
    ),
    "control character in a name": ("ctl\x01.launch.xml", "<launch><oops/></launch>\n", "del\x7f\x85.stl"),
}


STRUCTURAL = (
    "dangling link",
    "link cycle",
    "link loop",
    "link out of the tree",
    "link to a system file",
    "mesh replaced by a link out",
    "urdf folder is a link up",
    "unreadable mesh",
    "unreadable urdf folder",
    "unreadable launch file",
    "read-only package",
    "deep nesting",
    "many files",
    "fifo",
    "launch folder is a file",
    "space and unicode in names",
    # issue 30: colcon's ROS extension rejects the manifest, so its python extension runs setup.py,
    # which fails: the traceback of the Python colcon started is one located line
    "rejected manifest and a setup.py that cannot run",
    *HOSTILE_NAMES,
    # FIFOs and devices where files stand (issue 35), after the others: each keeps its base
    "package.xml is a FIFO",
    "CMakeLists.txt is a FIFO",
    "package.xml linked to /dev/zero",
    "package.xml linked to /dev/urandom",
    "launch file linked to /dev/zero",
    "launch file linked to /dev/urandom",
    "mesh linked to /dev/zero",
    "mesh linked to /dev/urandom",
    "nested package",
    "rviz 1 config",
)


# --- building the campaign ----------------------------------------------------------------------


def byte_plan(rng) -> list[tuple[str, str, str, dict]]:
    """(base, kind, mutation, parameters) for every base × file kind it has × byte mutation."""
    plan = []
    for base in BASES:
        for kind in KINDS:
            mutations = ("truncate", "flip", "empty") if kind == "stl" else BYTE_MUTATIONS
            if kind in LAUNCH_KINDS:
                mutations += ("latin-1 text",)
            for mutation in mutations:
                parameters = {}
                if mutation == "truncate":
                    parameters["fraction"] = rng.uniform(0.01, 0.99)
                elif mutation == "flip":
                    count = rng.randint(1, 8)
                    parameters["positions"] = [rng.randrange(2**20) for _ in range(count)]
                    parameters["values"] = [rng.randint(1, 255) for _ in range(count)]
                plan.append((base, kind, mutation, parameters))
    return plan


def apply_bytes(package: Path, kind: str, mutation: str, parameters: dict) -> str | None:
    files = files_of(package, kind)
    if not files:
        return None
    path = files[0]
    if mutation == "latin-1 text":
        return f"{path.relative_to(package)}: {latin1_text(path)}"
    if mutation == "truncate":
        done = truncate(path, parameters["fraction"])
    elif mutation == "flip":
        done = flip(path, parameters["positions"], parameters["values"])
    elif mutation in ("latin-1", "utf-16"):
        done = reencode(path, mutation)
    elif mutation == "bom":
        done = bom(path)
    elif mutation == "crlf":
        done = crlf(path)
    else:
        done = empty(path)
    return f"{path.relative_to(package)}: {done}"


class Campaign:
    def __init__(self, bases: Path, root: Path):
        self.bases, self.root, self.count = bases, root, 0
        self.outside = root / "outside"
        self.outside.mkdir(parents=True, exist_ok=True)
        (self.outside / "mesh.stl").write_bytes(b"solid o\nendsolid o\n")
        (self.outside / "secret.txt").write_text("not the package's\n")

    def package(self, src: Path, base: str) -> tuple[str, Path]:
        self.count += 1
        name = f"c{self.count:04d}_{base.replace('_', '')}"
        return name, clone(self.bases, base, src, name)

    def byte_cases(self, src: Path, plan) -> list[Case]:
        cases = []
        for base, kind, mutation, parameters in plan:
            name, package = self.package(src, base)
            what = apply_bytes(package, kind, mutation, parameters)
            if what is None:
                shutil.rmtree(package)
                continue
            case = Case(
                name, base, what, installable=kind not in ("package.xml", "CMakeLists.txt", "setup.py")
            )
            # (where the package's name is its own: rob_description's clones all name robot_description,
            # and of packages that share a name only one is in the tree whose launch files are evaluated)
            own_name = f"<name>{name}</name>".encode() in (package / "package.xml").read_bytes()
            if kind in LAUNCH_KINDS and mutation in ENCODINGS and own_name:
                path = files_of(package, kind)[0]
                verdict = launch_verdict(path)
                if verdict is not None:
                    code, severity, line = verdict
                    case.expect.append((code, severity, f"src/{name}/{path.relative_to(package)}", line))
            cases.append(case)
        return cases

    def huge_cases(self, src: Path) -> list[Case]:
        cases = []
        for kind in ("package.xml", "launch.py", "urdf", "stl", "rviz"):
            name, package = self.package(src, "cbasepy")
            path = files_of(package, kind)[0]
            cases.append(
                Case(name, "cbasepy", f"{path.relative_to(package)}: {huge(path)}", kind != "package.xml")
            )
        return cases

    def hostile_cases(self, src: Path) -> list[Case]:
        cases = []
        for file, content in {**HOSTILE_LAUNCH, **HOSTILE_XACRO, **HOSTILE_RVIZ}.items():
            base = (
                "cbasexml" if file.endswith(".xml") else "cbaseyaml" if file.endswith(".yaml") else "cbasepy"
            )
            name, package = self.package(src, base)
            folder = "launch" if ".launch." in file else "rviz" if file.endswith(".rviz") else "urdf"
            (package / folder / file).write_text(content.replace("NAME", name).replace("SRC", str(package)))
            if folder == "urdf":  # a launch file that runs xacro on it
                (package / "launch" / f"run_{file}.launch.py").write_text(
                    "from launch import LaunchDescription\nfrom launch.substitutions import Command\n"
                    "from launch_ros.actions import Node\nfrom launch_ros.parameter_descriptions import ParameterValue\n"
                    "from ament_index_python.packages import get_package_share_directory\n"
                    "def generate_launch_description():\n"
                    f"    model = get_package_share_directory({name!r}) + '/urdf/{file}'\n"
                    "    return LaunchDescription([Node(package='robot_state_publisher', executable="
                    "'robot_state_publisher', parameters=[{'robot_description': ParameterValue("
                    "Command(['xacro ', model]), value_type=str)}])])\n"
                )
            cases.append(Case(name, base, f"hostile {file}"))
        for file, content in HOSTILE_PARAMS.items():
            name, package = self.package(src, "cbasepy")
            (package / "rviz" / file).write_text(content)
            (package / "launch" / "params.launch.py").write_text(
                "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n"
                "from ament_index_python.packages import get_package_share_directory\n"
                "def generate_launch_description():\n"
                f"    path = get_package_share_directory({name!r}) + '/rviz/{file}'\n"
                "    return LaunchDescription([\n"
                "        Node(package='robot_state_publisher', executable='robot_state_publisher', "
                "parameters=[path]),\n"
                "        Node(package='ros_gz_bridge', executable='parameter_bridge', "
                "parameters=[{'config_file': path}]),\n"
                "    ])\n"
            )
            cases.append(Case(name, "cbasepy", f"hostile parameters {file}"))
        for what, code in HOSTILE_SETUP.items():
            name, package = self.package(src, "cbasepython")
            (package / "setup.py").write_text(SETUP_TEMPLATE.replace("NAME", name).replace("HOSTILE", code))
            cases.append(Case(name, "cbasepython", f"hostile setup.py: {what}"))
        return cases

    def structural_cases(self, src: Path) -> list[Case]:
        cases = []
        for index, what in enumerate(STRUCTURAL):
            base = list(BASES)[index % 4]
            name, package = self.package(src, base)
            structural(package, what, self.outside)
            expect = []
            if what in HOSTILE_NAMES:  # the report names the file that fails to load, as it is named
                expect.append(("PF301", "error", f"src/{name}/launch/{HOSTILE_NAMES[what][0]}", 1))
            cases.append(
                Case(
                    name,
                    base,
                    what,
                    installable=what
                    not in (
                        "urdf folder is a link up",
                        "launch folder is a file",
                        "unreadable urdf folder",
                        "unreadable launch file",
                        "fifo",
                        "package.xml is a FIFO",
                        "CMakeLists.txt is a FIFO",
                        "package.xml linked to /dev/zero",
                        "package.xml linked to /dev/urandom",
                        "link loop",
                        "dangling link",
                        "deep nesting",
                    ),
                    expect=expect,
                )
            )
        return cases


def install_like_colcon(src: Path, install: Path) -> None:
    """A merged install base as `colcon build --symlink-install` leaves it: each package's
    folders and package.xml in share/<name> (links kept as links), and the ament index."""
    index = install / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True, exist_ok=True)
    (install / ".colcon_install_layout").write_text("merged\n")
    for package in sorted(src.iterdir()):
        share = install / "share" / package.name
        share.mkdir(parents=True)
        (index / package.name).write_text("")
        for entry in package.iterdir():
            if entry.name in ("launch", "meshes", "rviz", "urdf", "package.xml"):
                target = share / entry.name
                try:
                    if entry.is_dir() and not entry.is_symlink():
                        shutil.copytree(entry, target, symlinks=True)
                    elif entry.is_symlink():
                        target.symlink_to(os.readlink(entry))
                    else:
                        shutil.copy2(entry, target)
                except (OSError, shutil.Error):
                    continue  # unreadable: left out, as a failed install would


# --- running verify on a batch ------------------------------------------------------------------


def readable(folder: Path) -> None:
    """Give back read permission (the permission cases), so pytest can clean up."""
    for root, dirs, _files in os.walk(folder):
        for name in dirs:
            path = os.path.join(root, name)
            if not os.path.islink(path):
                try:
                    os.chmod(path, 0o755)
                except OSError:
                    pass


# what no report may hold as it is: C0 controls but the newline, DEL, C1 controls
RAW_CONTROL = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f]")


def verify_batch(workspace: Path, cases: list[Case], *mode: str) -> list[str]:
    """Problems of one verify run over many cases (empty: all held)."""
    before = fingerprint(workspace, skip=("build",))
    limit = PER_CASE_SECONDS * max(1, len(cases))
    junit = workspace.parent / f"{workspace.name}.junit.xml"  # beside the workspace: not of it
    junit.unlink(missing_ok=True)
    try:
        result = run_command(
            [sys.executable, "-m", "pkgforge", "verify", ".", "--format", "json", "--no-cache"]
            + ["--launch-timeout", LAUNCH_TIMEOUT, "--junit-xml", str(junit), *mode],
            cwd=workspace,
            timeout=limit,
        )
    except subprocess.TimeoutExpired:
        return [f"hang: no answer after {limit} s"]
    problems = []
    output = result.stdout + result.stderr
    if "Traceback" in output:
        problems.append("traceback:\n" + output[-3000:])
    if result.returncode not in (0, 1):
        problems.append(f"exit status {result.returncode}: {result.stderr[-2000:]}")
    after = fingerprint(workspace, skip=("build",))
    if after != before:
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        problems.append(f"changed: {changed[:20]}")
    if result.returncode in (0, 1):
        try:
            report = json.loads(result.stdout)
        except ValueError:
            problems.append(f"not JSON: {result.stdout[:500]}")
        else:
            unlocated = [d for d in report["diagnostics"] if not d.get("path")]
            if unlocated:
                problems.append(f"unlocated: {unlocated[:5]}")
            problems += missing_expected(report, cases)
        problems += junit_problems(junit)
    return problems


def missing_expected(report: dict, cases: list[Case]) -> list[str]:
    """Each case's expected diagnostic, if the report lacks it (with what it says of that file)."""
    found = {(d["code"], d["severity"], d["path"], d["line"]) for d in report["diagnostics"]}
    problems = []
    for case in cases:
        for expected in case.expect:
            if expected not in found:
                said = [
                    (d["code"], d["severity"], d["line"], d["message"][:200])
                    for d in report["diagnostics"]
                    if d["path"] == expected[2]
                ]
                problems.append(f"{case.name} ({case.what}): no {expected}; said: {said}")
    return problems


def junit_problems(junit: Path) -> list[str]:
    """The JUnit report beside the JSON one: written, well-formed, no control character."""
    from lxml import etree

    try:
        text = junit.read_text(encoding="utf-8")
        etree.fromstring(text.encode())
    except (OSError, ValueError, etree.XMLSyntaxError) as error:
        return [f"JUnit report: {error}"]
    finally:
        junit.unlink(missing_ok=True)
    raw = sorted({repr(c) for c in RAW_CONTROL.findall(text)})
    return [f"JUnit report holds control characters: {raw}"] if raw else []


def each_alone(workspace: Path, cases: list[Case], *mode: str) -> dict[str, list[str]]:
    """A batch failed: which cases fail on their own (a workspace with just that package)."""
    failing = {}
    by_package: dict[str, list[Case]] = {}
    for case in cases:
        by_package.setdefault(case.name, []).append(case)
    for package_cases in by_package.values():
        case = Case(
            package_cases[0].name,
            package_cases[0].base,
            "; ".join(c.what for c in package_cases),
            expect=[e for c in package_cases for e in c.expect],
        )
        alone = workspace.parent / f"alone-{case.name}"
        (alone / "src").mkdir(parents=True)
        shutil.move(str(workspace / "src" / case.name), alone / "src" / case.name)
        if (workspace / "install").exists() and mode:
            shutil.copytree(workspace / "install", alone / "install", symlinks=True)
        problems = verify_batch(alone, [case], *mode)
        if problems:
            failing[f"{case.name} ({case.base}: {case.what})"] = problems
    return failing


def check(workspace: Path, cases: list[Case], *mode: str) -> None:
    problems = verify_batch(workspace, cases, *mode)
    if problems:
        failing = each_alone(workspace, cases, *mode)
        raise AssertionError(
            f"{len(failing)} of {len(cases)} cases fail alone: "
            + json.dumps(failing, indent=1)[:20000]
            + "\nthe batch: "
            + "\n".join(problems)[:5000]
        )


# --- the campaign -------------------------------------------------------------------------------

CAMPAIGN_SETTINGS = settings(
    max_examples=1,
    derandomize=True,
    database=None,
    deadline=None,
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
)


@pytest.mark.slow
@CAMPAIGN_SETTINGS
@given(data=st.data())
def test_campaign_default_and_install_base(bases, tmp_path_factory, data):
    """Every broken package, in the default mode and against an install base that holds it."""
    root = tmp_path_factory.mktemp("campaign")
    campaign = Campaign(bases, root)
    batches = []
    # Hypothesis's first example is its simplest (every number 0): a seeded Random it draws
    # gives the byte-level parameters their spread, and the same ones on every run
    plan = byte_plan(data.draw(st.randoms(use_true_random=True), label="mutations"))
    half = len(plan) // 2
    for index, part in enumerate((plan[:half], plan[half:])):
        workspace = root / f"bytes{index}"
        (workspace / "src").mkdir(parents=True)
        batches.append((workspace, campaign.byte_cases(workspace / "src", part)))
    workspace = root / "hostile"
    (workspace / "src").mkdir(parents=True)
    batches.append(
        (
            workspace,
            campaign.huge_cases(workspace / "src")
            + campaign.hostile_cases(workspace / "src")
            + campaign.structural_cases(workspace / "src"),
        )
    )
    inputs = sum(len(cases) for _, cases in batches)
    assert inputs >= 300, inputs
    try:
        for workspace, cases in batches:
            check(workspace, cases)
            install_like_colcon(workspace / "src", workspace / "install")
            check(workspace, cases, "--install-base", "install")
    finally:
        readable(root)
    print(
        f"campaign: {inputs} broken inputs, {2 * len(batches)} verify runs, 0 tracebacks, 0 hangs, 0 changes"
    )


@pytest.mark.slow
def test_campaign_build_mode(bases, tmp_path):
    """`verify --build`: broken packages whose build files still build (launch, models, RViz,
    meshes, links), built by real colcon into pkgforge's own folder."""
    campaign = Campaign(bases, tmp_path)
    workspace = tmp_path / "ws"
    (workspace / "src").mkdir(parents=True)
    src = workspace / "src"
    # a colcon build costs seconds per package: several broken inputs share each package here
    parameters = {"fraction": 0.5, "positions": [10, 200, 400], "values": [0x20, 0x41, 0xFF]}
    damage = {
        "cbasepy": [("launch.py", "truncate"), ("urdf", "bom"), ("rviz", "flip"), ("stl", "empty")],
        "cbasexml": [("launch.xml", "flip"), "link cycle", "link out of the tree"],
        "cbaseyaml": [("launch.yaml", "utf-16"), ("urdf", "truncate"), "mesh replaced by a link out"],
    }
    cases = []
    for base, inputs in damage.items():
        name, package = campaign.package(src, base)
        done = []
        for item in inputs:
            if isinstance(item, tuple):
                done.append(apply_bytes(package, *item, parameters))
            else:
                structural(package, item, campaign.outside)
                done.append(item)
        cases += [Case(name, base, what) for what in done]
    name, package = campaign.package(src, "cbasepy")
    for file in ("writes.launch.py", "kill.launch.py", "loop.launch.py"):
        (package / "launch" / file).write_text(HOSTILE_LAUNCH[file])
        cases.append(Case(name, "cbasepy", f"hostile {file}"))
    try:
        check(workspace, cases, "--build")
    finally:
        readable(tmp_path)


# --- migrate --gazebo on broken ROS 1 input (issue 31) ------------------------------------------

GAZEBO_MODEL, GAZEBO_CONTROLLERS, GAZEBO_LAUNCH = (
    "urdf/sim_bot.urdf.xacro",
    "config/controllers.yaml",
    "launch/gazebo.launch",
)
# what is broken → (file of migrate_fixtures.ros1_gazebo_package, text replaced or None for the
# whole file, the new text): controller YAML, transmissions, Classic plugins, the launch file's
# <rosparam> and spawner
HOSTILE_GAZEBO_MIGRATE: dict[str, tuple[str, str | None, str | bytes]] = {
    "controllers not YAML": (GAZEBO_CONTROLLERS, None, "a: [\n"),
    "controllers alias bomb": (GAZEBO_CONTROLLERS, None, "\n".join(ALIAS_BOMB) + "\n"),
    "controllers nested 5000 deep": (GAZEBO_CONTROLLERS, None, "a: " + "[" * 5000 + "]" * 5000 + "\n"),
    "controllers a list": (GAZEBO_CONTROLLERS, None, "- type: x/Y\n"),
    "controllers with odd values": (
        GAZEBO_CONTROLLERS,
        None,
        "c1: {type: 123}\nc2: {type: [a/b]}\nc3: {type: position_controllers/JointTrajectoryController, "
        "joints: {a: 1}}\nc4: {type: diff_drive_controller/DiffDriveController, left_wheel: {x: 1}, right_wheel: 5}\n",
    ),
    "controllers binary": (GAZEBO_CONTROLLERS, None, b"\xff\xfe\x00\x01type: \x80\n"),
    "controllers empty": (GAZEBO_CONTROLLERS, None, ""),
    "only controllers with no ROS 2 type": (
        GAZEBO_CONTROLLERS,
        None,
        "pid: {type: effort_controllers/JointPositionController, joint: arm_joint}\n",
    ),
    "transmission with no interface": (GAZEBO_MODEL, "hardware_interface/PositionJointInterface", ""),
    "transmission with a state interface": (
        GAZEBO_MODEL,
        "hardware_interface/PositionJointInterface",
        "hardware_interface/JointStateInterface",
    ),
    "transmission names with markup": (
        GAZEBO_MODEL,
        '<transmission name="arm_transmission">',
        '<transmission name="a&quot;&lt;b&amp;">',
    ),
    "plugin filename an unknown property": (
        GAZEBO_MODEL,
        'filename="libgazebo_ros_diff_drive.so"',
        'filename="${nope}"',
    ),
    "plugin filename empty": (GAZEBO_MODEL, 'filename="libgazebo_ros_diff_drive.so"', 'filename=""'),
    "wheel diameter no number": (
        GAZEBO_MODEL,
        "<wheelDiameter>0.1</wheelDiameter>",
        "<wheelDiameter>abc</wheelDiameter>",
    ),
    "wheel diameter nested expression": (
        GAZEBO_MODEL,
        "<wheelDiameter>0.1</wheelDiameter>",
        "<wheelDiameter>${2*${r}}</wheelDiameter>",
    ),
    "Classic plugin at the robot's root": (
        GAZEBO_MODEL,
        '  <gazebo>\n    <plugin name="gazebo_ros_control"',
        '  <plugin name="x" filename="libgazebo_ros_p3d.so"/>\n  <gazebo>\n    <plugin name="gazebo_ros_control"',
    ),
    "model with an external entity": (
        GAZEBO_MODEL,
        '<?xml version="1.0"?>',
        '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>',
    ),
    "rosparam file computed": (GAZEBO_LAUNCH, "config/controllers.yaml", "config/$(arg c).yaml"),
    "rosparam file missing": (GAZEBO_LAUNCH, "config/controllers.yaml", "config/none.yaml"),
    "rosparam file a folder": (GAZEBO_LAUNCH, "config/controllers.yaml", "config"),
    "rosparam file of another package": (GAZEBO_LAUNCH, "$(find sim_bot)/config", "$(find other_pkg)/config"),
    "spawner arguments computed": (
        GAZEBO_LAUNCH,
        'args="joint_state_controller arm_controller"',
        'args="$(arg controllers)"',
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("what", list(HOSTILE_GAZEBO_MIGRATE))
def test_campaign_migrate_gazebo(tmp_path, what):
    """`migrate --gazebo` of a broken ROS 1 Gazebo package: no traceback, exit 0, 1 or 2, nothing
    of the source changed, nothing written on exit 2, every note naming a file."""
    from migrate_fixtures import ros1_gazebo_package

    relative, old, new = HOSTILE_GAZEBO_MIGRATE[what]
    source = ros1_gazebo_package(tmp_path / "ros1", "sim_bot")
    path = source / relative
    if old is None:
        path.write_bytes(new if isinstance(new, bytes) else new.encode())
    else:
        text = path.read_text()
        assert old in text
        path.write_text(text.replace(old, str(new), 1))
    before = fingerprint(source)
    (tmp_path / "ws" / "src").mkdir(parents=True)
    result = run_pkgforge(
        "migrate",
        source,
        "--gazebo",
        "--distro",
        "jazzy",
        "--destination",
        "src",
        cwd=tmp_path / "ws",
        timeout=300,
    )
    assert "Traceback" not in result.stdout + result.stderr, result.stderr
    assert result.returncode in (0, 1, 2), result.stdout + result.stderr
    assert fingerprint(source) == before
    if result.returncode == 2:
        assert not (tmp_path / "ws" / "src" / "sim_bot").exists()
        assert len(result.stderr.strip().splitlines()) == 1 and "(nothing written)" in result.stderr
    notes = [line for line in result.stdout.splitlines() if re.search(r" PF\d{3} \[", line)]
    assert all(re.match(r"^\S+: PF\d{3} \[", line) for line in notes), notes
