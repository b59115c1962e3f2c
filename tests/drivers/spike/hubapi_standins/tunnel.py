"""Stand-in for the program side of TunnelMessage that roboscript's agent assumes."""

from __future__ import annotations

from collections.abc import Callable

RECEIVER: list[Callable[[bytes], None]] = []
SENT: list[bytes] = []


def callback(function: Callable[[bytes], None]) -> None:
    RECEIVER[:] = [function]


def send(data: bytes) -> None:
    SENT.append(bytes(data))


def deliver(data: bytes) -> None:
    """What the firmware would do with a TunnelMessage from the host."""
    RECEIVER[0](data)
