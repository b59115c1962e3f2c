"""The robots' pages say which firmware build each check against the firmware ran on."""

from __future__ import annotations

from pathlib import Path

import pytest
from firmware.recipes import Recipe, mirtle_328p, plen2_32u4, stackmod_328p

DOCS = Path(__file__).resolve().parents[2] / "docs" / "robots"


@pytest.mark.parametrize(
    ("page", "recipe"),
    [
        ("mirto.md", mirtle_328p()),
        ("stackmod-rover.md", stackmod_328p()),
        ("plen2.md", plen2_32u4()),
    ],
    ids=["mirto", "stackmod", "plen2"],
)
def test_each_robot_page_states_the_compiler_flags_of_the_firmware_build_it_cites(
    page: str, recipe: Recipe
) -> None:
    text = " ".join((DOCS / page).read_text(encoding="utf-8").split())
    assert f"`{' '.join(recipe.common_flags())}`" in text
    assert "avr-gcc 5.4.0" in text and "Arduino AVR core 1.8.7" in text and "simavr 1.6" in text
