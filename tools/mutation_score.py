"""Mutation testing with mutmut: run it over some of roboscript and print the mutation score.

    python tools/mutation_score.py                          # everything [tool.mutmut] names
    python tools/mutation_score.py roboscript/control       # one package (or file)
    python tools/mutation_score.py --changed origin/main    # the changed files under the scope

The run happens in a scratch copy of the checkout (``build/mutation/``), whose
``pyproject.toml`` gets a ``[tool.mutmut]`` narrowed to the paths given and to the tests that
exercise them, so the checkout itself is never touched. The last line printed is

    mutation score: KILLED/TOTAL = X.X %

followed by the surviving mutants (``--show`` prints their diffs). See
docs/development/mutation-testing.md.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

if sys.version_info < (3, 11):
    sys.exit("tools/mutation_score.py needs Python 3.11 or later (tomllib)")

import tomllib

ROOT = Path(__file__).resolve().parent.parent
SCRATCH = ROOT / "build" / "mutation"
COPIED = ("roboscript", "tests", "docs", "missions", "drivers", "README.md", "pyproject.toml")

TESTS_FOR: dict[str, tuple[str, ...]] = {
    "roboscript/control": ("tests/control", "tests/actions/test_motion.py"),
    "roboscript/actions": ("tests/actions", "tests/mission/test_runner.py"),
    "roboscript/mission": ("tests/mission",),
    "roboscript/grading/expectations": (
        "tests/grading/expectations",
        "tests/grading/test_documented_defaults.py",
        "tests/grading/test_spec.py",
    ),
}
"""The tests that exercise each package in scope: mutmut runs only these (and, per mutant,
only those of them that reach the mutated function)."""

DESELECTED: tuple[str, ...] = (
    # grades a mission in a worker process, which imports the mutated copy without mutmut's
    # trampoline state and crashes: mutmut's first, unmutated run then fails
    "tests/grading/expectations/test_reading.py::test_wall_ahead_and_run_targets_through_the_grader",
    # run `roboscript` in a child process from a temporary folder: mutmut's trampoline there
    # looks for its configuration in that folder while it records which tests reach what
    "tests/mission/test_behaviours.py::test_an_exception_in_a_behaviour_ends_the_mission_in_one_sentence",
    "tests/mission/test_behaviours.py::test_the_traceback_is_there_with_debug",
    "tests/mission/test_behaviours.py::test_a_python_mission_imports_a_behaviour",
    # grades a run in a worker process, as the first one above
    "tests/mission/test_where_the_robot_is.py::test_a_graded_run_reads_the_same_regions_as_the_run_at_home",
    "tests/mission/test_where_the_robot_is.py::test_a_world_whose_regions_outgrow_a_command_line_is_still_graded",
    # quotes Python's own TypeError for a misspelt state() keyword, which under mutmut names
    # the trampoline's copy of state() instead of state()
    "tests/mission/test_python_loader.py::test_golden_messages_for_python_mission_files",
)
"""Tests left out of every mutation run (each with the reason it cannot run under mutmut)."""


def _scope() -> list[str]:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns: list[str] = config["tool"]["mutmut"]["only_mutate"]
    return [p.removesuffix("/*") for p in patterns]


def _in_scope(path: str, scope: list[str]) -> str | None:
    """The scope entry ``path`` falls under, or ``None``."""
    for entry in scope:
        if path == entry or path.startswith(entry.rstrip("/") + "/"):
            return entry
    return None


def _changed(base: str, scope: list[str]) -> list[str]:
    out = subprocess.run(
        ["git", "diff", "--name-only", base, "--", "roboscript"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return [p for p in out.split() if p.endswith(".py") and _in_scope(p, scope)]


def _patterns(paths: list[str]) -> list[str]:
    return [f"{p.rstrip('/')}/*" if (ROOT / p).is_dir() else p for p in paths]


def _tests(paths: list[str], scope: list[str]) -> list[str]:
    tests: list[str] = []
    for path in paths:
        owner = _in_scope(path, scope) or _in_scope(path, list(TESTS_FOR))
        for test in TESTS_FOR.get(owner or "", ("tests",)):
            if test not in tests:
                tests.append(test)
    return tests


def _prepare(paths: list[str], tests: list[str]) -> None:
    if SCRATCH.exists():
        shutil.rmtree(SCRATCH)
    SCRATCH.mkdir(parents=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "mutants", ".*cache")
    for name in COPIED:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, SCRATCH / name, ignore=ignore)
        elif source.exists():
            shutil.copy2(source, SCRATCH / name)
    text = (SCRATCH / "pyproject.toml").read_text(encoding="utf-8")
    head, _, _ = text.partition("[tool.mutmut]")
    narrowed = [
        "[tool.mutmut]",
        'source_paths = ["roboscript"]',
        f"only_mutate = {json.dumps(_patterns(paths))}",
        'also_copy = ["docs/", "missions/", "drivers/", "README.md"]',
        f"pytest_add_cli_args_test_selection = {json.dumps(tests)}",
        "pytest_add_cli_args = "
        + json.dumps(
            ["-p", "no:cacheprovider", "-q", "-x"]
            + [arg for test in DESELECTED for arg in ("--deselect", test)]
        ),
    ]
    (SCRATCH / "pyproject.toml").write_text(head + "\n".join(narrowed) + "\n", encoding="utf-8")


def _mutmut(*args: str, log: Path | None = None) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)  # mutmut puts its mutated copy first on sys.path itself
    command = [sys.executable, "-m", "mutmut", *args]
    if log is None:
        return subprocess.run(
            command, cwd=SCRATCH, env=env, capture_output=True, text=True, check=False
        )
    with log.open("w", encoding="utf-8") as out:
        return subprocess.run(
            command,
            cwd=SCRATCH,
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            text=True,
            check=False,
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", help="files or folders under roboscript/")
    parser.add_argument("--changed", metavar="BASE", help="only files changed since git BASE")
    parser.add_argument("--jobs", type=int, default=2, help="parallel mutants (default 2)")
    parser.add_argument("--show", action="store_true", help="print each survivor's diff")
    parser.add_argument("--min-score", type=float, default=0.0, help="fail below this %%")
    options = parser.parse_args(argv)

    scope = _scope()
    paths = [p.rstrip("/") for p in options.paths] or scope
    if options.changed:
        paths = [p for p in _changed(options.changed, scope) if _in_scope(p, paths)]
        if not paths:
            print("mutation score: no changed files in scope")
            return 0
    tests = _tests(paths, scope)
    print(f"mutating {' '.join(paths)}\n  tests: {' '.join(tests)}", flush=True)
    _prepare(paths, tests)
    log = SCRATCH / "mutmut.log"
    run = _mutmut("run", "--max-children", str(options.jobs), log=log)
    if run.returncode != 0:
        print(log.read_text(encoding="utf-8")[-3000:], file=sys.stderr)
        print(f"mutmut failed (exit {run.returncode}); its log: {log}", file=sys.stderr)
        return 2
    _mutmut("export-cicd-stats")
    stats = json.loads((SCRATCH / "mutants" / "mutmut-cicd-stats.json").read_text("utf-8"))
    survivors = [
        line.strip().removesuffix(": survived")
        for line in _mutmut("results").stdout.splitlines()
        if line.strip().endswith(": survived")
    ]
    for name in survivors:
        print(f"  survived: {name}")
        if options.show:
            print(_mutmut("show", name).stdout)
    others = {k: v for k, v in stats.items() if k not in ("killed", "survived", "total") and v}
    if others:
        print(f"  also: {others}")
    killed, total = stats["killed"], stats["total"]
    score = 100.0 * killed / total if total else 100.0
    print(f"mutation score: {killed}/{total} = {score:.1f} %")
    return 1 if score < options.min_score else 0


if __name__ == "__main__":
    raise SystemExit(main())
