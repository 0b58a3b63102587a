"""YAML node trees (values with lines) for reading configs: libyaml's parser, each distinct text once.

PyYAML's pure-Python composer takes about 70 ms for a 3 KB RViz config; libyaml's
(CSafeLoader) about 5 ms, with the same nodes, tags and marks (only a plain
scalar's `style` is '' instead of None; nothing here reads it). A workspace often
holds the same config many times (scaffolded packages), so the trees of the last
texts are kept: callers only read them. When libyaml rejects a text, the
pure-Python composer runs on it, so the error (its words and mark) is exactly
the one PyYAML gives, and a text only libyaml refuses is still read.
"""

from __future__ import annotations

from functools import lru_cache

import yaml

_FAST = getattr(yaml, "CSafeLoader", None)
MEMO_SIZE = 32  # distinct texts kept (a 3 KB config's tree is about 150 KB)


def compose(text: str):
    """The single document of `text` (None when empty), as yaml.compose gives it."""
    return _compose(text, False)


def compose_all(text: str) -> list:
    """Every document of `text`, as list(yaml.compose_all(text, Loader=yaml.SafeLoader))."""
    return list(_compose(text, True))


@lru_cache(maxsize=MEMO_SIZE)
def _compose(text: str, every: bool):
    if _FAST is not None:
        try:
            return tuple(yaml.compose_all(text, Loader=_FAST)) if every else yaml.compose(text, Loader=_FAST)
        except yaml.YAMLError:
            pass  # PyYAML's own words below
    return (
        tuple(yaml.compose_all(text, Loader=yaml.SafeLoader))
        if every
        else yaml.compose(text, Loader=yaml.SafeLoader)
    )
