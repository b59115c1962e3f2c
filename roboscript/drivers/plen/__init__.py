"""The plen protocol: the PLEN2 humanoid, firmware 1.4.2.

``codec.py`` is the sans-IO codec (both roles), ``driver.py`` the host side, ``device.py`` the
simulated robot's side. :data:`PROTOCOL` names them for the registries; importing this package
imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.plen.profiles import PROFILES
from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="plen",
    title="PLEN2",
    speakers="a PLEN2",
    codec="roboscript.drivers.plen.codec:codec_for",
    driver="roboscript.drivers.plen.driver:PlenDriver",
    device="roboscript.drivers.plen.device:simulated_device",
    profiles=PROFILES,
    listed=40,
    usb=(
        (0x2341, 0x8037, "Arduino Micro"),
        (0x2341, 0x0037, "Arduino Micro bootloader (being flashed)"),
    ),
    contract=ContractCases(walking=("plen2",)),
)
"""The plen protocol unit."""
