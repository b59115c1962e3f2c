"""A real robot from the browser app, through the page's Web Serial and Web Bluetooth layers.

Headless Chromium has no serial or Bluetooth devices, so every page gets a stand-in
``navigator.serial`` and ``navigator.bluetooth`` (a script added before the page's own) whose
port or hub is bridged by this test to a simulated robot served by ``roboscript sim --tcp`` on
loopback: what the page writes reaches the test through a binding as it is written, and what
the robot answers is pushed back into the port's readable stream (or the hub's notifications,
20 bytes at most each). The page's code is the one a student runs: its Connect buttons, the
browser's chooser, the run on the robot, its Stop button.

A PLEN2 mission is used because its conversation does not depend on timing (no sensor
streams): against a fresh ``roboscript sim --tcp`` the page's wire log holds the same messages
both ways as the command line's, but for the liveness polls, whose number follows the wall
clock. Waits are long enough for a machine whose every core is busy; nothing here is timed.
The simulator runs as a class runs it, with its defaults: a page slow to say its first
byte keeps the robot, since nobody else wants it.
"""

from __future__ import annotations

import base64
import json
import select
import socket
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from browser import Browser, chromium
from helpers import MISSIONS, run_cli, served_simulator

from roboscript.codec import Role
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.messages import GetVersion, VersionReply
from roboscript.robot import Robot
from roboscript.transport.ble import SERVICE_UUID
from roboscript.transport.wirelog import read_wire_log

pytestmark = pytest.mark.timeout(1800)

LONG_S = 600.0  # Python in WebAssembly on a saturated machine takes its time; never a limit
MISSION = MISSIONS / "plen_walk.yaml"

