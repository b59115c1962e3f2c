"""roboscript's agent for the LEGO SPIKE Prime hub (SPIKE App 3 firmware, MicroPython).

The App 3 hub protocol has no motor commands, so roboscript uploads this program into a slot,
starts it, and speaks to it over TunnelMessage in the tunnel format of
``roboscript/drivers/spike/tunnel.py`` (``op u8, size u8, arguments``, little-endian). The
agent turns each command into a call of the hub's own API, so speeds are held by the hub's
motor control (firmware PID). Most sensor readings do not pass through the agent: the host asks
the firmware for DeviceNotification messages directly. The two things those messages lack, the
colour sensor's reflection and the hub buttons, the agent reads and reports itself (``Watch``).

This file is package data: the host reads it with ``importlib.resources`` and uploads it as
is. It must run under the hub's MicroPython, so it uses no typing, no dataclasses and no
standard-library module but ``struct`` (and ``os.uname`` for one message); roboscript's tests
also run it under CPython, with stand-ins for the hub modules.

Bump ``AGENT_VERSION`` whenever this file changes: the host uploads the agent only when the
hub's copy answers the version query with a different version.
"""

import struct

import color_sensor
import hub
import motor
import motor_pair
import runloop
from hub import button, light_matrix, motion_sensor, sound

try:
    from time import ticks_add, ticks_diff, ticks_ms
except ImportError:  # CPython, where roboscript's tests run the agent
    from time import monotonic_ns

    def ticks_ms():
        return monotonic_ns() // 1000000

    def ticks_add(ticks, delta):
        return ticks + delta

    def ticks_diff(new, old):
        return new - old

# MicroPython's ticks_ms() wraps (at 2**30 ms on most ports): a deadline is made with
# ticks_add() and compared with ticks_diff(), never with + and <, which go wrong at the wrap.


AGENT_VERSION = "roboscript-agent 2"

PAIR = motor_pair.PAIR_1
LOOP_MS = 5

# Commands (host -> hub) and replies (hub -> host); see tunnel.py for the table.
VERSION_QUERY = 0x01
CONFIGURE = 0x02
TANK = 0x03
TANK_FOR_DEGREES = 0x04
POWER = 0x05
BEEP = 0x06
SHOW_TEXT = 0x07
CLEAR_DISPLAY = 0x08
STOP = 0x09
WATCH = 0x0A
MOTOR_RUN = 0x0B
MOTOR_FOR_DEGREES = 0x0C
MOTOR_STOP = 0x0D
VERSION = 0x81
MOVE_DONE = 0x82
REPORT = 0x83
REFUSED = 0x8F

NO_PORT = 0xFF
NO_REFLECTION = 0xFF
LEFT_BUTTON_BIT = 0x01
RIGHT_BUTTON_BIT = 0x02

# How a program reaches the tunnel, tried in this order. The first is what the public programs
# that drive a real hub's tunnel use; the second is the older guess, kept as a fallback.
TUNNEL_FORMS = ("hub.config['module_tunnel']", "import tunnel")

UNKNOWN_COMMAND = 1
BAD_LENGTH = 2
BAD_VALUE = 3
NOT_CONFIGURED = 4

MOVE_DONE_OK = 0
MOVE_STALLED = 1
MOVE_CANCELLED = 2
MOVE_FAILED = 3

FORMATS = {
    VERSION_QUERY: "<",
    CONFIGURE: "<BB",
    TANK: "<hhHH",
    TANK_FOR_DEGREES: "<Bihh",
    POWER: "<hhH",
    BEEP: "<HHB",
    CLEAR_DISPLAY: "<",
    STOP: "<",
    WATCH: "<BH",
    MOTOR_RUN: "<BhH",
    MOTOR_FOR_DEGREES: "<BBiH",
    MOTOR_STOP: "<B",
}
TEXT_COMMANDS = (SHOW_TEXT,)
MOTION = (TANK, TANK_FOR_DEGREES, POWER)
ONE_MOTOR = (MOTOR_RUN, MOTOR_FOR_DEGREES, MOTOR_STOP)
MAX_TEXT_BYTES = 200


def move_status(result):
    """The tunnel's MoveDone status for a motor_pair move result."""
    if result == motor.READY:
        return MOVE_DONE_OK
    if result == motor.STALLED:
        return MOVE_STALLED
    if result == getattr(motor, "CANCELED", -1):
        return MOVE_CANCELLED
    return MOVE_FAILED


PLAIN_VALUES = (str, bytes, bytearray, list, tuple, dict)


def is_awaitable(value):
    """True for what the hub API returns when an action finishes later.

    MicroPython's ``await`` takes any object it can iterate: a coroutine or generator
    (``send``), an object with ``__await__``, or an iterator (``__next__``/``__iter__``).
    Plain values (numbers, text, containers) are results, not actions still running.
    """
    if isinstance(value, PLAIN_VALUES):
        return False
    return any(hasattr(value, name) for name in ("__await__", "send", "__next__", "__iter__"))


