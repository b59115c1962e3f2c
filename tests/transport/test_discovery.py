"""``roboscript ports``: serial ports with robot hints."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

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
    found = discovery.list_robot_ports()
    assert [p.device for p in found] == ["/dev/ttyACM0", "/dev/ttyUSB0", "/dev/ttyS0"]
    assert found[0].usb_id == "2341:8037"
    assert found[0].hint is not None and "plen2" in found[0].hint
    assert found[1].hint is not None and "CH340" in found[1].hint
    assert found[2].hint is None and found[2].description == ""


def test_unknown_product_of_a_known_vendor_gets_the_vendor_hint() -> None:
    assert discovery._hint(0x2341, 0x9999) == discovery.USB_HINTS[(0x2341, None)]
    assert discovery._hint(0x1234, 0x5678) is None
