"""The launch workers' fork server (sandbox/zygote.py): started early only when launch files or
models will be evaluated, and never left running after verify, whatever way verify ends."""

from __future__ import annotations

import os

import pytest
from test_processes import MARKER, marked

from pkgforge.errors import PkgforgeError
from pkgforge.verify.config import Selection
from pkgforge.verify.options import VerifyOptions
from pkgforge.verify.pipeline import _early_zygote, verify


def _fork_servers() -> list[int]:
    """The live fork servers started from this test (their environment holds its marker)."""
    return [pid for pid, command in marked(os.environ[MARKER]) if "--fork-server" in command]


@pytest.fixture(autouse=True)
def _marker(monkeypatch, request):
    monkeypatch.setenv(MARKER, f"zygote-{os.getpid()}-{request.node.name}")


def test_select_without_tree_checks_starts_no_fork_server():
    options = VerifyOptions(selection=Selection(select=["PF1"]), launch_engine="builtin")
    assert _early_zygote(options, options.engine()) is None
    assert _fork_servers() == []


def test_default_verify_starts_the_fork_server_and_close_ends_it():
    options = VerifyOptions(launch_engine="builtin")
    zygote = _early_zygote(options, options.engine())
    try:
        assert zygote is not None and _fork_servers() == [zygote.pid]
    finally:
        zygote.close()
    assert _fork_servers() == []


def test_fork_server_is_gone_when_verify_stops_with_an_error(tmp_path):
    (tmp_path / "src").mkdir()  # a workspace with no package: discovery fails after the server started
    with pytest.raises(PkgforgeError, match="no package found"):
        verify(tmp_path, VerifyOptions(launch_engine="builtin", use_cache=False))
    assert _fork_servers() == []


def test_cli_starts_the_fork_server_first_without_cache_and_ends_it_on_an_error(tmp_path):
    """`verify --no-cache` starts the server before its own imports (cli.verify._fork_server_first); a
    verify that stops with an error before it would have started one (a path that is not there)
    still ends it, and says why on one line."""
    from click.testing import CliRunner

    from pkgforge.cli import main
    from pkgforge.cli import verify as command

    started: list[int | None] = []
    first = command._fork_server_first

    def recorded(*args):
        server = first(*args)
        started.append(server.pid if server is not None else None)
        return server

    missing = tmp_path / "missing"
    command._fork_server_first = recorded
    try:
        result = CliRunner().invoke(
            main, ["verify", str(missing), "--no-cache", "--launch-engine", "builtin"]
        )
    finally:
        command._fork_server_first = first
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [f"pkgforge: error: {missing} does not exist"]
    assert len(started) == 1 and started[0] is not None
    assert _fork_servers() == []


def test_the_fork_server_writes_no_byte_code_beside_a_module_from_the_user_s_path(tmp_path, template_package):
    """The server's preload imports ament_index_python (and xacro) from the user's PYTHONPATH when
    it is there (a sourced overlay): nothing may be written in those folders, even where the
    interpreter would write byte code."""
    import shutil
    from pathlib import Path

    from conftest import run_pkgforge

    import pkgforge

    overlay = tmp_path / "overlay"
    stand_in = Path(pkgforge.__file__).parent / "launch" / "api_ament" / "ament_index_python"
    shutil.copytree(stand_in, overlay / "ament_index_python", ignore=shutil.ignore_patterns("__pycache__"))
    workspace = tmp_path / "ws"
    shutil.copytree(template_package, workspace / "src" / "rob_description")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(overlay), env.get("PYTHONPATH")]))
    result = run_pkgforge("verify", "src/rob_description", "--no-cache", cwd=workspace, env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    assert not list(overlay.rglob("__pycache__")) and not list(overlay.rglob("*.pyc"))
