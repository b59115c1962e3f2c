"""The asip protocol: ASIP 1.1 (MIRTO and other ASIP boards).

``codec.py`` is the sans-IO codec (both roles), ``driver.py`` the host side, ``device.py`` the
simulated robot's side. :data:`PROTOCOL` names them for the registries; importing this package
imports none of them.
"""

from __future__ import annotations

from roboscript.drivers.unit import ContractCases, ProtocolUnit

__all__ = ["PROTOCOL"]

PROTOCOL = ProtocolUnit(
    name="asip",
    codec="roboscript.drivers.asip.codec:codec_for",
    driver="roboscript.drivers.asip.driver:AsipDriver",
    device="roboscript.drivers.asip.device:simulated_device",
    profiles=("mirto", "asip-basic"),
    contract=ContractCases(wheeled=("mirto", "asip-basic")),
)
"""The asip protocol unit."""
