"""The kinematic tree as SVG: links as boxes, joints as labelled edges (type, axis, limits).

Plain text, no library: verify --artifacts writes it even without the `view` extra.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import escape

if TYPE_CHECKING:  # scene needs numpy; the tree does not
    from pkgforge.view.scene import Robot

BOX_W, BOX_H, GAP_X, GAP_Y = 150, 30, 24, 78


def _joint_label(joint: dict[str, Any]) -> list[str]:
    lines = [f"{joint.get('name')} ({joint.get('type')})"]
    if joint.get("type") not in ("fixed", "floating", "planar"):
        axis = joint.get("axis") or [1.0, 0.0, 0.0]
        lines.append("axis " + " ".join(f"{a:g}" for a in axis))
    limit = joint.get("limit")
    if limit and joint.get("type") in ("revolute", "prismatic"):
        lines.append(
            f"[{limit.get('lower') or 0:g}, {limit.get('upper') or 0:g}]"
            f" v{limit.get('velocity')} e{limit.get('effort')}"
        )
    return lines


class _Placing:
    """A link being placed: its joints to children (those not its ancestors nor placed yet when
    it was reached), and the columns of the children placed so far."""

    __slots__ = ("depth", "kids", "name", "xs")

    def __init__(self, name: str, depth: int, kids: list[dict[str, Any]]):
        self.name, self.depth, self.kids = name, depth, kids
        self.xs: list[float] = []


def _place(
    root: str,
    children: dict[str, list[dict[str, Any]]],
    position: dict[str, tuple[float, int]],
    column: list[int],
) -> None:
    """Place root's tree: a leaf in the next column, a parent centred over its first and last
    child, each link at its depth; depth first, without recursion (a chain of links is as deep as
    it is long)."""
    ancestors: dict[str, int] = {}  # the links on the way down (a count: a joint may loop back)

    def reach(name: str, depth: int) -> _Placing:
        kids = [
            j
            for j in children.get(name, [])
            if j.get("child") not in ancestors and j.get("child") not in position
        ]
        ancestors[name] = ancestors.get(name, 0) + 1
        return _Placing(name, depth, kids)

    stack = [reach(root, 0)]
    while stack:
        top = stack[-1]
        if len(top.xs) < len(top.kids):
            stack.append(reach(top.kids[len(top.xs)]["child"], top.depth + 1))
            continue
        stack.pop()
        ancestors[top.name] -= 1
        if not ancestors[top.name]:
            del ancestors[top.name]
        if top.kids:
            x = (top.xs[0] + top.xs[-1]) / 2
        else:
            x = column[0]
            column[0] += 1
        position[top.name] = (x, top.depth)
        if stack:
            stack[-1].xs.append(x)


def tree_svg(robot: Robot) -> str:
    links = [link["name"] for link in robot.get("links", [])]
    joints = robot.get("joints", [])
    children: dict[str, list[dict[str, Any]]] = {}
    parent_of: dict[str, dict[str, Any]] = {}
    for joint in joints:
        children.setdefault(joint.get("parent"), []).append(joint)
        parent_of.setdefault(joint.get("child"), joint)
    roots = [name for name in links if name not in parent_of] or links[:1]
    position: dict[str, tuple[float, int]] = {}
    column = [0]
    for root in roots:
        _place(root, children, position, column)
    for name in links:  # unreachable (a cycle): a row of their own at the bottom
        if name not in position:
            position[name] = (column[0], max((d for _, d in position.values()), default=0) + 1)
            column[0] += 1

    def centre(name: str) -> tuple[float, float]:
        x, depth = position[name]
        return 20 + x * (BOX_W + GAP_X) + BOX_W / 2, 20 + depth * (BOX_H + GAP_Y) + BOX_H / 2

    width = 40 + max(column[0], 1) * (BOX_W + GAP_X)
    height = 40 + (max((d for _, d in position.values()), default=0) + 1) * (BOX_H + GAP_Y)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
        f'font-family="sans-serif" font-size="11">',
        f"<title>{escape(str(robot.get('name')))}: kinematic tree</title>",
        '<rect width="100%" height="100%" fill="white"/>',
    ]
    for joint in joints:
        if joint.get("parent") not in position or joint.get("child") not in position:
            continue
        (x1, y1), (x2, y2) = centre(joint["parent"]), centre(joint["child"])
        out.append(
            f'<line x1="{x1:.1f}" y1="{y1 + BOX_H / 2:.1f}" x2="{x2:.1f}" y2="{y2 - BOX_H / 2:.1f}" '
            'stroke="#777" stroke-width="1.5"/>'
        )
        label_y = (y1 + y2) / 2 - 6
        for index, text in enumerate(_joint_label(joint)):
            out.append(
                f'<text class="joint" x="{(x1 + x2) / 2 + 4:.1f}" y="{label_y + index * 12:.1f}" '
                f'fill="#335">{escape(text)}</text>'
            )
    for name in links:
        x, y = centre(name)
        out.append(
            f'<g class="link"><rect x="{x - BOX_W / 2:.1f}" y="{y - BOX_H / 2:.1f}" width="{BOX_W}" '
            f'height="{BOX_H}" rx="5" fill="#eef2f8" stroke="#456"/>'
            f'<text x="{x:.1f}" y="{y + 4:.1f}" text-anchor="middle">{escape(name)}</text></g>'
        )
    out.append("</svg>")
    return "\n".join(out) + "\n"
