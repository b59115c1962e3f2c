"""A student's own Python in the page: it runs, and the tab keeps it from the computer.

Headless Chromium from file:// with the network off. A Python mission with a behaviour the
student wrote runs to the same JSON as on the command line; a mission whose code loops forever
is stopped at its line while the tab lives on; a mission that tries to read a file of the
computer finds only the page's own (virtual) disk. Nothing here is timed.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from browser import Browser
from helpers import MISSIONS, run_cli
from test_watchdog import SPIN
from web_app import LONG_S

from roboscript.web.bridge import run_text

pytestmark = pytest.mark.timeout(1200)


WEAVE = (
    (MISSIONS / "behaviours" / "zigzag.py").read_text(encoding="utf-8")
    + """

from roboscript import Mission, state


class Weave(Mission):
    go = state(ZigZag(leg_mm=150, legs=2), initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""
)

PEEK = """from roboscript import Mission, PlayTone, state

SECRET = {secret!r}


class Peek(Mission):
    go = state(PlayTone(frequency_hz=440, duration_s=0.1), initial=True,
               on_done=[("read_it", "leaked"), "safe"])
    leaked = state(final="failure")
    safe = state(final="success")

    def read_it(self) -> bool:
        try:
            with open(SECRET, encoding="utf-8") as f:
                return f.read() == "top secret"
        except OSError:
            return False
"""


def _run(page: Browser, name: str, text: str) -> dict[str, object]:
    # The text before the name, and the last check's answer cleared: a name changed first is
    # checked with the last text, and that answer could disable Run as it is pressed.
    page.evaluate(
        f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)});"
        f"document.querySelector('[data-role=name]').value = {json.dumps(name)};"
        "document.querySelector('[data-role=name]').dispatchEvent(new Event('change'));"
        "document.querySelector('[data-role=problems]').removeAttribute('data-errors');"
        "document.querySelector('[data-role=result]').removeAttribute('data-outcome');"
    )
    page.wait_for("document.querySelector('[data-role=problems]').dataset.errors === '0'", LONG_S)
    page.wait_for("!document.querySelector('[data-action=run]').disabled", LONG_S)
    page.evaluate("document.querySelector('[data-action=run]').click()")
    page.wait_for("document.querySelector('[data-role=result]').dataset.outcome", LONG_S)
    summary: dict[str, object] = json.loads(
        page.evaluate("document.querySelector('[data-role=result]').dataset.json")
    )
    return summary


def test_a_python_mission_with_the_students_own_behaviour_runs_as_on_the_command_line(
    page: Browser, tmp_path: Path
) -> None:
    in_browser = _run(page, "weave.py", WEAVE)
    (tmp_path / "weave.py").write_text(WEAVE, encoding="utf-8")
    in_cpython = json.loads(run_cli("run", "weave.py", "--json", cwd=tmp_path).stdout)
    assert in_browser == in_cpython
    assert in_browser["outcome"] == "success"
    assert page.errors == []


def test_code_that_loops_forever_is_stopped_at_its_line_and_the_tab_lives_on(
    page: Browser,
) -> None:
    # a tab has no timer signal and no second thread: the watchdog checks between lines
    summary = _run(page, "spin.py", SPIN)
    assert summary["outcome"] == "error"
    reason = str(summary["reason"])
    assert reason.startswith(
        "the mission's code did not return for 5 s and was stopped at spin.py:2"
    ), reason
    assert " in far: is there a loop that never ends?" in reason
    page.wait_for("!document.querySelector('[data-action=run]').disabled", LONG_S)
    assert page.errors == []


def test_the_students_code_cannot_read_the_computers_files(page: Browser, tmp_path: Path) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("top secret", encoding="utf-8")
    mission = PEEK.format(secret=str(secret))
    # the same code run by roboscript on the computer reads it: the tab is what keeps it out
    assert json.loads(run_text("peek.py", mission))["summary"]["final_state"] == "leaked"
    assert _run(page, "peek.py", mission)["final_state"] == "safe"
