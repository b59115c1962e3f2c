# Stand-in for SPIKE App 3's motor module (LEGO's documentation: constants and calls).
from calls import Pending, record

READY = 0
RUNNING = 1
STALLED = 2
CANCELED = 3
ERROR = 4
DISCONNECTED = 5

COAST = 0
BRAKE = 1
HOLD = 2
CONTINUE = 3
SMART_COAST = 4
SMART_BRAKE = 5


def run(port, velocity, *, acceleration=1000):
    record("motor.run", port, velocity)


def run_for_degrees(port, degrees, velocity, *, stop=BRAKE, acceleration=1000, deceleration=1000):
    record("motor.run_for_degrees", port, degrees, velocity)
    return Pending(abs(degrees) * 1000 // max(1, abs(velocity)), READY)


def set_duty_cycle(port, pwm):
    record("motor.set_duty_cycle", port, pwm)


def stop(port, *, stop=BRAKE):
    record("motor.stop", port)
