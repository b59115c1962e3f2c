"""The robot: a container of capabilities that always stops when you are done with it.

Example:
    >>> from roboscript.robot import Robot
    >>> with Robot.connect("mirto") as robot:        # the built-in simulator
    ...     robot.speaker.beep(880, 0.2)
    ...     robot.run_for(0.5)
    >>> # here the motors have been told to stop and the port is closed

:meth:`Robot.connect` opens the port (``sim://`` by default), starts the driver's handshake
on the scheduler and waits until the robot has answered, never with a fixed sleep. Leaving
the ``with`` block, normally or by any exception (Ctrl-C included), sends the stop command
first and closes the port after.
"""

from __future__ import annotations

import logging
import urllib.parse
from collections.abc import Callable
from types import TracebackType
from typing import TYPE_CHECKING, Any, cast

from roboscript import capabilities as cap
from roboscript.clock import Clock, MonotonicClock, SimClock
from roboscript.drivers import driver_class
from roboscript.drivers.recognise import handshake_failure, wrong_robot_hint
from roboscript.errors import CapabilityError, LinkError, LinkTimeoutError
from roboscript.interrupts import deferred, kept
from roboscript.profiles import RobotProfile, get_profile, register_profile
from roboscript.scheduler import Scheduler
from roboscript.transport import Link, open_port
from roboscript.transport.link import PortLike
from roboscript.transport.wirelog import WireLog
from roboscript.watchdog import cpu_wait_s

if TYPE_CHECKING:
    # typing_extensions is not a dependency: Self (Python 3.11+) is only an annotation here
    from typing_extensions import Self

    from roboscript.drivers.base import Driver

__all__ = ["Robot"]

logger = logging.getLogger(__name__)

DEFAULT_PERIOD_S = 0.02


