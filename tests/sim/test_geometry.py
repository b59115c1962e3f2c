"""Geometry helpers: the culled look-ups never miss a segment a brute-force search would find."""

from __future__ import annotations

import itertools
import random

from roboscript.sim.geometry import NearbySegments, Segment, SegmentGrid, segment_distance
from roboscript.sim.sensors import spot_on_strip


def random_segments(rng: random.Random, count: int) -> tuple[Segment, ...]:
    segments = []
    for _ in range(count):
        x, y = rng.uniform(-2000, 2000), rng.uniform(-2000, 2000)
        segments.append(Segment(x, y, x + rng.uniform(-600, 600), y + rng.uniform(-600, 600)))
    return tuple(segments)


def test_nearby_segments_keeps_every_segment_within_reach_of_a_moving_point() -> None:
    rng = random.Random(3)
    segments = random_segments(rng, 60)
    near = NearbySegments(segments, reach_mm=105.0, refresh_mm=100.0)
    x, y = 0.0, 0.0
    for _ in range(3000):
        x += rng.uniform(-30, 30)
        y += rng.uniform(-30, 30)
        found = set(near.around(x, y))
        within = {s for s in segments if segment_distance(x, y, s) < 105.0}
        assert within <= found


def test_segment_grid_lists_every_segment_within_reach_of_a_point() -> None:
    rng = random.Random(4)
    segments = random_segments(rng, 80)
    grid = SegmentGrid(segments, reach_mm=14.0, cell_mm=50.0)
    for _ in range(3000):
        x, y = rng.uniform(-2500, 2500), rng.uniform(-2500, 2500)
        within = {s for s in segments if segment_distance(x, y, s) <= 14.0}
        assert within <= set(grid.near(x, y))


def test_a_spot_covers_a_strip_in_proportion_across_its_edge() -> None:
    assert spot_on_strip(0.0, 10.0, 4.0) == 1.0
    assert spot_on_strip(10.0, 10.0, 4.0) == 0.5  # centred on the edge
    assert spot_on_strip(14.0, 10.0, 4.0) == 0.0
    values = [spot_on_strip(10.0 + d / 4, 10.0, 4.0) for d in range(-16, 17)]
    assert all(a > b for a, b in itertools.pairwise(values))
    # A spot wider than a thin strip sees at most the strip's share of it.
    assert spot_on_strip(0.0, 1.0, 10.0) < 0.2
