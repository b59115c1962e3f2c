"""The lockstep wire: a robot's protocol bytes and simulated time between two processes.

When roboscript grades a mission, the simulated world (physics, sensors, the simulated device)
runs in a process the grader owns, and the student's mission runs in another, sandboxed one.
They share one socket. It carries what a serial line would carry (the host's bytes to the
device, the device's bytes to the host) plus the one thing a serial line gets for free: time.
The mission side asks the world to advance to its scheduler's time; the world steps its
physics there and answers with the bytes the device sent. The host's writes need no answer:
the world hands them to the device the moment it reads them, in order, at the current
simulated time, and what the device answers comes back with the next tick's answer. Should the
host read before that tick, it first asks for what is waiting (``Y``). So a run over this wire
is, byte for byte, the run the in-process ``sim://`` port gives, with one round trip a tick.

Frames that need no answer (``W``, ``S``, ``Q``, ``P``) leave with the next frame that does,
in one write: the world handles frames in order and only a question moves simulated time, so
it reads them at the same simulated time as if each had been sent alone, while a tick costs
one write and one wake-up of the world instead of one per frame (what a round trip costs is
mostly the wake-ups, on a busy machine a scheduler slice each).

Frames are ``kind (1 byte) | length (4 bytes, big-endian) | payload``.

Mission to world:

=====  ==========================================  ======================================
kind   payload                                     answer
=====  ==========================================  ======================================
``C``  (none): the port was opened                 ``O``: what the device said on power-up
``W``  bytes the host wrote                        none (the device reads them at once)
``Y``  (none): the host wants to read now          ``O``: what the device has sent
``T``  scheduler time, float64 seconds             ``O`` (advanced), or ``X`` (time is up)
``L``  UTF-8 JSON ``{"mission": name}``: loaded    none
``E``  UTF-8 JSON ``{"message": ...}``: load error none; the mission process ends
``S``  (none): the mission starts now              none
``Q``  UTF-8 state name: a state was entered now   none
       (then a newline and UTF-8 JSON
       ``{"action", "why"}``, its account)
``P``  UTF-8 text: a line the mission printed now  none
       (empty past the lines a record keeps)
``F``  UTF-8 JSON outcome, final state, reason     none; the mission process ends
=====  ==========================================  ======================================

World to mission: ``O`` (device output) and ``X`` (the world has stopped: the time limit was
reached or the run is over).

This module is sans-IO except :class:`WorldChannel`, the mission side's blocking socket
endpoint. Everything the mission side sends is a claim; the world validates it
(:mod:`roboscript.grading.world_host`).
"""

from __future__ import annotations

import json
import os
import socket
import struct
from collections import deque
from typing import Any, Final

from roboscript.watchdog import wire_wait

__all__ = [
    "MAX_HELD_BYTES",
    "MAX_PAYLOAD_BYTES",
    "FrameDecoder",
    "FrameError",
    "Kind",
    "WorldChannel",
    "WorldStoppedError",
    "encode_frame",
    "encode_time",
]

MAX_PAYLOAD_BYTES: Final = 256 * 1024
"""Largest payload either side accepts: a serial line's worth of bytes for many seconds."""

MAX_HELD_BYTES: Final = 64 * 1024
"""Bytes of frames that need no answer the mission side holds before it sends them anyway."""

_HEADER = struct.Struct(">cI")
_TIME = struct.Struct(">d")


class Kind:
    """Frame kinds (one ASCII byte each)."""

    OPEN: Final = b"C"
    WRITE: Final = b"W"
    SYNC: Final = b"Y"
    TICK: Final = b"T"
    LOADED: Final = b"L"
    LOAD_ERROR: Final = b"E"
    START: Final = b"S"
    STATE: Final = b"Q"
    PRINT: Final = b"P"
    FINISH: Final = b"F"
    OUTPUT: Final = b"O"
    STOPPED: Final = b"X"

    FROM_MISSION: Final = frozenset(b"CWYTLESQPF")
    FROM_WORLD: Final = frozenset(b"OX")


