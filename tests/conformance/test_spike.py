"""SPIKE Prime facts from code that roboscript did not write, pinned as bytes.

Each test states the fact it pins and where it comes from (LEGO's own example client in
``LEGO/spike-prime-docs`` v1.0, and the public programs that drive a real hub's tunnel; see
``docs/robots/spike-prime.md``). They hold the host driver and the simulated hub to those
facts separately, so the two cannot agree on something a real hub does not do.
"""

from __future__ import annotations

import ast
import sys
import zlib
from pathlib import Path
from types import ModuleType, SimpleNamespace
from typing import Any

import pytest

from roboscript.codec import Role, drain
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.crc import crc32
from roboscript.drivers.spike.device import AGENT_TUNNEL_ORDER, SpikeHub
from roboscript.drivers.spike.driver import AGENT_FILE_NAME, agent_source
from roboscript.errors import LocalProtocolError
from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import load_world

AGENT = Path(__file__).parents[2] / "roboscript" / "drivers" / "spike" / "agent" / "hub_agent.py"


class _Hub:
    """The simulated hub, spoken to in unframed message bytes."""

    def __init__(self) -> None:
        self.sim = Simulation(load_world("empty"), get_profile("spike-prime"), seed=1)
        self.sim.connect()
        self.host = SpikeCodec(Role.HOST)

    @property
    def device(self) -> SpikeHub:
        assert isinstance(self.sim.device, SpikeHub)
        return self.sim.device

    def ask(self, message: bytes) -> list[bytes]:
        """Send one message's bytes (id + fields); return the bytes of each answer."""
        self.sim.write(self.host.send(m.decode_message(message)))
        self.host.receive_data(self.sim.read(self.sim.in_waiting))
        return [x.encode() for x in drain(self.host) if isinstance(x, m.Message)]


# ------------------------------------------------------------------ StartFileUploadRequest


def test_the_upload_name_is_utf8_then_one_nul_then_slot_and_crc() -> None:
    """LEGO's example packs StartFileUploadRequest as ``<B{len+1}sBI``: id, the UTF-8 name
    and one NUL, slot (u8), CRC (u32 little-endian). ``string[32]`` is the most, not a fixed
    width: a hub reading the name up to its NUL would take padding for slot 0 and CRC 0."""
    wire = m.StartFileUploadRequest("program.py", 0, 0xDEADBEEF).encode()
    assert wire == b"\x0cprogram.py\x00\x00\xef\xbe\xad\xde"


def test_the_driver_uploads_its_agent_under_that_layout() -> None:
    """The same layout for the name the driver stores its agent under, in slot 19."""
    crc = crc32(agent_source()).to_bytes(4, "little")
    wire = m.StartFileUploadRequest(AGENT_FILE_NAME, 19, crc32(agent_source())).encode()
    assert wire == b"\x0croboscript_agent.py\x00\x13" + crc


def test_a_name_of_31_bytes_is_the_longest() -> None:
    """LEGO's example refuses a name of 32 or more UTF-8 bytes (it and its NUL fill 32)."""
    assert m.StartFileUploadRequest("x" * 31, 1, 2).encode() == (
        b"\x0c" + b"x" * 31 + b"\x00\x01\x02\x00\x00\x00"
    )
    with pytest.raises(LocalProtocolError):
        m.StartFileUploadRequest("x" * 32, 1, 2)


@pytest.mark.parametrize(
    "request_bytes",
    [
        b"\x0cprogram.py\x00\x05\x50\x68\x5d\xa7",
        b"\x0cprogram.py" + b"\x00" * 22 + b"\x05\x50\x68\x5d\xa7",
    ],
    ids=["lego-name-and-nul", "seed-fixed-32-bytes"],
)
def test_the_simulated_hub_accepts_both_name_forms(request_bytes: bytes) -> None:
    """The hub model takes LEGO's form and the seed document's NUL-padded 32-byte form (the
    name ends at its NUL in both) and answers ``0d 00`` (ACK) to each, then stores the file
    ``abc`` whose CRC 0xa75d6850 the request announced."""
    hub = _Hub()
    assert hub.ask(request_bytes) == [b"\x0d\x00"]
    assert hub.ask(b"\x10\x50\x68\x5d\xa7\x03\x00abc") == [b"\x11\x00"]
    assert hub.device.slots[5] == b"abc"


# --------------------------------------------------------------------------------- CRC


def test_the_crc_pads_the_data_with_zeros_to_a_multiple_of_4_bytes() -> None:
    """LEGO's ``crc(data, seed=0, align=4)`` zero-pads ``data`` to a multiple of 4 bytes, then
    takes ``zlib.crc32(data, seed)``: ``abc`` is checked as ``abc\\0``."""
    assert crc32(b"abc") == zlib.crc32(b"abc\x00") == 0xA75D6850
    assert crc32(b"abcd") == 0xED82CD11  # already aligned: no padding


def test_each_chunk_is_padded_on_its_own_seeded_with_the_running_crc() -> None:
    """The running CRC of each TransferChunkRequest is ``crc(chunk, previous)``: every chunk
    is padded, so chunks of 5 and 3 bytes end at 0x9d3f9c20, which is not the file's CRC of
    ``abcdefgh`` (0xaeef2a50): only chunks of multiples of 4 bytes keep the two equal."""
    running = crc32(b"abcde")
    assert running == 0x8B6089C8
    assert crc32(b"fgh", running) == 0x9D3F9C20
    assert crc32(b"abcdefgh") == 0xAEEF2A50
    assert crc32(b"efgh", crc32(b"abcd")) == 0xAEEF2A50


