"""Stand-in for ``hub.button``: a test holds buttons down in ``HELD``."""

from __future__ import annotations

LEFT = 1
RIGHT = 2

HELD: set[int] = set()


def pressed(button: int) -> int:
    """How long ``button`` has been held, ms (0: not held), as App 3's ``button.pressed``."""
    return 120 if button in HELD else 0
