"""roboscript's SPIKE hub agent, run under CPython with stand-ins for the hub's MicroPython API.

The stand-ins (``hubapi_standins/``) record every call the agent makes; the host side of the
tunnel (:mod:`roboscript.drivers.spike.tunnel`) writes the commands and reads the replies, so
these tests also check that the agent and the host agree on the bytes.
"""

from __future__ import annotations

import ast
import importlib.util
import sys
from collections.abc import Coroutine, Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roboscript.codec import Role
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.driver import agent_source
from roboscript.errors import RemoteProtocolError

STANDINS = Path(__file__).parent / "hubapi_standins"
AGENT = Path(__file__).parents[3] / "roboscript" / "drivers" / "spike" / "agent" / "hub_agent.py"
HUB_MODULES = {
    "hub",
    "motor",
    "motor_pair",
    "runloop",
    "tunnel",
    "standin_log",
    "color_sensor",
}
CONFIG_FORM = "hub.config['module_tunnel']"
IMPORT_FORM = "import tunnel"


def _forget_standins() -> None:
    for name in list(sys.modules):
        if name.split(".")[0] in HUB_MODULES:
            del sys.modules[name]


@pytest.fixture
def hub(monkeypatch: pytest.MonkeyPatch) -> Iterator[ModuleType]:
    """A fresh stand-in hub API on sys.path; yields its call log."""
    monkeypatch.syspath_prepend(str(STANDINS))
    _forget_standins()
    import standin_log

    yield standin_log
    import runloop

    for coroutine in runloop.STARTED:
        coroutine.close()
    _forget_standins()


