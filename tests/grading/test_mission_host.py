"""The mission process of a graded run (``roboscript.grading.mission_host``), seen from outside."""

from __future__ import annotations

import signal
from pathlib import Path

import pytest
from helpers import one_run_spec

from roboscript.grading import world_host
from roboscript.grading.run import grade_run
from roboscript.grading.sandbox import Jail

# Finishes at once; as its robot's link closes, the process is sent Ctrl-C's signal.
SIGNALLED_WHILE_CLOSING = """\
import os, signal

from roboscript import Mission, Wait, state
from roboscript.transport.link import Link

_close = Link.close


def close(self):
    os.kill(os.getpid(), signal.SIGINT)  # the mission has ended: the port is closing
    _close(self)


Link.close = close


class Short(Mission):
    go = state(Wait(duration_s=0.1), initial=True, on_done="end")
    end = state(final="success")
"""


def test_a_ctrl_c_while_the_mission_process_closes_ends_it_with_the_signals_status(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Ctrl-C (SIGINT) is the signal Python turns into an exception the run catches; SIGTERM
    # and SIGHUP end the process by themselves.
    statuses: list[int] = []

    class Watched(Jail):
        """The mission process's jail, keeping the status it ended with."""

        def poll(self) -> int | None:
            status = super().poll()
            if status is not None and not statuses:
                statuses.append(status)
            return status

    monkeypatch.setattr(world_host, "Jail", Watched)
    spec = one_run_spec(tmp_path)
    mission = tmp_path / "short.py"
    mission.write_text(SIGNALLED_WHILE_CLOSING, encoding="utf-8")
    result = grade_run(spec, str(mission), spec.variants[0])
    assert result.status == "passed", result.message  # it had finished: its result stands
    signum = signal.SIGINT
    # 128 + N as it exits; under bubblewrap that reads as -N, as an end by the signal does
    assert statuses in ([128 + signum], [-signum]), statuses
