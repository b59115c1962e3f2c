"""A simulated robot: a world, a body and a device, stepped at a fixed physics rate.

The simulation is a *Tickable*: in-process (``sim://``) it runs in lockstep with the mission
scheduler, advancing its physics in fixed steps up to the scheduler's time on every tick; in
``roboscript sim`` it is ticked from the wall clock. Bytes to and from the device go through
:meth:`Simulation.write` and :meth:`Simulation.read`, the way a serial line would carry them.
"""

from __future__ import annotations

import dataclasses
import random
from collections.abc import Callable, Mapping

from roboscript.angles import wrap_deg
from roboscript.drivers import protocol_unit
from roboscript.profiles import RobotProfile, get_profile
from roboscript.sim.body import Body, BodySpec, SimLog
from roboscript.sim.device import SimDevice
from roboscript.sim.world import Pose, World, load_world

__all__ = ["Simulation", "body_spec_for", "build_device", "make_simulation"]

PHYSICS_DT_S = 0.005
PATH_INTERVAL_S = 0.1
"""Time between path samples while the path has room, seconds."""
MAX_PATH_SAMPLES = 8192
"""Most path samples a run keeps. At ``PATH_INTERVAL_S`` that is 13.6 simulated minutes at
full resolution, longer than any graded run or test, so their paths (and every expectation
read from them) are exactly as sampled. A longer run (a mission that never ends, stopped by
``--max-time``) drops every other sample when the path is full and samples half as often from
then on, so memory and ``run --json`` stay flat however long it goes; the samples taken with
:meth:`Simulation.sample_path` (the mission's start) are always kept."""


class Simulation:
    """A world, a body and a device on simulated time.

    Args:
        world: The static world.
        profile: The robot being simulated.
        seed: Seed of every random draw in the run.
        start: Start pose (default: the world's).
        physics_dt_s: Fixed physics step, seconds.
    """

    def __init__(
        self,
        world: World,
        profile: RobotProfile,
        seed: int = 1,
        *,
        start: Pose | None = None,
        physics_dt_s: float = PHYSICS_DT_S,
    ) -> None:
        self.world = world
        self.profile = profile
        self.seed = seed
        self.rng = random.Random(seed)
        self.body = Body(world, body_spec_for(profile), self.rng, start)
        self.device: SimDevice = build_device(profile, self.body)
        self.physics_dt_s = physics_dt_s
        self.time_s = 0.0
        self._steps = 0
        self._to_host = bytearray()
        self._next_path_s = 0.0
        self.path_interval_s = PATH_INTERVAL_S
        """Time between path samples now, seconds (doubles each time the path is thinned)."""
        self._pinned: set[float] = set()
        self._record_path()

    @property
    def log(self) -> SimLog:
        """What has happened so far (tones, collisions, path)."""
        return self.body.log

    def connect(self) -> None:
        """A host opened the line: the device greets it."""
        self.device.connect(self.time_s)
        self._collect()

    def tick(self, now_s: float, dt_s: float) -> None:
        """Advance physics and firmware in fixed steps up to ``now_s``."""
        del dt_s  # the simulation keeps its own fixed step
        step = self.physics_dt_s
        while (self._steps + 1) * step <= now_s + 1e-9:
            self._steps += 1
            self.time_s = self._steps * step
            self.body.step(step)
            self.device.step(self.time_s)
            if self.time_s >= self._next_path_s - 1e-9:
                self._record_path()
        self._collect()

    def write(self, data: bytes) -> None:
        """Bytes from the host reach the device."""
        self.device.receive(data, self.time_s)
        self._collect()

    def read(self, size: int) -> bytes:
        """Take up to ``size`` bytes the device has sent."""
        data = bytes(self._to_host[:size])
        del self._to_host[:size]
        return data

    @property
    def input_pending(self) -> int:
        """Bytes from the host the device holds as an unfinished message."""
        return self.device.pending_input_bytes()

    @property
    def in_waiting(self) -> int:
        """Bytes waiting for the host."""
        return len(self._to_host)

    def stop_all(self) -> None:
        """Cut the device's actuators (power loss)."""
        self.device.stop_all()

    def _collect(self) -> None:
        self._to_host += self.device.read_output()

    def path_since(self, start_s: float) -> list[tuple[float, float, float, float]]:
        """Path samples from ``start_s`` on, timed from it: ``(t s, x mm, y mm, heading deg)``.

        ``run --json`` and the grader both report these, so a graded run is the same run.
        """
        start = start_s - 1e-9
        return [(round(t - start_s, 3), x, y, h) for t, x, y, h in self.log.path if t >= start]

    def tones_since(self, start_s: float) -> list[tuple[float, float, float]]:
        """Every tone started from ``start_s`` on: ``(t s from start_s, Hz, duration s)``."""
        start = start_s - 1e-9
        return [(round(t - start_s, 3), f, round(d, 3)) for t, f, d in self.log.tones if t >= start]

    def final_pose(self) -> tuple[float, float, float]:
        """The body's pose now: ``(x mm, y mm, heading deg)``, rounded; heading in [-180, 180)."""
        body = self.body
        return round(body.x_mm, 1), round(body.y_mm, 1), round(wrap_deg(body.heading_deg), 1)

    def start_mission(self) -> None:
        """The mission starts now: the path starts here, and the tones and collisions logged
        before are forgotten, since only what the robot does after its start counts (a mission
        cannot earn a beep, or fill the log, before it has started)."""
        self.sample_path()
        self.log.forget_events()

    def sample_path(self) -> None:
        """Record a path sample now (the grader and ``--json`` start the path here).

        The sample is kept however long the run goes (see :data:`MAX_PATH_SAMPLES`).
        """
        self._record_path()
        self._pinned.add(self.log.path[-1][0])

    def _record_path(self) -> None:
        body = self.body
        path = self.log.path
        path.append(
            (
                round(self.time_s, 3),
                round(body.x_mm, 1),
                round(body.y_mm, 1),
                round(wrap_deg(body.heading_deg), 2),  # the one convention: [-180, 180)
            )
        )
        if len(path) > MAX_PATH_SAMPLES:
            self._thin_path()
        self._next_path_s = self.time_s + self.path_interval_s

    def _thin_path(self) -> None:
        """Drop every other sample (keeping the first, the last and the pinned ones) and
        sample half as often from now on."""
        path = self.log.path
        last = len(path) - 1
        path[:] = [
            sample
            for index, sample in enumerate(path)
            if index % 2 == 0 or index == last or sample[0] in self._pinned
        ]
        self.path_interval_s *= 2


