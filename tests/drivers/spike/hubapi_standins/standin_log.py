"""What the agent asked of the stand-in hub API, in order: (name, args, kwargs)."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

CALLS: list[tuple[str, tuple[Any, ...], dict[str, Any]]] = []


def record(name: str, *args: Any, **kwargs: Any) -> None:
    CALLS.append((name, args, kwargs))


def names() -> list[str]:
    return [name for name, _, _ in CALLS]


class Pending:
    """An awaitable action that finishes when a test says so, with ``result``."""

    def __init__(self, name: str, result: Any = None) -> None:
        self.name = name
        self.result = result
        self.done = False

    def finish(self, result: Any = None) -> None:
        if result is not None:
            self.result = result
        self.done = True

    def __await__(self) -> Generator[None, None, Any]:
        while not self.done:
            yield
        return self.result


PENDING: list[Pending] = []


def pending(name: str, result: Any = None) -> Pending:
    action = Pending(name, result)
    PENDING.append(action)
    return action