STAND_IN = """
(function () {
  var ports = [];
  window.rsStandInWritten = 0;  // writes the device has taken (as rsStandInWrite said them)
  function bytesOf(text) {
    var raw = atob(text), out = new Uint8Array(raw.length);
    for (var i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
    return out;
  }
  function textOf(bytes) {
    var raw = "";
    for (var i = 0; i < bytes.length; i++) raw += String.fromCharCode(bytes[i]);
    return btoa(raw);
  }
  function StandInPort(n) {
    var port = this, incoming = null, gone = [];
    this.dead = false;  // unplugged: the browser opens this object no more
    this.readable = null;
    this.writable = null;
    this.addEventListener = function (type, f) { if (type === "disconnect") gone.push(f); };
    this.removeEventListener = function (type, f) {
      var i = gone.indexOf(f);
      if (i >= 0) gone.splice(i, 1);
    };
    this.getInfo = function () { return { usbVendorId: 0x2341, usbProductId: 0x8037 }; };
    this.open = function (options) {
      if (port.dead) {
        return Promise.reject(new DOMException("Failed to open serial port.", "NetworkError"));
      }
      window.rsStandInOpen(JSON.stringify({ port: n, baudRate: options.baudRate }));
      port.readable = new ReadableStream({ start: function (c) { incoming = c; } });
      port.writable = new WritableStream({
        write: function (chunk) {
          window.rsStandInWritten += 1;  // the page's count, taken with what it does next
          window.rsStandInWrite(JSON.stringify({ port: n, data: textOf(chunk) }));
        }
      });
      return Promise.resolve();
    };
    this.close = function () {
      port.readable = null;
      port.writable = null;
      window.rsStandInClose(JSON.stringify({ port: n }));
      return Promise.resolve();
    };
    this.push = function (text) {
      if (port.readable) incoming.enqueue(bytesOf(text));  // a closed port hears nothing
    };
    this.lose = function () {  // a cable pulled out: the stream fails, and no new one comes
      incoming.error(new DOMException("The device has been lost.", "NetworkError"));
      port.readable = null;
    };
    this.unplug = function () {  // as a real unplug: the stream fails and the port says so
      port.dead = true;
      port.lose();
      gone.slice().forEach(function (f) { f({ type: "disconnect", target: port }); });
    };
  }
  var serial = {
    requestPort: function (options) {
      window.rsStandInAsked(JSON.stringify(options || {}));
      var port = new StandInPort(ports.length);
      ports.push(port);
      return Promise.resolve(port);
    },
    getPorts: function () {  // the ports this page may use: a port unplugged is not one
      return Promise.resolve(ports.filter(function (p) {
        return p instanceof StandInPort && !p.dead;
      }));
    },
    addEventListener: function () {},
    removeEventListener: function () {}
  };
  Object.defineProperty(Navigator.prototype, "serial", {
    get: function () { return serial; }, configurable: true
  });

  // A SPIKE hub over Bluetooth: its GATT service, notifications of at most 20 bytes.
  function StandInHub(n) {
    var hub = this, changed = [];
    var tx = {
      addEventListener: function (type, f) { changed.push(f); },
      removeEventListener: function (type, f) {
        var i = changed.indexOf(f);
        if (i >= 0) changed.splice(i, 1);
      },
      listeners: function () { return changed.length; },
      startNotifications: function () { return Promise.resolve(tx); }
    };
    hub.tx = tx;
    var rx = {
      writeValueWithoutResponse: function (data) {
        window.rsStandInWrite(JSON.stringify({ port: n, data: textOf(new Uint8Array(data)) }));
        return Promise.resolve();
      }
    };
    var service = {
      getCharacteristic: function (uuid) {
        return Promise.resolve(uuid.indexOf("fd02-0001") >= 0 ? rx : tx);
      }
    };
    var dropped = [];
    this.addEventListener = function (type, f) {
      if (type === "gattserverdisconnected") dropped.push(f);
    };
    this.removeEventListener = function (type, f) {
      var i = dropped.indexOf(f);
      if (i >= 0) dropped.splice(i, 1);
    };
    this.lose = function () {  // the hub switched off or out of reach: the link drops
      hub.gatt.connected = false;
      dropped.slice().forEach(function (f) { f({ type: "gattserverdisconnected", target: hub }); });
    };
    this.gatt = {
      connected: false,
      connect: function () {
        hub.gatt.connected = true;
        window.rsStandInOpen(JSON.stringify({ port: n }));
        return Promise.resolve({
          getPrimaryService: function () { return Promise.resolve(service); }
        });
      },
      disconnect: function () {
        hub.gatt.connected = false;
        window.rsStandInClose(JSON.stringify({ port: n }));
      }
    };
    this.push = function (text) {
      if (!hub.gatt.connected) return;  // a disconnected hub notifies nobody
      var bytes = bytesOf(text);
      for (var i = 0; i < bytes.length; i += 20) {
        var part = bytes.slice(i, i + 20);
        var event = { target: { value: new DataView(part.buffer) } };
        changed.forEach(function (f) { f(event); });
      }
    };
  }
  var bluetooth = {
    requestDevice: function (options) {
      window.rsStandInAsked(JSON.stringify(options || {}));
      var hub = new StandInHub(ports.length);
      ports.push(hub);
      return Promise.resolve(hub);
    }
  };
  Object.defineProperty(Navigator.prototype, "bluetooth", {
    get: function () { return bluetooth; }, configurable: true
  });
  window.rsStandIn = ports;
  // The board plugged in again: a new port for the browser, which the page may use (a board
  // with a USB serial number keeps its permission), and no chooser is asked. Its index.
  window.rsStandInPlugBack = function () {
    ports.push(new StandInPort(ports.length));
    return ports.length - 1;
  };
})();
"""


