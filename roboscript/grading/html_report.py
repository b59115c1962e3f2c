"""``roboscript grade --html DIR``: static pages for the teacher, and one for each student.

For the teacher only (every student's name and score, every run in full):

* ``DIR/index.html``: the class page, one row per student and test: ✓/✗ with the runs that
  passed, the score, the points, the worst margin (or why it stopped), a link to each run and
  to the student's own page;
* ``DIR/runs/*.html``: one page per run: what went wrong in one sentence, the trajectory over
  the world, the state timeline, the replay viewer (:mod:`roboscript.replay.viewer`, opening
  at the first violated expectation), and every expectation with its margin and first
  violation.

For the students, to hand out one each:

* ``DIR/students/NAME.html``: one student's tests and runs, points, and each run as on its run
  page; nothing of a classmate, no spec path, and a hidden variant only as "hidden run N" with
  pass or fail and the reason (:func:`~roboscript.grading.text.public_reason`).

Self-contained files: styles are inline, pictures are inline SVG, the replay's script and its
data (recorded in the world's process, ten frames a second) are inline, once per page;
nothing is fetched. Every
pass or fail is a word and a symbol as well as a colour; pictures carry a text alternative.
"""

from __future__ import annotations

import hashlib
import re
from html import escape
from pathlib import Path

from roboscript import __version__
from roboscript.grading.batch import Cell, ClassReport
from roboscript.grading.judge import failure_marks
from roboscript.grading.record import RunResult, Verdict
from roboscript.grading.spec import TestSpec
from roboscript.grading.svg import (
    COLLISION,
    END,
    PATH,
    REGION,
    START,
    TONE,
    VIOLATION,
    state_colours,
    timeline_svg,
    trajectory_svg,
)
from roboscript.grading.text import advice, format_points, one_line, public_reason
from roboscript.replay.recording import Recording, fill_frames
from roboscript.replay.viewer import viewer_block, viewer_script, viewer_style

__all__ = ["run_page_names", "student_page_names", "write_html"]

_CSS = """
:root { color-scheme: light; }
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: #1a1a1a;
       margin: 0 auto; max-width: 1100px; padding: 1.2rem 1.5rem 3rem; background: #fff; }
h1 { font-size: 1.55rem; margin: 0.2rem 0 0.6rem; }
h2 { font-size: 1.2rem; margin: 1.6rem 0 0.5rem; border-bottom: 1px solid #ddd; }
a { color: #0b57d0; }
a:focus { outline: 3px solid #f9a825; }
.muted { color: #555; }
table { border-collapse: collapse; width: 100%; margin: 0.4rem 0 1rem; }
th, td { text-align: left; padding: 0.35rem 0.6rem; border-bottom: 1px solid #e4e4e4;
         vertical-align: top; }
th { background: #f3f4f6; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.nowrap { white-space: nowrap; }
.pass { color: #1b5e20; font-weight: 600; }
.fail { color: #b71c1c; font-weight: 600; }
.badge { display: inline-block; padding: 0.05rem 0.45rem; border-radius: 0.6rem;
         font-weight: 600; white-space: nowrap; }
.badge.pass { background: #e8f5e9; border: 1px solid #81c784; }
.badge.fail { background: #ffebee; border: 1px solid #e57373; }
.runs a { margin-right: 0.5rem; white-space: nowrap; }
.banner { padding: 0.7rem 1rem; border-radius: 6px; margin: 0.6rem 0 1rem; font-size: 1.05rem; }
.banner.pass { background: #e8f5e9; border-left: 6px solid #2e7d32; }
.banner.fail { background: #ffebee; border-left: 6px solid #c62828; }
.banner.teacher { background: #fff8e1; border-left: 6px solid #f9a825; }
h2.run { font-size: 1.1rem; border-bottom: none; margin-top: 1.4rem; }
section { margin-bottom: 2rem; }
figure { margin: 0.5rem 0 1rem; }
figcaption { color: #444; font-size: 0.92rem; margin-top: 0.3rem; }
svg { max-width: 100%; height: auto; border: 1px solid #ddd; background: #fff; }
.legend { list-style: none; padding: 0; margin: 0.3rem 0; display: flex; flex-wrap: wrap;
          gap: 0.3rem 1.2rem; font-size: 0.92rem; }
.legend svg { border: none; vertical-align: middle; }
.swatch { display: inline-block; width: 0.9rem; height: 0.9rem; border-radius: 2px;
          vertical-align: middle; margin-right: 0.3rem; }
dl.facts { display: grid; grid-template-columns: max-content 1fr; gap: 0.2rem 1rem; }
dl.facts dt { font-weight: 600; }
dl.facts dd { margin: 0; }
pre { background: #f6f8fa; padding: 0.6rem; overflow-x: auto; font-size: 0.85rem; }
"""


