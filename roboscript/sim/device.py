"""The contract between the simulation and a simulated device (board, hub, module set).

A device is the robot's side of a protocol: it decodes requests with the protocol's codec in
the device role, drives the :class:`~roboscript.sim.body.Body`, and encodes replies and events
at the rates the real firmware uses. It never sleeps and never reads a clock: the simulation
calls :meth:`SimDevice.step` with the simulated time after every physics step.
"""

from __future__ import annotations

from typing import Protocol

__all__ = ["SimDevice"]


class SimDevice(Protocol):
    """A simulated robot controller speaking its protocol's real bytes."""

    def connect(self, now_s: float) -> None:
        """A host has opened the line (power-on, or a new TCP client): greet it."""
        ...

    def receive(self, data: bytes, now_s: float) -> None:
        """Bytes arrived from the host."""
        ...

    def step(self, now_s: float) -> None:
        """Run the firmware's periodic work up to ``now_s`` (after a physics step)."""
        ...

    def pending_input_bytes(self) -> int:
        """Request bytes received and not yet a whole message: the host stopped mid-frame
        (``roboscript sim`` drops a client that stays so)."""
        ...

    def read_output(self) -> bytes:
        """Take the bytes the device has written since the last call."""
        ...

    def stop_all(self) -> None:
        """Cut every actuator, as a power loss would."""
        ...
