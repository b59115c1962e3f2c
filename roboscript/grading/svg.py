"""Pictures of a graded run as inline SVG: the trajectory over the world, and the state timeline.

Plain text, no plotting library: the HTML report embeds them, so it is one self-contained file
per run. Every mark has a shape as well as a colour (start ring, end square, collision cross,
tone diamond, violation ring with "!"), and a ``<title>`` that screen readers and mouse
hover show.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from html import escape

from roboscript.grading.expectations import Expectation
from roboscript.grading.record import RunRecord, Verdict
from roboscript.sim.world import World

__all__ = ["STATE_COLOURS", "state_colours", "timeline_svg", "trajectory_svg"]

STATE_COLOURS = (
    "#4e79a7",
    "#f28e2b",
    "#59a14f",
    "#b07aa1",
    "#edc948",
    "#76b7b2",
    "#ff9da7",
    "#9c755f",
    "#bab0ac",
    "#e15759",
)
"""Colour-blind-friendly fills for states, in the order states are first entered."""

PATH = "#1f5fbf"
START = "#2e7d32"
END = "#c62828"
COLLISION = "#e65100"
TONE = "#6a1b9a"
VIOLATION = "#d50000"
REGION = "#43a047"
WALL = "#212121"
TAPE = "#616161"


def _f(value: float) -> str:
    return f"{value:.1f}"


class _Frame:
    """World millimetres to SVG pixels: x east to the right, y north up, equal scale."""

    def __init__(
        self, xs: Sequence[float], ys: Sequence[float], width_px: float, max_height_px: float
    ) -> None:
        pad_mm = 150.0
        self.min_x = min(xs) - pad_mm
        self.max_y = max(ys) + pad_mm
        span_x = max(max(xs) - min(xs) + 2 * pad_mm, 600.0)
        span_y = max(max(ys) - min(ys) + 2 * pad_mm, 600.0)
        # Centre a small drawing in its minimum span.
        self.min_x -= (span_x - (max(xs) - min(xs) + 2 * pad_mm)) / 2
        self.max_y += (span_y - (max(ys) - min(ys) + 2 * pad_mm)) / 2
        # A long world (a corridor) is drawn narrower, so the picture fits on a screen.
        self.scale = min(width_px / span_x, max_height_px / span_y)
        self.width = span_x * self.scale
        self.height = span_y * self.scale

    def x(self, x_mm: float) -> float:
        return (x_mm - self.min_x) * self.scale

    def y(self, y_mm: float) -> float:
        return (self.max_y - y_mm) * self.scale

    def point(self, x_mm: float, y_mm: float) -> str:
        return f"{_f(self.x(x_mm))},{_f(self.y(y_mm))}"

    def target_circle(self, x_mm: float, y_mm: float, radius_mm: float, title: str) -> str:
        """A dashed circle an expectation's target is drawn as (see ``Rule.draw``)."""
        return (
            f'<circle cx="{_f(self.x(x_mm))}" cy="{_f(self.y(y_mm))}"'
            f' r="{_f(radius_mm * self.scale)}" fill="none" stroke="{END}"'
            f' stroke-width="1.5" stroke-dasharray="5 4"><title>{escape(title)}</title></circle>'
        )


def _extent(world: World, record: RunRecord) -> tuple[list[float], list[float]]:
    xs: list[float] = []
    ys: list[float] = []
    for seg in world.walls:
        xs += [seg.x0, seg.x1]
        ys += [seg.y0, seg.y1]
    for line in world.lines:
        for seg in line.segments:
            xs += [seg.x0, seg.x1]
            ys += [seg.y0, seg.y1]
    for region in world.regions.values():
        if region.radius_mm is not None:
            cx, cy = region.center
            xs += [cx - region.radius_mm, cx + region.radius_mm]
            ys += [cy - region.radius_mm, cy + region.radius_mm]
        else:
            xs += [p[0] for p in region.points]
            ys += [p[1] for p in region.points]
    xs += [p[1] for p in record.path]
    ys += [p[2] for p in record.path]
    xs.append(record.final_pose[0])
    ys.append(record.final_pose[1])
    return xs, ys


