"""Stand-in for the SPIKE App 3 ``motor`` module (constants with made-up values)."""

from __future__ import annotations

from standin_log import Pending, pending, record

READY = 10
RUNNING = 11
STALLED = 12
CANCELED = 13
ERROR = 14
DISCONNECTED = 15

COAST = 20
BRAKE = 21
HOLD = 22


def set_duty_cycle(port: int, pwm: int) -> None:
    record("motor.set_duty_cycle", port, pwm)


def stop(port: int, *, stop: int = BRAKE) -> None:
    record("motor.stop", port, stop=stop)


def run(port: int, velocity: int) -> None:
    record("motor.run", port, velocity)


def run_for_degrees(port: int, degrees: int, velocity: int, **kwargs: int) -> Pending:
    record("motor.run_for_degrees", port, degrees, velocity)
    return pending("motor.run_for_degrees", READY)
