"""Small unit helpers: clamping and angle wrapping. Units live in names, not in types."""

from __future__ import annotations

import math

__all__ = ["clamp", "hypot_mm", "wrap_angle_deg"]


def clamp(value: float, low: float, high: float) -> float:
    """Return ``value`` limited to ``[low, high]``."""
    return low if value < low else min(value, high)


def wrap_angle_deg(angle_deg: float) -> float:
    """Return the same direction as ``angle_deg`` in ``[-180, 180)`` degrees."""
    return (angle_deg + 180.0) % 360.0 - 180.0


def hypot_mm(dx_mm: float, dy_mm: float) -> float:
    """Distance in millimetres of a displacement."""
    return math.hypot(dx_mm, dy_mm)
