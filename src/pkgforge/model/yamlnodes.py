"""The one YAML reader for the user's files: node trees (values with lines) and loaded data,
bounded in nesting and in what aliases expand to, each distinct text composed once.

PyYAML's pure-Python composer takes about 70 ms for a 3 KB RViz config; libyaml's
(CSafeLoader) about 5 ms, with the same nodes, tags and marks (only a plain
scalar's `style` is '' instead of None; nothing here reads it). A workspace often
holds the same config many times (scaffolded packages), so the trees of the last
texts are kept: callers only read them. When libyaml rejects a text, the
pure-Python parser runs on it, so the error (its words and mark) is exactly
the one PyYAML gives, and a text only libyaml refuses is still read.

Bounds, because every reader of a tree walks it: a 2 KB file of anchors and aliases ("billion
laughs") is a tree of 10**11 nodes to walk, an alias inside the collection it names is one
that never ends, and 50,000 nested brackets overflow the stack of a recursive composer
(PyYAML's own raises RecursionError). A text with no alias is composed by libyaml, whose
parser refuses nesting past 1000 levels itself, and its tree is then measured; any other text
is composed here from the parser's events, iteratively, counting as it goes, so the error is
raised where the limit is crossed, before anything is expanded.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import yaml
from yaml.events import AliasEvent, MappingEndEvent, ScalarEvent, SequenceEndEvent, SequenceStartEvent

_FAST = getattr(yaml, "CSafeLoader", None)
MEMO_SIZE = 32  # distinct texts kept (a 3 KB config's tree is about 150 KB)
# Deeper than any real file (an RViz config's TF tree nests once per link of the chain), and within
# what ros2 launch's own pure-Python loader reads before its RecursionError (about 490 levels)
MAX_DEPTH = 500
# nodes the aliases of one text may add when expanded (a walk of a million nodes takes seconds)
MAX_ALIAS_NODES = 1_000_000
LIBYAML_TOO_DEEP = "exceeded maximum nesting depth"  # libyaml's words for its own bound (1000)

Loader = type[yaml.SafeLoader]


class YAMLLimit(yaml.MarkedYAMLError):
    """A text past one of the reader's bounds: what, and where it was crossed (problem_mark)."""

    def __str__(self) -> str:
        mark = self.problem_mark
        return f"{self.problem} (line {mark.line + 1})" if mark is not None else str(self.problem)


def compose(text: str) -> yaml.Node | None:
    """The single document of `text` (None when empty), as yaml.compose gives it."""
    nodes = _compose(text, False)
    return nodes[0] if nodes else None


def compose_all(text: str) -> list[yaml.Node]:
    """Every document of `text`, as list(yaml.compose_all(text, Loader=yaml.SafeLoader))."""
    return list(_compose(text, True))


def load(text: str, loader: Loader = yaml.SafeLoader) -> Any:
    """yaml.safe_load(text) (or yaml.load with `loader`, a SafeLoader), within the bounds."""
    node = compose(text)
    return None if node is None else _construct(node, loader)


def load_all(text: str, loader: Loader = yaml.SafeLoader) -> list[Any]:
    """list(yaml.safe_load_all(text)), within the bounds."""
    return [_construct(node, loader) for node in compose_all(text)]


def problem(error: yaml.YAMLError) -> str:
    """What is wrong, in one line: a bound's own words, else PyYAML's problem ('not valid YAML: …')."""
    if isinstance(error, YAMLLimit):
        return str(error.problem)
    return f"not valid YAML: {getattr(error, 'problem', None) or error}"


def _construct(node: yaml.Node, loader: Loader) -> Any:
    constructor = loader("")
    try:
        return constructor.construct_document(node)
    except RecursionError:  # a deep key (`? [[[…]]]`) or merge chain: PyYAML constructs those recursively
        raise YAMLLimit(
            None, None, "nested too deep to read: a key or a merge (<<) holds deep nesting", node.start_mark
        ) from None
    finally:
        constructor.dispose()


