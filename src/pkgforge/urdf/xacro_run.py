"""The one run of the real xacro library on a model, and where a failure of it is: the file and
line a person would edit, the argument it needed, ROS 1's tags, a recursion's macros.

Runs in the launch worker (xacro evaluates ${} and $(eval) expressions: user code).
"""

from __future__ import annotations

import dataclasses
import io
import os
import re
import sys
import typing
from collections.abc import Mapping
from typing import Any

from lxml import etree

from pkgforge.model.source import read_regular
from pkgforge.sandbox.protocol import ErrorRecord
from pkgforge.urdf.ros1_xacro import describe, ros1_tags
from pkgforge.urdf.structure import ModelReply, ModelStatus, Ros1Tag

# a ${...} or $(...) inside an attribute's value: what xacro writes there is known only after it ran
EXPRESSION = re.compile(r"\$\{[^}]*\}|\$\([^)]*\)")

NEEDS_ARGUMENT = re.compile(r"[Uu]ndefined substitution argument (\S+)")
MAX_MODEL_BYTES = 8 * 1024 * 1024
# libxml2 refuses elements nested deeper than this (unless told XML_PARSE_HUGE), in these words
MAX_XML_DEPTH = 256
LIBXML_TOO_DEEP = f"Excessive depth in document: {MAX_XML_DEPTH}"
# xacro:args with an empty default tried one by one when a model fails on its own (each is a run)
MAX_BLAME_RUNS = 8
XACRO_ARG = r"<xacro:arg\b[^>]*\bname\s*=\s*[\"']{}[\"']"


@dataclasses.dataclass
class XacroRun:
    """One run of the real xacro library on one file: the document it produced (None when it
    failed), the files it included (absolute, sorted, the file itself left out), what it wrote
    to stderr, and the exception it failed with. After a failure, xacro's module state
    (filestack, macrostack, all_includes) still describes the failed run."""

    document: typing.Any
    includes: list[str]
    stderr: str
    failure: BaseException | None


def run_xacro(path: str, mappings: dict[str, str]) -> XacroRun:
    """The one xacro runner: the model worker and a launch file's Command(['xacro', ...]) both
    call it. `mappings` is xacro's own: it adds the model's xacro:arg defaults to it as it
    reads them. Uses the real process_file even when the launch worker watches the module
    (the launch file's own xacro calls are recorded; pkgforge's are not)."""
    import xacro

    process_file = getattr(xacro, "_pkgforge_real_process_file", xacro.process_file)
    stderr = io.StringIO()
    real_stderr, sys.stderr = sys.stderr, stderr
    # xacro keeps module state between runs: a fresh include list for each run
    xacro.all_includes[:] = []
    try:
        document = process_file(path, mappings=mappings)
        includes = sorted({os.path.abspath(f) for f in xacro.all_includes} - {os.path.abspath(path)})
        return XacroRun(document, includes, stderr.getvalue(), None)
    except BaseException as exc:  # XacroException, XML errors, IOError, SystemExit from xacro's own checks
        return XacroRun(None, [], stderr.getvalue(), exc)
    finally:
        sys.stderr = real_stderr


def expand(path: str, raw: str, mappings: dict[str, str]) -> tuple[str, list[str] | None] | ModelReply:
    """The xacro output of the model at `path`, whose text is `raw` (or the text itself when it
    uses no xacro), with the files it included (None: the file itself); or the reply saying why
    there is none."""
    if "xacro" not in raw:
        return raw, None  # no includes: the output is the file itself
    import xacro

    arguments = dict(mappings)  # xacro adds the model's own xacro:arg defaults to it as it reads them
    run = run_xacro(path, arguments)
    exc = run.failure
    if exc is None:
        output: str = run.document.toxml()
        return output, run.includes
    if isinstance(exc, RecursionError) or "recursion depth" in str(exc):
        return _recursion_error(xacro, path)
    status, record = _xacro_error(xacro, exc, path, mappings)
    # ROS 1's bare <macro>, <property> ... in the files xacro read: the failure is theirs (a
    # macro's parameter undefined where ROS 2's xacro evaluates the bare <macro>'s body)
    read = [path, *(f for f in (getattr(xacro, "all_includes", None) or []) if f != path)]
    tags = ros1_tags(read) if status == "error" and record["stage"] == "xacro" else []
    if tags:
        return {"status": "error", "error": _ros1_error(path, tags, record)}
    if (
        not mappings and status == "error" and record["stage"] == "xacro" and "type" not in record
    ):  # a worker limit hit: no second run
        status = _blame_empty_arguments(xacro, path, record, arguments) or status
    return {"status": status, "error": record}