def start_agent() -> ModuleType:
    """Import the agent on the stand-in hub, which starts it as the hub would."""
    spec = importlib.util.spec_from_file_location("hub_agent", AGENT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def agent_module(hub: ModuleType) -> ModuleType:
    """The agent, started on the stand-in hub."""
    return start_agent()


def replies(sent: list[bytes]) -> list[t.Record | RemoteProtocolError]:
    """Decode what the agent sent, as the host does."""
    return [item for data in sent for item in t.decode_records(data, Role.HOST)]


def make_agent(module: ModuleType) -> tuple[Any, list[bytes]]:
    sent: list[bytes] = []
    return module.Agent(sent.append), sent


def command(agent: Any, *records: t.Record, now_ms: int = 0) -> None:
    agent.receive(t.encode(*records))
    agent.poll(now_ms)


def step(coroutine: Coroutine[Any, Any, Any], times: int = 1) -> None:
    for _ in range(times):
        coroutine.send(None)


# ---------------------------------------------------------------------------------- start


def test_starting_the_agent_binds_the_tunnel_resets_yaw_and_runs_four_tasks(
    hub: ModuleType, capsys: pytest.CaptureFixture[str]
) -> None:
    agent_module = start_agent()
    import runloop
    import tunnel

    assert capsys.readouterr().out == (
        f"{agent_module.AGENT_VERSION} ready, tunnel from {CONFIG_FORM}\n"
    )
    assert hub.CALLS[0] == ("hub.config[]", ("module_tunnel",), {})
    assert hub.CALLS[1] == ("motion_sensor.reset_yaw", (0,), {})
    assert len(tunnel.RECEIVER) == 1
    assert [c.__name__ for c in runloop.STARTED] == [
        "serve",
        "finish_moves",
        "finish_jobs",
        "finish_jobs",
    ]


def test_with_hub_config_and_a_tunnel_module_the_agent_binds_hub_config_and_never_imports(
    hub: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    import hub as hub_api
    import tunnel

    imported = ModuleType("tunnel")  # what "import tunnel" would give, if it ran
    monkeypatch.setitem(sys.modules, "tunnel", imported)
    agent_module = start_agent()
    tried: list[str] = []
    assert agent_module.find_tunnel(tried) == (tunnel, CONFIG_FORM)
    assert tried == [CONFIG_FORM]
    assert hub_api.config["module_tunnel"] is tunnel
    assert len(tunnel.RECEIVER) == 1  # main() bound the hub.config module, not the import


def test_without_hub_config_the_agent_falls_back_to_import_tunnel(
    hub: ModuleType, capsys: pytest.CaptureFixture[str]
) -> None:
    import hub as hub_api
    import tunnel

    del hub_api.config["module_tunnel"]
    agent_module = start_agent()
    assert capsys.readouterr().out == (
        f"{agent_module.AGENT_VERSION} ready, tunnel from {IMPORT_FORM}\n"
    )
    assert len(tunnel.RECEIVER) == 1
    tried: list[str] = []
    assert agent_module.find_tunnel(tried) == (tunnel, IMPORT_FORM)
    assert tried == [CONFIG_FORM, IMPORT_FORM]


def test_without_a_tunnel_the_agent_names_the_firmware_and_both_forms_instead_of_ready(
    hub: ModuleType, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import os

    import hub as hub_api

    del hub_api.config["module_tunnel"]
    monkeypatch.setitem(sys.modules, "tunnel", None)  # makes "import tunnel" fail
    uname = os.uname_result(("LEGO", "hub", "3.4.0", "v3.4.0 on 2024-05-01", "SPIKE"))
    monkeypatch.setattr(os, "uname", lambda: uname)
    start_agent()
    assert capsys.readouterr().out == (
        "roboscript agent: no tunnel on this hub (firmware 3.4.0 (v3.4.0 on 2024-05-01)):"
        f" tried {CONFIG_FORM} and {IMPORT_FORM}; update the hub with the SPIKE App 3\n"
    )
    assert ("light_matrix.write", ("NO TUNNEL",), {}) in hub.CALLS


def test_the_running_agent_answers_a_version_query_from_the_tunnel(
    agent_module: ModuleType,
) -> None:
    import runloop
    import tunnel

    tunnel.deliver(t.VersionQuery().encode())
    step(runloop.STARTED[0])  # serve: one poll, then it sleeps
    assert replies(tunnel.SENT) == [t.Version(agent_module.AGENT_VERSION)]
    assert t.agent_version_of(agent_source()) == agent_module.AGENT_VERSION


def test_the_agent_source_is_the_package_data_the_driver_uploads() -> None:
    assert agent_source() == AGENT.read_bytes()


def test_the_agent_uses_only_what_the_hubs_micropython_has() -> None:
    tree = ast.parse(AGENT.read_text(encoding="utf-8"))
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imported |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            imported.add(node.module or "")
        # MicroPython's compiler rejects some annotation forms: the agent has none.
        assert not isinstance(node, ast.AnnAssign), f"line {node.lineno}: annotation"
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            assert node.returns is None and all(a.annotation is None for a in node.args.args)
    assert imported == {
        "struct",
        "time",
        "os",
        "motor",
        "motor_pair",
        "runloop",
        "hub",
        "tunnel",
        "color_sensor",
    }


# ------------------------------------------------------------------------------- commands


CALLS = [
    pytest.param(t.Tank(300, -300, 4000, 0), [("motor_pair.move_tank", (0, 300, -300))], id="tank"),
    pytest.param(
        t.Power(5000, 2500, 0),
        [("motor.set_duty_cycle", (0, -5000)), ("motor.set_duty_cycle", (1, 2500))],
        id="power-left-mirrored",
    ),
    pytest.param(t.Beep(880, 200, 70), [("sound.beep", (880, 200, 70))], id="beep"),
    pytest.param(t.ShowText("Hi"), [("light_matrix.write", ("Hi",))], id="text"),
    pytest.param(t.ShowText(""), [("light_matrix.clear", ())], id="empty-text-clears"),
    pytest.param(t.ClearDisplay(), [("light_matrix.clear", ())], id="clear"),
    pytest.param(
        t.Stop(),
        [("motor_pair.stop", (0,)), ("motor.stop", (0,)), ("motor.stop", (1,))],
        id="stop-brakes-pair-and-motors",
    ),
    pytest.param(
        t.TankForDegrees(3, 720, 200, 100),
        [("motor_pair.move_tank_for_degrees", (0, 720, 200, 100))],
        id="move",
    ),
    pytest.param(t.MotorRun(2, -150, 0), [("motor.run", (2, -150))], id="motor-run"),
    pytest.param(
        t.MotorForDegrees(4, 5, -90, 300),
        [("motor.run_for_degrees", (5, -90, 300))],
        id="motor-for-degrees",
    ),
    pytest.param(t.MotorStop(3), [("motor.stop", (3,))], id="motor-stop"),
]


@pytest.mark.parametrize(("record", "expected"), CALLS)
def test_each_command_calls_the_hub_api(
    agent_module: ModuleType, hub: ModuleType, record: t.Record, expected: list[Any]
) -> None:
    agent, sent = make_agent(agent_module)
    command(agent, t.Configure(0, 1))
    assert hub.CALLS[-1] == ("motor_pair.pair", (0, 0, 1), {})
    start = len(hub.CALLS)
    command(agent, record)
    assert [(name, args) for name, args, _ in hub.CALLS[start:]] == expected
    assert sent == []


def test_tank_passes_the_acceleration_and_stop_brakes(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    import motor

    agent, _ = make_agent(agent_module)
    command(agent, t.Configure(4, 5), t.Tank(100, 100, 2500, 0), t.Stop())
    kwargs = {name: kw for name, _, kw in hub.CALLS}
    assert kwargs["motor_pair.move_tank"] == {"acceleration": 2500}
    assert kwargs["motor_pair.stop"] == {"stop": motor.BRAKE}


def test_reconfiguring_unpairs_first(agent_module: ModuleType, hub: ModuleType) -> None:
    agent, _ = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.Configure(2, 3))
    assert hub.names()[-3:] == ["motor_pair.pair", "motor_pair.unpair", "motor_pair.pair"]


def test_motion_before_configure_is_refused_and_nothing_moves(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, sent = make_agent(agent_module)
    command(agent, t.Tank(100, 100, 1000, 0), t.Power(1, 1, 0), t.Stop())
    assert replies(sent) == [
        t.Refused(t.Tank.op, t.RefuseReason.NOT_CONFIGURED),
        t.Refused(t.Power.op, t.RefuseReason.NOT_CONFIGURED),
    ]
    assert not [name for name in hub.names() if name.startswith("motor")]


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (b"\x40\x00", t.RefuseReason.UNKNOWN_COMMAND),
        (b"\x81\x01x", t.RefuseReason.UNKNOWN_COMMAND),
        (b"\x03\x02\x00\x00", t.RefuseReason.BAD_LENGTH),
        (b"\x07\x02\xff\xfe", t.RefuseReason.BAD_VALUE),
        (b"\x02\x02\x01\x01", t.RefuseReason.BAD_VALUE),
    ],
)
def test_bad_records_are_refused_with_a_reason(
    agent_module: ModuleType, data: bytes, reason: t.RefuseReason
) -> None:
    agent, sent = make_agent(agent_module)
    agent.receive(data)
    agent.poll(0)
    assert replies(sent) == [t.Refused(data[0], reason)]


def test_records_split_or_merged_across_tunnel_messages_are_read_whole(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, sent = make_agent(agent_module)
    wire = t.encode(t.Configure(0, 1), t.Tank(10, 20, 1000, 0), t.VersionQuery())
    for index in range(len(wire)):
        agent.receive(wire[index : index + 1])
        agent.poll(0)
    assert replies(sent) == [t.Version(agent_module.AGENT_VERSION)]
    assert "motor_pair.move_tank" in hub.names()


def test_the_watchdog_brakes_when_no_motion_command_follows_in_time(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, _ = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.Tank(100, 100, 1000, 500), now_ms=1000)
    agent.poll(1499)
    assert "motor_pair.stop" not in hub.names()
    command(agent, t.Tank(100, 100, 1000, 500), now_ms=1400)  # refreshed: a new deadline
    agent.poll(1899)
    assert "motor_pair.stop" not in hub.names()
    agent.poll(1900)
    assert hub.names()[-3:] == ["motor_pair.stop", "motor.stop", "motor.stop"]
    agent.poll(5000)
    assert hub.names().count("motor_pair.stop") == 1


def test_a_zero_watchdog_never_stops(agent_module: ModuleType, hub: ModuleType) -> None:
    agent, _ = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.Tank(100, 100, 1000, 0), now_ms=0)
    agent.poll(10**9)
    assert "motor_pair.stop" not in hub.names()


# ---------------------------------------------------------------------------- coroutines


@pytest.mark.parametrize(
    ("firmware_status", "status"),
    [
        ("READY", t.MoveStatus.DONE),
        ("STALLED", t.MoveStatus.STALLED),
        ("CANCELED", t.MoveStatus.CANCELLED),
        ("DISCONNECTED", t.MoveStatus.FAILED),
    ],
)
def test_a_move_reports_how_it_ended_once_the_firmware_finishes_it(
    agent_module: ModuleType, hub: ModuleType, firmware_status: str, status: t.MoveStatus
) -> None:
    import motor

    agent, sent = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.TankForDegrees(9, 360, 300, 300))
    mover = agent_module.finish_moves(agent)
    step(mover, 3)
    assert sent == []  # still moving
    (move,) = hub.PENDING
    move.finish(getattr(motor, firmware_status))
    step(mover)
    assert replies(sent) == [t.MoveDone(9, status)]
    mover.close()


def test_tones_play_one_after_the_other(agent_module: ModuleType, hub: ModuleType) -> None:
    agent, _ = make_agent(agent_module)
    command(agent, t.Beep(440, 100, 50), t.Beep(880, 100, 50))
    first, second = hub.PENDING
    player = agent_module.finish_jobs(agent.sounds)
    step(player, 2)
    assert agent.sounds == [second]  # the second waits for the first
    first.finish()
    step(player, 2)
    assert agent.sounds == []
    player.close()


# ---------------------------------------------------------------------------- properties

I16 = st.integers(-0x8000, 0x7FFF)
MOTION = st.one_of(
    st.builds(t.Tank, I16, I16, st.integers(0, 10000), st.integers(0, 0xFFFF)),
    st.builds(t.Power, st.integers(-10000, 10000), st.integers(-10000, 10000), st.just(0)),
    st.builds(t.TankForDegrees, st.integers(0, 255), st.integers(0, 2**31 - 1), I16, I16),
    st.builds(t.Beep, st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), st.integers(0, 100)),
)
PASSED_ON = {
    t.Tank: lambda r: [("motor_pair.move_tank", (0, r.left_deg_s, r.right_deg_s))],
    t.Power: lambda r: [
        ("motor.set_duty_cycle", (0, -r.left_duty)),
        ("motor.set_duty_cycle", (1, r.right_duty)),
    ],
    t.TankForDegrees: lambda r: [
        ("motor_pair.move_tank_for_degrees", (0, r.degrees, r.left_deg_s, r.right_deg_s))
    ],
    t.Beep: lambda r: [("sound.beep", (r.frequency_hz, r.duration_ms, r.volume_percent))],
}


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(record=MOTION)
def test_the_agent_reads_every_value_the_host_can_write(
    agent_module: ModuleType, hub: ModuleType, record: t.Record
) -> None:
    agent, sent = make_agent(agent_module)
    command(agent, t.Configure(0, 1))
    start = len(hub.CALLS)
    command(agent, record)
    assert [(name, args) for name, args, _ in hub.CALLS[start:]] == PASSED_ON[type(record)](record)
    assert sent == []


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(chunks=st.lists(st.binary(max_size=40), max_size=8))
def test_arbitrary_tunnel_bytes_never_stop_the_agent_and_every_reply_is_readable(
    agent_module: ModuleType, chunks: list[bytes]
) -> None:
    agent, sent = make_agent(agent_module)
    for now_ms, chunk in enumerate(chunks):
        agent.receive(chunk)
        agent.poll(now_ms)
    for item in replies(sent):
        assert isinstance(item, t.Record), item


