"""Text that is safe to print: what every output of pkgforge (reports, errors) writes a name or a
message through. It sits at the ground floor because the error type and every report use it."""

from __future__ import annotations

import re

# What a report must not print as it is: C0 controls (a newline would start a line a CI runner
# reads as its own, ESC a sequence that retitles or clears the terminal), DEL, C1 controls (CSI,
# OSC and NEL in one character), lone surrogates (a file name's bytes that are not UTF-8, which a
# UTF-8 stream refuses to write) and U+FFFE/U+FFFF (XML 1.0 forbids them, and lxml raises)
_UNPRINTABLE = re.compile("[\x00-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
_NAMED_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def printable(text: str) -> str:
    """text safe to print on one line of a terminal, a CI log or an XML report: each control
    character written visibly as Python writes it in a string (`\\n`, `\\t`, `\\x1b`, `\\x85`), a
    byte that was not UTF-8 as `\\xe9`, so that a name stays recognisable and cannot act.
    A backslash is kept as it is (Windows paths and regular expressions read as written)."""
    if _UNPRINTABLE.search(text) is None:
        return text
    return _UNPRINTABLE.sub(_escape, text)


def _escape(match: re.Match[str]) -> str:
    character = match.group(0)
    code = ord(character)
    if character in _NAMED_ESCAPES:
        return _NAMED_ESCAPES[character]
    if 0xDC80 <= code <= 0xDCFF:  # os.fsdecode's stand-in for the byte code - 0xDC00
        return f"\\x{code - 0xDC00:02x}"
    return f"\\x{code:02x}" if code <= 0xFF else f"\\u{code:04x}"