class StandInBridge:
    """Moves bytes between the page's stand-in port or hub and ``roboscript sim --tcp``.

    Args:
        browser: The page.
        tcp_port: Where the simulator listens on loopback.
    """

    def __init__(self, browser: Browser, tcp_port: int) -> None:
        self.browser = browser
        self.tcp_port = tcp_port
        self.sock: socket.socket | None = None
        self.port_index: int | None = None
        self.writes: list[bytes] = []
        """Each chunk the page wrote, in order."""
        self.asked: list[dict[str, object]] = []
        self.opened = 0
        """How many times the page opened a port."""
        self.closed = False

    def _handle(self, name: str, payload: str) -> None:
        message = json.loads(payload)
        if name == "rsStandInAsked":
            self.asked.append(message)
        elif name == "rsStandInOpen":
            self.opened += 1
            self.port_index = int(message["port"])
            self.sock = socket.create_connection(("127.0.0.1", self.tcp_port))
        elif name == "rsStandInWrite":
            data = base64.b64decode(message["data"])
            self.writes.append(data)
            if self.sock is not None:
                self.sock.sendall(data)
        elif name == "rsStandInClose":
            self.closed = True
            if self.sock is not None:
                self.sock.close()
                self.sock = None

    def pump(self, until: str | None = None, *, timeout_s: float = LONG_S) -> None:
        """Move bytes both ways until the page's expression ``until`` is truthy (or, with
        ``None``, until the page closes its port)."""
        deadline = time.monotonic() + timeout_s
        checks = 0
        while True:
            for name, payload in self.browser.take_bindings(0.01):
                self._handle(name, payload)
            if self.sock is not None:
                ready, _, _ = select.select([self.sock], [], [], 0)
                if ready:
                    data = self.sock.recv(65536)
                    if data:
                        pushed = base64.b64encode(data).decode()
                        self.browser.evaluate(
                            f"rsStandIn[{self.port_index}].push({json.dumps(pushed)})"
                        )
            checks += 1
            if checks % 10 == 0 and (
                (until is None and self.closed)
                or (until is not None and self.browser.evaluate(until))
            ):
                # what the page did before it said so came in ahead of the answer, and waits
                # among the bindings: take it, or the last writes would be missing
                for name, payload in self.browser.take_bindings(0):
                    self._handle(name, payload)
                return
            if time.monotonic() > deadline:
                raise AssertionError(f"never true while bridging: {until or 'port closed'}")


