"""The contract every protocol codec follows (sans-IO, standard library only).

It sits below both :mod:`roboscript.transport` (a :class:`~roboscript.transport.link.Link`
joins a port and a codec) and :mod:`roboscript.drivers` (each protocol's ``codec.py``
implements it), so neither of them imports the other for it.

A codec turns bytes into messages and messages into bytes, and knows nothing of ports, threads
or time. Each protocol has one codec class used in both roles: the host driver builds it with
``Role.HOST`` (it encodes requests and decodes replies), the simulated device with
``Role.DEVICE`` (it decodes requests and encodes replies).

The verbs, after h11:

* :meth:`Codec.send` encodes one message to bytes, raising
  :class:`~roboscript.errors.LocalProtocolError` if the message is illegal for the role or out
  of range.
* :meth:`Codec.receive_data` buffers received bytes (bounded).
* :meth:`Codec.next_message` returns the next complete message, ``None`` when more bytes are
  needed, or raises :class:`~roboscript.errors.RemoteProtocolError` for a bad frame that it has
  already consumed, so calling it again continues with the bytes after the bad frame.
"""

from __future__ import annotations

import enum
from collections import Counter
from collections.abc import Iterator, Mapping
from typing import Any, Protocol, TypeVar

from roboscript.errors import RemoteProtocolError

__all__ = ["Codec", "CodecStats", "ProfileLike", "Role", "drain", "readable"]

M_co = TypeVar("M_co", covariant=True)


class Role(enum.Enum):
    """Which side of the link a codec speaks for."""

    HOST = "host"
    """roboscript's side: sends requests, receives events and replies."""
    DEVICE = "device"
    """The robot's side: receives requests, sends events and replies."""


class CodecStats:
    """Counts of what a codec received, for the garbage report and benchmarks.

    Attributes:
        messages: Complete messages decoded.
        faults: Bad frames or stray bytes, by fault kind.
        dropped_bytes: Bytes discarded as garbage.
    """

    def __init__(self) -> None:
        self.messages = 0
        self.faults: Counter[str] = Counter()
        self.dropped_bytes = 0

    def fault(self, kind: str, dropped: int) -> None:
        """Record one fault of ``kind`` that discarded ``dropped`` bytes."""
        self.faults[kind] += 1
        self.dropped_bytes += dropped


class Codec(Protocol[M_co]):
    """What :class:`~roboscript.transport.link.Link` needs of a protocol codec."""

    role: Role
    stats: CodecStats

    def send(self, message: object) -> bytes:
        """Encode ``message`` for the wire."""
        ...

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire."""
        ...

    def next_message(self) -> M_co | None:
        """Return the next decoded message, or ``None`` if more bytes are needed."""
        ...


class ProfileLike(Protocol):
    """What a codec factory reads of a robot profile (a :class:`~roboscript.profiles.RobotProfile`).

    Each protocol's codec factory, ``(role, profile) -> codec``, named by its
    :class:`~roboscript.drivers.unit.ProtocolUnit`, sets its codec up from the profile's
    protocol options.
    """

    @property
    def name(self) -> str:
        """The profile's name, for messages."""
        ...

    @property
    def options(self) -> Mapping[str, Any]:
        """The profile's protocol options."""
        ...


def drain(codec: Codec[M_co]) -> Iterator[M_co | RemoteProtocolError]:
    """Yield every complete message in ``codec``, and each fault as its exception object.

    Faults are yielded rather than raised so that one bad frame never hides the good ones
    after it.
    """
    while True:
        try:
            message = codec.next_message()
        except RemoteProtocolError as fault:
            yield fault
            continue
        if message is None:
            return
        yield message


def readable(codec: Codec[M_co]) -> Iterator[M_co]:
    """Yield every complete message in ``codec``, skipping bad frames.

    For simulated devices: firmware drops what it cannot read without a word, and the codec
    has already counted it in :attr:`Codec.stats`.
    """
    for message in drain(codec):
        if not isinstance(message, RemoteProtocolError):
            yield message
