"""Which protocol a port speaks, from the bytes it sent: for a handshake that failed.

A student who forgets ``--robot spike-prime`` should hear "this port speaks the SPIKE hub
protocol", not "is it switched on". Each protocol's own host codec reads the bytes the port
sent before the handshake gave up (kept by the link, :attr:`Link.heard
<roboscript.transport.link.Link.heard>`); the protocol whose codec reads the most whole
messages from them, more than it refuses, is the one the port speaks. The signatures are the
codecs' own framing: ASIP's ``@``/``~``/``!`` lines, SPIKE's COBS frames ending ``0x02``,
StackMod's ``{…}`` frames with their checksum, PLEN2's replies. Sans-IO, standard library
only.
"""

from __future__ import annotations

import contextlib

from roboscript.codec import Role
from roboscript.drivers.unit import ProtocolUnit
from roboscript.errors import RemoteProtocolError

__all__ = ["PROTOCOL_TITLES", "handshake_failure", "recognise_protocol", "wrong_robot_hint"]

PROTOCOL_TITLES = {"asip": "ASIP", "spike": "SPIKE hub", "stackmod": "StackMod", "plen": "PLEN2"}
"""How a protocol is named to a user."""

_SPOKEN_BY = {
    "asip": "a MIRTO or another ASIP board",
    "spike": "a LEGO SPIKE Prime hub",
    "stackmod": "a StackMod bridge",
    "plen": "a PLEN2",
}

_NOT_PROOF = frozenset({"DebugLine"})
"""Message types any text reads as (an ASIP board's free-text line): they prove nothing."""

_MOST_MESSAGES = 64  # a handful is proof enough; the bytes kept are bounded anyway


def _messages_read(unit: ProtocolUnit, data: bytes) -> tuple[int, int]:
    """(messages read, frames refused) when ``unit``'s host codec reads ``data``."""
    from roboscript.profiles import get_profile

    try:
        codec = unit.make_codec(Role.HOST, get_profile(unit.profiles[0]))
    except Exception:  # noqa: BLE001 - a unit that cannot even build its codec proves nothing
        return 0, 0
    read = refused = 0
    try:
        codec.receive_data(data)
        while read < _MOST_MESSAGES:
            try:
                message = codec.next_message()
            except RemoteProtocolError:
                refused += 1
                continue
            if message is None:
                break
            if type(message).__name__ not in _NOT_PROOF:
                read += 1
    except Exception:  # noqa: BLE001 - bytes of another protocol may upset a codec anyhow
        return 0, refused + 1
    return read, refused


def recognise_protocol(data: bytes, units: tuple[ProtocolUnit, ...] | None = None) -> str | None:
    """The protocol ``data`` is written in, or ``None`` if none reads it clearly.

    Args:
        data: Bytes a port sent.
        units: The protocols to try (default: every protocol roboscript has).

    Returns:
        The protocol's name (``"spike"``), as in a profile's ``protocol``.
    """
    if not data:
        return None
    if units is None:
        from roboscript.drivers import UNITS

        units = UNITS
    scores = []
    for unit in units:
        read, refused = _messages_read(unit, data)
        if read > 0 and read > refused:
            scores.append((read - refused, unit.name))
    if not scores:
        return None
    scores.sort(reverse=True)
    if len(scores) > 1 and scores[0][0] == scores[1][0]:
        return None  # two protocols read it equally well: say nothing rather than guess
    return scores[0][1]


def wrong_robot_hint(heard: bytes, expected_protocol: str) -> str | None:
    """``this port speaks the SPIKE hub protocol: use --robot spike-prime``, or ``None``.

    Args:
        heard: The bytes the port sent.
        expected_protocol: The protocol of the robot that was asked for.
    """
    from roboscript.drivers import UNITS, protocol_unit

    # The robot asked for is the usual speaker: when its own codec reads the bytes cleanly,
    # no other codec is imported (a graded run's handshake then loads one protocol, not all).
    with contextlib.suppress(NotImplementedError):
        read, refused = _messages_read(protocol_unit(expected_protocol), heard)
        if read > 0 and refused == 0:
            return None
    found = recognise_protocol(heard)
    if found is None or found == expected_protocol:
        return None
    unit = next(u for u in UNITS if u.name == found)
    title = PROTOCOL_TITLES.get(found, found)
    robot = _SPOKEN_BY.get(found, "another robot")
    return f"this port speaks the {title} protocol ({robot}): use --robot {unit.profiles[0]}"


def handshake_failure(
    robot: str, protocol: str, url: str, heard: bytes, bytes_sent: int, waited: str
) -> str:
    """One sentence for a robot that did not finish its handshake, naming what was heard.

    Args:
        robot: The robot asked for (``mirto``).
        protocol: Its protocol (``asip``).
        url: The port.
        heard: The bytes the port sent.
        bytes_sent: How many bytes of the handshake were sent.
        waited: How long it was waited for, as text (``within 3 s``).
    """
    title = PROTOCOL_TITLES.get(protocol, protocol)
    hint = wrong_robot_hint(heard, protocol)
    if hint is not None:
        return f"{robot} did not answer on {url}: {hint}"
    if heard:
        return (
            f"{robot} did not answer on {url} {waited}: the port sent {len(heard)} bytes "
            f"that are not the {title} protocol nor any other roboscript knows: is the "
            "baud rate right, and is it running its firmware?"
        )
    return (
        f"{robot} did not answer on {url} {waited}: nothing came back to {bytes_sent} bytes of "
        f"the {title} handshake: is it switched on and running its firmware? (A SPIKE hub "
        "or a StackMod bridge says nothing until asked in its own protocol: if it is "
        "another robot, name it with --robot.)"
    )
