"""What the tutorials and README show a newcomer is what the commands print."""

from __future__ import annotations

import doctest
import io
import json
import re
from pathlib import Path

import pytest
from helpers import ROOT, run_cli

from roboscript.watchdog import TICK_BUDGET

FIRST_MISSION = ROOT / "docs" / "tutorial" / "first-mission.md"


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def test_the_square_run_ends_as_the_readme_and_the_tutorial_say() -> None:
    result = run_cli("run", "missions/square.yaml")
    assert result.returncode == 0, result.stderr
    lines = result.stderr.splitlines()
    last = lines[-1]
    assert f"`{last}`" in _text(ROOT / "README.md")
    tutorial = _text(FIRST_MISSION)
    assert last in tutorial
    assert lines[1] in tutorial and lines[2] in tutorial  # the first two states and times


def test_the_json_example_matches_a_real_run() -> None:
    result = run_cli("run", "missions/square.yaml", "--json")
    actual = json.loads(result.stdout)
    example_text = re.search(
        r"### `--json`\n\n```json\n(.*?)```",
        _text(ROOT / "docs" / "reference" / "cli.md"),
        re.DOTALL,
    )
    assert example_text is not None
    example = json.loads(example_text.group(1))
    assert example.keys() == actual.keys() and example["sim"].keys() == actual["sim"].keys()
    for key in ("duration_s", "outcome", "final_state"):
        assert example[key] == actual[key], key
    assert example["states"] == actual["states"][: len(example["states"])]
    assert example["transitions"] == actual["transitions"][: len(example["transitions"])]
    for key in ("final_pose", "distance_travelled_mm", "collisions"):
        assert example["sim"][key] == actual["sim"][key], key
    assert example["sim"]["tones"] == actual["sim"]["tones"][:1]


def test_the_tutorials_mistakes_are_reported_as_it_shows(tmp_path: Path) -> None:
    tutorial = _text(FIRST_MISSION)
    start = tutorial.index("Create `hello.yaml`")
    hello = re.search(r"```yaml\n(.*?)```", tutorial[start:], re.DOTALL)
    assert hello is not None
    broken = (
        hello.group(1)
        .replace("speed: 15 cm/s", "speed: 15 deg")
        .replace("{rotate:", "{rotat:")
        .replace("{done: beep,", "{done: beeep,")
    )
    (tmp_path / "hello.yaml").write_text(broken, encoding="utf-8")
    result = run_cli("check", "hello.yaml", cwd=tmp_path)
    assert result.returncode == 2
    shown = re.search(r"`check` prints:\n\n```\n(.*?)```", tutorial, re.DOTALL)
    assert shown is not None
    assert result.stderr == shown.group(1)


def test_the_behaviour_tutorials_run_ends_as_it_shows() -> None:
    result = run_cli("run", "missions/zigzag.yaml")
    assert result.returncode == 0, result.stderr
    doc = _text(ROOT / "docs" / "tutorial" / "write-your-own-behaviour.md")
    for line in result.stderr.splitlines():
        assert line in doc, line


def test_the_readme_command_summary_is_the_cli_references() -> None:
    def summary(path: Path) -> str:
        text = _text(path)
        found = re.search(r"```\n(roboscript run .*?)```", text, re.DOTALL)
        assert found is not None, path
        return found.group(1)

    assert summary(ROOT / "README.md") == summary(ROOT / "docs" / "reference" / "cli.md")


def _summary_commands() -> dict[str, str]:
    """The command line reference's summary, one entry per command (``run``, ``web build``)
    with its continuation lines joined."""
    found = re.search(
        r"```\n(roboscript run .*?)```", _text(ROOT / "docs" / "reference" / "cli.md"), re.DOTALL
    )
    assert found is not None
    commands: dict[str, str] = {}
    name = ""
    for line in found.group(1).splitlines():
        if line.startswith("roboscript "):
            words = line.split()
            name = " ".join(words[1:3]) if words[1] == "web" else words[1]
            commands[name] = line[len("roboscript " + name) :]
        else:
            commands[name] += " " + line.strip()
    return commands


def _as_usage(written: str) -> str:
    """A metavar as the summary writes it, as ``--help`` does: ``SPEC...`` is ``SPEC``,
    ``mermaid|dot`` is ``{mermaid,dot}``."""
    written = written.removesuffix("...")
    return "{" + written.replace("|", ",") + "}" if "|" in written else written


_OPTION = re.compile(r"(?<![\w-])(-{1,2}[a-z][\w-]*)(?: ([^\s\[\]()]+))?")


