"""roslaunch's substitutions as tokens: Token("text", s), Token("find", pkg), Token("var", name),
Token("env", name, default), Token("anon", name), Token("dirname"); the emitters write each in
ROS 2 terms. What ROS 2 cannot express raises Unconvertible (a `migrate-dropped` note at its line).
"""

from __future__ import annotations

import re
from typing import Literal, NamedTuple

SUBSTITUTION = re.compile(r"\$\(([a-z_]+)((?:\s+[^)\s]+)*)\s*\)")
XACRO_COMMAND = re.compile(
    r"^\s*(?:\$\(find xacro\)/xacro(?:\.py)?|xacro(?:\.py)?|rosrun xacro xacro(?:\.py)?)\s+"
)


class Unconvertible(Exception):
    pass


class Token(NamedTuple):
    """A piece of a roslaunch value: text, or a substitution the emitters write in ROS 2 terms."""

    kind: Literal["text", "find", "var", "env", "anon", "dirname"]
    value: str = ""  # the text, package, argument, variable or name ("" for dirname)
    default: str | None = None  # env: $(optenv NAME default)'s default


# <node if=...>/<group unless=...>: the attribute and its value
Condition = tuple[Literal["if", "unless"], list[Token]]


def tokens(text: str | None) -> list[Token]:
    """A roslaunch attribute value as tokens; $(eval) and unknown substitutions raise Unconvertible."""
    if text is None:
        return []
    found: list[Token] = []
    position = 0
    for match in SUBSTITUTION.finditer(text):
        if match.start() > position:
            found.append(Token("text", text[position : match.start()]))
        kind, words = match.group(1), match.group(2).split()
        if kind == "find" and len(words) == 1:
            found.append(Token("find", words[0]))
        elif kind == "arg" and len(words) == 1:
            found.append(Token("var", words[0]))
        elif kind in ("env", "optenv") and words:
            found.append(Token("env", words[0], " ".join(words[1:]) if kind == "optenv" else None))
        elif kind == "anon" and len(words) == 1:
            found.append(Token("anon", words[0]))
        elif kind == "dirname" and not words:
            found.append(Token("dirname"))
        else:
            raise Unconvertible(f"$({kind}) has no ROS 2 equivalent pkgforge can write")
        position = match.end()
    if "$(" in text[position:]:
        raise Unconvertible(f"'{text}' holds a substitution pkgforge cannot read")
    if position < len(text):
        found.append(Token("text", text[position:]))
    return found


def literal(parts: list[Token]) -> str | None:
    """The text of tokens that are all text, else None."""
    return "".join(p[1] for p in parts) if all(p[0] == "text" for p in parts) else None


def split_words(parts: list[Token]) -> list[list[Token]]:
    """Tokens split at white space in their text (node args)."""
    words: list[list[Token]] = [[]]
    for part in parts:
        if part[0] != "text":
            words[-1].append(part)
            continue
        pieces = re.split(r"(\s+)", part[1])
        for piece in pieces:
            if not piece:
                continue
            if piece.isspace():
                words.append([])
            else:
                words[-1].append(Token("text", piece.strip("'\"")))
    return [w for w in words if w]
