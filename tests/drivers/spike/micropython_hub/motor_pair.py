# Stand-in for SPIKE App 3's motor_pair module (LEGO's documentation).
from calls import Pending, record
from motor import BRAKE, READY

PAIR_1 = 0
PAIR_2 = 1
PAIR_3 = 2


def pair(pair, left_motor, right_motor):
    record("motor_pair.pair", pair, left_motor, right_motor)


def unpair(pair):
    record("motor_pair.unpair", pair)


def move_tank(pair, left_velocity, right_velocity, *, acceleration=1000):
    record("motor_pair.move_tank", pair, left_velocity, right_velocity)


def move_tank_for_degrees(
    pair,
    degrees,
    left_velocity,
    right_velocity,
    *,
    stop=BRAKE,
    acceleration=1000,
    deceleration=1000,
):
    record("motor_pair.move_tank_for_degrees", pair, degrees, left_velocity, right_velocity)
    fastest = max(abs(left_velocity), abs(right_velocity), 1)
    return Pending(abs(degrees) * 1000 // fastest, READY)


def stop(pair, *, stop=BRAKE):
    record("motor_pair.stop", pair)
