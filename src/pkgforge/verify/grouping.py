"""One cause, one diagnostic: the findings a check gives per item (each joint with velocity="0",
each node of a package not declared) shown as one diagnostic per file that names the items.

A check says which of its findings may group (Finding.group: the cause, the item, the grouped
message); this step groups them, for every check alike, after the suppression comments and
per-file ignores have removed what the user silenced line by line, so that a comment on one
joint's line silences that joint and no other. Each item's own message and line stay in the
diagnostic's detail (the JSON report).
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import replace

from pkgforge.diagnostics import MESSAGE_LIMIT, Diagnostic, PackageReport, one_line


def grouped(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """The diagnostics with those of one check, file, severity, cause (and fix) made one; the
    order of the first of each kept."""
    out: list[list[Diagnostic]] = []
    groups: dict[tuple[str, ...], list[Diagnostic]] = {}
    for diagnostic in diagnostics:
        group = diagnostic.group
        # (a finding without a Group groups with the same message, hint and fix at other lines)
        cause = ("group", group.cause) if group is not None else ("same", diagnostic.message, diagnostic.hint)
        key = (
            diagnostic.code,
            str(diagnostic.path),
            str(int(diagnostic.severity)),
            *cause,
            json.dumps(diagnostic.fix, sort_keys=True, default=str),
        )
        if key not in groups:
            groups[key] = []
            out.append(groups[key])
        groups[key].append(diagnostic)
    return [
        d for members in out for d in ([_one(members)] if members[0].group is not None else _same(members))
    ]


def _same(members: list[Diagnostic]) -> list[Diagnostic]:
    """One diagnostic for the same message at several lines of a file: at the first, naming the
    others (at one line, in several columns: each stays)."""
    members = sorted(members, key=lambda d: (d.line is None, d.line or 0, d.column or 0))
    first = members[0]
    lines = sorted({d.line for d in members if d.line is not None})
    if len(lines) < 2:
        return members
    room = MESSAGE_LIMIT - len(first.message) - len(" (lines )")
    message, detail = one_line(
        f"{first.message} (lines {listed([str(n) for n in lines], max(room, 20))})", _each(members)
    )
    return [replace(first, message=message, detail=detail)]


def _each(members: list[Diagnostic]) -> str:
    """The detail of a grouped diagnostic: each finding's line and whole text, one a line."""
    return "\n".join(
        (f"line {d.line}: " if d.line is not None else "") + (d.detail or d.message) for d in members
    )


def _one(members: list[Diagnostic]) -> Diagnostic:
    members = sorted(members, key=lambda d: (d.line is None, d.line or 0, d.column or 0))
    first = members[0]
    assert first.group is not None
    if len(members) == 1:
        return replace(first, group=None)
    items = list(dict.fromkeys(d.group.item for d in members if d.group is not None))
    lines = sorted({d.line for d in members if d.line is not None})
    each = _each(members)
    if len(items) == 1:  # one item found more than once (a mesh of two models): the first's message
        where = f" (lines {listed([str(n) for n in lines], 60)})" if len(lines) > 1 else ""
        message, detail = one_line(first.message + where, each)
        return replace(first, message=message, detail=detail, group=None)
    template = first.group.many
    bare = _filled(template, len(items), "")
    where = f" (lines {', '.join(map(str, lines))})" if len(lines) > 1 else ""
    room = MESSAGE_LIMIT - len(bare)
    if len(where) > room // 3:  # the items first; the lines as many as fit after them
        where = " (lines " + listed([str(n) for n in lines], room // 3 - len(" (lines )")) + ")"
    message = _filled(template, len(items), listed(items, room - len(where))) + where
    message, detail = one_line(message, each)
    return replace(first, message=message, detail=detail, group=None)


def _filled(template: str, count: int, items: str) -> str:
    """The group's message: its template with {count} and {items} put in (not str.format: the
    template holds names from the user's files, braces and all)."""
    return template.replace("{count}", str(count)).replace("{items}", items)


def listed(words: list[str], room: int) -> str:
    """words joined with ", ", as many as fit in `room` characters, then "and N more"."""
    text = ", ".join(words)
    if len(text) <= room:
        return text
    for count in range(len(words) - 1, 0, -1):
        text = f"{', '.join(words[:count])} and {len(words) - count} more"
        if len(text) <= room:
            return text
    return f"{words[0][: max(room - 20, 10)]} and {len(words) - 1} more"


def once_across_packages(reports: list[PackageReport]) -> list[PackageReport]:
    """The reports with a diagnostic that several packages give in the same file (a link of one
    package's model that three packages' launch files run xacro on: each package's check places it
    in the link's file, at its line, or at the link's own line where xacro's output hides the
    <limit>'s) kept once: by the package whose folder holds that file, else the first."""
    keeper: dict[tuple[object, ...], PackageReport] = {}
    for report in reports:
        for diagnostic in report.diagnostics:
            key = _place(diagnostic)
            kept = keeper.get(key)
            if kept is None or (
                diagnostic.path.is_relative_to(report.path) and not diagnostic.path.is_relative_to(kept.path)
            ):
                keeper[key] = report
    for report in reports:
        report.diagnostics = [d for d in report.diagnostics if keeper[_place(d)] is report]
    return reports


def _place(diagnostic: Diagnostic) -> tuple[object, ...]:
    return (diagnostic.code, str(diagnostic.path), diagnostic.message)
