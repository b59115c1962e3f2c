"""A student's code that runs away in the page: the page stays the student's.

The student's Python runs in a worker of its own, so a mission that loops
without end never holds the page: it answers while the run goes on (a script run in
the page gets its answer before the run ends), the Stop beside Run ends the run at once, and
a fresh Python takes the next run. Headless Chromium from file:// with the network off;
nothing here is timed: "while the run goes on" is checked by what the page shows, not by a
clock.
"""

from __future__ import annotations

import json

import pytest
from browser import Browser
from test_watchdog import SPIN
from web_app import LONG_S

pytestmark = pytest.mark.timeout(1200)

BUSY = '''from roboscript import Drive, Mission, state


class {name}(Mission):
    """Drive very slowly for as long as a run may last, checking a condition every tick."""

    go = state(Drive(distance_mm=100000, speed_mm_s=10), initial=True, on_done="done",
               on_failed="done", when=[("check", "done")])
    done = state(final="success")
    kept = []

    def check(self) -> bool:
{body}
        return False
'''
LONG = BUSY.format(name="Long", body="        sum(range(300))")

RESULT = "document.querySelector('[data-role=result]')"


def _start(page: Browser, name: str, text: str) -> dict[str, object]:
    """Put the mission in the editor, press Run, and say what the page shows right after."""
    page.evaluate(
        f"document.querySelector('[data-role=name]').value = {json.dumps(name)};"
        "document.querySelector('[data-role=name]').dispatchEvent(new Event('change'));"
        f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)});"
        f"{RESULT}.textContent = ''; {RESULT}.removeAttribute('data-outcome');"
    )
    page.wait_for(
        "document.body.dataset.ready === '1' &&"
        " document.querySelector('[data-role=problems]').dataset.errors === '0' &&"
        " !document.querySelector('[data-action=run]').disabled",
        LONG_S,
    )
    page.click("[data-action=run]")
    shown: dict[str, object] = page.evaluate(
        "({status: document.querySelector('[data-role=status]').textContent,"
        f" result: {RESULT}.textContent,"
        " stop: !document.querySelector('[data-action=stop-run]').disabled})"
    )
    return shown


def _summary(page: Browser) -> dict[str, object]:
    page.wait_for(f"{RESULT}.dataset.outcome", LONG_S)
    summary: dict[str, object] = json.loads(page.evaluate(f"{RESULT}.dataset.json"))
    return summary


def test_the_page_answers_while_the_students_code_loops_forever(page: Browser) -> None:
    shown = _start(page, "spin.py", SPIN)
    # the page ran this script while the loop went on: the run is not over, Stop is offered
    assert shown == {
        "status": "Running on the simulator… (■ Stop ends it)",
        "result": "",
        "stop": True,
    }
    reason = str(_summary(page)["reason"])
    assert reason.startswith("the mission's code did not return for 5 s and was stopped at spin.py")
    assert page.errors == []


def test_stop_ends_a_run_at_once_and_the_next_run_gets_a_fresh_python(page: Browser) -> None:
    assert _start(page, "long.py", LONG)["stop"] is True
    page.click("[data-action=stop-run]")
    stopped = page.wait_for(f"{RESULT}.dataset.stopped", LONG_S)
    assert stopped == (
        "Stopped with the Stop button: the run was ended and nothing of it was kept."
    )
    assert page.evaluate(f"{RESULT}.dataset.outcome") is None
    assert page.evaluate("document.querySelector('[data-action=stop-run]').disabled") is True
    hello = page.evaluate("window.rsExamples['hello.yaml']")
    _start(page, "hello.yaml", hello)
    assert _summary(page)["final_state"] == "beep"
    assert page.errors == []
