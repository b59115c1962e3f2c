"""The tunnel format between the host and the agent on the SPIKE hub: bytes, round trips, faults."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from roboscript.codec import Role
from roboscript.drivers.spike import tunnel as t
from roboscript.errors import LocalProtocolError, RemoteProtocolError

EXAMPLES = [
    pytest.param(t.VersionQuery(), "01 00", id="version-query"),
    pytest.param(t.Configure(0, 1), "02 02 00 01", id="configure-A-B"),
    pytest.param(t.Tank(300, 300, 5000, 1500), "03 08 2c 01 2c 01 88 13 dc 05", id="tank"),
    pytest.param(t.Tank(-1, 2, 0, 0), "03 08 ff ff 02 00 00 00 00 00", id="tank-reverse"),
    pytest.param(
        t.TankForDegrees(7, 360, 200, -200), "04 09 07 68 01 00 00 c8 00 38 ff", id="move"
    ),
    pytest.param(t.Power(-10000, 10000, 1000), "05 06 f0 d8 10 27 e8 03", id="power"),
    pytest.param(t.Beep(880, 200, 100), "06 05 70 03 c8 00 64", id="beep"),
    pytest.param(t.ShowText("Hi"), "07 02 48 69", id="text"),
    pytest.param(t.ShowText(""), "07 00", id="empty-text"),
    pytest.param(t.ClearDisplay(), "08 00", id="clear"),
    pytest.param(t.Stop(), "09 00", id="stop"),
    pytest.param(t.Version("roboscript-agent 1"), "81 12" + b"roboscript-agent 1".hex(), id="ver"),
    pytest.param(t.MoveDone(7, t.MoveStatus.STALLED), "82 02 07 01", id="move-done"),
    pytest.param(t.Refused(0x03, t.RefuseReason.NOT_CONFIGURED), "8f 02 03 04", id="refused"),
]


@pytest.mark.parametrize(("record", "wire"), EXAMPLES)
def test_records_have_these_exact_bytes_and_decode_back(record: t.Record, wire: str) -> None:
    data = bytes.fromhex(wire.replace(" ", ""))
    assert record.encode() == data
    reader = Role.HOST if record.op >= 0x80 else Role.DEVICE
    assert list(t.decode_records(data, reader)) == [record]


def test_several_records_share_one_message() -> None:
    data = t.encode(t.Configure(0, 1), t.Tank(100, 100, 1000, 0), t.Beep(440, 100, 50))
    assert list(t.decode_records(data, Role.DEVICE)) == [
        t.Configure(0, 1),
        t.Tank(100, 100, 1000, 0),
        t.Beep(440, 100, 50),
    ]


@pytest.mark.parametrize(
    ("build", "problem"),
    [
        (lambda: t.Tank(40000, 0, 0, 0), "Tank"),
        (lambda: t.Tank(0, 0, 20000, 0), "acceleration"),
        (lambda: t.Configure(0, 6), "port 6"),
        (lambda: t.Configure(2, 2), "different ports"),
        (lambda: t.Power(10001, 0, 0), "duty"),
        (lambda: t.Beep(440, 100, 101), "volume"),
        (lambda: t.TankForDegrees(1, -5, 100, 100), "negative"),
        (lambda: t.TankForDegrees(256, 5, 100, 100), "TankForDegrees"),
        (lambda: t.ShowText("x" * 201), "longer than 200"),
        (lambda: t.Version(""), "1..64"),
        (lambda: t.MoveDone(1, 9), "MoveStatus"),
    ],
)
def test_records_out_of_range_are_refused_when_built(build: object, problem: str) -> None:
    with pytest.raises(LocalProtocolError, match=problem):
        build()  # type: ignore[operator]


def test_each_side_reads_only_what_the_other_sends() -> None:
    faults = list(t.decode_records(t.Stop().encode(), Role.HOST))
    assert [f.kind for f in faults if isinstance(f, RemoteProtocolError)] == ["tunnel_role"]
    faults = list(t.decode_records(t.Version("1").encode(), Role.DEVICE))
    assert [f.kind for f in faults if isinstance(f, RemoteProtocolError)] == ["tunnel_role"]


def test_a_bad_record_is_skipped_and_the_next_one_still_read() -> None:
    data = bytes.fromhex("4002aaaa") + bytes.fromhex("0301ff") + t.Stop().encode() + b"\x07"
    items = list(t.decode_records(data, Role.DEVICE))
    kinds = [item.kind if isinstance(item, RemoteProtocolError) else item for item in items]
    assert kinds == ["tunnel_unknown", "tunnel_length", t.Stop(), "tunnel_length"]


def test_text_that_is_not_utf8_is_a_value_fault() -> None:
    (fault,) = t.decode_records(b"\x07\x02\xff\xfe", Role.DEVICE)
    assert isinstance(fault, RemoteProtocolError) and fault.kind == "tunnel_value"


def test_the_stream_decoder_waits_for_the_rest_of_a_record_and_names_its_op() -> None:
    decoder = t.TunnelDecoder(Role.DEVICE)
    decoder.feed(b"\x03\x08\x2c\x01")
    assert decoder.next_record() is None
    assert decoder.pending_bytes == 4
    decoder.feed(b"\x2c\x01\x88\x13\xdc\x05\x40\x00")
    assert decoder.next_record() == t.Tank(300, 300, 5000, 1500)
    with pytest.raises(RemoteProtocolError):
        decoder.next_record()
    assert decoder.last_op == 0x40
    assert decoder.next_record() is None


def test_agent_version_is_read_from_a_program_source() -> None:
    assert t.agent_version_of(b'import x\nAGENT_VERSION = "roboscript-agent 7"\n') == (
        "roboscript-agent 7"
    )
    assert t.agent_version_of(b"print('hello')\n") is None
    assert t.agent_version_of(b'  AGENT_VERSION = "indented"\n') is None


# ----------------------------------------------------------------------------- properties

I16 = st.integers(-0x8000, 0x7FFF)
U16 = st.integers(0, 0xFFFF)
TEXT = st.text(max_size=60).filter(lambda s: len(s.encode()) <= t.MAX_TEXT_BYTES)
COMMANDS = st.one_of(
    st.just(t.VersionQuery()),
    st.tuples(st.integers(0, 5), st.integers(0, 5))
    .filter(lambda p: p[0] != p[1])
    .map(lambda p: t.Configure(*p)),
    st.builds(t.Tank, I16, I16, st.integers(0, 10000), U16),
    st.builds(t.TankForDegrees, st.integers(0, 255), st.integers(0, 2**31 - 1), I16, I16),
    st.builds(t.Power, st.integers(-10000, 10000), st.integers(-10000, 10000), U16),
    st.builds(t.Beep, U16, U16, st.integers(0, 100)),
    st.builds(t.ShowText, TEXT),
    st.just(t.ClearDisplay()),
    st.just(t.Stop()),
)
REPLIES = st.one_of(
    st.builds(t.Version, st.text(min_size=1, max_size=20)),
    st.builds(t.MoveDone, st.integers(0, 255), st.sampled_from(t.MoveStatus)),
    st.builds(t.Refused, st.integers(0, 255), st.sampled_from(t.RefuseReason)),
)


@given(st.lists(COMMANDS, max_size=8))
def test_commands_round_trip(records: list[t.Record]) -> None:
    assert list(t.decode_records(t.encode(*records), Role.DEVICE)) == records


@given(st.lists(REPLIES, max_size=8))
def test_replies_round_trip(records: list[t.Record]) -> None:
    assert list(t.decode_records(t.encode(*records), Role.HOST)) == records


@given(st.lists(COMMANDS, min_size=1, max_size=6), st.data())
def test_records_split_anywhere_decode_the_same(
    records: list[t.Record], data: st.DataObject
) -> None:
    wire = t.encode(*records)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(wire)), max_size=5)))
    decoder = t.TunnelDecoder(Role.DEVICE)
    got: list[t.Record] = []
    for start, end in zip([0, *cuts], [*cuts, len(wire)], strict=True):
        decoder.feed(wire[start:end])
        while (record := decoder.next_record()) is not None:
            got.append(record)
    assert got == records
    assert decoder.pending_bytes == 0


@given(st.binary(max_size=600), st.sampled_from([Role.HOST, Role.DEVICE]))
def test_arbitrary_bytes_only_ever_give_records_or_remote_protocol_errors(
    data: bytes, role: Role
) -> None:
    for item in t.decode_records(data, role):
        assert isinstance(item, t.Record | RemoteProtocolError)
    decoder = t.TunnelDecoder(role)
    decoder.feed(data)
    for _ in range(len(data) + 1):
        try:
            if decoder.next_record() is None:
                break
        except RemoteProtocolError:
            continue
    assert decoder.pending_bytes <= 257