@lru_cache(maxsize=MEMO_SIZE)
def _compose(text: str, every: bool) -> tuple[yaml.Node, ...]:
    """Every document (`every`), or the single one yaml.compose gives (none when empty)."""
    fast = _FAST
    if fast is not None:
        if "*" not in text and _libyaml_bounds_nesting(fast):  # no alias: libyaml's own composer
            try:
                nodes = _documents(text, every, fast)
            except yaml.YAMLError:
                pass  # composed again below: which bound (where it is passed), or PyYAML's words
            else:
                _within_depth(nodes)
                return nodes
        try:
            return _Composer(fast(text)).documents(every)
        except YAMLLimit:
            raise
        except yaml.YAMLError as error:
            _raise_if_too_deep(error)  # else PyYAML's own words below
    return _Composer(yaml.SafeLoader(text)).documents(every)


def _raise_if_too_deep(error: yaml.YAMLError) -> None:
    """libyaml's refusal of nesting past 1000 levels as the reader's own, where libyaml met it:
    its scanner reads ahead of the events on a line of brackets, so it refuses before the
    composer counts 500 (PyYAML's scanner, reading as far ahead, takes seconds to get there)."""
    if getattr(error, "problem", None) == LIBYAML_TOO_DEEP:
        raise _too_deep(getattr(error, "problem_mark", None)) from None


def _documents(text: str, every: bool, loader: type[yaml.CSafeLoader]) -> tuple[yaml.Node, ...]:
    if every:
        return tuple(yaml.compose_all(text, Loader=loader))
    node = yaml.compose(text, Loader=loader)
    return () if node is None else (node,)


@lru_cache(maxsize=1)
def _libyaml_bounds_nesting(loader: type[yaml.CSafeLoader]) -> bool:
    """Whether libyaml's parser refuses deep nesting itself (since 2024: past 1000 levels), so
    that its recursive composer cannot run out of stack; an older libyaml's events are composed
    here instead."""
    try:
        for _ in yaml.parse("[" * 2000 + "]" * 2000, Loader=loader):
            pass
    except yaml.YAMLError:
        return True
    return False


def _within_depth(nodes: tuple[yaml.Node, ...]) -> None:
    """YAMLLimit at the first collection (in the text's order) nested deeper than MAX_DEPTH,
    in trees without aliases (each node reached once)."""
    for root in nodes:
        stack: list[tuple[yaml.Node, int]] = [(root, 1)]
        while stack:
            node, depth = stack.pop()
            if isinstance(node, yaml.ScalarNode):
                continue
            if depth > MAX_DEPTH:
                raise _too_deep(node.start_mark)
            if isinstance(node, yaml.SequenceNode):
                stack.extend((child, depth + 1) for child in reversed(node.value))
            else:
                for key, value in reversed(node.value):
                    stack += [(value, depth + 1), (key, depth + 1)]


def _too_deep(mark: yaml.Mark | None, through_alias: bool = False) -> YAMLLimit:
    expanded = " with its aliases expanded" if through_alias else ""
    return YAMLLimit(
        None,
        None,
        f"nested deeper than {MAX_DEPTH} levels{expanded}: pkgforge reads YAML up to that depth",
        mark,
    )


class _Open:
    """A collection being composed: its node, anchor, and its size and height so far (expanded)."""

    __slots__ = ("anchor", "height", "key", "node", "size")

    def __init__(self, node: yaml.CollectionNode, anchor: str | None):
        self.node, self.anchor = node, anchor
        self.size, self.height = 1, 1
        self.key: yaml.Node | None = None  # a mapping's key waiting for its value


