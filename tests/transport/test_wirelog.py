"""Wire logs: the documented format round-trips any byte, and recorded transcripts replay
through the codecs without a single fault."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import ROOT

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.errors import RemoteProtocolError
from roboscript.transport.wirelog import WireLog, read_wire_log

TRANSCRIPTS = sorted((ROOT / "drivers").glob("*/transcripts/*.wire"))


def test_every_byte_value_round_trips(tmp_path: Path) -> None:
    log = WireLog(tmp_path / "all.wire")
    log.record(1.5, ">", bytes(range(256)))
    log.record(2.25, "<", b'"quoted"\\\n\r\x00')
    log.close()
    assert read_wire_log(tmp_path / "all.wire") == [
        (1.5, ">", bytes(range(256))),
        (2.25, "<", b'"quoted"\\\n\r\x00'),
    ]


def test_there_is_a_transcript_to_replay() -> None:
    assert TRANSCRIPTS


@pytest.mark.parametrize("path", TRANSCRIPTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_transcript_replays_through_the_asip_codec_in_both_roles(path: Path) -> None:
    records = read_wire_log(path)
    times = [t for t, _, _ in records]
    assert times == sorted(times)
    host = AsipCodec(Role.HOST)
    device = AsipCodec(Role.DEVICE)
    from_robot: list[object] = []
    to_robot: list[object] = []
    for _, direction, data in records:
        codec, sink = (host, from_robot) if direction == "<" else (device, to_robot)
        codec.receive_data(data)
        for item in drain(codec):
            assert not isinstance(item, RemoteProtocolError), item
            sink.append(item)
    assert isinstance(from_robot[0], m.StartupLine)
    assert any(isinstance(x, m.EncoderEvent) for x in from_robot)
    assert to_robot[0] == m.VersionRequest()
    assert m.EnableEncoderEvents(True) in to_robot
    assert to_robot[-2:] == [m.StopMotors(), m.SetMotorsPower(0, 0)]  # it ended stopped
