"""A mission's file that takes away what stops it at a line, at home as in class.

A graded run refuses a mission that takes the watchdog's SIGALRM, sets a recursion limit it
cannot stop or ends its own process; ``roboscript check`` and ``run`` load the file in their
own process, where the same file hung (a loop after ``signal.signal(signal.SIGALRM,
signal.SIG_IGN)``), crashed, or ended with nothing said (``os._exit(3)``). Each is now said at
the student's line.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import run_cli

HEAD = "from roboscript import Drive, Mission, state\n"
CLASS = (
    "\n\nclass M(Mission):\n"
    '    go = state(Drive(distance_mm=500), initial=True, on_done="end", on_failed="end")\n'
    '    end = state(final="success")\n'
)
ALARM = (
    "PermissionError: the watchdog that stops code that never returns uses SIGALRM and the"
    " real-time timer (signal.alarm, signal.setitimer(signal.ITIMER_REAL)): a mission may not"
    " change, ignore or block them"
)


def _mission(tmp_path: Path, top: str, name: str = "m.py") -> str:
    (tmp_path / name).write_text(HEAD + top + CLASS, encoding="utf-8")
    return name


@pytest.mark.parametrize(
    "takes",
    [
        "signal.signal(signal.SIGALRM, signal.SIG_IGN)",
        "signal.signal(signal.SIGALRM, lambda *a: None)",
        "signal.setitimer(signal.ITIMER_REAL, 0)",
        "signal.alarm(0)",
        "signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGALRM])",
    ],
)
def test_a_file_that_takes_the_alarm_then_loops_is_refused_at_that_line_by_check(
    tmp_path: Path, takes: str
) -> None:
    name = _mission(tmp_path, f"import signal\n{takes}\nwhile True:\n    pass\n")
    result = run_cli("check", name, cwd=tmp_path)
    assert result.stderr.splitlines() == [
        f"m.py:3:1: error: {ALARM}",
        "checked 1 file: 1 with errors",
    ]


def test_a_recursion_limit_no_watchdog_can_stop_is_refused_at_its_line(tmp_path: Path) -> None:
    name = _mission(
        tmp_path,
        "import sys\nsys.setrecursionlimit(10**6)\n\n\ndef deep(n):\n    return deep(n + 1)\n",
    )
    result = run_cli("check", name, cwd=tmp_path)
    assert result.stderr.splitlines() == [
        (
            "m.py:3:1: error: a mission's recursion limit is between 250 and 10000 (it was asked"
            " for 1000000): roboscript's own calls need 250, and deeper calls than 10000 are a"
            " runaway recursion"
        ),
        "checked 1 file: 1 with errors",
    ]


@pytest.mark.parametrize("command", ["check", "run"])
def test_os_exit_while_the_file_loads_is_told_at_its_line(tmp_path: Path, command: str) -> None:
    name = _mission(tmp_path, "import os\nos._exit(3)\n")
    result = run_cli(command, name, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines()[0] == (
        "m.py:3:1: error: the mission file called exit() while it was loaded"
    )


def test_os_exit_in_an_actions_helper_ends_the_run_naming_its_line(tmp_path: Path) -> None:
    (tmp_path / "m.py").write_text(
        "import os\n\nfrom roboscript import Action, Mission, Result, state\n\n\n"
        "def leave():\n    os._exit(3)\n\n\nclass Pause(Action):\n"
        '    name = "pause"\n    requires = frozenset({"drive_base"})\n\n'
        "    def update(self, ctx):\n        leave()\n        return Result.done()\n\n\n"
        "class M(Mission):\n"
        '    go = state(Pause(), initial=True, on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("run", "m.py", cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == (
        "failure: your behaviour 'pause' called exit() in state 'go': a mission ends by going to"
        " a final state, not by ending the program (m.py:7)"
    )


def test_os_exit_in_a_thread_of_the_file_is_told_and_the_check_goes_on(tmp_path: Path) -> None:
    name = _mission(
        tmp_path,
        "import os\nimport threading\n\nthreading.Thread(target=lambda: os._exit(4)).start()\n",
    )
    result = run_cli("check", name, cwd=tmp_path)
    assert result.returncode == 0
    # the thread writes as the check goes on: its line may come before or after the count
    assert "checked 1 file: 0 with errors" in result.stderr
    assert (
        "m.py:5:33: warning: os._exit(4) in a thread would end the whole program, not the"
        " mission: the thread was ended instead (a mission ends by going to a final state)"
    ) in result.stderr


def test_an_exit_at_the_programs_end_is_told_at_its_atexit_line_without_a_traceback(
    tmp_path: Path,
) -> None:
    name = _mission(tmp_path, "import atexit\nimport sys\n\natexit.register(sys.exit, 5)\n")
    result = run_cli("check", name, cwd=tmp_path)
    assert result.stderr.splitlines() == [
        "checked 1 file: 0 with errors",
        (
            "m.py:5:1: warning: the function given to atexit.register here raised SystemExit as"
            " the program ended (a mission's work ends with its final state: take atexit away)"
        ),
    ]
