"""A picture of a simulated run: the world, the path, collisions and tones, as a PNG.

Needs matplotlib (``pip install 'roboscript[plot]'``), imported only when a plot is drawn and
used through its Agg canvas, so no window opens and no global backend is changed.

Example:
    >>> from roboscript.sim.plot import plot_run
    >>> plot_run(sim.world, sim.log, "square: success", "square.png")  # doctest: +SKIP
"""

from __future__ import annotations

import bisect
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from roboscript.errors import RoboscriptError
from roboscript.sim.body import SimLog
from roboscript.sim.geometry import Segment
from roboscript.sim.world import World

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["PlotUnavailableError", "plot_run", "require_matplotlib"]

_MARGIN_MM = 150.0
_WALL = "#222222"
_TAPE = "#9a9a9a"
_PATH = "#1f6fb4"
_REGION = "#2ca02c"


class PlotUnavailableError(RoboscriptError, ImportError):
    """matplotlib, which plotting needs, is not installed."""


def require_matplotlib() -> None:
    """Check that plots can be drawn.

    Raises:
        PlotUnavailableError: matplotlib is not installed.
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise PlotUnavailableError(
            "--plot needs matplotlib, which is not installed (pip install 'roboscript[plot]')"
        ) from None


def plot_run(
    world: World,
    log: SimLog,
    title: str,
    path: str | Path,
    *,
    body_radius_mm: float | None = None,
) -> None:
    """Draw a run over its world and save it as a PNG.

    Walls are black, floor tape grey, named regions green with their names; the path is blue
    from a start marker to an end marker; crosses mark where collisions began and stars where
    tones were played. Axes are millimetres (x east, y north) at equal scale.

    Args:
        world: The world the run took place in.
        log: What happened: path, collisions, tones (all on the simulation clock).
        title: Title above the plot, e.g. the mission name and outcome.
        path: Where to write the PNG.
        body_radius_mm: If given, the robot's outline is drawn at its end pose.

    Raises:
        PlotUnavailableError: matplotlib is not installed.
        OSError: The file cannot be written.
    """
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    x0, y0, x1, y1 = _bounds(world, log)
    width_mm, height_mm = x1 - x0, y1 - y0
    # About 8 inches on the long side, the other in proportion (but never a sliver).
    scale = 8.0 / max(width_mm, height_mm)
    size = (max(4.5, width_mm * scale + 1.5), max(4.0, height_mm * scale + 1.0))
    figure = Figure(figsize=size, dpi=110, layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    _draw_world(axes, world)
    _draw_run(axes, log, body_radius_mm)
    axes.set_xlim(x0, x1)
    axes.set_ylim(y0, y1)
    axes.set_aspect("equal", adjustable="box")
    axes.set_xlabel("x (mm, east)")
    axes.set_ylabel("y (mm, north)")
    axes.grid(True, color="#dddddd", linewidth=0.6)
    axes.set_axisbelow(True)
    axes.set_title(title)
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, frameon=False)
    figure.savefig(Path(path), format="png")


def _bounds(world: World, log: SimLog) -> tuple[float, float, float, float]:
    xs: list[float] = [world.start.x_mm]
    ys: list[float] = [world.start.y_mm]
    for seg in world.walls:
        xs += (seg.x0, seg.x1)
        ys += (seg.y0, seg.y1)
    for line in world.lines:
        for seg in line.segments:
            xs += (seg.x0, seg.x1)
            ys += (seg.y0, seg.y1)
    for region in world.regions.values():
        if region.radius_mm is not None:
            cx, cy = region.center
            xs += (cx - region.radius_mm, cx + region.radius_mm)
            ys += (cy - region.radius_mm, cy + region.radius_mm)
        else:
            xs += [p[0] for p in region.points]
            ys += [p[1] for p in region.points]
    xs += [sample[1] for sample in log.path]
    ys += [sample[2] for sample in log.path]
    x0, x1 = min(xs) - _MARGIN_MM, max(xs) + _MARGIN_MM
    y0, y1 = min(ys) - _MARGIN_MM, max(ys) + _MARGIN_MM
    return x0, y0, x1, y1


def _draw_world(axes: Axes, world: World) -> None:
    from matplotlib.patches import Circle, Polygon

    for name, region in world.regions.items():
        patch: Any
        if region.radius_mm is not None:
            patch = Circle(region.center, region.radius_mm)
        else:
            patch = Polygon(list(region.points), closed=True)
        patch.set(facecolor=_REGION, alpha=0.12, edgecolor=_REGION, linewidth=1.0, zorder=1)
        axes.add_patch(patch)
        # Labelled near the top, clear of a robot starting at the centre.
        cx, cy = region.center
        if region.radius_mm is not None:
            top, height = cy + region.radius_mm, 2.0 * region.radius_mm
        else:
            ys = [p[1] for p in region.points]
            top, height = max(ys), max(ys) - min(ys)
        axes.annotate(
            name,
            (cx, top - 0.08 * height),
            ha="center",
            va="top",
            fontsize=8,
            color="#1a661a",
            zorder=6,
        )
    for index, line in enumerate(world.lines):
        # One stroke per run of joined segments, so the joints do not show.
        for k, (xs, ys) in enumerate(_strokes(line.segments)):
            axes.plot(
                xs,
                ys,
                color=_TAPE,
                linewidth=3.5,
                solid_capstyle="round",
                solid_joinstyle="round",
                zorder=2,
                label="floor tape" if index == 0 and k == 0 else None,
            )
    for k, seg in enumerate(world.walls):
        axes.plot(
            (seg.x0, seg.x1),
            (seg.y0, seg.y1),
            color=_WALL,
            linewidth=2.5,
            solid_capstyle="projecting",
            zorder=3,
            label="wall" if k == 0 else None,
        )


def _strokes(segments: tuple[Segment, ...]) -> list[tuple[list[float], list[float]]]:
    """Chains of segments that meet end to start, as x and y lists."""
    strokes: list[tuple[list[float], list[float]]] = []
    for seg in segments:
        if strokes and (strokes[-1][0][-1], strokes[-1][1][-1]) == (seg.x0, seg.y0):
            strokes[-1][0].append(seg.x1)
            strokes[-1][1].append(seg.y1)
        else:
            strokes.append(([seg.x0, seg.x1], [seg.y0, seg.y1]))
    return strokes


def _draw_run(axes: Axes, log: SimLog, body_radius_mm: float | None) -> None:
    from matplotlib.patches import Circle

    path = log.path
    if not path:
        return
    xs = [sample[1] for sample in path]
    ys = [sample[2] for sample in path]
    axes.plot(xs, ys, color=_PATH, linewidth=1.6, zorder=4, label="path")
    start, end = path[0], path[-1]
    # A ring, so an end marker on the same spot (a closed path) leaves it visible.
    axes.plot(
        start[1],
        start[2],
        "o",
        markerfacecolor="none",
        markeredgecolor="#2ca02c",
        markeredgewidth=2.2,
        markersize=13,
        zorder=7,
        label="start",
    )
    axes.plot(end[1], end[2], "s", color="#d62728", markersize=8, zorder=7, label="end")
    if body_radius_mm is not None:
        axes.add_patch(
            Circle(
                (end[1], end[2]),
                body_radius_mm,
                fill=False,
                edgecolor="#d62728",
                linewidth=1.0,
                linestyle="--",
                zorder=5,
            )
        )
        heading = math.radians(end[3])
        axes.plot(
            (end[1], end[1] + body_radius_mm * math.sin(heading)),
            (end[2], end[2] + body_radius_mm * math.cos(heading)),
            color="#d62728",
            linewidth=1.0,
            zorder=5,
        )
    hits = [(c.x_mm, c.y_mm) for c in log.contacts]
    if hits:
        axes.plot(
            [p[0] for p in hits],
            [p[1] for p in hits],
            "X",
            color="#ff7f0e",
            markersize=11,
            markeredgecolor="black",
            markeredgewidth=0.6,
            linestyle="none",
            zorder=8,
            label=f"collision ({len(hits)})",
        )
    if log.tones:
        places = [_position_at(path, t) for t, _, _ in log.tones]
        axes.plot(
            [p[0] for p in places],
            [p[1] for p in places],
            "*",
            color="#9467bd",
            markersize=13,
            markeredgecolor="black",
            markeredgewidth=0.5,
            linestyle="none",
            zorder=8,
            label=f"tone ({len(places)})",
        )


def _position_at(
    path: list[tuple[float, float, float, float]], time_s: float
) -> tuple[float, float]:
    """Where the path was at ``time_s``, interpolated between its samples."""
    times = [sample[0] for sample in path]
    i = bisect.bisect_right(times, time_s)
    if i == 0:
        return path[0][1], path[0][2]
    if i == len(path):
        return path[-1][1], path[-1][2]
    (t0, x0, y0, _), (t1, x1, y1, _) = path[i - 1], path[i]
    f = 0.0 if t1 == t0 else (time_s - t0) / (t1 - t0)
    return x0 + f * (x1 - x0), y0 + f * (y1 - y0)
