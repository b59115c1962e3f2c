# Stand-in for SPIKE App 3's color_sensor module (LEGO's documentation).
from calls import record


def reflection(port):
    record("color_sensor.reflection", port)
    return 42
