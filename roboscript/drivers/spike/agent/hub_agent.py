"""roboscript's agent for the LEGO SPIKE Prime hub (SPIKE App 3 firmware, MicroPython).

The App 3 hub protocol has no motor commands, so roboscript uploads this program into a slot,
starts it, and speaks to it over TunnelMessage in the tunnel format of
``roboscript/drivers/spike/tunnel.py`` (``op u8, size u8, arguments``, little-endian). The
agent turns each command into a call of the hub's own API, so speeds are held by the hub's
motor control (firmware PID). Sensor readings do not pass through the agent: the host asks the
firmware for DeviceNotification messages directly.

This file is package data: the host reads it with ``importlib.resources`` and uploads it as
is. It must run under the hub's MicroPython, so it uses no typing, no dataclasses and no
standard-library module but ``struct``; roboscript's tests also run it under CPython, with
stand-ins for the hub modules.

Bump ``AGENT_VERSION`` whenever this file changes: the host uploads the agent only when the
hub's copy answers the version query with a different version.
"""

import struct

import motor
import motor_pair
import runloop
from hub import light_matrix, motion_sensor, sound

try:
    from time import ticks_diff, ticks_ms
except ImportError:  # CPython, where roboscript's tests run the agent
    from time import monotonic_ns

    def ticks_ms():
        return monotonic_ns() // 1000000

    def ticks_diff(new, old):
        return new - old


AGENT_VERSION = "roboscript-agent 1"

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
VERSION = 0x81
MOVE_DONE = 0x82
REFUSED = 0x8F

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
}
TEXT_COMMANDS = (SHOW_TEXT,)
MOTION = (TANK, TANK_FOR_DEGREES, POWER)
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


def is_awaitable(value):
    """True for what the hub API returns when an action finishes later."""
    return hasattr(value, "__await__") or hasattr(value, "send")


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
            self.watchdog_deadline = None
            self.stop_motors()

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
        self.watchdog_deadline = None if watchdog_ms == 0 else now_ms + watchdog_ms

    def stop_motors(self):
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


def bind_tunnel(receive):
    """Connect ``receive`` to the tunnel and return the function that sends on it.

    The App 3 firmware does not document the program's side of TunnelMessage. The agent
    expects a module ``tunnel`` with ``callback(function)`` (the function gets the payload of
    each TunnelMessage from the host) and ``send(data)``. Everything that depends on that
    assumption is here.
    """
    try:
        import tunnel
    except ImportError:
        print("roboscript agent: this firmware has no tunnel module; nothing will answer")
        return None
    tunnel.callback(receive)
    return tunnel.send


def main():
    agent = Agent(None)
    agent.send = bind_tunnel(agent.receive)
    motion_sensor.reset_yaw(0)
    if agent.send is not None:
        print(AGENT_VERSION, "ready")
    runloop.run(
        serve(agent), finish_moves(agent), finish_jobs(agent.sounds), finish_jobs(agent.texts)
    )
    return agent


main()
