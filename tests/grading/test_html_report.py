"""The HTML report: self-contained pages, linked as a teacher clicks them, and shown for real in
headless Chromium (screenshots of the class page, a run page and a student's page must not be
blank); a student's page shows that student only, and a hidden run only by number."""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
import zlib
from pathlib import Path

import pytest
from hand_graded import HIDDEN_SECRETS, hand_report
from helpers import HANG_BOUND_S, MISSIONS, run_cli

from roboscript.grading.html_report import write_html

TEACHER = MISSIONS / "teacher"
CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
)


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The line-track test graded for a good and a bad student, as HTML."""
    root = tmp_path_factory.mktemp("html")
    folder = root / "class"
    folder.mkdir()
    shutil.copy(TEACHER / "line-track" / "good.yaml", folder / "amy.yaml")
    shutil.copy(TEACHER / "line-track" / "bad.yaml", folder / "bo.yaml")
    out = root / "report"
    result = run_cli(
        "grade", str(TEACHER / "line-track" / "test.yaml"), "--mission", str(folder),
        "--html", str(out), "--quiet",
    )  # fmt: skip
    assert result.returncode == 1, result.stderr
    return out


def test_the_class_page_links_every_run_page(report: Path) -> None:
    index = (report / "index.html").read_text(encoding="utf-8")
    links = re.findall(r'href="(runs/[^"]+)"', index)
    assert len(links) == 6
    for link in links:
        assert (report / link).is_file(), link
    assert "✓ 3/3 passed" in index and "✗ 0/3 failed" in index
    assert "check: stays_on_line failed by" in index


def test_pages_are_self_contained_and_accessible(report: Path) -> None:
    pages = [report / "index.html", *sorted(report.glob("*/*.html"))]  # runs/, students/
    assert len(pages) == 1 + 6 + 2
    for page in pages:
        text = page.read_text(encoding="utf-8")
        assert '<html lang="en">' in text
        # Nothing is fetched: the only URL is the SVG namespace, which is a name, not a fetch.
        assert not re.search(r'(src|href)="(https?:)?//', text), page.name
        assert "<link" not in text and "<script src" not in text
        # The only scripts are inline: the replay viewer's code and each run's data.
        scripts = set(re.findall(r"<script[^>]*>", text))
        assert scripts <= {"<script>", '<script type="application/json" class="rs-data">'}
        for svg in re.findall(r"<svg [^>]*>", text):
            assert 'aria-hidden="true"' in svg or ('role="img"' in svg and "aria-labelledby" in svg)
    run_page = (report / "runs" / "bo--line-track-lap--1.html").read_text(encoding="utf-8")
    assert "✗ failed" in run_page and "✓ passed" in run_page  # words and symbols, not colour
    assert "first failed here, at 7.1 s" in run_page
    assert '<polyline points="' in run_page  # the path
    assert "State timeline over" in run_page
    # What only the mission's own process could say is labelled as its claim.
    assert "Outcome (reported by the mission)" in run_page


def test_the_teacher_and_student_pages_are_apart(report: Path) -> None:
    index = (report / "index.html").read_text(encoding="utf-8")
    assert "For the teacher only." in index[: index.index("<h2>")]
    assert sorted(p.name for p in (report / "students").iterdir()) == ["amy.html", "bo.html"]
    assert 'href="students/bo.html"' in index
    bo = (report / "students" / "bo.html").read_text(encoding="utf-8")
    assert "amy" not in bo and "index.html" not in bo and "runs/" not in bo
    assert "test.yaml" not in bo and str(TEACHER) not in bo
    runs = [p.read_text(encoding="utf-8") for p in sorted((report / "runs").glob("bo--*"))]
    assert len(runs) == 3  # every run's picture, on one page:
    assert bo.count('<polyline points="') == sum(r.count('<polyline points="') for r in runs)
    assert len(set(re.findall(r'id="([^"]+)"', bo))) == len(re.findall(r'id="([^"]+)"', bo))


@pytest.fixture
def hand_pages(tmp_path: Path) -> Path:
    """The hand-made class (Quentin 6/12 with a hidden run failed, Zelda 12/12) as HTML."""
    out = tmp_path / "report"
    write_html(hand_report(tmp_path), out)
    return out


def test_a_students_page_shows_only_that_student(hand_pages: Path) -> None:
    quentin = (hand_pages / "students" / "Quentin.html").read_text(encoding="utf-8")
    zelda = (hand_pages / "students" / "Zelda.html").read_text(encoding="utf-8")
    assert "Zelda" not in quentin and "Quentin" not in zelda
    assert "1 of 3 runs passed</strong>: 6/12 points" in quentin
    assert "3 of 3 runs passed</strong>: 12/12 points" in zelda
    assert "12/12" not in quentin  # not even a classmate's score
    assert "ZeroDivisionError: division by zero (square.py:12)" in quentin
    assert "Traceback" not in quentin


def test_a_hidden_run_is_named_by_number_with_its_result_and_reason_only(
    hand_pages: Path,
) -> None:
    for page in (hand_pages / "students").iterdir():
        text = page.read_text(encoding="utf-8")
        assert "square-50cm, hidden run 3</h2>" in text
        for secret in HIDDEN_SECRETS:
            assert secret not in text, (page.name, secret)
        assert text.count('<polyline points="') == 2 - ("Quentin" in page.name)  # crash: none
    quentin = (hand_pages / "students" / "Quentin.html").read_text(encoding="utf-8")
    hidden = quentin[quentin.index("hidden run 3</h2>") :]
    assert "✗ failed</strong>: final_pose_within failed by 41.5 cm" in hidden
    # the teacher's pages show it all
    teacher = (hand_pages / "runs" / "Quentin--square-50cm--3.html").read_text(encoding="utf-8")
    assert "seed 7919, start (417, -173) mm 33°" in teacher
    assert "secret-tests" in teacher and "as “hidden run 3”" in teacher


def _chromium() -> str | None:
    """The Chromium binary, or None (.ci/run installs Debian's package; tests install nothing)."""
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _screenshot(browser: str, page: Path, png: Path, profile: Path, height: int) -> None:
    subprocess.run(
        [
            browser,
            *CHROMIUM_FLAGS,
            f"--user-data-dir={profile}",
            f"--screenshot={png}",
            f"--window-size=1280,{height}",
            page.resolve().as_uri(),
        ],
        capture_output=True,
        timeout=HANG_BOUND_S,
        check=False,
    )


def _distinct_pixel_bytes(png: Path) -> int:
    """How many different byte values the decoded image holds (1 or 2 for a blank page)."""
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    offset, idat = 8, b""
    while offset < len(data):
        (length,) = struct.unpack(">I", data[offset : offset + 4])
        kind = data[offset + 4 : offset + 8]
        if kind == b"IDAT":
            idat += data[offset + 8 : offset + 8 + length]
        offset += 12 + length
    return len(set(zlib.decompress(idat)))


def test_a_real_browser_shows_the_class_page_and_a_run_page(report: Path, tmp_path: Path) -> None:
    browser = _chromium()
    if browser is None:
        pytest.skip("Chromium is not installed (apt-get install chromium; .ci/run does it)")
    shots = {
        "class": (report / "index.html", 900),
        "run": (report / "runs" / "bo--line-track-lap--3.html", 1400),
        "student": (report / "students" / "bo.html", 1400),
    }
    for name, (page, height) in shots.items():
        png = tmp_path / f"{name}.png"
        _screenshot(browser, page, png, tmp_path / f"profile-{name}", height)
        assert png.is_file(), f"Chromium made no screenshot of {page.name}"
        assert png.stat().st_size > 20_000, f"the {name} page looks empty"
        assert _distinct_pixel_bytes(png) > 50, f"the {name} page is blank"


def test_page_names_sharing_their_first_80_characters_cost_one_try_each() -> None:
    # A class of thousands whose names are cut to one 80-character base: each name is found
    # in a bounded number of tries (work counted, not timed), and all of them differ.
    from roboscript.grading.html_report import _UniqueNames

    unique = _UniqueNames()
    names = [unique("x" * 80) for _ in range(3000)]
    assert len({name.lower() for name in names}) == 3000
    assert names[:3] == ["x" * 80 + ".html", "x" * 80 + "-2.html", "x" * 80 + "-3.html"]
    assert unique.tries <= 3000


def test_a_page_name_another_base_made_is_stepped_over_once() -> None:
    from roboscript.grading.html_report import _UniqueNames

    unique = _UniqueNames()
    made = [unique(base) for base in ("ana-2", "Ana", "ana", "ana", "ana-2", "ana-3")]
    assert made == ["ana-2.html", "Ana.html", "ana-3.html", "ana-4.html", "ana-2-2.html",
                    "ana-3-2.html"]  # fmt: skip
    assert unique.tries == len(made) + 2  # 'ana' steps over ana-2, the last 'ana-3' over ana-3


@pytest.mark.parametrize(
    ("student", "page"),
    [
        ("con", "con_"),
        ("NUL.x", "NUL.x_"),
        ("Com1", "Com1_"),
        ("console", "console"),
        ("lpt", "lpt"),
    ],
)
def test_a_student_named_like_a_windows_device_gets_a_page_windows_can_unzip(
    student: str, page: str
) -> None:
    from roboscript.grading.html_report import _safe_name

    assert _safe_name(student) == page
