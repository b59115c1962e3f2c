"""``lockstep://FD``: a simulated robot in another process, reached over the lockstep wire.

The grader's mission process opens this port on the socket the grader handed it (file
descriptor ``FD``). It behaves like ``sim://``: reads never block, writes reach the device at
once, and :attr:`Serial.simulation` is a Tickable the robot adds to its scheduler, so time is
simulated and the run is deterministic. The difference is where the world lives: in the
grader's process, which the mission can reach only through these frames
(:mod:`roboscript.transport.lockstep`).
"""

from __future__ import annotations

from serial.serialutil import SerialException

from roboscript.errors import LinkClosedError
from roboscript.transport.device_port import DevicePort
from roboscript.transport.lockstep import Kind, WorldChannel, WorldStoppedError, encode_time

__all__ = ["RemoteWorld", "Serial"]


class RemoteWorld:
    """The world on the other side of the wire, as the robot's scheduler sees it.

    Args:
        channel: The mission side's end of the wire.
    """

    def __init__(self, channel: WorldChannel) -> None:
        self.channel = channel
        self._to_host = bytearray()
        self._unanswered = False  # writes whose answers have not been collected

    def connect(self) -> None:
        """Power the device on: it greets the host."""
        self._exchange(Kind.OPEN)

    def tick(self, now_s: float, dt_s: float) -> None:
        """Ask the world to advance to ``now_s`` and collect what the device said."""
        del dt_s
        self._exchange(Kind.TICK, encode_time(now_s))

    def write(self, data: bytes) -> None:
        """Bytes from the host reach the device (its answer comes with the next read or tick)."""
        self._send(Kind.WRITE, data)
        self._unanswered = True

    def read(self, size: int) -> bytes:
        """Take up to ``size`` bytes the device has sent."""
        self._collect()
        waiting = self._to_host
        if size >= len(waiting):  # all of it (the link reads everything, every tick)
            self._to_host = bytearray()
            return bytes(waiting)
        data = bytes(waiting[:size])
        del waiting[:size]
        return data

    @property
    def in_waiting(self) -> int:
        """Bytes waiting for the host."""
        self._collect()
        return len(self._to_host)

    def _collect(self) -> None:
        """Read as the in-process port would: after a write, the device has answered it."""
        if self._unanswered:
            self._exchange(Kind.SYNC)

    def start_mission(self) -> None:
        """The mission starts now (the world starts its mission clock)."""
        self._send(Kind.START)

    def state_entered(self, name: str) -> None:
        """Tell the world a state was entered now."""
        self._send(Kind.STATE, name.encode("utf-8", "replace")[:256])

    def _send(self, kind: bytes, payload: bytes = b"") -> None:
        try:
            self.channel.send(kind, payload)
        except WorldStoppedError as exc:
            raise LinkClosedError(str(exc)) from None

    def _exchange(self, kind: bytes, payload: bytes = b"") -> None:
        try:
            self._to_host += self.channel.request(kind, payload)
        except WorldStoppedError as exc:
            raise LinkClosedError(str(exc)) from None
        self._unanswered = False


class Serial(DevicePort):
    """A pyserial port whose device lives in the grader's world process."""

    simulation: RemoteWorld | None = None

    def open(self) -> None:
        """Attach to the wire on the descriptor the URL names and power the device on."""
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        text = str(self.port)
        try:
            fd = int(text.removeprefix("lockstep://").strip("/"))
        except ValueError:
            raise SerialException(f"expected lockstep://FD, got {text!r}") from None
        try:
            self.simulation = RemoteWorld(WorldChannel.for_fd(fd))
        except OSError as exc:
            raise SerialException(f"cannot use descriptor {fd}: {exc}") from None
        self.simulation.connect()
        self.is_open = True
