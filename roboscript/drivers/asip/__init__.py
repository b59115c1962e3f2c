"""The asip protocol: ASIP 1.1 (MIRTO and other ASIP boards).

``codec.py`` is the sans-IO codec (both roles), composed of ``framing.py`` (bytes into lines),
``host_side.py`` (requests written, the board's lines read), ``device_side.py`` (requests read
the firmware's way, replies written) and ``value_ranges.py`` (what each number can be);
``driver.py`` is the host side, ``device.py`` the simulated robot's side. :data:`PROTOCOL`
names them for the registries; importing this package imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.asip.profiles import PROFILES
from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="asip",
    title="ASIP",
    speakers="a MIRTO or another ASIP board",
    codec="roboscript.drivers.asip.codec:codec_for",
    driver="roboscript.drivers.asip.driver:AsipDriver",
    device="roboscript.drivers.asip.device:simulated_device",
    profiles=PROFILES,
    proves_nothing=frozenset({"DebugLine"}),
    listed=10,
    usb=(
        (0x2341, 0x0043, "Arduino Uno"),
        (0x2341, 0x0001, "Arduino Uno"),
        (0x2341, 0x0042, "Arduino Mega"),
        (0x2341, None, "Arduino"),
        (0x16C0, 0x0483, "Teensy"),
        (0x0403, 0x6001, "FTDI USB-serial"),
        (0x0403, 0x6015, "FTDI USB-serial"),
        (0x1A86, 0x7523, "CH340 USB-serial (an Arduino clone)"),
        (0x10C4, 0xEA60, "CP210x USB-serial"),
    ),
    contract=ContractCases(wheeled=("mirto", "asip-basic")),
)
"""The asip protocol unit."""
