"""A mission's state diagram as a picture: SVG (standard library) or PNG (matplotlib).

``roboscript graph MISSION --format svg|png`` draws what :mod:`roboscript.mission.graph_layout`
lays out: a box per state (final states green or red with a double border, nested states as
dashed boxes holding their own diagram), an arrow per transition labelled with its trigger and
condition, and a dot where the mission starts. Given a run (:class:`RunMarks`), the states it
visited are drawn in blue with how often and when they were first entered, the transitions it
took in blue, the state it ended in with a thick border, and the rest in grey.

Every text in the SVG is escaped: state names and conditions come from a student's file.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import escape, quoteattr

from roboscript.errors import RoboscriptError
from roboscript.mission.graph_layout import (
    DETAIL_FONT_PX,
    LABEL_FONT_PX,
    NAME_FONT_PX,
    TITLE_FONT_PX,
    Cubic,
    Diagram,
    EdgeLine,
    Point,
    StateBox,
    layout,
)
from roboscript.mission.spec import MissionSpec

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["PictureUnavailableError", "RunMarks", "diagram_for", "to_svg", "write_png"]

_FONT = "Helvetica, Arial, 'DejaVu Sans', sans-serif"
_INK = "#222222"
_EDGE = "#555555"
_MUTED = "#b0b0b0"
_MUTED_TEXT = "#808080"
_VISITED = "#1f6fb4"
_VISITED_FILL = "#e3effa"
_FILL = {"success": "#c8f0c8", "failure": "#f6c6c6", None: "#ffffff"}
_STROKE = {"success": "#2a7a2a", "failure": "#a02020", None: _INK}
_ARROW_PX = 8.0
_DOUBLE_PX = 3.0  # the inner border of a final state


class PictureUnavailableError(RoboscriptError, ImportError):
    """matplotlib, which a PNG needs, is not installed."""


@dataclass(frozen=True)
class RunMarks:
    """What one run did, to highlight on the diagram.

    Attributes:
        entered: Every state entered, in order, as ``(mission time s, full name)``; a state
            inside a nested one is ``outer.inner``.
        outcome: ``success``, ``failure`` or ``error``, or ``None`` if not known.
        final_state: The state the run ended in, or ``None``.
    """

    entered: tuple[tuple[float, str], ...]
    outcome: str | None = None
    final_state: str | None = None
    visits: Mapping[str, int] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        counts: dict[str, int] = {}
        for _, name in self.entered:
            counts[name] = counts.get(name, 0) + 1
        object.__setattr__(self, "visits", counts)

    @classmethod
    def from_frames(
        cls, frames: Iterable[Mapping[str, Any]], result: Mapping[str, Any] | None
    ) -> RunMarks:
        """The marks of a recorded run (:func:`roboscript.replay.recording.load_recording`).

        The result's ``states`` list is used when the recording has one (it holds every
        entry, also a state left within one tick); otherwise each change of the frames'
        ``state``.
        """
        entered: list[tuple[float, str]] = []
        listed = (result or {}).get("states")
        if isinstance(listed, list) and all(
            isinstance(item, list | tuple) and len(item) == 2 for item in listed
        ):
            entered = [(float(t), str(name)) for t, name in listed]
        else:
            last = None
            for frame in frames:
                name = frame.get("state")
                if isinstance(name, str) and name != last:
                    entered.append((float(frame.get("t", 0.0)), name))
                    last = name
        result = result or {}
        outcome = result.get("outcome")
        final = result.get("final_state")
        return cls(
            tuple(entered),
            outcome if isinstance(outcome, str) else None,
            final if isinstance(final, str) else (entered[-1][1] if entered else None),
        )

    def visited(self, name: str) -> bool:
        """Whether the run entered ``name`` (a nested state: or any state inside it)."""
        return name in self.visits or any(n.startswith(name + ".") for n in self.visits)

    def took(self, edge: EdgeLine) -> bool:
        """Whether the run went along ``edge`` (the start's arrow: entered its first state).

        Two transitions between the same states (``done`` and ``when``, say) cannot be told
        apart from the states alone: both count as taken.
        """
        if edge.source is None:
            return self.visited(edge.dest)
        names = [name for _, name in self.entered]
        for before, after in itertools.pairwise(names):
            left = before == edge.source or before.startswith(edge.source + ".")
            if left and (after == edge.dest or after.startswith(edge.dest + ".")):
                return True
        return False

    def note(self, name: str) -> str | None:
        """The line a visited plain state shows: how many times, and when first."""
        count = self.visits.get(name, 0)
        if not count:
            return None
        first = next(t for t, n in self.entered if n == name)
        times = "once" if count == 1 else f"{count} times"
        return f"visited {times}, first at {first:.2f} s"


def diagram_for(spec: MissionSpec, run: RunMarks | None = None) -> Diagram:
    """Lay out ``spec``, with room for a run's notes under the states it visited."""
    notes: dict[str, str] = {}
    if run is not None:
        for name in run.visits:
            note = run.note(name)
            if note is not None:
                notes[name] = note
    return layout(spec, notes)


def _caption(spec: MissionSpec, run: RunMarks | None) -> str:
    if run is None or run.outcome is None:
        return spec.name
    ended = f" in '{run.final_state}'" if run.final_state else ""
    return f"{spec.name}: {run.outcome}{ended}"


# ------------------------------------------------------------------------------------ SVG


def _num(value: float) -> str:
    return f"{value:.1f}".rstrip("0").rstrip(".")


def _tag(name: str, attrs: Mapping[str, object], text: str | None = None) -> str:
    """One SVG element; numbers are written to 0.1 px, every value and text is escaped."""
    written = "".join(
        f" {key.replace('_', '-')}={quoteattr(_num(v) if isinstance(v, float) else str(v))}"
        for key, v in attrs.items()
        if v is not None
    )
    if text is None:
        return f"<{name}{written}/>"
    return f"<{name}{written}>{escape(text)}</{name}>"


def _path_d(curves: Sequence[Cubic]) -> str:
    def pair(point: Point) -> str:
        return f"{_num(point[0])},{_num(point[1])}"

    parts = [f"M{pair(curves[0][0])}"]
    parts.extend(f"C{pair(c1)} {pair(c2)} {pair(end)}" for _, c1, c2, end in curves)
    return " ".join(parts)


def _arrowhead(curves: Sequence[Cubic]) -> list[Point]:
    """A triangle at the end of the last curve, along its final direction."""
    _, _, before, tip = curves[-1]
    dx, dy = tip[0] - before[0], tip[1] - before[1]
    length = (dx * dx + dy * dy) ** 0.5 or 1.0
    ux, uy = dx / length, dy / length
    base = (tip[0] - ux * _ARROW_PX, tip[1] - uy * _ARROW_PX)
    half = _ARROW_PX * 0.45
    return [
        tip,
        (base[0] - uy * half, base[1] + ux * half),
        (base[0] + uy * half, base[1] - ux * half),
    ]


def _state_colours(box: StateBox, run: RunMarks | None) -> tuple[str, str, float, str]:
    """(fill, stroke, stroke width, text colour) of a box."""
    fill, stroke, width, text = _FILL[box.final], _STROKE[box.final], 1.5, _INK
    if box.nested:
        fill = "none"
    if run is not None:
        if run.visited(box.name):
            stroke, width = _VISITED, 2.5
            if box.final is None and not box.nested:
                fill = _VISITED_FILL
        else:
            stroke, text = _MUTED, _MUTED_TEXT
        if box.name == run.final_state:
            width = 4.0
    return fill, stroke, width, text


def _edge_colours(edge: EdgeLine, run: RunMarks | None) -> tuple[bool, str, float, str]:
    """(taken, line colour, line width, label colour) of an arrow."""
    if run is None:
        return False, _EDGE, 1.2, _INK
    if run.took(edge):
        return True, _VISITED, 2.2, _INK
    return False, _MUTED, 1.2, _MUTED_TEXT


def _state_classes(box: StateBox, run: RunMarks | None) -> str:
    classes = ["state"]
    if box.nested:
        classes.append("nested")
    if box.final:
        classes.append(f"final-{box.final}")
    if run is not None:
        classes.append("visited" if run.visited(box.name) else "not-visited")
        if box.name == run.final_state:
            classes.append("ended")
    return " ".join(classes)


def _svg_state(box: StateBox, run: RunMarks | None) -> list[str]:
    x, y, w, h = box.rect
    fill, stroke, width, colour = _state_colours(box, run)
    tip = box.name
    if run is not None:
        seen = run.note(box.name) or ("visited" if run.visited(box.name) else "not visited")
        tip += f": {seen}"
    out = [
        f"<g class={quoteattr(_state_classes(box, run))} data-state={quoteattr(box.name)}>",
        _tag("title", {}, tip),
        _tag(
            "rect",
            {
                "x": x, "y": y, "width": w, "height": h, "rx": 6.0, "fill": fill,
                "stroke": stroke, "stroke_width": width,
                "stroke_dasharray": "6 4" if box.nested else None,
            },
        ),
    ]  # fmt: skip
    if box.final:
        inset = _DOUBLE_PX + width / 2
        out.append(
            _tag(
                "rect",
                {
                    "x": x + inset, "y": y + inset, "width": w - 2 * inset,
                    "height": h - 2 * inset, "rx": 4.0, "fill": "none", "stroke": stroke,
                    "stroke_width": 1.0,
                },
            )
        )  # fmt: skip
    name = {"font_size": NAME_FONT_PX, "font_weight": "bold", "fill": colour}
    if box.nested:
        out.append(_tag("text", {"x": x + 10, "y": y + 17, **name}, box.title))
    else:
        middle = {"x": x + w / 2, "text_anchor": "middle"}
        out.append(_tag("text", {**middle, "y": y + 18, **name}, box.title))
        for k, line in enumerate(box.lines):
            detail = {"y": y + 33 + 15 * k, "font_size": DETAIL_FONT_PX, "fill": colour}
            out.append(_tag("text", {**middle, **detail}, line))
    out.append("</g>")
    return out


def _svg_edge(edge: EdgeLine, run: RunMarks | None) -> list[str]:
    taken, colour, width, text = _edge_colours(edge, run)
    group = {
        "class": "edge taken" if taken else "edge",
        "data_source": edge.source,
        "data_dest": edge.dest,
        "data_label": edge.label,
    }
    head = " ".join(f"{_num(px)},{_num(py)}" for px, py in _arrowhead(edge.curves))
    out = [
        _tag("g", group).replace("/>", ">"),
        _tag("path", {"d": _path_d(edge.curves), "fill": "none", "stroke": colour,
                      "stroke_width": width}),
        _tag("polygon", {"points": head, "fill": colour}),
    ]  # fmt: skip
    if edge.label_rect is not None:
        x, y, w, h = edge.label_rect
        out.append(
            _tag("rect", {"x": x, "y": y, "width": w, "height": h, "rx": 3.0,
                          "fill": "#ffffff", "fill_opacity": 0.9})
        )  # fmt: skip
        out.append(
            _tag(
                "text",
                {"x": x + w / 2, "y": y + h / 2 + 4, "text_anchor": "middle",
                 "font_size": LABEL_FONT_PX, "fill": text},
                edge.label,
            )
        )  # fmt: skip
    out.append("</g>")
    return out


def to_svg(spec: MissionSpec, run: RunMarks | None = None) -> str:
    """The mission's state diagram as a standalone SVG document.

    Args:
        spec: The mission.
        run: A run to highlight, or ``None``.

    Returns:
        The SVG text. Each state is a ``<g class="state ...">`` with ``data-state`` (its full
        name) and the classes ``visited``/``not-visited`` and ``ended`` when a run is given;
        each transition a ``<g class="edge ...">`` with ``data-source`` (none from the start
        dot), ``data-dest``, ``data-label`` and the class ``taken``.
    """
    diagram = diagram_for(spec, run)
    width, height = diagram.width_px, diagram.height_px
    caption = _caption(spec, run)
    root = {
        "xmlns": "http://www.w3.org/2000/svg",
        "width": width,
        "height": height,
        "viewBox": f"0 0 {_num(width)} {_num(height)}",
        "font_family": _FONT,
        "role": "img",
        "aria_label": f"state diagram of {spec.name}",
    }
    title_x, title_y = diagram.title_pos
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        _tag("svg", root).replace("/>", ">"),
        _tag("title", {}, caption),
        _tag("rect", {"width": width, "height": height, "fill": "#ffffff"}),
        _tag(
            "text",
            {"class": "caption", "x": title_x, "y": title_y, "font_size": TITLE_FONT_PX,
             "font_weight": "bold", "fill": _INK},
            caption,
        ),
    ]  # fmt: skip
    for box in diagram.states:
        if box.nested:
            out.extend(_svg_state(box, run))
    for edge in diagram.edges:
        out.extend(_svg_edge(edge, run))
    for box in diagram.states:
        if not box.nested:
            out.extend(_svg_state(box, run))
    for mark in diagram.starts:
        cx, cy = mark.center
        out.append(
            _tag("circle", {"class": "start", "cx": cx, "cy": cy, "r": mark.radius_px,
                            "fill": _INK, "data_dest": mark.dest})
        )  # fmt: skip
    out.append("</svg>")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------------------------ PNG


