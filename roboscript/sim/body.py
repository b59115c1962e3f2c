"""A simulated two-wheeled robot body: motors, encoders, sensors and collisions.

The body knows physics, not protocols: a simulated board (ASIP, SPIKE, ...) sets motor power
and reads encoders and sensors through it. Every random draw comes from one seeded
``random.Random`` in a fixed order, so a run is a pure function of its seed and inputs: the
sensors draw from their own streams, split off that source when the body is built, so reading a
sensor more or less often never changes the wheel slip.

Model, per fixed step ``dt``:

* Motor power (-1..1) maps to a wheel speed target after a dead band; the wheel reaches it with
  a first-order lag (time constant ``motor_lag_s``) and saturates at ``max_wheel_speed_mm_s``.
* Encoders count wheel rotation, quantised to whole ticks. The ground moves each wheel by its
  rotation times ``1 - slip``, with slip drawn per step (seeded), so odometry drifts a little.
* The pose follows the exact arc of the two wheel travels. If the body circle would overlap a
  wall, the body stays where it was (it is stopped by the wall) and a collision is recorded
  when contact begins; the bump switch on that side reads pressed while in contact. Contact
  ends once the body is ``contact_release_mm`` clear of every wall, so a robot that keeps
  pushing (and creeps the last millimetre) is one collision, not one per step.
* The range sensors are HC-SR04-like: a cone of rays, nearest echo, no echo from a wall met at
  a grazing angle, at most one measurement per 60 ms (see :mod:`roboscript.sim.sensors`). The
  IR line sensors read the part of their spot covered by tape, so they change smoothly across a
  tape edge. The IMU yaw drifts slowly.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import TypeVar

from roboscript.angles import wrap_deg
from roboscript.sim.floor import FloorReader, FloorReading
from roboscript.sim.geometry import (
    NearbySegments,
    circle_hits_segment,
    closest_point,
    heading_vector,
    segment_distance,
)
from roboscript.sim.sensors import Sonar, SonarSpec, TapeReader
from roboscript.sim.world import Pose, World

__all__ = ["Body", "BodySpec", "Contact", "SimLog"]

_NEW_CONTACT_S = 0.25


@dataclass(frozen=True)
class BodySpec:
    """Physical parameters of a simulated robot (defaults: the MIRTO).

    Attributes:
        wheel_diameter_mm: Wheel diameter.
        track_mm: Distance between the wheels.
        ticks_per_rev: Encoder ticks per wheel revolution.
        body_radius_mm: Radius of the round body used for collisions.
        max_wheel_speed_mm_s: Wheel speed at full power.
        motor_lag_s: First-order time constant of the motors.
        dead_band: Power fraction below which a wheel does not turn.
        slip_sd: Standard deviation of per-step wheel slip (fraction of travel).
        range_max_mm: Farthest echo the range sensor reports.
        range_cone_deg: Full width of the range sensor's beam.
        range_rays: Rays cast across the beam.
        range_incidence_max_deg: Largest angle from a wall's normal that still echoes.
        range_period_s: Shortest time between two range measurements.
        range_noise_mm: Standard deviation of range noise.
        range_offset_mm: Sensor distance ahead of the body centre.
        line_sensor_offsets_mm: (forward, right) positions of IR sensors, left to right.
        line_spot_mm: Diameter of the patch of floor each IR sensor sees.
        bumper_names: Bump switches, left then right.
        imu_drift_deg_s: Yaw drift rate of the simulated IMU.
        contact_release_mm: Gap to every wall at which a contact ends (bumper travel).
        side_range_offset_mm: Side range sensor's distance right of the body centre.
    """

    wheel_diameter_mm: float = 64.0
    track_mm: float = 162.0
    ticks_per_rev: int = 1632
    body_radius_mm: float = 100.0
    max_wheel_speed_mm_s: float = 400.0
    motor_lag_s: float = 0.08
    dead_band: float = 0.04
    slip_sd: float = 0.01
    range_max_mm: float = 1000.0
    range_cone_deg: float = 15.0
    range_rays: int = 7
    range_incidence_max_deg: float = 22.5
    range_period_s: float = 0.06
    range_noise_mm: float = 3.0
    range_offset_mm: float = 90.0
    line_sensor_offsets_mm: tuple[tuple[float, float], ...] = (
        (80.0, -15.0),
        (80.0, 0.0),
        (80.0, 15.0),
    )
    line_spot_mm: float = 8.0
    bumper_names: tuple[str, ...] = ("left", "right")
    imu_drift_deg_s: float = 0.02
    contact_release_mm: float = 5.0
    side_range_offset_mm: float = 80.0

    @property
    def mm_per_tick(self) -> float:
        """Wheel travel per encoder tick, millimetres."""
        return math.pi * self.wheel_diameter_mm / self.ticks_per_rev


@dataclass
class Contact:
    """One collision: the body touching a wall.

    Attributes:
        start_s: Simulated time the contact began.
        x_mm: Body centre when it began, east.
        y_mm: Body centre when it began, north.
        side: Bump switch that pressed (``left`` or ``right``).
        end_s: Time it ended, or ``None`` while still touching.
    """

    start_s: float
    x_mm: float
    y_mm: float
    side: str
    end_s: float | None = None

    def duration_s(self, now_s: float) -> float:
        """How long the contact lasted (up to ``now_s`` if it has not ended)."""
        return (now_s if self.end_s is None else self.end_s) - self.start_s


MAX_TONES = 1000
"""Most tones a run's log keeps (the first ones); later ones are only counted."""
MAX_CONTACTS = 1000
"""Most collisions a run's log keeps (the first ones); later ones are only counted."""

