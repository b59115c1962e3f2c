"""The built-in robots that speak the StackMod protocol."""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.robot_profile import RobotProfile

__all__ = ["PROFILES"]

PROFILES = (
    RobotProfile(
        name="stackmod-rover",
        protocol="stackmod",
        description="StackMod modules on a 9600 baud line: no encoders, timed moves",
        encoders=False,
        baudrate=9600,
        capabilities=frozenset(
            {
                cap.DRIVE_BASE,
                cap.RANGE,
                cap.SIDE_RANGE,
                cap.LINE,
                cap.BUMPER,
                cap.SPEAKER,
                cap.SERVOS,
            }
        ),
        firmware_pid=False,
        wheel_diameter_mm=65.0,
        track_mm=140.0,
        body_radius_mm=90.0,
        handshake_timeout_s=2.0,
    ),
    # The StackMod author's own firmware (74ls04/StackMod): motor SETs over I2C, nothing else.
    RobotProfile(
        name="stackmod-reference",
        protocol="stackmod",
        description="StackMod author's motor firmware (I2C, PWM): drive only, timed moves",
        encoders=False,
        baudrate=100_000,  # I2C standard mode, Arduino Wire's default clock
        capabilities=frozenset({cap.DRIVE_BASE}),
        firmware_pid=False,
        wheel_diameter_mm=65.0,
        track_mm=140.0,
        body_radius_mm=90.0,
        handshake_timeout_s=2.0,
        options={
            "firmware": "reference",
            "checksum": "braces_excluded",
            "framing": "i2c",
            "motor_address": "E",
        },
    ),
)
"""The built-in profiles of the StackMod protocol."""
