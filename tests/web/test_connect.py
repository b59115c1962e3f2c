"""A run on a robot from the page, through its Python bridge here in CPython: a handshake that
fails names the page's own Robot list, since a student in the page cannot give ``--robot``.

The robots are the real served simulators on loopback TCP, so the bytes the handshake hears
are each protocol's own.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import MISSIONS, served_simulator

from roboscript.drivers.recognise import handshake_failure
from roboscript.errors import LinkError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.transport.wirelog import read_wire_log
from roboscript.web import connect
from roboscript.web.bridge import run_text
from roboscript.web.connect import RobotRun, on_robot, stop_bytes

SQUARE = (MISSIONS / "square.yaml").read_text(encoding="utf-8")


@pytest.fixture
def served_mirto() -> Iterator[str]:
    with served_simulator("mirto") as port:
        yield f"socket://127.0.0.1:{port}"


@pytest.fixture
def served_spike() -> Iterator[str]:
    with served_simulator("spike-prime") as port:
        yield f"socket://127.0.0.1:{port}"


def test_a_mirto_run_as_a_spike_hub_from_the_page_names_the_robot_list(served_mirto: str) -> None:
    answer = json.loads(run_text("square.yaml", SQUARE, robot="spike-prime", port=served_mirto))
    assert answer["summary"] is None
    assert answer["error"] == (
        f"spike-prime did not answer on {served_mirto}: this port speaks the ASIP protocol"
        " (a MIRTO or another ASIP board): choose mirto in the Robot list, and run again"
    )


def test_a_silent_spike_hub_run_as_a_mirto_from_the_page_names_the_robot_list(
    served_spike: str,
) -> None:
    answer = json.loads(run_text("square.yaml", SQUARE, robot="mirto", port=served_spike))
    assert answer["summary"] is None
    assert answer["error"].startswith(f"mirto did not answer on {served_spike} within 5 s:")
    assert answer["error"].endswith(
        "(A SPIKE hub or a StackMod bridge says nothing until asked in its own protocol: if it"
        " is another robot, choose it in the Robot list.)"
    )
    assert "--robot" not in answer["error"]


def test_after_a_run_in_the_page_the_command_line_still_names_its_option(
    served_mirto: str,
) -> None:
    json.loads(run_text("square.yaml", SQUARE, robot="spike-prime", port=served_mirto))
    assert handshake_failure("mirto", "asip", "socket://h:1", b"", 48, "within 3 s").endswith(
        "if it is another robot, name it with --robot.)"
    )


ASIP_BANNER = b"!Mirtle2017 running on ATmega328P\n@I,a,2,{4:578,5:615}\n"


def test_a_robot_chosen_in_the_page_is_named_as_chosen_never_by_its_url(tmp_path: Path) -> None:
    with on_robot("webserial://1", tmp_path):
        wrong = handshake_failure("spike-prime", "spike", "webserial://1", ASIP_BANNER, 12, "")
        silent = handshake_failure("mirto", "asip", "webbluetooth://2", b"", 48, "within 3 s")
    assert wrong == (
        "the robot on the serial port you chose did not answer as spike-prime: this port speaks"
        " the ASIP protocol (a MIRTO or another ASIP board): choose mirto in the Robot list, and"
        " run again"
    )
    assert silent.startswith(
        "the Bluetooth robot you chose did not answer as mirto within 3 s: nothing came back to"
        " 48 bytes of the ASIP handshake"
    )
    assert "://" not in wrong + silent


@pytest.mark.parametrize("robot", ["mirto", "plen2", "spike-prime", "stackmod-rover"])
def test_the_stop_the_page_is_handed_is_what_the_driver_sends_to_stop(
    robot: str, tmp_path: Path
) -> None:
    log = tmp_path / "stop.log"
    with Robot.connect(robot, wire_log=str(log)) as connected:
        wire_log = connected.driver.link.wire_log
        assert wire_log is not None
        wire_log.flush()
        before = len(read_wire_log(log))
        connected.stop()
        wire_log.flush()
        sent = b"".join(data for _, way, data in read_wire_log(log)[before:] if way == ">")
    assert sent and stop_bytes(get_profile(robot)) == sent


def test_a_robot_whose_stop_cannot_be_worked_out_still_runs_from_the_page(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def no_simulator(profile: object) -> bytes:
        raise LinkError("no simulator of this robot")

    monkeypatch.setattr(connect, "stop_bytes", no_simulator)
    run = RobotRun("webserial://1", tmp_path, get_profile("mirto"))
    assert run.options["port"] == "webserial://1"  # the stop is left to the run itself
