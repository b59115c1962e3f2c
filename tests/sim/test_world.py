"""Worlds: built-ins, files, and golden messages for mistakes in world files."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import WorldError
from roboscript.sim.world import load_world


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
    assert world.on_tape(10.0, 250.0) and not world.on_tape(20.0, 250.0)
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
    ],
)
def test_golden_world_errors(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(WorldError) as info:
        load_world(str(path))
    assert info.value.format().replace(str(path), "W") == expected


def test_unknown_world_name_lists_the_built_ins() -> None:
    with pytest.raises(WorldError, match="built-in worlds: corridor, empty, square-room"):
        load_world("squre-room")
