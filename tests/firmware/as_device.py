"""Put an emulated board where the simulator would put its own model of a robot's board."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Protocol, TypeVar

import roboscript.sim.simulation as simulation_module

if TYPE_CHECKING:
    import pytest
    from firmware.avr import Board

    from roboscript.profiles import RobotProfile
    from roboscript.sim.body import Body
    from roboscript.sim.device import SimDevice


class EmulatedDevice(Protocol):
    """A :class:`SimDevice` backed by an emulated board (closed when the test ends)."""

    @property
    def board(self) -> Board: ...


DeviceT = TypeVar("DeviceT", bound=EmulatedDevice)


@contextmanager
def firmware_as_device(
    monkeypatch: pytest.MonkeyPatch,
    wanted: Callable[[RobotProfile], bool],
    make: Callable[[Body], DeviceT],
) -> Iterator[list[DeviceT]]:
    """Make every simulated robot whose profile is ``wanted`` a device made by ``make`` (on
    the simulated body) for the rest of the test; yields the devices made, closes their
    boards at the end."""
    built: list[DeviceT] = []
    original: Callable[[RobotProfile, Body], SimDevice] = simulation_module.build_device

    def build_device(profile: RobotProfile, body: Body) -> SimDevice:
        if not wanted(profile):
            return original(profile, body)
        device = make(body)
        built.append(device)
        return device  # type: ignore[return-value]  # each device implements SimDevice

    monkeypatch.setattr(simulation_module, "build_device", build_device)
    try:
        yield built
    finally:
        for device in built:
            device.board.close()