# ------------------------------------------------------------------ colour, buttons, motors


def test_watch_reports_reflection_and_buttons_every_interval(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    import color_sensor
    from hub import button

    color_sensor.REFLECTION[4] = 37
    button.HELD.add(button.RIGHT)
    agent, sent = make_agent(agent_module)
    command(agent, t.Watch(4, 50), now_ms=1000)
    assert replies(sent) == [t.Report(37, t.BUTTON_BITS["right"])]
    color_sensor.REFLECTION[4] = 80
    button.HELD.clear()
    agent.poll(1049)
    assert len(sent) == 1  # not yet: 50 ms apart
    agent.poll(1050)
    assert replies(sent)[1:] == [t.Report(80, 0)]
    command(agent, t.Watch(4, 0), now_ms=1100)
    agent.poll(2000)
    assert len(sent) == 2  # interval 0 stops the reports


def test_a_port_without_a_colour_sensor_reports_no_reflection(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, sent = make_agent(agent_module)
    command(agent, t.Watch(2, 20))
    command(agent, t.Watch(t.NO_PORT, 20))
    assert replies(sent) == [t.Report(t.NO_REFLECTION, 0), t.Report(t.NO_REFLECTION, 0)]
    assert hub.names().count("color_sensor.reflection") == 1


def test_a_one_motor_command_on_a_drive_port_is_refused(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, sent = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.MotorRun(1, 100, 0), t.MotorForDegrees(1, 0, 90, 100))
    assert replies(sent) == [
        t.Refused(t.MotorRun.op, t.RefuseReason.BAD_VALUE),
        t.Refused(t.MotorForDegrees.op, t.RefuseReason.BAD_VALUE),
    ]
    assert "motor.run" not in hub.names() and "motor.run_for_degrees" not in hub.names()


def test_the_watchdog_brakes_the_other_motors_too_but_stop_brakes_only_the_wheels(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    agent, _ = make_agent(agent_module)
    command(agent, t.Configure(0, 1), t.MotorRun(5, 200, 0), t.Stop(), now_ms=0)
    assert ("motor.stop", (5,)) not in [(name, args) for name, args, _ in hub.CALLS]
    command(agent, t.MotorRun(5, 200, 300), now_ms=0)
    start = len(hub.CALLS)
    agent.poll(299)
    assert len(hub.CALLS) == start
    agent.poll(300)  # the MotorRun's watchdog: the host went quiet
    stopped = [args for name, args, _ in hub.CALLS[start:] if name == "motor.stop"]
    assert stopped == [(0,), (1,), (5,)]


def test_a_motor_move_reports_move_done_with_its_seq(
    agent_module: ModuleType, hub: ModuleType
) -> None:
    import runloop
    import standin_log
    import tunnel

    tunnel.deliver(t.encode(t.MotorForDegrees(9, 2, 180, 360)))
    step(runloop.STARTED[0])
    move = standin_log.PENDING[-1]
    assert move.name == "motor.run_for_degrees"
    step(runloop.STARTED[1])
    assert replies(tunnel.SENT) == []
    move.finish()
    step(runloop.STARTED[1])
    assert replies(tunnel.SENT) == [t.MoveDone(9, t.MoveStatus.DONE)]


# ---------------------------------------------------------------------- MicroPython's ticks

TICKS_PERIOD = 2**30
"""``time.ticks_ms()`` wraps at 2**30 on MicroPython's ports (``MICROPY_PY_TIME_TICKS_PERIOD``)."""


def _micropython_ticks(module: ModuleType, monkeypatch: pytest.MonkeyPatch) -> None:
    """Give the agent MicroPython's ticks arithmetic (from its documentation): values live in
    the period, and ``ticks_diff`` is only defined for values ``ticks_ms``/``ticks_add`` made."""

    def ticks_add(ticks: int, delta: int) -> int:
        assert 0 <= ticks < TICKS_PERIOD, f"not a ticks value: {ticks}"
        return (ticks + delta) % TICKS_PERIOD

    def ticks_diff(new: int, old: int) -> int:
        assert 0 <= new < TICKS_PERIOD and 0 <= old < TICKS_PERIOD, (new, old)
        half = TICKS_PERIOD // 2
        return (new - old + half) % TICKS_PERIOD - half

    monkeypatch.setattr(module, "ticks_add", ticks_add)
    monkeypatch.setattr(module, "ticks_diff", ticks_diff)


def test_the_watchdog_fires_on_time_across_the_ticks_wrap(
    agent_module: ModuleType, hub: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    _micropython_ticks(agent_module, monkeypatch)
    agent, _ = make_agent(agent_module)
    near_wrap = TICKS_PERIOD - 100
    command(agent, t.Configure(0, 1), t.Tank(100, 100, 1000, 500), now_ms=near_wrap)
    agent.poll(TICKS_PERIOD - 1)
    agent.poll(399)  # wrapped: 499 ms after the command
    assert "motor_pair.stop" not in hub.names()
    agent.poll(400)
    assert hub.names()[-3:] == ["motor_pair.stop", "motor.stop", "motor.stop"]


def test_reports_keep_their_interval_across_the_ticks_wrap(
    agent_module: ModuleType, hub: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    _micropython_ticks(agent_module, monkeypatch)
    agent, sent = make_agent(agent_module)
    command(agent, t.Watch(t.NO_PORT, 100), now_ms=TICKS_PERIOD - 150)
    for now_ms in (TICKS_PERIOD - 50, 49, 50):
        agent.poll(now_ms)
    assert len(replies(sent)) == 3  # at -150, -50 and 50: every 100 ms through the wrap


class _IteratorOnly:
    """What MicroPython's ``await`` takes besides coroutines: an object it can iterate."""

    def __iter__(self) -> _IteratorOnly:
        return self

    def __next__(self) -> None:
        raise StopIteration


def test_what_micropython_can_await_is_awaited_and_plain_results_are_not(
    agent_module: ModuleType,
) -> None:
    import motor

    assert agent_module.is_awaitable(_IteratorOnly())
    assert agent_module.is_awaitable(x for x in ())
    for result in (motor.READY, 0, None, "text", b"", [1], (1,), {}):
        assert not agent_module.is_awaitable(result), result
