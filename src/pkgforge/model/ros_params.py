"""ROS 2 parameter files as rcl reads them (`--params-file`), and ros_gz_bridge's config files.

rcl_yaml_param_parser (rcl's parser.c/parse.c, humble and jazzy alike) reads a parameters file
as a stream of YAML events: the keys above `ros__parameters` name the node (with its namespace,
`/**` and `*` wildcards), the map under it holds the parameters (nested maps give dotted names),
each a scalar or a list of scalars of one type. It stops at the first thing it refuses, and the
node given the file does not start (rcl_parse_arguments fails). Only what it refuses for sure
is reported here, the first in the file; a file laid out in a way its event walk reads
differently from the tree it is (a map after `ros__parameters` beside it, a list of maps, an
empty map as a value) is not judged past that point.

ros_gz_bridge's `config_file` is read with yaml-cpp (bridge_config.cpp): a list of maps, each
with ros_type_name and gz_type_name; an entry it cannot read is logged and skipped, a YAML
error ends the node.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import yaml

from pkgforge.model.yamlnodes import compose_all

PARAMS_KEY = "ros__parameters"  # rcl compares the key's start with it (strncmp)
QUOTED = ("'", '"')
# rcl's get_value: these plain words are booleans, whatever YAML 1.1 or 1.2 would say
TRUE_WORDS = {"Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"}
FALSE_WORDS = {"N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF"}
# the YAML spellings of infinity and NaN rcl reads as doubles (strtod reads inf, nan too)
YAML_SPECIAL_FLOATS = {f"{sign}.{word}" for sign in ("", "+", "-") for word in ("inf", "Inf", "INF")} | {
    ".nan",
    ".NaN",
    ".NAN",
}
# strtoll(value, &end, 0) reading the whole text: decimal, 0x hexadecimal, 0 octal
C_INTEGER = re.compile(r"[+-]?(0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)")
# strtod reading the whole text (decimal; hexadecimal floats, inf, nan are left undecided)
C_DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
C_WORDS = re.compile(r"[+-]?(inf|infinity|nan)", re.I)
NODE_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# ros_gz_bridge's keys whose value it reads as a string
BRIDGE_STRINGS = (
    "topic_name",
    "ros_topic_name",
    "gz_topic_name",
    "ros_type_name",
    "gz_type_name",
    "direction",
)
BRIDGE_DIRECTIONS = {"BIDIRECTIONAL", "GZ_TO_ROS", "ROS_TO_GZ"}
# read by humble's ros_gz_bridge (deprecated there), no longer from jazzy on
BRIDGE_IGN_DIRECTIONS = {"IGN_TO_ROS", "ROS_TO_IGN"}


@dataclass(frozen=True)
class Problem:
    line: int  # 1-based, in the YAML file
    message: str
    # the ROS 2 distros where it is no problem (bridge configs: humble reads what jazzy no longer does)
    fine_on: tuple[str, ...] = ()


@dataclass
class ParametersFile:
    """What rcl makes of a parameters file: the first thing it refuses (None: it reads it, as
    far as pkgforge can tell) and every parameter name some node entry gives."""

    problem: Problem | None = None
    parameters: set[str] = field(default_factory=set)
    judged: bool = True  # False: a layout rcl reads differently from its tree; not judged past it


class _Unsure(Exception):
    """A layout whose reading by rcl's event walk pkgforge does not follow: stop judging."""

    def __init__(self, node: yaml.Node | None):
        super().__init__()
        # where judging stopped; None: at an alias's use (the tree keeps only its anchor's place)
        self.line = node.start_mark.line + 1 if node is not None else None


class _Refused(Exception):
    def __init__(self, node: yaml.Node, message: str):
        super().__init__(message)
        self.line = node.start_mark.line + 1
        self.message = message


def _yaml_error(error: yaml.YAMLError) -> Problem:
    mark = getattr(error, "problem_mark", None) or getattr(error, "context_mark", None)
    problem = getattr(error, "problem", None) or str(error).splitlines()[0]
    return Problem(mark.line + 1 if mark is not None else 1, f"not valid YAML: {problem}")


def _documents(text: str) -> list[yaml.Node]:
    return [d for d in compose_all(text) if d is not None]