class Robot:
    """A connected robot and the scheduler that runs it.

    Use :meth:`connect` to make one. Capabilities are attributes (``robot.drive_base``,
    ``robot.speaker``, ...) and :attr:`capabilities` maps their names to the objects.

    Attributes:
        profile: The robot model.
        scheduler: The tick loop the robot's driver (and simulation) runs on.
        clock: The scheduler's clock.
        url: The port the robot was reached on.
        simulation: The in-process simulation, when the port is ``sim://``.
    """

    def __init__(
        self,
        profile: RobotProfile,
        driver: Driver,
        scheduler: Scheduler,
        *,
        url: str,
        simulation: Any = None,
    ) -> None:
        self.profile = profile
        self.driver = driver
        self.scheduler = scheduler
        self.clock: Clock = scheduler.clock
        self.url = url
        self.simulation = simulation
        self.capabilities: dict[str, object] = driver.capabilities()
        self._closed = False

    # ----------------------------------------------------------------------------- connect

    @classmethod
    def connect(
        cls,
        robot: str | RobotProfile = "mirto",
        port: str | None = None,
        *,
        world: str = "empty",
        seed: int = 1,
        start: tuple[float, float, float] | None = None,
        period_s: float = DEFAULT_PERIOD_S,
        realtime: bool = False,
        wire_log: str | None = None,
    ) -> Robot:
        """Connect to a robot (by default, a simulated one) and finish the handshake.

        Args:
            robot: A built-in profile name, a profile file path, or a profile.
            port: A serial port or URL; ``None`` means the in-process simulator.
            world: Simulator world (name or path); only used for ``sim://``.
            seed: Simulator seed; only used for ``sim://``.
            start: Simulator start pose ``(x_mm, y_mm, heading_deg)``, or the world's.
            period_s: Scheduler tick period, seconds.
            realtime: Pace a simulated robot to the wall clock.
            wire_log: Record every byte to this file.

        Raises:
            ProfileError: Unknown robot.
            LinkError: The port cannot be opened.
            LinkTimeoutError: The robot did not answer within the profile's handshake time.
        """
        profile = robot if isinstance(robot, RobotProfile) else get_profile(robot)
        register_profile(profile)
        url = port or _sim_url(profile.name, world, seed, start)
        driver_cls = driver_class(profile.protocol)
        opened = _Opened(url)
        try:
            # A signal that something on the way drops (a finalizer, a library that ignores
            # every exception) still ends the connection here, with the port closed.
            with kept():
                serial_port = opened.port = open_port(url, baudrate=profile.baudrate)
                log = opened.log = WireLog(wire_log) if wire_log else None
                simulation = getattr(serial_port, "simulation", None)
                # A port in a browser tab brings the page's clock: waiting there must let the
                # page run (its port reads, its Stop button), which only the page's clock can.
                clock: Clock = getattr(serial_port, "clock", None) or (
                    SimClock() if simulation is not None and not realtime else MonotonicClock()
                )
                link = opened.link = Link(
                    serial_port, driver_cls.make_codec(profile), clock=clock, wire_log=log, name=url
                )
                scheduler = Scheduler(clock, period_s)
                driver = opened.driver = driver_cls(link, profile, clock)
                if simulation is not None:
                    scheduler.add(simulation, "sense")
                scheduler.add(driver.tick, "sense")
                scheduler.add(driver.flush, "act")
                other = _OtherProtocol(profile.protocol)  # a SPIKE hub need not be waited 20 s for
                driver.start()
                answered = _wait_for_handshake(
                    scheduler,
                    lambda: bool(driver.ready) or other.heard(link.heard),
                    profile.handshake_timeout_s,
                    on_wall_clock=isinstance(clock, MonotonicClock),
                )
        except LinkError as exc:  # a port that did not open, or a driver that gave up
            opened.abandon()
            if opened.link is None or wrong_robot_hint(bytes(link.heard), profile.protocol) is None:
                raise  # was it another robot? only a link that heard something can tell
            raise LinkTimeoutError(
                handshake_failure(
                    profile.name, profile.protocol, url, bytes(link.heard), link.bytes_sent, ""
                )
            ) from exc
        except BaseException:
            opened.abandon()
            raise
        if not (answered and driver.ready):  # not ready: another protocol was heard
            opened.abandon()
            waited = f"within {profile.handshake_timeout_s:g} s"
            raise LinkTimeoutError(
                handshake_failure(
                    profile.name, profile.protocol, url, bytes(link.heard), link.bytes_sent, waited
                )
            )
        return cls(profile, driver, scheduler, url=url, simulation=simulation)

    # -------------------------------------------------------------------------- capabilities

    def has(self, name: str) -> bool:
        """True if the robot has capability ``name``."""
        return name in self.capabilities

    def require(self, *names: str) -> None:
        """Check that the robot has every capability in ``names``.

        Raises:
            CapabilityError: Naming each missing capability.
        """
        missing = tuple(name for name in names if name not in self.capabilities)
        if missing:
            listed = ", ".join(f"{n} ({cap.CAPABILITY_NAMES.get(n, n)})" for n in missing)
            raise CapabilityError(f"{self.profile.name} has no {listed}", missing=missing)

    def _get(self, name: str) -> Any:
        self.require(name)
        return self.capabilities[name]

    @property
    def drive_base(self) -> cap.DriveBase:
        """The wheels (:class:`~roboscript.capabilities.DriveBase`)."""
        return cast(cap.DriveBase, self._get(cap.DRIVE_BASE))

    @property
    def range(self) -> cap.RangeSensor:
        """The distance sensor."""
        return cast(cap.RangeSensor, self._get(cap.RANGE))

    @property
    def bumper(self) -> cap.Bumpers:
        """The bump switches."""
        return cast(cap.Bumpers, self._get(cap.BUMPER))

    @property
    def line(self) -> cap.LineSensors:
        """The line sensors."""
        return cast(cap.LineSensors, self._get(cap.LINE))

    @property
    def speaker(self) -> cap.Speaker:
        """The tone generator."""
        return cast(cap.Speaker, self._get(cap.SPEAKER))

    @property
    def display(self) -> cap.Display:
        """The text display."""
        return cast(cap.Display, self._get(cap.DISPLAY))

    @property
    def heading(self) -> cap.HeadingSensor:
        """The IMU heading."""
        return cast(cap.HeadingSensor, self._get(cap.HEADING))

    # ------------------------------------------------------------------------------ running

    def run_for(self, duration_s: float) -> None:
        """Tick the scheduler for ``duration_s`` seconds of its clock."""
        self.scheduler.run(until=lambda: False, max_duration_s=duration_s)

    def describe(self) -> str:
        """What is on the other end, as the robot reported it."""
        return str(self.driver.describe())

    # ------------------------------------------------------------------------------ safety

    def stop(self) -> None:
        """Stop every actuator now (sends the stop command).

        A Ctrl-C, SIGTERM or SIGHUP arriving meanwhile waits until the stop has gone out
        (:func:`roboscript.interrupts.deferred`), then is raised; nothing else is.
        """
        with deferred(), kept():
            self.driver.stop_all()

    def close(self) -> None:
        """Stop the robot, then close the port. Safe to call more than once.

        A Ctrl-C, SIGTERM or SIGHUP arriving meanwhile is raised once the port is closed,
        even when the port's own close swallows it (pyserial's ``socket://`` port ignores
        every exception while it closes).
        """
        if self._closed:
            return
        self._closed = True
        with kept():
            try:
                self.stop()
            finally:
                self.driver.link.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        try:
            self.close()
        except LinkError as error:
            logger.debug("closing after %s: %s", exc_type, error)