@pytest.mark.parametrize("command", sorted(_summary_commands()))
def test_each_commands_help_shows_the_options_the_reference_summary_lists(command: str) -> None:
    written = _summary_commands()[command]
    done = run_cli(*command.split(), "--help")
    assert done.returncode == 0, done.stderr
    usage = " ".join(done.stdout.split("\n\n")[0].split())  # as one line, however wrapped
    positionals = written.split(" -")[0].split(" [")[0].split()  # what comes before any option
    for positional in positionals:
        assert f" {_as_usage(positional)}" in usage, (positional, usage)
    for option, metavar in _OPTION.findall(written):
        shown = f"{option} {_as_usage(metavar)}" if metavar else option
        assert re.search(rf"[\[( ]{re.escape(shown)}[\]) ]", usage + " "), (shown, usage)
    listed = {option for option, _ in _OPTION.findall(written)}
    for option, _ in _OPTION.findall(usage.removeprefix(f"usage: roboscript {command}")):
        assert option in listed | {"-h"}, f"{option} of `{command}` is missing from the summary"


COMMON_MISTAKES = ROOT / "docs" / "tutorial" / "common-mistakes.md"


def _mistakes() -> list[tuple[str, dict[str, str], str, str]]:
    """Each section of common-mistakes.md that runs: (title, files, command, output)."""
    found = []
    for section in _text(COMMON_MISTAKES).split("\n## ")[1:]:
        title = section.splitlines()[0]
        files = dict(
            re.findall(r"`([\w.-]+)`:\n\n```(?:yaml|python)\n(.*?)```", section, re.DOTALL)
        )
        shown = re.search(r"```text\n\$ roboscript (.*?)\n(.*?)```", section, re.DOTALL)
        if files and shown is not None:
            found.append((title, files, shown.group(1), shown.group(2)))
    return found


def test_the_common_mistakes_page_shows_each_mistake_of_issue_14() -> None:
    titles = {title for title, *_ in _mistakes()}
    assert len(titles) >= 16
    for must in ("A number without its unit", "A tab in the indentation", "No final state"):
        assert must in titles


# A slow tick's time as ``run`` prints it: the code's own time, wall time less its waits for a
# CPU. A wait that falls inside a sleep (preempted on its way into ``time.sleep``, or woken by
# the watchdog's alarm) is left out although the sleep to its deadline did not last longer, so
# on a busy machine a sleeping tick can show less than the page, never a tick. It can show a
# little more too: in a virtual machine, time its host gives another machine is no wait the
# guest sees (a 0.05 s sleep read 0.06 s with every core busy), so up to half again is let by.
_OWN_TIME_OVER_PAGE = 1.5
_TICK_TIME = re.compile(r"(took (?:up to )?)(\d+\.\d\d)( s (?:in one|per) tick)")


def _own_times_as_shown(printed: str, shown: str) -> str:
    """``printed``, its slow-tick times written as ``shown`` has them, once each is checked to
    be at most the page's and more than a tick."""
    page = [float(found.group(2)) for found in _TICK_TIME.finditer(shown)]
    measured = [float(found.group(2)) for found in _TICK_TIME.finditer(printed)]
    if len(page) != len(measured):
        return printed  # the comparison shows what differs
    for on_page, own_s in zip(page, measured, strict=True):
        assert TICK_BUDGET.slow_tick_s < own_s <= on_page * _OWN_TIME_OVER_PAGE, printed
    times = iter(f"{value:.2f}" for value in page)
    return _TICK_TIME.sub(lambda found: found.group(1) + next(times) + found.group(3), printed)


@pytest.mark.parametrize(
    ("title", "files", "command", "output"), _mistakes(), ids=[m[0] for m in _mistakes()]
)
def test_each_common_mistake_prints_what_the_page_shows(
    tmp_path: Path, title: str, files: dict[str, str], command: str, output: str
) -> None:
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    result = run_cli(*command.split(), cwd=tmp_path)
    assert _own_times_as_shown(result.stderr + result.stdout, output) == output
    assert "Traceback" not in result.stderr
    assert (result.returncode != 0) == ("error:" in output), result.returncode


def _hello() -> str:
    tutorial = _text(FIRST_MISSION)
    start = tutorial.index("Create `hello.yaml`")
    hello = re.search(r"```yaml\n(.*?)```", tutorial[start:], re.DOTALL)
    assert hello is not None
    return hello.group(1)


