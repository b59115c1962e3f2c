"""A pyserial port whose other end is a simulated device object, not a line.

``sim://`` (the simulation in this process) and ``lockstep://`` (the grader's world, over the
lockstep wire) are both this port: writes reach the device at once, reads never block and
return what the device has sent, and :attr:`DevicePort.simulation` is a Tickable the robot
adds to its scheduler, so time is simulated and a run is deterministic. Each handler only
says how to find its device (:meth:`DevicePort.open`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

from serial.serialutil import PortNotOpenError, SerialBase, SerialException

if TYPE_CHECKING:
    from _typeshed import ReadableBuffer

__all__ = ["DeviceEnd", "DevicePort", "SerialException"]
# SerialException is what a handler's open() raises for a URL it cannot serve; it is exported
# so handlers outside transport (the simulator's sim://) need not import pyserial themselves.


class DeviceEnd(Protocol):
    """The device side as the port sees it."""

    @property
    def in_waiting(self) -> int:
        """Bytes the device has sent and the host has not read."""
        ...

    def read(self, size: int) -> bytes:
        """Take up to ``size`` bytes the device has sent."""
        ...

    def write(self, data: bytes) -> None:
        """Bytes from the host reach the device."""
        ...


class DevicePort(SerialBase):
    """The pyserial face of a :class:`DeviceEnd`; subclasses open it."""

    def _device(self) -> DeviceEnd:
        device: DeviceEnd | None = getattr(self, "simulation", None)
        if not self.is_open or device is None:
            raise PortNotOpenError()
        return device

    def close(self) -> None:
        """Close the port (the device stays readable, e.g. for a simulation's log)."""
        self.is_open = False

    def _reconfigure_port(self) -> None:
        """Baud rate and framing mean nothing to a simulated device."""

    @property
    def in_waiting(self) -> int:
        """Bytes the device has sent and the host has not read."""
        return self._device().in_waiting

    def read(self, size: int = 1) -> bytes:
        """Return up to ``size`` bytes the device has sent (never blocks)."""
        return self._device().read(size)

    def write(self, data: ReadableBuffer, /) -> int:
        """Deliver bytes to the device at once."""
        chunk = memoryview(data).tobytes()
        self._device().write(chunk)
        return len(chunk)

    def reset_input_buffer(self) -> None:
        """Discard bytes waiting for the host."""
        device = self._device()
        device.read(device.in_waiting)

    def reset_output_buffer(self) -> None:
        """Nothing is buffered on the way to the device."""
