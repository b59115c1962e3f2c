"""Quantities with units, as students write them: ``50 cm``, ``15 cm/s``, ``200 ms``, ``90 deg``.

Each field of a mission, world or test spec has a *dimension*; a bare number takes that
field's documented unit, and a number with a unit is converted to the base unit of the
dimension (millimetres, seconds, degrees, hertz). A unit of the wrong dimension
(``speed: 50 deg``) is an error that says which units would fit, and a decimal comma
(``0,2 m/s``) an error that shows the decimal point.

Where the unit matters (a distance, a speed, a time, an angle, a turn rate, a frequency), a
bare number is a likely mistake (``distance: 50`` is 50 mm, not 50 cm):
:func:`bare_number_warning` says how it was taken and how to write it, for the mission
checks to report as a warning.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from roboscript.inputs.limits import MAX_QUANTITY_CHARS

__all__ = [
    "CLOCK",
    "CURLY_QUOTES",
    "DASHES",
    "DIMENSIONS",
    "UNIT_MATTERS",
    "Dimension",
    "QuantityError",
    "bare_number_warning",
    "clock_reading",
    "clock_time",
    "parse_quantity",
    "radians_warning",
    "without_leading_zeros",
]


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

UNIT_MATTERS = frozenset({"distance", "speed", "time", "angle", "turn_rate", "frequency"})
"""Dimensions whose bare numbers draw a :func:`bare_number_warning` (not percent or count)."""

# The number at the start of a quantity. One run of digits on each side of the point, so
# matching is linear in the text's length (``\d+\.?\d*`` backtracks quadratically).
_NUMBER = re.compile(r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")
_DECIMAL_COMMA = re.compile(r"[-+]?\d+,\d+")


class QuantityError(ValueError):
    """A value could not be read as a quantity of the wanted dimension.

    Attributes:
        message: What is wrong.
        hint: How to write it instead, or ``None``; ``str()`` of the error shows both.
    """

    def __init__(self, message: str, hint: str | None = None) -> None:
        self.message = message
        self.hint = hint
        super().__init__(f"{message} ({hint})" if hint else message)


CURLY_QUOTES = "\u2018\u2019\u201c\u201d\u201e\u201a\u00ab\u00bb"
"""‘ ’ “ ” „ ‚ « »: the quotes a word processor or a web page puts in place of typed ones,
told as such in a YAML value, a condition and Python code alike."""
DASHES = "\u2013\u2014\u2212"
"""– — −: an en dash, an em dash and the minus sign, which a word processor or a web page
writes for a typed minus, told as such in a YAML value, a condition and Python code alike."""

CLOCK = re.compile(r"([-+]?)(\d[\d_]*(?::\d[\d_]*)+(?:\.[\d_]*)?)")
"""A time written as a clock writes it, ``1:30`` or ``-1:00:00`` (its sign, its digits)."""


def clock_reading(text: str) -> tuple[float, str | None] | None:
    """The seconds a time written as a clock writes it reads (``1:30``: 90, counted in
    sixties) and how it reads in units (``1 min 30 s``; ``None`` for no time or more parts
    than hours, minutes and seconds); ``None`` for any other text.

    Example:
        >>> clock_reading("1:00:30")
        (3630.0, '1 h 30 s')
    """
    found = CLOCK.fullmatch(text.strip())
    if found is None:
        return None
    parts = found.group(2).replace("_", "").split(":")
    seconds = 0.0
    for part in parts:
        seconds = seconds * 60 + float(part)
    sign = found.group(1).replace("+", "")
    if seconds == 0 or len(parts) > 3:
        return (float(f"{sign}{seconds}") if seconds else 0.0), None
    read = " ".join(
        f"{float(part):g} {unit}"
        for part, unit in zip(parts, ("h", "min", "s")[-len(parts) :], strict=True)
        if float(part)
    )
    return float(f"{sign}{seconds}"), f"{sign}{read}"


def clock_time(text: str) -> tuple[float, str] | None:
    """A time written as a clock writes it (``1:30``, ``1:00:00``): the seconds it reads as
    counted in sixties, and how to write it with a unit; ``None`` for any other text.

    Example:
        >>> clock_time("1:30")
        (90.0, 'for 1 min 30 s, write `90 s` or `1.5 min`')
    """
    found = clock_reading(text)
    if found is None:
        return None
    seconds, read = found
    if seconds == 0:
        return 0.0, "write `0 s`"
    minutes = seconds / 60
    in_minutes = f" or `{minutes:g} min`" if (minutes * 10).is_integer() else ""
    written = f"write `{seconds:g} s`{in_minutes}"
    return seconds, f"for {read}, {written}" if read else written


def without_leading_zeros(written: str) -> str:
    """A whole number written with leading zeros (``010``, ``-007``, ``0_10``), as written
    without them (``10``, ``-7``): YAML 1.1 reads ``010`` as an octal number, 8, and Python
    refuses it.

    Example:
        >>> without_leading_zeros("-0_10")
        '-10'
    """
    sign = "-" if written.startswith("-") else ""
    return sign + (written.lstrip("+-").replace("_", "").lstrip("0") or "0")


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
        The value in the dimension's base unit (mm, mm/s, s, deg, deg/s, Hz). A number too
        large for a float (``1e400 mm``) comes back infinite: callers that need a finite value
        check for it where they can say where it was written.

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
    if len(value) > MAX_QUANTITY_CHARS:
        raise QuantityError(
            f"expected {_a(dim.name)} such as {_example(dim)}, got {len(value)} characters"
            f" (a quantity is at most {MAX_QUANTITY_CHARS})"
        )
    text = value.strip()
    comma = _DECIMAL_COMMA.match(text)
    if comma:
        raise QuantityError(
            f"'{text}' has a decimal comma",
            f"use a decimal point: {comma.group().replace(',', '.')}{text[comma.end() :]}",
        )
    if text[:1] in CURLY_QUOTES or text[-1:] in CURLY_QUOTES:  # ‘50 cm’, from a word processor
        bare = text.strip(CURLY_QUOTES)
        raise QuantityError(
            f"'{text}' is in curly quotes, as a word processor writes them",
            f"type straight quotes, or none: {bare}",
        )
    if text[:1] in DASHES:  # –90 deg, from a word processor
        raise QuantityError(
            f"'{text}' starts with a dash, as a word processor writes a minus",
            f"type the minus key: -{text[1:].strip()}",
        )
    clock = clock_time(text)
    if clock is not None:  # "1:30", quoted (unquoted, YAML refuses it as a number)
        raise QuantityError(
            f"'{text}' is written as a clock writes a time, and {_a(dim.name)} is one number"
            " with its unit",
            clock[1] if dimension == "time" else None,
        )
    number_match = _NUMBER.match(text)
    unit = text[number_match.end() :].strip() if number_match else ""
    fraction = _FRACTION.match(text) if unit.startswith("/") else None
    if fraction is not None:  # "1/2 m"
        raise QuantityError(f"'{text}' is a fraction", _fraction_written(fraction, dim))
    if not number_match or unit[:1].isdigit():
        raise QuantityError(f"expected {_a(dim.name)} such as {_example(dim)}, got {value!r}")
    number = float(number_match.group())
    if not unit:
        factor = 1.0 if default_unit is None else dim.units.get(default_unit, 1.0)
        return number * factor
    unit_factor = _unit_for(dim, unit)
    zeros = re.match(r"[Oo]+(?=\s|$|[A-Za-z])", text[number_match.end() :])
    if unit_factor is None and zeros is not None:  # "5O cm": a letter O typed for a zero
        meant = (
            number_match.group()
            + "0" * len(zeros.group())
            + text[number_match.end() + zeros.end() :]
        )
        try:
            parse_quantity(meant, dimension, default_unit)
        except QuantityError:
            pass
        else:
            raise QuantityError(
                f"'{text}' has the letter {zeros.group()[0]} where a zero was meant",
                f"write {meant}",
            )
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
        written = _written_otherwise(number, unit, dim)
        raise QuantityError(
            f"unknown unit '{unit}' for {_a(dim.name)}" + ("" if written else f" (use {fits})"),
            written,
        )
    return number * unit_factor


_WORDS = {
    "millimeter": "mm",
    "millimetre": "mm",
    "centimeter": "cm",
    "centimetre": "cm",
    "centímetro": "cm",
    "centimetro": "cm",
    "meter": "m",
    "metre": "m",
    "metro": "m",
    "mtr": "m",
    "inch": "in",
    "second": "s",
    "secs": "s",
    "segundo": "s",
    "millisecond": "ms",
    "msec": "ms",
    "minute": "min",
    "mins": "min",
    "degree": "deg",
    "degre": "deg",
    "degs": "deg",
    "grad": "deg",
    "grados": "deg",
    "º": "deg",
    "˚": "deg",
    "radian": "rad",
    "rads": "rad",
    "revolution": "rev",
    "revs": "rev",
    "hertz": "Hz",
    "kilohertz": "kHz",
}
"""Units written out, in the plural, in another language or with a look-alike sign, and the
unit roboscript spells them with."""
_CONVERTED = {
    "foot": ("in", 12.0),
    "feet": ("in", 12.0),
    "ft": ("in", 12.0),
    "dm": ("cm", 10.0),
    "turn": ("deg", 360.0),
    "rotation": ("deg", 360.0),
    "km/h": ("cm/s", 100_000 / 3600),
    "kph": ("cm/s", 100_000 / 3600),
    "mph": ("cm/s", 160_934.4 / 3600),
}
"""Units roboscript has no name for, as a number of a unit it has."""
_PER_SECOND = re.compile(r"\s*(?:/|per|a|an)\s*(?:s|sec|secs|second|seconds)$", re.IGNORECASE)
_FRACTION = re.compile(r"^([-+]?\d+)\s*/\s*(\d+)\s*(.*)$")


def _fraction_written(fraction: re.Match[str], dim: Dimension) -> str | None:
    """How to write a quantity written as a fraction (``1/2 m``: ``0.5 m``), or ``None``."""
    if int(fraction.group(2)) == 0:
        return None
    value = int(fraction.group(1)) / int(fraction.group(2))
    unit = fraction.group(3).strip()
    written = f"{value:g} {unit}".strip()
    if unit and _unit_for(dim, unit) is None:
        otherwise = _written_otherwise(value, unit, dim)
        return None if otherwise is None else f"a quantity is one number: {otherwise}"
    return f"a quantity is one number and its unit: write {written}"


def _written_otherwise(number: float, unit: str, dim: Dimension) -> str | None:
    """How to write a quantity whose unit roboscript does not know with one it does
    (``10 centimeters``: ``write 10 cm``), or ``None``."""
    per_second = _PER_SECOND.search(unit)
    base = unit[: per_second.start()] if per_second else unit
    known = _known_unit(base.strip().rstrip(".").removesuffix("'s").lower())
    if known is None:
        return None
    name, factor = known
    written_unit = f"{name}/s" if per_second and "/" not in name else name
    if _unit_for(dim, written_unit) is None:
        return None
    return f"write {number * factor:.4g} {written_unit}"


def _known_unit(word: str) -> tuple[str, float] | None:
    """The unit roboscript names ``word`` by, and how many of it one ``word`` is."""
    for spelled in (word, word.removesuffix("s"), word.removesuffix("es")):
        if spelled in _WORDS:
            return _WORDS[spelled], 1.0
        if spelled in _CONVERTED:
            return _CONVERTED[spelled]
        if any(spelled == unit.lower() for d in DIMENSIONS.values() for unit in d.units):
            return spelled, 1.0
    return None


def bare_number_warning(
    value: object, dimension: str, default_unit: str | None = None
) -> tuple[str, str | None] | None:
    """The warning for a number written without a unit where the unit matters.

    Args:
        value: The value as written (a number, or text such as ``"50"``).
        dimension: A key of :data:`DIMENSIONS`.
        default_unit: The unit a bare number is in (default: the base unit).

    Returns:
        ``(message, hint)``, such as ``("50 taken as 50 mm; write `50 mm`", "or did you mean
        50 cm?")``, the hint ``None`` when no other unit is likely; ``None`` when ``value``
        has a unit, is zero (the same in every unit), is not a finite number, or its
        dimension has no unit that matters (:data:`UNIT_MATTERS`).

    Example:
        >>> bare_number_warning(90, "angle")
        ('90 taken as 90 deg; write `90 deg`', None)
    """
    if dimension not in UNIT_MATTERS or isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        written = str(value)
    elif isinstance(value, str) and len(value) <= MAX_QUANTITY_CHARS:
        written = value.strip()
        if not _NUMBER.fullmatch(written):
            return None
    else:
        return None
    try:
        number = float(written)
    except (ValueError, OverflowError):
        return None
    if number == 0 or not math.isfinite(number):
        return None
    unit = default_unit or DIMENSIONS[dimension].base_unit
    likely = _likely_unit(dimension, number)
    hint = f"or did you mean {written} {likely}?" if likely and likely != unit else None
    return f"{written} taken as {written} {unit}; write `{written} {unit}`", hint


def radians_warning(angle_deg: object, keyword: str | None = None) -> tuple[str, str] | None:
    """The warning for an angle in degrees that looks like radians (1.57 deg, ``math.pi``).

    Args:
        angle_deg: The angle, degrees.
        keyword: The Python keyword it was given as (``angle_deg``), to write the fix that
            way; ``None`` for a mission file.

    Returns:
        ``(message, hint)`` for a fraction of a degree, up to 2π degrees, that is not a
        whole number; else ``None`` (a whole number of degrees is meant as written).

    Example:
        >>> radians_warning(1.5708)
        ('1.5708 deg is a very small angle', 'if you meant radians, that is 90 deg: write 90 deg')
    """
    if isinstance(angle_deg, bool) or not isinstance(angle_deg, int | float):
        return None
    if not math.isfinite(angle_deg) or angle_deg == 0 or float(angle_deg).is_integer():
        return None
    if abs(angle_deg) > 2 * math.pi + 0.01:
        return None
    degrees = f"{math.degrees(angle_deg):.0f}"
    fix = f"{keyword}={degrees}" if keyword else f"{degrees} deg"
    return (
        f"{angle_deg:g} deg is a very small angle",
        f"if you meant radians, that is {degrees} deg: write {fix}",
    )


def _likely_unit(dimension: str, number: float) -> str | None:
    """The unit a beginner more likely meant: centimetres for a length or a speed (the unit
    the examples and most rulers use), milliseconds for a time of 50 or more (a beep of
    200, not a wait of over three minutes), radians for a fraction of a degree up to 2π."""
    if dimension == "distance":
        return "cm"
    if dimension == "speed":
        return "cm/s"
    if dimension == "time" and abs(number) >= 50:
        return "ms"
    if dimension == "angle" and not number.is_integer() and abs(number) <= 2 * math.pi + 0.01:
        return "rad"  # 1.57, 3.14: a quarter, a half turn in radians (maths lessons use them)
    return None


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
