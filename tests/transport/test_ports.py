"""Opening ports by URL: why a port did not open is told by the error, not by its text."""

from __future__ import annotations

import errno
import socket
from pathlib import Path

import pytest
import serial

from roboscript.errors import LinkError
from roboscript.transport import ports
from roboscript.transport.ports import open_port


def _refuse(exc: Exception) -> object:
    def serial_for_url(*args: object, **kwargs: object) -> object:
        raise exc

    return serial_for_url


def test_permission_denied_on_a_port_whose_name_contains_111(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # pyserial's own message for a device the user may not open (serialposix.Serial.open)
    name = "/dev/ttyUSB111"
    denied = serial.SerialException(
        errno.EACCES, f"could not open port {name}: [Errno 13] Permission denied: '{name}'"
    )
    monkeypatch.setattr(ports.serial, "serial_for_url", _refuse(denied))
    with pytest.raises(LinkError, match="permission denied") as caught:
        open_port(name)
    assert "nothing is listening" not in str(caught.value)
    assert name in str(caught.value)


def test_a_missing_device_is_no_such_port(tmp_path: Path) -> None:
    with pytest.raises(LinkError, match="there is no such port") as caught:
        open_port(str(tmp_path / "ttyACM111"))
    assert "nothing is listening" not in str(caught.value)


def test_refused_connection_through_pyserial_handler_is_nothing_listening() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    free_port = server.getsockname()[1]
    server.close()
    # an option sends the URL to pyserial's socket handler, which chains the OSError
    with pytest.raises(LinkError, match="nothing is listening there"):
        open_port(f"socket://127.0.0.1:{free_port}?logging=warning")


def test_an_unexplained_error_keeps_its_own_text(monkeypatch: pytest.MonkeyPatch) -> None:
    odd = serial.SerialException("Could not configure port: (5, 'Input/output error 111')")
    monkeypatch.setattr(ports.serial, "serial_for_url", _refuse(odd))
    with pytest.raises(LinkError, match="Input/output error 111"):
        open_port("/dev/ttyS111")
