"""Build the robots' published firmware unchanged and run it on an emulated AVR (simavr).

The sources live beside the project (``../shared/firmware``, or ``$ROBOSCRIPT_FIRMWARE``) and
are never edited: what a board needs that the AVR build lacks comes from stand-ins in
``shims/`` (libraries Debian does not package; none holds protocol code) and from the few
build facts each :class:`Recipe` states. Builds are cached by the hash of everything that goes
into them, so the tier costs a compile once per machine.

:class:`Board` is one emulated board in lockstep: it runs only when told to advance, so what
the firmware does is decided by the simulated time alone, never by the machine's load.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Self

from helpers import HANG_BOUND_S

HERE = Path(__file__).resolve().parent
SHIMS = HERE / "shims"
HARNESS_SOURCE = HERE / "harness" / "avrboard.c"
ARDUINO_AVR = Path("/usr/share/arduino/hardware/arduino/avr")
TOOLS = ("avr-gcc", "avr-g++", "avr-ar", "avr-nm", "cc", "pkg-config")
ARDUINO_VERSION = "10807"
"""The Arduino IDE version Debian's arduino-core-avr 1.8.7 comes from."""
WROTE_OUTSIDE_RAM = 100
"""The harness's answer ``X 100``: the firmware wrote to the data space above its part's RAM,
which reads 0 there (an AVR core has no bus fault; ``harness/avrboard.c``)."""
CORE_FILE_DEFINES = {"WString.cpp": ("DECIMAL_DIG=__DECIMAL_DIG__",)}
"""Debian pairs core 1.8.7 with avr-gcc 5.4, whose ``float.h`` hides ``DECIMAL_DIG`` from
C++11; the compiler's own built-in value is the one a newer ``float.h`` would give."""


def firmware_root() -> Path:
    """Where the published firmware sources are: ``$ROBOSCRIPT_FIRMWARE``, or the nearest
    ``shared/firmware`` beside the checkout or one of its parent folders."""
    configured = os.environ.get("ROBOSCRIPT_FIRMWARE")
    if configured:
        return Path(configured)
    checkout = HERE.parents[1]
    for folder in checkout.parents:
        candidate = folder / "shared" / "firmware"
        if candidate.is_dir():
            return candidate
    return checkout.parent / "shared" / "firmware"


def cache_root() -> Path:
    """Where builds are kept between runs (``$ROBOSCRIPT_FIRMWARE_CACHE`` or the temp dir)."""
    configured = os.environ.get("ROBOSCRIPT_FIRMWARE_CACHE")
    root = Path(configured) if configured else Path(tempfile.gettempdir()) / "roboscript-firmware"
    root.mkdir(parents=True, exist_ok=True)
    return root


def missing_prerequisite() -> str | None:
    """Why the firmware tier cannot run here, in one line, or None when it can."""
    for tool in TOOLS:
        if shutil.which(tool) is None:
            return f"{tool} is not installed (Debian: gcc-avr avr-libc simavr libsimavr-dev)"
    if not (ARDUINO_AVR / "cores" / "arduino" / "Arduino.h").is_file():
        return f"the Arduino AVR core is not at {ARDUINO_AVR} (Debian: arduino-core-avr)"
    probe = subprocess.run(
        ["pkg-config", "--exists", "simavr", "simavrparts"], capture_output=True, check=False
    )
    if probe.returncode != 0:
        return "simavr's library is not installed (Debian: libsimavr-dev libelf-dev)"
    if not firmware_root().is_dir():
        return f"the published firmware sources are not at {firmware_root()}"
    return None