def _page(title: str, body: str) -> str:
    # The replay viewer's script and styles once per page, however many runs it shows.
    replays = 'class="rs-viewer"' in body
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{escape(title)}</title>\n<style>{_CSS}</style>\n"
        + (viewer_style() if replays else "")
        + "</head>\n<body>\n"
        f"{body}\n"
        f'<p class="muted">Made by roboscript {escape(__version__)} <code>grade</code>.'
        " Times are on the mission clock (0 s = the mission started).</p>\n"
        + (viewer_script() if replays else "")
        + "</body>\n</html>\n"
    )


def _replay(result: RunResult, heading: str) -> list[str]:
    """The run's replay viewer, opening where an expectation first failed (if one did)."""
    data = result.replay
    if not data or not data.get("frames"):
        return []
    marks = failure_marks(result.verdicts)
    open_at = min((mark["t"] for mark in marks), default=None)
    recording = Recording(data["header"], fill_frames(data["frames"]), data.get("result"))
    where = (
        f" It opens at {open_at:.2f} s, where an expectation first failed (the red dashed line"
        " on the plots)."
        if open_at is not None
        else ""
    )
    return [
        heading,
        viewer_block(recording, open_at_s=open_at, marks=marks, label="replay of the run"),
        (
            '<p class="muted">Play, pause, step one tick (◀ ▶), pick a speed, drag the time'
            " bar, or click a state to jump to it; the plots show the sensors and the wheel"
            " speeds ten times a second. What the mission printed is marked under the states"
            " (click a mark to jump there) and listed beside the sensors: the mission's own"
            f" words, at the tick it printed them.{where}</p>"
        ),
    ]


def _mark(passed: bool) -> str:
    return '<span class="pass">✓ passed</span>' if passed else '<span class="fail">✗ failed</span>'


def _status_words(result: RunResult) -> str:
    return {
        "passed": "✓ passed",
        "failed": "✗ failed",
        "too slow": "✗ too slow",
        "timeout": "✗ did not finish",
        "hung": "✗ stopped responding",
        "crashed": "✗ crashed",
        "invalid": "✗ mission error",
        "missing": "✗ missing",
    }.get(result.status, result.status)


_WINDOWS_DEVICES = frozenset(
    ["CON", "PRN", "AUX", "NUL", *(f"{port}{n}" for port in ("COM", "LPT") for n in range(1, 10))]
)
"""Names Windows keeps for devices, whatever follows the first dot: no file may have them."""


def _safe_name(raw: str, fallback: str = "student") -> str:
    """``raw`` as a file name or id any system takes: ASCII letters, digits, ``.``, ``_``, ``-``.

    It never starts with ``-`` (``--help`` is ``help.html``), so no command a teacher runs on
    the pages (``zip pages.zip *``) reads one as an option. A name with none of them
    (``Анна``, ``王芳``) becomes ``fallback`` and a short digest of the name, so two such
    names still make two files. A name Windows keeps for a device (``con``, ``nul.x``,
    ``COM1``) gets a ``_``, so the pages unzip there too.
    """
    safe = re.sub(r"[^A-Za-z0-9._-]+", "_", raw).lstrip("._-").rstrip("._")[:80]
    if safe.split(".")[0].upper() in _WINDOWS_DEVICES:
        return f"{safe}_"  # nul.html cannot be unzipped on Windows: nul_.html can
    if safe:
        return safe
    return f"{fallback}-{hashlib.sha256(raw.encode('utf-8', 'replace')).hexdigest()[:10]}"


