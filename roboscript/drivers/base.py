"""The host-side driver contract: what every protocol driver provides.

A driver owns a :class:`~roboscript.transport.Link` and turns it into capabilities. It is
ticked twice per scheduler tick: :meth:`Driver.tick` in the *sense* phase (read the link,
update cached sensor values, advance the handshake, watch for silence) and :meth:`Driver.flush`
in the *act* phase (send setpoints that changed). It never blocks and never sleeps.

Safety: :meth:`Driver.stop_all` must stop every actuator with the fewest bytes that work on
the real firmware, must be callable at any time (even before the handshake finished), and
must never raise: it is called on every exit path, including after the link has failed.
"""

from __future__ import annotations

import abc
import logging
from collections.abc import Callable
from typing import Any, ClassVar, Protocol

from roboscript.clock import Clock
from roboscript.drivers.codec import Codec
from roboscript.profiles import RobotProfile
from roboscript.transport.link import Link

__all__ = ["Driver", "WheelDriveBase"]

logger = logging.getLogger("roboscript.drivers")


class Driver(abc.ABC):
    """Base class of protocol drivers.

    Args:
        link: The open link to the robot (its codec made by :meth:`make_codec`).
        profile: The robot model.
        clock: The scheduler's clock.
    """

    protocol: ClassVar[str]

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        self.link = link
        self.profile = profile
        self.clock = clock
        self.ready = False
        self.notices: list[str] = []
        """One-line messages for the user (for example a switch to host-side control)."""
        self.device_errors: list[str] = []
        """Errors the robot reported (refused requests), oldest first, not yet taken."""

    @classmethod
    @abc.abstractmethod
    def make_codec(cls, profile: RobotProfile) -> Codec[Any]:
        """The host-role codec for this protocol."""

    @abc.abstractmethod
    def start(self) -> None:
        """Begin the handshake (send the first probe)."""

    @abc.abstractmethod
    def tick(self, now_s: float, dt_s: float) -> None:
        """Sense phase: read the link, update sensor values, advance the handshake.

        Raises:
            LinkError: The link was lost or the robot stopped responding.
        """

    @abc.abstractmethod
    def flush(self, now_s: float, dt_s: float) -> None:
        """Act phase: send setpoints that changed since the last tick."""

    @abc.abstractmethod
    def capabilities(self) -> dict[str, object]:
        """The capability objects, by capability name (after the handshake)."""

    @abc.abstractmethod
    def stop_all(self) -> None:
        """Stop every actuator now. Never raises."""

    def describe(self) -> str:
        """What is on the other end, in a few words (after the handshake)."""
        return self.profile.name

    def take_device_error(self) -> str | None:
        """The oldest error the robot reported and nobody has taken yet, or ``None``.

        The mission runner takes them every tick and fails the running action with them.
        """
        return self.device_errors.pop(0) if self.device_errors else None

    def notice(self, text: str) -> None:
        """Tell the user something once, in one line (logged at once as a warning)."""
        if text not in self.notices:
            self.notices.append(text)
            logger.warning("%s", text)


class _WheelSetpoints(Protocol):
    profile: RobotProfile

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None: ...


class WheelDriveBase:
    """The ``drive_base`` capability of a driver that takes wheel speed setpoints.

    It limits setpoints to the profile's top speed and reads wheel travel from the driver;
    the driver decides how speeds are held (firmware PID, host PID, or timing).

    Args:
        driver: Takes ``set_wheel_speeds(left_mm_s, right_mm_s)``; its ``profile`` gives the
            track and top speed.
        distances: Returns the wheel travel (left, right) since connection, mm.
        odometry_is_estimated: True when travel is computed from time, not encoders.
    """

    def __init__(
        self,
        driver: _WheelSetpoints,
        distances: Callable[[], tuple[float, float]],
        *,
        odometry_is_estimated: bool = False,
    ) -> None:
        self._driver = driver
        self._distances = distances
        self.track_mm = driver.profile.track_mm
        self.max_speed_mm_s = driver.profile.max_speed_mm_s
        self.odometry_is_estimated = odometry_is_estimated

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Hold each wheel at a speed, mm/s (forward positive), limited to the top speed."""
        limit = self.max_speed_mm_s
        self._driver.set_wheel_speeds(
            max(-limit, min(limit, left_mm_s)), max(-limit, min(limit, right_mm_s))
        )

    def stop(self) -> None:
        """Stop both wheels."""
        self._driver.set_wheel_speeds(0.0, 0.0)

    def wheel_distances_mm(self) -> tuple[float, float]:
        """Wheel travel (left, right) since connection, mm; forward positive."""
        return self._distances()
