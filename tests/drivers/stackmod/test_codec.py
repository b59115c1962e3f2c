"""Example-based tests for the StackMod codec: seed packets, faults, framing, both roles."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from roboscript.codec import Codec, Role, drain
from roboscript.drivers.stackmod.codec import (
    I2C_WRITE_MAX_BYTES,
    LONGEST_PACKET_BYTES,
    ChecksumRule,
    StackModCodec,
    braces_excluded_checksum,
    checksum,
    seed_checksum,
)
from roboscript.drivers.stackmod.messages import (
    FORMATS,
    HOST_SOURCE,
    ULT_NO_ECHO,
    Command,
    Get,
    GetReply,
    Message,
    MotorPwm,
    Set,
)
from roboscript.errors import LocalProtocolError, RemoteProtocolError

X = ord("X")
RULES: tuple[ChecksumRule, ...] = ("seed", "braces_excluded")

# (frame, seed checksum, braces-excluded checksum, message): the six packets of the seed,
# with both checksums as recomputed in protocols.md section 3.2.
SEED_PACKETS: list[tuple[bytes, bytes, bytes, Message]] = [
    (b"{X?MTR2}", b"X", b"^", Get(X, Command.MTR, 2)),
    (b"{X?MTR2+078}", b"C", b"I", GetReply(X, Command.MTR, 2, 78)),
    (b"{X$MTR2+025}", b" ", b"&", Set(X, Command.MTR, 2, 25)),
    (b"{X?SRV1}", b"_", b"e", Get(X, Command.SRV, 1)),
    (b"{X?SRV1038}", b";", b"A", GetReply(X, Command.SRV, 1, 38)),
    (b"{X$SRV1168}", b"$", b"*", Set(X, Command.SRV, 1, 168)),
]


def packet(frame: bytes, rule: ChecksumRule = "seed") -> bytes:
    """Return ``frame`` with its checksum byte appended."""
    return frame + bytes([checksum(frame, rule)])


def decode(codec: StackModCodec, data: bytes) -> list[Message | str]:
    """Feed ``data`` and return the messages and fault kinds, in order."""
    codec.receive_data(data)
    typed: Codec[Message] = codec
    return [item.kind if isinstance(item, RemoteProtocolError) else item for item in drain(typed)]


def sender_for(message: Message) -> Role:
    return Role.DEVICE if isinstance(message, GetReply) else Role.HOST


def receiver_for(message: Message) -> Role:
    return Role.HOST if isinstance(message, GetReply) else Role.DEVICE


# -- checksums ---------------------------------------------------------------------------------


@pytest.mark.parametrize(("frame", "seed", "excluded", "message"), SEED_PACKETS)
def test_seed_checksums(frame: bytes, seed: bytes, excluded: bytes, message: Message) -> None:
    assert bytes([seed_checksum(frame)]) == seed
    assert bytes([braces_excluded_checksum(frame)]) == excluded
    assert bytes([checksum(frame, "seed")]) == seed
    assert bytes([checksum(frame, "braces_excluded")]) == excluded
    assert (seed[0] - excluded[0]) % 95 == 89


def test_checksum_rejects_unknown_rule() -> None:
    with pytest.raises(ValueError):
        checksum(b"{X?MTR2}", "crc")  # type: ignore[arg-type]


def test_reference_code_comment_example() -> None:
    # The Arduino source comment {Ae$MTR1+139}Y follows the braces-excluded rule.
    assert braces_excluded_checksum(b"{Ae$MTR1+139}") == ord("Y")
    # protocols.md: {p@?MTR2+078} has the seed checksum "{".
    assert seed_checksum(b"{p@?MTR2+078}") == ord("{")


# -- the seed's examples, both ways, both rules --------------------------------------------------


@pytest.mark.parametrize("rule", RULES)
@pytest.mark.parametrize(("frame", "seed", "excluded", "message"), SEED_PACKETS)
def test_seed_examples_encode(
    rule: ChecksumRule, frame: bytes, seed: bytes, excluded: bytes, message: Message
) -> None:
    codec = StackModCodec(sender_for(message), checksum=rule)
    assert codec.send(message) == frame + (seed if rule == "seed" else excluded)


@pytest.mark.parametrize("rule", RULES)
@pytest.mark.parametrize(("frame", "seed", "excluded", "message"), SEED_PACKETS)
def test_seed_examples_decode(
    rule: ChecksumRule, frame: bytes, seed: bytes, excluded: bytes, message: Message
) -> None:
    codec = StackModCodec(receiver_for(message), checksum=rule)
    assert decode(codec, frame + (seed if rule == "seed" else excluded)) == [message]
    assert codec.stats.messages == 1
    assert not codec.stats.faults
    assert codec.buffered == 0


@pytest.mark.parametrize(("frame", "seed", "excluded", "message"), SEED_PACKETS)
def test_other_rules_checksum_is_refused(
    frame: bytes, seed: bytes, excluded: bytes, message: Message
) -> None:
    seed_codec = StackModCodec(receiver_for(message), checksum="seed")
    assert decode(seed_codec, frame + excluded) == ["bad_checksum"]
    excluded_codec = StackModCodec(receiver_for(message), checksum="braces_excluded")
    assert decode(excluded_codec, frame + seed) == ["bad_checksum"]
    assert excluded_codec.stats.faults == {"bad_checksum": 1}
    assert excluded_codec.stats.dropped_bytes == len(frame) + 1


def test_seed_examples_as_one_stream_byte_by_byte() -> None:
    host, device = StackModCodec(Role.HOST), StackModCodec(Role.DEVICE)
    stream = b"".join(frame + seed for frame, seed, _, _ in SEED_PACKETS)
    got: list[Message | str] = []
    for byte in stream:
        got += decode(host, bytes([byte]))
        got += decode(device, bytes([byte]))
    requests = [m for *_, m in SEED_PACKETS if not isinstance(m, GetReply)]
    replies = [m for *_, m in SEED_PACKETS if isinstance(m, GetReply)]
    assert [m for m in got if isinstance(m, GetReply)] == replies
    assert [m for m in got if isinstance(m, (Get, Set))] == requests
    assert host.stats.faults == {"wrong_role": 4}
    assert device.stats.faults == {"wrong_role": 2}


# -- checksum bytes that look like braces -------------------------------------------------------


@pytest.mark.parametrize(
    ("rule", "frame", "check"),
    [
        ("seed", b"{X$MTR0+005}", b"{"),
        ("seed", b"{X$MTR0+007}", b"}"),
        ("braces_excluded", b"{X$SRV0002}", b"{"),
        ("braces_excluded", b"{X$MTR0+001}", b"}"),
    ],
)
def test_brace_checksum_followed_by_packet(rule: ChecksumRule, frame: bytes, check: bytes) -> None:
    assert packet(frame, rule) == frame + check
    device = StackModCodec(Role.DEVICE, checksum=rule)
    follower = Set(X, Command.SRV, 1, 168)
    stream = frame + check + StackModCodec(Role.HOST, checksum=rule).send(follower)
    first = decode(device, stream)
    assert len(first) == 2
    assert first[1] == follower
    assert not device.stats.faults
    # The same, one byte at a time.
    device = StackModCodec(Role.DEVICE, checksum=rule)
    got: list[Message | str] = []
    for byte in stream:
        got += decode(device, bytes([byte]))
    assert got == first


def test_brace_checksum_followed_by_garbage_and_packet() -> None:
    device = StackModCodec(Role.DEVICE)
    stream = b"{X$MTR0+005}{" + b"}}" + b"{X?MTR2}X"
    assert decode(device, stream) == [Set(X, Command.MTR, 0, 5), "garbage", Get(X, Command.MTR, 2)]
    assert device.stats.dropped_bytes == 2


# -- round trips of every command -----------------------------------------------------------------


def sample_messages() -> list[Message]:
    messages: list[Message] = []
    for command, fmt in FORMATS.items():
        for selector in (0, fmt.selector_max):
            values = [fmt.value_min, fmt.value_max, *sorted(fmt.special_values)]
            messages.append(Get(ord("@"), command, selector))
            messages.append(Get(ord("_"), command, selector, source=HOST_SOURCE))
            for value in values:
                messages.append(GetReply(X, command, selector, value))
                if fmt.settable:
                    messages.append(Set(X, command, selector, value))
                    messages.append(Set(0x45, command, selector, value, source=HOST_SOURCE))
    return messages


@pytest.mark.parametrize("rule", RULES)
def test_round_trip_every_command(rule: ChecksumRule) -> None:
    codecs = {role: StackModCodec(role, checksum=rule) for role in Role}
    for message in sample_messages():
        data = codecs[sender_for(message)].send(message)
        assert len(data) <= LONGEST_PACKET_BYTES
        assert decode(codecs[receiver_for(message)], data) == [message], data
    assert not codecs[Role.HOST].stats.faults
    assert not codecs[Role.DEVICE].stats.faults
    assert sorted({m.command for m in sample_messages()}, key=str) == sorted(Command, key=str)


def test_defined_formats_on_the_wire() -> None:
    host, device = StackModCodec(Role.HOST), StackModCodec(Role.DEVICE)
    assert host.send(Get(X, Command.ULT, 0))[:-1] == b"{X?ULT0}"
    assert device.send(GetReply(X, Command.ULT, 0, 123))[:-1] == b"{X?ULT0123}"
    assert device.send(GetReply(X, Command.ULT, 1, ULT_NO_ECHO))[:-1] == b"{X?ULT1999}"
    assert device.send(GetReply(X, Command.IRS, 2, 7))[:-1] == b"{X?IRS20007}"
    assert host.send(Set(X, Command.DGT, 13, 1))[:-1] == b"{X$DGT131}"
    assert host.send(Get(X, Command.DGT, 5))[:-1] == b"{X?DGT05}"
    assert device.send(GetReply(X, Command.ANL, 3, 1023))[:-1] == b"{X?ANL31023}"
    assert host.send(Set(X, Command.ARM, 0, 1))[:-1] == b"{X$ARM01}"
    assert host.send(Set(X, Command.MTR, 1, 0))[:-1] == b"{X$MTR1+000}"
    assert host.send(Set(X, Command.MTR, 1, -7))[:-1] == b"{X$MTR1-007}"


def test_minus_zero_is_accepted() -> None:
    device = StackModCodec(Role.DEVICE)
    assert decode(device, packet(b"{X$MTR1-000}")) == [Set(X, Command.MTR, 1, 0)]


# -- sending the wrong thing -------------------------------------------------------------------


def test_send_refuses_messages_of_the_other_role() -> None:
    host, device = StackModCodec(Role.HOST), StackModCodec(Role.DEVICE)
    with pytest.raises(LocalProtocolError):
        host.send(GetReply(X, Command.MTR, 2, 78))
    with pytest.raises(LocalProtocolError):
        device.send(Get(X, Command.MTR, 2))
    with pytest.raises(LocalProtocolError):
        device.send(Set(X, Command.MTR, 2, 5))
    with pytest.raises(LocalProtocolError):
        host.send(b"{X?MTR2}X")


def test_constructor_checks() -> None:
    with pytest.raises(ValueError):
        StackModCodec(Role.HOST, checksum="crc")  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        StackModCodec(Role.HOST, max_packet_bytes=LONGEST_PACKET_BYTES - 1)
    with pytest.raises(TypeError):
        StackModCodec("host")  # type: ignore[arg-type]
    codec = StackModCodec(Role.DEVICE, checksum="braces_excluded", max_packet_bytes=20)
    assert (codec.role, codec.checksum, codec.max_packet_bytes) == (
        Role.DEVICE,
        "braces_excluded",
        20,
    )
    assert "braces_excluded" in repr(codec)


def test_satisfies_codec_protocol() -> None:
    codec: Codec[Message] = StackModCodec(Role.HOST)
    assert codec.role is Role.HOST
    assert codec.next_message() is None


# -- faults ----------------------------------------------------------------------------------------

FOLLOWER = b"{X?MTR2}X"


@pytest.mark.parametrize(
    ("role", "bad", "kind"),
    [
        (Role.DEVICE, b"{X?MTR2}Y", "bad_checksum"),
        (Role.DEVICE, b"{X?MTR2}\xff", "bad_checksum"),
        (Role.DEVICE, packet(b"{X?FOO2}"), "unknown_command"),
        (Role.DEVICE, b"{1?MTR2}X", "malformed"),
        (Role.DEVICE, b"{X!MTR2}X", "malformed"),
        (Role.DEVICE, b"{X?Mtr2}X", "malformed"),
        (Role.DEVICE, b"{X?MTR2 }X", "malformed"),
        (Role.DEVICE, b"{X?MTR2\x00}X", "malformed"),
        (Role.DEVICE, packet(b"{X?MTR}"), "malformed"),
        (Role.DEVICE, packet(b"{X$MTR2}"), "malformed"),
        (Role.DEVICE, packet(b"{X$MTR21078}"), "malformed"),
        (Role.DEVICE, packet(b"{X$MTR2+07}"), "malformed"),
        (Role.DEVICE, packet(b"{X$MTR+2078}"), "malformed"),
        (Role.DEVICE, packet(b"{X$SRV1+38}"), "malformed"),
        (Role.DEVICE, packet(b"{X$MTR2+150}"), "out_of_range"),
        (Role.DEVICE, packet(b"{X$SRV1181}"), "out_of_range"),
        (Role.DEVICE, packet(b"{X$DGT132}"), "out_of_range"),
        (Role.DEVICE, packet(b"{X$ULT0100}"), "read_only"),
        (Role.DEVICE, packet(b"{X$ANL01000}"), "read_only"),
        (Role.DEVICE, packet(b"{X?MTR2+078}"), "wrong_role"),
        (Role.DEVICE, b"{X$MTR" + b"1" * 40, "overlong"),
        (Role.HOST, packet(b"{X?MTR2}"), "wrong_role"),
        (Role.HOST, packet(b"{X$MTR2+025}"), "wrong_role"),
        (Role.HOST, packet(b"{X?ULT0401}"), "out_of_range"),
        (Role.HOST, packet(b"{X?IRS01024}"), "out_of_range"),
        (Role.HOST, packet(b"{Xp?MTR2+078}"), "malformed"),
        (Role.HOST, packet(b"{pX?MTR2+078}"), "malformed"),
    ],
)
def test_fault_is_counted_refused_and_skipped(role: Role, bad: bytes, kind: str) -> None:
    codec = StackModCodec(role)
    good = FOLLOWER if role is Role.DEVICE else packet(b"{X?MTR2+078}")
    expected = Get(X, Command.MTR, 2) if role is Role.DEVICE else GetReply(X, Command.MTR, 2, 78)
    assert decode(codec, bad + good) == [kind, expected]
    assert codec.stats.faults == {kind: 1}
    assert codec.stats.dropped_bytes == len(bad)
    assert codec.stats.messages == 1


def test_fault_raises_remote_protocol_error_with_data() -> None:
    codec = StackModCodec(Role.DEVICE)
    codec.receive_data(b"{X?MTR2}Y" + FOLLOWER)
    with pytest.raises(RemoteProtocolError) as caught:
        codec.next_message()
    assert caught.value.kind == "bad_checksum"
    assert caught.value.data == b"{X?MTR2}Y"
    assert codec.next_message() == Get(X, Command.MTR, 2)
    assert codec.next_message() is None


def test_garbage_run_counts_once_however_split() -> None:
    for chunks in (
        [b"junk!!" + FOLLOWER],
        [b"ju", b"nk", b"!!", FOLLOWER],
        [b"junk!!{", FOLLOWER[1:]],
    ):
        codec = StackModCodec(Role.DEVICE)
        got: list[Message | str] = []
        for chunk in chunks:
            got += decode(codec, chunk)
        assert got == ["garbage", Get(X, Command.MTR, 2)], chunks
        assert codec.stats.faults == {"garbage": 1}
        assert codec.stats.dropped_bytes == 6


def test_garbage_between_packets_and_at_end() -> None:
    codec = StackModCodec(Role.DEVICE)
    got = decode(codec, FOLLOWER + b"\x00\x32" + FOLLOWER + b"\r\n")
    assert got == [Get(X, Command.MTR, 2), "garbage", Get(X, Command.MTR, 2), "garbage"]
    assert codec.stats.faults == {"garbage": 2}
    assert codec.stats.dropped_bytes == 4


def test_bytes_after_a_fault_belong_to_it() -> None:
    codec = StackModCodec(Role.DEVICE)
    assert decode(codec, b"{X?MTR2}Yjunk" + FOLLOWER) == ["bad_checksum", Get(X, Command.MTR, 2)]
    assert codec.stats.faults == {"bad_checksum": 1}
    assert codec.stats.dropped_bytes == 13


def test_new_start_inside_a_packet_restarts() -> None:
    codec = StackModCodec(Role.DEVICE)
    assert decode(codec, b"{X?MT" + FOLLOWER) == ["malformed", Get(X, Command.MTR, 2)]
    assert codec.stats.dropped_bytes == 5


def test_overlong_is_bounded_and_recovers() -> None:
    codec = StackModCodec(Role.DEVICE, max_packet_bytes=16)
    codec.receive_data(b"{X$MTR")
    assert codec.next_message() is None
    kinds: list[Message | str] = []
    for _ in range(100):
        codec.receive_data(b"1234567890")
        assert codec.buffered < 16 + 10
        kinds += decode(codec, b"")
        assert codec.buffered < 16
    assert kinds == ["overlong"]
    assert decode(codec, FOLLOWER) == [Get(X, Command.MTR, 2)]
    assert codec.stats.faults == {"overlong": 1}
    assert codec.stats.dropped_bytes == 6 + 1000


def test_max_packet_bytes_counts_the_whole_packet() -> None:
    fits = packet(b"{Xp$MTR2+025}")
    assert len(fits) == LONGEST_PACKET_BYTES
    codec = StackModCodec(Role.DEVICE, max_packet_bytes=LONGEST_PACKET_BYTES)
    assert decode(codec, fits) == [Set(X, Command.MTR, 2, 25, source=HOST_SOURCE)]
    assert decode(codec, packet(b"{Xp$MTR2+0250}")) == ["overlong"]


def test_incomplete_packet_waits() -> None:
    codec = StackModCodec(Role.DEVICE)
    for byte in FOLLOWER[:-1]:
        codec.receive_data(bytes([byte]))
        assert codec.next_message() is None
    codec.receive_data(FOLLOWER[-1:])
    assert codec.next_message() == Get(X, Command.MTR, 2)
    codec.receive_data(b"")
    assert codec.next_message() is None


# -- the reference code's two-address form -------------------------------------------------------


@pytest.mark.parametrize("rule", RULES)
def test_device_accepts_two_address_form(rule: ChecksumRule) -> None:
    device = StackModCodec(Role.DEVICE, checksum=rule)
    assert decode(device, packet(b"{Ep$MTR1+100}", rule)) == [
        Set(0x45, Command.MTR, 1, 100, source=0x70)
    ]
    # Source first, as the Arduino header comment's <SRC><DEST> order has it.
    assert decode(device, packet(b"{pE$MTR1-050}", rule)) == [
        Set(0x45, Command.MTR, 1, -50, source=0x70)
    ]
    assert decode(device, packet(b"{@p?MTR2}", rule)) == [Get(0x40, Command.MTR, 2, source=0x70)]
    assert decode(device, packet(b"{Ae$MTR1+099}", rule)) == [
        Set(0x41, Command.MTR, 1, 99, source=ord("e"))
    ]
    assert not device.stats.faults


def test_two_address_ambiguous_or_wrong_is_refused() -> None:
    device = StackModCodec(Role.DEVICE)
    assert decode(device, packet(b"{AX?MTR2}")) == ["malformed"]
    assert decode(device, packet(b"{pq?MTR2}")) == ["malformed"]
    assert decode(device, packet(b"{Xp}MTR2}")) == ["malformed"]


def test_reference_host_packet_out_of_seed_range() -> None:
    # StackModIO.set_motor sends PWM values up to 255; the seed's range is +-100.
    device = StackModCodec(Role.DEVICE, checksum="braces_excluded")
    assert decode(device, b"\x32" + packet(b"{Ep$MTR1+139}", "braces_excluded")) == [
        "garbage",
        "out_of_range",
    ]


def test_host_sends_two_address_form() -> None:
    host = StackModCodec(Role.HOST, checksum="braces_excluded")
    data = host.send(Set(0x45, Command.MTR, 1, -100, source=HOST_SOURCE))
    assert data == packet(b"{Ep$MTR1-100}", "braces_excluded")


# -- the author's own packet and I2C framing ---------------------------------------------------


def test_host_sends_the_authors_motor_packet_with_pwm_values() -> None:
    host = StackModCodec(Role.HOST, checksum="braces_excluded")
    assert host.send(MotorPwm(ord("M"), 1, 139)) == b"{Mp$MTR1+139}p"
    assert host.send(MotorPwm(ord("E"), 2, -255)) == b"{Ep$MTR2-255}j"
    assert host.send(MotorPwm(ord("E"), 1, 0)) == b"{Ep$MTR1+000}["


def test_i2c_framing_leads_every_write_with_the_register_byte() -> None:
    host = StackModCodec(Role.HOST, checksum="braces_excluded", framing="i2c")
    assert host.send(MotorPwm(ord("E"), 1, 139)) == b"2{Ep$MTR1+139}h"
    assert host.send(Get(X, Command.MTR, 2)) == b"2" + packet(b"{X?MTR2}", "braces_excluded")
    longest = host.send(Set(X, Command.MTR, 1, -100, source=HOST_SOURCE))
    assert len(longest) == LONGEST_PACKET_BYTES + 1 <= I2C_WRITE_MAX_BYTES


def test_a_device_with_i2c_framing_skips_register_bytes_but_not_other_strays() -> None:
    device = StackModCodec(Role.DEVICE, framing="i2c")
    one, two = packet(b"{X$MTR1+010}"), packet(b"{X$MTR2+020}")
    assert decode(device, b"2" + one + b"2" + two) == [
        Set(X, Command.MTR, 1, 10),
        Set(X, Command.MTR, 2, 20),
    ]
    assert not device.stats.faults
    assert decode(device, b"22" + one) == ["garbage", Set(X, Command.MTR, 1, 10)]
    serial = StackModCodec(Role.DEVICE)
    assert decode(serial, b"2" + one) == ["garbage", Set(X, Command.MTR, 1, 10)]


def test_a_register_byte_split_from_its_packet_is_still_skipped() -> None:
    device = StackModCodec(Role.DEVICE, framing="i2c")
    device.receive_data(b"2")
    assert device.next_message() is None
    device.receive_data(packet(b"{X$MTR1+010}"))
    assert list(drain(device)) == [Set(X, Command.MTR, 1, 10)]


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: MotorPwm(ord("E"), 0, 10), "motor must be an int 1..9"),
        (lambda: MotorPwm(ord("E"), 10, 10), "motor must be an int 1..9"),
        (lambda: MotorPwm(ord("E"), 1, 256), "PWM must be an int -255..255"),
        (lambda: MotorPwm(ord("E"), 1, -256), "PWM must be an int -255..255"),
        (lambda: MotorPwm(ord("p"), 1, 0), "address must be an int 0x40..0x5F"),
        (lambda: MotorPwm(ord("E"), 1, 0, ord("E")), "source must be None or an int 0x60"),
    ],
)
def test_the_authors_packet_refuses_values_it_cannot_carry(
    make: Callable[[], object], message: str
) -> None:
    with pytest.raises(LocalProtocolError, match=message):
        make()


def test_an_unknown_framing_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown StackMod framing 'spi'"):
        StackModCodec(Role.HOST, framing="spi")  # type: ignore[arg-type]
