"""A protocol is one unit: every registry is derived from the units in roboscript.drivers."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, cast

import pytest

from roboscript.codec import CodecStats, Role
from roboscript.drivers import (
    DRIVERS,
    UNITS,
    contract_cases,
    driver_class,
    protocol_unit,
    register_unit,
    units,
    unregister_unit,
)
from roboscript.drivers.base import Driver
from roboscript.drivers.unit import ContractCases, ProtocolUnit, resolve
from roboscript.profiles import BUILTIN_PROFILES, RobotProfile
from roboscript.sim.body import Body
from roboscript.sim.simulation import build_device

ROOT = Path(__file__).resolve().parents[2]


# ------------------------------------------------------------------------- built-in units


def test_every_builtin_profile_has_exactly_one_unit_that_lists_it() -> None:
    for name, profile in BUILTIN_PROFILES.items():
        unit = protocol_unit(profile.protocol)
        assert profile in unit.profiles, f"{unit.name} does not list {name}"
    listed = [name for unit in UNITS for name in unit.profile_names]
    assert listed == list(BUILTIN_PROFILES)  # in the units' order
    for unit in UNITS:
        assert {profile.protocol for profile in unit.profiles} == {unit.name}


def test_every_builtin_profile_runs_a_driver_contract() -> None:
    cases = contract_cases()
    assert sorted(cases.wheeled + cases.walking + cases.open_loop) == sorted(BUILTIN_PROFILES)


@pytest.mark.parametrize("unit", UNITS, ids=lambda u: u.name)
def test_each_unit_names_its_driver_device_and_codec(unit: ProtocolUnit) -> None:
    cls = driver_class(unit.name)
    assert issubclass(cls, Driver)
    assert cls.protocol == unit.name
    assert DRIVERS[unit.name] == tuple(unit.driver.split(":"))
    assert f"roboscript.drivers.{unit.name}." in unit.device
    profile = unit.profiles[0]
    for role in Role:
        codec = unit.make_codec(role, profile)
        assert codec.role is role
        assert isinstance(codec.stats, CodecStats)
    host = cls.make_codec(profile)
    assert type(host) is type(unit.make_codec(Role.HOST, profile))  # the unit's own factory
    assert host.role is Role.HOST
    assert callable(unit.device_factory()(profile))


def test_the_package_lists_each_unit_once_under_its_folder_name() -> None:
    folders = sorted(
        p.name for p in (ROOT / "roboscript" / "drivers").iterdir() if (p / "driver.py").exists()
    )
    assert sorted(unit.name for unit in UNITS) == folders
    for unit in UNITS:
        assert resolve(f"roboscript.drivers.{unit.name}:PROTOCOL") is unit


def _run(code: str) -> None:
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_importing_the_units_imports_no_protocol_code() -> None:
    _run(
        "import sys\n"
        "import roboscript.drivers\n"
        "loaded = [n for n in sys.modules if n.startswith('roboscript.drivers.')]\n"
        "code = [n for n in loaded if not n.endswith(('.profiles', '.unit'))]\n"
        "extra = [n for n in code if n.count('.') > 2 or n.endswith(('base', 'codec'))]\n"
        "assert not extra, extra\n"
        "assert 'serial' not in sys.modules\n"
    )


def test_the_simulator_builds_every_device_without_a_host_driver_or_transport() -> None:
    _run(
        "import sys\n"
        "from roboscript.profiles import BUILTIN_PROFILES\n"
        "from roboscript.sim.simulation import make_simulation\n"
        "for name in BUILTIN_PROFILES:\n"
        "    make_simulation(name)\n"
        "bad = [n for n in sys.modules if n.endswith(('.driver', '.drivers.base'))\n"
        "       or n.startswith('roboscript.transport')]\n"
        "assert not bad, bad\n"
    )


# ---------------------------------------------------------------------- a fake protocol


class FakeCodec:
    def __init__(self, role: Role, profile: RobotProfile) -> None:
        self.role = role
        self.profile = profile
        self.stats = CodecStats()


class FakeDevice:
    def __init__(self, body: Body, tag: str) -> None:
        self.body = body
        self.tag = tag


def fake_device(profile: RobotProfile) -> Callable[[Body], FakeDevice]:
    return lambda body: FakeDevice(body, profile.name)


class FakeDriver(Driver):
    protocol = "fake"

    def start(self) -> None:
        pass

    def tick(self, now_s: float, dt_s: float) -> None:
        pass

    def flush(self, now_s: float, dt_s: float) -> None:
        pass

    def send_stop(self) -> None:
        pass


FAKE_PROFILE = dataclasses.replace(BUILTIN_PROFILES["mirto"], name="fake-rover", protocol="fake")
FAKE = ProtocolUnit(
    name="fake",
    title="Fake",
    speakers="a fake robot",
    codec=f"{__name__}:FakeCodec",
    driver=f"{__name__}:FakeDriver",
    device=f"{__name__}:fake_device",
    profiles=(FAKE_PROFILE, dataclasses.replace(FAKE_PROFILE, name="fake-walker")),
    contract=ContractCases(wheeled=("fake-rover",), walking=("fake-walker",)),
)


@pytest.fixture
def fake() -> Iterator[ProtocolUnit]:
    register_unit(FAKE)
    try:
        yield FAKE
    finally:
        unregister_unit(FAKE.name)


def test_a_registered_unit_shows_up_in_every_registry(fake: ProtocolUnit) -> None:
    assert fake in units()
    # The driver registry.
    assert "fake" in DRIVERS
    assert DRIVERS["fake"] == (__name__, "FakeDriver")
    assert driver_class("fake") is FakeDriver
    codec = cast(Any, FakeDriver.make_codec(FAKE_PROFILE))
    assert isinstance(codec, FakeCodec)
    assert (codec.role, codec.profile) == (Role.HOST, FAKE_PROFILE)
    # The simulator's device table.
    body = cast(Body, object())
    device = cast(Any, build_device(FAKE_PROFILE, body))
    assert isinstance(device, FakeDevice)
    assert (device.body, device.tag) == (body, "fake-rover")
    # The contract tests' parameters.
    assert "fake-rover" in contract_cases().wheeled
    assert "fake-walker" in contract_cases().walking


def test_an_unregistered_unit_is_gone_everywhere(fake: ProtocolUnit) -> None:
    unregister_unit("fake")
    assert "fake" not in DRIVERS
    with pytest.raises(NotImplementedError, match="no driver for fake"):
        driver_class("fake")
    with pytest.raises(NotImplementedError, match="simulator has no fake device"):
        build_device(FAKE_PROFILE, cast(Body, object()))
    assert "fake-rover" not in contract_cases().wheeled


def test_units_cannot_clash_or_remove_builtins(fake: ProtocolUnit) -> None:
    register_unit(fake)  # the same unit again is harmless
    with pytest.raises(ValueError, match="registered already"):
        other = dataclasses.replace(FAKE_PROFILE, name="other")
        register_unit(dataclasses.replace(fake, profiles=(other,), contract=ContractCases()))
    with pytest.raises(ValueError, match="built-in"):
        unregister_unit("asip")


def test_a_unit_is_checked_when_it_is_written() -> None:
    with pytest.raises(ValueError, match=r"driver must be 'package\.module:attribute'"):
        dataclasses.replace(FAKE, driver="roboscript.drivers.fake.driver.FakeDriver")
    with pytest.raises(ValueError, match="not among its profiles"):
        dataclasses.replace(FAKE, contract=ContractCases(wheeled=("mirto",)))
    with pytest.raises(ValueError, match="its profiles must speak it"):
        dataclasses.replace(FAKE, profiles=(BUILTIN_PROFILES["mirto"],), contract=ContractCases())
    with pytest.raises(ValueError):
        resolve("no-colon")


# ------------------------------------------------------- a new robot is one folder, whole

TOY = {
    "__init__.py": """\
