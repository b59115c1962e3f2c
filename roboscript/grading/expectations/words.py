"""How verdicts word their measures: centimetres, seconds, degrees, counts and margins."""

from __future__ import annotations

__all__ = ["at", "by", "cm", "deg", "plural", "seconds"]


def cm(value_mm: float) -> str:
    """``12.3 cm`` for a size in millimetres (its sign is left to the words around it)."""
    return f"{abs(value_mm) / 10.0:.1f} cm"


def seconds(value_s: float) -> str:
    """``0.25 s`` under a second, ``1.5 s`` above (unsigned)."""
    return f"{abs(value_s):.2f} s" if abs(value_s) < 1.0 else f"{abs(value_s):.1f} s"


def deg(value: float) -> str:
    """``4.5°`` (unsigned)."""
    return f"{abs(value):.1f}°"


def by(margin: float, words: str) -> str:
    """``passed by WORDS`` for a margin of at least 0, else ``failed by WORDS``."""
    return f"{'passed' if margin >= 0 else 'failed'} by {words}"


def plural(n: int, word: str) -> str:
    """``1 tone``, ``2 tones``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def at(t_s: float) -> str:
    """A moment of the mission clock: ``3.4 s``."""
    return f"{t_s:.1f} s"