_T = TypeVar("_T")


class FirstOf(list[_T]):
    """A list that keeps its first ``cap`` items and counts the ones after in :attr:`more`.

    A run that goes on for hours (a mission that never ends, stopped by ``--max-time``) then
    keeps a log of bounded size; reports say "… N more".

    Args:
        cap: How many items to keep.

    Attributes:
        more: Items appended after the list was full (not kept).
    """

    def __init__(self, cap: int) -> None:
        super().__init__()
        self.cap = cap
        self.more = 0

    def append(self, item: _T, /) -> None:
        """Keep ``item`` if there is room, else count it."""
        if len(self) < self.cap:
            super().append(item)
        else:
            self.more += 1

    @property
    def total(self) -> int:
        """Every item appended, kept or not."""
        return len(self) + self.more


@dataclass
class SimLog:
    """What happened during a simulated run, for reports and grading.

    Attributes:
        tones: (time s, frequency Hz, duration s) of each tone started: the first
            :data:`MAX_TONES`; ``tones.more`` counts the rest.
        contacts: Each collision with where it began and how long it lasted: the first
            :data:`MAX_CONTACTS`; ``contacts.more`` counts the rest.
        path: (time s, x mm, y mm, heading deg) samples (bounded by the simulation, see
            :data:`~roboscript.sim.simulation.MAX_PATH_SAMPLES`).
        distance_travelled_mm: Path length of the body centre.
        display: The text on the display now.
    """

    tones: FirstOf[tuple[float, float, float]] = field(default_factory=lambda: FirstOf(MAX_TONES))
    contacts: FirstOf[Contact] = field(default_factory=lambda: FirstOf(MAX_CONTACTS))
    path: list[tuple[float, float, float, float]] = field(default_factory=list)
    distance_travelled_mm: float = 0.0
    display: str = ""

    @property
    def collisions(self) -> list[float]:
        """Time (s) each collision began."""
        return [contact.start_s for contact in self.contacts]

    def forget_events(self) -> None:
        """Start the tones and collisions afresh (the mission starts now)."""
        self.tones = FirstOf(MAX_TONES)
        self.contacts = FirstOf(MAX_CONTACTS)