from roboscript.drivers.toy.profiles import PROFILES
from roboscript.drivers.unit import ProtocolUnit

PROTOCOL = ProtocolUnit(
    name="toy",
    title="Toy",
    speakers="a toy robot",
    codec="roboscript.drivers.toy.codec:codec_for",
    driver="roboscript.drivers.toy.driver:ToyDriver",
    device="roboscript.drivers.toy.device:simulated_device",
    profiles=PROFILES,
    usb=((0x1234, 0x0001, "Toy board"),),
)
""",
    "profiles.py": """\
from roboscript import capabilities as cap
from roboscript.robot_profile import RobotProfile

PROFILES = (
    RobotProfile(
        name="toy-bot",
        protocol="toy",
        description="a robot made up for a test",
        baudrate=9600,
        capabilities=frozenset({cap.DRIVE_BASE}),
        firmware_pid=True,
    ),
)
""",
    "codec.py": """\
from roboscript.codec import CodecStats


class ToyCodec:
    # one message per line: TOY <number>
    def __init__(self, role, profile):
        self.role = role
        self.stats = CodecStats()
        self._buffer = b""

    def receive_data(self, data):
        self._buffer += data

    def next_message(self):
        line, sep, rest = self._buffer.partition(b"\\n")
        if not sep:
            return None
        self._buffer = rest
        if not line.startswith(b"TOY "):
            from roboscript.errors import RemoteProtocolError

            raise RemoteProtocolError("not a toy line", kind="garbage")
        return int(line[4:])


