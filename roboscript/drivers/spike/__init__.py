"""The spike protocol: the LEGO SPIKE Prime hub (App 3 protocol) and roboscript's agent on it.

``codec.py`` is the sans-IO codec (both roles), ``driver.py`` the host side, ``device.py`` the
simulated robot's side. :data:`PROTOCOL` names them for the registries; importing this package
imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.spike.profiles import PROFILES
from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="spike",
    title="SPIKE hub",
    speakers="a LEGO SPIKE Prime hub",
    codec="roboscript.drivers.spike.codec:codec_for",
    driver="roboscript.drivers.spike.driver:SpikeDriver",
    device="roboscript.drivers.spike.device:simulated_device",
    profiles=PROFILES,
    listed=30,
    usb=((0x0694, None, "LEGO hub (SPIKE Prime connects over Bluetooth: --port ble://NAME)"),),
    contract=ContractCases(wheeled=("spike-prime",)),
)
"""The spike protocol unit."""
