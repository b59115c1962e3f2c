"""StackMod, pinned to what the protocol's author's own firmware and client do.

The author's repository (``74ls04/StackMod``: the Arduino ``Stackmodio`` library, the
``stackmod`` sketch and the Python ``StackModIO.py`` client) differs from the 0.9.1 document
that the ``stackmod-rover`` profile follows. ``stackmod-reference`` speaks the author's form,
and its simulated twin parses bytes the way that firmware does. The byte literals here are
worked out by hand from the author's rules (checksums summed in the docstrings), never taken
from roboscript's encoder, so the driver and the twin cannot agree on something the firmware
does not do.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from helpers import MISSIONS, run_cli

from roboscript.drivers.stackmod.device import StackModRover
from roboscript.drivers.stackmod.reference_device import LOOP_PERIOD_S, ReferenceModule
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.session import run_session
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.transport.wirelog import read_wire_log


def _module() -> tuple[Simulation, ReferenceModule]:
    sim = make_simulation("stackmod-reference")
    sim.connect()
    assert isinstance(sim.device, ReferenceModule)
    return sim, sim.device


def _sent(log: Path) -> list[bytes]:
    return [data for _, direction, data in read_wire_log(log) if direction == ">"]


# -- the author's packet -----------------------------------------------------------------------


def test_the_authors_client_packet_takes_effect() -> None:
    """The author's client writes ``{Mp$MTR1+139}p``: module address, then its own address
    ``p``, then the action. Between the braces: M45 p80 $4 M45 T52 R50 1:17 +:11 1:17 3:19
    9:25 = 365; 365 % 95 = 80; + 32 = 112, ``p``. The firmware sets motor 1 to 139."""
    sim, module = _module()
    sim.write(b"2{Mp$MTR1+139}p")
    assert module.motor_registers[0] == 139
    sim.tick(LOOP_PERIOD_S, LOOP_PERIOD_S)
    assert sim.body.power[0] == pytest.approx(139 / 255)


def test_two_address_bytes_come_before_the_action(tmp_path: Path) -> None:
    """The author's packets carry two address bytes before ``$``; the driver sends the module's
    (``E``, I2C slave 0x45) and then ``p``, as the author's client does. Its first writes stop
    both motors: E37 p80 $4 M45 T52 R50 1:17 +:11 0:16*3 = 344 -> 59 + 32 = 91, ``[``; motor 2
    sums one more, 92, a backslash."""
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)):
        pass
    assert _sent(log)[:2] == [b"2{Ep$MTR1+000}[", b"2{Ep$MTR2+000}\\"]


def test_the_checksum_leaves_the_braces_out() -> None:
    """The firmware sums only the text between the braces. The seed's rule adds ``{`` (91) and
    ``}`` (93): 365 + 184 = 549 -> 74 + 32 = 106, ``j``; the firmware drops that packet."""
    sim, module = _module()
    sim.write(b"2{Mp$MTR1+139}j")
    assert module.motor_registers[0] == 0
    assert module.bad_checksums == 1
    sim.write(b"2{Mp$MTR1+139}p")
    assert module.motor_registers[0] == 139


def test_motor_values_are_pwm_up_to_255(tmp_path: Path) -> None:
    """Motor values are an 8-bit PWM duty with a sign, ±255 for full power, not the seed's
    ±100. Full power forward on motor 1: E37 p80 $4 M45 T52 R50 1:17 +:11 2:18 5:21 5:21 =
    356 -> 71 + 32 = 103, ``g``; full reverse on motor 2: 1 -> 2 (+1), + -> - (+2): 359 ->
    106, ``j``."""
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        driver: Any = bot.driver
        driver.set_wheel_speeds(1000.0, -1000.0)
        bot.run_for(0.5)
        assert bot.simulation is not None
        power = list(bot.simulation.body.power)
    assert _sent(log)[2:4] == [b"2{Ep$MTR1+255}g", b"2{Ep$MTR2-255}j"]
    assert power == [1.0, -1.0]


def test_no_get_is_answered_so_moves_are_timed(tmp_path: Path) -> None:
    """The firmware answers nothing, not even a GET (``{Mp?MTR1}``: M45 p80 ?31 M45 T52 R50
    1:17 = 320 -> 35 + 32 = 67, ``C``). So the driver never asks: it estimates distances from
    a calibrated speed at a PWM and ends a move on time."""
    sim, _ = _module()
    sim.write(b"2{Mp?MTR1}C")
    sim.tick(1.0, 1.0)
    assert sim.read(100) == b""
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        bot.drive_base.set_wheel_speeds(150.0, 150.0)
        bot.run_for(2.0)
        estimated = bot.drive_base.wheel_distances_mm()
    assert not any(b"?" in data for data in _sent(log))
    assert estimated == pytest.approx((300.0, 300.0), abs=5.0)


def test_each_packet_is_one_i2c_write_led_by_register_0x32(tmp_path: Path) -> None:
    """The author's client writes each packet as one I2C transaction, register byte 0x32
    (``2``) first, which the firmware skips as it is not ``{``. A write ends by resetting the
    parser, so a packet split over two writes is lost; a write holds at most 32 bytes."""
    sim, module = _module()
    sim.write(b"2{Ep$MTR1")
    sim.write(b"+139}h")  # E37 p80 $4 M45 T52 R50 1:17 +:11 1:17 3:19 9:25 = 357 -> 104
    assert module.motor_registers[0] == 0
    sim.write(b"2{Ep$MTR1+139}h")
    assert module.motor_registers[0] == 139
    log = tmp_path / "wire.log"
    with Robot.connect("stackmod-reference", wire_log=str(log)) as bot:
        bot.drive_base.set_wheel_speeds(100.0, -100.0)
        bot.run_for(0.5)
    writes = _sent(log)
    assert len(writes) == 6
    assert all(len(data) == 15 and data[:2] == b"2{" for data in writes)


@pytest.mark.parametrize(
    ("write", "why"),
    [
        # E37 $4 M45 T52 R50 1:17 +:11 1:17 0:16 0:16 = 265 -> 75 + 32 = 107.
        (b"2{E$MTR1+100}k", "one address byte: the firmware reads 'TR1' as the command"),
        # E37 p80 $4 M45 T52 R50 0:16 +:11 1:17 0:16 0:16 = 344 -> 91.
        (b"2{Ep$MTR0+100}[", "motors count from 1: motor 0 is ignored"),
        # E37 p80 $4 S51 R50 V54 1:17 0:16 9:25 0:16 = 350 -> 65 + 32 = 97.
        (b"2{Ep$SRV1090}a", "only MTR is acted on"),
    ],
)
def test_only_an_11_character_mtr_set_of_a_motor_from_1_exists(write: bytes, why: str) -> None:
    """The firmware acts only on ``MTR`` with ``$`` and exactly 11 characters between the
    braces, and counts motors from 1."""
    sim, module = _module()
    sim.write(write)
    assert module.motor_registers == [0] * 15, why
    assert module.taken == 0 and module.bad_checksums == 0, why


def test_sensors_the_firmware_lacks_are_not_offered() -> None:
    """The author's firmware has no sensor and answers nothing: ``stackmod-reference`` offers
    a drive base only, and a mission that reads a sensor is refused at check time."""
    assert get_profile("stackmod-reference").capabilities == {"drive_base"}
    checked = run_cli("check", "missions/stackmod_patrol.yaml", "--robot", "stackmod-reference")
    assert checked.returncode != 0
    lacks = "which stackmod-reference does not have"
    for line in (
        f"16:9: error: the condition 'range.distance_cm < 25' reads range, {lacks}",
        f"17:9: error: the condition 'bumper.any' reads bumper, {lacks}",
        "20:10: error: 'play_tone' needs speaker",
    ):
        assert f"stackmod_patrol.yaml:{line}" in checked.stderr + checked.stdout


# -- the seed document's form --------------------------------------------------------------------


def test_the_seed_form_stays_the_default_and_moves_without_arm() -> None:
    """``stackmod-rover`` keeps the 0.9.1 document's form, and its simulated module obeys a
    plain seed ``MTR`` SET without roboscript's own ``ARM``: ``{M$MTR2+025}`` sums {91 M45 $4
    M45 T52 R50 2:18 +:11 0:16 2:18 5:21 }93 = 464 -> 84 + 32 = 116, ``t``."""
    assert get_profile("stackmod-rover").options == {}
    sim = make_simulation("stackmod-rover")
    sim.connect()
    assert isinstance(sim.device, StackModRover)
    sim.write(b"{M$MTR2+025}t")
    assert sim.body.power == [0.0, 0.25]


# -- stackmod_patrol on the author's firmware ----------------------------------------------------


def _yaml_1_2_keys(value: Any) -> Any:
    """PyYAML reads the key ``on`` as ``True`` (YAML 1.1); roboscript reads YAML 1.2."""
    if isinstance(value, dict):
        return {("on" if k is True else k): _yaml_1_2_keys(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_yaml_1_2_keys(v) for v in value]
    return value


def _timed_patrol(tmp_path: Path) -> Path:
    """``stackmod_patrol.yaml`` with what needs a sensor taken out: the same moves, timed."""
    text = (MISSIONS / "stackmod_patrol.yaml").read_text(encoding="utf-8")
    mission = _yaml_1_2_keys(yaml.safe_load(text))
    mission.update(robot="stackmod-reference", world="empty")
    states = mission["states"]
    del states["forward"]["when"], states["alert"], states["back_off"]
    states["lost"]["do"] = "stop"
    path = tmp_path / "stackmod_patrol_timed.yaml"
    path.write_text(yaml.safe_dump(mission), encoding="utf-8")
    return path


def test_the_patrols_moves_run_open_loop_and_every_packet_takes_effect(tmp_path: Path) -> None:
    """Run on ``stackmod-reference``, the patrol's moves (3 m ahead, 90 degrees right, six
    times) finish on time, and every packet the driver writes is taken by the module that
    parses as the author's firmware does."""
    profile = get_profile("stackmod-reference")
    spec, _ = load_mission(_timed_patrol(tmp_path), profile)
    log = tmp_path / "wire.log"
    session = run_session(spec, profile, wire_log=str(log), max_time_s=300.0)
    assert (session.result.outcome, session.result.final_state) == ("success", "home")
    sim = session.simulation
    assert sim is not None
    module = sim.device
    assert isinstance(module, ReferenceModule)
    writes = _sent(log)
    assert len(writes) > 20
    assert module.taken == len(writes)
    assert not module.ignored and module.bad_checksums == 0
    # Six right turns of 90 degrees: facing south, within what timing alone can do.
    assert abs((sim.body.heading_deg % 360.0) - 180.0) < 20.0


def test_the_seed_profiles_patrol_packets_do_nothing_on_the_authors_firmware(
    tmp_path: Path,
) -> None:
    """The issue's measurement: the packets ``stackmod-rover`` writes for the patrol (one
    address, braces in the checksum, GETs) are all ignored by the author's firmware."""
    profile = get_profile("stackmod-rover")
    spec, _ = load_mission(MISSIONS / "stackmod_patrol.yaml", profile)
    log = tmp_path / "wire.log"
    run_session(spec, profile, world="square-room", wire_log=str(log), max_time_s=40.0)
    sim, module = _module()
    for data in _sent(log):
        sim.write(data)
    assert len(_sent(log)) > 100
    assert module.taken == 0