def codec_for(role, profile):
    return ToyCodec(role, profile)
""",
    "driver.py": """\
from roboscript.drivers.base import Driver


class ToyDriver(Driver):
    protocol = "toy"

    def start(self):
        pass

    def tick(self, now_s, dt_s):
        pass

    def flush(self, now_s, dt_s):
        pass

    def send_stop(self):
        pass
""",
    "device.py": """\
class ToyDevice:
    def __init__(self, body, profile):
        self.body = body
        self.profile = profile


def simulated_device(profile):
    return lambda body: ToyDevice(body, profile)
""",
}


@pytest.fixture
def toy_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A protocol folder beside the built-in ones, where the package looks for units."""
    from roboscript import drivers

    folder = tmp_path / "toy"
    folder.mkdir()
    for name, text in TOY.items():
        (folder / name).write_text(text, encoding="utf-8")
    monkeypatch.setattr(drivers, "__path__", [*drivers.__path__, str(tmp_path)])
    try:
        yield folder
    finally:
        unregister_unit("toy")
        for name in [n for n in sys.modules if n.startswith("roboscript.drivers.toy")]:
            del sys.modules[name]


def test_a_new_protocol_is_one_folder_and_every_registry_follows(toy_folder: Path) -> None:
    from roboscript.drivers import discover_units, usb_hints
    from roboscript.drivers.recognise import handshake_failure, recognise_protocol, wrong_robot_hint
    from roboscript.profiles import get_profile

    [toy] = [unit for unit in discover_units() if unit.name == "toy"]
    assert [unit.name for unit in discover_units() if unit in UNITS] == [u.name for u in UNITS]
    register_unit(toy)
    # its robots are built-in robots
    profile = get_profile("toy-bot")
    assert (profile.protocol, BUILTIN_PROFILES["toy-bot"]) == ("toy", profile)
    # its driver, codec and simulated device
    cls = driver_class("toy")
    assert cls.__module__ == "roboscript.drivers.toy.driver" and issubclass(cls, Driver)
    body = cast(Body, object())
    device = cast(Any, build_device(profile, body))
    assert (type(device).__name__, device.body, device.profile) == ("ToyDevice", body, profile)
    # a port that speaks it is recognised, and named by the unit's own words
    heard = b"TOY 1\nTOY 2\nTOY 3\n"
    assert recognise_protocol(heard) == "toy"
    hint = "this port speaks the Toy protocol (a toy robot): use --robot toy-bot"
    assert wrong_robot_hint(heard, "asip") == hint
    assert handshake_failure("mirto", "asip", "sim://x", heard, 10, "within 3 s") == (
        f"mirto did not answer on sim://x: {hint}"
    )
    # a port on its USB board is named as one of its robots
    assert usb_hints()[(0x1234, 0x0001)] == "Toy board: a toy robot (--robot toy-bot)"
    silent = handshake_failure("toy-bot", "toy", "sim://x", b"", 10, "within 3 s")
    assert "nothing came back to 10 bytes of the Toy handshake" in silent
