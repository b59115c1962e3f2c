"""Finding robots: serial ports with a hint of which robot each may be."""

from __future__ import annotations

from dataclasses import dataclass

from serial.tools import list_ports

__all__ = ["USB_HINTS", "PortInfo", "list_robot_ports"]

USB_HINTS: dict[tuple[int, int | None], str] = {
    (0x2341, 0x0043): "Arduino Uno: an ASIP robot (--robot mirto)",
    (0x2341, 0x0001): "Arduino Uno: an ASIP robot (--robot mirto)",
    (0x2341, 0x0042): "Arduino Mega: an ASIP robot (--robot mirto)",
    (0x2341, 0x8037): "Arduino Micro: a PLEN2 (--robot plen2)",
    (0x2341, 0x0037): "Arduino Micro bootloader: a PLEN2 being flashed",
    (0x2341, None): "Arduino: an ASIP robot (--robot mirto)",
    (0x16C0, 0x0483): "Teensy: a MIRTO (--robot mirto)",
    (0x0403, 0x6001): "FTDI USB-serial: an ASIP robot or a StackMod bridge",
    (0x0403, 0x6015): "FTDI USB-serial: an ASIP robot or a StackMod bridge",
    (0x1A86, 0x7523): "CH340 USB-serial: an Arduino clone (--robot mirto or stackmod-rover)",
    (0x10C4, 0xEA60): "CP210x USB-serial: an ASIP robot or a StackMod bridge",
    (0x0694, None): "LEGO hub (SPIKE Prime connects over Bluetooth: --port ble://NAME)",
}
"""(USB vendor id, product id or None for any) -> what the port probably is."""


@dataclass(frozen=True)
class PortInfo:
    """A serial port and what it may be."""

    device: str
    description: str
    usb_id: str | None
    hint: str | None


def _hint(vid: int | None, pid: int | None) -> str | None:
    if vid is None:
        return None
    return USB_HINTS.get((vid, pid)) or USB_HINTS.get((vid, None))


def list_robot_ports() -> list[PortInfo]:
    """Every serial port on this computer, robots first."""
    found = []
    for port in list_ports.comports():
        vid, pid = port.vid, port.pid
        usb_id = f"{vid:04x}:{pid:04x}" if vid is not None and pid is not None else None
        description = port.description if port.description != "n/a" else ""
        found.append(PortInfo(port.device, description, usb_id, _hint(vid, pid)))
    found.sort(key=lambda info: (info.hint is None, info.device))
    return found