class _UniqueNames:
    """Page names, each different from every other (case aside): ``base.html``, or
    ``base-2.html``, ``base-3.html``... for a base given again.

    Linear in the names made: each base remembers the number it reached, so a class of
    thousands whose names share their first 80 characters (all one base once cut) does not
    try every number again for each of them. A name another base already made (``ana-2``
    beside a second ``ana``) costs one more try, once.

    Attributes:
        tries: How many names were tried so far (the work done).
    """

    def __init__(self) -> None:
        self._taken: set[str] = set()
        self._next: dict[str, int] = {}
        self.tries = 0

    def __call__(self, base: str) -> str:
        """The page name for ``base``, never given before."""
        key = base.lower()  # two names that read the same once made safe
        n = self._next.get(key, 1)
        while True:
            self.tries += 1
            name = f"{base}.html" if n == 1 else f"{base}-{n}.html"
            if name.lower() not in self._taken:
                break
            n += 1
        self._next[key] = n + 1
        self._taken.add(name.lower())
        return name


def student_page_names(report: ClassReport) -> dict[str, str]:
    """Each student's feedback page's file name inside ``students/`` (``alice.html``)."""
    unique = _UniqueNames()
    return {s.student: unique(_safe_name(s.student)) for s in report.submissions}


def run_page_names(report: ClassReport) -> dict[tuple[str, str, int], str]:
    """Each run page's file name inside ``runs/``, by (student, test, variant): all different.

    ``alice--square-50cm--2.html``; the student part is their page's name, so two students
    whose names read the same once made safe never share a run page.
    """
    students = {name: page[: -len(".html")] for name, page in student_page_names(report).items()}
    unique = _UniqueNames()
    names = {}
    for result in report.results:
        student = students.get(result.student) or _safe_name(result.student)
        base = f"{student}--{_safe_name(result.test, 'test')}--{result.variant + 1}"
        names[result.student, result.test, result.variant] = unique(base)
    return names


def write_html(report: ClassReport, folder: str | Path) -> Path:
    """Write the teacher's pages and one feedback page per student; return the class page.

    ``folder/index.html`` and ``folder/runs/`` are the teacher's: every student's score, every
    variant in full. ``folder/students/NAME.html`` is one student's page, to hand out: that
    student only, hidden variants only as "hidden run N", no spec path.
    """
    report = report.capped()
    root = Path(folder)
    runs = root / "runs"
    students = root / "students"
    runs.mkdir(parents=True, exist_ok=True)
    students.mkdir(parents=True, exist_ok=True)
    run_pages = run_page_names(report)
    for result in report.results:
        page = run_pages[result.student, result.test, result.variant]
        (runs / page).write_text(_run_page(report, result), encoding="utf-8")
    pages = student_page_names(report)
    for submission in report.submissions:
        page = _student_page(report, submission.student)
        (students / pages[submission.student]).write_text(page, encoding="utf-8")
    index = root / "index.html"
    index.write_text(_class_page(report, pages, run_pages), encoding="utf-8")
    return index


# ------------------------------------------------------------------------------ class page


