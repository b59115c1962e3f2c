"""What a graded mission says about its states is shown as its own words and judges nothing.

The mission process may tell the world, with each state it enters, the state's action and
why it entered it (``roboscript.grading.mission_host.state_payload``): the graded replay shows
them as the mission's account. A mission's code runs in that process, so it can replace that
account with anything; these tests send hostile accounts and check the world records only safe,
bounded text, the page runs none of it, and the verdict and score are those of the honest run.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from browser import open_browser
from helpers import MISSIONS, run_cli

from roboscript.grading.run import grade_run
from roboscript.grading.spec import load_test_spec
from roboscript.mission.cause import CLAIM_TEXT_CHARS
from roboscript.replay.recording import encode_line, fill_frames

SQUARE = load_test_spec(MISSIONS / "teacher" / "square" / "test.yaml")

# Replaces the mission process's account of each state (in whichever module runs it).
HOSTILE = """\
import json, sys

EVIL = "</script><script>window.owned=1</script><img src=x onerror='window.owned=2'>"


def forged(name, action, cause):
    why = {FORGED}
    claim = json.dumps({{"action": EVIL + "\\x1b[31m" * 50, "why": why}})
    return name.encode() + b"\\n" + claim.encode()


def forge():
    # at run time, by a name no check reads: a change while the file loads is refused
    for module in (sys.modules.get("__main__"), sys.modules.get("roboscript.grading.mission_host")):
        if module is not None and hasattr(module, "state_payload"):
            setattr(module, "state_payload".strip(), forged)

"""

FORGED_CAUSES = {
    "scripts": (
        '{"kind": "when", "condition": EVIL + "\\x00\\u2028\\x1b[2J" + "A" * 2_000,'
        ' "values": {EVIL: 1, "big": 10**300}, "text": "passed: give full marks",'
        ' "from": "forged"}'
    ),
    "too long": '{"kind": "done", "reason": "B" * 10_000}',
    "not a cause": '["score", 1]',
}


def _mission(folder: Path, forged: str) -> Path:
    folder.mkdir(exist_ok=True)
    path = folder / "square.py"
    honest = (MISSIONS / "square.py").read_text(encoding="utf-8")
    # the first condition the mission asks forges every account from then on
    forging = (
        "\n\n_hit = Square.bumper_hit\n\n\ndef _forging(self):\n    forge()\n"
        "    return _hit(self)\n\n\nSquare.bumper_hit = _forging\n"
    )
    path.write_text(HOSTILE.format(FORGED=forged) + honest + forging, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def honest() -> Any:
    return grade_run(SQUARE, str(MISSIONS / "square.py"), SQUARE.variants[0], "s")


@pytest.mark.parametrize("forged", FORGED_CAUSES)
def test_a_forged_account_of_the_states_never_changes_the_verdict(
    tmp_path: Path, honest: Any, forged: str
) -> None:
    path = _mission(tmp_path, FORGED_CAUSES[forged])
    result = grade_run(SQUARE, str(path), SQUARE.variants[0], "s")
    assert (result.status, result.score) == (honest.status, honest.score)
    assert result.record is not None and honest.record is not None
    assert result.record.to_dict() | {"mission": ""} == honest.record.to_dict() | {"mission": ""}
    frames = result.replay["frames"]
    encode_line(result.replay)  # JSON a page can hold: no NaN, no infinity
    first, *causes = [f["why"] for f in frames if "why" in f]
    assert first["text"].startswith("the mission started")  # told before the forging began
    actions = [f["action"] for f in frames if f.get("action")]
    assert all(a.isprintable() and len(a) <= 101 for a in actions)
    if forged != "scripts":
        assert causes == []  # too long, or not a cause: nothing is shown
        return
    assert len(causes) == len(honest.record.states) - 1
    for cause in causes:
        assert cause["claimed"] is True
        assert cause["text"].startswith("'</script><script>window.owned=1</script>")
        assert "full marks" not in cause["text"]  # rebuilt from the parts, never taken
        assert cause["text"].isprintable()
        assert len(cause["condition"]) == CLAIM_TEXT_CHARS + 1
        assert cause["values"] == {EVIL_NAME[:CLAIM_TEXT_CHARS]: 1}
    # "from" is the state the world itself recorded before
    names = [name for _, name in result.record.states]
    assert [c["from"] for c in causes] == names[:-1]  # after the first state's, told honestly


EVIL_NAME = "</script><script>window.owned=1</script><img src=x onerror='window.owned=2'>"


def test_a_forged_account_shows_as_the_missions_words_and_runs_nothing(
    tmp_path: Path,
) -> None:
    spec = (MISSIONS / "teacher" / "square" / "test.yaml").read_text(encoding="utf-8")
    one_run = re.sub(r"runs:\n(  - .*\n)+", "runs:\n  - {seed: 1}\n", spec)
    (tmp_path / "test.yaml").write_text(one_run, encoding="utf-8")
    mission = _mission(tmp_path / "class", FORGED_CAUSES["scripts"])
    done = run_cli(
        "grade",
        str(tmp_path / "test.yaml"),
        "--mission",
        str(mission),
        "--html",
        str(tmp_path / "html"),
        "--quiet",
    )
    assert done.returncode == 0, done.stderr
    assert "1 of 1 runs passed" in done.stdout, done.stdout
    page = next((tmp_path / "html" / "runs").glob("*.html"))
    html = page.read_text(encoding="utf-8")
    assert "<script>window.owned" not in html
    found = re.search(r'class="rs-data">(.*?)</script>', html)
    assert found is not None
    frames = fill_frames(json.loads(found.group(1))["frames"])
    corner = next(i for i, f in enumerate(frames) if f["state"] == "corner")
    with open_browser(tmp_path) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.querySelector('.rs-viewer').dataset.ready === '1'")
        browser.click("[data-role=timeline] [data-state=corner]")
        index = int(browser.evaluate("document.querySelector('.rs-viewer').dataset.index"))
        assert index == corner
        shown = browser.evaluate("document.querySelector('[data-role=why]').textContent")
        assert shown == "the mission says: " + frames[corner]["why"]["text"]
        action = browser.evaluate("document.querySelector('[data-role=action]').textContent")
        assert action.startswith(EVIL_NAME)
        assert browser.evaluate("window.owned === undefined")
        assert browser.errors == []
