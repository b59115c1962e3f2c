"""Stand-in for the SPIKE App 3 ``runloop`` module: ``run`` keeps the coroutines for a test."""

from __future__ import annotations

from collections.abc import Coroutine, Generator
from typing import Any

STARTED: list[Coroutine[Any, Any, Any]] = []


def run(*coroutines: Coroutine[Any, Any, Any]) -> None:
    STARTED.extend(coroutines)


class _Sleep:
    def __init__(self, ms: int) -> None:
        self.ms = ms

    def __await__(self) -> Generator[None, None, None]:
        yield


def sleep_ms(ms: int) -> _Sleep:
    return _Sleep(ms)
