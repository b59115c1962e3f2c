"""A simulated MIRTO board: the ASIP 1.1 firmware's device side, on a simulated body.

This is a second, independent implementation of the protocol (it never imports the host
driver), written from the firmware's behaviour:

* On connection it sends the startup line ``!<sketch> running on <chip> with Services: ...``,
  then, as the ``mirtle2017`` sketch does, its pin modes and port map and one unprefixed
  ``<name> is service <id>`` line per service (CRLF-terminated).
* Requests are parsed with the firmware's ``Stream`` semantics (see
  :mod:`~roboscript.drivers.asip.device_side`), each timed read's 1000 ms timeout counted on
  the simulation clock. While a timed read waits (``T,P,440,250`` with no newline waits a
  second for the byte after ``250``), the board runs nothing else: no events, no PID frames.
* On a UART board (``transport: uart``) the firmware keeps its own clock
  (:mod:`~roboscript.drivers.asip.uart`): the host's bytes arrive one byte time apart, and each
  request is read with the bytes that have arrived by the time the firmware reads them; its
  replies take it time, so an unknown service skips what arrived while its error was written,
  and a request that arrived while the board wrote is read whole.
* Like the sketch, the board has :class:`~roboscript.drivers.asip.options.AsipOptions`'
  servos (1) and pixels (9); its LCD keeps 20 characters a row.
* The motor service runs every 33 ms (30 Hz): it services the firmware PID of ``M,r``,
  ``M,R``, ``M,c`` and ``M,a`` (integer gains Kp 20, Ki 0, Kd 12, divisor Ko 20, acceleration
  limit per frame, stop when the duration has passed or after 2000 ms without an encoder
  pulse) and, when enabled with ``M,A,1``, sends ``@M,e,2,{delta:total,...}``.
* Without firmware PID (``asip-basic``) the PID tags answer ``~M,<tag>,2{UNKNOWN_REQUEST}``.
* The IO service streams free analog pins every 50 ms from power-on (``@I,a``); bump, IR and
  distance events follow their ``A`` intervals; errors carry the firmware's numbers and texts.
  A pin set to INPUT or INPUT_PULLUP joins its port's report mask (even when the pin belongs
  to another service and the request is refused) and every port with a non-zero mask is
  reported at once (``@I,d,port,HEX``), then whenever its level changes.

Where the firmware's behaviour is undefined (a pixel strip other than 0, an LCD line below 0)
the simulated board refuses the request instead (``~P,<tag>,7{INVALID_DEVICE_NUMBER}``, or
silently for the LCD).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from roboscript.codec import Role, readable
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import DeviceAsipCodec
from roboscript.drivers.asip.options import AsipOptions
from roboscript.drivers.asip.uart import (
    RECEIVE_RING_BYTES,
    ReceiveLine,
    Transmitter,
    avr_byte_s,
)
from roboscript.errors import RemoteProtocolError

if TYPE_CHECKING:
    from roboscript.robot_profile import RobotProfile
    from roboscript.sim.body import Body

__all__ = ["BoardConfig", "MirtoBoard", "simulated_device"]

_MOTOR_FRAME_S = 0.033  # 1000 / PID_FRAME_HZ in integer milliseconds
RESET_UART_ON_S = 3.0013
"""After a reset, when the sketch opens its UART (``Serial.begin`` in ``beginAsipComms()``,
after ``pixelFun()``'s three 1 s delays and the LCD's start-up text), seconds. A byte that
arrives before is lost; later ones wait in the receive ring until ``loop()`` reads them.
Measured on the emulated ATmega328P build (the UART's RXEN0 bit is set at 3.00132 s)."""
RESET_GREETING_S = 3.2014
"""After a reset, when the sketch writes its first start-up byte (``delay(200)`` after
``Serial.begin``), seconds. Measured on the emulated build (the first byte at 3.20138 s)."""
REQUEST_S = 50e-6
"""On a UART board, the firmware's time from the byte that completes what a request needs to
be read (its fourth byte, ``MIN_MSG_LEN``) to writing its answer, when the byte finds it idle
in ``loop()``: the rest of a loop turn and the parse, seconds. Measured on the emulated
firmware: the first byte of the answer comes 54 to 72 us after that byte (``#,?``, ``I,M``,
``X,?``), of which the first byte's own write is :data:`~roboscript.drivers.asip.uart.
WRITE_BYTE_S`. A byte that arrives while the firmware waits inside a request (a timed read)
is read at once."""
SKIP_BYTE_S = 5e-6
"""On a UART board, the firmware's time per byte skipping the rest of a line after an error
(``asip.cpp``'s ``while (serial->available() && serial->read() != '\\n')``: two virtual
calls into ``HardwareSerial`` and the ring's index arithmetic, about 80 cycles at 16 MHz),
seconds: a byte that arrives meanwhile is skipped too."""
OPTIBOOT_FLASHES_S = 6 * 976 / (16_000_000 / 1024)
"""After an external reset, how long an Arduino Uno's bootloader (optiboot, as the Arduino AVR
core ships it: ``bootloaders/optiboot/optiboot.c``, built with ``LED_START_FLASHES=3``) flashes
its LED before it listens: six Timer1 waits of 976 ticks at F_CPU / 1024, 374.8 ms. Bytes that
arrive meanwhile are its own (the USART is on, at 115200 baud)."""
OPTIBOOT_WAIT_S = 1.0
"""How long optiboot then waits for an upload before its watchdog (``WATCHDOG_1S``) starts the
sketch, seconds."""
OPTIBOOT_EXIT_S = 0.016
"""How soon optiboot starts the sketch once two bytes that are not an upload's have come: it
reads a command byte, then ``verifySpace()`` reads the next, and any byte but ``CRC_EOP``
sets its watchdog to ``WATCHDOG_16MS`` and waits for it, seconds."""
TIMER0_START_S = 0.784e-3
"""After a reset, when an AVR board's Timer0 starts counting (the C runtime's start-up and the
core's ``init()``), seconds: its first overflow, the first ``millis()`` tick, comes one
overflow later. Measured on the emulated ATmega328P build (the first at 1.808 ms, then every
1.024 ms)."""
_AVR_MILLIS_FRACT = (3, 125)
"""The Arduino AVR core's ``millis()``: one per Timer0 overflow (64 x 256 cycles, 1.024 ms at
16 MHz) and one more each time the overflows' 24 us remainders (3 in units of 8 us) make up a
millisecond (125 units): ``millis = n + 3 n / 125`` after ``n`` overflows."""
_LOOP_SERVICES = "IMBRD"
"""The services with auto-events, in the order of ``mirtle2017``'s ``services[]``."""
_AUTO_STOP_S = 2.0
_MOST_EVENTS_A_STEP = 64
"""A bound on one service's events in one physics step (a wrapped interval reports on every
turn of the loop: on a UART board the line's pace allows a few a step)."""
_PARSE_TIMEOUT_S = 1.0

# Pin map of the MIRTO 328 V2 board as the mirtle2017 sketch allocates it (robot_pins.h, the
# 328 branch): motors 8, 11, 5, 12, 13, 6 and encoders 3, 7, 2, 4; bumpers 9, 10; IR 14-17
# (14 drives the emitters); the UART's pins 0, 1 and the LCD's I2C pins 18, 19 are reserved
# before the servo (18) and distance sensor (19) register, so both show as reserved.
_PIN_SERVICES = "@@MMMMMMMBBMMMRRRR@@"
_PORT_MAP = tuple([(4, 1 << i) for i in range(8)] + [(2, 1 << i) for i in range(6)]) + tuple(
    (3, 1 << i) for i in range(6)
)
_ANALOG_PINS = {14 + i: i for i in range(6)}
_PWM_PINS = {3, 5, 6, 9, 10, 11}
_BUMP_PINS = (9, 10)  # left, right: INPUT_PULLUP, so 0 while pressed
_ENCODER_PINS = {3: (0, 0), 7: (0, 1), 2: (1, 0), 4: (1, 1)}  # pin -> (wheel, 0 A / 1 B)
_QUADRATURE = ((1, 1), (1, 0), (0, 0), (0, 1))
"""The encoder lines' levels (A, B) at each tick modulo 4, forward: the Encoder library
pulls both lines up, and a wheel at tick 0 reads them high, as the emulated board does."""
_SERVICE_NAMES = {  # in the order of the sketch's services[]
    "I": "ASIP core IO",
    "M": "Motors",
    "B": "Bump Sensors",
    "R": "IR Sensors",
    "T": "Tone",
    "S": "Servos",
    "D": "Distance",
    "L": "LCD",
    "P": "Pixels",
}
# Like the LCD (on I2C), servos and the pixel strip sit on pins the 20-pin map does not show.
_LCD_ROW_BYTES = m.LCD_COLUMNS + 1  # asipLCD keeps each row in 21 bytes, NUL-terminated


def _cdiv(a: int, b: int) -> int:
    """C integer division (truncates toward zero)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


@dataclass(frozen=True)
class BoardConfig:
    """How the simulated board is built.

    Attributes:
        firmware_pid: Whether the sketch was built with the motor PID (``ASIP_PID``).
        sketch: Sketch name in the startup line and version reply.
        chip: Chip name in the startup line and version reply.
        kp: Proportional gain (integer, firmware units).
        ki: Integral gain.
        kd: Derivative gain.
        ko: Output divisor.
        max_pwm: PWM limit.
        max_pwm_delta: Largest PWM change per PID frame.
        encoder_events_on: Whether ``@M,e`` events are on at power-on (V1.1: off).
        servo_count: Servos the sketch declares (``mirtle2017``: 1).
        pixel_count: Pixels on strip 0 (``mirtle2017``: 9).
        whole_lines: True for a USB board (a Teensy: a line written at once arrives at
            once); False for a UART board, whose firmware sees each byte as it arrives and
            acts on what has arrived so far (see :class:`~roboscript.drivers.asip.options.
            AsipOptions`).
        baud: A UART board's line speed, bits per second: bytes arrive one byte time
            apart, and a reply takes the firmware time (:mod:`~roboscript.drivers.asip.uart`).
        f_cpu_hz: A UART board's clock, hertz: its USART sends at the rate its divisor makes
            of :attr:`baud` (:func:`~roboscript.drivers.asip.uart.avr_byte_s`).
        int_bits: The width of the firmware's ``int`` and ``unsigned int``, bits: 16 on a
            UART board (an ATmega328P: ``M,A,65536`` turns encoder events off, an auto-event
            interval's due tick wraps at 65536 ms), 32 on the USB board (the MIRTO's Teensy
            3.1, an ARM).
        resets_on_connect: Whether opening the port resets the board (an Arduino Uno-style
            board whose DTR line drives its reset): it then starts afresh and is deaf until
            its sketch opens the UART (:data:`RESET_UART_ON_S`), and greets at
            :data:`RESET_GREETING_S`.
        bootloader: Whether a reset by the port's opening first runs the Uno's bootloader
            (optiboot), which takes the bytes that arrive meanwhile and starts the sketch
            :data:`OPTIBOOT_EXIT_S` after the second, or :data:`OPTIBOOT_WAIT_S` after its
            LED flashes (:data:`OPTIBOOT_FLASHES_S`) when fewer come. (A power-on or a dip
            in the supply starts the sketch at once: optiboot runs only after an external
            reset.)
    """

    firmware_pid: bool = True
    sketch: str = "Mirtle2017"
    chip: str = "ATmega328P"
    kp: int = 20
    ki: int = 0
    kd: int = 12
    ko: int = 20
    max_pwm: int = 255
    max_pwm_delta: int = 30
    encoder_events_on: bool = False
    servo_count: int = 1
    pixel_count: int = 9
    whole_lines: bool = True
    baud: int = 57600
    f_cpu_hz: int = 16_000_000
    int_bits: int = 32
    resets_on_connect: bool = False
    bootloader: bool = True


@dataclass
class _Wheel:
    pwm: int = 0
    pid_active: bool = False
    target_ticks_per_s: int = 0
    start_s: float = 0.0
    duration_s: float = 0.0
    prev_pulse_s: float = 0.0
    prev_input: int = 0
    prev_output: int = 0
    iterm: int = 0
    last_ticks: int = 0
    delta: int = 0
    total_offset: int = 0


@dataclass
class _AutoEvent:
    """A service's auto-events as ``asipService``'s ``setAutoreport`` keeps them: in
    ``unsigned int`` ticks of ``millis()``. On an ATmega328P those are 16 bits, so ``-5`` is
    65531 ms and ``tick + interval`` wraps (the due tick is then below the tick now, and the
    board reports on every turn of ``loop()``, as fast as its line takes the events, until
    ``millis()`` wraps too); on a Teensy 3.1 they are 32 bits, and wrap after 49 days."""

    tick_mask: int = 0xFFFF  # the unsigned int's values: 0xFFFF (16 bits) or 0xFFFF_FFFF
    interval_ms: int = 0
    next_tick: int = 0  # the tick from which it reports
    checked_ms: int = 0  # millis() when the firmware last looked

    @property
    def interval_s(self) -> float:
        """The interval, seconds (0: off)."""
        return self.interval_ms / 1000.0

    def start(self, interval_ms: int, now_ms: int) -> None:
        """``setAutoreport(interval)`` at ``millis()`` ``now_ms``."""
        self.interval_ms = interval_ms & self.tick_mask
        self.next_tick = (now_ms + self.interval_ms) & self.tick_mask
        self.checked_ms = now_ms

    def due_ms(self) -> int:
        """The first ``millis()`` from the last look on at which ``tick >= nextTrigger``."""
        low = self.checked_ms & self.tick_mask
        return self.checked_ms if low >= self.next_tick else self.checked_ms + self.next_tick - low


@dataclass
class _State:
    wheels: list[_Wheel] = field(default_factory=lambda: [_Wheel(), _Wheel()])
    encoder_events: bool = False
    motor_frames: bool = True
    next_motor_frame_s: float = 0.0
    motor_event: _AutoEvent = field(default_factory=_AutoEvent)
    """A UART board's motor frame, ``setAutoreport(1000 / PID_FRAME_HZ)`` in its ``begin``
    (a USB board keeps :attr:`next_motor_frame_s` instead)."""
    auto: dict[str, _AutoEvent] = field(default_factory=dict)
    pin_modes: list[int] = field(default_factory=list)
    analog_channels: set[int] = field(default_factory=set)  # analogInputsToReport
    report_masks: dict[int, int] = field(default_factory=dict)  # port -> reportPinMasks
    port_levels: dict[int, int] = field(default_factory=dict)  # port -> previousPINs
    lcd: list[bytearray] = field(
        default_factory=lambda: [bytearray(_LCD_ROW_BYTES) for _ in range(m.LCD_LINES)]
    )
    servos_deg: list[int] = field(default_factory=list)
    pixels: list[tuple[int, int, int]] = field(default_factory=list)
    brightness: int = 64

    @property
    def lcd_rows(self) -> list[str]:
        """The LCD's rows as shown: each up to its first NUL."""
        return [bytes(row).split(b"\0", 1)[0].decode("latin-1") for row in self.lcd]


class MirtoBoard:
    """The simulated MIRTO board on a body (see the module docstring).

    Args:
        body: The simulated body the board drives and senses.
        config: Firmware build options.
    """

    def __init__(self, body: Body, config: BoardConfig | None = None) -> None:
        self.body = body
        self.config = config or BoardConfig()
        self.codec = self._new_codec()
        self._out = bytearray()
        self._now_s = 0.0  # the simulation's time, as last told
        self._wait_since_s = 0.0
        # A UART board's line and its firmware's own clock (at or past the simulation's
        # while it writes): what a request reads depends on when it reads.
        self._line = ReceiveLine(self.config.baud)
        self._transmitter = Transmitter(avr_byte_s(self.config.baud, self.config.f_cpu_hz))
        self._clock_s = 0.0
        self._powered_s = 0.0  # when the board last started: millis() counts from it
        self._due_s: float | None = None  # a UART board's next auto-event, once worked out
        # an AVR's Timer0 overflow, seconds: a millis() tick, less the ones it makes up
        self._overflow_s = 64 * 256 / self.config.f_cpu_hz
        self.state = self._power_on_state()
        # After a reset: when the sketch opens its UART and when it greets (None: running).
        self._booting: tuple[float, float] | None = None
        # After a reset by the port's opening: when the bootloader started (None: not in it),
        # and when the host's bytes it took came.
        self._bootloader_s: float | None = None
        self._bootloader_bytes_s: list[float] = []

    def _new_codec(self) -> DeviceAsipCodec:
        services = "".join(_SERVICE_NAMES)
        return DeviceAsipCodec(
            Role.DEVICE,
            services=services,
            servo_count=self.config.servo_count,
            int_bits=self.config.int_bits,
        )

    def _power_on_state(self) -> _State:
        state = _State(encoder_events=self.config.encoder_events_on)
        state.servos_deg = [90] * self.config.servo_count
        state.pixels = [(0, 0, 0)] * self.config.pixel_count
        for service in "IBRD":
            state.auto[service] = _AutoEvent((1 << self.config.int_bits) - 1)
        state.motor_event = _AutoEvent((1 << self.config.int_bits) - 1)
        modes = []
        for pin, owner in enumerate(_PIN_SERVICES):
            if owner == "@":
                modes.append(int(m.PinMode.RESERVED))
            elif owner == "I":
                # Without STRICT_PINMODE every free analog pin starts in ANALOG mode.
                modes.append(
                    int(m.PinMode.ANALOG if pin in _ANALOG_PINS else m.PinMode.UNALLOCATED)
                )
            else:
                modes.append(int(m.PinMode.OTHER_SERVICE))
        state.pin_modes = modes
        state.analog_channels = {
            chan for pin, chan in _ANALOG_PINS.items() if modes[pin] == m.PinMode.ANALOG
        }
        state.auto["I"].interval_ms = 50
        return state

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """A host opened the port: greet it the way the sketch's ``setup()`` does, or, on a
        board that resets when its port opens, start afresh and greet once booted."""
        self._now_s = max(self._now_s, now_s)
        self.codec = self._new_codec()
        self._line.clear()
        if not self.config.resets_on_connect:
            self._greet(now_s)
            return
        self.reset(now_s, external=self.config.bootloader)

    def reset(self, now_s: float, *, external: bool = False) -> None:
        """The board resets at ``now_s`` (its reset line, or its power dipping under the
        motors' load): the motors stop, what it had not yet sent and what it had not yet read
        is gone, and it is deaf until its sketch opens the UART again
        (:data:`RESET_UART_ON_S`), then greets (:data:`RESET_GREETING_S`) as at power-on.
        ``external``: the reset line was pulled (a port opening), so the bootloader runs
        first (see :attr:`BoardConfig.bootloader`)."""
        self._now_s = max(self._now_s, now_s)
        self.codec = self._new_codec()
        self.stop_all()
        # what its USART had taken is on the wire; the rest of its transmit buffer is gone
        self._out += self._transmitter.take_handed(now_s)
        self._transmitter.clear()
        ticks = self.body.ticks
        self.state = self._power_on_state()  # the encoders count from 0 again
        for index, wheel in enumerate(self.state.wheels):
            wheel.last_ticks = wheel.total_offset = ticks[index]
        self._powered_s = now_s
        self._clock_s = now_s
        self._due_s = None
        self._booting = None
        self._bootloader_bytes_s = []
        self._bootloader_s = now_s if external else None
        if not external:
            self._start_sketch(now_s)

    def _start_sketch(self, now_s: float) -> None:
        """The sketch starts at ``now_s``: ``millis()`` counts from it, and it greets once its
        ``setup()`` is done."""
        self._powered_s = now_s
        self._booting = (now_s + RESET_UART_ON_S, now_s + RESET_GREETING_S)

    def _bootloader_exit_s(self, now_s: float) -> float | None:
        """When the bootloader started the sketch, once that is known by ``now_s`` (None:
        it is still waiting)."""
        start_s = self._bootloader_s
        assert start_s is not None
        listening_s = start_s + OPTIBOOT_FLASHES_S
        deadline_s = listening_s + OPTIBOOT_WAIT_S
        taken = self._bootloader_bytes_s
        if not self.config.whole_lines:  # the line's bytes, one at a time, as they come
            while len(taken) < 2 and self._line.next_arrival_s() <= min(now_s, deadline_s):
                arrival_s = self._line.next_arrival_s()
                self._line.take_arrived(arrival_s)
                taken.append(arrival_s)
        if len(taken) >= 2 and taken[1] <= deadline_s:
            return max(listening_s, taken[1]) + OPTIBOOT_EXIT_S
        return deadline_s if now_s >= deadline_s - 1e-9 else None

    def _greet(self, now_s: float) -> None:
        self._clock_s = max(self._clock_s, now_s)
        self._due_s = None
        services = tuple(_SERVICE_NAMES)
        self._send(m.StartupLine(self.config.sketch, self.config.chip, services))
        # mirtle2017's setup(): asip.begin's line, then each service's begin (the motors'
        # and the IO's set their auto-reports), then the pin modes, port map and names
        begun_ms = self._millis(self._clock_s)
        self._send(m.PinModesReply(tuple(self.state.pin_modes)))
        self._send(m.PortMapReply(_PORT_MAP))
        for service, name in _SERVICE_NAMES.items():
            self._write(f"{name} is service {service}\r\n".encode("ascii"))
        for event in self.state.auto.values():
            event.start(event.interval_ms, self._millis(now_s))
        if not self.config.whole_lines:
            self.state.auto["I"].start(self.state.auto["I"].interval_ms, begun_ms)
            self.state.motor_event.start(round(_MOTOR_FRAME_S * 1000), begun_ms)
        self.state.next_motor_frame_s = now_s + _MOTOR_FRAME_S

    def _boot(self, now_s: float) -> bool:
        """A board booting after a reset, up to ``now_s``: True while it is still booting.

        Bytes that arrived before the sketch opened its UART are lost; later ones wait in the
        receive ring and are read once the greeting is written (see :meth:`receive`)."""
        if self._bootloader_s is not None:
            exit_s = self._bootloader_exit_s(now_s)
            if exit_s is None:
                return True
            self._bootloader_s = None
            self._start_sketch(exit_s)
        if self._booting is None:
            return False
        uart_on_s, greeting_s = self._booting
        if now_s < greeting_s - 1e-9:
            return True
        self._booting = None
        self._line.take_arrived(uart_on_s - 1e-9)  # lost: the UART was off
        self._greet(greeting_s)
        if self.config.whole_lines:
            self._wait_since_s = greeting_s
            self._process(greeting_s)
        return False

    def receive(self, data: bytes, now_s: float) -> None:
        """Parse and act on request bytes."""
        self._now_s = max(self._now_s, now_s)
        if not data:
            return
        if not self.config.whole_lines:
            self._line.send(data, now_s)  # read as it arrives, by step()
            return
        if self._bootloader_s is not None:  # the bootloader's, as they come
            taken = self._bootloader_bytes_s
            taken += [now_s] * min(len(data), 2 - len(taken))
            return
        if self._booting is not None:
            if now_s >= self._booting[0]:  # the UART is on: the bytes wait to be read
                room = max(0, RECEIVE_RING_BYTES - self.codec.pending_bytes())
                self.codec.receive_data(data[:room])
            return
        self._wait_since_s = now_s  # a byte ends the wait; the next one starts now
        self.codec.receive_data(data)
        self._process(now_s)

    def step(self, now_s: float) -> None:
        """Run timers: parse timeout, PID frames, auto-events, digital port changes (and, on a
        UART board, the requests whose bytes have arrived)."""
        self._now_s = max(self._now_s, now_s)
        if self._boot(now_s):
            return  # the sketch's start-up: nothing else runs
        codec = self.codec
        if not self.config.whole_lines:
            self._run_loop(now_s)
            return
        if codec.waiting:
            # Stream's timed reads give up after a second without a byte; each has its own.
            if now_s - self._wait_since_s >= _PARSE_TIMEOUT_S - 1e-9:
                self._wait_since_s = now_s
                codec.parse_timeout()
                self._process(now_s)
            if codec.waiting:
                return  # the firmware is inside parseInt: nothing else runs
        self._send_port_changes(force=False)
        state = self.state
        # The epsilon keeps float sums of intervals (20 x 0.05 s) from slipping a tick.
        if state.motor_frames and now_s >= state.next_motor_frame_s - 1e-9:
            self._motor_frame(now_s)
            state.next_motor_frame_s += _MOTOR_FRAME_S
            if state.next_motor_frame_s < now_s:
                state.next_motor_frame_s = now_s + _MOTOR_FRAME_S
        for service, event in state.auto.items():
            if event.interval_ms:
                self._auto_report(service, event, now_s)

    def _run_loop(self, now_s: float) -> None:
        """A UART board's ``loop()`` up to ``now_s``, on the firmware's own clock: each turn
        reads what has arrived (``asip.service()``), then reports each service whose
        auto-event is due at the turn's ``millis()``, in the sketch's ``services[]`` order,
        each written as the line takes it; a request that arrives while it writes is read at
        the next turn, before the next event (``B,A,0`` stops a stream at once)."""
        state = self.state
        for _ in range(_MOST_EVENTS_A_STEP):
            turn_s = self._next_turn_s()
            self._serve_line(min(now_s, turn_s))
            if self.codec.waiting:  # inside parseInt: nothing else runs until it returns
                self._serve_line(now_s)
                if self.codec.waiting:
                    return
            if self._due_s is None or self._clock_s > turn_s:
                turn_s = self._next_turn_s()  # what it read may have changed an interval
            if turn_s > now_s + 1e-9:
                break
            self._clock_s = turn_s
            self._due_s = None
            tick = self._millis(turn_s)
            for service in _LOOP_SERVICES:  # the sketch's services[] order
                if service == "M":
                    if not state.motor_frames:
                        continue
                    event = state.motor_event
                else:
                    event = state.auto[service]
                event.checked_ms = max(event.checked_ms, tick)
                if event.interval_ms and event.due_ms() <= tick:  # tick >= nextTrigger
                    if service == "M":
                        self._motor_frame(turn_s)
                    else:
                        self._report(service)
                    event.next_tick = (tick + event.interval_ms) & event.tick_mask
        self._clock_s = max(self._clock_s, now_s)
        self._send_port_changes(force=False)

    def _next_turn_s(self) -> float:
        """A UART board: when its loop next finds an auto-event due, seconds (infinity when
        none is on); never before the firmware is free. Kept until a request is handled or
        an event reported (:attr:`_due_s`): most physics steps only look at it."""
        due_s = self._due_s
        if due_s is None:
            state = self.state
            due_ms = math.inf
            if state.motor_frames and state.motor_event.interval_ms:
                due_ms = state.motor_event.due_ms()
            for event in state.auto.values():
                if event.interval_ms:
                    due_ms = min(due_ms, event.due_ms())
            due_s = math.inf if due_ms == math.inf else self._millis_s(int(due_ms))
            self._due_s = due_s
        return max(self._clock_s, due_s)

    def _millis(self, time_s: float) -> int:
        """The firmware's ``millis()`` at simulated ``time_s``, since power-on: on a UART
        board (an AVR) counted in Timer0 overflows (``_AVR_MILLIS_FRACT``), else whole ms."""
        if self.config.whole_lines:
            return math.floor((time_s - self._powered_s) * 1000.0 + 1e-6)
        overflows = math.floor(
            (time_s - self._powered_s - TIMER0_START_S) / self._overflow_s + 1e-6
        )
        if overflows <= 0:
            return 0
        extra, unit = _AVR_MILLIS_FRACT
        return overflows + overflows * extra // unit

    def _millis_s(self, millis: int) -> float:
        """When ``millis()`` first reads ``millis`` (or more), simulated seconds."""
        if self.config.whole_lines:
            return self._powered_s + millis / 1000.0
        if millis <= 0:
            return self._powered_s
        extra, unit = _AVR_MILLIS_FRACT
        overflows = max(1, millis * unit // (unit + extra) - 1)
        while overflows + overflows * extra // unit < millis:
            overflows += 1
        return self._powered_s + TIMER0_START_S + overflows * self._overflow_s

    def _auto_report(self, service: str, event: _AutoEvent, now_s: float) -> None:
        """A USB board: the service's auto-events due up to ``now_s``: one each time the
        firmware's loop finds ``tick >= nextTrigger``, then ``nextTrigger = tick + interval``
        (32 bits); it looks again at the next ms."""
        free_s = -math.inf
        for _ in range(_MOST_EVENTS_A_STEP):
            at_s = max(self._powered_s + event.due_ms() / 1000.0, free_s)
            if at_s > now_s + 1e-9:
                return
            tick = self._millis(at_s)
            self._report(service)
            free_s = at_s + 0.001
            event.next_tick = (tick + event.interval_ms) & event.tick_mask
            event.checked_ms = max(tick, self._millis(free_s))

    def pending_input_bytes(self) -> int:
        """Request bytes received and not yet a whole message (a frame the host has not
        finished), those still on a UART board's line included."""
        if self.config.whole_lines:  # a USB board: nothing waits on a line
            return self.codec.pending_bytes()
        return self.codec.pending_bytes() + self._line.pending_bytes()

    def read_output(self) -> bytes:
        """Take the bytes written since the last call (on a UART board, those its USART has
        taken by the simulation's time: the rest wait in its transmit buffer)."""
        if not self.config.whole_lines:
            self._out += self._transmitter.take_handed(self._now_s)
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Stop both motors and their PID."""
        for index in (0, 1):
            self._stop_wheel(index)

    # ------------------------------------------------------------------------------ helpers

    def _send(self, message: object) -> None:
        self._write(self.codec.send(message))

    def _write(self, data: bytes) -> None:
        if self.config.whole_lines:
            self._out += data
        else:  # the firmware's time writing it, and the line's sending it
            self._clock_s = self._transmitter.write(data, self._clock_s)

    def _serve_line(self, until_s: float) -> None:
        """A UART board's firmware up to ``until_s``: each request read with the bytes that
        have arrived by the time the firmware reads them (on its own clock, which its replies
        move on), each timed read waiting for the next byte or its 1 s timeout."""
        codec, line = self.codec, self._line
        if (
            line.next_arrival_s() > until_s + 1e-9
            and not codec.pending_bytes()
            and not codec.waiting
        ):
            # Nothing arrives by then and nothing is left to read: the firmware's loop finds
            # nothing, most steps. (A skip of the rest of a line that the last answer left
            # pending is done at the next read, on the firmware's clock, before what comes
            # next arrives: nothing is skipped, as when it is done now.)
            return
        while self._clock_s <= until_s + 1e-9:  # (a firmware still writing reads on later)
            progressed = self._take_arrived()
            while True:
                try:
                    message = codec.next_message()
                except RemoteProtocolError:
                    progressed = True  # dropped without a word, as the firmware does
                    continue
                if message is None:
                    break
                progressed = True
                self._handle(message, self._clock_s)
                self._take_arrived()  # what came while it answered
                self._skip_rest_of_line()  # at once, as asip.cpp does after its answer
                if self._clock_s > until_s:
                    return  # it reads on, with what has come meanwhile, later
            if progressed:
                self._wait_since_s = self._clock_s  # a timed read waits from now on
            arrival_s = line.next_arrival_s()
            timeout_s = self._wait_since_s + _PARSE_TIMEOUT_S if codec.waiting else math.inf
            if min(arrival_s, timeout_s) > until_s + 1e-9:
                return
            if timeout_s < arrival_s:
                self._clock_s = self._wait_since_s = max(self._clock_s, timeout_s)
                codec.parse_timeout()
            elif codec.waiting or self._clock_s >= arrival_s:
                self._clock_s = max(self._clock_s, arrival_s)  # read at once
            else:
                self._clock_s = arrival_s + REQUEST_S  # found at its next loop turn

    def _skip_rest_of_line(self) -> None:
        """The firmware skips the rest of a request's line after answering it
        (``asip.cpp``: ``while (serial->available() && serial->read() != '\\n')``), a byte
        per :data:`SKIP_BYTE_S` of its time: a byte that arrives meanwhile is skipped too."""
        codec = self.codec
        while codec.skip_pending:
            dropped = codec.skip_received()
            self._clock_s += dropped * SKIP_BYTE_S
            if codec.skip_pending and not self._take_arrived():
                codec.end_skip()

    def _take_arrived(self) -> bool:
        """Hand the codec the bytes that have arrived by the firmware's clock, less those
        that found the receive ring full."""
        arrived = self._line.take_arrived(self._clock_s)
        if not arrived:
            return False
        if not self.codec.waiting:
            # Bytes the codec holds outside a timed read are the ring's unread bytes; a
            # firmware inside a timed read reads each byte as it comes and never fills it.
            room = max(0, RECEIVE_RING_BYTES - self.codec.pending_bytes())
            arrived = arrived[:room]
        self.codec.receive_data(arrived)
        return True

    def _error(self, service: str, tag: str, code: m.ErrorCode) -> None:
        self._send(m.ErrorReply(service, tag, int(code)))

    def _process(self, now_s: float) -> None:
        # The firmware drops what it cannot parse, silently.
        for message in readable(self.codec):
            self._handle(message, now_s)

    def _set_pwm(self, index: int, pwm: int) -> None:
        wheel = self.state.wheels[index]
        limit = self.config.max_pwm
        wheel.pwm = max(-limit, min(limit, pwm))
        powers = [w.pwm / limit for w in self.state.wheels]
        self.body.set_power(powers[0], powers[1])

    def _stop_wheel(self, index: int) -> None:
        self.state.wheels[index].pid_active = False
        self._set_pwm(index, 0)

    def _start_pid(self, index: int, rpm: int, duration_ms: int, now_s: float) -> None:
        wheel = self.state.wheels[index]
        if rpm == 0:  # V1.1 ignores r with rpm 0
            return
        wheel.pid_active = True
        wheel.start_s = wheel.prev_pulse_s = now_s
        wheel.duration_s = duration_ms / 1000.0
        wheel.prev_input = wheel.prev_output = 0
        wheel.target_ticks_per_s = rpm * self.body.spec.ticks_per_rev // 60

    # -------------------------------------------------------------------------- motor frame

    def _motor_frame(self, now_s: float) -> None:
        ticks = self.body.ticks
        for index, wheel in enumerate(self.state.wheels):
            wheel.delta = ticks[index] - wheel.last_ticks
            wheel.last_ticks = ticks[index]
            if wheel.pid_active:
                self._service_pid(index, wheel, now_s)
        if self.state.encoder_events:
            counts = tuple((w.delta, w.last_ticks - w.total_offset) for w in self.state.wheels)
            self._send(m.EncoderEvent(counts))

    def _service_pid(self, index: int, wheel: _Wheel, now_s: float) -> None:
        cfg = self.config
        if now_s - wheel.start_s > wheel.duration_s:
            self._stop_wheel(index)
            return
        encoder = wheel.delta
        if encoder != 0:
            wheel.prev_pulse_s = now_s
        elif now_s - wheel.prev_pulse_s > _AUTO_STOP_S:
            self._stop_wheel(index)
            return
        frame_ms = round(_MOTOR_FRAME_S * 1000)
        target = wheel.target_ticks_per_s * frame_ms // 1000
        error = target - encoder
        pid = _cdiv(cfg.kp * error - cfg.kd * (encoder - wheel.prev_input) + wheel.iterm, cfg.ko)
        pid = max(-cfg.max_pwm_delta, min(cfg.max_pwm_delta, pid))
        output = pid + wheel.prev_output
        if output >= cfg.max_pwm:
            output = cfg.max_pwm
        elif output <= -cfg.max_pwm:
            output = -cfg.max_pwm
        else:
            wheel.iterm += cfg.ki * error
        wheel.prev_output = output
        wheel.prev_input = encoder
        self._set_pwm(index, output)

    # --------------------------------------------------------------------------- reporting

    def _report(self, service: str) -> None:
        body = self.body
        if service == "I":
            values = tuple(
                (chan, 512 + (pin * 37) % 200)
                for pin, chan in _ANALOG_PINS.items()
                if chan in self.state.analog_channels
            )
            if values:
                self._send(m.AnalogEvent(values))
        elif service == "B":
            self._send(
                m.BumpEvent(tuple(0 if pressed else 1 for pressed in body.bumpers_pressed()))
            )
        elif service == "R":
            self._send(m.IrEvent(body.line_readings()))
        elif service == "D":
            self._send(m.DistanceEvent(self._distances_cm()))

    def _distances_cm(self) -> tuple[int, ...]:
        # Two HC-SR04 sensors on the distance service: 0 faces forward, 1 faces right.
        readings = (self.body.range_mm(), self.body.side_range_mm())
        return tuple(0 if r is None else int(r // 10) for r in readings)

    # ------------------------------------------------------------------------------ requests

    def _handle(self, msg: object, now_s: float) -> None:
        state = self.state
        self._due_s = None  # it may change an auto-event
        if isinstance(msg, m.InvalidServiceRequest):
            self._error(msg.service, "?", m.ErrorCode.INVALID_SERVICE)
        elif isinstance(msg, m.RefusedRequest):
            self._error(msg.service, msg.tag, m.ErrorCode(msg.errno))
        elif isinstance(msg, m.VersionRequest):
            self._send(
                m.VersionReply(1, 1, self.config.chip, len(_PIN_SERVICES), self.config.sketch)
            )
        elif isinstance(msg, m.ServiceNamesRequest):
            self._send(m.ServiceNamesReply(tuple(_SERVICE_NAMES.items())))
        elif isinstance(msg, m.PinServicesRequest):
            self._send(m.PinServicesReply(tuple(_PIN_SERVICES)))
        elif isinstance(msg, m.RestartRequest):
            self.stop_all()
            # asipIO.reset() frees every pin it may: reserved and service pins stay.
            state.pin_modes = [
                mode if mode >= m.PinMode.RESERVED else int(m.PinMode.UNALLOCATED)
                for mode in state.pin_modes
            ]
            for event in state.auto.values():
                event.interval_ms = 0
            state.motor_frames = False  # reset() zeroes every auto-report, the PID's too
        elif isinstance(msg, m.SetAutoEventInterval):
            if msg.service in state.auto:
                state.auto[msg.service].start(msg.interval_ms, self._millis(now_s))
        elif isinstance(msg, m.MeasureRequest):
            if msg.service == "D":
                self._send(m.DistanceEvent(self._distances_cm()))
            else:
                self._error(msg.service, "M", m.ErrorCode.UNKNOWN_REQUEST)
        elif isinstance(msg, m.EnableEncoderEvents):
            state.encoder_events = msg.enabled
        elif isinstance(msg, m.SetMotorPower):
            # As on the board, power does not stop a running PID: its next frame overrides it.
            if msg.motor < 2:
                self._set_pwm(msg.motor, msg.power_pct * self.config.max_pwm // 100)
        elif isinstance(msg, m.SetMotorsPower):
            for index, power in enumerate((msg.power0_pct, msg.power1_pct)):
                self._set_pwm(index, power * self.config.max_pwm // 100)
        elif isinstance(msg, m.StopMotor):
            if msg.motor < 2:
                self._stop_wheel(msg.motor)
        elif isinstance(msg, m.StopMotors):
            self.stop_all()
        elif isinstance(msg, m.ResetEncoders):
            for wheel in state.wheels:
                wheel.total_offset = wheel.last_ticks
        elif isinstance(msg, m.SetMotorRpm | m.SetMotorsRpm | m.SetRobotSpeed | m.RotateRobot):
            self._pid_request(msg, now_s)
        elif isinstance(msg, m.PlayTone):
            self.body.log.tones.append((now_s, float(msg.frequency_hz), msg.duration_ms / 1000.0))
        elif isinstance(msg, m.LcdWrite | m.LcdWriteAt | m.LcdClear | m.LcdBarGraph):
            self._lcd(msg)
        elif isinstance(msg, m.ServoWrite):
            # The codec refused ids past the last servo while reading them.
            if msg.servo < len(state.servos_deg):
                state.servos_deg[msg.servo] = msg.angle_deg
        elif isinstance(
            msg,
            m.PixelsSet
            | m.PixelsSetRgb
            | m.PixelsSequence
            | m.PixelsSequenceRgb
            | m.PixelsBrightness
            | m.PixelsInfoRequest
            | m.PixelsClear,
        ):
            self._pixels(msg)
        else:
            self._io_or_unknown(msg)

    def _pid_request(self, msg: object, now_s: float) -> None:
        tags = {m.SetMotorRpm: "r", m.SetMotorsRpm: "R", m.SetRobotSpeed: "c", m.RotateRobot: "a"}
        if not self.config.firmware_pid:
            self._error("M", tags[type(msg)], m.ErrorCode.UNKNOWN_REQUEST)
            return
        wheel_circ_mm = math.pi * self.body.spec.wheel_diameter_mm
        if isinstance(msg, m.SetMotorRpm):
            if msg.motor < 2:
                self._start_pid(msg.motor, msg.rpm, msg.duration_ms, now_s)
        elif isinstance(msg, m.SetMotorsRpm):
            self._start_pid(0, msg.rpm0, msg.duration_ms, now_s)
            self._start_pid(1, msg.rpm1, msg.duration_ms, now_s)
        elif isinstance(msg, m.SetRobotSpeed):
            rpm = int(60 * msg.speed_cm_s / (wheel_circ_mm / 10.0))
            self._start_pid(0, rpm, msg.duration_ms, now_s)
            self._start_pid(1, rpm, msg.duration_ms, now_s)
        elif isinstance(msg, m.RotateRobot):
            # rotateRobot(dps, angle), with the firmware's integer rounding.
            track_circ_mm = math.pi * self.body.spec.track_mm
            duration = abs(msg.angle_deg * 1000 // msg.turn_rate_deg_s) if msg.angle_deg else 0
            distance = int(track_circ_mm * msg.angle_deg / 360.0)
            if duration == 0 or distance == 0:
                return
            speed = _cdiv(distance * 100, duration)
            if speed == 0:
                return
            duration = abs(_cdiv(distance * 100, speed))
            rpm = int(60 * speed / (wheel_circ_mm / 10.0))
            self._start_pid(0, rpm, duration, now_s)
            self._start_pid(1, -rpm, duration, now_s)

    def _pixels(self, msg: object) -> None:
        state = self.state
        strip = getattr(msg, "strip", 0)
        tag = {
            m.PixelsSet: "P", m.PixelsSetRgb: "p", m.PixelsSequence: "S",
            m.PixelsSequenceRgb: "s", m.PixelsBrightness: "B", m.PixelsInfoRequest: "I",
            m.PixelsClear: "C",
        }[type(msg)]  # fmt: skip
        if strip != 0:
            self._error("P", tag, m.ErrorCode.INVALID_DEVICE_NUMBER)
            return

        def unpack(color: int) -> tuple[int, int, int]:
            return (color >> 16) & 0xFF, (color >> 8) & 0xFF, color & 0xFF

        updates: list[tuple[int, tuple[int, int, int]]] = []
        if isinstance(msg, m.PixelsSet):
            updates = [(pixel, unpack(color)) for pixel, color in msg.pixels]
        elif isinstance(msg, m.PixelsSetRgb):
            updates = list(msg.pixels)
        elif isinstance(msg, m.PixelsSequence):
            updates = [(msg.first + i, unpack(c)) for i, c in enumerate(msg.colors)]
        elif isinstance(msg, m.PixelsSequenceRgb):
            updates = [(msg.first + i, rgb) for i, rgb in enumerate(msg.colors)]
        elif isinstance(msg, m.PixelsBrightness):
            state.brightness = msg.level
        elif isinstance(msg, m.PixelsInfoRequest):
            self._send(m.PixelsInfoReply(0, len(state.pixels)))
        else:
            state.pixels = [(0, 0, 0)] * len(state.pixels)
        for pixel, rgb in updates:
            if 0 <= pixel < len(state.pixels):  # the library ignores pixels past the end
                state.pixels[pixel] = rgb

    def _lcd(self, msg: object) -> None:
        rows = self.state.lcd
        if isinstance(msg, m.LcdWrite | m.LcdWriteAt):
            # strlcpy into the row from the column: at most 20 - column characters, then NUL
            # (a row shows up to its first NUL, so a gap before the column hides the text).
            column = msg.column if isinstance(msg, m.LcdWriteAt) else 0
            text = msg.text.encode("ascii")[: _LCD_ROW_BYTES - 1 - column]
            row = rows[msg.line]
            row[column : column + len(text) + 1] = text + b"\0"
        elif isinstance(msg, m.LcdClear):
            for row in rows:
                row[:] = bytes(_LCD_ROW_BYTES)
        self.body.log.display = "\n".join(row for row in self.state.lcd_rows if row)

    def _io_or_unknown(self, msg: object) -> None:
        state = self.state
        if isinstance(msg, m.PortMapRequest):
            self._send(m.PortMapReply(_PORT_MAP))
        elif isinstance(msg, m.AnalogMapRequest):
            self._send(m.AnalogMapReply(tuple(_ANALOG_PINS.items())))
        elif isinstance(msg, m.PinModesRequest):
            self._send(m.PinModesReply(tuple(state.pin_modes)))
        elif isinstance(msg, m.CapabilitiesRequest):
            caps = tuple(
                1 | (2 if pin in _ANALOG_PINS else 0) | (4 if pin in _PWM_PINS else 0)
                for pin in range(len(_PIN_SERVICES))
            )
            self._send(m.CapabilitiesReply(caps))
        elif isinstance(msg, m.SetPinMode):
            self._set_pin_mode(msg.pin, int(msg.mode))
        elif isinstance(msg, m.UnknownRequest) and msg.service == "I" and msg.tag == "P":
            self._set_pin_mode(msg.args[0], msg.args[1])  # a mode number the firmware lacks
        elif isinstance(msg, m.DigitalWrite):
            modes = (m.PinMode.OUTPUT, m.PinMode.INPUT, m.PinMode.INPUT_PULLUP)
            if msg.pin >= len(_PIN_SERVICES):
                self._error("I", "d", m.ErrorCode.INVALID_PIN)
            elif state.pin_modes[msg.pin] not in modes:
                self._error("I", "d", m.ErrorCode.WRONG_MODE)
        elif isinstance(msg, m.AnalogWrite):
            # AnalogWrite: a pin that cannot do PWM is invalid; a PWM pin reserved or owned
            # by another service is in the wrong mode.
            if msg.pin not in _PWM_PINS:
                self._error("I", "a", m.ErrorCode.INVALID_PIN)
            elif state.pin_modes[msg.pin] >= m.PinMode.RESERVED:
                self._error("I", "a", m.ErrorCode.WRONG_MODE)
        elif isinstance(msg, m.UnknownRequest) and msg.service not in "TLS":
            # (tone and LCD ignore unknown tags silently; the servo service answers its own)
            self._error(msg.service, msg.tag, m.ErrorCode.UNKNOWN_REQUEST)
        elif isinstance(msg, m.UnknownRequest) and msg.service == "S" and msg.tag != "W":
            self._error("S", msg.tag, m.ErrorCode.UNKNOWN_REQUEST)

    def _set_pin_mode(self, pin: int, mode: int) -> None:
        """asipIO's ``PinMode``, then the ports report and the error, in the firmware's order."""
        state = self.state
        pin_count = len(_PIN_SERVICES)
        current = state.pin_modes[pin] if pin < pin_count else int(m.PinMode.INVALID)
        error: m.ErrorCode | None = m.ErrorCode.INVALID_MODE
        is_input = mode in (m.PinMode.INPUT, m.PinMode.INPUT_PULLUP)
        if current == m.PinMode.RESERVED:
            error = m.ErrorCode.MODE_UNAVAILABLE
        elif pin < pin_count:
            # The reporting flags change before the pin is registered, so a refused request
            # still changes what is reported.
            if pin in _ANALOG_PINS:
                state.analog_channels.discard(_ANALOG_PINS[pin])
                if mode == m.PinMode.ANALOG:
                    state.analog_channels.add(_ANALOG_PINS[pin])
            port, bit = _PORT_MAP[pin]
            mask = state.report_masks.get(port, 0) & ~bit
            state.report_masks[port] = mask | (bit if is_input else 0)
            allowed = (
                m.PinMode.UNALLOCATED,
                m.PinMode.INPUT,
                m.PinMode.INPUT_PULLUP,
                m.PinMode.OUTPUT,
            )
            if (
                mode in allowed
                or (mode == m.PinMode.ANALOG and pin in _ANALOG_PINS)
                or (mode == m.PinMode.PWM and pin in _PWM_PINS)
            ):
                if current < m.PinMode.RESERVED:
                    state.pin_modes[pin] = mode
                    error = None
                else:
                    error = m.ErrorCode.MODE_UNAVAILABLE
        if is_input:
            self._send_port_changes(force=True)
        if error is not None:
            self._error("I", "P", error)

    def _pin_level(self, pin: int) -> int:
        if pin in _BUMP_PINS:
            pressed = self.body.bumpers_pressed()
            index = _BUMP_PINS.index(pin)
            return 0 if index < len(pressed) and pressed[index] else 1
        if pin in _ENCODER_PINS:
            wheel, line = _ENCODER_PINS[pin]
            return _QUADRATURE[self.body.ticks[wheel] % 4][line]
        return 1 if self.state.pin_modes[pin] == m.PinMode.INPUT_PULLUP else 0

    def _send_port_changes(self, *, force: bool) -> None:
        """``sendDigitalPortChanges``: each port with a non-zero report mask, in the order the
        firmware assigned them, when its masked level changed (or always, when forced)."""
        state = self.state
        if not any(state.report_masks.values()):
            return
        for port in dict.fromkeys(port for port, _ in _PORT_MAP):
            mask = state.report_masks.get(port, 0)
            if not mask:
                continue
            data = 0
            for pin, (pin_port, bit) in enumerate(_PORT_MAP):
                if pin_port == port and mask & bit and self._pin_level(pin):
                    data |= bit
            if force or data != state.port_levels.get(port, 0):
                self._send(m.DigitalPortEvent(port, data))
                state.port_levels[port] = data


def simulated_device(profile: RobotProfile) -> Callable[[Body], MirtoBoard]:
    """The ASIP unit's simulated device factory: a MIRTO board, with firmware PID or without
    as the profile says."""
    options = AsipOptions.from_mapping(profile.options, profile=profile.name)
    config = BoardConfig(
        firmware_pid=profile.firmware_pid,
        servo_count=options.servo_count,
        pixel_count=options.pixel_count,
        whole_lines=options.whole_lines,
        int_bits=options.int_bits,
        resets_on_connect=options.reset_on_connect,
    )
    return lambda body: MirtoBoard(body, config)
