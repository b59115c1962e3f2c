"""ASIP 1.1 messages, one frozen dataclass per request and reply.

Requests travel host -> board as ``<service>,<tag>[,args]\\n``; replies travel board -> host as
``@`` events, ``~`` errors and ``!`` info lines (see ``../shared`` protocol facts, section 1).
Field names carry their units. Values are checked when a message is built, so an out-of-range
request never reaches the wire (:class:`~roboscript.errors.LocalProtocolError`).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from roboscript.errors import LocalProtocolError

__all__ = [
    "ERROR_TEXTS",
    "AccelerometerEvent",
    "AnalogEvent",
    "AnalogMapReply",
    "AnalogMapRequest",
    "AnalogWrite",
    "AsipMessage",
    "BumpEvent",
    "CapabilitiesReply",
    "CapabilitiesRequest",
    "DebugEchoRequest",
    "DebugLine",
    "DigitalPortEvent",
    "DigitalWrite",
    "DistanceEvent",
    "EnableEncoderEvents",
    "EncoderEvent",
    "ErrorCode",
    "ErrorReply",
    "GenericEvent",
    "GyroEvent",
    "HeadingEvent",
    "IgnoredRequest",
    "InfoLine",
    "InvalidServiceRequest",
    "IrEvent",
    "LcdBarGraph",
    "LcdClear",
    "LcdWrite",
    "LcdWriteAt",
    "LegacyEncoderEvent",
    "MeasureRequest",
    "PinMode",
    "PinModesReply",
    "PinModesRequest",
    "PinServicesReply",
    "PinServicesRequest",
    "PixelsBrightness",
    "PixelsClear",
    "PixelsInfoReply",
    "PixelsInfoRequest",
    "PixelsSequence",
    "PixelsSequenceRgb",
    "PixelsSet",
    "PixelsSetRgb",
    "PlayTone",
    "PortMapReply",
    "PortMapRequest",
    "PressureEvent",
    "RefusedRequest",
    "ResetEncoders",
    "RestartRequest",
    "RotateRobot",
    "ServiceNamesReply",
    "ServiceNamesRequest",
    "ServoWrite",
    "SetAutoEventInterval",
    "SetMotorPower",
    "SetMotorRpm",
    "SetMotorsPower",
    "SetMotorsRpm",
    "SetPinMode",
    "SetRobotSpeed",
    "StartupLine",
    "StopMotor",
    "StopMotors",
    "UnknownRequest",
    "VersionReply",
    "VersionRequest",
    "WifiConfig",
]


class PinMode(enum.IntEnum):
    """Pin modes of ``I,P`` and ``@I,p`` (V1.1 ``asip.h`` ``pinMode_t``)."""

    UNALLOCATED = 0
    INPUT = 1
    INPUT_PULLUP = 2
    OUTPUT = 3
    ANALOG = 4
    PWM = 5
    RESERVED = 6
    OTHER_SERVICE = 7
    INVALID = 8


class ErrorCode(enum.IntEnum):
    """Error numbers of ``~`` replies."""

    NO_ERROR = 0
    INVALID_SERVICE = 1
    UNKNOWN_REQUEST = 2
    INVALID_PIN = 3
    MODE_UNAVAILABLE = 4
    INVALID_MODE = 5
    WRONG_MODE = 6
    INVALID_DEVICE_NUMBER = 7
    DEVICE_NOT_AVAILABLE = 8
    I2C_NOT_ENABLED = 9


ERROR_TEXTS: dict[int, str] = {code: code.name for code in ErrorCode}
# The firmware's text for 9 has spaces, not underscores.
ERROR_TEXTS[ErrorCode.I2C_NOT_ENABLED] = "I2C NOT ENABLED"


def _check(condition: bool, message: str) -> None:
    if not condition:
        raise LocalProtocolError(message)


def _check_range(name: str, value: int, low: int, high: int) -> None:
    _check(low <= value <= high, f"{name} must be in {low}..{high}, got {value}")


def _check_text(name: str, text: str) -> None:
    _check("\n" not in text and "\r" not in text, f"{name} must not contain a line break")
    _check(text.isascii(), f"{name} must be ASCII")


# --------------------------------------------------------------------------------------------
# Requests: host -> board


@dataclass(frozen=True, slots=True)
class VersionRequest:
    """``#,?``: ask for the ASIP version, chip and sketch."""