def _ros1_error(path: str, tags: list[Ros1Tag], failure: ErrorRecord) -> ErrorRecord:
    """The error of a model whose xacro run failed with ROS 1's bare xacro tags in its files: at
    the first tag, naming them all and what xacro then said."""
    first = tags[0]
    said = [line.strip() for line in str(failure.get("message") or "").strip().splitlines()]
    return {
        "message": f"{describe(tags, path)}: ROS 1's xacro tags without the xacro: prefix, which ROS 2's "
        "xacro does not process (it keeps them as plain elements)"
        + (f"; xacro then fails: {said[0]}" if said else ""),
        "file": first["file"],
        "line": first["line"],
        "stage": "ros1-xacro",
        "hint": f"write <xacro:{first['tag']}> (each of them with the xacro: prefix), with "
        'xmlns:xacro="http://www.ros.org/wiki/xacro" on <robot>',
    }


def _blame_empty_arguments(
    xacro: Any, path: str, error: ErrorRecord, declared: dict[str, str]
) -> ModelStatus | None:
    """A model run on its own with its defaults whose failure comes from xacro:args declared with
    an empty default (values its launch files always give, e.g. dof:=7 naming the file to include)
    needs those values: it becomes needs-arguments, naming them. The test: xacro run again with one
    such argument set to a stand-in value fails otherwise (or not at all); a defect of its own
    fails the same whatever the value. Returns the new status (needs-arguments), or None."""
    failure = (error["message"], error["file"], error["line"])
    blamed: list[str] = []
    for name in [n for n, value in declared.items() if value == ""][:MAX_BLAME_RUNS]:
        exc = run_xacro(path, {name: f"pkgforge-stand-in-{name}"}).failure
        if exc is None:
            blamed.append(name)
            continue
        if isinstance(exc, RecursionError) or "recursion depth" in str(exc):
            continue
        again = _xacro_error(xacro, exc, path, {})[1]
        if (again["message"], again["file"], again["line"]) != failure:
            blamed.append(name)
    if not blamed:
        return None
    file, line = _declaration(path, blamed[0], xacro)
    # the failure keeps its own place (a launch file giving no value makes it an error there)
    error["arguments"], error["argument"], error["declared"] = blamed, blamed[0], {"file": file, "line": line}
    return "needs-arguments"


def _recursion_error(xacro: Any, path: str) -> ModelReply:
    stack = list(getattr(xacro, "filestack", None) or [path])
    repeated = next((f for f in stack if stack.count(f) > 1), None)
    # xacro leaves the macros it was expanding on its macrostack when it fails
    macros = list(getattr(xacro, "macrostack", None) or [])
    names = [m.body.getAttribute("name") if getattr(m, "body", None) is not None else "" for m in macros]
    looping = next((i for i, n in enumerate(names) if n and names.count(n) > 1), None)
    if repeated is None and looping is not None:
        name = names[looping].removeprefix("xacro:")
        history = getattr(macros[looping], "history", None) or [[]]
        file = (history[-1][-1] if history[-1] else None) or stack[-1]
        return {
            "status": "error",
            "error": {
                "message": f"macro {name} calls itself (directly or through another macro) and nothing ends "
                "the calls: xacro recursed without end",
                "file": file,
                "line": _line_matching(file, re.compile(rf"<xacro:{re.escape(name)}[\s/>]")),
                "stage": "xacro",
                "hint": f"give the call of {name} inside its own body an xacro:if/xacro:unless that becomes "
                "false (a counter parameter), or call another macro",
            },
        }
    if repeated is None:  # no file includes itself, no macro calls itself: nesting xacro recursed into
        return _too_deep(list(dict.fromkeys([*(f for f in reversed(stack) if f), path])), len(macros))
    return {
        "status": "error",
        "error": {
            "message": f"{os.path.basename(repeated)} includes itself (directly or through another file): "
            "xacro recursed without end",
            "file": repeated,
            "line": _line_mentioning(repeated, "xacro:include"),
            "stage": "xacro",
        },
    }


