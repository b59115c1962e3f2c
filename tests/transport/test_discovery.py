"""``roboscript ports``: serial ports with robot hints."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from roboscript.drivers import usb_hints
from roboscript.transport import discovery


def _port(device: str, vid: int | None, pid: int | None, description: str) -> SimpleNamespace:
    return SimpleNamespace(device=device, vid=vid, pid=pid, description=description)


def test_ports_are_hinted_and_robots_listed_first(monkeypatch: pytest.MonkeyPatch) -> None:
    ports = [
        _port("/dev/ttyS0", None, None, "n/a"),
        _port("/dev/ttyACM0", 0x2341, 0x8037, "Arduino Micro"),
        _port("/dev/ttyUSB0", 0x1A86, 0x7523, "USB Serial"),
    ]
    monkeypatch.setattr(discovery.list_ports, "comports", lambda: ports)
    found = discovery.list_robot_ports(usb_hints())
    assert [p.device for p in found] == ["/dev/ttyACM0", "/dev/ttyUSB0", "/dev/ttyS0"]
    assert found[0].usb_id == "2341:8037"
    assert found[0].hint is not None and "plen2" in found[0].hint
    assert found[1].hint == (
        "CH340 USB-serial (an Arduino clone): a MIRTO or another ASIP board (--robot mirto)"
        " or a StackMod bridge (--robot stackmod-rover)"
    )
    assert found[2].hint is None and found[2].description == ""


def test_unknown_product_of_a_known_vendor_gets_the_vendor_hint() -> None:
    hints = usb_hints()
    assert discovery._hint(0x2341, 0x9999, hints) == hints[(0x2341, None)]
    assert hints[(0x2341, None)] == "Arduino: a MIRTO or another ASIP board (--robot mirto)"
    assert discovery._hint(0x1234, 0x5678, hints) is None


def test_without_hints_a_port_is_only_listed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(discovery.list_ports, "comports", lambda: [_port("COM3", 0x2341, 1, "")])
    [found] = discovery.list_robot_ports()
    assert (found.device, found.usb_id, found.hint) == ("COM3", "2341:0001", None)
