"""The simulator: worlds, a differential-drive body, and simulated devices.

The simulated devices are the robot side of each protocol; the simulator never imports a host
driver, so a wrong driver cannot hide behind a matching wrong simulator.
"""
