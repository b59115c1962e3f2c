"""Finding robots: serial ports with a hint of which robot each may be.

The hints come from above (each protocol's unit names the USB boards its robots are reached
through: :func:`roboscript.drivers.usb_hints`); transport knows no robot.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from serial.tools import list_ports

__all__ = ["PortInfo", "UsbHints", "list_robot_ports"]

UsbHints = Mapping[tuple[int, int | None], str]
"""(USB vendor id, product id or None for any of the vendor's) -> what the port probably is."""


@dataclass(frozen=True)
class PortInfo:
    """A serial port and what it may be."""

    device: str
    description: str
    usb_id: str | None
    hint: str | None


def _hint(vid: int | None, pid: int | None, hints: UsbHints) -> str | None:
    if vid is None:
        return None
    return hints.get((vid, pid)) or hints.get((vid, None))


def list_robot_ports(hints: UsbHints | None = None) -> list[PortInfo]:
    """Every serial port on this computer, robots first.

    Args:
        hints: What each USB board probably is (none by default).
    """
    found = []
    for port in list_ports.comports():
        vid, pid = port.vid, port.pid
        usb_id = f"{vid:04x}:{pid:04x}" if vid is not None and pid is not None else None
        description = port.description if port.description != "n/a" else ""
        found.append(PortInfo(port.device, description, usb_id, _hint(vid, pid, hints or {})))
    found.sort(key=lambda info: (info.hint is None, info.device))
    return found