@pytest.fixture
def page(app: Path, tmp_path: Path) -> Iterator[Browser]:
    browser = Browser(chromium() or "", tmp_path / "profile", timeout_s=LONG_S)
    try:
        browser._call(
            "Network.emulateNetworkConditions",
            {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
        )
        for name in ("rsStandInAsked", "rsStandInOpen", "rsStandInWrite", "rsStandInClose"):
            browser.add_binding(name)
        browser._call("Page.addScriptToEvaluateOnNewDocument", {"source": STAND_IN})
        browser._call("Page.navigate", {"url": app.as_uri()})
        browser.wait_for("document.body && document.body.dataset.ready !== undefined", LONG_S)
        assert browser.evaluate("document.body.dataset.ready") == "1"
        browser.evaluate(
            "document.querySelector('.CodeMirror').CodeMirror.setValue("
            + json.dumps(MISSION.read_text(encoding="utf-8"))
            + "); document.querySelector('[data-role=name]').value = 'plen_walk.yaml'"
        )
        browser.wait_for(
            "document.querySelector('[data-role=problems]').dataset.errors === '0'", LONG_S
        )
        yield browser
    finally:
        browser.close()


def _connect_and_run(
    page: Browser, bridge: StandInBridge, choice: str = "[data-robot=plen2]"
) -> None:
    page.click(f"[data-action=connect]{choice}")
    bridge.pump("document.body.dataset.robotPort", timeout_s=LONG_S)
    page.wait_for("!document.querySelector('[data-action=run-robot]').disabled", LONG_S)
    page.click("[data-action=run-robot]")


def _stop_bytes(folder: Path) -> bytes:
    """What the PLEN2 driver sends to stop, by its own path (on the in-process simulator)."""
    log = folder / "stop-wire.log"
    with Robot.connect("plen2", wire_log=str(log)) as robot:
        wire_log = robot.driver.link.wire_log
        assert wire_log is not None
        wire_log.flush()
        before = len(read_wire_log(log))
        robot.stop()
        wire_log.flush()
        records = read_wire_log(log)[before:]
    stop = b"".join(data for _, direction, data in records if direction == ">")
    assert stop
    return stop


def _sent_and_received(wire_log: Path) -> tuple[bytes, bytes]:
    records = read_wire_log(wire_log)
    sent = b"".join(data for _, direction, data in records if direction == ">")
    received = b"".join(data for _, direction, data in records if direction == "<")
    return sent, received


def _messages(data: bytes, role: Role) -> list[object]:
    """The PLEN2 messages in ``data``, read as the side opposite ``role`` sent them."""
    codec = PlenCodec(role)
    codec.receive_data(data)
    messages = []
    while (message := codec.next_message()) is not None:
        messages.append(message)
    return messages


def _conversation(wire_log: Path) -> tuple[list[object], list[object]]:
    """The wire log's messages both ways, without the liveness polls.

    The driver asks ``<VI`` whenever the line has been quiet for a second
    (:mod:`roboscript.drivers.plen.driver`): how many it asks depends on the wall clock, which
    no two real-time runs share. Every other byte depends on the mission and the robot only.
    """
    sent, received = _sent_and_received(wire_log)
    requests = [m for m in _messages(sent, Role.DEVICE) if not isinstance(m, GetVersion)]
    replies = [m for m in _messages(received, Role.HOST) if not isinstance(m, VersionReply)]
    return requests, replies


def test_a_mission_on_a_robot_from_the_page_puts_the_same_bytes_on_the_wire_as_the_command_line(
    page: Browser, tmp_path: Path
) -> None:
    cli_log = tmp_path / "cli-wire.log"
    # Both runs mostly wait on their robot's clock, each with its own simulator: run together.
    with served_simulator("plen2") as cli_port, ThreadPoolExecutor(1) as pool:
        on_the_command_line = pool.submit(
            run_cli,
            "run",
            str(MISSION),
            "--port",
            f"socket://127.0.0.1:{cli_port}",
            "--wire-log",
            str(cli_log),
            "--quiet",
        )
        with served_simulator("plen2") as tcp_port:
            bridge = StandInBridge(page, tcp_port)
            _connect_and_run(page, bridge)
            bridge.pump("document.body.dataset.wireLog", timeout_s=LONG_S)
        done = on_the_command_line.result()
    summary = json.loads(page.evaluate("document.querySelector('[data-role=result]').dataset.json"))
    assert (summary["outcome"], summary["final_state"]) == ("success", "rest")
    in_page = tmp_path / "page-wire.log"
    in_page.write_text(page.evaluate("document.body.dataset.wireLog"), encoding="utf-8")
    assert bridge.asked == [
        {
            "filters": [
                {"usbVendorId": 0x2341, "usbProductId": 0x8037},
                {"usbVendorId": 0x2341, "usbProductId": 0x0037},
            ]
        }
    ]

    assert done.returncode == 0, done.stderr
    in_page_conversation = _conversation(in_page)
    assert len(in_page_conversation[0]) > 40  # motions uploaded and played, and the stop
    assert in_page_conversation == _conversation(cli_log)
    assert b"".join(bridge.writes) == _sent_and_received(in_page)[0]  # the log is the wire
    assert page.errors == []


def _stopped_mid_mission(page: Browser, folder: Path, how: str) -> tuple[bytes, list[bytes]]:
    """Run the mission on the robot, and once it runs, stop it ``how``: ``"button"``,
    ``"lost"`` (the stand-in port's stream fails) or ``"close"`` (the page is closed).

    Returns:
        The driver's stop bytes, and each write the device took from the moment the page was
        told (counted by the page as it was told, so a write made just before is not taken
        for one made after).
    """
    stop = _stop_bytes(folder)
    with served_simulator("plen2") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge)
        bridge.pump("document.body.dataset.robotReady === '1'")
        if how == "button":
            before = page.evaluate(
                "(() => { const n = window.rsStandInWritten;"
                " document.querySelector('[data-action=stop]').click(); return n; })()"
            )
        elif how == "lost":
            before = page.evaluate(
                f"(() => {{ const n = window.rsStandInWritten; rsStandIn[{bridge.port_index}]"
                ".lose(); return n; })()"
            )
        else:
            before = page.evaluate("window.rsStandInWritten")
            page._call("Page.close")
            # Its last words are the stop: wait for it, never a fixed time.
            deadline = time.monotonic() + LONG_S
            while stop not in bridge.writes[before:] and time.monotonic() < deadline:
                for name, payload in page.take_bindings(0.1):
                    bridge._handle(name, payload)
        if how != "close":
            bridge.pump(None)
    return stop, bridge.writes[before:]


