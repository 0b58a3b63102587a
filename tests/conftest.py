"""Shared helpers and session fixtures: real `pkgforge`, real colcon, real xacro."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

FIXTURES = Path(__file__).parent / "fixtures"
SCRIPTS = Path(sysconfig.get_path("scripts"))

# Every scaffold variant the acceptance matrix names: each distro (py launch),
# each launch format, and ament_python (with py and xml launch files).
VARIANTS = {
    "v_humble": ["--distro", "humble"],
    "v_jazzy": ["--distro", "jazzy"],
    "v_kilted": ["--distro", "kilted"],
    "v_lyrical": ["--distro", "lyrical"],
    "v_rolling": ["--distro", "rolling"],
    "v_xml": ["--launch-format", "xml"],
    "v_yaml": ["--launch-format", "yaml"],
    "v_humble_xml": ["--launch-format", "xml", "--distro", "humble"],
    "v_humble_yaml": ["--launch-format", "yaml", "--distro", "humble"],
    "v_python": ["--build-type", "ament_python"],
    "v_python_xml": ["--build-type", "ament_python", "--launch-format", "xml"],
}

MAINTAINER = ["--maintainer-name", "Test Maintainer", "--maintainer-email", "test@example.com"]
# the command line prefix that runs what follows as nobody (root only; setpriv is util-linux)
NOBODY = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]


def pytest_sessionstart(session: pytest.Session) -> None:
    """The tests run the installed pkgforge: a non-editable install older than src/ (scripts/bootstrap
    installs a copy, as CI does) would test the old code and pass. Stop at once when a file differs."""
    import importlib.util

    spec = importlib.util.find_spec("pkgforge")
    source = Path(__file__).resolve().parent.parent / "src" / "pkgforge"
    if spec is None or spec.origin is None or not source.is_dir():
        return
    installed = Path(spec.origin).resolve().parent
    if installed == source.resolve():
        return  # editable
    stale = [
        path.relative_to(source)
        for path in sorted(source.rglob("*"))
        if path.is_file()
        and "__pycache__" not in path.parts
        and (
            not (installed / path.relative_to(source)).is_file()
            or (installed / path.relative_to(source)).read_bytes() != path.read_bytes()
        )
    ]
    if stale:
        pytest.exit(
            f"the installed pkgforge ({installed}) is not src/ ({stale[0]} differs, {len(stale)} in all): "
            "run scripts/bootstrap test again, or .venv/bin/pip install -e '.[ament,test]'",
            returncode=2,
        )


# every check code a real pkgforge run printed in this session: a test marked
# @pytest.mark.triggers(CODE) must have made pkgforge print CODE (see _triggers_printed)
PRINTED_CODES: set[str] = set()


def run_command(
    command: list, *, cwd: Path | None = None, env: dict | None = None, timeout: float = 300
) -> subprocess.CompletedProcess:
    """A command in a subprocess as a user runs it: its output captured as text, no input (a
    prompt is not answered), and a hang guard (`timeout`, not a timing assert)."""
    return subprocess.run(
        [str(word) for word in command],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
        stdin=subprocess.DEVNULL,
        env=env,
    )


def run_pkgforge(*args, cwd: Path, env: dict | None = None, timeout: float = 900):
    """Run the installed pkgforge in a subprocess, as a user would."""
    import re

    result = run_command([sys.executable, "-m", "pkgforge", *args], cwd=cwd, env=env, timeout=timeout)
    printed = (result.stdout or "") + (result.stderr or "")
    words = list(map(str, args))
    for option, value in zip(words, words[1:], strict=False):  # and the report files it wrote
        if option in ("--output", "-o", "--junit-xml") and (Path(cwd) / value).is_file():
            printed += (Path(cwd) / value).read_text(errors="replace")
    PRINTED_CODES.update(re.findall(r"\bPF\d{3}\b", printed))
    return result


@pytest.fixture(autouse=True)
def _triggers_printed(request):
    """A test marked @pytest.mark.triggers(CODE) ran the real pkgforge and it printed CODE
    (tests/test_conventions.py counts the marks: every check code needs one)."""
    yield
    marker = request.node.get_closest_marker("triggers")
    if marker is not None:
        missing = sorted(set(marker.args) - PRINTED_CODES)
        if missing:
            pytest.fail(
                f"{request.node.nodeid} is marked triggers({', '.join(missing)}) but no "
                f"pkgforge it ran (conftest.run_pkgforge) printed {', '.join(missing)}"
            )


def colcon(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    """The installed colcon (with pkgforge's verb), run in a subprocess as a user would."""
    return run_command([SCRIPTS / "colcon", *args], cwd=cwd, env=env, timeout=600)


def new_package(workspace: Path, name: str, *options: str) -> Path:
    result = run_pkgforge("new", name, *MAINTAINER, *options, cwd=workspace)
    assert result.returncode == 0, result.stderr
    return workspace / "src" / name


def copy_fixture(relative: str, workspace: Path) -> Path:
    source = FIXTURES / relative
    target = workspace / "src" / source.name
    shutil.copytree(source, target)
    return target


def line_of(path: Path, text: str) -> int:
    """The first line of path that contains text (tests assert exact lines with it)."""
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if text in line:
            return number
    raise AssertionError(f"{text!r} not in {path}")


def lines_of(path: Path, text: str) -> list[int]:
    """Every line of path that contains text."""
    found = [n for n, line in enumerate(path.read_text().splitlines(), start=1) if text in line]
    assert found, f"{text!r} not in {path}"
    return found


def edit(path: Path, old: str, new: str) -> None:
    """Replace old (which must be there) by new, once."""
    content = path.read_text()
    assert old in content, f"{old!r} not in {path}"
    path.write_text(content.replace(old, new, 1))


def hand_made_install(package: Path, layout: str = "merged") -> Path:
    """An install folder as colcon builds it for the package, in its workspace (without running
    colcon): the package's share folder in it."""
    install = package.parent.parent / "install"
    prefix = install if layout == "merged" else install / package.name
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / package.name).touch()
    (install / "COLCON_IGNORE").touch()
    (install / ".colcon_install_layout").write_text(f"{layout}\n")
    share = prefix / "share" / package.name
    for folder in ("launch", "urdf", "meshes", "rviz"):
        shutil.copytree(package / folder, share / folder)
    shutil.copy(package / "package.xml", share)
    return share