def test_the_tutorials_mission_runs_without_a_warning(tmp_path: Path) -> None:
    (tmp_path / "hello.yaml").write_text(_hello(), encoding="utf-8")
    result = run_cli("run", "hello.yaml", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "warning" not in result.stderr
    assert result.stderr.splitlines()[-1] in _text(FIRST_MISSION)


def test_the_tutorials_step_4_fits_the_mission_it_changes(tmp_path: Path) -> None:
    snippet = re.search(
        r"Replace `out` in `hello.yaml` with:\n\n```yaml\n(.*?)```", _text(FIRST_MISSION), re.DOTALL
    )
    assert snippet is not None
    hello = _hello()
    out = re.search(r"  out:\n(?:    .*\n)+", hello)
    assert out is not None
    (tmp_path / "hello.yaml").write_text(hello.replace(out.group(0), snippet.group(1)))
    result = run_cli("check", "--strict", "hello.yaml", cwd=tmp_path)
    assert result.stderr == "checked 1 file: 0 with errors\n"
    assert run_cli("run", "hello.yaml", cwd=tmp_path).returncode == 0


def test_docs_for_users_never_send_them_to_source_files() -> None:
    for path in sorted((ROOT / "docs").rglob("*.md")):
        if "development" in path.parts:
            continue  # the developers' guide is about the source
        for line in _text(path).splitlines():
            assert not re.search(r"(?<![\w/])roboscript/\w+[/.]", line), f"{path.name}: {line}"


def test_the_docs_python_prompt_sessions_print_what_they_show(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # typed at the Python prompt in the roboscript folder, as the tutorial says
    monkeypatch.chdir(ROOT)
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    report = io.StringIO()
    sessions = 0
    for path in sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")]):
        prompt: dict[str, object] = {}  # a page's sessions are typed at one prompt, in order
        for session in re.findall(r"```python\n(>>> .*?)```", _text(path), re.DOTALL):
            sessions += 1
            typed = parser.get_doctest(session, prompt, path.name, str(path), 0)
            runner.run(typed, out=report.write, clear_globs=False)
            prompt = typed.globs  # a DocTest types at a copy of the names it is given
    assert sessions >= 2
    assert runner.summarize(verbose=False).failed == 0, report.getvalue()


def _transcripts() -> list[tuple[str, str, str]]:
    """Each ``$ roboscript ...`` transcript of a page that names only files of the roboscript
    folder: (page, command, what it prints). ``...`` as the last line: more lines follow."""
    found = []
    pages = [*(ROOT / "docs").glob("*/*.md"), ROOT / "README.md"]
    for path in sorted(p for p in pages if p != COMMON_MISTAKES):  # that page has its own test
        for command, shown in re.findall(
            r"```(?:text)?\n\$ roboscript (.*?)\n(.*?)```", _text(path), re.DOTALL
        ):
            files = [word for word in command.split() if "." in word or "/" in word]
            if all((ROOT / word).exists() for word in files):
                found.append((path.name, command, shown))
    return found


@pytest.mark.parametrize(
    ("page", "command", "shown"), _transcripts(), ids=[f"{p}: {c}" for p, c, _ in _transcripts()]
)
def test_each_transcript_prints_what_its_page_shows(page: str, command: str, shown: str) -> None:
    done = run_cli(*command.split())
    printed = done.stderr + done.stdout
    if shown.endswith("...\n"):
        assert printed.startswith(shown.removesuffix("...\n")), printed
    else:
        assert printed == shown
    assert (done.returncode != 0) == ("error:" in shown), done.returncode


def test_a_page_that_shows_an_example_file_shows_it_as_it_is() -> None:
    # a reader copies the page; the test suite runs the file: they must be one mission
    shown = {
        "missions/behaviours/zigzag.py": _text(
            ROOT / "docs" / "tutorial" / "write-your-own-behaviour.md"
        ).split("`missions/behaviours/zigzag.py`:\n\n```python\n")[1],
        "missions/square.py": _text(ROOT / "docs" / "tutorial" / "python-missions.md").split(
            "`missions/square.py` is the twin of `missions/square.yaml`:\n\n```python\n"
        )[1],
        "missions/square.yaml": _text(ROOT / "README.md").split(
            "## Writing a mission\n\n```yaml\n"
        )[1],
    }
    for path, page in shown.items():
        text = page.split("```")[0]
        actual = _text(ROOT / path)
        if path.endswith("square.py"):  # its last two lines come in the tutorial's section 7
            actual = actual.split('\n\nif __name__ == "__main__":')[0].rstrip() + "\n"
        assert text == actual, path


def test_the_browser_pages_examples_are_the_tutorials_missions() -> None:
    # the page's Example menu offers "the tutorial's missions": the same files, not copies apart
    examples = ROOT / "roboscript" / "web" / "examples"
    assert _text(examples / "square.yaml") == _text(ROOT / "missions" / "square.yaml")
    assert _text(examples / "hello.yaml") == _hello()
