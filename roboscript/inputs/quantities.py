"""Quantities with units, as students write them: ``50 cm``, ``15 cm/s``, ``200 ms``, ``90 deg``.

Each field of a mission, world or test spec has a *dimension*; a bare number takes that
field's documented unit, and a number with a unit is converted to the base unit of the
dimension (millimetres, seconds, degrees, hertz). A unit of the wrong dimension
(``speed: 50 deg``) is an error that says which units would fit.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["DIMENSIONS", "Dimension", "QuantityError", "parse_quantity"]


@dataclass(frozen=True)
class Dimension:
    """A kind of quantity.

    Attributes:
        name: Human name ("distance", "speed", ...).
        base_unit: The unit values are returned in.
        units: Accepted unit spellings and their factor to the base unit.
    """

    name: str
    base_unit: str
    units: dict[str, float]


_LENGTH = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}
_TIME = {"s": 1.0, "sec": 1.0, "ms": 0.001, "min": 60.0}
_ANGLE = {"deg": 1.0, "°": 1.0, "degrees": 1.0, "rad": 57.29577951308232, "rev": 360.0}

DIMENSIONS: dict[str, Dimension] = {
    "distance": Dimension("distance", "mm", _LENGTH),
    "speed": Dimension(
        "speed", "mm/s", {f"{u}/s": f for u, f in _LENGTH.items()} | {"mm/sec": 1.0}
    ),
    "time": Dimension("time", "s", _TIME),
    "angle": Dimension("angle", "deg", _ANGLE),
    "turn_rate": Dimension(
        "turn rate", "deg/s", {f"{u}/s": f for u, f in _ANGLE.items()} | {"rpm": 6.0}
    ),
    "frequency": Dimension("frequency", "Hz", {"hz": 1.0, "khz": 1000.0}),
    "percent": Dimension("percent", "%", {"%": 1.0, "pct": 1.0}),
    "count": Dimension("count", "", {}),
}

_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([^\s\d].*?)?\s*$")


class QuantityError(ValueError):
    """A value could not be read as a quantity of the wanted dimension."""


def _unit_for(dimension: Dimension, unit: str) -> float | None:
    if unit in dimension.units:
        return dimension.units[unit]
    return dimension.units.get(unit.lower())


def parse_quantity(value: object, dimension: str, default_unit: str | None = None) -> float:
    """Read ``value`` as a quantity of ``dimension`` in its base unit.

    Args:
        value: A number, or a string such as ``"50 cm"`` or ``"-90 deg"``.
        dimension: A key of :data:`DIMENSIONS`.
        default_unit: The unit a bare number is in (default: the base unit).

    Returns:
        The value in the dimension's base unit (mm, mm/s, s, deg, deg/s, Hz).

    Raises:
        QuantityError: With a sentence saying what was expected.

    Example:
        >>> parse_quantity("15 cm/s", "speed")
        150.0
        >>> parse_quantity(0.2, "time")
        0.2
    """
    dim = DIMENSIONS[dimension]
    if isinstance(value, bool):
        raise QuantityError(f"expected {_a(dim.name)}, got {value!r}")
    if isinstance(value, int | float):
        factor = 1.0 if default_unit is None else dim.units.get(default_unit, 1.0)
        return float(value) * factor
    if not isinstance(value, str):
        raise QuantityError(f"expected {_a(dim.name)} such as {_example(dim)}, got {value!r}")
    match = _QUANTITY.match(value)
    if not match:
        raise QuantityError(f"expected {_a(dim.name)} such as {_example(dim)}, got {value!r}")
    number = float(match.group(1))
    unit = (match.group(2) or "").strip()
    if not unit:
        factor = 1.0 if default_unit is None else dim.units.get(default_unit, 1.0)
        return number * factor
    unit_factor = _unit_for(dim, unit)
    if unit_factor is None:
        other = next(
            (d for d in DIMENSIONS.values() if d is not dim and _unit_for(d, unit) is not None),
            None,
        )
        fits = ", ".join([u for u in dim.units if u.isascii()][:5])
        if other is not None:
            raise QuantityError(
                f"'{unit}' is a unit of {other.name}, but this is {_a(dim.name)} (use {fits})"
            )
        raise QuantityError(f"unknown unit '{unit}' for {_a(dim.name)} (use {fits})")
    return number * unit_factor


def _a(noun: str) -> str:
    return f"an {noun}" if noun[0] in "aeiou" else f"a {noun}"


def _example(dim: Dimension) -> str:
    examples = {
        "distance": "'50 cm'",
        "speed": "'15 cm/s'",
        "time": "'200 ms'",
        "angle": "'90 deg'",
        "turn rate": "'90 deg/s'",
        "frequency": "'880 Hz'",
        "percent": "'50 %'",
        "count": "3",
    }
    return examples.get(dim.name, "a number")
