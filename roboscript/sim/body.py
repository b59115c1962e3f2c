"""A simulated two-wheeled robot body: motors, encoders, sensors and collisions.

The body knows physics, not protocols: a simulated board (ASIP, SPIKE, ...) sets motor power
and reads encoders and sensors through it. Every random draw comes from one seeded
``random.Random`` in a fixed order, so a run is a pure function of its seed and inputs.

Model, per fixed step ``dt``:

* Motor power (-1..1) maps to a wheel speed target after a dead band; the wheel reaches it with
  a first-order lag (time constant ``motor_lag_s``) and saturates at ``max_wheel_speed_mm_s``.
* Encoders count wheel rotation, quantised to whole ticks. The ground moves each wheel by its
  rotation times ``1 - slip``, with slip drawn per step (seeded), so odometry drifts a little.
* The pose follows the exact arc of the two wheel travels. If the body circle would overlap a
  wall, the body stays where it was (it is stopped by the wall) and a collision is recorded
  when contact begins; the bump switch on that side reads pressed while in contact.
* The range sensor casts rays across its beam cone and reports the nearest echo with seeded
  noise; the IR line sensors read dark over floor tape; the IMU yaw drifts slowly.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

from roboscript.sim.geometry import circle_hits_segment, closest_point, heading_vector, ray_cast
from roboscript.sim.world import Pose, World

__all__ = ["Body", "BodySpec", "SimLog"]

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
        range_noise_mm: Standard deviation of range noise.
        range_offset_mm: Sensor distance ahead of the body centre.
        line_sensor_offsets_mm: (forward, right) positions of IR sensors, left to right.
        bumper_names: Bump switches, left then right.
        imu_drift_deg_s: Yaw drift rate of the simulated IMU.
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
    range_noise_mm: float = 3.0
    range_offset_mm: float = 90.0
    line_sensor_offsets_mm: tuple[tuple[float, float], ...] = (
        (80.0, -15.0),
        (80.0, 0.0),
        (80.0, 15.0),
    )
    bumper_names: tuple[str, ...] = ("left", "right")
    imu_drift_deg_s: float = 0.02
    side_range_offset_mm: float = 80.0

    @property
    def mm_per_tick(self) -> float:
        """Wheel travel per encoder tick, millimetres."""
        return math.pi * self.wheel_diameter_mm / self.ticks_per_rev


@dataclass
class SimLog:
    """What happened during a simulated run, for reports and grading.

    Attributes:
        tones: (time s, frequency Hz, duration s) of each tone started.
        collisions: Time (s) each collision began.
        path: (time s, x mm, y mm, heading deg) samples.
        distance_travelled_mm: Path length of the body centre.
        display: The text on the display now.
    """

    tones: list[tuple[float, float, float]] = field(default_factory=list)
    collisions: list[float] = field(default_factory=list)
    path: list[tuple[float, float, float, float]] = field(default_factory=list)
    distance_travelled_mm: float = 0.0
    display: str = ""


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
            self.in_contact = False
            self.contact_side = None
            self.heading_deg = new_heading
            return True
        # A body held against a wall re-touches it step after step (it stops up to one step
        # short); only a contact after a quarter second clear of walls is a new collision.
        if not self.in_contact and self.time_s - self._last_contact_s > _NEW_CONTACT_S:
            self.log.collisions.append(self.time_s)
        self._last_contact_s = self.time_s
        self.in_contact = True
        self.contact_side = hit
        return False

    def _wall_contact(self, x_mm: float, y_mm: float) -> str | None:
        radius = self.spec.body_radius_mm
        for seg in self.world.walls:
            if circle_hits_segment(x_mm, y_mm, radius, seg):
                qx, qy = closest_point(x_mm, y_mm, seg)
                bearing = math.degrees(math.atan2(qx - x_mm, qy - y_mm)) - self.heading_deg
                bearing = (bearing + 180.0) % 360.0 - 180.0
                return "left" if bearing < 0 else "right"
        return None

    # ------------------------------------------------------------------------------ sensors

    def range_mm(self) -> float | None:
        """Nearest echo across the beam cone with noise, or ``None`` for no echo."""
        spec = self.spec
        fx, fy = heading_vector(self.heading_deg)
        ox = self.x_mm + fx * spec.range_offset_mm
        oy = self.y_mm + fy * spec.range_offset_mm
        nearest: float | None = None
        half = spec.range_cone_deg / 2.0
        for offset in (-half, 0.0, half):
            dx, dy = heading_vector(self.heading_deg + offset)
            hit = ray_cast(ox, oy, dx, dy, list(self.world.walls), spec.range_max_mm)
            if hit is not None and (nearest is None or hit < nearest):
                nearest = hit
        if nearest is None:
            return None
        noisy = nearest + self.rng.gauss(0.0, spec.range_noise_mm)
        return max(0.0, noisy) if noisy <= spec.range_max_mm else None

    def side_range_mm(self) -> float | None:
        """The side-facing range sensor: one ray square to the right, with noise.

        It sits on the body's edge, so readings are the gap between the robot's side and the
        wall; ``None`` when nothing is within :attr:`BodySpec.range_max_mm`.
        """
        spec = self.spec
        rx, ry = heading_vector(self.heading_deg + 90.0)
        ox = self.x_mm + rx * spec.side_range_offset_mm
        oy = self.y_mm + ry * spec.side_range_offset_mm
        hit = ray_cast(ox, oy, rx, ry, list(self.world.walls), spec.range_max_mm)
        if hit is None:
            return None
        noisy = hit + self.rng.gauss(0.0, spec.range_noise_mm)
        return max(0.0, noisy) if noisy <= spec.range_max_mm else None

    def bumpers_pressed(self) -> tuple[bool, ...]:
        """Each bump switch (in :attr:`BodySpec.bumper_names` order): pressed or not."""
        return tuple(
            self.in_contact and self.contact_side == name for name in self.spec.bumper_names
        )

    def line_readings(self) -> tuple[int, ...]:
        """IR reflectance 0-1023 of each line sensor (dark tape reads high)."""
        fx, fy = heading_vector(self.heading_deg)
        rx, ry = fy, -fx  # unit vector to the robot's right
        readings = []
        for forward, right in self.spec.line_sensor_offsets_mm:
            px = self.x_mm + fx * forward + rx * right
            py = self.y_mm + fy * forward + ry * right
            base = 850.0 if self.world.on_tape(px, py) else 90.0
            readings.append(int(max(0.0, min(1023.0, base + self.rng.gauss(0.0, 12.0)))))
        return tuple(readings)

    def imu_heading_deg(self) -> float:
        """IMU yaw: the true heading plus slow drift, degrees clockwise."""
        return (self.heading_deg + self._imu_bias_deg) % 360.0
