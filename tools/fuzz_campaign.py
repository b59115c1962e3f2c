"""The fuzz campaign of issue 17: hostile missions and faulted robots, counted.

    nice -n 10 python tools/fuzz_campaign.py --missions 10000 --faulted-runs 50 --seed 1

Two parts, each reporting what the issue's "done when" asks for:

**Missions.** ``--missions`` inputs from ``tools/fuzz_shapes.py`` (mutated and generated YAML
missions, generated conditions, Python missions), each written to its own folder under
``build/fuzz/inputs/``. A worker process runs ``roboscript check`` on each, in-process (the
command line's own ``main``), then, if it passed, a bounded ``roboscript run`` on the built-in
simulator (``--max-time 30``). The worker restarts every 250 inputs and whenever one input
takes longer than ``--hang-s`` (it is killed: a *hang*). Every ``--subprocess-every``-th
input is also run through a real ``python -m roboscript`` process, whose exit status must be
0, 1 or 2. Counted per input: *tracebacks* (an exception out of ``main``, an exit status
other than 0/1/2, ``Traceback`` on stderr), *hangs*, inputs slower than 5 s, and the peak
memory (``ru_maxrss`` of the worker after each input, an upper bound on the input's own, and
``RLIMIT_AS`` of 1 GB so a runaway cannot take the machine).

**Faulted runs.** ``--faulted-runs`` per protocol (ASIP on ``mirto``, SPIKE on
``spike-prime``, StackMod on ``stackmod-rover``, PLEN2 on ``plen2``): a real
``roboscript run --port socket://...`` process drives a simulator served on loopback
(:class:`roboscript.sim.server.SimServer`) through a proxy that injects one fault at a random
instant: a garbage flood, a disconnect, silence, or SIGTERM / SIGHUP / SIGINT to the run
process. The proxy keeps every byte the host sent; replayed into a fresh simulated robot of the
same kind (as ``tests/test_interrupts.py`` judges its signals), the robot must not be moving
after the last of them. Counted: tracebacks, hangs (no exit within 60 s), runs whose robot was
left moving, exit statuses.

The report goes to stdout and, as JSON, to ``build/fuzz/report.json`` (with every failing
input's folder, to reproduce it by hand). Exit status 1 if anything was found.
See docs/development/fuzzing.md.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import random
import resource
import signal
import socket
import subprocess
import sys
import threading
import time
import traceback
from collections import Counter
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tools"))

import fuzz_shapes  # noqa: E402

BUILD = ROOT / "build" / "fuzz"
SLOW_S = 5.0
MEMORY_LIMIT_MB = 256
ADDRESS_SPACE_LIMIT = 1024 * 1024 * 1024
WORKER_BATCH = 250
RUN_MAX_TIME_S = "30"


# ------------------------------------------------------------------------------- missions


def write_input(index: int, seed: int) -> tuple[str, Path]:
    """Generate input ``index`` of campaign ``seed`` into its own folder; (kind, mission)."""
    rng = random.Random(f"{seed}:{index}")
    kind, files = fuzz_shapes.make_input(rng)
    folder = BUILD / "inputs" / f"{index:06d}"
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (folder / name).write_bytes(data)
    fifo = folder / "fifo"
    if not fifo.exists():
        os.mkfifo(fifo)  # a name a mission may give: reading it would wait forever
    return kind, folder / next(iter(files))


class _CurrentStderr(io.TextIOBase):
    """Log records go to whatever ``sys.stderr`` is when they are written (it is captured)."""

    def write(self, text: str) -> int:
        return sys.stderr.write(text)


def _in_process(argv: list[str]) -> tuple[int | str, str]:
    """Run the command line in this process: (exit status or "traceback", its stderr)."""
    from roboscript.cli import main

    err, out = io.StringIO(), io.StringIO()
    code: int | str
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            main(argv)
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 2
        except BaseException:  # noqa: BLE001 - what escapes main is what the campaign counts
            code = "traceback"
            err.write(traceback.format_exc())
    return code, err.getvalue()


def _judge(code: int | str, stderr: str) -> str | None:
    """What is wrong with one command's ending, or ``None``."""
    if code == "traceback" or "Traceback (most recent call last)" in stderr:
        return "traceback"
    if code not in (0, 1, 2):
        return f"exit {code}"
    return None