def _the_stop_came_next(stop: bytes, writes: list[bytes]) -> None:
    """What the device took once the page was told to stop: at most the one write already on
    its way (begun before), then the robot's stop, and nothing after it."""
    assert stop in writes, writes
    assert writes.index(stop) <= 1 and writes[writes.index(stop) :] == [stop], writes


def test_the_stop_button_sends_the_stop_first_and_ends_the_run(
    page: Browser, tmp_path: Path
) -> None:
    _the_stop_came_next(*_stopped_mid_mission(page, tmp_path, "button"))
    result = page.wait_for("document.querySelector('[data-role=result]').textContent", LONG_S)
    assert result.startswith("error: plen-walk ended in ")
    assert result.endswith("(stopped with the Stop button)")
    assert page.errors == []


def test_a_lost_link_stops_the_mission_in_one_sentence(page: Browser, tmp_path: Path) -> None:
    _the_stop_came_next(*_stopped_mid_mission(page, tmp_path, "lost"))
    result = page.wait_for("document.querySelector('[data-role=result]').textContent", LONG_S)
    assert result.startswith("error: plen-walk ended in ")
    assert result.endswith("(the robot's USB connection was lost (was the cable pulled out?))")
    assert "Traceback" not in result and page.errors == []


def test_closing_the_page_sends_the_stop(page: Browser, tmp_path: Path) -> None:
    stop, writes = _stopped_mid_mission(page, tmp_path, "close")
    assert stop in writes[:2]  # the one write on its way, if any, then the stop


def test_a_spike_hub_over_bluetooth_runs_its_mission_from_the_page(
    page: Browser, tmp_path: Path
) -> None:
    mission = MISSIONS / "spike_square.yaml"
    page.evaluate(
        "document.querySelector('.CodeMirror').CodeMirror.setValue("
        + json.dumps(mission.read_text(encoding="utf-8"))
        + "); document.querySelector('[data-role=name]').value = 'spike_square.yaml'"
    )
    # Both runs mostly wait on their robot's clock, each with its own simulator: run together.
    with served_simulator("spike-prime") as cli_port, ThreadPoolExecutor(1) as pool:
        on_the_command_line = pool.submit(
            run_cli, "run", str(mission), "--port", f"socket://127.0.0.1:{cli_port}", "--json"
        )
        with served_simulator("spike-prime") as tcp_port:
            bridge = StandInBridge(page, tcp_port)
            _connect_and_run(page, bridge, "[data-via=bluetooth]")
            bridge.pump("document.body.dataset.wireLog", timeout_s=LONG_S)
        done = on_the_command_line.result()
    assert bridge.asked == [{"filters": [{"services": [SERVICE_UUID]}]}]
    summary = json.loads(page.evaluate("document.querySelector('[data-role=result]').dataset.json"))
    assert (summary["outcome"], summary["final_state"]) == ("success", "finished")
    assert max(len(chunk) for chunk in bridge.writes) <= 20  # the hub's packets
    in_page = tmp_path / "page-wire.log"
    in_page.write_text(page.evaluate("document.body.dataset.wireLog"), encoding="utf-8")
    assert b"".join(bridge.writes) == _sent_and_received(in_page)[0]  # the log is the wire
    assert done.returncode == 0, done.stderr
    on_the_command_line = json.loads(done.stdout)
    assert [s for _, s in summary["states"]] == [s for _, s in on_the_command_line["states"]]
    # the closed port listens no more: a notification still on its way calls nothing
    assert page.evaluate(f"rsStandIn[{bridge.port_index}].tx.listeners()") == 0
    assert page.errors == []