_MOST_HANDSHAKE_EXTENSIONS = 10.0
"""At most this many times the handshake's limit is given again for a busy machine: a bound
for a system that misreports, never reached by a machine that runs this process at all."""


def _wait_for_handshake(
    scheduler: Scheduler, until: Callable[[], bool], limit_s: float, *, on_wall_clock: bool
) -> bool:
    """Tick until ``until()`` is true or the robot has had ``limit_s`` seconds to answer.

    On the wall clock, time this process waited for a CPU (a busy machine) was not spent
    listening: the robot is given it again, so a robot that answers in time is never refused
    because its host was too busy to hear it. A simulated clock needs none of this.

    Returns:
        True if ``until()`` became true.
    """
    waited_from_s = cpu_wait_s()
    answered = scheduler.run(until=until, max_duration_s=limit_s)
    given_s = 0.0
    while not answered and on_wall_clock and given_s < _MOST_HANDSHAKE_EXTENSIONS * limit_s:
        owed_s = cpu_wait_s() - waited_from_s - given_s
        if owed_s < scheduler.period_s:
            break
        given_s += owed_s
        answered = scheduler.run(until=until, max_duration_s=owed_s)
    return answered


class _Opened:
    """What :meth:`Robot.connect` has opened so far, to stop and close if it gives up.

    Args:
        name: The port's name, for the log.
    """

    def __init__(self, name: str) -> None:
        self.name = name
        self.log: WireLog | None = None
        self.port: PortLike | None = None
        self.link: Link | None = None
        self.driver: Driver | None = None

    def abandon(self) -> None:
        """Stop the robot (if a driver got that far), then close the port and the wire log
        (:meth:`Link.close_port_and_log`, with or without their link).

        A signal meanwhile waits for the stop, as in :meth:`Robot.stop`, and is raised once
        everything is closed.
        """
        try:
            if self.driver is not None:
                with deferred():
                    self.driver.stop_all()
        finally:
            if self.link is not None:
                self.link.close()
            else:
                Link.close_port_and_log(self.port, self.log, self.name)


class _OtherProtocol:
    """Whether the bytes heard so far are another protocol's (checked as they grow)."""

    def __init__(self, protocol: str) -> None:
        self.protocol = protocol
        self._checked = 0

    def heard(self, data: bytearray) -> bool:
        if len(data) == self._checked:
            return False
        self._checked = len(data)

        return wrong_robot_hint(bytes(data), self.protocol) is not None


def _sim_url(robot: str, world: str, seed: int, start: tuple[float, float, float] | None) -> str:
    query: dict[str, str] = {"world": world, "seed": str(seed)}
    if start is not None:
        query.update(x=f"{start[0]:g}", y=f"{start[1]:g}", heading=f"{start[2]:g}")
    return f"sim://{robot}?{urllib.parse.urlencode(query)}"