def worker(list_file: str) -> int:
    """Check and run each mission named in ``list_file``; one JSON line per input on stdout."""
    import logging

    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE_LIMIT, ADDRESS_SPACE_LIMIT))
    logging.basicConfig(stream=_CurrentStderr(), level=logging.WARNING, format="%(message)s")
    sys.setrecursionlimit(1000)  # the interpreter's default, whatever the caller had
    out = sys.stdout
    for line in Path(list_file).read_text(encoding="utf-8").splitlines():
        index, path = line.split("\t")
        started = time.monotonic()
        record: dict[str, Any] = {"index": int(index)}
        code, stderr = _in_process(["check", path])
        record["check"] = code
        problem = _judge(code, stderr)
        if problem is None and code == 0:
            code, stderr = _in_process(["run", path, "--max-time", RUN_MAX_TIME_S, "--quiet"])
            record["run"] = code
            problem = _judge(code, stderr)
        if problem is not None:
            record["problem"] = problem
            record["stderr"] = stderr[-4000:]
        record["wall_s"] = round(time.monotonic() - started, 3)
        record["maxrss_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)
        out.write(json.dumps(record) + "\n")
        out.flush()
    return 0


def _run_worker(batch: list[tuple[int, Path]], hang_s: float) -> list[dict[str, Any]]:
    """Run a worker over ``batch``; restart it after a hang (that input is recorded)."""
    records: list[dict[str, Any]] = []
    todo = list(batch)
    while todo:
        list_file = BUILD / "worker-inputs.txt"
        list_file.write_text("".join(f"{i}\t{p}\n" for i, p in todo), encoding="utf-8")
        proc = subprocess.Popen(
            [sys.executable, __file__, "--worker", str(list_file)],
            cwd=BUILD,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        assert proc.stdout is not None
        lines: list[str] = []
        reader = threading.Thread(target=lines.extend, args=(proc.stdout,), daemon=True)
        reader.start()
        done = 0
        last_progress = time.monotonic()
        while proc.poll() is None:
            time.sleep(0.05)
            if len(lines) > done:
                done = len(lines)
                last_progress = time.monotonic()
            elif time.monotonic() - last_progress > hang_s:
                proc.kill()
                break
        proc.wait()
        reader.join(timeout=5)
        finished = [json.loads(line) for line in lines]
        records.extend(finished)
        todo = todo[len(finished) :]
        if todo and proc.returncode != 0:
            index, _ = todo.pop(0)
            killed = proc.returncode == -signal.SIGKILL
            records.append(
                {
                    "index": index,
                    "problem": "hang" if killed else f"worker died ({proc.returncode})",
                    "wall_s": hang_s,
                }
            )
    return records


def _subprocess_sample(index: int, path: Path, hang_s: float) -> dict[str, Any]:
    """One input through real processes: ``check``, then ``run`` if it passed."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    record: dict[str, Any] = {"index": index}
    for argv in (["check", str(path)], ["run", str(path), "--max-time", RUN_MAX_TIME_S]):
        try:
            done = subprocess.run(
                [sys.executable, "-m", "roboscript", *argv],
                capture_output=True,
                text=True,
                errors="replace",
                timeout=hang_s,
                cwd=ROOT,
                env=env,
                check=False,
            )
        except subprocess.TimeoutExpired:
            record["problem"] = "hang"
            return record
        record[argv[0]] = done.returncode
        problem = _judge(done.returncode, done.stderr)
        if problem is not None:
            record["problem"] = problem
            record["stderr"] = done.stderr[-4000:]
            return record
        if done.returncode != 0:
            break
    return record


def mission_campaign(count: int, seed: int, sample_every: int, hang_s: float) -> dict[str, Any]:
    """Generate, check and run ``count`` missions; the figures."""
    started = time.monotonic()
    inputs = []
    kinds: dict[int, str] = {}
    for index in range(count):
        kind, path = write_input(index, seed)
        kinds[index] = kind
        inputs.append((index, path))
    records: list[dict[str, Any]] = []
    for start in range(0, count, WORKER_BATCH):
        records.extend(_run_worker(inputs[start : start + WORKER_BATCH], hang_s))
        print(f"  missions: {len(records)}/{count}", file=sys.stderr, flush=True)
    samples = [
        _subprocess_sample(index, path, hang_s) for index, path in inputs[:: max(1, sample_every)]
    ]
    problems = [r for r in records + samples if "problem" in r]
    for record in problems:
        record["kind"] = kinds[record["index"]]
        record["input"] = str(inputs[record["index"]][1].relative_to(ROOT))
    checks = Counter(str(r.get("check")) for r in records)
    runs = Counter(str(r["run"]) for r in records if "run" in r)
    return {
        "missions": count,
        "by_kind": dict(Counter(kinds.values())),
        "check_exit": dict(checks),
        "run_exit": dict(runs),
        "subprocess_samples": len(samples),
        "subprocess_exit": dict(Counter(str(r.get("run", r.get("check"))) for r in samples)),
        "tracebacks": sum(1 for r in problems if r["problem"] != "hang"),
        "hangs": sum(1 for r in problems if r["problem"] == "hang"),
        "over_5_s": sum(1 for r in records if r.get("wall_s", 0) > SLOW_S),
        "slowest_s": max((r.get("wall_s", 0) for r in records), default=0),
        "slow": [
            {"input": str(inputs[r["index"]][1].relative_to(ROOT)), "wall_s": r["wall_s"]}
            for r in records
            if r.get("wall_s", 0) > SLOW_S
        ],
        "peak_memory_mb": max((r.get("maxrss_mb", 0) for r in records), default=0),
        "over_memory_limit": sum(1 for r in records if r.get("maxrss_mb", 0) > MEMORY_LIMIT_MB),
        "problems": problems,
        "wall_s": round(time.monotonic() - started, 1),
    }


# --------------------------------------------------------------------------- faulted runs

PROTOCOLS = {"asip": "mirto", "spike": "spike-prime", "stackmod": "stackmod-rover", "plen": "plen2"}
FAULTS = ("garbage", "disconnect", "silence", "SIGTERM", "SIGHUP", "SIGINT")
WHEELED_MISSION = """\
mission: faulted
states:
  go:
    do: {drive: {distance: 80 cm, speed: 20 cm/s}}
    timeout: 20 s
    on: {done: beep, failed: stuck, timeout: stuck}
  beep:
    do: {play_tone: {frequency: 880 Hz, duration: 200 ms}}
    final: success
  stuck: {final: failure}
"""
WALKING_MISSION = """\
mission: faulted-walk
states:
  go:
    do: {walk: {steps: 8}}
    timeout: 30 s
    on: {done: end, timeout: stuck}
  end: {final: success}
  stuck: {final: failure}
"""


class FaultProxy:
    """A loopback proxy between ``roboscript run`` and a served simulator that injects a fault.

    Args:
        upstream: The simulator's ``(host, port)``.
        fault: ``garbage``, ``disconnect``, ``silence`` or a signal name (``None``: no fault).
        at_s: Seconds after the host connects at which the fault starts.
        rng: For the garbage.
    """

    def __init__(
        self, upstream: tuple[str, int], fault: str, at_s: float, rng: random.Random
    ) -> None:
        self.fault = fault
        self.at_s = at_s
        self.rng = rng
        self.sent: list[tuple[float, bytes]] = []
        self.connected_at: float | None = None
        self.faulted = False
        self._upstream = upstream
        self._server = socket.create_server(("127.0.0.1", 0))
        self.port = self._server.getsockname()[1]
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def close(self) -> None:
        """Stop proxying."""
        self._done.set()
        self._server.close()
        self._thread.join(timeout=10)

    def due(self) -> bool:
        """True once the fault's instant has come."""
        return self.connected_at is not None and time.monotonic() - self.connected_at >= self.at_s

    def _serve(self) -> None:
        with contextlib.suppress(OSError):
            self._server.settimeout(30)
            host, _ = self._server.accept()
            device = socket.create_connection(self._upstream)
            self.connected_at = time.monotonic()
            with host, device:
                self._pump(host, device)

    def _pump(self, host: socket.socket, device: socket.socket) -> None:
        import select

        silent = False
        flood_until = 0.0
        while not self._done.is_set():
            if (
                self.fault in ("garbage", "disconnect", "silence")
                and not self.faulted
                and self.due()
            ):
                self.faulted = True
                if self.fault == "disconnect":
                    return
                if self.fault == "silence":
                    silent = True
                else:
                    flood_until = time.monotonic() + 1.5
            if flood_until > time.monotonic():
                junk = bytes(self.rng.randrange(256) for _ in range(self.rng.choice([1, 64, 512])))
                junk += self.rng.choice([b"\n", b"\x00", b"{" * 200, b"@" * 100, b"\r\n"])
                with contextlib.suppress(BlockingIOError):
                    host.send(junk)
            ready, _, _ = select.select([host, device], [], [], 0.01)
            for sock in ready:
                data = sock.recv(65536)
                if not data:
                    return
                if sock is host:
                    self.sent.append((time.monotonic(), data))
                    device.sendall(data)
                elif not silent:
                    host.sendall(data)


def _moving_after(robot: str, sent: list[tuple[float, bytes]]) -> tuple[bool, bool]:
    """Replay the host's bytes into a fresh simulated robot: (it moved, still moving at end).

    "Still moving" is protocol-independent: the body's pose changes over two seconds after the
    last byte (and one second for the firmware to act on it), or a wheel has power.
    """
    from roboscript.sim.simulation import make_simulation

    sim = make_simulation(robot)
    sim.connect()
    if not sent:
        return False, False
    origin = sent[0][0]
    start = sim.final_pose()
    moved = False
    for t, data in sent:
        sim.tick(t - origin, 0.0)
        sim.write(data)
        sim.read(sim.in_waiting)
        moved = moved or sim.final_pose()[:2] != start[:2]
    sim.tick(sim.time_s + 1.0, 0.0)
    sim.read(sim.in_waiting)
    before = sim.final_pose()
    sim.tick(sim.time_s + 2.0, 0.0)
    sim.read(sim.in_waiting)
    after = sim.final_pose()
    travelled = abs(after[0] - before[0]) + abs(after[1] - before[1])
    turning = abs(after[2] - before[2])
    powered = any(abs(p) > 1e-6 for p in sim.body.power)
    return moved or before[:2] != start[:2], travelled > 1.0 or turning > 1.0 or powered


def _serve_simulator(robot: str) -> tuple[Any, tuple[str, int], threading.Thread]:
    from roboscript.sim.server import SimServer
    from roboscript.sim.simulation import make_simulation

    lines: list[str] = []
    ready = threading.Event()

    def announce(line: str) -> None:
        lines.append(line)
        ready.set()

    server = SimServer(make_simulation(robot), announce, handshake_wait_s=5.0)
    thread = threading.Thread(target=server.serve_tcp, args=("127.0.0.1", 0), daemon=True)
    thread.start()
    ready.wait(10)
    address = lines[0].split("tcp://")[1].split(" ")[0]
    host, port = address.rsplit(":", 1)
    return server, (host, int(port)), thread


def faulted_run(
    protocol: str, fault: str, rng: random.Random, mission: Path, hang_s: float
) -> dict[str, Any]:
    """One run of ``mission`` with ``fault``; what happened."""
    robot = PROTOCOLS[protocol]
    server, address, thread = _serve_simulator(robot)
    # from the connection: the wheeled robots drive from about 0.5 s for 4 s; the PLEN2 takes
    # about 5.5 s to be sent its motions, then walks for 8 s
    at_s = rng.uniform(6.0, 12.0) if protocol == "plen" else rng.uniform(0.8, 4.0)
    proxy = FaultProxy(address, fault, at_s, rng)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [
            *(sys.executable, "-m", "roboscript", "run", str(mission)),
            *("--robot", robot, "--port", f"socket://127.0.0.1:{proxy.port}"),
        ],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
        errors="replace",
    )
    record: dict[str, Any] = {"protocol": protocol, "fault": fault, "at_s": round(proxy.at_s, 2)}
    try:
        if fault.startswith("SIG"):
            deadline = time.monotonic() + hang_s
            while not proxy.due() and proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.01)
            if proc.poll() is None:
                proc.send_signal(getattr(signal, fault))
                proxy.faulted = True
        try:
            _, stderr = proc.communicate(timeout=hang_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, stderr = proc.communicate()
            record["problem"] = "hang"
    finally:
        proxy.close()
        server.stop()
        thread.join(timeout=10)
    record["exit"] = proc.returncode
    record["faulted"] = proxy.faulted
    record["last_line"] = stderr.strip().splitlines()[-1] if stderr.strip() else ""
    if "problem" not in record:
        problem = _judge(proc.returncode, stderr)
        if (
            fault.startswith("SIG")
            and proxy.faulted
            and proc.returncode == 128 + getattr(signal, fault)
        ):
            problem = None
        if problem is not None:
            record["problem"] = problem
            record["stderr"] = stderr[-4000:]
    moved, moving = _moving_after(robot, proxy.sent)
    record["moved"] = moved
    # After a disconnect nothing the host does can reach the robot: what it sent before the cut
    # is all there is, and the robot's firmware decides (the served simulator stops its motors).
    if moving and fault != "disconnect":
        record["problem"] = record.get("problem", "left moving")
        record["left_moving"] = True
    return record


def fault_campaign(runs: int, seed: int, hang_s: float, protocols: list[str]) -> dict[str, Any]:
    """``runs`` faulted runs per protocol; the figures."""
    started = time.monotonic()
    BUILD.mkdir(parents=True, exist_ok=True)
    wheeled = BUILD / "faulted.yaml"
    wheeled.write_text(WHEELED_MISSION, encoding="utf-8")
    walking = BUILD / "faulted-walk.yaml"
    walking.write_text(WALKING_MISSION, encoding="utf-8")
    rng = random.Random(f"faults:{seed}")
    figures: dict[str, Any] = {}
    problems: list[dict[str, Any]] = []
    for protocol in protocols:
        mission = walking if protocol == "plen" else wheeled
        records = []
        for index in range(runs):
            fault = FAULTS[index % len(FAULTS)]
            record = faulted_run(protocol, fault, rng, mission, hang_s)
            records.append(record)
            if "problem" in record:
                problems.append(record)
            print(
                f"  {protocol} {index + 1}/{runs} {fault}: exit {record['exit']}"
                f" {record.get('problem', 'ok')} ({record['last_line'][:90]})",
                file=sys.stderr,
                flush=True,
            )
        figures[protocol] = {
            "runs": runs,
            "faults": dict(Counter(r["fault"] for r in records)),
            "exit": dict(Counter(str(r["exit"]) for r in records)),
            "tracebacks": sum(1 for r in records if r.get("problem") == "traceback"),
            "hangs": sum(1 for r in records if r.get("problem") == "hang"),
            "left_moving": sum(1 for r in records if r.get("left_moving")),
            "moved_before_the_end": sum(1 for r in records if r["moved"]),
            "other_problems": sum(
                1
                for r in records
                if r.get("problem") not in (None, "traceback", "hang", "left moving")
            ),
        }
    return {
        "per_protocol": figures,
        "problems": problems,
        "wall_s": round(time.monotonic() - started, 1),
    }


# ----------------------------------------------------------------------------------- main


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--missions", type=int, default=10000, help="missions to fuzz")
    parser.add_argument("--faulted-runs", type=int, default=50, help="faulted runs per protocol")
    parser.add_argument("--seed", type=int, default=1, help="campaign seed (default 1)")
    parser.add_argument(
        "--subprocess-every", type=int, default=100, help="also run every Nth input as a process"
    )
    parser.add_argument("--hang-s", type=float, default=60.0, help="a hang after this long")
    parser.add_argument(
        "--protocols", default=",".join(PROTOCOLS), help="comma-separated (default: all four)"
    )
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    options = parser.parse_args(argv)
    if options.worker:
        return worker(options.worker)

    BUILD.mkdir(parents=True, exist_ok=True)
    report: dict[str, Any] = {"seed": options.seed}
    if options.missions:
        print(f"fuzzing {options.missions} missions", file=sys.stderr, flush=True)
        report["missions"] = mission_campaign(
            options.missions, options.seed, options.subprocess_every, options.hang_s
        )
    if options.faulted_runs:
        protocols = [p for p in options.protocols.split(",") if p]
        print(f"{options.faulted_runs} faulted runs per protocol", file=sys.stderr, flush=True)
        report["faults"] = fault_campaign(
            options.faulted_runs, options.seed, options.hang_s, protocols
        )
    (BUILD / "report.json").write_text(json.dumps(report, indent=2), encoding="utf-8")
    found = 0
    if "missions" in report:
        m = report["missions"]
        found += m["tracebacks"] + m["hangs"] + m["over_memory_limit"]
        print(
            f"missions: {m['missions']} ({m['by_kind']}) in {m['wall_s']} s;"
            f" check exit {m['check_exit']}, run exit {m['run_exit']};"
            f" {m['subprocess_samples']} through processes (exit {m['subprocess_exit']})\n"
            f"  tracebacks {m['tracebacks']}, hangs {m['hangs']}, over {SLOW_S:g} s"
            f" {m['over_5_s']} (slowest {m['slowest_s']} s), peak memory"
            f" {m['peak_memory_mb']} MB ({m['over_memory_limit']} over {MEMORY_LIMIT_MB} MB)"
        )
    if "faults" in report:
        for protocol, f in report["faults"]["per_protocol"].items():
            found += f["tracebacks"] + f["hangs"] + f["left_moving"] + f["other_problems"]
            print(
                f"faults {protocol}: {f['runs']} runs {f['faults']}; exit {f['exit']};"
                f" tracebacks {f['tracebacks']}, hangs {f['hangs']}, left moving"
                f" {f['left_moving']}, other {f['other_problems']}"
                f" (moved before the end: {f['moved_before_the_end']})"
            )
    print(f"report: {(BUILD / 'report.json').relative_to(ROOT)}; problems found: {found}")
    return 1 if found else 0


if __name__ == "__main__":
    raise SystemExit(main())
