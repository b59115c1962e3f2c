"""The built-in robots that speak the ASIP protocol."""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.robot_profile import RobotProfile

__all__ = ["PROFILES"]

_CAPABILITIES = frozenset(
    {
        cap.DRIVE_BASE,
        cap.RANGE,
        cap.SIDE_RANGE,
        cap.BUMPER,
        cap.LINE,
        cap.SPEAKER,
        cap.DISPLAY,
        cap.SERVOS,
        cap.LEDS,
    }
)


PROFILES = (
    RobotProfile(
        name="mirto",
        protocol="asip",
        description="MIRTO robot, ASIP 1.1 firmware with motor PID",
        baudrate=57600,
        capabilities=_CAPABILITIES,
        firmware_pid=True,
        # The V1.1 mirtle2017 sketch: one servo, nine pixels; the LCD keeps 20 characters.
        options={"servo_count": 1, "pixel_count": 9, "lcd_columns": 20},
        # A board that resets when the port opens (an Uno-style 328 board) runs the sketch's
        # start-up for 3.2 s (pixelFun's three 1 s delays, then setup()) before it answers.
        handshake_timeout_s=5.0,
    ),
    RobotProfile(
        name="asip-basic",
        protocol="asip",
        description="ASIP robot whose firmware has no PID: the host closes every loop",
        baudrate=57600,
        capabilities=_CAPABILITIES,
        firmware_pid=False,
        gains={"wheel_speed": (0.0015, 0.004, 0.0)},
    ),
)
"""The built-in profiles of the ASIP protocol."""