_HELD_KINDS: Final = frozenset((Kind.WRITE, Kind.START, Kind.STATE, Kind.PRINT))
"""Frames that need no answer and change nothing the mission can see before its next question."""


class FrameError(ValueError):
    """The peer broke the framing: an unknown kind, an oversized or malformed payload."""


class WorldStoppedError(ConnectionError):
    """The world ended the run (its time limit was reached, or it hung up)."""


def encode_frame(kind: bytes, payload: bytes = b"") -> bytes:
    """One frame.

    Raises:
        FrameError: The payload is larger than :data:`MAX_PAYLOAD_BYTES`.
    """
    if len(payload) > MAX_PAYLOAD_BYTES:
        raise FrameError(f"a {len(payload)}-byte payload is over {MAX_PAYLOAD_BYTES} bytes")
    return _HEADER.pack(kind, len(payload)) + payload


def encode_time(now_s: float) -> bytes:
    """A ``T`` payload."""
    return _TIME.pack(now_s)


def decode_time(payload: bytes) -> float:
    """The seconds in a ``T`` payload.

    Raises:
        FrameError: The payload is not 8 bytes.
    """
    if len(payload) != _TIME.size:
        raise FrameError(f"a time takes 8 bytes, not {len(payload)}")
    value: float = _TIME.unpack(payload)[0]
    return value


