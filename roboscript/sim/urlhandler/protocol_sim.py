"""``sim://ROBOT?world=W&seed=N&x=MM&y=MM&heading=DEG``: an in-process simulated robot.

pyserial finds this module by name (``protocol_sim``) in one of the packages ``open_port``
registers (:data:`roboscript.transport.ports.HANDLER_PACKAGES`). The port's
:attr:`Serial.simulation` is a Tickable: the caller adds it to the scheduler, so the device runs
in lockstep with the mission and a run is deterministic. Writes reach the device at once; reads
return what the device has sent so far and never block.
"""

from __future__ import annotations

import math
import urllib.parse

from roboscript.errors import InputError
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.sim.world import Pose
from roboscript.transport.device_port import DevicePort, SerialException

__all__ = ["Serial", "parse_sim_url"]


def parse_sim_url(url: str) -> tuple[str, str, int, Pose | None]:
    """Split a ``sim://`` URL into (robot, world, seed, start pose or None).

    Raises:
        ValueError: The URL is not a valid ``sim://`` URL.
    """
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "sim":
        raise ValueError(f"expected a sim:// URL, got {url!r}")
    robot = parts.netloc or "mirto"
    query = urllib.parse.parse_qs(parts.query)
    world = query.get("world", ["empty"])[-1]

    def number(key: str, default: str, kind: type[int | float]) -> float:
        text = query.get(key, [default])[-1]
        try:
            value = kind(text)
        except ValueError:
            what = "a whole number" if kind is int else "a number"
            raise ValueError(f"{key} must be {what} (got {text!r})") from None
        if not math.isfinite(value):
            raise ValueError(f"{key} must be a finite number (got {text!r})")
        return value

    seed = int(number("seed", "1", int))
    start = None
    if {"x", "y", "heading"} & query.keys():
        start = Pose(
            number("x", "0", float), number("y", "0", float), number("heading", "0", float)
        )
    return robot, world, seed, start


class Serial(DevicePort):
    """A pyserial port backed by a :class:`~roboscript.sim.simulation.Simulation`."""

    simulation: Simulation | None = None

    def open(self) -> None:
        """Build the simulation named by the URL and power the device on."""
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        try:
            robot, world, seed, start = parse_sim_url(str(self.port))
            self.simulation = make_simulation(robot, world, seed, start)
        except InputError:
            raise  # a bad world or profile is the user's input: open_port lets it through
        except (ValueError, NotImplementedError) as exc:
            raise SerialException(str(exc)) from exc
        self.simulation.connect()
        self.is_open = True
