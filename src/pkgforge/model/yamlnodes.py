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


def compose(text: str) -> yaml.Node | None:
    """The single document of `text` (None when empty), as yaml.compose gives it."""
    nodes = _compose(text, False)
    return nodes[0] if nodes else None


def compose_all(text: str) -> list[yaml.Node]:
    """Every document of `text`, as list(yaml.compose_all(text, Loader=yaml.SafeLoader))."""
    return list(_compose(text, True))


@lru_cache(maxsize=MEMO_SIZE)
def _compose(text: str, every: bool) -> tuple[yaml.Node, ...]:
    """Every document (`every`), or the single one yaml.compose gives (none when empty)."""
    if _FAST is not None:
        try:
            return _documents(text, every, _FAST)
        except yaml.YAMLError:
            pass  # PyYAML's own words below
    return _documents(text, every, yaml.SafeLoader)


def _documents(text: str, every: bool, loader: type[yaml.SafeLoader]) -> tuple[yaml.Node, ...]:
    if every:
        return tuple(yaml.compose_all(text, Loader=loader))
    node = yaml.compose(text, Loader=loader)
    return () if node is None else (node,)
