"""The public python-asip-client (1.0.9) drives ``roboscript sim`` as it would a MIRTO.

That client writes requests without newlines (``M,A,1M,A,1R,A,25...``), swaps motor indices,
and reads fields by character position, so it only works if the simulated board parses and
replies exactly as the firmware does.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

from helpers import HANG_BOUND_S, ROOT

CLIENT = r"""
import json, sys, time
from python_asip_client.tcp_mirto_robot import TCPMirtoRobot

robot = TCPMirtoRobot(ip_address="127.0.0.1", tcp_port=int(sys.argv[1]))
services = robot.get_services()
time.sleep(0.5)
before = [m.get_count() for m in services["motors"]]
for motor in services["motors"]:
    motor.set_motor(60)
# until the wheels have turned and the IR sensors have reported (however busy the machine)
end = time.monotonic() + float(sys.argv[2])
while time.monotonic() < end and (
    min(m.get_count() for m in services["motors"]) <= 500
    or all(ir.get_ir() == 0 for ir in services["irs"])
):
    time.sleep(0.05)
during = [m.get_count() for m in services["motors"]]
for motor in services["motors"]:
    motor.stop_motor()
irs = [ir.get_ir() for ir in services["irs"]]
bumps = [bump.is_pressed() for bump in services["bumps"]]
robot.thread_killer()
print("RESULT " + json.dumps({"before": before, "during": during, "irs": irs, "bumps": bumps}))
"""


def test_python_asip_client_moves_motors_and_reads_sensors() -> None:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    server = subprocess.Popen(
        [sys.executable, "-m", "roboscript", "sim", "--robot", "mirto", "--tcp", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=ROOT,
    )
    try:
        assert server.stdout is not None
        match = re.search(r":(\d+) ", server.stdout.readline())
        assert match
        client = subprocess.run(
            [sys.executable, "-c", CLIENT, match.group(1), str(HANG_BOUND_S / 2)],
            capture_output=True,
            text=True,
            timeout=HANG_BOUND_S,
            env=env,
            check=False,
        )
    finally:
        server.terminate()
        server.wait(timeout=HANG_BOUND_S)
    line = next((row for row in client.stdout.splitlines() if row.startswith("RESULT ")), None)
    assert line is not None, client.stdout + client.stderr
    result = json.loads(line[len("RESULT ") :])
    assert all(count > 500 for count in result["during"]), result
    assert all(
        after > before for after, before in zip(result["during"], result["before"], strict=True)
    )
    assert all(0 <= value <= 1023 for value in result["irs"]), result
    assert result["irs"] != [0, 0, 0], "IR events never reached the client"
    assert result["bumps"] == [False, False]
