"""Where each box and arrow of a state diagram goes: a small layered layout, no graphviz.

The diagram reads left to right, as ``graph --format dot`` does. The layout is the classic
layered one (Sugiyama): transitions that lead back (loops) are turned round so the rest has no
cycle; each state gets a column by its longest path from the start; an edge that crosses
columns passes through invisible points, one per column, and its label is a box of its own in
the column after its source, so labels never cover a state or each other; the order within a
column is improved by barycentre sweeps (fewer crossings); heights are then placed as close to
their neighbours as the spacing allows (a least-squares fit under order constraints).

Nested states are laid out the same way, inside their state's box. Coordinates are pixels with
the origin at the top left and y growing down, as in SVG.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field

from roboscript.mission.graph import _describe, _edges
from roboscript.mission.spec import MissionSpec

__all__ = [
    "DETAIL_FONT_PX",
    "LABEL_FONT_PX",
    "NAME_FONT_PX",
    "TITLE_FONT_PX",
    "Cubic",
    "Diagram",
    "EdgeLine",
    "Point",
    "Rect",
    "StartMark",
    "StateBox",
    "layout",
    "text_width_px",
]

Point = tuple[float, float]
"""``(x px, y px)``, y down."""
Rect = tuple[float, float, float, float]
"""``(left px, top px, width px, height px)``."""
Cubic = tuple[Point, Point, Point, Point]
"""A cubic Bézier segment: start, two control points, end."""

NAME_FONT_PX = 13.0
"""The state's name (bold)."""
DETAIL_FONT_PX = 11.0
"""The lines under the name: the action, a run's visits."""
LABEL_FONT_PX = 11.0
"""Transition labels."""
TITLE_FONT_PX = 15.0
"""The mission's name above the diagram."""

_PAD_X = 12.0
_LINE_PX = 15.0  # one line of detail text
_NAME_LINE_PX = 28.0  # the name line with the box's top and bottom padding
_LABEL_H = 16.0
_LABEL_PAD = 5.0
_DUMMY_H = 4.0
_NODE_GAP = 22.0  # between boxes of one column
_DUMMY_GAP = 8.0  # between pass-through points and labels
_MIXED_GAP = 14.0  # between a box and an arrow passing it
_RANK_GAP = 24.0  # between columns
_START_R = 7.0
_NEST_PAD = 12.0
_NEST_TITLE = 26.0
_LOOP_H = 16.0  # a self-loop's arc above its box
_MARGIN = 16.0
_TITLE_H = 30.0
_SWEEPS = 12
_PLACEMENT_ROUNDS = 24


def text_width_px(text: str, size_px: float, *, bold: bool = False) -> float:
    """An upper estimate of ``text``'s width in a sans-serif font of ``size_px``.

    There are no font metrics without a renderer; the widths are DejaVu Sans's (matplotlib's
    font, wider than Helvetica), so the text fits its box in both pictures.
    """
    em = 0.0
    for char in text:
        if char in "ijl|!.,:;'":
            em += 0.30
        elif char in "frt()[]{} ":
            em += 0.42
        elif char in "mwMW@%":
            em += 0.98
        elif char.isupper():
            em += 0.74
        else:
            em += 0.64
    return em * size_px * (1.08 if bold else 1.0)


@dataclass(frozen=True)
class StateBox:
    """One state's box.

    Attributes:
        name: The state's full name as a run reports it (``first.out`` inside ``first``).
        title: The state's own name, shown in bold.
        lines: The text under the title (the action and its timeout, notes given).
        rect: Where the box is.
        final: ``"success"``, ``"failure"`` or ``None``.
        nested: True for a state that runs a mission of its own, drawn inside the box.
        parent: The full name of the nested state this box is inside, or ``None``.
    """

    name: str
    title: str
    lines: tuple[str, ...]
    rect: Rect
    final: str | None
    nested: bool
    parent: str | None


