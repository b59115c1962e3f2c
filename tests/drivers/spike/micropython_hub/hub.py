# Stand-in for SPIKE App 3's hub module (LEGO's documentation), with the tunnel where two
# public programs that drive real hubs find it: hub.config["module_tunnel"].
import vclock
from calls import Pending, record


class light_matrix:  # noqa: N801 - the hub's submodule name
    @staticmethod
    def write(text, intensity=100, time_per_character=500):
        record("light_matrix.write", text)
        return Pending(len(text) * time_per_character, 0)

    @staticmethod
    def clear():
        record("light_matrix.clear")


class sound:  # noqa: N801
    @staticmethod
    def beep(freq=440, duration=500, volume=100, **kwargs):
        record("sound.beep", freq, duration, volume)
        return Pending(duration, 0)


class button:  # noqa: N801
    LEFT = 1
    RIGHT = 2

    @staticmethod
    def pressed(which):
        return 0  # milliseconds held: never pressed


class motion_sensor:  # noqa: N801
    @staticmethod
    def reset_yaw(angle):
        record("motion_sensor.reset_yaw", angle)


class _Tunnel:
    def __init__(self):
        self.receive = None

    def callback(self, function):
        record("tunnel.callback")
        self.receive = function

    def send(self, data):
        print("TX", vclock.elapsed_ms, bytes(data).hex())


tunnel = _Tunnel()
config = {"module_tunnel": tunnel}