def read_parameters(text: str) -> ParametersFile:
    """The file as rcl_parse_yaml_file reads it."""
    try:
        documents = _documents(text)
    except yaml.YAMLError as error:
        return ParametersFile(_yaml_error(error))
    except RecursionError:
        return ParametersFile(judged=False)
    found = ParametersFile()
    walk = _Walk(found)
    stopped: int | None = None  # where judging stopped (a layout not followed)
    try:
        for document in documents:  # (rcl's walk runs on from one document into the next)
            walk.document(document)
    except _Refused as refused:
        found.problem = Problem(refused.line, refused.message)
    except _Unsure as unsure:
        found.judged, stopped = False, unsure.line
    # rcl stops at the first event it refuses: an alias before anything else
    alias = _first_alias(text)
    first = found.problem.line if found.problem is not None else stopped
    if alias is not None and (first is None or alias < first):  # (None: judged to the end, or to an alias)
        found.problem = Problem(alias, "an alias (*name): rcl does not read YAML aliases")
    return found


def _first_alias(text: str) -> int | None:
    """The line of the file's first alias (*name, <<: *name), which rcl refuses; None if none."""
    if "*" not in text:
        return None
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        for event in yaml.parse(text, Loader=loader):
            if isinstance(event, yaml.AliasEvent) and event.start_mark is not None:
                return int(event.start_mark.line) + 1
    except yaml.YAMLError:
        return None
    return None


class _Walk:
    """rcl's walk of one document, in document order."""

    def __init__(self, found: ParametersFile):
        self.found = found
        self.counts: dict[str, int] = {}  # node name → parameters it has so far
        self.seen: set[int] = set()  # the collections walked: one met again is an alias

    def enter(self, node: yaml.Node) -> None:
        """A map or list met a second time is an alias's (rcl refuses it, at the alias): not
        walked again, so a file of nested aliases costs its size, not their expansion."""
        if id(node) in self.seen:
            raise _Unsure(None)
        self.seen.add(id(node))

    def document(self, root: yaml.Node) -> None:
        if isinstance(root, yaml.ScalarNode):
            if root.value == "" and root.style not in QUOTED:
                raise _Refused(root, "the file holds an empty document, no node names")
            return  # one key with nothing under it: no node, no parameter, no error
        if isinstance(root, yaml.SequenceNode):
            raise _Refused(
                root,
                "the top level is a list: a parameters file maps node names (or /**) to ros__parameters",
            )
        if isinstance(root, yaml.MappingNode):
            self.node_level(root, [])

    def node_level(self, mapping: yaml.MappingNode, names: list[str], near: str = "") -> None:
        """`near`: what a key above said that looks like ros__parameters misspelt."""
        self.enter(mapping)
        after_parameters = False
        for key, value in mapping.value:
            if not isinstance(key, yaml.ScalarNode):
                raise _Unsure(key)
            if key.value == "":
                raise _Refused(key, "an empty key")
            if key.value.startswith(PARAMS_KEY):
                self.parameters_of(key, value, names)
                after_parameters = True
                continue
            if isinstance(value, (yaml.ScalarNode, yaml.SequenceNode)):
                what = "has a value" if isinstance(value, yaml.ScalarNode) else "is a list"
                raise _Refused(
                    value,
                    f"'{key.value}' {what} outside ros__parameters"
                    + (
                        near
                        or ": a parameters file maps node names (or /**) to ros__parameters, which "
                        "holds the parameters"
                    ),
                )
            if after_parameters:
                raise _Unsure(key)  # rcl's node name no longer follows the keys here
            if _misspelt(key.value):
                near = f" ('{key.value}' at line {key.start_mark.line + 1} is not {PARAMS_KEY})"
            self.node_level(value, [*names, key.value], near)

    def parameters_of(self, key: yaml.ScalarNode, value: yaml.Node, names: list[str]) -> None:
        if not names:
            raise _Refused(key, "ros__parameters with no node name above it (write /**: for every node)")
        node = _joined(names)
        problem = _invalid_node_name(node)
        if problem is not None:
            raise _Refused(key, f"'{node}' is no valid node name: {problem}")
        count = self.counts.setdefault(node, 0)
        if isinstance(value, yaml.MappingNode):
            self.parameter_map(value, node, None)
            return
        if isinstance(value, yaml.ScalarNode):
            if value.value == "" and value.style not in QUOTED:
                raise _Refused(value, f"ros__parameters of '{node}' is empty (write {{}} for none)")
            if count == 0:
                raise _Refused(
                    value, f"ros__parameters of '{node}' is a single value, not a map of parameters"
                )
        elif isinstance(value, yaml.SequenceNode) and value.value and count == 0:
            raise _Refused(value, f"ros__parameters of '{node}' is a list, not a map of parameters")
        raise _Unsure(value)  # rcl goes on reading the keys after it as this node's parameters

    def parameter_map(self, mapping: yaml.MappingNode, node: str, prefix: str | None) -> None:
        self.enter(mapping)
        if not mapping.value and prefix is not None:
            raise _Unsure(mapping)  # an empty map as a value ends rcl's parameter level early
        for key, value in mapping.value:
            if not isinstance(key, yaml.ScalarNode):
                raise _Unsure(key)
            if key.value == "":
                raise _Refused(key, "an empty parameter name")
            name = f"{prefix}.{key.value}" if prefix else key.value
            if isinstance(value, yaml.MappingNode):
                self.parameter_map(value, node, name)
                continue
            self.counts[node] = self.counts.get(node, 0) + 1
            self.found.parameters.add(name)
            if isinstance(value, yaml.ScalarNode):
                if value.value == "" and value.style not in QUOTED:
                    raise _Refused(value, f"parameter '{name}' has no value (write '' for an empty string)")
            elif isinstance(value, yaml.SequenceNode):
                self.parameter_list(value, name)

    def parameter_list(self, sequence: yaml.SequenceNode, name: str) -> None:
        self.enter(sequence)
        kinds: list[tuple[yaml.ScalarNode, str | None]] = []
        for item in sequence.value:
            if not isinstance(item, yaml.ScalarNode):
                raise _Unsure(item)  # rcl reads a list of maps or of lists its own way
            if item.value == "" and item.style not in QUOTED:
                raise _Refused(item, f"parameter '{name}' has an empty item")
            kinds.append((item, _scalar_kind(item)))
        if any(kind is None for _, kind in kinds):
            return  # a value whose type rcl's C parsing may see otherwise: not judged
        first = kinds[0][1] if kinds else None
        for item, kind in kinds:
            if kind != first:
                numbers = {first, kind} == {"integer", "double"}
                integer = next((i.value for i, k in kinds if k == "integer"), "")
                word = next(
                    (i.value for i, k in kinds if k == "bool" and i.value.lower() not in ("true", "false")),
                    None,
                )
                advice = (
                    f" (write {integer}.0, not {integer})"
                    if numbers
                    else f" ('{word}' is a boolean to rcl: quote it)"
                    if word
                    else ""
                )
                raise _Refused(
                    item,
                    f"parameter '{name}' mixes {first} and {kind} items: rcl takes a list of one type{advice}",
                )