@dataclass(frozen=True)
class EdgeLine:
    """One transition's arrow.

    Attributes:
        source: The full name of the state it leaves, or ``None`` for the start marker.
        dest: The full name of the state it enters.
        label: Its trigger and condition (``done [visits.side >= 4]``); empty from the start.
        curves: The arrow as Bézier segments; the arrowhead is at the last point.
        label_rect: The label's box, or ``None`` without a label.
        parent: As for :class:`StateBox`.
    """

    source: str | None
    dest: str
    label: str
    curves: tuple[Cubic, ...]
    label_rect: Rect | None
    parent: str | None


@dataclass(frozen=True)
class StartMark:
    """The filled dot the mission (or a nested state's mission) starts from.

    Attributes:
        center: Its centre.
        radius_px: Its radius.
        dest: The full name of the first state.
        parent: As for :class:`StateBox`.
    """

    center: Point
    radius_px: float
    dest: str
    parent: str | None


@dataclass(frozen=True)
class Diagram:
    """A laid-out state diagram, ready to draw.

    Attributes:
        title: The mission's name.
        width_px: The picture's width.
        height_px: The picture's height.
        states: Every box; a nested state comes before the boxes inside it.
        edges: Every arrow.
        starts: Every start marker.
    """

    title: str
    width_px: float
    height_px: float
    states: tuple[StateBox, ...]
    edges: tuple[EdgeLine, ...]
    starts: tuple[StartMark, ...]
    title_pos: Point = (0.0, 0.0)


# ------------------------------------------------------------------------ the layered graph


@dataclass
class _Node:
    kind: str  # "start", "state", "label" or "point"
    width: float
    height: float
    rank: int = 0
    state: str = ""
    label: str = ""
    loops: list[str] = field(default_factory=list)  # self-loop labels, above the box
    box_width: float = 0.0
    box_height: float = 0.0
    up: list[int] = field(default_factory=list)
    down: list[int] = field(default_factory=list)
    x: float = 0.0  # centre
    y: float = 0.0  # centre

    @property
    def box_center_y(self) -> float:
        """A state's box sits at the bottom of its node, under its self-loops."""
        return self.y + self.height / 2 - self.box_height / 2


@dataclass
class _Block:
    """One level's layout in its own coordinates (origin top left)."""

    width: float
    height: float
    states: list[StateBox]
    edges: list[EdgeLine]
    starts: list[StartMark]


def layout(spec: MissionSpec, notes: Mapping[str, str] | None = None) -> Diagram:
    """Lay out ``spec``'s state diagram.

    Args:
        spec: The mission.
        notes: An extra line of text per state, by full name (a run's visits, say).

    Returns:
        Where every box, arrow, label and start marker goes.
    """
    block = _layout_level(spec, "", None, notes or {})
    top = _MARGIN + _TITLE_H
    title_width = text_width_px(spec.name, TITLE_FONT_PX, bold=True)
    width = max(block.width, title_width) + 2 * _MARGIN
    height = block.height + top + _MARGIN
    moved = _moved(block, _MARGIN, top)
    return Diagram(
        spec.name,
        width,
        height,
        tuple(moved.states),
        tuple(moved.edges),
        tuple(moved.starts),
        (_MARGIN, _MARGIN + TITLE_FONT_PX),
    )


def _state_lines(spec: MissionSpec, name: str, full: str, notes: Mapping[str, str]) -> list[str]:
    lines = []
    description = _describe(spec, name)
    if description:
        lines.append(description)
    if full in notes:
        lines.append(notes[full])
    return lines