def body_spec_for(profile: RobotProfile) -> BodySpec:
    """The simulated body of a robot profile."""
    return BodySpec(
        wheel_diameter_mm=profile.wheel_diameter_mm,
        track_mm=profile.track_mm,
        ticks_per_rev=profile.ticks_per_rev,
        body_radius_mm=profile.body_radius_mm,
    )


def build_device(profile: RobotProfile, body: Body) -> SimDevice:
    """The simulated controller for ``profile``'s protocol, on ``body``.

    The device factory comes from the protocol's unit
    (:class:`~roboscript.drivers.unit.ProtocolUnit`), which imports the protocol's device
    module only, never its host driver.

    Raises:
        NotImplementedError: No protocol unit has that name.
        ProfileError: The profile's options are invalid.
    """
    try:
        unit = protocol_unit(profile.protocol)
    except NotImplementedError:
        raise NotImplementedError(f"the simulator has no {profile.protocol} device yet") from None
    factory: Callable[[RobotProfile], Callable[[Body], SimDevice]] = unit.device_factory()
    return factory(profile)(body)


def make_simulation(
    robot: str = "mirto",
    world: str = "empty",
    seed: int = 1,
    start: Pose | None = None,
    *,
    options: Mapping[str, object] | None = None,
) -> Simulation:
    """Build a simulation from a profile name and a world name or path; ``options`` change
    the profile's options for the simulated board (``{"reset_on_connect": True}``).

    Raises:
        ProfileError: The robot's family has no such option, or a bad value.
    """
    profile = get_profile(robot)
    if options:
        profile = dataclasses.replace(profile, options={**profile.options, **options})
    return Simulation(load_world(world), profile, seed, start=start)