def trajectory_svg(
    world: World,
    record: RunRecord,
    verdicts: Sequence[Verdict] = (),
    expectations: Sequence[Expectation] = (),
    width_px: float = 640.0,
    max_height_px: float = 560.0,
    id_suffix: str = "",
) -> str:
    """The run seen from above: world, path, start and end, collisions, tones, violations.

    Args:
        world: The world the run happened in.
        record: The run.
        verdicts: Their first violations are marked on the path.
        expectations: Each draws its target for this run (``final_pose_within``: a dashed
            circle).
        width_px: Largest width of the picture.
        max_height_px: Largest height of the picture.
        id_suffix: Added to the element ids, to tell several pictures on one page apart.
    """
    xs, ys = _extent(world, record)
    frame = _Frame(xs, ys, width_px, max_height_px)
    out: list[str] = []
    title = (
        f"Trajectory of {record.mission} in the world {world.name} (seed {record.seed}):"
        f" {_plural(len(record.collisions), 'collision')}, {_plural(len(record.tones), 'tone')},"
        f" ended at ({record.final_pose[0]:.0f}, {record.final_pose[1]:.0f}) mm"
    )
    out.append(
        f'<svg xmlns="http://www.w3.org/2000/svg" role="img"'
        f' aria-labelledby="traj-title{id_suffix}"'
        f' width="{_f(frame.width)}" height="{_f(frame.height)}"'
        f' viewBox="0 0 {_f(frame.width)} {_f(frame.height)}" class="trajectory">'
    )
    out.append(f'<title id="traj-title{id_suffix}">{escape(title)}</title>')
    out.append(f'<rect width="{_f(frame.width)}" height="{_f(frame.height)}" fill="#fbfbf8"/>')
    out += _grid(frame)
    for region in world.regions.values():
        out += _region(frame, region.name, region.center, region.radius_mm, region.points)
    for line in world.lines:
        pts = [frame.point(line.segments[0].x0, line.segments[0].y0)]
        pts += [frame.point(seg.x1, seg.y1) for seg in line.segments]
        width = max(2.0, line.width_mm * frame.scale)
        out.append(
            f'<polyline points="{" ".join(pts)}" fill="none" stroke="{TAPE}"'
            f' stroke-width="{_f(width)}" stroke-linejoin="round"><title>floor tape</title>'
            "</polyline>"
        )
    for seg in world.walls:
        out.append(
            f'<line x1="{_f(frame.x(seg.x0))}" y1="{_f(frame.y(seg.y0))}"'
            f' x2="{_f(frame.x(seg.x1))}" y2="{_f(frame.y(seg.y1))}" stroke="{WALL}"'
            ' stroke-width="3" stroke-linecap="round"/>'
        )
    for expectation in expectations:
        out += expectation.for_record(record).draw(record, frame)
    if record.path:
        trail = " ".join(frame.point(x, y) for _, x, y, _ in record.path)
        out.append(
            f'<polyline points="{trail}" fill="none" stroke="{PATH}" stroke-width="2.2"'
            ' stroke-linejoin="round" stroke-linecap="round"><title>the path of the robot'
            " centre</title></polyline>"
        )
    sx, sy, _ = record.start_pose
    out.append(
        f'<circle cx="{_f(frame.x(sx))}" cy="{_f(frame.y(sy))}" r="7" fill="white"'
        f' stroke="{START}" stroke-width="3"><title>start ({sx:.0f}, {sy:.0f}) mm</title></circle>'
    )
    out += _robot_at_end(frame, record)
    for hit in record.collisions:
        cx, cy = frame.x(hit.x_mm), frame.y(hit.y_mm)
        out.append(
            f'<g stroke="{COLLISION}" stroke-width="3"><title>collision at {hit.t_s:.1f} s'
            f" ({hit.side} bumper)</title>"
            f'<line x1="{_f(cx - 6)}" y1="{_f(cy - 6)}" x2="{_f(cx + 6)}" y2="{_f(cy + 6)}"/>'
            f'<line x1="{_f(cx - 6)}" y1="{_f(cy + 6)}" x2="{_f(cx + 6)}" y2="{_f(cy - 6)}"/></g>'
        )
    for tone in record.tones:
        x, y, _ = record.pose_at(tone.t_s)
        cx, cy = frame.x(x), frame.y(y)
        out.append(
            f'<polygon points="{_f(cx)},{_f(cy - 7)} {_f(cx + 6)},{_f(cy)} {_f(cx)},{_f(cy + 7)}'
            f' {_f(cx - 6)},{_f(cy)}" fill="{TONE}" stroke="white" stroke-width="1">'
            f"<title>tone {tone.frequency_hz:g} Hz at {tone.t_s:.1f} s</title></polygon>"
        )
    for verdict in verdicts:
        if verdict.first_violation_s is None:
            continue
        x, y, _ = record.pose_at(verdict.first_violation_s)
        cx, cy = frame.x(x), frame.y(y)
        out.append(
            f"<g><title>{escape(verdict.name)} first failed here, at"
            f" {verdict.first_violation_s:.1f} s</title>"
            f'<circle cx="{_f(cx)}" cy="{_f(cy)}" r="11" fill="white" fill-opacity="0.85"'
            f' stroke="{VIOLATION}" stroke-width="3"/>'
            f'<text x="{_f(cx)}" y="{_f(cy + 5)}" text-anchor="middle" font-size="14"'
            f' font-weight="bold" fill="{VIOLATION}">!</text></g>'
        )
    out.append(_scale_bar(frame))
    out.append("</svg>")
    return "\n".join(out)


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _grid(frame: _Frame) -> list[str]:
    step = 500.0 if frame.width / frame.scale < 4000 else 1000.0
    out = []
    x = math.ceil(frame.min_x / step) * step
    right = frame.min_x + frame.width / frame.scale
    while x <= right:
        out.append(
            f'<line x1="{_f(frame.x(x))}" y1="0" x2="{_f(frame.x(x))}" y2="{_f(frame.height)}"'
            ' stroke="#e3e3dc" stroke-width="1"/>'
        )
        x += step
    bottom = frame.max_y - frame.height / frame.scale
    y = math.ceil(bottom / step) * step
    while y <= frame.max_y:
        out.append(
            f'<line x1="0" y1="{_f(frame.y(y))}" x2="{_f(frame.width)}" y2="{_f(frame.y(y))}"'
            ' stroke="#e3e3dc" stroke-width="1"/>'
        )
        y += step
    return out


