"""The built-in robots that speak the PLEN2 protocol."""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.robot_profile import RobotProfile

__all__ = ["PROFILES"]

PROFILES = (
    RobotProfile(
        name="plen2",
        protocol="plen",
        description="PLEN2 humanoid, firmware 1.4.2: walks and turns by gait motions",
        baudrate=2_000_000,
        capabilities=frozenset({cap.WALKER, cap.JOINTS}),
        firmware_pid=False,
        body_radius_mm=60.0,
        # Room for a first install of the four gait motions (32-byte writes 50 ms apart).
        handshake_timeout_s=20.0,
    ),
)
"""The built-in profiles of the PLEN2 protocol."""
