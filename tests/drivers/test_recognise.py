"""A port that speaks another robot's protocol is named (issue 14, item 7).

The recogniser is fed the bytes a port sent; each protocol's signature is read by its own
codec. The end-to-end tests connect to the real served simulators on loopback TCP.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, run_cli, served_simulator

from roboscript.drivers.recognise import (
    RobotPicker,
    handshake_failure,
    recognise_protocol,
    robots_picked_with,
    wrong_robot_hint,
)
from roboscript.profiles import get_profile
from roboscript.robot import Robot


@pytest.mark.parametrize(
    ("robot", "protocol"),
    [
        ("mirto", "asip"),
        ("spike-prime", "spike"),
        ("stackmod-rover", "stackmod"),
        ("plen2", "plen"),
    ],
)
def test_what_each_simulated_robot_sends_is_recognised_as_its_protocol(
    robot: str, protocol: str
) -> None:
    with Robot.connect(robot) as bot:
        bot.scheduler.run(until=lambda: False, max_duration_s=1.0)
        heard = bytes(bot.driver.link.heard)  # type: ignore[attr-defined]
    assert heard
    assert recognise_protocol(heard) == protocol
    assert wrong_robot_hint(heard, protocol) is None  # its own robot: nothing to say


@pytest.mark.parametrize("data", [b"", b"hello world\n", b"\xff\xfe\xfd" * 20, b"OK\r\n" * 5])
def test_text_or_noise_is_no_protocol(data: bytes) -> None:
    assert recognise_protocol(data) is None


def test_an_asip_banner_names_the_robot_to_use() -> None:
    banner = b"!Mirtle2017 running on ATmega328P\n@I,a,2,{4:578,5:615}\n"
    assert wrong_robot_hint(banner, "spike") == (
        "this port speaks the ASIP protocol (a MIRTO or another ASIP board): use --robot mirto"
    )


def test_a_front_end_with_its_own_robot_control_is_named_instead_of_the_option() -> None:
    banner = b"!Mirtle2017 running on ATmega328P\n@I,a,2,{4:578,5:615}\n"
    picker = RobotPicker("pick {robot} in the menu", "pick it in the menu")
    with pytest.raises(KeyError), robots_picked_with(picker):
        assert wrong_robot_hint(banner, "spike") == (
            "this port speaks the ASIP protocol (a MIRTO or another ASIP board): pick mirto in"
            " the menu"
        )
        assert handshake_failure("mirto", "asip", "socket://h:1", b"", 48, "").endswith(
            "if it is another robot, pick it in the menu.)"
        )
        raise KeyError("the run ends by an error")
    after = wrong_robot_hint(banner, "spike")
    assert after is not None and after.endswith(": use --robot mirto")


def test_silence_says_what_was_tried() -> None:
    text = handshake_failure("mirto", "asip", "socket://h:1", b"", 48, "within 3 s")
    assert text.startswith(
        "mirto did not answer on socket://h:1 within 3 s: nothing came back to 48 bytes of the "
        "ASIP handshake"
    )


def test_a_board_that_spoke_its_protocol_but_never_finished_is_told_so() -> None:
    # a MIRTO still starting up when the wait ended: its start-up line came, no version reply
    heard = b"!Mirtle2017 running on ATmega328P with Services: I M B R T S D L P \n"
    text = handshake_failure("mirto", "asip", "/dev/ttyACM0", heard, 80, "within 5 s")
    assert text == (
        f"mirto did not answer on /dev/ttyACM0 within 5 s: it sent {len(heard)} bytes of the "
        "ASIP protocol but did not finish the handshake: is it still starting up (a board that "
        "restarts when its port opens takes seconds), and does its firmware answer what "
        "roboscript asks?"
    )


@pytest.mark.parametrize(
    ("robot", "answer"),
    [
        # what the MIRTO firmware answers each one's first bytes with, when the host missed
        # its start-up lines (a board that does not reset greets only at power-on)
        ("plen2", b"~<,?,1{INVALID_SERVICE}\n~I,?,1{INVALID_SERVICE}\n"),
        ("stackmod-rover", b"~{,?,1{INVALID_SERVICE}\n~M,?,1{INVALID_SERVICE}\n"),
        ("plen2", b"~<,?,1{INVALID_SERVICE}\n"),
    ],
)
def test_a_mirto_whose_greeting_was_missed_is_named_by_its_error_lines(
    robot: str, answer: bytes
) -> None:
    assert wrong_robot_hint(answer, get_profile(robot).protocol) == (
        "this port speaks the ASIP protocol (a MIRTO or another ASIP board): use --robot mirto"
    )


@pytest.fixture
def served_mirto() -> Iterator[int]:
    with served_simulator("mirto") as port:
        yield port


def test_a_served_mirto_asked_for_as_a_spike_hub_is_named(served_mirto: int) -> None:
    url = f"socket://127.0.0.1:{served_mirto}"
    done = run_cli("run", "missions/square.yaml", "--robot", "spike-prime", "--port", url)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines()[-1] == (
        f"error: spike-prime did not answer on {url}: this port speaks the ASIP protocol "
        "(a MIRTO or another ASIP board): use --robot mirto"
    )
    assert "Traceback" not in done.stderr


def test_a_served_mirto_asked_for_as_a_plen2_is_named(served_mirto: int, tmp_path: Path) -> None:
    mission = tmp_path / "walk.yaml"
    mission.write_text(
        "states:\n  go:\n    do: {walk: {steps: 2}}\n    on: {done: end, failed: end}\n"
        "  end: {final: success}\n"
    )
    url = f"socket://127.0.0.1:{served_mirto}"
    done = run_cli("run", str(mission), "--robot", "plen2", "--port", url)
    assert done.returncode == 1
    assert "this port speaks the ASIP protocol" in done.stderr
    assert "use --robot mirto" in done.stderr


@pytest.fixture
def served_spike() -> Iterator[int]:
    with served_simulator("spike-prime") as port:
        yield port


def test_a_served_spike_hub_that_stays_silent_is_told_what_was_tried(served_spike: int) -> None:
    url = f"socket://127.0.0.1:{served_spike}"
    done = run_cli("run", "missions/square.yaml", "--robot", "mirto", "--port", url)
    assert done.returncode == 1
    [line] = done.stderr.strip().splitlines()
    # how many probes went out in those 5 s depends on the machine's load: not the count
    assert re.match(
        rf"error: mirto did not answer on {re.escape(url)} within 5 s: nothing came back to "
        r"\d+ bytes of the ASIP handshake",
        line,
    )
    assert "A SPIKE hub or a StackMod bridge says nothing until asked" in line


@pytest.mark.parametrize(
    ("robot", "protocol"),
    [("mirto", "asip"), ("spike-prime", "spike"), ("stackmod-rover", "stackmod")],
)
def test_a_handshake_with_the_robot_asked_for_loads_no_other_protocols_codec(
    robot: str, protocol: str
) -> None:
    # A graded run's mission process connects once per run: every codec it imports on the
    # way is start-up time charged to the student, so only the robot's own may be loaded.
    code = (
        "import sys\n"
        "from roboscript.robot import Robot\n"
        f"with Robot.connect({robot!r}) as bot:\n"
        "    bot.scheduler.run(until=lambda: False, max_duration_s=1.0)\n"
        "print(sorted(m for m in sys.modules if m.startswith('roboscript.drivers.')"
        " and m.endswith('.codec')))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
        check=True,
    )
    codecs = ast.literal_eval(done.stdout.strip().splitlines()[-1])
    assert codecs == [f"roboscript.drivers.{protocol}.codec"]