def _class_page(
    report: ClassReport, pages: dict[str, str], run_pages: dict[tuple[str, str, int], str]
) -> str:
    runs = len(report.results)
    passed = sum(1 for r in report.results if r.passed)
    parts = [
        "<header><h1>Class report</h1>",
        (
            '<div class="banner teacher" role="note"><strong>For the teacher only.</strong>'
            " This page and the pages in <code>runs/</code> show every student's name and"
            " score, and every run in full, hidden ones included: do not share them. Each"
            " student's own feedback page is in <code>students/</code> (one file per"
            " student, linked below): hand out those.</div>"
        ),
        (
            f'<p class="muted">{len(report.submissions)} students, {len(report.specs)} test'
            f"{'s' if len(report.specs) != 1 else ''}, {runs} runs: <strong>{passed} passed,"
            f" {runs - passed} failed</strong>.</p>"
            + (
                f'<p class="muted">Isolation: {escape(report.isolation)}.</p>'
                if report.isolation
                else ""
            )
            + "</header>"
        ),
        "<main>",
        "<h2>Results</h2>",
        (
            '<table><caption class="muted" style="text-align:left">One row per student and test.'
            " A test passes when every run of it passes; the score gives partial credit for the"
            " expectations that held, and each run earns its share of the test's points."
            "</caption>"
        ),
        (
            '<thead><tr><th scope="col">Student</th><th scope="col">Test</th>'
            '<th scope="col">Result</th><th scope="col">Score</th><th scope="col">Points</th>'
            '<th scope="col">Worst margin, or why it stopped</th><th scope="col">Runs</th>'
            '<th scope="col">Student\'s page</th></tr></thead><tbody>'
        ),
    ]
    for submission in report.submissions:
        for spec in report.specs:
            cell = report.cell(submission.student, spec.name)
            badge = "pass" if cell.passed else "fail"
            symbol = "✓" if cell.passed else "✗"
            links = " ".join(
                f'<a href="runs/{escape(run_pages[r.student, r.test, r.variant])}">'
                f"{escape(r.label)}"
                f"{' (hidden)' if report.is_hidden(r) else ''} {'✓' if r.passed else '✗'}</a>"
                for r in cell.results
            )
            page = f"students/{pages[submission.student]}"
            parts.append(
                f'<tr><th scope="row">{escape(submission.student)}</th>'
                f'<td class="nowrap">{escape(spec.name)}</td>'
                f'<td><span class="badge {badge}">{symbol} {cell.passed_runs}/{cell.total_runs}'
                f" {'passed' if cell.passed else 'failed'}</span></td>"
                f'<td class="num">{cell.score * 100:.0f}%</td>'
                f'<td class="num">{_points(cell.points, cell.max_points)}</td>'
                f"<td>{escape(cell.summary())}</td>"
                f'<td class="runs">{links}</td>'
                f'<td><a href="{escape(page)}">{escape(pages[submission.student])}</a></td></tr>'
            )
    parts.append("</tbody></table>")
    parts.append("<h2>Tests</h2>")
    for spec in report.specs:
        variants = ", ".join(
            escape(v.label) + (" (hidden from students)" if v.hidden else "") for v in spec.variants
        )
        parts.append(
            f"<h3>{escape(spec.name)}</h3>"
            + (f"<p>{escape(spec.description)}</p>" if spec.description else "")
            + f'<p class="muted">World <code>{escape(_short_world(spec.world))}</code>,'
            f" robot <code>{escape(spec.robot)}</code>, up to {spec.max_time_s:g} s per run,"
            f" worth {format_points(spec.max_points)} points. Runs: {variants}. Spec"
            f" <code>{escape(spec.path)}</code>.</p>" + _expectation_list(spec)
        )
    parts.append("</main>")
    return _page("Class report (teacher only) — roboscript grade", "\n".join(parts))


def _short_world(world: str) -> str:
    return Path(world).name if "/" in world or "\\" in world else world


def _points(points: float, max_points: float) -> str:
    return f"{format_points(points)}/{format_points(max_points)}"


def _expectation_list(spec: TestSpec) -> str:
    items = "".join(
        f"<li><code>{escape(e.name)}</code>"
        + (f" (weight {e.weight:g})" if e.weight != 1 else "")
        + "</li>"
        for e in spec.expectations
    )
    return f"<ul>{items}</ul>"


# -------------------------------------------------------------------------------- run page