def _layout_level(
    spec: MissionSpec, prefix: str, parent: str | None, notes: Mapping[str, str]
) -> _Block:
    names = list(spec.states)
    nodes: list[_Node] = [_Node("start", 2 * _START_R, 2 * _START_R)]
    index = {name: i + 1 for i, name in enumerate(names)}
    inner_blocks: dict[str, _Block] = {}
    for name in names:
        full = prefix + name
        action = spec.states[name].action
        inner = action.inner if action is not None else None
        title_w = text_width_px(name, NAME_FONT_PX, bold=True)
        if inner is not None:
            block = _layout_level(inner, full + ".", full, notes)
            inner_blocks[name] = block
            width = max(block.width, title_w) + 2 * _NEST_PAD
            height = _NEST_TITLE + block.height + _NEST_PAD
        else:
            lines = _state_lines(spec, name, full, notes)
            widths = [text_width_px(line, DETAIL_FONT_PX) for line in lines]
            width = max([title_w, *widths]) + 2 * _PAD_X
            height = _NAME_LINE_PX + _LINE_PX * len(lines)
        nodes.append(_Node("state", width, height, state=name, box_width=width, box_height=height))

    edges = [(index[source], index[dest], label) for source, dest, label in _edges(spec)]
    edges.insert(0, (0, index[spec.initial], ""))
    for source, dest, label in edges:
        if source == dest:
            nodes[source].loops.append(label)
    for node in nodes:
        if node.loops:
            widest = max(text_width_px(text, LABEL_FONT_PX) for text in node.loops)
            node.width = max(node.width, widest + 2 * _LABEL_PAD)
            node.height += _LOOP_H + _LABEL_H * len(node.loops)

    back = _back_edges(len(nodes), edges)
    _assign_ranks(nodes, edges, back)
    chains = _expand(nodes, edges, back)
    layers = _layers(nodes)
    _order(nodes, layers)
    _place_x(nodes, layers)
    _place_y(nodes, layers)

    top = min((n.y - n.height / 2 for n in nodes), default=0.0)
    for node in nodes:
        node.y -= top
    width = max((n.x + n.width / 2 for n in nodes), default=0.0)
    height = max((n.y + n.height / 2 for n in nodes), default=0.0)

    states: list[StateBox] = []
    starts = [StartMark((nodes[0].x, nodes[0].y), _START_R, prefix + spec.initial, parent)]
    inner_parts: list[tuple[str, _Block]] = []
    for name in names:
        node = nodes[index[name]]
        rect = (
            node.x - node.box_width / 2,
            node.y + node.height / 2 - node.box_height,
            node.box_width,
            node.box_height,
        )
        full = prefix + name
        is_nested = name in inner_blocks
        text = () if is_nested else tuple(_state_lines(spec, name, full, notes))
        states.append(StateBox(full, name, text, rect, spec.states[name].final, is_nested, parent))
        if is_nested:
            inner_parts.append(
                (full, _moved(inner_blocks[name], rect[0] + _NEST_PAD, rect[1] + _NEST_TITLE))
            )
    lines_out = _edge_lines(nodes, edges, back, chains, prefix, parent)
    for full, part in inner_parts:
        # a nested state's box comes before the boxes inside it (drawn under them)
        at = next(i for i, box in enumerate(states) if box.name == full) + 1
        states[at:at] = part.states
        lines_out.extend(part.edges)
        starts.extend(part.starts)
    return _Block(width, height, states, lines_out, starts)


def _moved(block: _Block, dx: float, dy: float) -> _Block:
    def point(p: Point) -> Point:
        return (p[0] + dx, p[1] + dy)

    def rect(r: Rect) -> Rect:
        return (r[0] + dx, r[1] + dy, r[2], r[3])

    return _Block(
        block.width,
        block.height,
        [
            StateBox(s.name, s.title, s.lines, rect(s.rect), s.final, s.nested, s.parent)
            for s in block.states
        ],
        [
            EdgeLine(
                e.source,
                e.dest,
                e.label,
                tuple((point(c[0]), point(c[1]), point(c[2]), point(c[3])) for c in e.curves),
                rect(e.label_rect) if e.label_rect is not None else None,
                e.parent,
            )
            for e in block.edges
        ],
        [StartMark(point(s.center), s.radius_px, s.dest, s.parent) for s in block.starts],
    )


# --------------------------------------------------------------------- ranks and columns


