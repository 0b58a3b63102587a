"""launch.substitutions.Command: what a command substitution runs at verify time, and what it only records.

Real: launch/substitutions/command.py. Only a pure function of files runs (xacro with the
real library, cat...: records.runs_at_verify_time); a run-time query is recorded, not run.
"""

from __future__ import annotations

import os
import shlex
import subprocess

from pkgforge.launch.builtin.launch.errors import SubstitutionFailure, Unresolved
from pkgforge.launch.builtin.launch.launch_context import (
    MISSING_PACKAGE_ROOT,
    RECORDER,
    LaunchContext,
    record_path,
)
from pkgforge.launch.builtin.launch.substitution import (
    SomeSubstitutionsType,
    Substitution,
    normalize,
    perform_substitutions,
)
from pkgforge.launch.records import CommandRunRecordDict, runs_at_verify_time

_RUNNING_XACRO = False  # pkgforge's own xacro run (a Command), not the launch file's


def running_xacro() -> bool:
    """Whether pkgforge's own xacro run (a Command) is what reads now, not the launch file."""
    return _RUNNING_XACRO


class Command(Substitution):
    """Runs only what is a pure function of files (records.runs_at_verify_time); any other
    command (a `ros2 param get`, a script) is run-time only: recorded, not run."""

    def __init__(self, command: SomeSubstitutionsType, *, on_stderr: SomeSubstitutionsType = "fail") -> None:
        super().__init__()
        self.command = normalize(command)
        self.on_stderr = normalize(on_stderr)

    def perform(self, context: LaunchContext) -> str:
        return command_output(
            self, perform_substitutions(context, self.command), perform_substitutions(context, self.on_stderr)
        )


def command_output(
    owner: object, text: str, on_stderr: str, failure: type[Exception] = SubstitutionFailure
) -> str:
    """`Command.perform` of both engines (the real engine's Command calls it too, with launch's
    own SubstitutionFailure): launch's on_stderr rule; a command verify may run is run (once per
    file) and recorded; a run-time only one is recorded as such and its output is '' ."""
    words = shlex.split(text)
    if not words:
        raise failure("empty command")
    if on_stderr not in ("fail", "ignore", "warn", "capture"):
        raise failure("expected 'on_stderr' to be one of: 'fail', 'ignore', 'warn' or 'capture'")
    if not runs_at_verify_time(words):
        RECORDER.add(
            "commands",
            {"command": words, "text": text, "ok": True, "message": "", "runtime_only": True},
            owner,
        )
        return ""
    if any(w.startswith(MISSING_PACKAGE_ROOT) for w in words):
        raise Unresolved(f"<{words[0]} of a file in a package not found>")
    key = tuple(words)
    if key not in RECORDER.command_cache:
        RECORDER.command_cache[key] = _run_command(words)
    ok, output, message, extra = RECORDER.command_cache[key]
    stderr = extra.get("stderr", "")
    extra = extra.copy()  # (the cached one stays whole)
    extra.pop("stderr", None)
    problem = None
    if ok and stderr and on_stderr == "fail":
        # launch fails a Command that writes to stderr unless on_stderr says otherwise
        problem = f"executed command showed stderr output. Command: {text}\nCaptured stderr output:\n{stderr}"
        first = stderr.strip().splitlines()[0] if stderr.strip() else ""
        ok, message = (
            False,
            (
                f"{first} (written to stderr: Command's on_stderr='fail' stops the launch; "
                "fix the warning or pass on_stderr='warn')"
            ),
        )
    elif ok and stderr and on_stderr == "capture":
        output = output + stderr
    record: CommandRunRecordDict = {"command": words, "text": text, "ok": ok, "message": message, **extra}
    if os.path.basename(words[0]) == "xacro":
        RECORDER.add("packages", {"name": "xacro", "via": "Command xacro"}, owner)
        for word in words[1:]:
            if ":=" not in word and not word.startswith("-"):
                record_path(word, owner, "xacro input")
                record["model"] = word
                break
        record["mappings"] = dict(w.split(":=", 1) for w in words[1:] if ":=" in w)
    RECORDER.add("commands", record, owner)
    if not ok:
        raise failure(
            problem if problem is not None else f"executed command failed. Command: {text}\n{message}"
        )
    return output


def _run_command(words: list[str]) -> tuple[bool, str, str, CommandRunRecordDict]:
    """Run a Command; xacro runs in this process with the real xacro library."""
    if os.path.basename(words[0]) == "xacro":
        return _run_xacro(words[1:])
    try:
        done = subprocess.run(words, capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    except FileNotFoundError as exc:
        return False, "", f"file not found: {exc}", {}
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, "", str(exc), {}
    if done.returncode != 0:
        return False, "", (f"Captured stderr output: {done.stderr}" if done.stderr else ""), {}
    return True, done.stdout, "", {"stderr": done.stderr}


def _run_xacro(args: list[str]) -> tuple[bool, str, str, CommandRunRecordDict]:
    """xacro with the real library (urdf.xacro_run's runner); a success also yields the model's
    structure, so the model checks need not run xacro on it a second time."""
    from pkgforge.urdf.robot import structure_of_output
    from pkgforge.urdf.xacro_run import run_xacro

    files = [a for a in args if ":=" not in a and not a.startswith("-")]
    mappings = dict(a.split(":=", 1) for a in args if ":=" in a)
    if not files:
        return False, "", "xacro: no input file", {}
    global _RUNNING_XACRO
    _RUNNING_XACRO = True
    try:
        run = run_xacro(files[0], mappings)
    finally:
        _RUNNING_XACRO = False
    if run.failure is not None:
        exc = run.failure
        message = getattr(exc, "msg", None) or str(exc) or type(exc).__name__
        return False, "", f"{message}\n{run.stderr.strip()}".strip(), {}
    output = run.document.toprettyxml(indent="  ")
    robot = structure_of_output(files[0], output, run.includes)
    found: CommandRunRecordDict = {"robot": robot, "includes": run.includes} if robot else {}
    return True, output, "", {**found, "stderr": run.stderr}