def decode_json(payload: bytes) -> Any:
    """A JSON payload.

    Raises:
        FrameError: It is not UTF-8 JSON.
    """
    try:
        return json.loads(payload.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise FrameError(f"not a JSON payload: {exc}") from None


class FrameDecoder:
    """Frames from a byte stream, for one role.

    Args:
        accept: The kinds this side may receive (:attr:`Kind.FROM_MISSION` or
            :attr:`Kind.FROM_WORLD`); anything else is a :class:`FrameError`.
        max_payload_bytes: Larger payloads are a :class:`FrameError`.
    """

    def __init__(self, accept: frozenset[int], max_payload_bytes: int = MAX_PAYLOAD_BYTES) -> None:
        self._accept = accept
        self._max = max_payload_bytes
        self._buffer = bytearray()

    def feed(self, data: bytes | bytearray | memoryview) -> list[tuple[bytes, bytes]]:
        """Add bytes; return each complete ``(kind, payload)``, in order.

        Raises:
            FrameError: The stream broke the framing; nothing after it can be trusted.
        """
        buffer = self._buffer
        if buffer:  # the rest of a frame that came in pieces
            buffer += data
            data = buffer
        frames: list[tuple[bytes, bytes]] = []
        accept, largest, header = self._accept, self._max, _HEADER.size
        # Read in place (bytes arrive as whole frames almost always: nothing is kept then).
        with memoryview(data) as view:
            start, length = 0, len(view)
            while length - start >= header:
                kind, size = _HEADER.unpack_from(view, start)
                if kind[0] not in accept:
                    raise FrameError(f"unknown frame kind {kind!r}")
                if size > largest:
                    raise FrameError(f"a {size}-byte frame is over the {largest}-byte limit")
                end = start + header + size
                if end > length:
                    break
                frames.append((kind, bytes(view[start + header : end])))
                start = end
            if data is not buffer and start < length:
                buffer += view[start:]
        if data is buffer:
            del buffer[:start]
        return frames

    @property
    def pending_bytes(self) -> int:
        """Bytes of an incomplete frame held."""
        return len(self._buffer)


_CHANNELS: dict[int, WorldChannel] = {}

_WIRE_WAIT = wire_wait()
"""Entered around every exchange with the world (a plain context manager: every tick)."""


class WorldChannel:
    """The mission side's end of the wire: blocking request/answer over a socket.

    Args:
        sock: A connected stream socket (the grader passes one end of a socket pair).
    """

    def __init__(self, sock: socket.socket) -> None:
        sock.setblocking(True)
        self._sock = sock
        self._decoder = FrameDecoder(Kind.FROM_WORLD)
        self._frames: deque[tuple[bytes, bytes]] = deque()
        # One buffer for every read: a fresh one this size each tick would be mapped and
        # unmapped by the allocator each time (three system calls a tick).
        self._inbox = bytearray(MAX_PAYLOAD_BYTES)
        self._held = bytearray()  # frames that need no answer, not sent yet
        self.stopped = False
        # True once the socket itself failed (closed, made non-blocking, shut down): the world
        # never closes first, so in a graded run the mission's own code broke it
        self.broken = False
        self._pid = os.getpid()  # a copy of this process (a fork) must not speak on the wire

    @classmethod
    def for_fd(cls, fd: int) -> WorldChannel:
        """The channel on an inherited socket file descriptor (one per descriptor)."""
        channel = _CHANNELS.get(fd)
        if channel is None:
            channel = _CHANNELS[fd] = cls(socket.socket(fileno=fd))
        return channel

    def send(self, kind: bytes, payload: bytes = b"") -> None:
        """Send a frame that needs no answer.

        ``W``, ``S``, ``Q`` and ``P`` frames wait (up to :data:`MAX_HELD_BYTES`) and leave
        with the next frame of another kind, in order; every other frame leaves at once.

        Raises:
            WorldStoppedError: The world has hung up.
        """
        held = self._held
        held += encode_frame(kind, payload)
        if kind not in _HELD_KINDS or len(held) > MAX_HELD_BYTES:
            self.flush()

    def flush(self) -> None:
        """Send the frames held back, if any.

        Raises:
            WorldStoppedError: The world has hung up.
        """
        if not self._held:
            return
        self._check_same_process()
        data, self._held = self._held, bytearray()
        with _WIRE_WAIT:  # a busy world's time, never the mission's own
            self._send_all(data)

    def send_json(self, kind: bytes, value: object) -> None:
        """Send a JSON frame that needs no answer."""
        self.send(kind, json.dumps(value).encode("utf-8"))

    def request(self, kind: bytes, payload: bytes = b"") -> bytes:
        """Send a frame and wait for the world's answer: the device's output.

        The frames held back leave with it, in one write.

        Raises:
            WorldStoppedError: The world has stopped the run or hung up.
        """
        if self.stopped:
            raise WorldStoppedError("the simulated world has stopped the run")
        self._check_same_process()
        frame = encode_frame(kind, payload)
        data, self._held = self._held, bytearray()
        data += frame
        with _WIRE_WAIT:  # the world reads, steps and answers: its time, never the mission's
            self._send_all(data)
            kind_back, answer = self._next_frame()
        if kind_back == Kind.STOPPED:
            self.stopped = True
            raise WorldStoppedError("the simulated world has stopped the run (time is up)")
        return answer

    def _check_same_process(self) -> None:
        """A forked copy of the process that opened the wire ends its run on it at once, before
        a byte: two processes on one wire would each take the other's answers."""
        if os.getpid() != self._pid:
            self.stopped = self.broken = True
            raise WorldStoppedError("a copy of the mission's process cannot use its wire")

    def _send_all(self, data: bytearray) -> None:
        try:
            self._sock.sendall(data)
        except OSError as exc:
            self.broken = True
            raise WorldStoppedError(f"the simulated world hung up: {exc}") from None

    def _next_frame(self) -> tuple[bytes, bytes]:
        """The world's next frame, read as it comes (inside the caller's wait on the wire)."""
        frames = self._frames
        while not frames:
            try:
                size = self._sock.recv_into(self._inbox)
            except OSError as exc:
                self.broken = True
                raise WorldStoppedError(f"the simulated world hung up: {exc}") from None
            if not size:
                self.broken = True
                raise WorldStoppedError("the simulated world hung up")
            try:  # the decoder copies what it keeps
                frames.extend(self._decoder.feed(memoryview(self._inbox)[:size]))
            except FrameError as exc:
                raise WorldStoppedError(f"the simulated world broke the wire: {exc}") from None
        return frames.popleft()

    def fileno(self) -> int:
        """The socket's file descriptor."""
        return self._sock.fileno()

    def close(self) -> None:
        """Send what is held back (if the world still listens), then close the socket."""
        try:
            self.flush()
        except WorldStoppedError:
            pass
        finally:
            self._sock.close()
