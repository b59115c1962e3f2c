"""A student's loop in the page, as a beginner lives it: mistakes while typing, files opened.

Headless Chromium from file:// with the network off. Each mistake beginners make (a tab in
YAML, a sensor's name misspelled, Python that does not parse) is listed under the editor as
``roboscript check`` prints it, with its line marked. A file opened that cannot be a mission (a
5 MB file, a picture) is refused in a sentence and the editor keeps its text; a file not saved
as UTF-8 opens with its letters, and a name beyond ASCII (even bytes that are no UTF-8) opens.
Nothing here is timed.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from browser import Browser
from helpers import MISSIONS, run_cli
from web_app import LONG_S

pytestmark = pytest.mark.timeout(1200)

HELLO = (Path(__file__).parents[2] / "roboscript" / "web" / "examples" / "hello.yaml").read_text(
    encoding="utf-8"
)
SQUARE = (MISSIONS / "square.yaml").read_text(encoding="utf-8")
BROKEN_PY = """from roboscript import Drive, Mission, state


class Go(Mission):
    go = state(Drive(distance_mm=100), initial=True, on_done="end"
    end = state(final="success")
"""
PROBLEMS = "document.querySelector('[data-role=problems]')"
EDITOR = "document.querySelector('.CodeMirror').CodeMirror"
NOTE = "document.querySelector('[data-role=file-note]')"


def _type(page: Browser, name: str, text: str) -> None:
    page.evaluate(
        f"{EDITOR}.setValue({json.dumps(text)});"
        f"document.querySelector('[data-role=name]').value = {json.dumps(name)};"
        "document.querySelector('[data-role=name]').dispatchEvent(new Event('change'));"
        f"{PROBLEMS}.removeAttribute('data-errors')"
    )


def _open(page: Browser, path: Path) -> None:
    """Choose ``path`` in the page's Open… file input, as the browser's chooser does."""
    page.evaluate(f"{NOTE}.removeAttribute('data-opened')")
    root = page._call("DOM.getDocument")["root"]["nodeId"]
    node = page._call("DOM.querySelector", {"nodeId": root, "selector": "[data-role=file]"})
    page._call("DOM.setFileInputFiles", {"files": [str(path)], "nodeId": node["nodeId"]})
    # read and handled (the file is read after the chooser's answer, in its own time)
    page.wait_for(f"{NOTE}.dataset.opened === {json.dumps(path.name)}", LONG_S)


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("tabs.yaml", HELLO.replace("\n  turn:", "\n\tturn:")),
        ("sensor.yaml", SQUARE.replace("bumper.any", "bumpr.any")),
        ("broken.py", BROKEN_PY),
    ],
    ids=["tab in YAML", "misspelled sensor", "Python syntax error"],
)
def test_a_beginners_mistake_is_shown_at_its_line_as_check_prints_it(
    page: Browser, tmp_path: Path, name: str, text: str
) -> None:
    (tmp_path / name).write_text(text, encoding="utf-8")
    printed = run_cli("check", name, cwd=tmp_path).stderr.splitlines()[0]
    _type(page, name, text)
    page.wait_for(f"{PROBLEMS}.dataset.errors === '1'", LONG_S)
    assert page.evaluate(f"{PROBLEMS}.querySelector('li').textContent") == printed
    line = int(printed.split(":")[1])
    assert page.evaluate(f"{EDITOR}.lineInfo({line - 1}).bgClass") == "rs-bad-line"
    assert page.evaluate("document.querySelector('[data-action=run]').disabled") is True


def test_a_file_far_too_big_for_a_mission_is_refused_and_the_editor_kept(
    page: Browser, tmp_path: Path
) -> None:
    _type(page, "hello.yaml", HELLO)
    big = tmp_path / "huge.yaml"
    big.write_text("# padding\n" * 500_000, encoding="utf-8")  # 5 MB
    _open(page, big)
    assert page.evaluate(f"{NOTE}.textContent") == (
        "Not opened: huge.yaml is 5.0 MB, far too big for a mission (a mission is a few kB of"
        " text). Did you pick the right file?"
    )
    assert page.evaluate(f"{EDITOR}.getValue()") == HELLO
    assert page.evaluate("document.querySelector('[data-role=name]').value") == "hello.yaml"


def test_a_binary_file_is_refused_and_the_editor_kept(page: Browser, tmp_path: Path) -> None:
    _type(page, "hello.yaml", HELLO)
    picture = tmp_path / "robot.yaml"  # a picture saved under a mission's name
    picture.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)))
    _open(page, picture)
    assert page.evaluate(f"{NOTE}.textContent") == (
        "Not opened: robot.yaml is not a text file (it holds binary data, like a picture or a"
        " program). Open a mission: a .yaml or .py file."
    )
    assert page.evaluate(f"{EDITOR}.getValue()") == HELLO


def test_a_file_not_saved_as_utf8_opens_with_its_letters_and_says_so(
    page: Browser, tmp_path: Path
) -> None:
    text = HELLO.replace("and beep.", "and beep (café, señal, Größe).")
    old = tmp_path / "accents.yaml"
    old.write_bytes(text.encode("cp1252"))
    _open(page, old)
    assert page.evaluate(f"{EDITOR}.getValue()") == text  # nothing lost to the replacement char
    assert page.evaluate(f"{NOTE}.textContent") == (
        "accents.yaml was not saved as UTF-8, so it was read as Western (Windows-1252) text:"
        " check its accented letters. Save writes it as UTF-8."
    )
    page.wait_for(f"{PROBLEMS}.dataset.errors === '0'", LONG_S)


def test_a_file_whose_name_is_not_utf8_opens_and_is_checked(page: Browser) -> None:
    # A name whose bytes are no UTF-8 (Latin-1's é) reaches a page with U+FFFD in its place
    # (DevTools cannot hand such a path to the chooser, so the page's input is given the file
    # as the browser would give it).
    text = HELLO.replace("{rotate:", "{rotat:")
    page.evaluate(
        f"{NOTE}.removeAttribute('data-opened');"
        "(function () { var input = document.querySelector('[data-role=file]');"
        " var files = new DataTransfer();"
        f" files.items.add(new File([{json.dumps(text)}], 'mission-\\ufffd.yaml'));"
        " input.files = files.files; input.dispatchEvent(new Event('change')); })()"
    )
    page.wait_for(f"{NOTE}.dataset.opened", LONG_S)
    assert page.evaluate(f"{NOTE}.textContent") == ""
    assert page.evaluate(f"{EDITOR}.getValue()") == text
    page.wait_for(f"{PROBLEMS}.dataset.errors === '1'", LONG_S)
    shown = page.evaluate(f"{PROBLEMS}.querySelector('li').textContent")
    assert shown.endswith(":9:10: error: unknown action 'rotat' (did you mean 'rotate'?)")
    assert page.errors == []


DIALOG = "document.querySelector('[data-role=unsaved]')"
CHOOSER = "window.rsChooserAsked"


def _count_choosers(page: Browser) -> None:
    """Count the times the page asks for the browser's file chooser (and open none)."""
    page.evaluate(
        f"{CHOOSER} = 0; document.querySelector('[data-role=file]').addEventListener('click',"
        f" function (event) {{ {CHOOSER} += 1; event.preventDefault(); }})"
    )


def _open_square(page: Browser, tmp_path: Path) -> None:
    square = tmp_path / "square.yaml"
    square.write_text(SQUARE, encoding="utf-8")
    _open(page, square)
    page.wait_for(f"{EDITOR}.getValue() === {json.dumps(SQUARE)}", LONG_S)


def _edit(page: Browser) -> str:
    """Type a line at the top of the editor, as a student does; the text after it."""
    edited: str = page.evaluate(
        f"{EDITOR}.replaceRange('# my own note\\n', {{line: 0, ch: 0}}); {EDITOR}.getValue()"
    )
    return edited


def test_open_asks_before_replacing_edits_not_saved_and_keeping_them_keeps_them(
    page: Browser, tmp_path: Path
) -> None:
    page._call("Browser.setDownloadBehavior", {"behavior": "deny"}, session=False)
    _open_square(page, tmp_path)
    _count_choosers(page)
    edited = _edit(page)
    page.click("[data-action=open]")
    assert page.wait_for(f"{DIALOG}.open", LONG_S) is True
    assert page.evaluate("document.querySelector('[data-role=unsaved-text]').textContent") == (
        "Your edits to square.yaml are not saved, and opening a file replaces them. Keep them"
        " (then Save, which downloads the file), or lose them?"
    )
    assert page.evaluate(CHOOSER) == 0  # nothing is replaced while the page asks
    page.click("[data-action=keep-edits]")
    page.wait_for(f"!{DIALOG}.open", LONG_S)
    assert page.evaluate(f"{EDITOR}.getValue()") == edited
    assert page.evaluate(CHOOSER) == 0
    # said so: the chooser opens, and the file opened replaces the edits
    page.click("[data-action=open]")
    page.wait_for(f"{DIALOG}.open", LONG_S)
    page.click("[data-action=lose-edits]")
    assert page.wait_for(f"{CHOOSER} === 1 && !{DIALOG}.open", LONG_S) is True
    _open_square(page, tmp_path)
    # nothing to lose: just opened, or saved since the last edit
    page.click("[data-action=open]")
    assert page.wait_for(f"{CHOOSER} === 2", LONG_S) is True
    _edit(page)
    page.click("[data-action=save]")
    page.click("[data-action=open]")
    assert page.wait_for(f"{CHOOSER} === 3", LONG_S) is True
    assert page.evaluate(f"{DIALOG}.open") is False
    assert page.errors == []


def test_an_example_picked_over_edits_not_saved_asks_first(page: Browser, tmp_path: Path) -> None:
    _open_square(page, tmp_path)
    edited = _edit(page)
    pick = (
        "(function () { var list = document.querySelector('[data-role=example]');"
        " list.value = 'hello.yaml'; list.dispatchEvent(new Event('change')); })()"
    )
    page.evaluate(pick)
    assert page.wait_for(f"{DIALOG}.open", LONG_S) is True
    page.click("[data-action=keep-edits]")
    page.wait_for(f"!{DIALOG}.open", LONG_S)
    assert page.evaluate(f"{EDITOR}.getValue()") == edited
    page.evaluate(pick)
    page.wait_for(f"{DIALOG}.open", LONG_S)
    page.click("[data-action=lose-edits]")
    page.wait_for(f"{EDITOR}.getValue() === {json.dumps(HELLO)}", LONG_S)
    assert page.evaluate("document.querySelector('[data-role=name]').value") == "hello.yaml"
