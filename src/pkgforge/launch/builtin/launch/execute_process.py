"""launch.actions.ExecuteProcess and ExecuteLocal: the command a process would run, recorded, not started.

Real: launch/actions/execute_process.py, launch/actions/execute_local.py.
"""

from __future__ import annotations

import os
import re
import shlex
from collections.abc import Iterable, Sequence
from typing import Any

from pkgforge.launch.builtin.launch.action import Action
from pkgforge.launch.builtin.launch.errors import failure_text
from pkgforge.launch.builtin.launch.launch_context import RECORDER, LaunchContext
from pkgforge.launch.builtin.launch.substitution import SomeSubstitutionsType, normalize, perform
from pkgforge.launch.builtin.launch.substitutions import _typed_bool
from pkgforge.launch.records import ExecutionRecordDict


class ExecuteProcess(Action):
    def __init__(
        self,
        *,
        cmd: Iterable[SomeSubstitutionsType],
        name: SomeSubstitutionsType | None = None,
        cwd: SomeSubstitutionsType | None = None,
        env: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        additional_env: dict[SomeSubstitutionsType, SomeSubstitutionsType] | None = None,
        shell: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.cmd = cmd
        self.shell = shell
        self.process_name, self.cwd = name, cwd
        self.env, self.additional_env = env, additional_env
        # ExecuteLocal's: what its execute performs too (the rest is read only once it runs)
        self.prefix: SomeSubstitutionsType | None = kwargs.get("prefix")
        self.output: SomeSubstitutionsType | dict[str, str] = kwargs.get("output", "log")
        self.respawn: bool | SomeSubstitutionsType = kwargs.get("respawn", False)

    def visit(self, context: LaunchContext) -> None:
        cmd = list(self.cmd)
        RECORDER.add(
            "nodes",
            {"kind": "process", "cmd": [perform(context, part) for part in cmd], "shell": bool(self.shell)},
            self,
        )
        execute_process(context, self, cmd)


# an action's substitutions performed again as its execute performs them: what they record was
# recorded by the visit already (a package looked up for ExecutableInPackage is the node's own)
PREPARING = [False]


def execute_process(
    context: LaunchContext, action: ExecuteProcess, cmd: Sequence[SomeSubstitutionsType]
) -> None:
    """What launch's ExecuteLocal.execute performs before it starts the process (its prepare: the
    command, launch-prefix, name, cwd, environment, respawn; then output), recorded as the
    action's execution; a failure is recorded there too, and raised as launch raises it."""
    PREPARING[0] = True
    try:
        record = _prepared(context, action, cmd)
    except Exception as error:
        RECORDER.add("executions", {"action": type(action).__name__, "failure": failure_text(error)}, action)
        raise
    finally:
        PREPARING[0] = False
    RECORDER.add("executions", record, action)


def _prepared(
    context: LaunchContext, action: ExecuteProcess, cmd: Sequence[SomeSubstitutionsType]
) -> ExecutionRecordDict:
    """launch.descriptions.Executable.prepare and ExecuteLocal's, in their order."""
    words = [perform(context, part) for part in cmd]
    if action.prefix is None:
        # LaunchConfiguration('launch-prefix(-filter)', default=''): a regular expression the
        # executable's name must match for the prefix to apply
        pattern = context.launch_configurations.get("launch-prefix-filter", "")
        applies = re.match(pattern, os.path.basename(words[0])) is not None
        prefix = context.launch_configurations.get("launch-prefix", "") if applies else ""
    else:
        prefix = perform(context, action.prefix)
    words = shlex.split(prefix) + words
    name = (
        os.path.basename(words[0]) if action.process_name is None else perform(context, action.process_name)
    )
    cwd = None if action.cwd is None else perform(context, action.cwd)
    env = None if action.env is None else _environment(context, action.env)
    additional = _environment(context, action.additional_env or {})
    respawn = action.respawn
    if not isinstance(respawn, bool):
        respawn = _typed_bool(context, normalize(respawn))
    output = None if isinstance(action.output, dict) else perform(context, action.output)
    return {
        "action": type(action).__name__,
        "cmd": words,
        "name": name,
        "cwd": cwd,
        "env": env,
        "additional_env": additional,
        "output": output,
        "respawn": respawn,
    }


def _environment(
    context: LaunchContext, variables: dict[SomeSubstitutionsType, SomeSubstitutionsType]
) -> list[list[str]]:
    """env= or additional_env= performed, as launch joins them into one dict (a name twice: the last)."""
    joined = {perform(context, k): perform(context, v) for k, v in variables.items()}
    return [[k, v] for k, v in joined.items()]


class ExecuteLocal(ExecuteProcess):
    def __init__(self, *, process_description: object = None, **kwargs: Any) -> None:
        super().__init__(cmd=[], **kwargs)

    def visit(self, context: LaunchContext) -> None:  # (its description's command is not read)
        RECORDER.add("nodes", {"kind": "process", "cmd": []}, self)
