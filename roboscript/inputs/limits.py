"""The limits on what a file roboscript reads may hold, each in one place.

Student and teacher files are untrusted. Each limit below lets the input layer refuse a
hostile or broken file with one located sentence *before* any expensive work: before reading a
device or a pipe, before expanding a YAML alias bomb, before Python's recursion limit or its
integer-string limit turns into a traceback. Every limit sits far above what a real mission,
world, profile or test spec needs (the largest shipped file is a few kilobytes, a few hundred
values, nested under 15 deep).

The user documentation lists them in ``docs/reference/missions.md`` ("Limits").
"""

from __future__ import annotations

__all__ = [
    "MAX_DEPTH",
    "MAX_FILE_BYTES",
    "MAX_INTEGER_DIGITS",
    "MAX_NAME_CHARS",
    "MAX_QUANTITY_CHARS",
    "MAX_VALUES",
    "name_too_long",
]

MAX_FILE_BYTES = 1024 * 1024
"""The largest file read, in bytes (1 MiB). Checked with ``os.stat`` before the file is opened,
and again on what is read, so a file that grows meanwhile is still refused."""

MAX_DEPTH = 50
"""How deeply mappings and lists may nest. Deeper YAML is refused where the 51st level opens,
long before Python's recursion limit (about 1000 frames) is near."""

MAX_VALUES = 100_000
"""How many values (mappings, lists, scalars) a file may hold, counting each use of an alias
(``*name``) as a full copy of what it names. A "billion laughs" file of a few hundred bytes
expands to 10**9 values; it is refused at the alias that crosses this budget, without being
expanded. This also bounds the work a file of :data:`MAX_FILE_BYTES` can cause."""

MAX_NAME_CHARS = 200
"""The longest key, or name-like value (one word: letters, digits, ``_``, ``.``, ``-``), in
characters: state, action, robot and world names are read into messages and tables."""


def name_too_long(name: str, kind: str = "name") -> str | None:
    """Why ``name`` is refused as a name (one sentence calling it ``kind``, such as ``state
    name``, and quoting its start), or ``None`` when it is at most :data:`MAX_NAME_CHARS`
    characters."""
    if len(name) <= MAX_NAME_CHARS:
        return None
    return (
        f"this {kind} is {len(name)} characters long; names are at most {MAX_NAME_CHARS}"
        f" ('{name[:20]}...')"
    )


MAX_INTEGER_DIGITS = 40
"""The most digits a whole number may have. Python refuses to convert more than 4300 digits
(and takes quadratic time below that); no field needs more than a 64-bit seed's 20."""

MAX_QUANTITY_CHARS = 100
"""The longest text read as a quantity (``"50 cm"``)."""
