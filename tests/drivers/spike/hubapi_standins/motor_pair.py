"""Stand-in for the SPIKE App 3 ``motor_pair`` module."""

from __future__ import annotations

import motor
from standin_log import Pending, pending, record

PAIR_1 = 0
PAIR_2 = 1
PAIR_3 = 2


def pair(pair: int, left_motor: int, right_motor: int) -> None:
    record("motor_pair.pair", pair, left_motor, right_motor)


def unpair(pair: int) -> None:
    record("motor_pair.unpair", pair)


def move_tank(
    pair: int, left_velocity: int, right_velocity: int, *, acceleration: int = 1000
) -> None:
    record("motor_pair.move_tank", pair, left_velocity, right_velocity, acceleration=acceleration)


def move_tank_for_degrees(
    pair: int, degrees: int, left_velocity: int, right_velocity: int, **kwargs: int
) -> Pending:
    record("motor_pair.move_tank_for_degrees", pair, degrees, left_velocity, right_velocity)
    return pending("motor_pair.move_tank_for_degrees", motor.READY)


def stop(pair: int, *, stop: int = motor.BRAKE) -> None:
    record("motor_pair.stop", pair, stop=stop)
