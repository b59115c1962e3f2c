"""ASIP codec: sans-IO, standard library only, host and device roles.

The codec is a composition, split the way h11 splits readers and writers:

* :mod:`~roboscript.drivers.asip.framing`: the board's byte stream into text lines (CRLF
  accepted, lines over ``max_line_bytes`` and lines that are not text counted and dropped);
* :mod:`~roboscript.drivers.asip.host_side`: requests written, the board's lines read (events,
  replies, errors, info and debug lines);
* :mod:`~roboscript.drivers.asip.device_side`: requests read with the firmware's ``Stream``
  semantics (no newline needed; :attr:`AsipCodec.waiting` while a timed read waits, and
  :meth:`AsipCodec.parse_timeout` ends that wait as its 1 s timeout does), replies written in
  the firmware's exact forms;
* :mod:`~roboscript.drivers.asip.value_ranges`: what every number the board prints can be.

Faults are counted in :attr:`AsipCodec.stats` by kind and raised as
:class:`~roboscript.errors.RemoteProtocolError` once consumed: ``"overlong"``, ``"garbage"``
(not text), ``"malformed"`` (does not parse) and ``"out_of_range"`` (a number beyond what the
firmware's types hold, such as a 400-digit encoder count). Nothing else escapes
:meth:`AsipCodec.next_message`.
"""

from __future__ import annotations

from collections.abc import Callable

from roboscript.codec import CodecStats, ProfileLike, Role
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.device_side import DEFAULT_SERVICES, DEVICE_ENCODERS, RequestReader
from roboscript.drivers.asip.framing import LineFramer
from roboscript.drivers.asip.host_side import HOST_ENCODERS, decode_line
from roboscript.errors import LocalProtocolError

__all__ = ["DEFAULT_SERVICES", "AsipCodec", "DeviceAsipCodec", "codec_for"]

_ENCODERS: dict[Role, dict[type, Callable[..., str]]] = {
    Role.HOST: HOST_ENCODERS,
    Role.DEVICE: DEVICE_ENCODERS,
}


class AsipCodec:
    """ASIP 1.1 codec for one end of a link.

    ``AsipCodec(role)`` builds the role's codec: the encoders of that role's side, and its
    reader, :class:`~roboscript.drivers.asip.framing.LineFramer` (host) or
    :class:`~roboscript.drivers.asip.device_side.RequestReader` (device), whose
    ``receive_data``, ``next_message`` and ``pending_bytes`` are the codec's own methods, so the
    ingest path takes no extra call.

    Args:
        role: ``Role.HOST`` for roboscript's driver, ``Role.DEVICE`` for a simulated board.
        services: Device role only: the service ids the board runs; a request for any other
            service decodes as :class:`~roboscript.drivers.asip.messages.InvalidServiceRequest`.
        max_line_bytes: Host role: longer lines are dropped as ``"overlong"``.
        max_buffer_bytes: Device role: bound on buffered request bytes.
        servo_count: Device role: the servos the sketch declares, so ``S,W`` is refused
            while it is read, as the firmware does; None reads every ``S,W`` in full.
        int_bits: Device role: the width of the board's ``int`` (16 on an ATmega328P, 32 on
            a Teensy 3.1), which each request number is cut to as the firmware keeps it.

    Example:
        >>> host = AsipCodec(Role.HOST)
        >>> host.send(m.SetMotorsPower(30, -30))
        b'M,M,30,-30\\n'
        >>> host.receive_data(b"@M,e,2,{10:100,12:120}\\n")
        >>> host.next_message()
        EncoderEvent(counts=((10, 100), (12, 120)))
    """

    role: Role
    stats: CodecStats
    services: str
    """The service ids the board runs (device role)."""

    receive_data: Callable[[bytes], None]
    """Buffer bytes read from the wire."""
    next_message: Callable[[], m.AsipMessage | None]
    """Return the next complete message, or ``None`` when more bytes are needed; raise
    :class:`~roboscript.errors.RemoteProtocolError` for a bad line or request, already consumed
    and counted in :attr:`stats`."""
    pending_bytes: Callable[[], int]
    """Number of buffered bytes not yet decoded or dropped."""
    parse_timeout: Callable[[], None]
    """Tell a device-role codec that the timed read its board waits in ran out (1 s with no
    byte): the next :meth:`next_message` goes on as ``parseInt`` does after its timeout. A
    host-role codec has nothing to complete."""

    # Not Self: AsipCodec(role) is an instance of the role's subclass.
    def __new__(cls, role: Role, **options: object) -> AsipCodec:  # noqa: PYI034
        chosen = cls
        if cls is AsipCodec:
            chosen = _HostAsipCodec if role is Role.HOST else DeviceAsipCodec
        return super().__new__(chosen)

    def __init__(
        self,
        role: Role,
        *,
        services: str = DEFAULT_SERVICES,
        max_line_bytes: int = 512,
        max_buffer_bytes: int = 4096,
        servo_count: int | None = None,
        int_bits: int = 16,
    ) -> None:
        self.role = role
        self.stats = CodecStats()
        self.services = services
        self.servo_count = servo_count
        self.int_bits = int_bits
        self._encoders = _ENCODERS[role]
        self._start_reader(max_line_bytes, max_buffer_bytes)

    @property
    def waiting(self) -> bool:
        """Device role: True while the board waits inside a request for a byte (it runs
        nothing else meanwhile). Always False for a host-role codec."""
        return False

    def _start_reader(self, max_line_bytes: int, max_buffer_bytes: int) -> None:
        raise NotImplementedError  # each role's class starts its own reader

    def send(self, message: object) -> bytes:
        """Encode one message for the wire.

        Raises:
            LocalProtocolError: The message is not one this role sends, or holds a value the
                firmware's types cannot (device role).
        """
        encode = self._encoders.get(type(message))
        if encode is None:
            for role, encoders in _ENCODERS.items():
                if type(message) in encoders:
                    raise LocalProtocolError(
                        f"{type(message).__name__} is sent by the {role.value}, "
                        f"not the {self.role.value}"
                    )
            raise LocalProtocolError(f"{type(message).__name__} is not an ASIP message")
        try:  # latin-1: a service or tag byte read from the wire goes back out unchanged
            return (encode(message) + "\n").encode("latin-1")
        except UnicodeEncodeError as exc:
            raise LocalProtocolError(f"{type(message).__name__} has a non-byte character") from exc


class _HostAsipCodec(AsipCodec, LineFramer):
    """The host role: request encoders, the board's lines framed and decoded."""

    def _start_reader(self, max_line_bytes: int, max_buffer_bytes: int) -> None:
        LineFramer.__init__(self, self.stats, max_line_bytes, decode_line)

    def parse_timeout(self) -> None:
        """Nothing to do: only the board's parser waits for digits."""


class DeviceAsipCodec(AsipCodec, RequestReader):
    """The device role: reply encoders, requests read with the firmware's semantics."""

    waiting = RequestReader.waiting  # AsipCodec's comes first in the lookup order
    # skipping the rest of a request's line is the device's alone (RequestReader's), never a
    # host's: the simulated board makes this class by name, so no host stub stands for it

    def _start_reader(self, max_line_bytes: int, max_buffer_bytes: int) -> None:
        RequestReader.__init__(
            self,
            self.stats,
            self.services,
            max_buffer_bytes,
            servo_count=self.servo_count,
            int_bits=self.int_bits,
        )


def codec_for(role: Role, profile: ProfileLike) -> AsipCodec:
    """The ASIP codec in ``role`` (the protocol unit's codec factory; no profile options)."""
    del profile
    return AsipCodec(role)