class Agent:
    """Reads tunnel commands and acts on them with the hub API.

    Args:
        send: Called with the bytes of each reply (one TunnelMessage each).
    """

    def __init__(self, send):
        self.send = send
        self.inbox = bytearray()
        self.left_port = None
        self.right_port = None
        self.watchdog_deadline = None
        self.moves = []
        self.sounds = []
        self.texts = []
        self.other_motors = []  # ports of motors run by MotorRun / MotorForDegrees
        self.color_port = NO_PORT
        self.watch_ms = 0
        self.next_report_ms = None

    def receive(self, data):
        """Buffer tunnel bytes from the host (records may arrive split or merged)."""
        self.inbox += data

    def reply(self, op, args):
        if self.send is not None:
            self.send(bytes((op, len(args))) + args)

    def refuse(self, op, reason):
        self.reply(REFUSED, struct.pack("<BB", op, reason))

    def poll(self, now_ms):
        """Act on every whole record received, then run the watchdog."""
        while len(self.inbox) >= 2:
            op = self.inbox[0]
            end = 2 + self.inbox[1]
            if len(self.inbox) < end:
                break
            args = bytes(self.inbox[2:end])
            self.inbox = self.inbox[end:]
            try:
                self.handle(op, args, now_ms)
            except Exception as error:  # noqa: BLE001 - a bad command must not end the agent
                print("roboscript agent: op", op, "failed:", error)
                self.refuse(op, BAD_VALUE)
        deadline = self.watchdog_deadline
        if deadline is not None and ticks_diff(now_ms, deadline) >= 0:
            self.watchdog_deadline = None  # the host went quiet: stop everything it started
            self.stop_motors()
            for port in self.other_motors:
                motor.stop(port, stop=motor.BRAKE)
        due = self.next_report_ms
        if due is not None and ticks_diff(now_ms, due) >= 0:
            self.next_report_ms = ticks_add(now_ms, self.watch_ms)
            self.report()

    def handle(self, op, args, now_ms):
        """Act on one record."""
        if op in TEXT_COMMANDS:
            if len(args) > MAX_TEXT_BYTES:
                self.refuse(op, BAD_LENGTH)
                return
            self.show_text(args.decode("utf-8"))
            return
        layout = FORMATS.get(op)
        if layout is None:
            self.refuse(op, UNKNOWN_COMMAND)
            return
        if len(args) != struct.calcsize(layout):
            self.refuse(op, BAD_LENGTH)
            return
        values = struct.unpack(layout, args)
        if op in MOTION and self.left_port is None:
            self.refuse(op, NOT_CONFIGURED)
            return
        if op in ONE_MOTOR and not self.may_drive_alone(
            values[1 if op == MOTOR_FOR_DEGREES else 0]
        ):
            self.refuse(op, BAD_VALUE)
            return
        if op == VERSION_QUERY:
            self.reply(VERSION, AGENT_VERSION.encode("utf-8"))
        elif op == CONFIGURE:
            self.configure(values[0], values[1])
        elif op == TANK:
            left, right, acceleration, watchdog_ms = values
            motor_pair.move_tank(PAIR, left, right, acceleration=acceleration)
            self.arm_watchdog(now_ms, watchdog_ms)
        elif op == TANK_FOR_DEGREES:
            seq, degrees, left, right = values
            self.watchdog_deadline = None  # the move ends by itself
            job = motor_pair.move_tank_for_degrees(PAIR, degrees, left, right)
            self.moves.append((seq, job))
        elif op == POWER:
            left, right, watchdog_ms = values
            # set_duty_cycle drives one motor as it turns; the left one is mounted mirrored.
            motor.set_duty_cycle(self.left_port, -left)
            motor.set_duty_cycle(self.right_port, right)
            self.arm_watchdog(now_ms, watchdog_ms)
        elif op == BEEP:
            frequency_hz, duration_ms, volume = values
            self.queue(self.sounds, sound.beep(frequency_hz, duration_ms, volume))
        elif op == CLEAR_DISPLAY:
            light_matrix.clear()
        elif op == STOP:
            self.watchdog_deadline = None
            self.stop_motors()
        elif op == WATCH:
            self.watch(values[0], values[1], now_ms)
        elif op == MOTOR_RUN:
            port, speed_deg_s, watchdog_ms = values
            self.remember_motor(port)
            motor.run(port, speed_deg_s)
            self.arm_watchdog(now_ms, watchdog_ms)
        elif op == MOTOR_FOR_DEGREES:
            seq, port, degrees, speed_deg_s = values
            self.remember_motor(port)
            self.moves.append((seq, motor.run_for_degrees(port, degrees, speed_deg_s)))
        elif op == MOTOR_STOP:
            motor.stop(values[0], stop=motor.BRAKE)

    def may_drive_alone(self, port):
        """A port other than the drive motors', 0..5."""
        return 0 <= port <= 5 and port != self.left_port and port != self.right_port

    def remember_motor(self, port):
        if port not in self.other_motors:
            self.other_motors.append(port)

    def watch(self, color_port, interval_ms, now_ms):
        if color_port != NO_PORT and color_port > 5:
            self.refuse(WATCH, BAD_VALUE)
            return
        self.color_port = color_port
        self.watch_ms = interval_ms
        self.next_report_ms = now_ms if interval_ms else None

    def report(self):
        """Send the colour sensor's reflection and the pressed buttons (one Report)."""
        reflection = NO_REFLECTION
        if self.color_port != NO_PORT:
            try:
                reflection = max(0, min(100, int(color_sensor.reflection(self.color_port))))
            except Exception:  # noqa: BLE001 - no sensor on the port (yet): report none
                reflection = NO_REFLECTION
        buttons = 0
        if button.pressed(button.LEFT):
            buttons |= LEFT_BUTTON_BIT
        if button.pressed(button.RIGHT):
            buttons |= RIGHT_BUTTON_BIT
        self.reply(REPORT, struct.pack("<BB", reflection, buttons))

    def configure(self, left_port, right_port):
        if left_port > 5 or right_port > 5 or left_port == right_port:
            self.refuse(CONFIGURE, BAD_VALUE)
            return
        if self.left_port is not None:
            motor_pair.unpair(PAIR)
        motor_pair.pair(PAIR, left_port, right_port)
        self.left_port = left_port
        self.right_port = right_port

    def arm_watchdog(self, now_ms, watchdog_ms):
        self.watchdog_deadline = None if watchdog_ms == 0 else ticks_add(now_ms, watchdog_ms)

    def stop_motors(self):
        """Brake the drive motors (Stop); the other motors keep what they were told."""
        if self.left_port is None:
            return
        motor_pair.stop(PAIR, stop=motor.BRAKE)
        # A Power command drives the motors one by one: stop them one by one too.
        motor.stop(self.left_port, stop=motor.BRAKE)
        motor.stop(self.right_port, stop=motor.BRAKE)

    def show_text(self, text):
        if text:
            self.queue(self.texts, light_matrix.write(text))
        else:
            light_matrix.clear()

    def queue(self, jobs, result):
        if is_awaitable(result):
            jobs.append(result)


