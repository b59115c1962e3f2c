"""Sensor models of the simulator: an ultrasonic range sensor and IR floor sensors.

They are physics, not protocols: a :class:`~roboscript.sim.body.Body` owns them and a simulated
device encodes what they report (ASIP reads "no echo" as 0 cm, another protocol as -1).

**Ultrasonic range (HC-SR04-like).** A measurement casts ``rays`` rays spread evenly across the
beam cone and keeps the nearest echo. A ray echoes only if it meets the first wall in its way
within ``max_range_mm`` and at an incidence of at most ``incidence_max_deg`` from the wall's
normal: at a grazing angle the sound glances off and never comes back (Webots' sonar uses the
same cut-off, π/8 = 22.5°; with the 15° cone the sensor sees a wall turned up to 30° away from
square). The sensor measures at most once per ``period_s`` (the HC-SR04 needs a 60 ms cycle) and
reports its last measurement when read more often. Each echo gets seeded Gaussian noise.

**IR line sensors.** A sensor sees a round spot of the floor (``spot_mm`` across) and its
reading is proportional to the part of that spot covered by dark tape, so it changes smoothly
across a tape edge over the width of the spot and a line follower gets a proportional signal.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from roboscript.sim.geometry import Segment, SegmentGrid, closest_point
from roboscript.sim.world import TapeLine

__all__ = ["Sonar", "SonarSpec", "TapeReader", "spot_on_strip"]


@dataclass(frozen=True)
class SonarSpec:
    """Where an ultrasonic range sensor sits and how it measures.

    Attributes:
        forward_mm: Mount position ahead of the body centre (negative: behind).
        right_mm: Mount position right of the body centre (negative: left).
        bearing_deg: Direction it faces, clockwise from the robot's heading (90: right).
        cone_deg: Full width of the beam.
        rays: Rays cast across the beam (odd numbers include the axis).
        max_range_mm: Farthest echo reported.
        incidence_max_deg: Largest angle between a ray and a wall's normal that still echoes.
        noise_mm: Standard deviation of the noise added to each echo.
        period_s: Shortest time between two measurements.
    """

    forward_mm: float = 0.0
    right_mm: float = 0.0
    bearing_deg: float = 0.0
    cone_deg: float = 15.0
    rays: int = 7
    max_range_mm: float = 1000.0
    incidence_max_deg: float = 22.5
    noise_mm: float = 3.0
    period_s: float = 0.06


class Sonar:
    """An ultrasonic range sensor among walls (see the module docstring).

    Args:
        spec: Mount and beam.
        walls: The world's walls.
        rng: This sensor's own seeded random source.
    """

    def __init__(self, spec: SonarSpec, walls: tuple[Segment, ...], rng: random.Random) -> None:
        self.spec = spec
        self.rng = rng
        # Per wall: start point, direction, length and bounding box, computed once.
        self._walls = tuple(
            (
                w.x0,
                w.y0,
                w.x1 - w.x0,
                w.y1 - w.y0,
                math.hypot(w.x1 - w.x0, w.y1 - w.y0),
                min(w.x0, w.x1),
                max(w.x0, w.x1),
                min(w.y0, w.y1),
                max(w.y0, w.y1),
            )
            for w in walls
            if (w.x0, w.y0) != (w.x1, w.y1)
        )
        count = max(1, spec.rays)
        half = spec.cone_deg / 2.0
        step = spec.cone_deg / (count - 1) if count > 1 else 0.0
        self._ray_offsets_deg = tuple(-half + i * step for i in range(count)) if step else (0.0,)
        self._cos_cut = math.cos(math.radians(spec.incidence_max_deg))
        # A point of the beam's arc lies at most this far outside the box of its ends and middle.
        self._arc_margin_mm = spec.max_range_mm * (1.0 - math.cos(math.radians(half))) + 1.0
        self._last_s = -math.inf
        self._last_mm: float | None = None

    @property
    def last_mm(self) -> float | None:
        """The last measurement (``None``: no echo, or none yet), without measuring again."""
        return self._last_mm

    def read(self, x_mm: float, y_mm: float, heading_deg: float, now_s: float) -> float | None:
        """The range, millimetres from the sensor, or ``None`` for no echo.

        Args:
            x_mm: Body centre, east.
            y_mm: Body centre, north.
            heading_deg: Body heading, clockwise from north.
            now_s: Simulated time; within ``period_s`` of the last measurement the last value
                is returned unchanged.
        """
        if now_s - self._last_s < self.spec.period_s - 1e-9:
            return self._last_mm
        self._last_s = now_s
        self._last_mm = self.measure(x_mm, y_mm, heading_deg)
        return self._last_mm

    def measure(self, x_mm: float, y_mm: float, heading_deg: float) -> float | None:
        """Measure now, whatever the period (one noise draw when there is an echo)."""
        spec = self.spec
        h = math.radians(heading_deg)
        fx, fy = math.sin(h), math.cos(h)
        ox = x_mm + fx * spec.forward_mm + fy * spec.right_mm
        oy = y_mm + fy * spec.forward_mm - fx * spec.right_mm
        axis = h + math.radians(spec.bearing_deg)
        rays = [
            (math.sin(axis + math.radians(a)), math.cos(axis + math.radians(a)))
            for a in self._ray_offsets_deg
        ]
        reach = spec.max_range_mm
        # Walls whose box misses the beam's box cannot echo: most of a maze is culled here.
        first, last = rays[0], rays[-1]
        mid_x, mid_y = math.sin(axis), math.cos(axis)
        margin = self._arc_margin_mm
        xs = (ox, ox + first[0] * reach, ox + last[0] * reach, ox + mid_x * reach)
        ys = (oy, oy + first[1] * reach, oy + last[1] * reach, oy + mid_y * reach)
        bx0, bx1 = min(xs) - margin, max(xs) + margin
        by0, by1 = min(ys) - margin, max(ys) + margin
        count = len(rays)
        best = [reach] * count
        echo = [False] * count
        cos_cut = self._cos_cut
        for wx0, wy0, ex, ey, length, minx, maxx, miny, maxy in self._walls:
            if maxx < bx0 or minx > bx1 or maxy < by0 or miny > by1:
                continue
            wx = wx0 - ox
            wy = wy0 - oy
            cross = wx * ey - wy * ex
            for i in range(count):
                dx, dy = rays[i]
                denom = dx * ey - dy * ex
                if denom == 0.0:
                    continue
                t = cross / denom
                if t < 0.0 or t >= best[i]:
                    continue
                u = (wx * dy - wy * dx) / denom
                if 0.0 <= u <= 1.0:
                    best[i] = t
                    # |denom| / length is the cosine of the angle between ray and normal.
                    echo[i] = abs(denom) >= cos_cut * length
        nearest: float | None = None
        for i in range(count):
            if echo[i] and (nearest is None or best[i] < nearest):
                nearest = best[i]
        if nearest is None:
            return None
        noisy = nearest + self.rng.gauss(0.0, spec.noise_mm)
        return max(0.0, noisy) if noisy <= spec.max_range_mm else None


def spot_on_strip(offset_mm: float, half_width_mm: float, spot_radius_mm: float) -> float:
    """Fraction (0-1) of a round spot that lies on a straight strip.

    Args:
        offset_mm: Distance from the spot's centre to the strip's centre line.
        half_width_mm: Half the strip's width.
        spot_radius_mm: Radius of the spot.
    """
    if spot_radius_mm <= 0.0:
        return 1.0 if offset_mm <= half_width_mm else 0.0
    near = _disc_beyond(offset_mm - half_width_mm, spot_radius_mm)
    far = _disc_beyond(offset_mm + half_width_mm, spot_radius_mm)
    return near - far


def _disc_beyond(distance_mm: float, radius_mm: float) -> float:
    """Fraction of a disc beyond a line ``distance_mm`` from its centre (negative: past it)."""
    if distance_mm >= radius_mm:
        return 0.0
    if distance_mm <= -radius_mm:
        return 1.0
    a = distance_mm / radius_mm
    return (math.acos(a) - a * math.sqrt(1.0 - a * a)) / math.pi


class TapeReader:
    """How much of an IR sensor's spot of floor is covered by tape.

    Args:
        lines: The world's floor tape.
        spot_mm: Diameter of the patch of floor one sensor sees.
    """

    _CELL_MM = 50.0

    def __init__(self, lines: tuple[TapeLine, ...], spot_mm: float) -> None:
        self.spot_radius_mm = spot_mm / 2.0
        self._lines = tuple(
            (half, SegmentGrid(line.segments, half + self.spot_radius_mm, self._CELL_MM))
            for line in lines
            for half in (line.width_mm / 2.0,)
        )

    def coverage(self, x_mm: float, y_mm: float) -> float:
        """Fraction (0-1) of the spot centred at ``(x_mm, y_mm)`` that is on tape."""
        best = 0.0
        for half, grid in self._lines:
            nearest = math.inf
            for seg in grid.near(x_mm, y_mm):
                qx, qy = closest_point(x_mm, y_mm, seg)
                nearest = min(nearest, (qx - x_mm) ** 2 + (qy - y_mm) ** 2)
            if nearest < math.inf:
                best = max(best, spot_on_strip(math.sqrt(nearest), half, self.spot_radius_mm))
        return best