@dataclass(frozen=True)
class Recipe:
    """How one firmware is built for one AVR: its sources, in the Arduino IDE's way.

    Attributes:
        name: Cache and report name.
        mcu: avr-gcc's ``-mmcu`` and simavr's part name.
        f_cpu_hz: Clock, hertz.
        variant: Arduino core variant (pin tables).
        sketch: The sketch file (``.ino`` gets the IDE's treatment: Arduino.h, prototypes).
        sources: Library sources compiled with it.
        include_dirs: Header search path (before the core's).
        forced_includes: Headers included ahead of the sketch only (board facts the sketch
            expects its IDE board package to give).
        file_defines: Extra ``-D`` for named files, each with its reason in the recipe.
        file_forced_includes: Headers included ahead of named library files.
        defines: Extra ``-D`` for every file (board facts the IDE's board menu gives).
        generated: Extra headers written into the build (name -> text).
    """

    name: str
    mcu: str
    f_cpu_hz: int
    variant: str
    board_define: str
    sketch: Path
    sources: tuple[Path, ...]
    include_dirs: tuple[Path, ...]
    forced_includes: tuple[Path, ...] = ()
    file_defines: dict[str, tuple[str, ...]] = field(default_factory=dict)
    file_forced_includes: dict[str, tuple[Path, ...]] = field(default_factory=dict)
    defines: tuple[str, ...] = ()
    generated: dict[str, str] = field(default_factory=dict)

    def core_sources(self) -> list[Path]:
        core = ARDUINO_AVR / "cores" / "arduino"
        return sorted(p for p in core.iterdir() if p.suffix in {".c", ".cpp", ".S"})

    def common_flags(self) -> list[str]:
        return [
            f"-mmcu={self.mcu}",
            f"-DF_CPU={self.f_cpu_hz}L",
            f"-DARDUINO={ARDUINO_VERSION}",
            f"-D{self.board_define}",
            "-DARDUINO_ARCH_AVR",
            "-Os",
            "-w",
            "-ffunction-sections",
            "-fdata-sections",
            *(f"-D{define}" for define in self.defines),
        ]

    def key(self) -> str:
        """Hash of every input: sources, shims, flags and the compiler's version."""
        digest = hashlib.sha256()
        version = subprocess.run(["avr-gcc", "--version"], capture_output=True, check=True)
        digest.update(version.stdout)
        digest.update(repr((self, self.common_flags())).encode())
        files = [self.sketch, *self.sources, *self.forced_includes, *self.core_sources()]
        for headers in self.file_forced_includes.values():
            files.extend(headers)
        for folder in self.include_dirs:
            files.extend(sorted(p for p in folder.rglob("*") if p.is_file()))
        for path in files:
            digest.update(str(path).encode())
            digest.update(path.read_bytes())
        return digest.hexdigest()[:16]


def _sketch_as_cpp(sketch: Path, forced: tuple[Path, ...]) -> str:
    """What the Arduino IDE compiles for a ``.ino``: Arduino.h, prototypes, then the sketch."""
    text = sketch.read_text(encoding="utf-8", errors="replace")
    if sketch.suffix != ".ino":
        return text
    prototypes = re.findall(r"^(void\s+\w+\s*\(\s*\))\s*\n?\s*\{", text, flags=re.MULTILINE)
    head = ["#include <Arduino.h>"]
    head += [f'#include "{path}"' for path in forced]
    head += [f"{proto};" for proto in prototypes]
    head.append(f'#line 1 "{sketch}"')
    return "\n".join(head) + "\n" + text


def build(recipe: Recipe) -> Path:
    """Build ``recipe`` (or take it from the cache) and return the ELF file's path.

    Raises:
        subprocess.CalledProcessError: The toolchain refused a source (output attached).
    """
    out = cache_root() / f"{recipe.name}-{recipe.key()}"
    elf = out / "firmware.elf"
    if elf.is_file():
        return elf
    work = Path(tempfile.mkdtemp(prefix=f"{recipe.name}-", dir=cache_root()))
    generated = work / "generated"
    generated.mkdir()
    for name, text in recipe.generated.items():
        (generated / name).write_text(text, encoding="utf-8")
    sketch_cpp = generated / "sketch.cpp"
    sketch_cpp.write_text(_sketch_as_cpp(recipe.sketch, recipe.forced_includes), encoding="utf-8")
    core_dir = ARDUINO_AVR / "cores" / "arduino"
    includes = [
        generated,
        *recipe.include_dirs,
        core_dir,
        ARDUINO_AVR / "variants" / recipe.variant,
    ]
    include_flags = [f"-I{path}" for path in includes]
    objects: list[Path] = []
    for index, source in enumerate([*recipe.core_sources(), *recipe.sources, sketch_cpp]):
        obj = work / f"{index:03d}-{source.stem}.o"
        if source.suffix == ".c":
            compiler = ["avr-gcc", "-std=gnu11"]
        elif source.suffix == ".S":
            compiler = ["avr-gcc", "-x", "assembler-with-cpp"]
        else:
            compiler = ["avr-g++", "-std=gnu++11", "-fpermissive", "-fno-exceptions"]
            compiler += ["-fno-threadsafe-statics"]
        defines = CORE_FILE_DEFINES.get(source.name, ()) + recipe.file_defines.get(source.name, ())
        extra = [f"-D{d}" for d in defines]
        for header in recipe.file_forced_includes.get(source.name, ()):
            extra += ["-include", str(header)]
        command = [*compiler, *recipe.common_flags(), *extra, *include_flags, "-c", str(source)]
        _run([*command, "-o", str(obj)])
        objects.append(obj)
    linked = work / "firmware.elf"
    _run(
        [
            "avr-gcc",
            f"-mmcu={recipe.mcu}",
            "-Os",
            "-Wl,--gc-sections",
            *map(str, objects),
            "-lm",
            "-o",
            str(linked),
        ]
    )
    out.mkdir(exist_ok=True)
    os.replace(linked, elf)
    shutil.rmtree(work, ignore_errors=True)
    return elf