def _run_page(report: ClassReport, result: RunResult) -> str:
    """The teacher's page of one run: everything, hidden or not."""
    spec = report.spec_for(result.test)
    title = f"{result.student} — {result.test} — {result.label}"
    hidden = report.is_hidden(result)
    parts = [
        '<nav><a href="../index.html">← Class report</a></nav>',
        f"<header><h1>{escape(title)}</h1>",
        '<p class="muted">For the teacher: the student sees this run on their own page'
        + (
            f", as “{escape(report.public_label(result))}”, without its seed, start or world"
            if hidden
            else ""
        )
        + ".</p>",
        _banner(result, result.message, report.cell(result.student, result.test)),
        "</header><main>",
        *_run_sections(report, result, spec),
        (
            f'<p class="muted">Mission <code>{escape(one_line(result.mission or "none"))}'
            "</code>; test"
            f" spec <code>{escape(spec.path)}</code>; seed {result.seed}.</p>"
        ),
        "</main>",
    ]
    return _page(f"{title} — roboscript grade", "\n".join(parts))


def _banner(result: RunResult, reason: str, cell: Cell) -> str:
    banner = "pass" if result.passed else "fail"
    return (
        f'<div class="banner {banner}" role="status"><strong>{_status_words(result)}</strong>'
        + (f": {escape(reason)}" if reason else "")
        + f' <span class="muted">(score {result.score * 100:.0f}%,'
        f" {_points(cell.run_points(result), cell.run_max_points)} points)</span></div>"
    )


def _run_sections(
    report: ClassReport, result: RunResult, spec: TestSpec, suffix: str = ""
) -> list[str]:
    """What happened in a run: pictures, verdicts, facts (``suffix`` keeps ids unique)."""
    result = report.in_full(result)  # one run's record and replay at a time
    parts: list[str] = []
    record = result.record
    world = report.world_for(result)
    if record is not None and world is not None:
        parts += _pictures(report, result, spec, suffix)
    if result.verdicts:
        parts.append("<h3>Expectations</h3>" if suffix else "<h2>Expectations</h2>")
        parts.append(_verdict_table(result.verdicts))
    what = "<h3>What happened</h3>" if suffix else "<h2>What happened</h2>"
    if record is not None:
        parts.append(what)
        parts.append(_facts(result))
    elif result.status != "missing":
        parts.append(
            f"{what}<p>The run did not finish, so there is no trajectory to show. "
            + escape(advice(result.status))
            + "</p>"
        )
    return parts


_PICTURES_CHARS = 600_000
"""The most a run's state timeline and replay may add to a page (characters): a mission that
enters thousands of long-named states would otherwise make pages of tens of megabytes."""


def _pictures(report: ClassReport, result: RunResult, spec: TestSpec, suffix: str) -> list[str]:
    """Where the robot went; the states over time and the replay, if they fit the budget."""
    record = result.record
    world = report.world_for(result)
    assert record is not None and world is not None
    parts: list[str] = []
    parts.append("<h3>Where the robot went</h3>" if suffix else "<h2>Where the robot went</h2>")
    parts.append(
        "<figure>"
        + trajectory_svg(world, record, result.verdicts, spec.expectations, id_suffix=suffix)
        + "<figcaption>Seen from above, north up. The blue line is the path of the"
        " robot's centre from the start ring to the end square (the circle there is the"
        " robot's body, the line its heading). Grey strips are floor tape, black lines"
        " walls, dashed green areas named regions, a dashed red circle the target.</figcaption>"
        "</figure>"
    )
    parts.append(_legend())
    over_time = "<h3>States over time</h3>" if suffix else "<h2>States over time</h2>"
    colours = state_colours(record)
    keys = "".join(
        f'<li><span class="swatch" style="background:{c}"></span>{escape(n)}</li>'
        for n, c in colours.items()
    )
    states = [
        over_time,
        "<figure>"
        + timeline_svg(record, result.verdicts, id_suffix=suffix)
        + "<figcaption>Each bar is a stay in a state. Diamonds are tones, crosses"
        " collisions, a red ! where an expectation first failed.</figcaption></figure>"
        f'<ul class="legend" aria-label="State colours">{keys}</ul>',
        *_replay(result, "<h3>Replay</h3>" if suffix else "<h2>Replay</h2>"),
    ]
    if sum(len(part) for part in states) > _PICTURES_CHARS:
        too_many = (
            f"<p>The mission went through {len(record.states)} states in this run ("
            f"{len(colours)} different ones): too many to draw them or replay the run here."
            " Its path is above, its expectations below.</p>"
        )
        states = [over_time, too_many]
    return parts + states


