"""The firmware builds the tier runs: each published sketch, on the AVR it runs on here."""

from __future__ import annotations

from firmware.avr import ARDUINO_AVR, SHIMS, Recipe, firmware_root

MIRTLE_MCU = "atmega328p"
MIRTLE_F_CPU_HZ = 16_000_000
MIRTLE_BAUD = 57600
STACKMOD_BAUD = 9600
"""The author's sketch opens its UART at 9600 baud (``Serial.begin(9600)``)."""


def mirtle_328p() -> Recipe:
    """ASIP V1.1 with the MIRTO sketch ``mirtle2017``, as an ATmega328P (MIRTO 328 V2) build.

    Build facts: ``asipLCD.cpp`` compiles only for boards it lists as having the RAM for a
    frame buffer (``#error`` otherwise); the stand-in U8g2 keeps none, so it is compiled as one
    of the listed boards (``ESP8266``, which no other file tests). ``asipRobot.cpp`` includes
    ``"config.h"`` while the file is ``Config.h``: a generated ``config.h`` includes it.
    """
    asip = firmware_root() / "ASIP-V1.1"
    lib = asip / "ASIP" / "src"
    sources = [
        *sorted(lib.glob("*.cpp")),
        *sorted((lib / "services").glob("*.cpp")),
        *sorted((lib / "utility").glob("*.cpp")),
        *sorted((asip / "asipRobot").glob("*.cpp")),
        asip / "asipLCD" / "asipLCD.cpp",
        asip / "asipPixels" / "asipPixels.cpp",
        SHIMS / "libraries" / "Adafruit_NeoPixel.cpp",
        SHIMS / "libraries" / "Encoder.cpp",
    ]
    return Recipe(
        name="mirtle2017-atmega328p",
        mcu=MIRTLE_MCU,
        f_cpu_hz=MIRTLE_F_CPU_HZ,
        variant="standard",
        board_define="ARDUINO_AVR_UNO",
        sketch=asip / "asipRobot" / "examples" / "mirtle2017" / "mirtle2017.ino",
        sources=tuple(sources),
        include_dirs=(
            lib,
            asip / "asipRobot",
            asip / "asipLCD",
            asip / "asipPixels",
            SHIMS / "libraries",
            ARDUINO_AVR / "libraries" / "EEPROM" / "src",
        ),
        forced_includes=(SHIMS / "asip" / "mirtle_on_328p.h",),
        file_defines={"asipLCD.cpp": ("ESP8266",)},
        generated={"config.h": f'#include "{asip / "asipRobot" / "Config.h"}"\n'},
    )


def stackmod_328p() -> Recipe:
    """The StackMod author's motor-module sketch and ``Stackmodio`` library on an ATmega328P.

    The module listens on I2C; the stand-in ``Wire`` carries each I2C write over the UART as
    a length byte and the bytes (the emulator has no I2C master to talk to it).
    """
    root = firmware_root() / "StackMod" / "arduino" / "stackmod"
    library = root / "libraries" / "Stackmodio" / "src"
    return Recipe(
        name="stackmod-atmega328p",
        mcu="atmega328p",
        f_cpu_hz=16_000_000,
        variant="standard",
        board_define="ARDUINO_AVR_UNO",
        sketch=root / "stackmod.cpp",
        sources=(library / "Stackmodio.cpp", SHIMS / "stackmod" / "Wire.cpp"),
        include_dirs=(SHIMS / "stackmod", library),
    )


PLEN2_MCU = "atmega32u4"
PLEN2_F_CPU_HZ = 16_000_000
PLEN2_BAUD = 2_000_000
"""``System.h``: ``BLESERIAL_BAUDRATE = 2000000L`` (the firmware's UART, not a developer build)."""
PLEN2_EEPROM = ((0x50, 0x54), 0x10000)
"""``ExternalEEPROM.h``: a 24FC1025 (128 KiB, two address bytes) at 0x50; its upper 64 KiB
answer at 0x54 (the block-select bit), so the emulator attaches two 64 KiB parts."""


def plen2_32u4() -> Recipe:
    """PLEN2 firmware 1.4.2 (``plen-Firmware_Arduino``) on its ATmega32u4, replies on UART1."""
    root = firmware_root() / "plen-Firmware_Arduino" / "firmware"
    wire = ARDUINO_AVR / "libraries" / "Wire" / "src"
    sources = [*sorted(root.glob("*.cpp")), wire / "Wire.cpp", wire / "utility" / "twi.c"]
    return Recipe(
        name="plen2-atmega32u4",
        mcu=PLEN2_MCU,
        f_cpu_hz=PLEN2_F_CPU_HZ,
        variant="leonardo",
        board_define="ARDUINO_AVR_LEONARDO",
        sketch=root / "firmware.ino",
        sources=tuple(sources),
        include_dirs=(root, wire, ARDUINO_AVR / "libraries" / "EEPROM" / "src"),
        file_forced_includes={"System.cpp": (SHIMS / "plen2" / "replies_on_uart1.h",)},
        # the Arduino Micro's board entry (PLEN2's controller board is one)
        defines=(
            "USB_VID=0x2341",
            "USB_PID=0x8037",
            'USB_MANUFACTURER="Unknown"',
            'USB_PRODUCT="Arduino Micro"',
        ),
    )