def test_a_robot_that_answers_as_another_is_named_as_the_student_chose_it(page: Browser) -> None:
    page.evaluate(
        "document.querySelector('.CodeMirror').CodeMirror.setValue("
        + json.dumps((MISSIONS / "square.yaml").read_text(encoding="utf-8"))
        + "); document.querySelector('[data-role=name]').value = 'square.yaml';"
        " document.querySelector('[data-role=robot]').value = 'spike-prime'"
    )
    with served_simulator("mirto") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge, "[data-robot=mirto]")
        bridge.pump("document.querySelector('[data-role=result]').dataset.error")
    error = page.evaluate("document.querySelector('[data-role=result]').dataset.error")
    assert error == (
        "the robot on the serial port you chose did not answer as spike-prime: this port speaks"
        " the ASIP protocol (a MIRTO or another ASIP board): choose mirto in the Robot list, and"
        " run again"
    )
    assert page.errors == []


def _robot_stop_bytes(folder: Path, robot: str) -> bytes:
    """What ``robot``'s driver sends to stop, by its own path (on the in-process simulator)."""
    log = folder / f"stop-{robot}.log"
    with Robot.connect(robot, wire_log=str(log)) as connected:
        wire_log = connected.driver.link.wire_log
        assert wire_log is not None
        wire_log.flush()
        before = len(read_wire_log(log))
        connected.stop()
        wire_log.flush()
        records = read_wire_log(log)[before:]
    return b"".join(data for _, direction, data in records if direction == ">")


def _mission_in_editor(page: Browser, path: Path) -> None:
    page.evaluate(
        "document.querySelector('.CodeMirror').CodeMirror.setValue("
        + json.dumps(path.read_text(encoding="utf-8"))
        + f"); document.querySelector('[data-role=name]').value = {json.dumps(path.name)}"
    )


HELLO = Path(__file__).parents[2] / "roboscript" / "web" / "examples" / "hello.yaml"
RESULT = "document.querySelector('[data-role=result]')"


def test_a_mirto_that_resets_when_its_port_opens_runs_its_mission_from_the_page(
    page: Browser,
) -> None:
    # the board is deaf for 3 s after the port opens, and greets at 3.2 s (an Arduino's reset)
    _mission_in_editor(page, HELLO)
    with served_simulator("mirto", "--reset-on-connect") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge, "[data-robot=mirto]")
        bridge.pump("document.body.dataset.wireLog", timeout_s=LONG_S)
    summary = json.loads(page.evaluate(f"{RESULT}.dataset.json"))
    assert (summary["outcome"], summary["final_state"]) == ("success", "beep")
    assert page.errors == []


def test_a_mirto_unplugged_mid_run_is_stopped_and_told_in_one_sentence(
    page: Browser, tmp_path: Path
) -> None:
    stop = _robot_stop_bytes(tmp_path, "mirto")
    _mission_in_editor(page, HELLO)
    with served_simulator("mirto", "--reset-on-connect") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge, "[data-robot=mirto]")
        bridge.pump("document.body.dataset.robotReady === '1'")
        before = page.evaluate(
            f"(() => {{ const n = window.rsStandInWritten; rsStandIn[{bridge.port_index}]"
            ".unplug(); return n; })()"
        )
        bridge.pump(None)
    _the_stop_came_next(stop, bridge.writes[before:])  # the motors' stop went out first
    result = page.wait_for(f"{RESULT}.textContent", LONG_S)
    assert result.startswith("error: hello ended in ")
    assert result.endswith("(the robot's USB connection was lost (was the cable pulled out?))")
    assert result.count("(the robot's USB connection was lost") == 1
    assert "Traceback" not in result and page.errors == []