@dataclass(frozen=True, slots=True)
class ServiceNamesRequest:
    """``#,N``: ask for the services the sketch runs."""


@dataclass(frozen=True, slots=True)
class PinServicesRequest:
    """``#,S``: ask which service owns each pin."""


@dataclass(frozen=True, slots=True)
class RestartRequest:
    """``#,R``: reset every service and stop every auto-event. The board does not reply."""


@dataclass(frozen=True, slots=True)
class DebugEchoRequest:
    """``!text``: text the board echoes to its debug output."""

    text: str

    def __post_init__(self) -> None:
        _check_text("text", self.text)


@dataclass(frozen=True, slots=True)
class WifiConfig:
    """``$$,ssid,password`` (ASIP 1.2): WiFi credentials of 2-31 characters each."""

    ssid: str
    password: str

    def __post_init__(self) -> None:
        for name, value in (("ssid", self.ssid), ("password", self.password)):
            _check_text(name, value)
            _check(2 <= len(value) <= 31, f"{name} must have 2-31 characters")
            _check("," not in value, f"{name} must not contain a comma")


@dataclass(frozen=True, slots=True)
class SetPinMode:
    """``I,P,pin,mode``: set a pin's mode. Modes 1 and 2 get an ``@I,d`` reply at once."""

    pin: int
    mode: PinMode

    def __post_init__(self) -> None:
        _check_range("pin", self.pin, 0, 255)
        _check_range("mode", int(self.mode), 0, 8)


@dataclass(frozen=True, slots=True)
class DigitalWrite:
    """``I,d,pin,value``: drive a digital output low (0) or high (1)."""

    pin: int
    value: int

    def __post_init__(self) -> None:
        _check_range("pin", self.pin, 0, 255)
        _check_range("value", self.value, 0, 1)


@dataclass(frozen=True, slots=True)
class AnalogWrite:
    """``I,a,pin,value``: PWM duty 0-255 on a PWM pin."""

    pin: int
    value: int

    def __post_init__(self) -> None:
        _check_range("pin", self.pin, 0, 255)
        _check_range("value", self.value, 0, 255)


@dataclass(frozen=True, slots=True)
class PortMapRequest:
    """``I,M``: ask for the port/bit mask of every pin."""


@dataclass(frozen=True, slots=True)
class AnalogMapRequest:
    """``I,m``: ask for the digital pin -> analog channel map."""


@dataclass(frozen=True, slots=True)
class PinModesRequest:
    """``I,p``: ask for every pin's mode."""


@dataclass(frozen=True, slots=True)
class CapabilitiesRequest:
    """``I,c``: ask for every pin's capabilities."""


AUTO_EVENT_SERVICES = frozenset("IEBRDAGHP")
MEASURE_SERVICES = frozenset("DAGHP")


@dataclass(frozen=True, slots=True)
class SetAutoEventInterval:
    """``<svc>,A,ms``: report a service's values every ``interval_ms`` (0 stops them).

    Services: ``I`` analog inputs, ``B`` bumpers, ``R`` IR line, ``D`` distance, ``A``
    accelerometer, ``G`` gyro, ``H`` heading, ``P`` pressure, ``E`` legacy encoders. The motor
    service uses :class:`EnableEncoderEvents` instead.
    """

    service: str
    interval_ms: int

    def __post_init__(self) -> None:
        _check(self.service in AUTO_EVENT_SERVICES, f"service {self.service!r} has no auto-events")
        # the firmware's unsigned int: 16 bits on an ATmega328P, 32 on a Teensy 3.1
        _check_range("interval_ms", self.interval_ms, 0, 0xFFFF_FFFF)


@dataclass(frozen=True, slots=True)
class MeasureRequest:
    """``<svc>,M``: measure once (``D`` distance, ``A``, ``G``, ``H``, ``P``)."""

    service: str

    def __post_init__(self) -> None:
        _check(self.service in MEASURE_SERVICES, f"service {self.service!r} cannot measure once")