class _Composer:
    """PyYAML's composition (the same nodes, tags, marks and errors) from a loader's event stream,
    without recursion, bounded: each anchor's expanded size and height are known when its
    collection ends, so an alias costs its size without being expanded."""

    def __init__(self, loader: Any):  # a SafeLoader or CSafeLoader (parser and resolver)
        self.loader = loader
        self.added = 0  # nodes the aliases add, over the whole stream

    def documents(self, every: bool) -> tuple[yaml.Node, ...]:
        loader = self.loader
        try:
            loader.get_event()  # the stream's start
            found: list[yaml.Node] = []
            while not loader.check_event(yaml.StreamEndEvent):
                if found and not every:
                    event = loader.get_event()
                    raise yaml.composer.ComposerError(
                        "expected a single document in the stream",
                        found[0].start_mark,
                        "but found another document",
                        event.start_mark,
                    )
                found.append(self._document())
            loader.get_event()
            return tuple(found)
        finally:
            loader.dispose()

    def _document(self) -> yaml.Node:
        get = self.loader.get_event
        get()  # the document's start
        anchors: dict[str, tuple[yaml.Node, int, int] | None] = {}  # None: its collection is open
        first: dict[str, yaml.Node] = {}  # each anchor's node (the first occurrence, for the error)
        stack: list[_Open] = []
        while True:
            event = get()
            kind = type(event)
            if kind is AliasEvent:
                node, size, height = self._alias(event, anchors, len(stack))
            elif kind is SequenceEndEvent or kind is MappingEndEvent:
                done = stack.pop()
                node, size, height = done.node, done.size, done.height
                node.end_mark = event.end_mark
                if done.anchor is not None:
                    anchors[done.anchor] = (node, size, height)
            else:
                anchor = event.anchor
                if anchor is not None and anchor in first:
                    raise yaml.composer.ComposerError(
                        f"found duplicate anchor {anchor!r}; first occurrence",
                        first[anchor].start_mark,
                        "second occurrence",
                        event.start_mark,
                    )
                if kind is ScalarEvent:
                    node, size, height = self._scalar(event), 1, 0
                    if anchor is not None:
                        first[anchor], anchors[anchor] = node, (node, 1, 0)
                else:
                    if len(stack) >= MAX_DEPTH:
                        raise _too_deep(event.start_mark)
                    opened = _Open(self._collection(event), anchor)
                    if anchor is not None:
                        first[anchor], anchors[anchor] = opened.node, None
                    stack.append(opened)
                    continue
            if not stack:
                get()  # the document's end
                return node
            self._add(stack[-1], node, size, height)

    def _alias(
        self, event: Any, anchors: dict[str, tuple[yaml.Node, int, int] | None], depth: int
    ) -> tuple[yaml.Node, int, int]:
        if event.anchor not in anchors:
            raise yaml.composer.ComposerError(
                None, None, f"found undefined alias {event.anchor!r}", event.start_mark
            )
        anchored = anchors[event.anchor]
        if anchored is None:
            raise YAMLLimit(
                None,
                None,
                f"alias *{event.anchor} is inside the collection it names: expanding it never ends",
                event.start_mark,
            )
        node, size, height = anchored
        self.added += size
        if self.added > MAX_ALIAS_NODES:
            raise YAMLLimit(
                None,
                None,
                f"its aliases expand to more than {MAX_ALIAS_NODES:,} nodes: pkgforge reads YAML up to that size",
                event.start_mark,
            )
        if depth + height > MAX_DEPTH:
            raise _too_deep(event.start_mark, through_alias=True)
        return node, size, height

    def _scalar(self, event: Any) -> yaml.ScalarNode:
        tag = event.tag
        if tag is None or tag == "!":
            tag = self.loader.resolve(yaml.ScalarNode, event.value, event.implicit)
        return yaml.ScalarNode(tag, event.value, event.start_mark, event.end_mark, style=event.style)

    def _collection(self, event: Any) -> yaml.CollectionNode:
        kind: type[yaml.CollectionNode] = (
            yaml.SequenceNode if type(event) is SequenceStartEvent else yaml.MappingNode
        )
        tag = event.tag
        if tag is None or tag == "!":
            tag = self.loader.resolve(kind, None, event.implicit)
        return kind(tag, [], event.start_mark, None, flow_style=event.flow_style)

    @staticmethod
    def _add(parent: _Open, node: yaml.Node, size: int, height: int) -> None:
        parent.size += size
        parent.height = max(parent.height, height + 1)
        if isinstance(parent.node, yaml.SequenceNode):
            parent.node.value.append(node)
        elif parent.key is None:
            parent.key = node
        else:
            parent.node.value.append((parent.key, node))
            parent.key = None
