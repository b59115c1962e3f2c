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
        assert name in unit.profiles, f"{unit.name} does not list {name}"
    listed = [name for unit in UNITS for name in unit.profiles]
    assert sorted(listed) == sorted(BUILTIN_PROFILES)
    for unit in UNITS:
        assert {BUILTIN_PROFILES[name].protocol for name in unit.profiles} == {unit.name}


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
    profile = BUILTIN_PROFILES[unit.profiles[0]]
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
        "extra = [n for n in loaded if n.count('.') > 2 or n.endswith(('base', 'codec'))]\n"
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


FAKE = ProtocolUnit(
    name="fake",
    codec=f"{__name__}:FakeCodec",
    driver=f"{__name__}:FakeDriver",
    device=f"{__name__}:fake_device",
    profiles=("fake-rover", "fake-walker"),
    contract=ContractCases(wheeled=("fake-rover",), walking=("fake-walker",)),
)
FAKE_PROFILE = dataclasses.replace(BUILTIN_PROFILES["mirto"], name="fake-rover", protocol="fake")


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
        register_unit(dataclasses.replace(fake, profiles=("other",), contract=ContractCases()))
    with pytest.raises(ValueError, match="built-in"):
        unregister_unit("asip")


def test_a_unit_is_checked_when_it_is_written() -> None:
    with pytest.raises(ValueError, match=r"driver must be 'package\.module:attribute'"):
        dataclasses.replace(FAKE, driver="roboscript.drivers.fake.driver.FakeDriver")
    with pytest.raises(ValueError, match="not among its profiles"):
        dataclasses.replace(FAKE, contract=ContractCases(wheeled=("mirto",)))
    with pytest.raises(ValueError):
        resolve("no-colon")
