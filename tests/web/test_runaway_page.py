"""A student's code that runs away in the page: the page stays the student's.

The student's Python runs in a worker of its own, so a mission that loops, floods ``print``
or allocates without end never holds the page: it answers while the run goes on (a script run
in the page gets its answer before the run ends), the Stop beside Run ends the run at once, and
a fresh Python takes the next run. Headless Chromium from file:// with the network off;
nothing here is timed: "while the run goes on" is checked by what the page shows, not by a
clock, and the bounds on printing and memory are counts (lines, bytes), which a busy machine
reaches in the same place, only later.
"""

from __future__ import annotations

import json

import pytest
from browser import Browser
from test_watchdog import SPIN
from web_app import FLOOD, LONG_S

from roboscript.mission.channels import MAX_PRINTED_LINES

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
# 1.5 GB, more than the page's Python may have (1 GB), fewer than a 32-bit Python refuses
# by itself: only the page's bound refuses it, at once, without touching a byte
HOG = BUSY.format(name="Hog", body="        self.kept.append(bytearray(1_500_000_000))")
OUT_OF_MEMORY = (
    "Python in this page ran out of memory: your code asked for more than the 1 GB the page"
    " gives it (does it keep making lists or strings that grow without end?). The page started"
    " Python again: fix the code, then run again."
)
NOTE = "document.querySelector('[data-role=run-note]')"

RESULT = "document.querySelector('[data-role=result]')"


def _start(page: Browser, name: str, text: str) -> dict[str, object]:
    """Put the mission in the editor, press Run, and say what the page shows right after."""
    # The text before the name: a name changed first is checked at once with the text still
    # in the editor (a YAML example under a .py name has an error), and that answer can land
    # after the wait below has seen the last mission's errors="0", so Run is pressed while
    # it is disabled and no run starts. The last answer is cleared, so only this text's counts.
    page.evaluate(
        f"document.querySelector('.CodeMirror').CodeMirror.setValue({json.dumps(text)});"
        f"document.querySelector('[data-role=name]').value = {json.dumps(name)};"
        "document.querySelector('[data-role=name]').dispatchEvent(new Event('change'));"
        "document.querySelector('[data-role=problems]').removeAttribute('data-errors');"
        f"{RESULT}.textContent = ''; {RESULT}.removeAttribute('data-outcome');"
    )
    page.wait_for(
        "document.body.dataset.ready === '1' &&"
        " document.querySelector('[data-role=problems]').dataset.errors === '0' &&"
        " !document.querySelector('[data-action=run]').disabled",
        LONG_S,
    )
    # the button's own click (a mouse click at where it was a moment ago can miss it on a
    # busy machine, while an answer that came in moves the page)
    page.evaluate("document.querySelector('[data-action=run]').click()")
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


def _press_stop(page: Browser) -> None:
    """The Stop button's own click (a mouse click can miss a button the page just moved)."""
    page.evaluate("document.querySelector('[data-action=stop-run]').click()")


def _run_hello(page: Browser) -> None:
    """Run the hello example after a stopped or refused run: it reaches its last state."""
    _start(page, "hello.yaml", page.evaluate("window.rsExamples['hello.yaml']"))
    assert _summary(page)["final_state"] == "beep"


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
    _press_stop(page)
    stopped = page.wait_for(f"{RESULT}.dataset.stopped", LONG_S)
    assert stopped == (
        "Stopped with the Stop button: the run was ended and nothing of it was kept."
    )
    assert page.evaluate(f"{RESULT}.dataset.outcome") is None
    assert page.evaluate("document.querySelector('[data-action=stop-run]').disabled") is True
    _run_hello(page)
    assert page.errors == []


def test_code_that_asks_for_more_memory_than_the_page_gives_is_told_and_python_starts_afresh(
    page: Browser,
) -> None:
    _start(page, "hog.py", HOG)
    summary = _summary(page)
    assert summary["outcome"] == "failure"
    assert summary["reason"] == (
        "your condition 'check' raised MemoryError in state 'go' (hog.py:13)"
    )
    assert page.wait_for(f"{NOTE}.dataset.note", LONG_S) == OUT_OF_MEMORY
    # a fresh Python, its heap well under the bound: Stop and the next run work as ever
    page.wait_for("document.body.dataset.ready === '1'", LONG_S)
    assert int(page.evaluate("document.body.dataset.heapBytes")) < 1024**3 // 2
    assert _start(page, "long.py", LONG)["stop"] is True
    assert page.evaluate(f"{NOTE}.textContent") == ""  # said till the next run
    _press_stop(page)
    page.wait_for(f"{RESULT}.dataset.stopped", LONG_S)
    _run_hello(page)
    assert page.errors == []


def test_a_flood_of_print_is_cut_at_the_records_bound_and_counted_in_one_sentence(
    page: Browser,
) -> None:
    _start(page, "flood.py", FLOOD)
    assert _summary(page)["outcome"] == "success"
    assert page.wait_for(f"{NOTE}.dataset.note", LONG_S) == (
        "Your mission printed 2500 lines: the replay keeps the first 2000 and counted the other"
        " 500 (print less often, or log() a value to plot it)."
    )
    kept = page.evaluate(
        "(() => { const run = JSON.parse(document.querySelector("
        "'.rs-viewer script.rs-data').textContent);"
        " return JSON.stringify(run); })()"
    )
    record = json.loads(kept)
    printed = len(record["header"].get("printed_before_start", [])) + sum(
        len(frame.get("print", [])) for frame in record["frames"]
    )
    assert printed == MAX_PRINTED_LINES
    assert page.errors == []
