"""Stand-in for ``hub.sound``."""

from __future__ import annotations

from standin_log import Pending, pending, record


def beep(freq: int = 440, duration: int = 500, volume: int = 100) -> Pending:
    record("sound.beep", freq, duration, volume)
    return pending("sound.beep")