def _back_edges(count: int, edges: list[tuple[int, int, str]]) -> set[int]:
    """Edges that close a cycle, found by a depth-first walk from the start marker."""
    out: list[list[int]] = [[] for _ in range(count)]
    for number, (source, dest, _) in enumerate(edges):
        if source != dest:
            out[source].append(number)
    back: set[int] = set()
    status = [0] * count  # 0 unseen, 1 on the path, 2 finished
    for root in range(count):
        if status[root]:
            continue
        status[root] = 1
        stack = [(root, 0)]
        while stack:
            node, next_edge = stack[-1]
            if next_edge == len(out[node]):
                status[node] = 2
                stack.pop()
                continue
            stack[-1] = (node, next_edge + 1)
            number = out[node][next_edge]
            dest = edges[number][1]
            if status[dest] == 1:
                back.add(number)
            elif status[dest] == 0:
                status[dest] = 1
                stack.append((dest, 0))
    return back


def _oriented(edge: tuple[int, int, str], reversed_: bool) -> tuple[int, int]:
    return (edge[1], edge[0]) if reversed_ else (edge[0], edge[1])


def _assign_ranks(nodes: list[_Node], edges: list[tuple[int, int, str]], back: set[int]) -> None:
    """Each node's column: its longest path from a node nothing leads to."""
    incoming = [0] * len(nodes)
    out: list[list[int]] = [[] for _ in nodes]
    for number, edge in enumerate(edges):
        if edge[0] == edge[1]:
            continue
        source, dest = _oriented(edge, number in back)
        out[source].append(dest)
        incoming[dest] += 1
    ready = [i for i in range(len(nodes)) if incoming[i] == 0]
    while ready:
        node = ready.pop(0)
        for dest in out[node]:
            nodes[dest].rank = max(nodes[dest].rank, nodes[node].rank + 1)
            incoming[dest] -= 1
            if incoming[dest] == 0:
                ready.append(dest)


def _expand(
    nodes: list[_Node], edges: list[tuple[int, int, str]], back: set[int]
) -> dict[int, list[int]]:
    """Give every edge a node in each column it crosses; its label is the first of them.

    States sit in the even columns (twice their rank), so every edge crosses at least one
    column, where its label goes.

    Returns:
        Each edge's chain of nodes, from its lower column to its higher one.
    """
    for node in nodes:
        node.rank *= 2
    chains: dict[int, list[int]] = {}
    for number, edge in enumerate(edges):
        if edge[0] == edge[1]:
            continue
        source, dest = _oriented(edge, number in back)
        chain = [source]
        for rank in range(nodes[source].rank + 1, nodes[dest].rank):
            label = edge[2] if rank == nodes[source].rank + 1 else ""
            if label:
                width = text_width_px(label, LABEL_FONT_PX) + 2 * _LABEL_PAD
                nodes.append(_Node("label", width, _LABEL_H, rank=rank, label=label))
            else:
                nodes.append(_Node("point", 2.0, _DUMMY_H, rank=rank))
            chain.append(len(nodes) - 1)
        chain.append(dest)
        for lower, higher in itertools.pairwise(chain):
            nodes[lower].down.append(higher)
            nodes[higher].up.append(lower)
        chains[number] = chain
    return chains


def _layers(nodes: list[_Node]) -> list[list[int]]:
    layers: list[list[int]] = [[] for _ in range(max(n.rank for n in nodes) + 1)]
    for number, node in enumerate(nodes):
        layers[node.rank].append(number)
    return layers


def _crossings(nodes: list[_Node], layers: list[list[int]]) -> int:
    position = {n: i for layer in layers for i, n in enumerate(layer)}
    total = 0
    for layer in layers:
        pairs = [(position[a], position[b]) for a in layer for b in nodes[a].down]
        for i, (a1, b1) in enumerate(pairs):
            for a2, b2 in pairs[i + 1 :]:
                if (a1 - a2) * (b1 - b2) < 0:
                    total += 1
    return total