def _scalar_kind(node: yaml.ScalarNode) -> str | None:
    """The type rcl's get_value gives a scalar: bool, integer, double or string; None when it is
    not certain (an explicit tag, which humble ignores and jazzy reads for !!str; a number C's
    strtoll/strtod may read otherwise)."""
    value, style = node.value, node.style
    if style in QUOTED:
        return "string"
    if style in ("", None) and node.tag != _implicit_tag(value):
        return None  # an explicit tag
    if value in TRUE_WORDS or value in FALSE_WORDS:
        return "bool"
    if C_INTEGER.fullmatch(value):
        return "integer" if -(2**63) <= _c_integer(value) < 2**63 else None  # (strtoll's ERANGE)
    if value in YAML_SPECIAL_FLOATS:
        return "double"
    if C_DECIMAL.fullmatch(value):
        number = float(value)
        if number in (float("inf"), float("-inf")) or (0 < abs(number) < sys.float_info.min):
            return None  # out of range: strtod sets ERANGE, rcl keeps the text
        if number == 0 and re.search(r"[1-9]", value.split("e")[0].split("E")[0]):
            return None  # underflow
        return "double"
    if C_WORDS.fullmatch(value) or value.lower().startswith(("0x", "+0x", "-0x", "0b", "nan(")):
        return None
    return "string"


def _c_integer(value: str) -> int:
    """strtoll(value, NULL, 0) of a text C_INTEGER matches, without its range limit."""
    sign = -1 if value.startswith("-") else 1
    digits = value.lstrip("+-")
    if digits[:2] in ("0x", "0X"):
        return sign * int(digits[2:], 16)
    if digits.startswith("0") and len(digits) > 1:
        return sign * int(digits[1:], 8)
    return sign * int(digits)


def _implicit_tag(value: str) -> str:
    """The tag YAML gives a plain scalar with no tag of its own."""
    resolve: Any = yaml.SafeLoader.resolve  # (the resolvers are the class's: no loader made)
    return str(resolve(yaml.SafeLoader, yaml.ScalarNode, value, (True, False)))


def _misspelt(key: str) -> bool:
    """Whether a key looks like ros__parameters written otherwise (ros_parameters, ros__params)."""
    import difflib

    squeezed = key.lower().replace("_", "").replace("-", "")
    return squeezed in ("rosparameters", "rosparams", "parameters") or (
        difflib.SequenceMatcher(None, key, PARAMS_KEY).ratio() >= 0.8
    )