@dataclass(frozen=True, slots=True)
class SetMotorPower:
    """``M,m,id,power``: open-loop power of one motor, percent; positive drives forward."""

    motor: int
    power_pct: int

    def __post_init__(self) -> None:
        _check_range("motor", self.motor, 0, 15)
        _check_range("power_pct", self.power_pct, -100, 100)


@dataclass(frozen=True, slots=True)
class SetMotorsPower:
    """``M,M,p0,p1``: open-loop power of motors 0 and 1, percent."""

    power0_pct: int
    power1_pct: int

    def __post_init__(self) -> None:
        _check_range("power0_pct", self.power0_pct, -100, 100)
        _check_range("power1_pct", self.power1_pct, -100, 100)


@dataclass(frozen=True, slots=True)
class SetMotorRpm:
    """``M,r,id,rpm,ms``: firmware PID holds one wheel at ``rpm`` for ``duration_ms``."""

    motor: int
    rpm: int
    duration_ms: int

    def __post_init__(self) -> None:
        _check_range("motor", self.motor, 0, 15)
        _check_range("rpm", self.rpm, -1000, 1000)
        _check_range("duration_ms", self.duration_ms, 0, 2_147_483_647)


@dataclass(frozen=True, slots=True)
class SetMotorsRpm:
    """``M,R,rpm0,rpm1,ms``: firmware PID holds both wheels for ``duration_ms``."""

    rpm0: int
    rpm1: int
    duration_ms: int

    def __post_init__(self) -> None:
        _check_range("rpm0", self.rpm0, -1000, 1000)
        _check_range("rpm1", self.rpm1, -1000, 1000)
        _check_range("duration_ms", self.duration_ms, 0, 2_147_483_647)


@dataclass(frozen=True, slots=True)
class SetRobotSpeed:
    """``M,c,cm_s,ms``: both wheels at ``speed_cm_s`` (negative = backward) for a time."""

    speed_cm_s: int
    duration_ms: int

    def __post_init__(self) -> None:
        _check_range("speed_cm_s", self.speed_cm_s, -1000, 1000)
        _check_range("duration_ms", self.duration_ms, 0, 2_147_483_647)


@dataclass(frozen=True, slots=True)
class RotateRobot:
    """``M,a,deg_s,angle``: turn in place by ``angle_deg`` at ``turn_rate_deg_s``.

    The firmware takes the rate first (the seed has the order reversed). Positive angles
    turn the robot right (clockwise seen from above).
    """

    turn_rate_deg_s: int
    angle_deg: int

    def __post_init__(self) -> None:
        _check_range("turn_rate_deg_s", self.turn_rate_deg_s, 1, 3600)
        _check_range("angle_deg", self.angle_deg, -32768, 32767)


@dataclass(frozen=True, slots=True)
class StopMotor:
    """``M,s,id``: stop one motor."""

    motor: int

    def __post_init__(self) -> None:
        _check_range("motor", self.motor, 0, 15)


@dataclass(frozen=True, slots=True)
class StopMotors:
    """``M,S``: stop every motor (sent with a dummy argument, see the codec)."""


@dataclass(frozen=True, slots=True)
class ResetEncoders:
    """``M,E``: zero the cumulative encoder counts (sent with a dummy argument)."""


@dataclass(frozen=True, slots=True)
class EnableEncoderEvents:
    """``M,A,1|0``: turn ``@M,e`` encoder events (every 33 ms) on or off."""

    enabled: bool


@dataclass(frozen=True, slots=True)
class ServoWrite:
    """``S,W,id,angle``: move servo ``servo`` to ``angle_deg`` (0-180)."""

    servo: int
    angle_deg: int

    def __post_init__(self) -> None:
        _check_range("servo", self.servo, 0, 255)
        _check_range("angle_deg", self.angle_deg, 0, 180)


