"""``sim://ROBOT?world=W&seed=N&x=MM&y=MM&heading=DEG&reset=1``: an in-process simulated robot.

``reset=1`` makes the board one that resets when its port opens (an ASIP board's
``reset_on_connect`` option, an Arduino Uno-style board): it answers only once its sketch has
started again, as the real board does.

pyserial finds this module by name (``protocol_sim``) in one of the packages ``open_port``
registers (:data:`roboscript.transport.ports.HANDLER_PACKAGES`). The port's
:attr:`Serial.simulation` is a Tickable: the caller adds it to the scheduler, so the device runs
in lockstep with the mission and a run is deterministic. Writes reach the device at once; reads
return what the device has sent so far and never block.
"""

from __future__ import annotations

import math
import urllib.parse

from roboscript.errors import InputError, did_you_mean
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.sim.world import Pose
from roboscript.transport.device_port import DevicePort, SerialException

__all__ = ["SIM_URL_KEYS", "Serial", "parse_sim_url"]

SIM_URL_KEYS = ("world", "seed", "x", "y", "heading", "reset")
"""What a ``sim://`` URL's query may set."""


def parse_sim_url(url: str) -> tuple[str, str, int, Pose | None, dict[str, object]]:
    """Split a ``sim://`` URL into (robot, world, seed, start pose or None, the profile
    options the URL sets).

    Raises:
        ValueError: The URL is not a valid ``sim://`` URL.
    """
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "sim":
        raise ValueError(f"expected a sim:// URL, got {url!r}")
    robot = parts.netloc or "mirto"
    query = urllib.parse.parse_qs(parts.query)
    for key in query:  # a misspelt key would leave its value unused: another run than asked
        if key not in SIM_URL_KEYS:
            hint = did_you_mean(key, SIM_URL_KEYS)
            raise ValueError(
                f"a sim:// URL takes {', '.join(SIM_URL_KEYS)}, not {key!r}"
                + (f" ({hint})" if hint else "")
            )
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
    options: dict[str, object] = {}
    if "reset" in query:
        text = query["reset"][-1]
        if text not in ("0", "1"):
            raise ValueError(f"reset must be 0 or 1 (got {text!r})")
        options["reset_on_connect"] = text == "1"
    return robot, world, seed, start, options


class Serial(DevicePort):
    """A pyserial port backed by a :class:`~roboscript.sim.simulation.Simulation`."""

    simulation: Simulation | None = None

    def open(self) -> None:
        """Build the simulation named by the URL and power the device on."""
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        try:
            robot, world, seed, start, options = parse_sim_url(str(self.port))
            self.simulation = make_simulation(robot, world, seed, start, options=options)
        except InputError:
            raise  # a bad world or profile is the user's input: open_port lets it through
        except (ValueError, NotImplementedError) as exc:
            raise SerialException(str(exc)) from exc
        self.simulation.connect()
        self.is_open = True