def symbol_address(elf: Path, name: str) -> int:
    """The data-space address of the variable ``name`` (demangled, as ``avr-nm -C`` prints
    it) in ``elf``.

    Raises:
        KeyError: The firmware has no such variable.
    """
    listing = subprocess.run(
        ["avr-nm", "-C", str(elf)], capture_output=True, text=True, check=True
    ).stdout
    for line in listing.splitlines():
        address, _, symbol = line.split(" ", 2)
        if symbol == name:
            return int(address, 16) & 0xFFFF  # the linker puts data space at 0x800000
    raise KeyError(name)


def harness() -> Path:
    """The lockstep harness (a small C program on libsimavr), compiled once per source."""
    source = HARNESS_SOURCE.read_bytes()
    key = hashlib.sha256(source).hexdigest()[:16]
    binary = cache_root() / f"avrboard-{key}"
    if binary.is_file():
        return binary
    flags = subprocess.run(
        ["pkg-config", "--cflags", "--libs", "simavr", "simavrparts"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    # a partial file of this process's own: test processes running at once may build it
    # together, and the one that finishes last replaces the same binary with its own
    partial = binary.with_suffix(f".{os.getpid()}.part")
    _run(["cc", "-O2", "-o", str(partial), str(HARNESS_SOURCE), *flags, "-lelf"])
    os.replace(partial, binary)
    return binary


def _run(command: list[str]) -> None:
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise subprocess.CalledProcessError(
            result.returncode, command, result.stdout, result.stderr
        )


class BoardStoppedError(RuntimeError):
    """The emulated AVR stopped running (crashed, or slept with interrupts off)."""


class Board:
    """One emulated board, advanced by the host in lockstep.

    Args:
        elf: The firmware.
        mcu: simavr's part name.
        f_cpu_hz: Clock, hertz.
        uart: Which UART the host's line is wired to (``"0"``, ``"1"``).
        baud: The line's speed, bits per second (the firmware's own ``Serial.begin``).
        eeprom: ``(i2c_addresses, bytes)``: an I2C EEPROM of that size (24xx-series, two
            address bytes, 128-byte pages; the harness's own model) on the TWI bus at each
            address, or None.
    """

    def __init__(
        self,
        elf: Path,
        mcu: str,
        f_cpu_hz: int,
        *,
        uart: str = "0",
        baud: int = 57600,
        eeprom: tuple[tuple[int, ...], int] | None = None,
    ) -> None:
        self.f_cpu_hz = f_cpu_hz
        self.baud = baud
        args = [str(harness()), str(elf), mcu, str(f_cpu_hz), uart, str(baud)]
        if eeprom is not None:
            args += [",".join(hex(address) for address in eeprom[0]), str(eeprom[1])]
        self._process = subprocess.Popen(
            args, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1
        )
        self.cycle = 0
        self.received = bytearray()
        """Every byte the board has sent, in order."""

    @property
    def pid(self) -> int:
        """The emulator's process id."""
        return self._process.pid

    @property
    def time_s(self) -> float:
        """The board's simulated time since power-on, seconds."""
        return self.cycle / self.f_cpu_hz

    def _ask(self, line: str) -> str:
        stdin, stdout = self._process.stdin, self._process.stdout
        assert stdin is not None and stdout is not None
        stdin.write(line + "\n")
        stdin.flush()
        answer = stdout.readline().rstrip("\n")
        if answer == f"X {WROTE_OUTSIDE_RAM}":
            raise BoardStoppedError("the firmware wrote above its part's RAM")
        if answer.startswith("X"):
            raise BoardStoppedError(f"the emulated AVR stopped (simavr state {answer[2:]})")
        if not answer:
            raise BoardStoppedError("the emulator ended")
        return answer

    def advance_to(self, time_s: float) -> bytes:
        """Run the firmware up to ``time_s`` (simulated) and return what it sent meanwhile."""
        target = max(self.cycle, round(time_s * self.f_cpu_hz))
        answer = self._ask(f"T {target}")
        self.cycle = target
        data = bytes.fromhex(answer[2:])
        self.received += data
        return data

    def advance(self, duration_s: float) -> bytes:
        """Run the firmware for ``duration_s`` more and return what it sent meanwhile."""
        return self.advance_to(self.time_s + duration_s)

    def write(self, data: bytes) -> None:
        """Send bytes down the line; they arrive one byte time apart from now."""
        for start in range(0, len(data), 4096):
            self._ask("W " + data[start : start + 4096].hex())

    def set_pin(self, port: str, bit: int, high: bool) -> None:
        """Drive an input pin (``port`` ``"B"``, ``"C"``, ``"D"``...)."""
        self._ask(f"P {port} {bit} {int(high)}")

    def set_analog_mv(self, channel: int, millivolts: int) -> None:
        """Set the voltage on an ADC channel, millivolts."""
        self._ask(f"A {channel} {millivolts}")

    def step(
        self, time_s: float, encoder_steps: tuple[int, int], address: int, count: int
    ) -> tuple[bytes, bytes]:
        """One lockstep step in one round trip: spread each encoder's steps (set up before
        with :meth:`turn_encoder`) over the span, run to ``time_s``, read ``count`` bytes
        of data memory at ``address``. Returns (what the board sent, the memory read)."""
        target = max(self.cycle, round(time_s * self.f_cpu_hz))
        steps0, steps1 = encoder_steps
        answer = self._ask(f"S {target} {steps0} {steps1} {address} {count}")
        self.cycle = target
        _, sent, memory = answer.split(" ")
        data = bytes.fromhex(sent)
        self.received += data
        return data, bytes.fromhex(memory)

    def turn_encoder(
        self, encoder: int, port: str, bit_a: int, bit_b: int, steps: int, span_cycles: int
    ) -> None:
        """Make ``steps`` quadrature steps (negative: backwards) on two input pins, spread
        evenly over the next ``span_cycles``, as a turning wheel's encoder would."""
        self._ask(f"E {encoder} {port} {bit_a} {bit_b} {steps} {span_cycles}")

    def reset(self) -> None:
        """Pull the reset line now (an Uno's DTR when a host opens its port, or the supply
        dipping): the firmware starts again from its first instruction, the clock runs on,
        and bytes already on the line keep arriving."""
        self._ask("Z")

    def peek(self, address: int, count: int = 1) -> bytes:
        """Read the board's data memory (I/O registers start at 0x20)."""
        return bytes.fromhex(self._ask(f"M {address} {count}")[2:])

    def watch(self, flag: int, address: int, count: int) -> None:
        """From now on, snapshot ``count`` bytes (at most 64) of data memory at ``address``
        each time the byte at ``flag`` falls from non-zero to zero; see :meth:`snapshots`."""
        self._ask(f"V {flag} {address} {count}")

    def snapshots(self) -> list[tuple[int, bytes]]:
        """The (cycle, bytes) snapshots :meth:`watch` took since the last call, oldest first."""
        taken = []
        for item in self._ask("G").split()[1:]:
            cycle, data = item.split(":")
            taken.append((int(cycle), bytes.fromhex(data)))
        return taken

    def read_eeprom(self, index: int, offset: int, count: int) -> bytes:
        """Read ``count`` bytes at ``offset`` of the ``index``-th I2C EEPROM attached (in the
        order of the addresses given), as the part holds them now."""
        return bytes.fromhex(self._ask(f"R {index} {offset} {count}")[2:])

    def exchange(self, data: bytes, settle_s: float) -> bytes:
        """Send ``data``, run ``settle_s`` more, and return what the board sent meanwhile."""
        self.write(data)
        return self.advance(settle_s)

    def lines(self) -> Iterator[bytes]:
        """Every complete line the board has sent so far."""
        yield from bytes(self.received).splitlines(keepends=True)

    def close(self) -> None:
        """End the emulator."""
        if self._process.poll() is None:
            stdin = self._process.stdin
            assert stdin is not None
            try:
                stdin.write("Q\n")
                stdin.close()
            except OSError:
                pass  # the emulator has already gone
            self._process.wait(timeout=HANG_BOUND_S)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
