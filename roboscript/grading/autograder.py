"""``roboscript autograder gradescope|classroom|prairielearn``: ready-to-upload graders.

Each package carries the teacher's test specs (hidden runs included; with the world files
they name and the ``check:`` Python files beside them), the wheels of roboscript and every
dependency (:mod:`roboscript.grading.wheels`: installed with ``pip install --no-index``, so
nothing comes from a package index), and the platform's scripts:

* **Gradescope**, a zip: ``setup.sh`` (run once when Gradescope builds the image: a venv in
  ``/opt/roboscript`` from the wheels, plus bubblewrap if the image lacks it),
  ``run_autograder`` (per submission: ``roboscript grade tests/ --mission
  /autograder/submission --gradescope /autograder/results/results.json``), ``tests/`` and
  ``wheels/``;
* **GitHub Classroom**, a folder: ``student-template/`` (the assignment's template
  repository: the workflow ``.github/workflows/roboscript.yml`` and ``robot/`` for the
  missions) and ``private-tests/`` (a private repository of the teacher's: ``specs/`` and
  ``wheels/``, checked out by the workflow with a read-only token);
* **PrairieLearn**, a folder laid out as a course: ``serverFilesCourse/roboscript/``
  (``run.sh``, the external grader's entrypoint, and ``wheels/``) and
  ``questions/NAME/`` (``info.json`` with ``externalGradingOptions``, ``question.html``,
  ``tests/``).

The same specs and installed roboscript make the same bytes: files in a fixed order, fixed
time stamps and modes, the question's UUID derived from the specs. The scripts take their
roots from the environment (``AUTOGRADER_ROOT``, ``GRADE_ROOT``, ``ROBOSCRIPT_VENV``) with
the platform's paths as defaults, so the tests run them unchanged in a temporary folder.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import uuid
from collections.abc import Mapping, Sequence
from pathlib import Path

from roboscript import __version__
from roboscript.errors import InputError
from roboscript.grading.spec import TestSpec
from roboscript.grading.wheels import Wheel, reproducible_zip

__all__ = [
    "PLATFORMS",
    "classroom_files",
    "default_question",
    "gradescope_zip",
    "prairielearn_files",
    "spec_files",
    "write_folder",
]

PLATFORMS = ("gradescope", "classroom", "prairielearn")

Files = dict[str, tuple[bytes, bool]]
"""Package contents: ``{relative path: (bytes, executable)}``."""

_PIP = "pip install --disable-pip-version-check --no-input --no-index"


def spec_files(specs: Sequence[TestSpec]) -> dict[str, Path]:
    """The files the specs need, by their path under a folder that keeps them side by side.

    That is each spec, the world files it names, and the Python files beside it that are not
    missions (its ``check:`` functions); paths are relative to the folder holding them all,
    so a spec's ``world: ../worlds/maze.yaml`` still finds it.
    """
    # the mission loader loads only when a folder is searched for missions
    from roboscript.mission.python_loader import is_python_mission

    needed: set[Path] = set()
    for spec in specs:
        path = Path(spec.path).resolve()
        needed.add(path)
        needed.update(Path(w) for w in spec.worlds if Path(w).is_file())
        needed.update(
            p for p in path.parent.glob("*.py") if p.is_file() and not is_python_mission(p)
        )
    root = Path(os.path.commonpath([p.parent for p in needed]))
    return {p.relative_to(root).as_posix(): p for p in sorted(needed)}


def _tree(prefix: str, specs: Sequence[TestSpec], wheels: Sequence[Wheel], wheel_dir: str) -> Files:
    files: Files = {f"{prefix}/{n}": (p.read_bytes(), False) for n, p in spec_files(specs).items()}
    files.update({f"{wheel_dir}/{w.filename}": (w.content, False) for w in wheels})
    return files


def _script(text: str) -> tuple[bytes, bool]:
    return text.replace("@VERSION@", __version__).encode("utf-8"), True


_GRADESCOPE_SETUP = """\
#!/usr/bin/env bash
# Made by `roboscript autograder gradescope` (roboscript @VERSION@). Gradescope runs it once,
# as root, when it builds the autograder image. roboscript and its dependencies come from
# wheels/ in this zip: no package index is used.
set -euo pipefail
SOURCE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
VENV="${ROBOSCRIPT_VENV:-/opt/roboscript}"
# Only what the image lacks, from Ubuntu's own packages: Python's venv, and bubblewrap, the
# sandbox that keeps students' code away from the tests.
missing=""
python3 -c "import ensurepip" 2>/dev/null || missing="python3 python3-venv"
command -v bwrap >/dev/null || missing="$missing bubblewrap"
if [ -n "$missing" ]; then
    apt-get update
    apt-get install -y --no-install-recommends $missing
