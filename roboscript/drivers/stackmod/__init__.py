"""The stackmod protocol: StackMod modules on one serial line.

``codec.py`` is the sans-IO codec (both roles), ``driver.py`` the host side, ``device.py`` the
simulated robot's side. :data:`PROTOCOL` names them for the registries; importing this package
imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="stackmod",
    codec="roboscript.drivers.stackmod.options:codec_for",
    driver="roboscript.drivers.stackmod.driver:StackModDriver",
    device="roboscript.drivers.stackmod.device:simulated_device",
    profiles=("stackmod-rover",),
    contract=ContractCases(wheeled=("stackmod-rover",)),
)
"""The stackmod protocol unit."""