def test_a_spike_hub_that_loses_its_bluetooth_link_mid_run_is_told_in_one_sentence(
    page: Browser,
) -> None:
    _mission_in_editor(page, MISSIONS / "spike_square.yaml")
    with served_simulator("spike-prime") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge, "[data-via=bluetooth]")
        bridge.pump("document.body.dataset.robotReady === '1'")
        page.evaluate(f"rsStandIn[{bridge.port_index}].lose()")
        bridge.pump(f"{RESULT}.textContent", timeout_s=LONG_S)
    result = page.evaluate(f"{RESULT}.textContent")
    assert result.startswith("error: spike-square ended in "), result
    assert result.endswith(
        "(the Bluetooth connection to the hub was lost (is it still on, and near the computer?))"
    )
    assert "Traceback" not in result and page.errors == []
    assert page.wait_for("document.querySelector('[data-action=stop]').disabled", LONG_S)


RUNAWAY = '''from collections import deque
from itertools import count

from roboscript import Drive, Mission, state


class Runaway(Mission):
    """Drive, checking a condition that never returns: a loop inside one call, which no
    check between two lines of Python can stop."""

    go = state(Drive(distance_mm=3000, speed_mm_s=100), initial=True, on_done="done",
               when=[("check", "done")])
    done = state(final="success")

    def check(self) -> bool:
        deque(count(), maxlen=0)
        return False
'''
ANSWERS_S = 120.0
"""How long the page may take to answer a script while the student's code loops: a bound for
a frozen page (it never answers), far above what a busy machine takes."""


def _run_away_on_a_mirto(page: Browser, tcp_port: int) -> tuple[StandInBridge, int]:
    """Connect a MIRTO, run the runaway mission on it, and wait until it reached the robot.

    Returns:
        The bridge, and how many writes the page had made by then.
    """
    page.evaluate(
        "document.querySelector('.CodeMirror').CodeMirror.setValue("
        + json.dumps(RUNAWAY)
        + "); document.querySelector('[data-role=name]').value = 'runaway.py';"
        " document.querySelector('[data-role=name]').dispatchEvent(new Event('change'));"
        " document.querySelector('[data-role=problems]').removeAttribute('data-errors')"
    )
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '0'", LONG_S)
    bridge = StandInBridge(page, tcp_port)
    _connect_and_run(page, bridge, "[data-robot=mirto]")
    page.timeout_s = ANSWERS_S  # from here on, a page that does not answer fails the test
    bridge.pump("document.body.dataset.robotReady === '1'")
    return bridge, len(bridge.writes)


def test_stop_stops_a_robot_whose_mission_code_loops_forever_and_the_page_says_why(
    page: Browser, tmp_path: Path
) -> None:
    stop = _robot_stop_bytes(tmp_path, "mirto")
    with served_simulator("mirto") as tcp_port:
        bridge, before = _run_away_on_a_mirto(page, tcp_port)
        # no other robot is connected while this one runs
        assert page.evaluate(
            "Array.from(document.querySelectorAll('[data-action=connect]'))"
            ".every(function (b) { return b.disabled; })"
        )
        # the page answers while the student's code loops: its Stop can be pressed
        page.evaluate("document.querySelector('[data-action=stop]').click()")
        bridge.pump(f"{RESULT}.dataset.stopped")
        bridge.pump(None)  # the page released the port
    after = b"".join(bridge.writes[before:])
    assert stop and after.endswith(stop)  # the robot's stop, and nothing after it
    assert page.evaluate(f"{RESULT}.dataset.stopped") == (
        "Stopped with the Stop button: the robot was sent its stop at once, and the mission's"
        " code, which no longer answered (a loop that never ends?), was ended; nothing of the"
        " run was kept."
    )
    # the page is the student's again: a fresh Python, and the robot can be run again
    page.timeout_s = LONG_S
    page.wait_for(
        "document.body.dataset.ready === '1' &&"
        " !document.querySelector('[data-action=run-robot]').disabled",
        LONG_S,
    )
    assert page.evaluate("document.querySelector('[data-action=stop]').disabled") is True
    assert page.evaluate("document.querySelector('[data-action=connect]').disabled") is False
    assert page.errors == []


