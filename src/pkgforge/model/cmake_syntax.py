"""The CMake language's syntax: command invocations with their arguments and lines.

Follows cmake-language(7): line comments, bracket comments and arguments
(`[==[ ... ]==]`), quoted arguments with escapes and line continuations,
unquoted arguments with nested parentheses.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
PLAIN_UNQUOTED = re.compile(r'[^\s()#"\\]+')
PLAIN_QUOTED = re.compile(r'[^"\\]+')
SPACE = re.compile(r"[ \t\r\n]+")
BRACKET_OPEN = re.compile(r"\[(=*)\[")


@dataclass(frozen=True)
class Argument:
    text: str  # the argument's content: quotes removed, escapes and ${} not yet evaluated
    kind: str  # "unquoted" | "quoted" | "bracket"
    line: int
    column: int


@dataclass(frozen=True)
class Command:
    name: str  # lower case: CMake command names are case-insensitive
    args: tuple[Argument, ...]
    path: Path
    line: int
    column: int


class CMakeSyntaxError(Exception):
    def __init__(self, message: str, path: Path, line: int, column: int):
        super().__init__(message)
        self.message, self.path, self.line, self.column = message, path, line, column

    def __reduce__(
        self,
    ) -> tuple[
        type[CMakeSyntaxError], tuple[str, Path, int, int]
    ]:  # models cross process boundaries (parallel loading) with their errors
        return type(self), (self.message, self.path, self.line, self.column)


class _Scanner:
    def __init__(self, text: str, path: Path):
        self.text, self.path = text, path
        self.pos, self.line, self.column = 0, 1, 1

    def peek(self, offset: int = 0) -> str:
        index = self.pos + offset
        return self.text[index] if index < len(self.text) else ""

    def advance(self, count: int = 1) -> str:
        chunk = self.text[self.pos : self.pos + count]
        newlines = chunk.count("\n")
        if newlines:
            self.line += newlines
            self.column = len(chunk) - chunk.rfind("\n")
        else:
            self.column += len(chunk)
        self.pos += len(chunk)
        return chunk

    def advance_to(self, index: int) -> str:
        return self.advance(index - self.pos)

    def error(self, message: str, line: int | None = None, column: int | None = None) -> CMakeSyntaxError:
        return CMakeSyntaxError(message, self.path, line or self.line, column or self.column)

    def match(self, pattern: re.Pattern[str]) -> re.Match[str]:
        """`pattern` at the cursor, where the character there says it matches."""
        match = pattern.match(self.text, self.pos)
        if match is None:  # not reached: the callers look at the character first
            raise self.error(f"unexpected {self.peek()!r}")
        return match

    def skip_line_comment(self) -> None:
        end = self.text.find("\n", self.pos)
        self.advance_to(len(self.text) if end < 0 else end)

    def bracket(self, what: str) -> str:
        """Read `[==[ ... ]==]` at the cursor; return its content."""
        line, column = self.line, self.column
        match = self.match(BRACKET_OPEN)
        closing = "]" + match.group(1) + "]"
        self.advance(len(match.group(0)))
        end = self.text.find(closing, self.pos)
        if end < 0:
            raise self.error(f"unterminated bracket {what} (no '{closing}')", line, column)
        content = self.text[self.pos : end]
        self.advance(end - self.pos + len(closing))
        # a newline right after the opening bracket is not part of the content
        return content[1:] if content.startswith("\n") else content


def parse(text: str, path: Path) -> list[Command]:
    scanner = _Scanner(text, path)
    commands: list[Command] = []
    while True:
        _skip_space_and_comments(scanner, newlines=True)
        if not scanner.peek():
            return commands
        match = IDENTIFIER.match(text, scanner.pos)
        if not match:
            raise scanner.error(f"expected a command name, found {scanner.peek()!r}")
        line, column = scanner.line, scanner.column
        scanner.advance(len(match.group(0)))
        while scanner.peek() in (" ", "\t"):
            scanner.advance()
        if scanner.peek() != "(":
            raise scanner.error(f"expected '(' after '{match.group(0)}'")
        scanner.advance()
        args = _arguments(scanner, match.group(0), line)
        commands.append(Command(match.group(0).lower(), tuple(args), path, line, column))


def _skip_space_and_comments(scanner: _Scanner, *, newlines: bool) -> None:
    while True:
        char = scanner.peek()
        if char in (" ", "\t", "\r") or (newlines and char == "\n"):
            scanner.advance_to(scanner.match(SPACE).end()) if newlines else scanner.advance()
        elif char == "#":
            scanner.advance()
            if BRACKET_OPEN.match(scanner.text, scanner.pos):
                scanner.bracket("comment")
            else:
                scanner.skip_line_comment()
        else:
            return


def _arguments(scanner: _Scanner, command: str, line: int) -> list[Argument]:
    args: list[Argument] = []
    depth = 0
    while True:
        _skip_space_and_comments(scanner, newlines=True)
        char = scanner.peek()
        if not char:
            raise scanner.error(f"'{command}(' opened at line {line} is never closed: missing ')'", line)
        arg_line, arg_column = scanner.line, scanner.column
        if char == ")":
            scanner.advance()
            if depth == 0:
                return args
            depth -= 1
            args.append(Argument(")", "unquoted", arg_line, arg_column))
        elif char == "(":
            scanner.advance()
            depth += 1
            args.append(Argument("(", "unquoted", arg_line, arg_column))
        elif char == '"':
            args.append(Argument(_quoted(scanner), "quoted", arg_line, arg_column))
        elif char == "[" and BRACKET_OPEN.match(scanner.text, scanner.pos):
            args.append(Argument(scanner.bracket("argument"), "bracket", arg_line, arg_column))
        else:
            args.append(Argument(_unquoted(scanner), "unquoted", arg_line, arg_column))


def _quoted(scanner: _Scanner) -> str:
    line, column = scanner.line, scanner.column
    scanner.advance()  # opening quote
    out = []
    while True:
        char = scanner.peek()
        if not char:
            raise scanner.error("unterminated quoted argument (no closing '\"')", line, column)
        if char == "\\":
            following = scanner.peek(1)
            if following == "\n":  # line continuation
                scanner.advance(2)
                continue
            out.append(scanner.advance(2))
            continue
        if char == '"':
            scanner.advance()
            return "".join(out)
        out.append(scanner.advance_to(scanner.match(PLAIN_QUOTED).end()))


def _unquoted(scanner: _Scanner) -> str:
    out: list[str] = []
    while True:
        char = scanner.peek()
        if not char or char in " \t\r\n()#":
            return "".join(out)
        if char == "\\":
            out.append(scanner.advance(2))
        elif char == '"':
            # legacy unquoted arguments may hold quoted parts: -DX="a b"
            start_line, start_column = scanner.line, scanner.column
            end = scanner.text.find('"', scanner.pos + 1)
            if end < 0:
                raise scanner.error(
                    "unterminated quoted argument (no closing '\"')", start_line, start_column
                )
            out.append(scanner.advance(end - scanner.pos + 1))
        else:
            out.append(scanner.advance_to(scanner.match(PLAIN_UNQUOTED).end()))