def test_the_driver_cuts_its_chunks_at_multiples_of_4_bytes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Hence the driver's chunks: multiples of 4 bytes each but the last, so its running CRC
    ends at the file CRC it announced."""
    from roboscript.robot import Robot

    chunks: list[bytes] = []
    take = SpikeHub._take_chunk

    def spy(hub: SpikeHub, message: m.TransferChunkRequest) -> str | None:
        chunks.append(message.data)
        return take(hub, message)

    monkeypatch.setattr(SpikeHub, "_take_chunk", spy)
    with Robot.connect("spike-prime"):
        pass
    assert len(chunks) > 2
    assert all(len(chunk) % 4 == 0 for chunk in chunks[:-1])
    assert b"".join(chunks) == agent_source()


# ------------------------------------------------------------------ refusing a bad chunk


def test_a_chunk_with_a_wrong_running_crc_is_refused_at_that_chunk() -> None:
    """A hub must refuse a bad chunk when it arrives (``11 01``, NACK), not ACK it and then
    refuse to run the file without a word. Chunk 1 (``abcd``, running CRC 0xed82cd11) is
    taken; chunk 2 carries the CRC of ``efgh`` alone instead of the running one."""
    hub = _Hub()
    assert hub.ask(b"\x0cp.py\x00\x05\x50\x2a\xef\xae") == [b"\x0d\x00"]
    assert hub.ask(b"\x10\x11\xcd\x82\xed\x04\x00abcd") == [b"\x11\x00"]
    wrong = zlib.crc32(b"efgh").to_bytes(4, "little")
    assert hub.ask(b"\x10" + wrong + b"\x04\x00efgh") == [b"\x11\x01"]
    assert [number for number, _ in hub.device.refused_chunks] == [2]
    assert 5 not in hub.device.slots
    right = (0xAEEF2A50).to_bytes(4, "little")
    assert hub.ask(b"\x10" + right + b"\x04\x00efgh") == [b"\x11\x00"]
    assert hub.device.slots[5] == b"abcdefgh"


def test_a_chunk_after_an_unaligned_one_is_refused_at_that_chunk() -> None:
    """Chunks of 5 then 3 bytes, each with LEGO's running CRC, can never end at the file CRC
    (padding inside the file): the hub refuses the second chunk (``11 01``) at once."""
    hub = _Hub()
    assert hub.ask(b"\x0cp.py\x00\x05\x50\x2a\xef\xae") == [b"\x0d\x00"]
    assert hub.ask(b"\x10\xc8\x89\x60\x8b\x05\x00abcde") == [b"\x11\x00"]
    assert hub.ask(b"\x10\x20\x9c\x3f\x9d\x03\x00fgh") == [b"\x11\x01"]
    assert 5 not in hub.device.slots


# ---------------------------------------------------------------------- tunnel binding


def _find_tunnel() -> Any:
    """The agent's own ``find_tunnel``, compiled alone from its source."""
    tree = ast.parse(AGENT.read_text(encoding="utf-8"))
    wanted = [
        node
        for node in tree.body
        if (isinstance(node, ast.FunctionDef) and node.name == "find_tunnel")
        or (isinstance(node, ast.Assign) and ast.unparse(node.targets[0]) == "TUNNEL_FORMS")
    ]
    namespace: dict[str, Any] = {}
    exec(compile(ast.Module(wanted, []), str(AGENT), "exec"), namespace)  # noqa: S102
    return namespace


class _Config(dict[str, Any]):
    def __init__(self, looked_up: list[str], **items: Any) -> None:
        super().__init__(items)
        self.looked_up = looked_up

    def __getitem__(self, key: str) -> Any:
        self.looked_up.append(f"hub.config[{key!r}]")
        return super().__getitem__(key)


def test_the_agent_binds_hub_config_module_tunnel_before_import_tunnel(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The public programs that drive a real hub's tunnel bind it as
    ``hub.config["module_tunnel"]``; no public source uses ``import tunnel``. The agent tries
    that first, and imports nothing when it is there."""
    agent = _find_tunnel()
    assert agent["TUNNEL_FORMS"] == ("hub.config['module_tunnel']", "import tunnel")
    assert agent["TUNNEL_FORMS"] == AGENT_TUNNEL_ORDER  # the simulated hub's model agrees
    looked_up: list[str] = []
    offered = ModuleType("module_tunnel")
    agent["hub"] = SimpleNamespace(config=_Config(looked_up, module_tunnel=offered))
    monkeypatch.setitem(sys.modules, "tunnel", ModuleType("tunnel"))
    tried: list[str] = []
    assert agent["find_tunnel"](tried) == (offered, "hub.config['module_tunnel']")
    assert (tried, looked_up) == (["hub.config['module_tunnel']"], ["hub.config['module_tunnel']"])


def test_the_agent_falls_back_to_import_tunnel_then_reports_none(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Unverified on hardware, so the other form stays as a fallback, tried second; with
    neither the agent finds nothing (and says so, naming the firmware: see test_agent)."""
    agent = _find_tunnel()
    agent["hub"] = SimpleNamespace(config=_Config([]))
    imported = ModuleType("tunnel")
    monkeypatch.setitem(sys.modules, "tunnel", imported)
    tried: list[str] = []
    assert agent["find_tunnel"](tried) == (imported, "import tunnel")
    assert tried == ["hub.config['module_tunnel']", "import tunnel"]
    monkeypatch.setitem(sys.modules, "tunnel", None)
    agent["hub"] = SimpleNamespace()  # a firmware whose hub module has no config at all
    assert agent["find_tunnel"]([]) == (None, None)