def verify_report(path: Path, *args: str) -> tuple[int, dict]:
    """`pkgforge verify PATH --format json ARGS` run in PATH: (exit status, report)."""
    import json

    result = run_pkgforge("verify", path, "--format", "json", *args, cwd=path)
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode in (0, 1), result.stdout + result.stderr
    return result.returncode, json.loads(result.stdout)


SEVERITIES = ["info", "warning", "error"]


def at_least(report: dict, minimum: str) -> list[dict]:
    return [d for d in report["diagnostics"] if SEVERITIES.index(d["severity"]) >= SEVERITIES.index(minimum)]


def xacro_command(model: Path, install: Path):
    """The real xacro command line tool against an install tree."""
    env = dict(os.environ, AMENT_PREFIX_PATH=str(install))
    return run_command([SCRIPTS / "xacro", model], env=env, timeout=60)


@pytest.fixture(scope="session")
def variants_workspace(tmp_path_factory) -> Path:
    """One workspace holding every scaffold variant, built once with `pkgforge build`."""
    workspace = tmp_path_factory.mktemp("variants")
    (workspace / "src").mkdir()
    for name, options in VARIANTS.items():
        new_package(workspace, name, *options)
    result = run_pkgforge("build", cwd=workspace)
    assert result.returncode == 0, result.stdout + result.stderr
    return workspace


@pytest.fixture(scope="session")
def template_package(tmp_path_factory) -> Path:
    """One clean `pkgforge new` package, made once; tests copy it, never change it."""
    folder = tmp_path_factory.mktemp("template")
    result = run_pkgforge("new", "rob_description", *MAINTAINER, cwd=folder)
    assert result.returncode == 0, result.stderr
    return folder / "rob_description"


@pytest.fixture
def package(tmp_path, template_package) -> Path:
    """A fresh copy of a clean package in a workspace (tmp_path), to break in one place."""
    target = tmp_path / "src" / "rob_description"
    shutil.copytree(template_package, target)
    return target
