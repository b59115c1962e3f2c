"""How a SPIKE Prime robot is built: which device is on which hub port, and agent settings.

These are *profile options* (:attr:`RobotProfile.options
<roboscript.profiles.RobotProfile.options>`), read here into a :class:`SpikeOptions`. Both the
host driver and the simulated hub use them, so the simulator is wired the way the profile says.
A profile file changes only what differs::

    extends: spike-prime
    name: team-4-base
    options:
      left_motor: E
      right_motor: F
      distance: A
      color: D
      motors: B           # an arm on B (``motor`` action)

The defaults follow a LEGO driving base: drive motors on A (left, mounted mirrored, as
``motor_pair`` expects) and B (right), force sensor on C (used as a front bumper), distance
sensor on D, colour sensor on E (looking down at the floor, for ``follow_line`` and ``color``),
and one more motor on F for the ``motor`` action.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from roboscript.drivers.options import read_options
from roboscript.drivers.spike.messages import SLOT_COUNT, HubPort
from roboscript.errors import ProfileError

__all__ = ["SpikeOptions", "port_name"]

_PORT_OPTIONS = ("left_motor", "right_motor", "force", "distance", "color")


def port_name(port: int) -> str:
    """A hub port number as printed on the hub (0 -> ``"A"``)."""
    return HubPort(port).name


@dataclass(frozen=True)
class SpikeOptions:
    """The options of a SPIKE Prime robot profile (defaults: the ``spike-prime`` profile).

    Ports are written as letters ``A``..``F`` in a profile file and held as numbers 0..5.

    Attributes:
        left_motor: Port of the left drive motor.
        right_motor: Port of the right drive motor.
        force: Port of the force sensor read as the front bumper (and ``force``).
        distance: Port of the distance sensor (``range``).
        color: Port of the colour sensor (``color``, and ``line`` for ``follow_line``).
        motors: Ports of the motors that are not drive motors (``motor`` action), written
            as letters (``CF``) or a list; may be empty. Not given: every port no other
            option uses (F with the default wiring).
        agent_slot: Program slot (0-19) the agent is uploaded to and run from. The default,
            the last slot, is the one students are least likely to use.
        telemetry_ms: Interval of the hub's DeviceNotification messages, milliseconds
            (10-1000): how often wheel positions and sensors are read.
    """

    left_motor: int = int(HubPort.A)
    right_motor: int = int(HubPort.B)
    force: int = int(HubPort.C)
    distance: int = int(HubPort.D)
    color: int = int(HubPort.E)
    motors: tuple[int, ...] = (int(HubPort.F),)
    agent_slot: int = SLOT_COUNT - 1
    telemetry_ms: int = 50

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any], *, profile: str) -> SpikeOptions:
        """Read the options of a profile, checking every value.

        Args:
            options: Option name -> value, as written in the profile (unknown names refused).
            profile: The profile's name, for error messages.

        Raises:
            ProfileError: An unknown option or a bad value, naming both.
        """
        result = read_options(cls, options, profile=profile, family="SPIKE", read=_read)
        if result.left_motor == result.right_motor:
            raise ProfileError(f"{profile}: left_motor and right_motor must be different ports")
        taken = {port: name for name, port in result.ports.items()}
        if "motors" not in options:
            free = tuple(port for port in range(len(HubPort)) if port not in taken)
            return dataclasses.replace(result, motors=free)
        for port in result.motors:
            if port in taken:
                raise ProfileError(
                    f"{profile}: option 'motors' lists port {port_name(port)},"
                    f" which is the {taken[port].replace('_', ' ')}'s port"
                )
        return result

    @property
    def ports(self) -> dict[str, int]:
        """Each device role (``left_motor``, ``distance``, ...) -> its port."""
        return {name: getattr(self, name) for name in _PORT_OPTIONS}


def _read(name: str, value: object, profile: str) -> int | tuple[int, ...]:
    """Check and convert one option value.

    Raises:
        ProfileError: The value does not fit the option.
    """
    if name == "motors":
        letters = list(value) if isinstance(value, str | list) else None
        if letters is None or not all(
            isinstance(letter, str) and letter.upper() in HubPort.__members__ for letter in letters
        ):
            raise ProfileError(
                f"{profile}: option 'motors' must be port letters A-F (e.g. CF), got {value!r}"
            )
        ports = tuple(int(HubPort[letter.upper()]) for letter in letters)
        if len(set(ports)) != len(ports):
            raise ProfileError(f"{profile}: option 'motors' lists a port twice: {value!r}")
        return ports
    if name in _PORT_OPTIONS:
        if isinstance(value, str) and value.upper() in HubPort.__members__:
            return int(HubPort[value.upper()])
        raise ProfileError(f"{profile}: option '{name}' must be a port letter A-F, got {value!r}")
    low, high = (0, SLOT_COUNT - 1) if name == "agent_slot" else (10, 1000)
    if isinstance(value, int) and not isinstance(value, bool) and low <= value <= high:
        return value
    raise ProfileError(
        f"{profile}: option '{name}' must be a whole number {low}-{high}, got {value!r}"
    )
