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
    contract=ContractCases(wheeled=("mirto", "asip-basic")),
)
"""The asip protocol unit."""
