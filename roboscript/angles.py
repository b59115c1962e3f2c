"""Angles in degrees: the one wrap, and the one turn measured from wheel travel.

Headings are degrees clockwise (right) positive, seen from above (see
``docs/development/architecture.md``). Standard library only: every layer may use this.
"""

from __future__ import annotations

import math

__all__ = ["turned_deg", "wrap_deg"]


def wrap_deg(angle_deg: float) -> float:
    """``angle_deg`` wrapped to [-180, 180): the short way round."""
    return (angle_deg + 180.0) % 360.0 - 180.0


def turned_deg(left_mm: float, right_mm: float, track_mm: float) -> float:
    """How far a two-wheeled robot turned from its wheels' travel, degrees clockwise.

    Not wrapped: two full turns are 720. The left wheel running further than the right one
    turns the robot right (clockwise), which is positive.

    Args:
        left_mm: Left wheel travel, mm (forward positive).
        right_mm: Right wheel travel, mm.
        track_mm: Distance between the wheels, mm.
    """
    return math.degrees((left_mm - right_mm) / track_mm)
