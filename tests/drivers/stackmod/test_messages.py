"""Tests for the StackMod message classes and data formats."""

from __future__ import annotations

import dataclasses

import pytest

from roboscript.drivers.stackmod.messages import (
    FORMATS,
    HOST_SOURCE,
    ULT_NO_ECHO,
    Command,
    Get,
    GetReply,
    Set,
)
from roboscript.errors import LocalProtocolError, ProtocolError

X = ord("X")


def test_every_command_has_a_format() -> None:
    assert set(FORMATS) == set(Command)
    assert [c.value for c in Command] == ["ARM", "MTR", "SRV", "ULT", "IRS", "DGT", "ANL"]


def test_seed_formats() -> None:
    mtr, srv = FORMATS[Command.MTR], FORMATS[Command.SRV]
    assert (mtr.selector_digits, mtr.value_width, mtr.value_min, mtr.value_max) == (1, 4, -100, 100)
    assert mtr.signed and mtr.settable
    assert (srv.selector_digits, srv.value_width, srv.value_min, srv.value_max) == (1, 3, 0, 180)
    assert not srv.signed and srv.settable


def test_format_value() -> None:
    mtr = FORMATS[Command.MTR]
    assert mtr.format_value(78) == "+078"
    assert mtr.format_value(-5) == "-005"
    assert mtr.format_value(0) == "+000"
    assert mtr.parse_value("-000") == 0
    assert mtr.parse_value("078") is None
    assert FORMATS[Command.SRV].parse_value("+38") is None
    assert FORMATS[Command.DGT].format_selector(7) == "07"


@pytest.mark.parametrize(
    "build",
    [
        lambda: Get(0x3F, Command.MTR, 2),
        lambda: Get(0x60, Command.MTR, 2),
        lambda: Get(X, "MTR", 2),  # type: ignore[arg-type]
        lambda: Get(X, Command.MTR, 10),
        lambda: Get(X, Command.MTR, -1),
        lambda: Get(X, Command.DGT, 100),
        lambda: Get(X, Command.MTR, True),
        lambda: Get(X, Command.MTR, 2, source=0x5F),
        lambda: Get(X, Command.MTR, 2, source=0x7B),
        lambda: Set(X, Command.MTR, 2, 101),
        lambda: Set(X, Command.MTR, 2, -101),
        lambda: Set(X, Command.SRV, 1, 181),
        lambda: Set(X, Command.SRV, 1, -1),
        lambda: Set(X, Command.ARM, 0, 2),
        lambda: Set(X, Command.DGT, 13, 2),
        lambda: Set(X, Command.MTR, 2, 1.5),  # type: ignore[arg-type]
        lambda: Set(X, Command.ULT, 0, 100),
        lambda: Set(X, Command.IRS, 0, 100),
        lambda: Set(X, Command.ANL, 0, 100),
        lambda: GetReply(X, Command.ULT, 0, 401),
        lambda: GetReply(X, Command.ULT, 0, 998),
        lambda: GetReply(X, Command.IRS, 0, 1024),
        lambda: GetReply(X, Command.ANL, 0, -1),
        lambda: GetReply(X, Command.DGT, 13, False),
    ],
)
def test_invalid_messages_raise_local_protocol_error(build: object) -> None:
    assert callable(build)
    with pytest.raises(LocalProtocolError):
        build()


def test_local_protocol_error_is_a_value_error() -> None:
    with pytest.raises(ValueError):
        Set(X, Command.MTR, 2, 500)
    assert issubclass(LocalProtocolError, ProtocolError)


def test_valid_edges() -> None:
    assert Set(X, Command.MTR, 9, -100).value == -100
    assert Set(0x40, Command.SRV, 0, 180).address == 0x40
    assert GetReply(0x5F, Command.ULT, 9, ULT_NO_ECHO).value == 999
    assert GetReply(X, Command.IRS, 0, 1023).value == 1023
    assert Set(X, Command.DGT, 99, 1).selector == 99
    assert Get(X, Command.MTR, 1, source=HOST_SOURCE).source == 0x70


def test_get_reply_helper() -> None:
    request = Get(X, Command.MTR, 2, source=HOST_SOURCE)
    assert request.reply(78) == GetReply(X, Command.MTR, 2, 78)
    with pytest.raises(LocalProtocolError):
        request.reply(200)


def test_messages_are_frozen_and_hashable() -> None:
    message = Set(X, Command.MTR, 2, 25)
    with pytest.raises(dataclasses.FrozenInstanceError):
        message.value = 30  # type: ignore[misc]
    assert {message, Set(X, Command.MTR, 2, 25)} == {message}