def _too_deep(files: list[str], macros: int) -> ModelReply:
    """xacro ran out of stack with nothing repeating: the file (the innermost of the include chain
    first) whose elements nest deeper than libxml2 reads them, at the line where they pass it;
    else macros calling other macros too deep."""
    for file in files:
        try:
            etree.fromstring(read_regular(file, MAX_MODEL_BYTES), etree.XMLParser(huge_tree=False))
        except etree.XMLSyntaxError as exc:
            if exc.msg and exc.msg.startswith(LIBXML_TOO_DEEP):
                return {
                    "status": "error",
                    "error": {
                        "message": f"elements nest deeper than {MAX_XML_DEPTH} levels here: xacro recurses "
                        "once per level, and ran out of stack",
                        "file": file,
                        "line": exc.lineno,
                        "stage": "xacro",
                        "hint": "nest the elements less deeply (a robot's elements nest a few levels)",
                    },
                }
        except (OSError, ValueError):
            continue
    return {
        "status": "error",
        "error": {
            "message": f"xacro recursed too deep ({macros} macros were calling one another, none itself): "
            "it ran out of stack",
            "file": files[0],
            "line": None,
            "stage": "xacro",
        },
    }


def _xacro_error(
    xacro: Any, exc: BaseException, path: str, mappings: Mapping[str, str]
) -> tuple[ModelStatus, ErrorRecord]:
    message = getattr(exc, "msg", None) or str(exc) or type(exc).__name__
    macro = getattr(exc, "macro", None)  # xacro's XacroException names the macro it was in
    if isinstance(macro, str):
        message = f"{message} (in macro {macro})"
    needs = NEEDS_ARGUMENT.search(message)
    status: ModelStatus = "needs-arguments" if needs and not mappings else "error"
    file, line = _xacro_location(exc, path, getattr(xacro, "filestack", None) or [])
    if line is None:  # the culprit may stand in a file the model included (a macro's body)
        file, line = _in_includes(exc, file, getattr(xacro, "all_includes", None) or [])
    stage = "xml" if "ExpatError" in type(exc).__name__ or "not well-formed" in message else "xacro"
    error: ErrorRecord = {
        "message": _said_once(message.strip()),
        "file": file,
        "line": line,
        "argument": needs.group(1) if needs else None,
        "stage": stage,
    }
    cause: BaseException | None = exc
    seen: set[int] = set()
    while cause is not None and id(cause) not in seen:  # a worker limit hit inside xacro: the worker names it
        seen.add(id(cause))
        if isinstance(cause, MemoryError):
            error["type"] = "MemoryError"
        cause = getattr(cause, "exc", None) or cause.__cause__ or cause.__context__
    return status, error


ERRNO = re.compile(r"\s*\[Errno \d+\] ([^:\[\]]+): '([^']*)'")


def _said_once(message: str) -> str:
    """xacro's message without the OSError it appends when it said the same already
    ("No such file or directory: a.xacro [Errno 2] No such file or directory: 'a.xacro'")."""

    def repeated(match: re.Match[str]) -> str:
        said = f"{match.group(1)}: {match.group(2)}"
        return "" if said in message[: match.start()] else match.group(0)

    return ERRNO.sub(repeated, message)