def _region(
    frame: _Frame,
    name: str,
    center: tuple[float, float],
    radius_mm: float | None,
    points: Sequence[tuple[float, float]],
) -> list[str]:
    style = (
        f'fill="{REGION}" fill-opacity="0.12" stroke="{REGION}" stroke-width="1.5"'
        ' stroke-dasharray="6 3"'
    )
    if radius_mm is not None:
        tag = "circle"
        shape = (
            f'<circle cx="{_f(frame.x(center[0]))}" cy="{_f(frame.y(center[1]))}"'
            f' r="{_f(radius_mm * frame.scale)}" {style}>'
        )
        top = center[1] + radius_mm
    else:
        tag = "polygon"
        pts = " ".join(frame.point(x, y) for x, y in points)
        shape = f'<polygon points="{pts}" {style}>'
        top = max(y for _, y in points)
    return [
        f"{shape}<title>region {escape(name)}</title></{tag}>",
        (
            f'<text x="{_f(frame.x(center[0]))}" y="{_f(frame.y(top) + 14)}" text-anchor="middle"'
            f' font-size="12" fill="#1b5e20">{escape(name)}</text>'
        ),
    ]


def _robot_at_end(frame: _Frame, record: RunRecord) -> list[str]:
    x, y, heading = record.final_pose
    cx, cy = frame.x(x), frame.y(y)
    radius = record.body_radius_mm * frame.scale
    rad = math.radians(heading)
    nose_x, nose_y = cx + math.sin(rad) * radius, cy - math.cos(rad) * radius
    return [
        (
            f"<g><title>end ({x:.0f}, {y:.0f}) mm, heading {heading:.0f}°</title>"
            f'<circle cx="{_f(cx)}" cy="{_f(cy)}" r="{_f(radius)}" fill="{END}" fill-opacity="0.08"'
            f' stroke="{END}" stroke-width="1.5"/>'
            f'<line x1="{_f(cx)}" y1="{_f(cy)}" x2="{_f(nose_x)}" y2="{_f(nose_y)}" stroke="{END}"'
            ' stroke-width="2"/>'
            f'<rect x="{_f(cx - 6)}" y="{_f(cy - 6)}" width="12" height="12" fill="{END}"/></g>'
        )
    ]


def _scale_bar(frame: _Frame) -> str:
    length_mm = 500.0 if frame.width / frame.scale < 4000 else 1000.0
    x0, y0 = 12.0, frame.height - 14.0
    x1 = x0 + length_mm * frame.scale
    return (
        f'<g><line x1="{_f(x0)}" y1="{_f(y0)}" x2="{_f(x1)}" y2="{_f(y0)}" stroke="#333"'
        ' stroke-width="2"/>'
        f'<text x="{_f(x0)}" y="{_f(y0 - 5)}" font-size="11" fill="#333">'
        f"{length_mm / 10:.0f} cm (grid {length_mm / 10:.0f} cm)</text></g>"
    )


def state_colours(record: RunRecord) -> dict[str, str]:
    """A colour per state, in the order the states were first entered."""
    colours: dict[str, str] = {}
    for _, name in record.states:
        if name not in colours:
            colours[name] = STATE_COLOURS[len(colours) % len(STATE_COLOURS)]
    return colours


def _tick_step(duration_s: float) -> float:
    for step in (0.5, 1, 2, 5, 10, 20, 30, 60, 120, 300):
        if duration_s / step <= 12:
            return float(step)
    return 600.0