# ---------------------------------------------------------------------------- student page


def _student_page(report: ClassReport, student: str) -> str:
    """One student's feedback: their tests and runs only; hidden runs only by number."""
    cells = [report.cell(student, spec.name) for spec in report.specs]
    runs = sum(c.total_runs for c in cells)
    passed = sum(c.passed_runs for c in cells)
    points = report.student_points(student)
    everything = all(c.passed for c in cells)
    parts = [
        f"<header><h1>Your feedback: {escape(student)}</h1>",
        (
            f'<div class="banner {"pass" if everything else "fail"}" role="status"><strong>'
            f"{'✓' if everything else '✗'} {passed} of {runs} runs passed</strong>:"
            f" {_points(points, report.max_points)} points.</div>"
        ),
        (
            '<p class="muted">Your own results only. A test is run several times (its runs),'
            " each with its own seed and sometimes another start, so a mission must work every"
            " time; each run earns its share of the test's points.</p>"
        ),
        "</header><main>",
        (
            '<table><thead><tr><th scope="col">Test</th><th scope="col">Result</th>'
            '<th scope="col">Points</th><th scope="col">Runs</th></tr></thead><tbody>'
        ),
    ]
    for spec, cell in zip(report.specs, cells, strict=True):
        links = " ".join(
            f'<a href="#{_anchor(spec.name, r.variant)}">{escape(report.public_label(r))}'
            f" {'✓' if r.passed else '✗'}</a>"
            for r in cell.results
        )
        parts.append(
            f'<tr><th scope="row">{escape(spec.name)}</th>'
            f'<td><span class="badge {"pass" if cell.passed else "fail"}">'
            f"{'✓' if cell.passed else '✗'} {cell.passed_runs}/{cell.total_runs}"
            f" {'passed' if cell.passed else 'failed'}</span></td>"
            f'<td class="num">{_points(cell.points, cell.max_points)}</td>'
            f'<td class="runs">{links}</td></tr>'
        )
    parts.append("</tbody></table>")
    for spec, cell in zip(report.specs, cells, strict=True):
        parts.append(
            f"<section><h2>{escape(spec.name)}:"
            f" {_points(cell.points, cell.max_points)} points</h2>"
            + (f"<p>{escape(spec.description)}</p>" if spec.description else "")
            + "<p>What is checked on every run:</p>"
            + _expectation_list(spec)
        )
        for result in cell.results:
            parts += _student_run(report, result, spec, cell)
        parts.append("</section>")
    parts.append("</main>")
    return _page(f"Your feedback: {student} — roboscript grade", "\n".join(parts))


def _anchor(test: str, variant: int) -> str:
    return f"{_safe_name(test, 'test')}-run-{variant + 1}"


def _student_run(report: ClassReport, result: RunResult, spec: TestSpec, cell: Cell) -> list[str]:
    hidden = report.is_hidden(result)
    label = report.public_label(result)
    parts = [
        (
            f'<h2 id="{_anchor(spec.name, result.variant)}" class="run">{escape(spec.name)},'
            f" {escape(label)}</h2>"
        ),
        _banner(result, public_reason(result, hidden), cell),
    ]
    if hidden:
        parts.append(
            '<p class="muted">A hidden run: its seed and start are not shown, so that a'
            " mission is tested on a case it was not tuned to. Make it work from any start.</p>"
        )
        return parts
    parts += _run_sections(report, result, spec, suffix=f"-{_anchor(spec.name, result.variant)}")
    if result.mission:
        parts.append(
            f'<p class="muted">Mission <code>{escape(one_line(Path(result.mission).name))}'
            "</code>.</p>"
        )
    return parts


