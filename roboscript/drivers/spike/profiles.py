"""The built-in robots that speak the SPIKE hub protocol."""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.robot_profile import RobotProfile

__all__ = ["PROFILES"]

PROFILES = (
    RobotProfile(
        name="spike-prime",
        protocol="spike",
        description="LEGO SPIKE Prime hub (App 3 firmware) running roboscript's agent",
        baudrate=115200,
        capabilities=frozenset(
            {
                cap.DRIVE_BASE,
                cap.RANGE,
                cap.BUMPER,
                cap.SPEAKER,
                cap.DISPLAY,
                cap.HEADING,
                cap.FORCE,
                cap.COLOR,
                cap.LINE,  # the colour sensor, read as one line sensor
                cap.BUTTONS,
                cap.MOTORS,
            }
        ),
        firmware_pid=True,
        # Ports (options, roboscript/drivers/spike/options.py): drive motors A and B, force
        # sensor C, distance sensor D, colour sensor E (looking down), one more motor on F.
        # follow_line on the one colour sensor follows the tape's edge: the reading swings
        # from -1 to 1 across the edge's few millimetres, so it needs a softer steer than
        # three IR sensors (150): on the simulated line-track, kp 30-40 follows the whole run
        # and 50 loses the line at the start.
        gains={"line": (40.0, 0.0, 3.0)},
        # LEGO's driving base: 56 mm wheels, 112 mm apart; motor degrees are the encoder ticks.
        wheel_diameter_mm=56.0,
        track_mm=112.0,
        ticks_per_rev=360,
        body_radius_mm=90.0,
        max_speed_mm_s=350.0,
        # Room for a first upload of the agent over BLE (about 14 kB in 20-byte packets).
        handshake_timeout_s=20.0,
    ),
)
"""The built-in profiles of the SPIKE hub protocol."""