class Body:
    """The state and physics of one simulated robot in a world.

    Args:
        world: The static world.
        spec: Physical parameters.
        rng: The run's seeded random source.
        start: Start pose (default: the world's).
    """

    def __init__(
        self, world: World, spec: BodySpec, rng: random.Random, start: Pose | None = None
    ) -> None:
        self.world = world
        self.spec = spec
        self.rng = rng
        pose = start or world.start
        self.x_mm = pose.x_mm
        self.y_mm = pose.y_mm
        self.heading_deg = pose.heading_deg
        self.time_s = 0.0
        self.power = [0.0, 0.0]
        self.wheel_speed_mm_s = [0.0, 0.0]
        self._ticks_exact = [0.0, 0.0]
        self.ticks = [0, 0]
        self.in_contact = False
        self._last_contact_s = -math.inf
        self.contact_side: str | None = None
        self._imu_bias_deg = 0.0
        self.log = SimLog()
        self._contact: Contact | None = None
        # Only walls near the body can stop it; refreshed every 100 mm of travel.
        self._near_walls = NearbySegments(
            world.walls, spec.body_radius_mm + spec.contact_release_mm, 100.0
        )
        # Split in a fixed order: one stream per sensor (see the module docstring).
        self._front_sonar = Sonar(
            self._sonar_spec(spec.range_offset_mm, 0.0, 0.0), world.walls, _split(rng)
        )
        self._side_sonar = Sonar(
            self._sonar_spec(0.0, spec.side_range_offset_mm, 90.0), world.walls, _split(rng)
        )
        self._line_rng = _split(rng)
        self._tape = TapeReader(world.lines, spec.line_spot_mm)
        self._floor: FloorReader | None = None  # built when a colour sensor first looks

    def _sonar_spec(self, forward_mm: float, right_mm: float, bearing_deg: float) -> SonarSpec:
        spec = self.spec
        return SonarSpec(
            forward_mm=forward_mm,
            right_mm=right_mm,
            bearing_deg=bearing_deg,
            cone_deg=spec.range_cone_deg,
            rays=spec.range_rays,
            max_range_mm=spec.range_max_mm,
            incidence_max_deg=spec.range_incidence_max_deg,
            noise_mm=spec.range_noise_mm,
            period_s=spec.range_period_s,
        )

    @property
    def pose(self) -> Pose:
        """The current pose."""
        return Pose(self.x_mm, self.y_mm, self.heading_deg)

    def set_power(self, left: float, right: float) -> None:
        """Set motor power, each -1 (full reverse) to 1 (full forward)."""
        self.power[0] = max(-1.0, min(1.0, left))
        self.power[1] = max(-1.0, min(1.0, right))

    def step(self, dt_s: float) -> None:
        """Advance the physics by ``dt_s`` seconds."""
        spec = self.spec
        alpha = 1.0 - math.exp(-dt_s / spec.motor_lag_s)
        travel = [0.0, 0.0]
        for i in (0, 1):
            power = self.power[i]
            target = 0.0 if abs(power) < spec.dead_band else power * spec.max_wheel_speed_mm_s
            self.wheel_speed_mm_s[i] += (target - self.wheel_speed_mm_s[i]) * alpha
            rolled = self.wheel_speed_mm_s[i] * dt_s
            self._ticks_exact[i] += rolled / spec.mm_per_tick
            self.ticks[i] = int(self._ticks_exact[i])
            slip = self.rng.gauss(0.0, spec.slip_sd) if rolled else 0.0
            travel[i] = rolled * (1.0 - abs(slip))
        self.time_s += dt_s
        self._imu_bias_deg += spec.imu_drift_deg_s * dt_s
        if not self._move(travel[0], travel[1]):
            # Pushing into a wall stalls the wheels: the encoders stop counting.
            for i in (0, 1):
                self._ticks_exact[i] -= self.wheel_speed_mm_s[i] * dt_s / spec.mm_per_tick
                self.ticks[i] = int(self._ticks_exact[i])
                self.wheel_speed_mm_s[i] = 0.0

    def displace(self, forward_mm: float, turn_deg: float) -> bool:
        """Move the body directly, for robots that walk instead of rolling.

        The move follows the same arc as wheels would (``forward_mm`` along the heading,
        negative backward; ``turn_deg`` clockwise, negative counterclockwise) and meets walls
        the same way: a blocked move leaves the body where it was and records a collision.

        Returns:
            False if a wall blocked the move.
        """
        half_turn_mm = math.radians(turn_deg) * self.spec.track_mm / 2.0
        return self._move(forward_mm + half_turn_mm, forward_mm - half_turn_mm)

    def _move(self, left_mm: float, right_mm: float) -> bool:
        """Move by the wheel travels; False if a wall blocked the move."""
        if left_mm == 0.0 and right_mm == 0.0:
            return True
        distance = (left_mm + right_mm) / 2.0
        turn_rad = (left_mm - right_mm) / self.spec.track_mm  # clockwise positive
        heading_rad = math.radians(self.heading_deg)
        if abs(turn_rad) < 1e-9:
            dx = distance * math.sin(heading_rad)
            dy = distance * math.cos(heading_rad)
        else:
            radius = distance / turn_rad
            dx = radius * (math.cos(heading_rad) - math.cos(heading_rad + turn_rad))
            dy = radius * (math.sin(heading_rad + turn_rad) - math.sin(heading_rad))
        new_x = self.x_mm + dx
        new_y = self.y_mm + dy
        new_heading = (self.heading_deg + math.degrees(turn_rad)) % 360.0
        hit = self._wall_contact(new_x, new_y)
        if hit is None:
            self.x_mm, self.y_mm = new_x, new_y
            self.log.distance_travelled_mm += math.hypot(dx, dy)
            self.heading_deg = new_heading
            # The bumper stays pressed until the body is clear of the wall by its travel, so
            # creeping the last millimetre against a wall does not flicker it.
            if self.in_contact and self._clear_of_walls():
                self.in_contact = False
                self.contact_side = None
                if self._contact is not None:
                    self._contact.end_s = self.time_s
            return True
        # A body held against a wall re-touches it step after step (it stops up to one step
        # short); only a contact after a quarter second clear of walls is a new collision.
        if not self.in_contact and self.time_s - self._last_contact_s > _NEW_CONTACT_S:
            # Held here, not as contacts[-1]: once the log is full it keeps older contacts.
            self._contact = Contact(self.time_s, self.x_mm, self.y_mm, hit)
            self.log.contacts.append(self._contact)
        elif self._contact is not None:
            self._contact.end_s = None  # the same contact goes on
        self._last_contact_s = self.time_s
        self.in_contact = True
        self.contact_side = hit
        return False

    def _clear_of_walls(self) -> bool:
        gap = self.spec.body_radius_mm + self.spec.contact_release_mm
        return all(
            segment_distance(self.x_mm, self.y_mm, seg) >= gap
            for seg in self._near_walls.around(self.x_mm, self.y_mm)
        )

    def _wall_contact(self, x_mm: float, y_mm: float) -> str | None:
        radius = self.spec.body_radius_mm
        for seg in self._near_walls.around(x_mm, y_mm):
            if circle_hits_segment(x_mm, y_mm, radius, seg):
                qx, qy = closest_point(x_mm, y_mm, seg)
                bearing = math.degrees(math.atan2(qx - x_mm, qy - y_mm)) - self.heading_deg
                bearing = wrap_deg(bearing)
                return "left" if bearing < 0 else "right"
        return None

    # ------------------------------------------------------------------------------ sensors

    def range_mm(self) -> float | None:
        """The forward range sensor: millimetres from the sensor, or ``None`` for no echo.

        A new measurement at most every :attr:`BodySpec.range_period_s`; the last one between.
        """
        return self._front_sonar.read(self.x_mm, self.y_mm, self.heading_deg, self.time_s)

    def side_range_mm(self) -> float | None:
        """The side-facing range sensor, square to the right (same model as the front one).

        It sits on the body's edge, so readings are the gap between the robot's side and the
        wall; ``None`` when nothing echoes within :attr:`BodySpec.range_max_mm`.
        """
        return self._side_sonar.read(self.x_mm, self.y_mm, self.heading_deg, self.time_s)

    def last_ranges_mm(self) -> tuple[float | None, float | None]:
        """The front and side range sensors' last measurements, without measuring again.

        For recording a run: a new measurement would draw from the sensors' random streams.
        """
        return self._front_sonar.last_mm, self._side_sonar.last_mm

    def bumpers_pressed(self) -> tuple[bool, ...]:
        """Each bump switch (in :attr:`BodySpec.bumper_names` order): pressed or not."""
        return tuple(
            self.in_contact and self.contact_side == name for name in self.spec.bumper_names
        )

    def line_readings(self) -> tuple[int, ...]:
        """IR reflectance 0-1023 of each line sensor, left to right.

        Bare floor reads about 90 and tape about 850; in between in proportion to the part of
        the sensor's spot on tape, plus seeded noise.
        """
        fx, fy = heading_vector(self.heading_deg)
        rx, ry = fy, -fx  # unit vector to the robot's right
        readings = []
        for forward, right in self.spec.line_sensor_offsets_mm:
            px = self.x_mm + fx * forward + rx * right
            py = self.y_mm + fy * forward + ry * right
            value = 90.0 + 760.0 * self._tape.coverage(px, py)
            readings.append(int(max(0.0, min(1023.0, value + self._line_rng.gauss(0.0, 12.0)))))
        return tuple(readings)

    def line_levels(self) -> tuple[int, ...]:
        """The line sensors' readings without their noise (no random draw), left to right.

        For recording a run: :meth:`line_readings` draws noise, and an extra draw would change
        what the mission reads next.
        """
        fx, fy = heading_vector(self.heading_deg)
        rx, ry = fy, -fx
        return tuple(
            int(
                90.0
                + 760.0
                * self._tape.coverage(self.x_mm + fx * f + rx * r, self.y_mm + fy * f + ry * r)
            )
            for f, r in self.spec.line_sensor_offsets_mm
        )

    def imu_heading_deg(self) -> float:
        """IMU yaw: the true heading plus slow drift, degrees clockwise."""
        return (self.heading_deg + self._imu_bias_deg) % 360.0

    def floor_reading(self, forward_mm: float, right_mm: float = 0.0) -> FloorReading:
        """What a colour sensor looking down at ``(forward_mm, right_mm)`` from the body's
        centre sees (:mod:`roboscript.sim.floor`; no noise, so no random draw)."""
        if self._floor is None:
            self._floor = FloorReader(self.world, self.spec.line_spot_mm)
        fx, fy = heading_vector(self.heading_deg)
        rx, ry = fy, -fx  # unit vector to the robot's right
        x = self.x_mm + fx * forward_mm + rx * right_mm
        y = self.y_mm + fy * forward_mm + ry * right_mm
        return self._floor.read(x, y)


def _split(rng: random.Random) -> random.Random:
    """A new random stream seeded from ``rng`` (one draw from it)."""
    return random.Random(rng.getrandbits(64))