fi
python3 -m venv "$VENV"
"$VENV/bin/python" -m @PIP@ --find-links "$SOURCE/wheels" "roboscript==@VERSION@"
"""

_GRADESCOPE_RUN = """\
#!/usr/bin/env bash
# Made by `roboscript autograder gradescope` (roboscript @VERSION@). Gradescope runs it for
# each submission: the student's files are in /autograder/submission, and Gradescope reads
# /autograder/results/results.json. What it prints is shown to the teacher only.
AUTOGRADER="${AUTOGRADER_ROOT:-/autograder}"
VENV="${ROBOSCRIPT_VENV:-/opt/roboscript}"
mkdir -p "$AUTOGRADER/results"
"$VENV/bin/roboscript" grade "$AUTOGRADER/source/tests" \\
    --mission "$AUTOGRADER/submission" \\
    --gradescope "$AUTOGRADER/results/results.json"
exit 0  # a failed run is a grade, not an autograder error: results.json holds it
"""


def gradescope_zip(specs: Sequence[TestSpec], wheels: Sequence[Wheel]) -> bytes:
    """The Gradescope autograder zip (see the module docstring)."""
    files = _tree("tests", specs, wheels, "wheels")
    files["setup.sh"] = _script(_GRADESCOPE_SETUP.replace("@PIP@", _PIP))
    files["run_autograder"] = _script(_GRADESCOPE_RUN)
    return reproducible_zip(files)


_CLASSROOM_WORKFLOW = """\
# Made by `roboscript autograder classroom` (roboscript @VERSION@): grades each push of the
# student's missions in robot/ against the tests in the teacher's private repository.
name: roboscript grade
on: [push, workflow_dispatch]
permissions:
  contents: read
jobs:
  grade:
    runs-on: ubuntu-latest
    timeout-minutes: 15
    steps:
      - uses: actions/checkout@v4
      - uses: actions/setup-python@v5
        with:
          python-version: "3.12"
      # The tests and roboscript's wheels, from the teacher's private repository: TESTS_TOKEN
      # is a read-only token for it, a secret of the classroom's organization.
      - uses: actions/checkout@v4
        with:
          repository: @TESTS_REPO@
          token: ${{ secrets.TESTS_TOKEN }}
          path: .tests
      - name: Install bubblewrap (the sandbox) if missing
        run: |
          command -v bwrap >/dev/null ||
            (sudo apt-get update && sudo apt-get install -y bubblewrap)
      - name: Install roboscript from the tests' wheels (no package index)
        run: python -m @PIP@ --find-links .tests/wheels "roboscript==@VERSION@"
      - name: Grade
        env:
          STUDENT: ${{ github.actor }}
        run: |
          mkdir -p "$RUNNER_TEMP/class"
          cp -r robot "$RUNNER_TEMP/class/$STUDENT"
          roboscript grade .tests/specs --mission "$RUNNER_TEMP/class" --junit grade.xml
      - uses: actions/upload-artifact@v4
        if: always()
        with:
          name: grade
          path: grade.xml
"""


def _mission_names(specs: Sequence[TestSpec]) -> str:
    if len(specs) == 1:
        return "your mission (one .yaml or .py file)"
    return "one mission per test, named after it: " + ", ".join(
        f"{spec.name}.yaml" for spec in specs
    )


def classroom_files(specs: Sequence[TestSpec], wheels: Sequence[Wheel], tests_repo: str) -> Files:
    """The GitHub Classroom template and private tests (see the module docstring)."""
    files = _tree("private-tests/specs", specs, wheels, "private-tests/wheels")
    workflow = _CLASSROOM_WORKFLOW.replace("@PIP@", _PIP).replace("@TESTS_REPO@", tests_repo)
    files["student-template/.github/workflows/roboscript.yml"] = (
        workflow.replace("@VERSION@", __version__).encode(),
        False,
    )
    files["student-template/robot/README.md"] = (
        f"# Your robot\n\nPut {_mission_names(specs)} in this folder, with any behaviour files"
        " it uses. Each push is graded: see the Actions tab.\n".encode(),
        False,
    )
    return files


_PRAIRIELEARN_RUN = """\
#!/usr/bin/env bash
# Made by `roboscript autograder prairielearn` (roboscript @VERSION@): the external grader's
# entrypoint. The student's files are in /grade/student, the question's tests in /grade/tests;
# PrairieLearn reads /grade/results/results.json. roboscript comes from wheels/ beside this
# script: no package index (the grading container has no network).
GRADE="${GRADE_ROOT:-/grade}"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
VENV="${ROBOSCRIPT_VENV:-${TMPDIR:-/tmp}/roboscript}"
mkdir -p "$GRADE/results"
if [ ! -x "$VENV/bin/roboscript" ]; then
    python3 -m venv "$VENV" &&
        "$VENV/bin/python" -m @PIP@ --quiet --find-links "$HERE/wheels" "roboscript==@VERSION@"
