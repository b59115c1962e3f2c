"""The stackmod protocol: StackMod modules on one serial line, or the author's module on I2C.

``codec.py`` is the sans-IO codec (both roles), ``driver.py`` the host side, ``device.py`` the
simulated robot's side (``reference_device.py`` for the author's own firmware). :data:`PROTOCOL`
names them for the registries; importing this package imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.stackmod.profiles import PROFILES
from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="stackmod",
    title="StackMod",
    speakers="a StackMod bridge",
    codec="roboscript.drivers.stackmod.options:codec_for",
    driver="roboscript.drivers.stackmod.driver:StackModDriver",
    device="roboscript.drivers.stackmod.device:simulated_device",
    profiles=PROFILES,
    listed=20,
    usb=(
        (0x0403, 0x6001, "FTDI USB-serial"),
        (0x0403, 0x6015, "FTDI USB-serial"),
        (0x1A86, 0x7523, "CH340 USB-serial (an Arduino clone)"),
        (0x10C4, 0xEA60, "CP210x USB-serial"),
    ),
    contract=ContractCases(wheeled=("stackmod-rover",), open_loop=("stackmod-reference",)),
)
"""The stackmod protocol unit."""