def _order(nodes: list[_Node], layers: list[list[int]]) -> None:
    """Order each column by the mean position of its neighbours, keeping the best found."""
    best = [list(layer) for layer in layers]
    best_crossings = _crossings(nodes, layers)
    for sweep in range(_SWEEPS):
        downward = sweep % 2 == 0
        sequence = range(1, len(layers)) if downward else range(len(layers) - 2, -1, -1)
        for rank in sequence:
            near = layers[rank - 1] if downward else layers[rank + 1]
            position = {n: i for i, n in enumerate(near)}

            def key(
                n: int, downward: bool = downward, position: dict[int, int] = position
            ) -> float:
                others = nodes[n].up if downward else nodes[n].down
                if not others:
                    return float(layers[nodes[n].rank].index(n))
                return sum(position[o] for o in others) / len(others)

            layers[rank] = sorted(layers[rank], key=key)  # stable: ties keep their order
        found = _crossings(nodes, layers)
        if found < best_crossings:
            best, best_crossings = [list(layer) for layer in layers], found
    layers[:] = best


def _place_x(nodes: list[_Node], layers: list[list[int]]) -> None:
    left = 0.0
    for layer in layers:
        width = max((nodes[n].width for n in layer), default=0.0)
        for n in layer:
            nodes[n].x = left + width / 2
        left += width + (_RANK_GAP if width > 0 else _RANK_GAP / 2)


def _gap(a: _Node, b: _Node) -> float:
    real = [n.kind in ("state", "start") for n in (a, b)]
    gap = _NODE_GAP if all(real) else _MIXED_GAP if any(real) else _DUMMY_GAP
    return (a.height + b.height) / 2 + gap


def _place_y(nodes: list[_Node], layers: list[list[int]]) -> None:
    """Stack each column, then pull nodes towards their neighbours without reordering."""
    for layer in layers:
        y = 0.0
        for i, n in enumerate(layer):
            if i:
                y += _gap(nodes[layer[i - 1]], nodes[n])
            nodes[n].y = y
    for round_ in range(_PLACEMENT_ROUNDS):
        sequence = layers if round_ % 2 == 0 else layers[::-1]
        for layer in sequence:
            wanted = []
            for n in layer:
                others = nodes[n].up + nodes[n].down
                if others:
                    wanted.append(sum(_attach_y(nodes[o]) for o in others) / len(others))
                else:
                    wanted.append(nodes[n].y)
                # a box's centre is not its node's centre when self-loops sit above it
                wanted[-1] -= _attach_y(nodes[n]) - nodes[n].y
            gaps = [_gap(nodes[a], nodes[b]) for a, b in itertools.pairwise(layer)]
            for n, y in zip(layer, _fit_in_order(wanted, gaps), strict=True):
                nodes[n].y = y


def _attach_y(node: _Node) -> float:
    return node.box_center_y if node.kind == "state" else node.y


def _fit_in_order(wanted: list[float], gaps: list[float]) -> list[float]:
    """Positions closest to ``wanted`` (least squares) with ``y[i+1] - y[i] >= gaps[i]``.

    Shifting each position by the gaps before it turns this into isotonic regression, solved
    by pooling adjacent violators.
    """
    offsets = [0.0]
    for gap in gaps:
        offsets.append(offsets[-1] + gap)
    blocks: list[list[float]] = []  # [sum, count]
    for target, offset in zip(wanted, offsets, strict=True):
        blocks.append([target - offset, 1.0])
        while len(blocks) > 1 and blocks[-2][0] / blocks[-2][1] > blocks[-1][0] / blocks[-1][1]:
            total, count = blocks.pop()
            blocks[-1][0] += total
            blocks[-1][1] += count
    fitted: list[float] = []
    for total, count in blocks:
        fitted.extend([total / count] * int(count))
    return [value + offset for value, offset in zip(fitted, offsets, strict=True)]


# ----------------------------------------------------------------------------- the arrows


