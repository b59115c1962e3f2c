"""Stand-in for the SPIKE App 3 ``color_sensor`` module: a test sets ``REFLECTION`` by port."""

from __future__ import annotations

from standin_log import record

REFLECTION: dict[int, int] = {}


def reflection(port: int) -> int:
    """Reflected light, 0-100 %; raises OSError for a port without a colour sensor."""
    record("color_sensor.reflection", port)
    if port not in REFLECTION:
        raise OSError(19, "ENODEV")
    return REFLECTION[port]
