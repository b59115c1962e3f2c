"""Stand-in for ``hub.light_matrix``."""

from __future__ import annotations

from standin_log import Pending, pending, record


def write(text: str, intensity: int = 100, time_per_character: int = 500) -> Pending:
    record("light_matrix.write", text)
    return pending("light_matrix.write")


def clear() -> None:
    record("light_matrix.clear")