def _edge_lines(
    nodes: list[_Node],
    edges: list[tuple[int, int, str]],
    back: set[int],
    chains: dict[int, list[int]],
    prefix: str,
    parent: str | None,
) -> list[EdgeLine]:
    paths: dict[int, list[Point]] = {}
    labels: dict[int, Rect] = {}
    for number, chain in chains.items():
        points: list[Point] = [_exit(nodes[chain[0]])]
        for n in chain[1:-1]:
            node = nodes[n]
            if node.kind == "label":
                points.append((node.x - node.width / 2, node.y))
                points.append((node.x + node.width / 2, node.y))
                labels[number] = (
                    node.x - node.width / 2,
                    node.y - node.height / 2,
                    node.width,
                    node.height,
                )
            else:
                points.append((node.x, node.y))
        points.append(_entry(nodes[chain[-1]]))
        paths[number] = points
    _spread_ends(nodes, chains, paths)
    lines: list[EdgeLine] = []
    loops_drawn = [0] * len(nodes)
    for number, (source, dest, label) in enumerate(edges):
        source_name = prefix + nodes[source].state if source else None
        dest_name = prefix + nodes[dest].state
        if source == dest:
            lines.append(_self_loop(nodes[source], loops_drawn[source], dest_name, parent))
            loops_drawn[source] += 1
            continue
        points = paths[number]
        if number in back:
            points = points[::-1]
        curves = tuple(_smooth(a, b) for a, b in itertools.pairwise(points))
        lines.append(EdgeLine(source_name, dest_name, label, curves, labels.get(number), parent))
    return lines


def _exit(node: _Node) -> Point:
    if node.kind == "start":
        return (node.x + _START_R, node.y)
    return (node.x + node.box_width / 2, node.box_center_y)


def _entry(node: _Node) -> Point:
    return (node.x - node.box_width / 2, node.box_center_y)


def _spread_ends(
    nodes: list[_Node], chains: dict[int, list[int]], paths: dict[int, list[Point]]
) -> None:
    """Several arrows on one side of a box meet it at different heights, in the order of
    where they come from, so they do not merge into one line."""
    sides: dict[tuple[int, str], list[tuple[float, int, int]]] = {}
    for number, chain in chains.items():
        points = paths[number]
        sides.setdefault((chain[0], "out"), []).append((points[1][1], number, 0))
        sides.setdefault((chain[-1], "in"), []).append((points[-2][1], number, len(points) - 1))
    for (n, _), ends in sides.items():
        node = nodes[n]
        if node.kind != "state" or len(ends) < 2:
            continue
        ends.sort()
        step = min(8.0, node.box_height * 0.6 / (len(ends) - 1))
        for k, (_, number, at) in enumerate(ends):
            x, _y = paths[number][at]
            paths[number][at] = (x, node.box_center_y + (k - (len(ends) - 1) / 2) * step)


def _smooth(a: Point, b: Point) -> Cubic:
    """A curve from ``a`` to ``b`` leaving and arriving horizontally."""
    middle = (a[0] + b[0]) / 2
    return (a, (middle, a[1]), (middle, b[1]), b)


def _self_loop(node: _Node, k: int, name: str, parent: str | None) -> EdgeLine:
    """The ``k``-th arc over a box's top, back into itself; the labels above the arcs."""
    label = node.loops[k]
    top = node.y + node.height / 2 - node.box_height
    reach = _LOOP_H * (k + 1) / len(node.loops)
    quarter = node.box_width / 4
    right = (node.x + quarter, top)
    left = (node.x - quarter, top)
    curve = (right, (right[0], top - reach * 1.33), (left[0], top - reach * 1.33), left)
    width = text_width_px(label, LABEL_FONT_PX) + 2 * _LABEL_PAD
    label_top = top - _LOOP_H - _LABEL_H * (len(node.loops) - k)
    rect = (node.x - width / 2, label_top, width, _LABEL_H)
    return EdgeLine(name, name, label, (curve,), rect, parent)