@dataclass(frozen=True, slots=True)
class PlayTone:
    """``T,P,hz,ms``: play a square-wave tone; the board ignores zero values."""

    frequency_hz: int
    duration_ms: int

    def __post_init__(self) -> None:
        _check_range("frequency_hz", self.frequency_hz, 1, 65535)
        _check_range("duration_ms", self.duration_ms, 1, 2_147_483_647)


LCD_LINES = 5
"""Text rows of the ASIP LCD service (``asipLCD``), 0 at the top."""
LCD_COLUMNS = 20
"""Characters a row shows: ``asipLCD`` keeps a row in 21 bytes, the last one its NUL."""


@dataclass(frozen=True, slots=True)
class LcdWrite:
    """``L,W,line,text``: write a line (0 = top, 5 lines of 20 characters; the board keeps
    the first 20 of the text and reads what follows them as the next request)."""

    line: int
    text: str

    def __post_init__(self) -> None:
        _check_range("line", self.line, 0, LCD_LINES - 1)
        _check_text("text", self.text)
        # Longer text would not be cut: the board reads what follows as new requests.
        _check_range("text length", len(self.text), 0, LCD_COLUMNS)


@dataclass(frozen=True, slots=True)
class LcdWriteAt:
    """``L,w,line,column,text``: write text from a line and column (0-based)."""

    line: int
    column: int
    text: str

    def __post_init__(self) -> None:
        _check_range("line", self.line, 0, LCD_LINES - 1)
        _check_range("column", self.column, 0, LCD_COLUMNS)  # the board takes column < 21
        _check_text("text", self.text)
        _check_range("text length", len(self.text), 0, LCD_COLUMNS - self.column)


@dataclass(frozen=True, slots=True)
class LcdBarGraph:
    """``L,G,n,{line:value,...}``: horizontal bars, value 0-100 percent."""

    bars: tuple[tuple[int, int], ...]

    def __post_init__(self) -> None:
        for line, value in self.bars:
            _check_range("line", line, 0, LCD_LINES - 1)
            _check_range("value", value, 0, 100)


@dataclass(frozen=True, slots=True)
class LcdClear:
    """``L,C``: clear the screen."""


def _check_rgb(rgb: tuple[int, int, int]) -> None:
    for channel in rgb:
        _check_range("colour channel", channel, 0, 255)


@dataclass(frozen=True, slots=True)
class PixelsSet:
    """``P,P,strip,n,{pixel:color,...}``: packed 24-bit colours ``r<<16 | g<<8 | b``."""

    strip: int
    pixels: tuple[tuple[int, int], ...]

    def __post_init__(self) -> None:
        for pixel, color in self.pixels:
            _check_range("pixel", pixel, 0, 65535)
            _check_range("color", color, 0, 0xFFFFFF)


@dataclass(frozen=True, slots=True)
class PixelsSetRgb:
    """``P,p,strip,n,{pixel:r:g:b,...}``: colours as three 0-255 channels."""

    strip: int
    pixels: tuple[tuple[int, tuple[int, int, int]], ...]

    def __post_init__(self) -> None:
        for pixel, rgb in self.pixels:
            _check_range("pixel", pixel, 0, 65535)
            _check_rgb(rgb)


@dataclass(frozen=True, slots=True)
class PixelsSequence:
    """``P,S,strip,n,first,{color,...}``: adjacent pixels from ``first``."""

    strip: int
    first: int
    colors: tuple[int, ...]

    def __post_init__(self) -> None:
        for color in self.colors:
            _check_range("color", color, 0, 0xFFFFFF)


@dataclass(frozen=True, slots=True)
class PixelsSequenceRgb:
    """``P,s,strip,n,first,{r:g:b,...}``: adjacent pixels from ``first``, as channels."""

    strip: int
    first: int
    colors: tuple[tuple[int, int, int], ...]

    def __post_init__(self) -> None:
        for rgb in self.colors:
            _check_rgb(rgb)


@dataclass(frozen=True, slots=True)
class PixelsBrightness:
    """``P,B,strip,level``: overall brightness 0-255 (default 64)."""

    strip: int
    level: int

    def __post_init__(self) -> None:
        _check_range("level", self.level, 0, 255)


@dataclass(frozen=True, slots=True)
class PixelsInfoRequest:
    """``P,I,strip``: ask for a strip's pixel count."""

    strip: int