async def serve(agent):
    """Read commands every few milliseconds for as long as the program runs."""
    while True:
        agent.poll(ticks_ms())
        await runloop.sleep_ms(LOOP_MS)


async def finish_moves(agent):
    """Wait for each move to end and tell the host how it ended."""
    while True:
        if agent.moves:
            seq, job = agent.moves.pop(0)
            result = (await job) if is_awaitable(job) else motor.READY
            agent.reply(MOVE_DONE, struct.pack("<BB", seq, move_status(result)))
        else:
            await runloop.sleep_ms(LOOP_MS)


async def finish_jobs(jobs):
    """Await tones or scrolling text one after the other, so they do not cut each other off."""
    while True:
        if jobs:
            await jobs.pop(0)
        else:
            await runloop.sleep_ms(LOOP_MS)


def firmware_version():
    """The hub's firmware as this program can read it (MicroPython's ``uname``), for messages."""
    try:
        import os

        uname = os.uname()
        return uname.release + " (" + uname.version + ")"
    except Exception:  # noqa: BLE001 - any answer is better than none in a message
        return "unknown"


def find_tunnel(tried):
    """The firmware's tunnel module and the form that found it, or ``(None, None)``.

    Each form is added to ``tried`` before it is tried, so a message (and a test) can say
    which forms were tried and in which order.
    """
    tried.append(TUNNEL_FORMS[0])
    try:
        module = hub.config["module_tunnel"]
    except Exception:  # noqa: BLE001 - no config, or no such key, on this firmware
        module = None
    if module is not None:
        return module, TUNNEL_FORMS[0]
    tried.append(TUNNEL_FORMS[1])
    try:
        import tunnel
    except ImportError:
        return None, None
    return tunnel, TUNNEL_FORMS[1]


def bind_tunnel(receive):
    """Connect ``receive`` to the tunnel; return the function that sends on it and the form.

    LEGO does not document the program's side of TunnelMessage. The module found (see
    :func:`find_tunnel`) is expected to have ``callback(function)`` (the function gets the
    payload of each TunnelMessage from the host) and ``send(data)``. Without one, it says so
    on the console (which the host shows), naming the firmware, and returns ``(None, None)``.
    """
    tried = []
    module, form = find_tunnel(tried)
    if module is None:
        print(
            "roboscript agent: no tunnel on this hub (firmware "
            + firmware_version()
            + "): tried "
            + " and ".join(tried)
            + "; update the hub with the SPIKE App 3"
        )
        return None, None
    module.callback(receive)
    return module.send, form


def main():
    agent = Agent(None)
    agent.send, form = bind_tunnel(agent.receive)
    motion_sensor.reset_yaw(0)
    if agent.send is not None:
        print(AGENT_VERSION, "ready, tunnel from", form)
    else:
        agent.show_text("NO TUNNEL")  # for whoever looks at the hub
    runloop.run(
        serve(agent), finish_moves(agent), finish_jobs(agent.sounds), finish_jobs(agent.texts)
    )
    return agent


main()