def _joined(names: list[str]) -> str:
    """The node name rcl builds from the keys above ros__parameters (no second '/' after one)."""
    out = ""
    for name in names:
        out = name if not out else out + ("" if out.endswith("/") else "/") + name
    return out


def _invalid_node_name(name: str) -> str | None:
    """Why rcl refuses a node name (rmw's node name and namespace rules, wildcards aside); None
    when it takes it."""
    if name in ("/**", "/*"):
        return None
    namespace, _, node = name.rpartition("/")
    if namespace or name.startswith("/"):
        tokens = namespace.split("/")
        if namespace.startswith("/"):
            tokens = tokens[1:]
        for token in tokens:
            if token == "":
                return "it has two '/' in a row"
            if token not in ("*", "**") and not NODE_TOKEN.fullmatch(token):
                return _token_problem(token)
    if node in ("*", "**"):
        return None
    if node == "":
        return "it ends with '/'"
    return _token_problem(node) if not NODE_TOKEN.fullmatch(node) else None


def _token_problem(token: str) -> str:
    if token[:1].isdigit():
        return f"'{token}' starts with a digit"
    bad = next((c for c in token if not (c.isascii() and (c.isalnum() or c == "_"))), token[:1])
    return f"'{token}' holds '{bad}' (only letters, digits and _)"


# --- ros_gz_bridge ---------------------------------------------------------------------------


def read_bridge_config(text: str) -> list[Problem]:
    """What ros_gz_bridge refuses in a config_file: a YAML error (the node ends), a top level
    that is no list, entries it skips (each logged as an error, nothing bridged for it)."""
    try:
        documents = _documents(text)
    except yaml.YAMLError as error:
        return [_yaml_error(error)]
    except RecursionError:
        return []
    if not documents:
        return [Problem(1, "the file is empty: nothing is bridged")]
    root = documents[0]
    if not isinstance(root, yaml.SequenceNode):
        return [
            Problem(
                root.start_mark.line + 1,
                "the top level is not a list: ros_gz_bridge bridges nothing (each entry is '- ros_topic_name: ...')",
            )
        ]
    return [problem for entry in root.value for problem in _bridge_entry(entry)]


def _bridge_entry(entry: yaml.Node) -> Iterator[Problem]:
    line = entry.start_mark.line + 1
    if not isinstance(entry, yaml.MappingNode):
        yield Problem(line, "an entry that is not a map: ros_gz_bridge skips it")
        return
    values: dict[str, yaml.Node] = {}
    for key, value in entry.value:
        if isinstance(key, yaml.ScalarNode):
            values[key.value] = value
    for key in BRIDGE_STRINGS:
        node = values.get(key)
        if node is not None and not isinstance(node, yaml.ScalarNode):
            yield Problem(
                node.start_mark.line + 1, f"'{key}' is not a single value: ros_gz_bridge stops on it"
            )
            return

    def text(key: str) -> str:
        node = values.get(key)
        return str(node.value) if isinstance(node, yaml.ScalarNode) else ""

    if text("topic_name") and (text("ros_topic_name") or text("gz_topic_name")):
        other = "ros_topic_name" if text("ros_topic_name") else "gz_topic_name"
        yield Problem(
            line, f"topic_name and {other} together: ros_gz_bridge skips the entry (give one or the other)"
        )
        return
    missing = [key for key in ("ros_type_name", "gz_type_name") if not text(key)]
    if missing == ["gz_type_name"] and text("ign_type_name"):
        yield Problem(
            line,
            "ign_type_name, which ros_gz_bridge reads only in humble: from jazzy on it skips the entry "
            "(write gz_type_name)",
            fine_on=("humble",),
        )
    elif missing:
        yield Problem(line, f"no {' and no '.join(missing)}: ros_gz_bridge skips the entry")
        return
    direction = text("direction")
    if direction in BRIDGE_IGN_DIRECTIONS:
        yield Problem(
            values["direction"].start_mark.line + 1,
            f"direction {direction}, which ros_gz_bridge reads only in humble: from jazzy on it skips "
            f"the entry (write {direction.replace('IGN', 'GZ')})",
            fine_on=("humble",),
        )
    elif "direction" in values and direction not in BRIDGE_DIRECTIONS:
        yield Problem(
            values["direction"].start_mark.line + 1,
            f"direction '{direction}' is none of BIDIRECTIONAL, GZ_TO_ROS, ROS_TO_GZ: ros_gz_bridge skips the entry",
        )