@dataclass(frozen=True, slots=True)
class PixelsClear:
    """``P,C,strip``: turn a strip off."""

    strip: int


@dataclass(frozen=True, slots=True)
class InvalidServiceRequest:
    """A request for a service the board does not run (decoded on the board side only)."""

    service: str


@dataclass(frozen=True, slots=True)
class RefusedRequest:
    """A request the board refuses while reading it (decoded on the board side only).

    The servo service answers ``S,W`` on an id past its last servo before it reads the
    angle; the request ends there, and the board sends ``~service,tag,errno{TEXT}``.
    """

    service: str
    tag: str
    errno: int


@dataclass(frozen=True, slots=True)
class IgnoredRequest:
    """A known request the board reads whole and then does nothing with, without a word
    (decoded on the board side only): ``M,m,-1,50`` (the firmware keeps the motor id in a
    ``byte``, 255, past its wheels), ``L,W,-1,text`` (the text goes to a row before the
    first), the ``!`` header on a build without ``ASIP_DEBUG`` (service ``!``, tag ``""``)."""

    service: str
    tag: str
    args: tuple[int, ...] = ()


@dataclass(frozen=True, slots=True)
class UnknownRequest:
    """A request with a tag the service does not know (decoded on the board side only)."""

    service: str
    tag: str
    args: tuple[int, ...] = ()


# --------------------------------------------------------------------------------------------
# Replies: board -> host


@dataclass(frozen=True, slots=True)
class VersionReply:
    """``@#,?,major,minor,chip,pins,sketch``."""

    major: int
    minor: int
    chip: str
    pin_count: int
    sketch: str


@dataclass(frozen=True, slots=True)
class ServiceNamesReply:
    """``@#,N,n,{id:name,...}``."""

    services: tuple[tuple[str, str], ...]


@dataclass(frozen=True, slots=True)
class PinServicesReply:
    """``@#,S,pins,{c,c,...}``: ``@`` reserved, ``I`` IO, else the owning service's id."""

    services: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class PortMapReply:
    """``@I,M,pins,{port:MASK,...}``: each pin's port (decimal) and bit mask (hex)."""

    ports: tuple[tuple[int, int], ...]


@dataclass(frozen=True, slots=True)
class AnalogMapReply:
    """``@I,m,n,{dpin:achan,...}``."""

    pairs: tuple[tuple[int, int], ...]


@dataclass(frozen=True, slots=True)
class PinModesReply:
    """``@I,p,pins,{mode,...}``."""

    modes: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class CapabilitiesReply:
    """``@I,c,pins,{caps,...}``: bit 1 digital, 2 analog, 4 PWM."""

    capabilities: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class DigitalPortEvent:
    """``@I,d,port,MASK``: the input pins of one port (mask in hex)."""

    port: int
    mask: int


@dataclass(frozen=True, slots=True)
class AnalogEvent:
    """``@I,a,n,{channel:value,...}``: analog channels, values 0-1023."""

    values: tuple[tuple[int, int], ...]


@dataclass(frozen=True, slots=True)
class EncoderEvent:
    """``@M,e,2,{delta:total,...}``: pulses since the last event and since reset, per wheel."""

    counts: tuple[tuple[int, int], ...]

    @property
    def totals(self) -> tuple[int, ...]:
        """Cumulative pulse count of each encoder."""
        return tuple(total for _, total in self.counts)


@dataclass(frozen=True, slots=True)
class LegacyEncoderEvent:
    """``@E,e,n,{pulse_width_us:count,...}`` (ASIP 1.0 and earlier)."""

    values: tuple[tuple[int, int], ...]


@dataclass(frozen=True, slots=True)
class BumpEvent:
    """``@B,e,n,{v,...}``: raw switch levels, where 0 means pressed (pull-up input)."""

    raw: tuple[int, ...]

    @property
    def pressed(self) -> tuple[bool, ...]:
        """Whether each switch is pressed."""
        return tuple(value == 0 for value in self.raw)


