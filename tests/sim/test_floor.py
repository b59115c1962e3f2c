"""The floor a colour sensor sees: white, coloured patches, and black tape on top."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import WorldError
from roboscript.sim.floor import FLOOR_COLORS, FloorReader
from roboscript.sim.geometry import Segment
from roboscript.sim.world import (
    FLOOR_COLOR_NAMES,
    FloorPatch,
    Region,
    TapeLine,
    World,
    load_world,
)

PATCH = FloorPatch(
    "red", Region("red", points=((0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)))
)
TAPE = TapeLine((Segment(-500.0, 50.0, 500.0, 50.0),), 20.0)


def test_bare_floor_is_white_and_a_patch_has_its_colour() -> None:
    floor = FloorReader(World("w", floor=(PATCH,)), spot_mm=8.0)
    white = floor.read(-200.0, -200.0)
    assert (white.color, white.reflection_percent, white.rgb) == ("white", *FLOOR_COLORS["white"])
    red = floor.read(50.0, 20.0)
    assert (red.color, red.reflection_percent, red.rgb) == ("red", *FLOOR_COLORS["red"])


def test_tape_lies_on_top_of_a_patch_and_mixes_across_its_edge() -> None:
    floor = FloorReader(World("w", lines=(TAPE,), floor=(PATCH,)), spot_mm=8.0)
    on_tape = floor.read(50.0, 50.0)
    assert (on_tape.color, on_tape.reflection_percent) == ("black", 10.0)
    edge = floor.read(50.0, 60.0)  # the spot's centre on the tape's edge: half on it
    assert edge.reflection_percent == pytest.approx((10.0 + 55.0) / 2)
    assert edge.rgb[0] == round((60 + 900) / 2)


def test_the_last_patch_listed_wins_where_patches_overlap() -> None:
    blue = FloorPatch("blue", Region("blue", points=((50.0, 0.0), (200.0, 0.0), (200.0, 100.0))))
    floor = FloorReader(World("w", floor=(PATCH, blue)), spot_mm=8.0)
    assert floor.color_at(90.0, 10.0) == "blue"
    assert floor.color_at(20.0, 10.0) == "red"


def test_a_world_file_gives_floor_patches_and_button_presses(tmp_path: Path) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(
        "world: w\n"
        "floor:\n"
        "  - {color: green, box: {x: 0, y: 0, width: 10 cm, height: 10 cm}}\n"
        "  - {color: yellow, polygon: [[0, 0], [300, 0], [0, 300]]}\n"
        "button_presses:\n"
        "  - {at: 3 s, button: right}\n"
        "  - {at: 1 s, button: left, for: 500 ms}\n",
        encoding="utf-8",
    )
    world = load_world(str(path))
    assert [patch.color for patch in world.floor] == ["green", "yellow"]
    assert world.floor[0].region.contains(99.0, 99.0)
    assert world.button_presses == ((1.0, "left", 0.5), (3.0, "right", 0.2))


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("floor:\n  - {color: pink, box: {x: 0, y: 0, width: 1, height: 1}}", "needs a color"),
        ("floor:\n  - {color: red}", "exactly one of box or polygon"),
        ("button_presses:\n  - {at: 1 s, button: center}", "'button: left' or 'button: right'"),
        ("button_presses:\n  - {button: left}", "needs 'at'"),
    ],
)
def test_bad_floor_and_button_entries_name_the_line(
    tmp_path: Path, entry: str, message: str
) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(f"world: w\n{entry}\n", encoding="utf-8")
    with pytest.raises(WorldError, match=message) as caught:
        load_world(str(path))
    assert str(caught.value).startswith(f"{path}:3:")


def test_every_colour_a_world_may_name_has_a_reflection_and_rgb() -> None:
    assert set(FLOOR_COLORS) == set(FLOOR_COLOR_NAMES)