fi
"$VENV/bin/roboscript" grade "$GRADE/tests" \\
    --mission "$GRADE/student" \\
    --prairielearn "$GRADE/results/results.json"
exit 0  # a failed run is a grade: results.json holds it
"""


def _question_html(specs: Sequence[TestSpec]) -> str:
    names = ", ".join(f"{spec.name}.yaml" for spec in specs)
    tasks = "".join(
        f"<li><b>{spec.name}</b>: {spec.description or 'see the assignment'}</li>" for spec in specs
    )
    return (
        "<pl-question-panel>\n"
        f"  <p>Upload your roboscript mission{'s' if len(specs) > 1 else ''}.</p>\n"
        f"  <ul>{tasks}</ul>\n"
        "</pl-question-panel>\n"
        f'<pl-file-upload file-names="{names}"></pl-file-upload>\n'
        "<pl-submission-panel>\n"
        "  <pl-external-grader-results></pl-external-grader-results>\n"
        "</pl-submission-panel>\n"
    )


def prairielearn_files(specs: Sequence[TestSpec], wheels: Sequence[Wheel], question: str) -> Files:
    """The PrairieLearn course files (see the module docstring)."""
    files = _tree(
        f"questions/{question}/tests", specs, wheels, "serverFilesCourse/roboscript/wheels"
    )
    files["serverFilesCourse/roboscript/run.sh"] = _script(_PRAIRIELEARN_RUN.replace("@PIP@", _PIP))
    digest = hashlib.sha256()
    for name, (content, _) in sorted(files.items()):
        if name.startswith("questions/"):
            digest.update(name.encode() + b"\0" + content)
    info = {
        "uuid": str(uuid.uuid5(uuid.NAMESPACE_URL, f"roboscript:{question}:{digest.hexdigest()}")),
        "title": ", ".join(spec.name for spec in specs),
        "topic": "Robotics",
        "tags": ["roboscript"],
        "type": "v3",
        "singleVariant": True,
        "gradingMethod": "External",
        "externalGradingOptions": {
            "enabled": True,
            "image": "prairielearn/grader-python",
            "serverFilesCourse": ["roboscript/"],
            "entrypoint": "/grade/serverFilesCourse/roboscript/run.sh",
            "timeout": 120,
        },
    }
    files[f"questions/{question}/info.json"] = (
        (json.dumps(info, indent=2) + "\n").encode(),
        False,
    )
    files[f"questions/{question}/question.html"] = (_question_html(specs).encode(), False)
    return files


def default_question(specs: Sequence[TestSpec]) -> str:
    """The PrairieLearn question's folder name for ``specs``: ``roboscript-`` and the first
    test's name, with anything but letters, digits, ``_``, ``-`` and ``.`` made ``-``."""
    return "roboscript-" + re.sub(r"[^A-Za-z0-9_.-]+", "-", specs[0].name).strip("-.")


def write_folder(files: Mapping[str, tuple[bytes, bool]], folder: str | Path) -> None:
    """Write the files under ``folder``, which must be new or empty.

    Raises:
        InputError: ``folder`` holds something already, is a file, or is under a file
            (nothing is overwritten).
        OSError: A file cannot be written.
    """
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise InputError(
            f"{folder} is a file, and this autograder is a folder of files: give -o the name"
            " of a new folder (the file is left as it is)"
        )
    if out.exists() and any(out.iterdir()):
        raise InputError(
            f"{folder} already holds files: give -o a new or empty folder (nothing in it is"
            " replaced)"
        )
    for parent in out.parents:
        if parent.exists() and not parent.is_dir():
            raise InputError(f"{folder} cannot be made: {parent} is a file, not a folder")
    for name in files:
        parts = name.split("/")
        if name.startswith("/") or any(part in {"", ".", ".."} for part in parts):
            raise InputError(f"{name!r} would be written outside {folder}")
    for name, (content, executable) in sorted(files.items()):
        target = out / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(content)
        target.chmod(0o755 if executable else 0o644)