def timeline_svg(
    record: RunRecord,
    verdicts: Sequence[Verdict] = (),
    width_px: float = 900.0,
    id_suffix: str = "",
) -> str:
    """The states over time as a strip of bars, with tones, collisions and first violations.

    ``id_suffix`` is added to the element ids, to tell several pictures on one page apart.
    """
    duration = max(record.duration_s, 0.1)
    left, right = 10.0, 20.0
    scale = (width_px - left - right) / duration
    bar_y, bar_h = 8.0, 34.0
    marks_y = bar_y + bar_h + 18.0
    axis_y = marks_y + 16.0
    height = axis_y + 24.0
    colours = state_colours(record)
    names = " then ".join(name for _, name in record.states[:12])
    more = " ..." if len(record.states) > 12 else ""
    out = [
        (
            f'<svg xmlns="http://www.w3.org/2000/svg" role="img"'
            f' aria-labelledby="tl-title{id_suffix}" width="{_f(width_px)}" height="{_f(height)}"'
            f' viewBox="0 0 {_f(width_px)} {_f(height)}" class="timeline">'
        ),
        (
            f'<title id="tl-title{id_suffix}">State timeline over {duration:.1f} s:'
            f" {escape(names)}{more}</title>"
        ),
    ]
    for start, end, name in record.state_intervals():
        x = left + start * scale
        w = max(1.0, (end - start) * scale)
        out.append(
            f"<g><title>{escape(name)}: {start:.2f} s to {end:.2f} s</title>"
            f'<rect x="{_f(x)}" y="{_f(bar_y)}" width="{_f(w)}" height="{_f(bar_h)}"'
            f' fill="{colours[name]}" stroke="white" stroke-width="1"/>'
        )
        if w > 7.5 * len(name) + 6:
            out.append(
                f'<text x="{_f(x + w / 2)}" y="{_f(bar_y + bar_h / 2 + 4)}" text-anchor="middle"'
                f' font-size="12" fill="#111">{escape(name)}</text>'
            )
        out.append("</g>")
    for tone in record.tones:
        cx = left + tone.t_s * scale
        out.append(
            f'<polygon points="{_f(cx)},{_f(marks_y - 6)} {_f(cx + 5)},{_f(marks_y)}'
            f' {_f(cx)},{_f(marks_y + 6)} {_f(cx - 5)},{_f(marks_y)}" fill="{TONE}">'
            f"<title>tone {tone.frequency_hz:g} Hz at {tone.t_s:.1f} s</title></polygon>"
        )
    for hit in record.collisions:
        cx = left + hit.t_s * scale
        out.append(
            f'<g stroke="{COLLISION}" stroke-width="2.5"><title>collision at {hit.t_s:.1f} s'
            f'</title><line x1="{_f(cx - 5)}" y1="{_f(marks_y - 5)}" x2="{_f(cx + 5)}"'
            f' y2="{_f(marks_y + 5)}"/><line x1="{_f(cx - 5)}" y1="{_f(marks_y + 5)}"'
            f' x2="{_f(cx + 5)}" y2="{_f(marks_y - 5)}"/></g>'
        )
    for verdict in verdicts:
        if verdict.first_violation_s is None:
            continue
        cx = left + min(verdict.first_violation_s, duration) * scale
        out.append(
            f"<g><title>{escape(verdict.name)} first failed at"
            f" {verdict.first_violation_s:.1f} s</title>"
            f'<line x1="{_f(cx)}" y1="{_f(bar_y - 4)}" x2="{_f(cx)}" y2="{_f(marks_y + 8)}"'
            f' stroke="{VIOLATION}" stroke-width="2" stroke-dasharray="3 2"/>'
            f'<circle cx="{_f(cx)}" cy="{_f(marks_y)}" r="7" fill="white" stroke="{VIOLATION}"'
            ' stroke-width="2"/>'
            f'<text x="{_f(cx)}" y="{_f(marks_y + 4)}" text-anchor="middle" font-size="11"'
            f' font-weight="bold" fill="{VIOLATION}">!</text></g>'
        )
    step = _tick_step(duration)
    out.append(
        f'<line x1="{_f(left)}" y1="{_f(axis_y)}" x2="{_f(left + duration * scale)}"'
        f' y2="{_f(axis_y)}" stroke="#555"/>'
    )
    t = 0.0
    while t <= duration + 1e-9:
        x = left + t * scale
        out.append(
            f'<line x1="{_f(x)}" y1="{_f(axis_y)}" x2="{_f(x)}" y2="{_f(axis_y + 4)}"'
            ' stroke="#555"/>'
            f'<text x="{_f(x)}" y="{_f(axis_y + 16)}" text-anchor="middle" font-size="11"'
            f' fill="#333">{t:g} s</text>'
        )
        t += step
    out.append("</svg>")
    return "\n".join(out)