@dataclass(frozen=True, slots=True)
class IrEvent:
    """``@R,e,n,{v,...}``: IR line sensor readings 0-1023 (higher = darker floor)."""

    values: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class DistanceEvent:
    """``@D,e,n,{cm,...}``: 0 means no echo (V1.2 I2C sensors report -1 when absent)."""

    distances_cm: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class AccelerometerEvent:
    """``@A,e,3,{x,y,z}``: raw int16 per axis."""

    x: int
    y: int
    z: int


@dataclass(frozen=True, slots=True)
class GyroEvent:
    """``@G,e,3,{x,y,z}``: raw int16 per axis."""

    x: int
    y: int
    z: int


@dataclass(frozen=True, slots=True)
class HeadingEvent:
    """``@H,e,4,{x,y,z,heading}``: magnetic flux per axis and heading in degrees."""

    x: int
    y: int
    z: int
    heading_deg: int


@dataclass(frozen=True, slots=True)
class PressureEvent:
    """``@P,e,3,{mbar,degC,m}``: floats with two decimals."""

    pressure_mbar: float
    temperature_c: float
    altitude_m: float


@dataclass(frozen=True, slots=True)
class PixelsInfoReply:
    """``@P,I,strip,count`` (the ASIP 0.4 form ``@P,I,count`` reads as strip 0)."""

    strip: int
    count: int


@dataclass(frozen=True, slots=True)
class GenericEvent:
    """An ``@`` line from a service roboscript has no model for; kept, not dropped."""

    service: str
    tag: str
    fields: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class ErrorReply:
    """``~svc,tag,errno{TEXT}``: the board refused a request."""

    service: str
    tag: str
    errno: int
    text: str = ""

    def __post_init__(self) -> None:
        if not self.text:
            object.__setattr__(self, "text", ERROR_TEXTS.get(self.errno, "UNKNOWN_ERROR"))


@dataclass(frozen=True, slots=True)
class StartupLine:
    """``!<sketch> running on <chip> with Services: I M ...`` sent when the sketch starts."""

    sketch: str
    chip: str
    services: tuple[str, ...] = field(default=())


@dataclass(frozen=True, slots=True)
class InfoLine:
    """``!text``: informational or debug text from the board."""

    text: str


@dataclass(frozen=True, slots=True)
class DebugLine:
    """A line with no ASIP prefix (sketch ``Serial.println`` output); clients ignore it."""

    text: str


AsipMessage = (
    VersionRequest
    | ServiceNamesRequest
    | PinServicesRequest
    | RestartRequest
    | DebugEchoRequest
    | WifiConfig
    | SetPinMode
    | DigitalWrite
    | AnalogWrite
    | PortMapRequest
    | AnalogMapRequest
    | PinModesRequest
    | CapabilitiesRequest
    | SetAutoEventInterval
    | MeasureRequest
    | SetMotorPower
    | SetMotorsPower
    | SetMotorRpm
    | SetMotorsRpm
    | SetRobotSpeed
    | RotateRobot
    | StopMotor
    | StopMotors
    | ResetEncoders
    | EnableEncoderEvents
    | ServoWrite
    | PlayTone
    | LcdWrite
    | LcdWriteAt
    | LcdBarGraph
    | LcdClear
    | PixelsSet
    | PixelsSetRgb
    | PixelsSequence
    | PixelsSequenceRgb
    | PixelsBrightness
    | PixelsInfoRequest
    | PixelsClear
    | InvalidServiceRequest
    | RefusedRequest
    | IgnoredRequest
    | UnknownRequest
    | VersionReply
    | ServiceNamesReply
    | PinServicesReply
    | PortMapReply
    | AnalogMapReply
    | PinModesReply
    | CapabilitiesReply
    | DigitalPortEvent
    | AnalogEvent
    | EncoderEvent
    | LegacyEncoderEvent
    | BumpEvent
    | IrEvent
    | DistanceEvent
    | AccelerometerEvent
    | GyroEvent
    | HeadingEvent
    | PressureEvent
    | PixelsInfoReply
    | GenericEvent
    | ErrorReply
    | StartupLine
    | InfoLine
    | DebugLine
)
"""Any ASIP message, either direction."""
