"""``motor``: turn a motor that is not a wheel (an arm or a claw on a SPIKE hub's port C).

Three forms, by the parameters given::

    motor: {port: C, angle: 90 deg}                      # turn by an angle, then done
    motor: {port: C, speed: 180 deg/s, duration: 2 s}    # run for a time, then brake
    motor: {port: C, direction: counterclockwise}        # run until the state is left

Angles are the motor's own: positive turns it clockwise seen from its face, as the hub
counts; a negative angle, or ``direction: counterclockwise``, turns it the other way. The
motor brakes whenever the state is left.
"""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.actions.base import FROM_INIT, Action, ActionContext, Param, Result

__all__ = ["Motor"]

_PORTS = ("A", "B", "C", "D", "E", "F")


class Motor(Action):
    """Turn one motor by an angle, or at a speed for a time (see the module docstring).

    Args:
        port: The motor's port letter (the robot profile lists which ports have motors).
        angle_deg: Turn by this angle, degrees; negative turns the other way. ``None``: run.
        speed_deg_s: Motor speed, degrees per second (positive).
        direction: ``"clockwise"`` or ``"counterclockwise"`` (reverses the angle or run).
        duration_s: Without an angle, brake after this long; ``None`` runs until the state
            is left.

    Outcomes: ``done`` (the angle reached, or the duration up); ``failed`` ("stalled") if the
    motor stalls on its way; ``failed`` ("not supported") if the robot has no motor on
    ``port``.
    """

    name = "motor"
    summary = "Turn a motor that is not a wheel (an arm, a claw) by an angle or for a time."
    params = (
        Param("port", "port", "choice", "the motor's port", choices=_PORTS),
        Param("angle", "angle_deg", "angle", "turn by this angle (negative: back)", FROM_INIT),
        Param("speed", "speed_deg_s", "turn_rate", "motor speed", FROM_INIT),
        Param("duration", "duration_s", "time", "with no angle: run this long", FROM_INIT),
        Param(
            "direction",
            "direction",
            "choice",
            "which way the motor turns",
            FROM_INIT,
            ("clockwise", "counterclockwise"),
        ),
    )
    requires = frozenset({cap.MOTORS})
    bounded_by = ("angle", "duration")

    def __init__(
        self,
        port: str,
        angle_deg: float | None = None,
        speed_deg_s: float = 360.0,
        duration_s: float | None = None,
        direction: str = "clockwise",
    ) -> None:
        if port.upper() not in _PORTS:
            raise ValueError(f"port must be one of {', '.join(_PORTS)}")
        if angle_deg is not None and duration_s is not None:
            raise ValueError("give a motor an angle or a duration, not both")
        if speed_deg_s <= 0:
            raise ValueError("a motor needs a positive speed (turn it back with a direction)")
        if direction not in ("clockwise", "counterclockwise"):
            raise ValueError("direction must be 'clockwise' or 'counterclockwise'")
        if duration_s is not None and duration_s < 0:
            raise ValueError("a motor's duration must not be negative")
        self.port = port.upper()
        self.angle_deg = angle_deg
        self.speed_deg_s = speed_deg_s
        self.duration_s = duration_s
        self.direction = direction
        self._sign = -1.0 if direction == "counterclockwise" else 1.0
        self._start_s = 0.0
        self._move: int | None = None
        self._running = False

    def start(self, ctx: ActionContext) -> None:
        self._start_s = ctx.now_s
        motors: cap.Motors = ctx.get(cap.MOTORS)
        if self.port not in motors.ports:
            return  # update() says why
        if self.angle_deg is not None:
            angle = self._sign * self.angle_deg
            self._move = motors.run_for_degrees(self.port, angle, self.speed_deg_s)
        else:
            motors.run(self.port, self._sign * self.speed_deg_s)
        self._running = True

    def update(self, ctx: ActionContext) -> Result | None:
        motors: cap.Motors = ctx.get(cap.MOTORS)
        if self.port not in motors.ports:
            have = ", ".join(motors.ports) or "none"
            return Result.failed(f"not supported: no motor on port {self.port} (motors: {have})")
        if self._move is not None:
            result = motors.move_result(self._move)
            if result is None:
                self.feedback = f"motor {self.port} turning {self.angle_deg:g} deg"
                return None
            self._running = False
            if result == "done":
                return Result.done()
            return Result.failed("stalled" if result == "stalled" else f"motor move {result}")
        if self.duration_s is not None and ctx.has_passed(self._start_s, self.duration_s):
            self._brake(motors)
            return Result.done()
        return None

    def stop(self, ctx: ActionContext) -> None:
        if self._running:
            self._brake(ctx.get(cap.MOTORS))

    def _brake(self, motors: cap.Motors) -> None:
        motors.stop(self.port)
        self._running = False