def _legend() -> str:
    def icon(shape: str) -> str:
        return f'<svg width="18" height="18" viewBox="-9 -9 18 18" aria-hidden="true">{shape}</svg>'

    items = [
        (icon(f'<line x1="-8" y1="0" x2="8" y2="0" stroke="{PATH}" stroke-width="3"/>'), "path"),
        (
            icon(f'<circle r="5" fill="white" stroke="{START}" stroke-width="3"/>'),
            "start",
        ),
        (icon(f'<rect x="-5" y="-5" width="10" height="10" fill="{END}"/>'), "end"),
        (
            icon(
                f'<g stroke="{COLLISION}" stroke-width="3"><line x1="-5" y1="-5" x2="5" y2="5"/>'
                '<line x1="-5" y1="5" x2="5" y2="-5"/></g>'
            ),
            "collision",
        ),
        (icon(f'<polygon points="0,-7 6,0 0,7 -6,0" fill="{TONE}"/>'), "tone"),
        (
            icon(
                f'<circle r="7" fill="white" stroke="{VIOLATION}" stroke-width="2"/>'
                f'<text y="4" text-anchor="middle" font-size="10" fill="{VIOLATION}">!</text>'
            ),
            "first violation",
        ),
        (
            icon(
                f'<rect x="-7" y="-7" width="14" height="14" fill="{REGION}" fill-opacity="0.2"'
                f' stroke="{REGION}" stroke-dasharray="3 2"/>'
            ),
            "region",
        ),
    ]
    entries = "".join(f"<li>{svg} {escape(text)}</li>" for svg, text in items)
    return f'<ul class="legend" aria-label="Legend">{entries}</ul>'


def _verdict_table(verdicts: tuple[Verdict, ...]) -> str:
    rows = []
    for verdict in verdicts:
        when = (
            f"{verdict.first_violation_s:.2f} s" if verdict.first_violation_s is not None else "—"
        )
        weight = f" (weight {verdict.weight:g})" if verdict.weight != 1 else ""
        rows.append(
            f'<tr><td class="nowrap">{_mark(verdict.passed)}</td>'
            f'<th scope="row"><code>{escape(verdict.name)}</code>{weight}</th>'
            f'<td class="nowrap">{escape(verdict.margin) or "—"}</td><td class="num">{when}</td>'
            f"<td>{escape(verdict.detail)}</td></tr>"
        )
    return (
        '<table><thead><tr><th scope="col">Result</th><th scope="col">Expectation</th>'
        '<th scope="col">Margin</th><th scope="col">First failed at</th>'
        '<th scope="col">What was seen</th></tr></thead><tbody>'
        + "".join(rows)
        + "</tbody></table>"
    )


def _facts(result: RunResult) -> str:
    record = result.record
    assert record is not None
    tones = ", ".join(f"{t.frequency_hz:g} Hz at {t.t_s:.1f} s" for t in record.tones) or "none"
    collisions = ", ".join(f"{c.t_s:.1f} s ({c.side})" for c in record.collisions) or "none"
    items = [
        ("Outcome (reported by the mission)", record.outcome),
        ("Final state (reported by the mission)", record.final_state or "—"),
        ("Reason (reported by the mission)", record.reason or "—"),
        ("Duration", f"{record.duration_s:.2f} s"),
        ("Distance travelled", f"{record.distance_travelled_mm / 10:.1f} cm"),
        ("Tones", tones),
        ("Collisions", collisions),
        ("Robot, world, seed", f"{record.robot}, {record.world_name}, {record.seed}"),
    ]
    body = "".join(f"<dt>{escape(k)}</dt><dd>{escape(v)}</dd>" for k, v in items)
    return f'<dl class="facts">{body}</dl>'
