"""Worlds: built-ins, files, and golden messages for mistakes in world files."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import WorldError
from roboscript.sim.body import BodySpec
from roboscript.sim.geometry import heading_vector, ray_cast, segment_distance
from roboscript.sim.sensors import TapeReader
from roboscript.sim.world import World, load_world


def test_square_room_has_four_walls_and_a_region() -> None:
    world = load_world("square-room")
    assert len(world.walls) == 4
    assert world.regions["centre"].contains(0.0, 100.0)
    assert not world.regions["centre"].contains(0.0, 500.0)


def test_world_file_with_units_lines_and_polygon_regions(tmp_path: Path) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(
        "start: {x: 10 cm, y: -0.5 m, heading: 90 deg}\n"
        "walls:\n  - polyline: [[0, 0], [1 m, 0], [1 m, 1 m]]\n"
        "lines:\n  - {segment: [[0, 0], [0, 500]], width: 3 cm}\n"
        "regions:\n  goal: {polygon: [[0, 0], [100, 0], [100, 100]]}\n",
        encoding="utf-8",
    )
    world = load_world(str(path))
    assert (world.start.x_mm, world.start.y_mm, world.start.heading_deg) == (100.0, -500.0, 90.0)
    assert len(world.walls) == 2
    tape = TapeReader(world.lines, spot_mm=2.0)  # a pinpoint spot: in or out of the 3 cm tape
    assert tape.coverage(10.0, 250.0) == 1.0 and tape.coverage(20.0, 250.0) == 0.0
    assert world.regions["goal"].contains(60.0, 20.0)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "walls:\n  - segmnt: [[0, 0], [1, 1]]\n",
            "W:2:5: error: unknown key 'segmnt' in a wall (did you mean 'segment'?)",
        ),
        (
            "walls:\n  - segment: [[0, 0], [1 deg, 1]]\n",
            "W:2:23: error: 'deg' is a unit of angle, but this is a distance (use mm, cm, m, in)",
        ),
        ("walls:\n  - box: {x: 0, y: 0, width: 1 m}\n", "W:2:10: error: a box needs 'height'"),
        (
            "start: {x: 0, y: 0, heading: 1 m}\n",
            (
                "W:1:30: error: 'm' is a unit of distance, but this is an angle"
                " (use deg, degrees, rad, rev)"
            ),
        ),
        ("wals: []\n", "W:1:1: error: unknown key 'wals' in world (did you mean 'walls'?)"),
        (
            "regions:\n  goal: {x: 1}\n",
            "W:2:9: error: region 'goal' needs a radius (with x, y), a box or a polygon",
        ),
        (  # so far out that a robot's millimetre steps vanish in the rounding
            "start: {x: 1e30 mm, y: 0, heading: 0 deg}\n",
            "W:1:12: error: 1e+27 m is farther than a world reaches (at most 1 km from its origin)",
        ),
        (
            "walls:\n  - segment: [[0, 0], [0, -2000 m]]\n",
            "W:2:23: error: -2000 m is farther than a world reaches (at most 1 km from its origin)",
        ),
    ],
)
def test_golden_world_errors(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(WorldError) as info:
        load_world(str(path))
    assert info.value.format().replace(str(path), "W") == expected


def test_unknown_world_name_lists_the_built_ins() -> None:
    with pytest.raises(
        WorldError, match="built-in worlds: corridor, empty, line-track, maze, square-room"
    ):
        load_world("squre-room")


# ----------------------------------------------------------------------------- built-ins

CELL_MM = 500.0
HEADINGS = ((0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0))  # N E S W: clockwise


def _open(world: World, x: float, y: float, heading: int) -> bool:
    """True if no wall lies between a cell centre and the next one in ``heading``."""
    dx, dy = HEADINGS[heading]
    return ray_cast(x, y, dx, dy, list(world.walls), CELL_MM) is None


def test_maze_is_left_by_keeping_a_hand_on_the_right_wall() -> None:
    world = load_world("maze")
    x, y, heading = world.start.x_mm, world.start.y_mm, round(world.start.heading_deg / 90) % 4
    cells = [(x, y)]
    for _ in range(100):
        if world.regions["exit"].contains(x, y):
            break
        for turn in (1, 0, -1, 2):  # right, straight, left, back
            if _open(world, x, y, (heading + turn) % 4):
                heading = (heading + turn) % 4
                x, y = x + CELL_MM * HEADINGS[heading][0], y + CELL_MM * HEADINGS[heading][1]
                cells.append((x, y))
                break
    assert world.regions["exit"].contains(x, y)
    assert world.regions["start-cell"].contains(*cells[0])
    assert 10 < len(cells) < 40  # a real maze, not a straight run


def test_maze_passages_are_wide_enough_for_the_robot() -> None:
    world = load_world("maze")
    gaps = [
        segment_distance(x, y, wall)
        for x in (250.0 + CELL_MM * i for i in range(5))
        for y in (250.0 + CELL_MM * j for j in range(4))
        for wall in world.walls
    ]
    assert min(gaps) >= 250.0 - 1e-9  # every cell centre is 25 cm from every wall


def test_line_track_starts_on_a_closed_line_facing_along_it() -> None:
    world = load_world("line-track")
    (tape,) = world.lines
    assert tape.width_mm == 20.0
    first, last = tape.segments[0], tape.segments[-1]
    assert (first.x0, first.y0) == (last.x1, last.y1)  # closed
    ahead = heading_vector(world.start.heading_deg)
    sensors = TapeReader(world.lines, BodySpec().line_spot_mm)  # what the IR sensors see
    for distance in (0.0, 80.0, 200.0):  # the IR sensors sit 80 mm ahead of the centre
        assert (
            sensors.coverage(
                world.start.x_mm + ahead[0] * distance, world.start.y_mm + ahead[1] * distance
            )
            > 0.9
        )
    assert world.regions["start-zone"].contains(world.start.x_mm, world.start.y_mm)
    assert not world.regions["lap-check"].contains(world.start.x_mm, world.start.y_mm)


def test_corridor_starts_20_cm_from_its_left_wall() -> None:
    world = load_world("corridor")
    start = world.start
    assert min(segment_distance(start.x_mm, start.y_mm, w) for w in world.walls) == 200.0