def require_matplotlib(option: str = "--format png") -> None:
    """Check that a PNG can be drawn.

    Raises:
        PictureUnavailableError: matplotlib is not installed.
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise PictureUnavailableError(
            f"{option} needs matplotlib, which is not installed"
            " (pip install 'roboscript[plot]'; or use --format svg, which needs nothing)"
        ) from None


def write_png(spec: MissionSpec, path: str | Path, run: RunMarks | None = None) -> None:
    """Draw the mission's state diagram (as :func:`to_svg` does) into the PNG ``path``.

    Raises:
        PictureUnavailableError: matplotlib is not installed.
        OSError: The file cannot be written.
    """
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    diagram = diagram_for(spec, run)
    # One layout pixel is one point, so font sizes in px read as points; 144 dpi is 2×.
    figure = Figure(figsize=(diagram.width_px / 72, diagram.height_px / 72), dpi=144)
    FigureCanvasAgg(figure)
    axes = figure.add_axes((0.0, 0.0, 1.0, 1.0))
    axes.set_xlim(0, diagram.width_px)
    axes.set_ylim(diagram.height_px, 0)
    axes.axis("off")
    axes.text(
        diagram.title_pos[0],
        diagram.title_pos[1],
        _caption(spec, run),
        fontsize=TITLE_FONT_PX,
        fontweight="bold",
        color=_INK,
        va="baseline",
    )
    for box in diagram.states:
        if box.nested:
            _draw_state(axes, box, run)
    for edge in diagram.edges:
        _draw_edge(axes, edge, run)
    for box in diagram.states:
        if not box.nested:
            _draw_state(axes, box, run)
    from matplotlib.patches import Circle

    for mark in diagram.starts:
        axes.add_patch(Circle(mark.center, mark.radius_px, color=_INK, zorder=3))
    figure.savefig(Path(path), format="png", facecolor="#ffffff")


def _draw_state(axes: Axes, box: StateBox, run: RunMarks | None) -> None:
    from matplotlib.patches import FancyBboxPatch

    x, y, w, h = box.rect
    fill, stroke, width, colour = _state_colours(box, run)
    axes.add_patch(
        FancyBboxPatch(
            (x, y),
            w,
            h,
            boxstyle="round,pad=0,rounding_size=6",
            facecolor=fill,
            edgecolor=stroke,
            linewidth=width,
            linestyle="--" if box.nested else "-",
            zorder=1 if box.nested else 2,
        )
    )
    if box.final:
        inset = _DOUBLE_PX + width / 2
        axes.add_patch(
            FancyBboxPatch(
                (x + inset, y + inset),
                w - 2 * inset,
                h - 2 * inset,
                boxstyle="round,pad=0,rounding_size=4",
                facecolor="none",
                edgecolor=stroke,
                linewidth=1.0,
                zorder=2,
            )
        )
    name: dict[str, Any] = {
        "fontsize": NAME_FONT_PX,
        "fontweight": "bold",
        "color": colour,
        "zorder": 3,
    }
    if box.nested:
        axes.text(x + 10, y + 17, box.title, va="baseline", **name)
        return
    middle = x + w / 2
    axes.text(middle, y + 18, box.title, ha="center", va="baseline", **name)
    for k, line in enumerate(box.lines):
        axes.text(
            middle, y + 33 + 15 * k, line, fontsize=DETAIL_FONT_PX, color=colour,
            ha="center", va="baseline", zorder=3,
        )  # fmt: skip


def _draw_edge(axes: Axes, edge: EdgeLine, run: RunMarks | None) -> None:
    from matplotlib.patches import FancyBboxPatch, PathPatch, Polygon
    from matplotlib.path import Path as CurvePath

    _, colour, width, text = _edge_colours(edge, run)
    vertices: list[Point] = [edge.curves[0][0]]
    codes = [CurvePath.MOVETO]
    for _, c1, c2, end in edge.curves:
        vertices.extend([c1, c2, end])
        codes.extend([CurvePath.CURVE4] * 3)
    curve = CurvePath(vertices, codes)
    axes.add_patch(PathPatch(curve, fill=False, edgecolor=colour, linewidth=width, zorder=1.5))
    axes.add_patch(Polygon(_arrowhead(edge.curves), closed=True, color=colour, zorder=1.5))
    if edge.label_rect is None:
        return
    x, y, w, h = edge.label_rect
    axes.add_patch(
        FancyBboxPatch(
            (x, y), w, h, boxstyle="round,pad=0,rounding_size=3", facecolor="#ffffff",
            edgecolor="none", alpha=0.9, zorder=1.6,
        )
    )  # fmt: skip
    axes.text(
        x + w / 2, y + h / 2 + 4, edge.label, fontsize=LABEL_FONT_PX, ha="center",
        va="baseline", color=text, zorder=1.7,
    )  # fmt: skip