def test_a_robot_whose_mission_code_stops_answering_is_stopped_by_the_page_itself(
    page: Browser, tmp_path: Path
) -> None:
    stop = _robot_stop_bytes(tmp_path, "mirto")
    with served_simulator("mirto") as tcp_port:
        bridge, before = _run_away_on_a_mirto(page, tcp_port)
        # nobody presses Stop: the page hears nothing from the worker, and stops the robot
        bridge.pump(f"{RESULT}.dataset.stopped")
        bridge.pump(None)
    after = b"".join(bridge.writes[before:])
    assert stop and after.endswith(stop)
    assert page.evaluate(f"{RESULT}.dataset.stopped") == (
        "The mission's code stopped answering for 2 s while the robot ran (a loop that never"
        " ends?), so the page stopped the robot and ended the run; nothing of it was kept."
    )
    assert page.errors == []


def test_a_mirto_plugged_in_again_after_an_unplug_runs_again_without_a_new_connect(
    page: Browser,
) -> None:
    _mission_in_editor(page, HELLO)
    with served_simulator("mirto") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        _connect_and_run(page, bridge, "[data-robot=mirto]")
        bridge.pump("document.body.dataset.robotReady === '1'")
        page.evaluate(f"rsStandIn[{bridge.port_index}].unplug()")
        bridge.pump(f"{RESULT}.dataset.json")
    assert page.evaluate(f"{RESULT}.textContent").endswith(
        "(the robot's USB connection was lost (was the cable pulled out?))"
    )
    # Run on the robot with the cable still out: the page says what to do, in a sentence
    page.evaluate(f"{RESULT}.removeAttribute('data-json')")
    page.wait_for("!document.querySelector('[data-action=run-robot]').disabled", LONG_S)
    page.click("[data-action=run-robot]")
    assert page.wait_for(f"{RESULT}.dataset.error", LONG_S) == (
        "cannot reach the robot on the serial port you chose: it was unplugged (or switched off)"
        " since you connected it: plug it in again, then press its Connect button and choose it"
    )
    # the student plugs the cable in again and presses Run on the robot: no Connect
    page.evaluate(
        "rsStandInPlugBack();"
        f" {RESULT}.removeAttribute('data-json'); {RESULT}.removeAttribute('data-error');"
        " document.body.removeAttribute('data-wire-log')"
    )
    with served_simulator("mirto") as tcp_port:
        bridge = StandInBridge(page, tcp_port)
        page.wait_for("!document.querySelector('[data-action=run-robot]').disabled", LONG_S)
        # pressed twice in a hurry: one run
        page.evaluate(
            "const run = document.querySelector('[data-action=run-robot]');"
            " run.click(); run.click()"
        )
        bridge.pump(f"{RESULT}.dataset.json || {RESULT}.dataset.error")
        assert page.evaluate(f"{RESULT}.dataset.error") is None
        bridge.pump("document.body.dataset.wireLog")
    summary = json.loads(page.evaluate(f"{RESULT}.dataset.json"))
    assert (summary["outcome"], summary["final_state"]) == ("success", "beep")
    assert bridge.opened == 1
    assert page.errors == []
