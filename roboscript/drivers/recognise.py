"""Which protocol a port speaks, from the bytes it sent: for a handshake that failed.

A student who forgets ``--robot spike-prime`` should hear "this port speaks the SPIKE hub
protocol", not "is it switched on". Each protocol's own host codec reads the bytes the port
sent before the handshake gave up (kept by the link, :attr:`Link.heard
<roboscript.transport.link.Link.heard>`); the protocol whose codec reads the most whole
messages from them, more than it refuses, is the one the port speaks. The signatures are the
codecs' own framing: ASIP's ``@``/``~``/``!`` lines, SPIKE's COBS frames ending ``0x02``,
StackMod's ``{…}`` frames with their checksum, PLEN2's replies. Each protocol's unit says how
it is named (:attr:`~roboscript.drivers.unit.ProtocolUnit.title`), who speaks it, and which of
its messages prove nothing, so a new protocol is recognised with no edit here. Sans-IO,
standard library only.

The hints name the robot as the user picks one: ``--robot`` on the command line; a front end
with its own control for it (the browser app's Robot list) names that instead, for as long as
it runs a mission (:func:`robots_picked_with`). The port is named as the user named it too: its
URL on the command line; in the browser app, as the student chose it ("the robot on the serial
port you chose"), never by a URL they never saw.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import NamedTuple

from roboscript.codec import Role
from roboscript.drivers import protocol_unit, units
from roboscript.drivers.unit import ProtocolUnit
from roboscript.errors import RemoteProtocolError

__all__ = [
    "COMMAND_LINE",
    "RobotPicker",
    "handshake_failure",
    "protocol_title",
    "recognise_protocol",
    "robots_picked_with",
    "wrong_robot_hint",
]

_MOST_MESSAGES = 64  # a handful is proof enough; the bytes kept are bounded anyway


class RobotPicker(NamedTuple):
    """How a user names the robot to drive, as a failed handshake's hints say it.

    Attributes:
        use: Naming the robot the port belongs to, ``{robot}`` for its name
            (``"use --robot {robot}"``).
        another: Naming some robot other than the one asked for (``"name it with --robot"``).
        robot_at: The front end's own words for the robot at a port's URL (``"the robot on
            the serial port you chose"``), or ``None`` where the URL is what the user gave
            (then the port is named by its URL).
    """

    use: str
    another: str
    robot_at: Callable[[str], str | None] = lambda url: None


COMMAND_LINE = RobotPicker("use --robot {robot}", "name it with --robot")
"""The command line's ``--robot`` option."""

_picker = COMMAND_LINE


@contextlib.contextmanager
def robots_picked_with(picker: RobotPicker) -> Iterator[None]:
    """Within the block, a failed handshake's hints name ``picker`` (a page's own control)
    instead of ``--robot``, which a page's user cannot give."""
    global _picker
    before, _picker = _picker, picker
    try:
        yield
    finally:
        _picker = before


def _messages_read(unit: ProtocolUnit, data: bytes) -> tuple[int, int]:
    """(messages read, frames refused) when ``unit``'s host codec reads ``data``."""
    try:
        codec = unit.make_codec(Role.HOST, unit.profiles[0])
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
            if type(message).__name__ not in unit.proves_nothing:
                read += 1
    except Exception:  # noqa: BLE001 - bytes of another protocol may upset a codec anyhow
        return 0, refused + 1
    return read, refused


def _speaks(data: bytes, protocol: str) -> bool:
    """True if ``protocol``'s own codec reads ``data`` cleanly (messages, none refused)."""
    try:
        read, refused = _messages_read(protocol_unit(protocol), data)
    except NotImplementedError:
        return False
    return read > 0 and refused == 0


def protocol_title(protocol: str) -> str:
    """How ``protocol`` is named to a user (``"SPIKE hub"``), or its name if unknown."""
    try:
        return protocol_unit(protocol).title
    except NotImplementedError:
        return protocol


def recognise_protocol(data: bytes, among: tuple[ProtocolUnit, ...] | None = None) -> str | None:
    """The protocol ``data`` is written in, or ``None`` if none reads it clearly.

    Args:
        data: Bytes a port sent.
        among: The protocols to try (default: every protocol roboscript has).

    Returns:
        The protocol's name (``"spike"``), as in a profile's ``protocol``.
    """
    if not data:
        return None
    scores = []
    for unit in units() if among is None else among:
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
    """``this port speaks the SPIKE hub protocol: use --robot spike-prime``, or ``None`` (the
    robot named as :func:`robots_picked_with` says).

    Args:
        heard: The bytes the port sent.
        expected_protocol: The protocol of the robot that was asked for.
    """
    # The robot asked for is the usual speaker: when its own codec reads the bytes cleanly,
    # no other codec is imported (a graded run's handshake then loads one protocol, not all).
    if _speaks(heard, expected_protocol):
        return None
    found = recognise_protocol(heard)
    if found is None or found == expected_protocol:
        return None
    unit = protocol_unit(found)
    use = _picker.use.format(robot=unit.profile_names[0])
    return f"this port speaks the {unit.title} protocol ({unit.speakers}): {use}"


def handshake_failure(
    robot: str, protocol: str, url: str, heard: bytes, bytes_sent: int, waited: str
) -> str:
    """One sentence for a robot that did not finish its handshake, naming what was heard.

    Args:
        robot: The robot asked for (``mirto``).
        protocol: Its protocol (``asip``).
        url: The port (named as :func:`robots_picked_with` says).
        heard: The bytes the port sent.
        bytes_sent: How many bytes of the handshake were sent.
        waited: How long it was waited for, as text (``within 3 s``).
    """
    title = protocol_title(protocol)
    hint = wrong_robot_hint(heard, protocol)
    at = _picker.robot_at(url)
    # the robot named as the user reached it: by the port's URL, or by how it was chosen
    silent = f"{robot} did not answer on {url}" if at is None else f"{at} did not answer as {robot}"
    if hint is not None:
        return f"{silent}: {hint}"
    within = f"{silent} {waited}" if waited else silent
    if heard and _speaks(heard, protocol):
        # its own protocol, but no end to the handshake: saying "not the protocol" would
        # send the user after the baud rate of a board that answered
        return (
            f"{within}: it sent {len(heard)} bytes of the {title} protocol but did not finish "
            "the handshake: is it still starting up (a board that restarts when its port "
            "opens takes seconds), and does its firmware answer what roboscript asks?"
        )
    if heard:
        return (
            f"{within}: the port sent {len(heard)} bytes "
            f"that are not the {title} protocol nor any other roboscript knows: is the "
            "baud rate right, and is it running its firmware?"
        )
    return (
        f"{within}: nothing came back to {bytes_sent} bytes of "
        f"the {title} handshake: is it switched on and running its firmware? (A SPIKE hub "
        "or a StackMod bridge says nothing until asked in its own protocol: if it is "
        f"another robot, {_picker.another}.)"
    )