def _xacro_location(exc: BaseException, path: str, filestack: list[str]) -> tuple[str, int | None]:
    """The file xacro was in when it failed (the end of its include chain), and the line naming the culprit."""
    file = next((f for f in reversed(filestack) if f), path)
    line = None
    text = str(exc)
    missing = re.search(r"No such file or directory: \[?'?([^'\]\s]+)", text)
    undefined = re.search(r"name '([^']+)' is not defined", text) or re.search(
        r"[Uu]ndefined substitution argument (\S+)", text
    )
    package = re.search(r"package '([^']+)' not found", text)
    # a macro called with a parameter it does not declare: the call that passes it
    parameter = re.search(r'Invalid parameter "([^"]+)"', text)
    if missing:
        line = _line_mentioning(file, os.path.basename(missing.group(1))) or _include_line(
            file, missing.group(1)
        )
    elif undefined:
        line = _line_mentioning(file, undefined.group(1))
    elif package:
        line = _line_mentioning(file, f"$(find {package.group(1)}")
    elif parameter:
        line = _attribute_line(file, parameter.group(1))
    return file, line


def _in_includes(exc: BaseException, file: str, includes: list[str]) -> tuple[str, int | None]:
    """Where in the files the model included the culprit of a failure stands (an include built
    from a macro's parameters, a macro call), when the file xacro was in does not hold it."""
    text = str(exc)
    missing = re.search(r"No such file or directory: \[?'?([^'\]\s]+)", text)
    parameter = re.search(r'Invalid parameter "([^"]+)"', text)
    for include in includes:
        if include == file:
            continue
        line = None
        if missing:
            line = _include_line(include, missing.group(1))
        elif parameter:
            line = _attribute_line(include, parameter.group(1))
        if line is not None:
            return include, line
    return file, None


def _attribute_line(path: str, name: str) -> int | None:
    """The line of the attribute `name=` of a macro call (<xacro:NAME ... name="...">), which may
    span lines."""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            text = handle.read()
    except OSError:
        return None
    for call in re.finditer(
        r"<\s*xacro:(?!macro\b|include\b|property\b|arg\b|if\b|unless\b)[\w.-]+\b[^>]*>", text
    ):
        attribute = re.search(rf"\s{re.escape(name)}\s*=", call.group(0))
        if attribute is not None:
            return text.count("\n", 0, call.start() + attribute.start() + 1) + 1
    return None


INCLUDE_FILENAME = re.compile(r"<\s*xacro:include\b[^>]*?\bfilename\s*=\s*[\"']([^\"']+)[\"']")


def _include_line(path: str, missing: str) -> int | None:
    """The line of the <xacro:include> whose filename, built from arguments or properties
    (`arms/$(arg arm)_$(arg dof).xacro`), names the missing file: of those whose literal text
    matches it, the one with the most."""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            lines = handle.read().splitlines()
    except OSError:
        return None
    best: tuple[int, int] | None = None  # (literal characters, line)
    for number, text in enumerate(lines, start=1):
        for match in INCLUDE_FILENAME.finditer(text):
            pieces = EXPRESSION.split(match.group(1))
            literal = sum(map(len, pieces))
            pattern = ".*".join(re.escape(piece) for piece in pieces)
            if (
                literal >= 4
                and re.search(f"(?:^|/){pattern}$", missing)
                and (best is None or literal > best[0])
            ):
                best = (literal, number)
    return best[1] if best else None


def _declaration(path: str, name: str, xacro: Any) -> tuple[str, int | None]:
    """The file and line of <xacro:arg name="name">: the model's own, else a file it included."""
    pattern = re.compile(XACRO_ARG.format(re.escape(name)))
    for file in [path, *(f for f in (getattr(xacro, "all_includes", None) or []) if f != path)]:
        line = _line_matching(file, pattern)
        if line is not None:
            return file, line
    return path, None


def _line_matching(path: str, pattern: re.Pattern[str]) -> int | None:
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, start=1):
                if pattern.search(line):
                    return number
    except OSError:
        return None
    return None


def _line_mentioning(path: str, text: str) -> int | None:
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, start=1):
                if text in line:
                    return number
    except OSError:
        pass
    return None
