"""The ``roboscript`` command line.

Exit status: 0 the mission succeeded (or every checked file is valid); 1 the mission failed,
timed out, or the robot or link failed; 2 the input was invalid (mission, profile, world,
arguments); 130, 143 or 129 ended by Ctrl-C, SIGTERM or SIGHUP (the robot is stopped first).
Problems with input print as
``file:line:col: error: message``, anything else as one plain sentence; a traceback appears
only with ``--debug``.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import logging
import math
import os
import re
import sys
import tempfile
import zipfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from roboscript import __version__
from roboscript.errors import (
    EXAMPLES_FOLDER,
    CapabilityError,
    InputError,
    MissionError,
    RoboscriptError,
    did_you_mean,
    grouped,
    nearby_file,
)
from roboscript.interrupts import exit_status_for, raise_dropped, reason_for
from roboscript.interrupts import install as install_interrupts
from roboscript.watchdog import DEFAULT_LIMIT_S, RunawayCode, Watchdog, keep_program

if TYPE_CHECKING:
    from roboscript.mission.cause import TransitionCause

__all__ = ["main"]

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_INPUT = 2
EXIT_CLOSED_PIPE = 141  # 128 + SIGPIPE, what the shell reports for a tool whose reader left


def _err(text: str) -> None:
    print(text, file=sys.stderr)


def _print_problems(error: InputError) -> None:
    for line in grouped(getattr(error, "problems", None) or [error]):
        _err(line)


# ------------------------------------------------------------------------------------- run


def _refuse_a_folder(path: str) -> None:
    """A folder named where a mission file belongs (``roboscript run missions``): say so, with
    a mission in it to name instead."""
    folder = Path(path)
    if not folder.is_dir():
        return
    inside = sorted(folder.glob("*.yaml"))[:1] or sorted(folder.glob("*.py"))[:1]
    raise InputError(
        "this is a folder, not a mission file",
        path=path,
        hint=f"name a mission in it, e.g. {inside[0]}" if inside else "name a mission file",
    )


def _load_mission(path: str, robot: str | None, strict: bool = False) -> tuple[Any, Any]:
    _refuse_a_folder(path)
    # YAML loads only for the commands that read a file
    from roboscript.mission import mission_for_robot
    from roboscript.mission.student_code import is_student_file, stuck_at

    # A mission's file runs in this process: it may not take the watchdog's alarm, nor end
    # the program with no word, as a graded run may not (each is said at its line).
    keep_program()
    # a Python mission or behaviour file runs when imported: a loop there would hang `check`
    try:
        with Watchdog(DEFAULT_LIMIT_S, stuck_at, watched=is_student_file):
            spec, profile, warnings = mission_for_robot(path, robot)
    except RunawayCode as exc:  # the file's own top level loops: that file's mistake
        raise MissionError(
            f"the file did not finish loading in {exc.limit_s:g} s: a loop at its top level"
            " (outside any def) never ends",
            path=exc.file or path,
            line=exc.line,
            hint="a file only defines the mission when it loads; the robot is moved by the"
            " states' actions, and a condition is a method the mission asks",
        ) from None
    if strict and warnings:  # check --strict: each warning is an error
        # missions load only for the commands that read one
        from roboscript.mission.builder import MissionProblemsError

        raise MissionProblemsError(
            [type(w)(w.message, path=w.path, line=w.line, col=w.col, hint=w.hint) for w in warnings]
        )
    for line in grouped(warnings):
        _err(line)
    return spec, profile


def _check_regions(spec: Any, world: str | None) -> None:
    """Refuse ``in_region.NAME`` the world has no region for, before the robot moves."""
    # missions load only for the commands that read one
    from roboscript.mission.builder import MissionProblemsError
    from roboscript.mission.checks import check_world_regions

    problems = check_world_regions(spec, world)
    if problems:
        raise MissionProblemsError(problems)


def _cmd_run(args: argparse.Namespace) -> int:
    if args.quiet:
        # "print only the result": driver notices (warnings logged during the run) too
        logging.getLogger("roboscript").setLevel(logging.ERROR)
    if not args.json:
        return _run(args)
    # stdout carries one JSON document: whatever the mission prints goes to stderr instead
    with contextlib.redirect_stdout(sys.stderr):
        code, summary = _run_collect(args)
    print(json.dumps(summary, indent=2))
    return code


def _run(args: argparse.Namespace) -> int:
    return _run_collect(args)[0]


def _run_collect(args: argparse.Namespace) -> tuple[int, dict[str, Any]]:
    # the run machinery loads only for `run`
    from roboscript.session import run_session, session_record

    unwritable = _unwritable_run_output(args)
    if unwritable:  # said before the robot moves, not after the run is lost
        raise InputError(unwritable)
    if args.view_port and not args.view:
        raise InputError("--view-port is the live view's port: add --view to watch the run")
    for target in (args.record, args.plot, args.wire_log):
        if target:
            _make_parent_folders(target)
    recording = live = None
    if args.record or args.view:
        # recording and the replay page load only when a run is recorded or viewed
        from roboscript.replay.session_tap import RunRecording

        recording = RunRecording(path=args.record)  # written as the run goes
    # what a Python mission prints while it loads is recorded too, as before the start
    with recording.loading() if recording is not None else contextlib.nullcontext():
        spec, profile = _load_mission(args.mission, args.robot)
    world = args.world or spec.world or "empty"
    _check_regions(spec, world if args.port is None or args.port.startswith("sim:") else None)
    quiet = args.json or args.quiet
    if args.plot:
        # the simulator loads only for a simulated robot or a world
        from roboscript.sim.plot import require_matplotlib

        require_matplotlib()  # say so before the run, not after it

    # the run machinery loads only for `run`
    from roboscript.status import StatusLine, describe_robot

    status = StatusLine(sys.stderr, live=not quiet and sys.stderr.isatty())

    def on_state(time_s: float, name: str, cause: TransitionCause) -> None:
        if not quiet:
            status.state(time_s, name, None if cause.kind == "start" else cause.text())

    def show(runner: Any, robot: Any) -> None:
        feedback = getattr(runner.action, "feedback", "") or ""
        status.update(runner.elapsed(), runner.state, feedback, describe_robot(robot))

    def on_connected(robot: Any) -> None:
        if not quiet:
            _err(f"{spec.name} on {robot.describe()} ({robot.url})")

    if args.view:  # the page is served from its own thread; the ticks only hand it frames
        # recording and the replay page load only when a run is recorded or viewed
        from roboscript.replay.live import LiveView

        live = LiveView(spec.name, port=args.view_port)
        _err(f"live view: {live.start()} (open it in a web browser)")
        recording.listeners.append(live.publish)  # type: ignore[union-attr]

    session = run_session(
        spec,
        profile,
        port=args.port,
        world=world,
        seed=args.seed,
        realtime=args.realtime or args.view,  # a live view shows the run at its real pace
        wire_log=args.wire_log,
        max_time_s=args.max_time,
        on_state=on_state,
        on_connected=on_connected,
        on_tick=show if status.live else None,
        recording=recording,
        on_slow_tick=status.warn,
    )
    status.close()
    result = session.result
    interrupted = session.interrupted
    summary = session_record(session).to_dict()
    if not args.json:
        _say_how_it_ended(spec.name, session)
    outputs_ok = _write_run_outputs(args, session, recording)
    if live is not None:
        live.serve_the_end(_err, interrupted=bool(interrupted))
    if interrupted:
        return interrupted, summary
    ok = result.outcome == "success" and outputs_ok
    return (EXIT_OK if ok else EXIT_FAILED), summary


def _say_how_it_ended(mission: str, session: Any) -> None:
    """The result line of a run (and the signal that came after it ended, if one did)."""
    result = session.result
    if result.outcome == "success":
        _err(f"success: {mission} ended in '{result.final_state}' after {result.duration_s:.2f} s")
    else:
        _err(f"{result.outcome}: {result.reason}")
    ended_by = session.interruption
    if ended_by is not None and result.reason != ended_by.reason:  # the mission had ended
        _err(f"error: {ended_by.reason}")


def _write_run_outputs(args: argparse.Namespace, session: Any, recording: Any) -> bool:
    """Finish the files ``run`` was asked for once the robot has stopped (the plot, the wire
    log's last word, the recording); False (each problem said) if one of them failed."""
    outputs_ok = _write_plot(args.plot, session.result, session.simulation) if args.plot else True
    if session.wire_log_error is not None:  # said now: the robot is stopped
        _err(f"error: {session.wire_log_error}")
        outputs_ok = False
    if recording is not None and args.record:
        # recording and the replay page load only when a run is recorded or viewed
        from roboscript.replay.session_tap import save_recording

        problem = save_recording(recording, args.record)
        if problem:
            _err(problem)
        outputs_ok = outputs_ok and not problem
    return outputs_ok


def _write_plot(path: str, result: Any, sim: Any) -> bool:
    """Draw the simulated run into the PNG ``path`` (``run --plot``); False if it failed."""
    if sim is None:
        _err("error: --plot draws simulated runs only (this robot was reached on a port)")
        return False
    # the simulator loads only for a simulated robot or a world
    from roboscript.sim.plot import plot_run

    ended = f"{result.outcome} in '{result.final_state}'" if result.final_state else result.outcome
    title = f"{result.mission}: {ended} ({sim.world.name}, seed {sim.seed})"
    try:
        plot_run(sim.world, sim.log, title, path, body_radius_mm=sim.body.spec.body_radius_mm)
    except OSError as exc:
        _err(f"error: cannot write the plot {path}: {exc.strerror or exc}")
        return False
    return True


# ----------------------------------------------------------------------------------- check


def _cmd_check(args: argparse.Namespace) -> int:
    # missions load only for the commands that read one
    from roboscript.mission.python_loader import is_python_mission

    files: list[Path] = []
    missing = 0
    paths = list(args.paths)
    while paths:
        raw = paths.pop(0)
        path = Path(raw)
        spaced, words = ("", 0) if os.path.lexists(path) else _spaced_path_from(raw, paths)
        if spaced:  # `check my mission.yaml`: one path with spaces, typed without quotes
            hint = f'did you mean "{spaced}"? A path with spaces goes in quotes'
            _print_problems(InputError("there is no such file or folder", path=raw, hint=hint))
            del paths[:words]
            missing += 1
        elif not path.suffix and not os.path.lexists(path):  # a folder named from elsewhere
            missed = InputError("there is no such file or folder", path=raw, hint=nearby_file(path))
            _print_problems(missed)
            missing += 1
        elif path.is_dir():
            found = _files_in(path)
            files.extend(sorted(p for p in found if p.suffix == ".yaml"))
            # A folder also holds behaviours and helpers: only .py files with a Mission class.
            files.extend(sorted(p for p in found if p.suffix == ".py" and is_python_mission(p)))
        else:
            files.append(path)
    if not files and not missing:
        _err("nothing to check: no mission files found")
        return EXIT_INPUT
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.spec import load_test_spec
    from roboscript.inputs.kinds import file_kind
    from roboscript.profiles import get_profile
    from roboscript.sim.world import load_world

    if args.robot:  # a --robot that names no robot is one mistake, not one in every file
        get_profile(args.robot)

    bad = 0
    for path in files:
        try:
            kind = file_kind(path)  # each kind of file is checked by its own reader
            if kind == "test spec":
                spec_warnings = load_test_spec(path).warnings
                for line in spec_warnings:  # check --strict: each warning is an error
                    _err(line.replace(": warning: ", ": error: ", 1) if args.strict else line)
                bad += 1 if args.strict and spec_warnings else 0
            elif kind == "world":
                load_world(str(path))
            elif kind == "profile":
                get_profile(str(path))
            else:
                spec, _ = _load_mission(str(path), args.robot, args.strict)
                if spec.world:  # region names are known only when the mission names its world
                    _check_regions(spec, spec.world)
        except InputError as exc:
            _print_problems(exc)
            bad += 1
    checked = len(files) + missing
    bad += missing
    _err(f"checked {checked} file{'s' if checked != 1 else ''}: {bad} with errors")
    return EXIT_INPUT if bad else EXIT_OK


def _files_in(folder: Path) -> list[Path]:
    """The files under ``folder`` that ``check`` reads, found without going into hidden
    folders (``.git``, ``.venv``) or a Python environment (a folder holding ``pyvenv.cfg``):
    ``roboscript check .`` in a project folder checks the student's files, not the copies of
    roboscript's own examples and worlds installed there."""
    found: list[Path] = []
    for root, folders, names in os.walk(folder):
        folders[:] = [
            name
            for name in folders
            if not name.startswith(".") and not (Path(root) / name / "pyvenv.cfg").is_file()
        ]
        found.extend(Path(root) / name for name in names if (Path(root) / name).is_file())
    return found


# ----------------------------------------------------------------------------------- grade


def _cmd_grade(args: argparse.Namespace) -> int:
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.batch import SummariesOnly, find_specs, grade_class
    from roboscript.grading.pool import bounded_jobs

    try:
        jobs, too_many = bounded_jobs(args.jobs)
    except ValueError as exc:
        _err(f"error: {exc}")
        return EXIT_INPUT
    if too_many:
        _err(f"warning: {too_many}")
    args.jobs = jobs
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.shards import Shard

    try:
        shard = Shard.parse(args.shard) if args.shard else None
    except ValueError as exc:
        _err(f"error: {exc}")
        return EXIT_INPUT
    if shard is not None and (args.gradescope or args.prairielearn):
        _err("error: --shard splits a class, and a platform's results.json is one submission's")
        return EXIT_INPUT
    unwritable = _unwritable_report(args)
    if unwritable:  # said now, not after grading the whole class
        _err(f"error: {unwritable}")
        return EXIT_INPUT
    specs = find_specs(args.specs)  # a SpecError prints file:line:col and exits 2
    for spec in specs:
        for line in spec.warnings:  # legal, but likely a mistake: told before any run
            _err(line)
    everyone = _grade_submissions(args, specs)
    submissions = [s for s in everyone if shard is None or shard.holds(s.student)]
    overwrites = _overwritten_input(_report_targets(args), _grading_inputs(specs, everyone))
    if overwrites:  # said now: the teacher's tests and the students' work are never written
        _err(f"error: {overwrites}")
        return EXIT_INPUT
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.sandbox import detect_isolation
    from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S

    isolation = detect_isolation()
    if not isolation.complete:
        _err(f"warning: {isolation.warning}")
    quiet = args.json or args.quiet
    runs = sum(len(spec.variants) for spec in specs) * len(submissions)
    done = 0
    # A CI log is read by the student it graded: progress names a hidden run "hidden run N".
    labels = {(s.name, v.index): v.public_label for s in specs for v in s.variants}

    def progress(result: Any) -> None:
        nonlocal done
        done += 1
        if not quiet:
            mark = "ok" if result.passed else result.status
            label = labels.get((result.test, result.variant), result.label)
            _err(f"[{done}/{runs}] {result.student} {result.test} {label}: {mark}")

    with contextlib.ExitStack() as cleanup:
        store = _run_store(args, specs, submissions, shard, isolation.statement, cleanup)
        if store is False:
            return EXIT_INPUT
        store = store or SummariesOnly()  # no report draws a run: only summaries are kept
        try:
            report = grade_class(
                specs,
                submissions,
                args.jobs,
                progress,
                hang_after_s=args.hang_after or DEFAULT_HANG_AFTER_S,
                store=store,
            )
        except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM, SIGHUP: every jail is ended by now
            kept = ""
            written = getattr(store, "written", 0)  # whole lines: a signal waits for one
            if args.results and written:
                kept = (
                    f" (the {written} finished {'are' if written > 1 else 'is'} in {args.results})"
                )
            _err(f"error: {reason_for(exc)} after {done} of {runs} runs: no report written{kept}")
            return exit_status_for(exc)
        # while the results file is still there: the reports read each run in full from it
        return _report_class(args, report)


def _report_class(args: argparse.Namespace, report: Any) -> int:
    """Print the table (or --json) and write the reports asked for; the exit status."""
    if args.json:
        # grading (sandbox, reports, worlds) loads only for the grading commands
        from roboscript.grading.json_report import write_report_json

        write_report_json(report, sys.stdout)
    else:
        # grading (sandbox, reports, worlds) loads only for the grading commands
        from roboscript.grading.table import format_table

        print(format_table(report, sys.stdout.encoding))
    written = _write_grade_reports(args, report)
    if not written:
        return EXIT_FAILED
    faults = report.teachers_faults
    if faults is not None:  # last, where the teacher looks: the grades above are wrong
        _err(f"error: {faults}")
        return EXIT_INPUT
    return EXIT_OK if report.passed else EXIT_FAILED


def _cmd_gradebook(args: argparse.Namespace) -> int:
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.shards import read_results

    for part in args.parts:
        if Path(part).is_dir():
            _err(
                f"error: {part} is a folder: give the files `grade --results FILE` wrote"
                f" (e.g. {Path(part) / 'part-*.jsonl'})"
            )
            return EXIT_INPUT
    refused: list[str] = []
    report = read_results(args.parts, refused.append)
    inputs = _grading_inputs(report.specs, [])
    inputs.update(
        {Path(part).resolve(): (f"the results file {part}", False) for part in args.parts}
    )
    overwrites = _overwritten_input(_report_targets(args), inputs)
    if overwrites:
        _err(f"error: {overwrites}")
        return EXIT_INPUT
    for sentence in refused:
        _err(f"error: {sentence}")
    if args.gradescope and len(report.submissions) != 1:
        _err(
            f"error: a Gradescope results.json is one student's, but these results hold"
            f" {len(report.submissions)} students: use --csv, --html or --json for a class"
        )
        return EXIT_INPUT
    status = _report_class(args, report)
    # The others' reports are written; the exit status still says some runs were refused.
    return EXIT_INPUT if refused else status


def _run_store(
    args: argparse.Namespace,
    specs: Any,
    submissions: Any,
    shard: Any,
    isolation: str,
    cleanup: contextlib.ExitStack,
) -> Any:
    """Where ``grade`` keeps each run in full while the report holds its summary, so a class
    of any size is graded in the same memory: ``--results FILE``, or a temporary results file
    when a report draws runs (``--html``, ``--json``); None when no report needs runs in
    full; False (said) when the file cannot be written."""
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.shards import ResultsFile

    path = args.results
    if not path:
        if not (args.html or args.json):
            return None
        folder = cleanup.enter_context(tempfile.TemporaryDirectory(prefix="roboscript-grade-"))
        path = os.path.join(folder, "results.jsonl")
    _make_parent_folders(path)  # as every report's: `--results parts/part-1.jsonl` on a new day
    try:
        results = ResultsFile(path, specs, submissions, shard, isolation)
    except OSError as exc:
        _err(f"error: cannot write {path}: {exc.strerror or exc}")
        return False
    cleanup.callback(results.close)
    return results


def _grade_submissions(args: argparse.Namespace, specs: Any) -> Any:
    """The students to grade; with --gradescope or --prairielearn, everything found is one
    submission.

    When that is not one student's submission (no mission in it, or a class), the platform's
    ``results.json`` still tells the student why (every run failed), before the error exits 2.
    """
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.batch import find_submissions

    if not (args.gradescope or args.prairielearn):
        found = find_submissions(args.missions)
        for sentence in found.lookalikes:  # even with --quiet: a grade could go to the wrong one
            _err(f"warning: {sentence}")
        if not args.quiet:
            _note_not_graded(found.unclaimed)
        return found.submissions
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.gradescope import (
        no_submission_results,
        one_submission,
        several_students,
    )

    try:
        submissions = find_submissions(args.missions).submissions
        several = several_students(submissions, specs)
        if several:
            raise InputError(several)
    except InputError as exc:
        _write_platform_results(args, no_submission_results(specs, str(exc)))
        raise
    folders = [m for m in args.missions if Path(m).is_dir()]
    folder = folders[0] if len(args.missions) == 1 and folders else None
    name = Path(folder).resolve().name if folder else "submission"
    return [one_submission(submissions, name or "submission", folder)]


def _note_not_graded(names: Sequence[str]) -> None:
    """Say which entries of a class folder are no student's work (``ana.zip``, ``notes/``):
    a student who handed in the wrong thing is otherwise simply not in the table."""
    if names:
        _err(
            f"note: not graded, as no student's work: {_first_few(names)}"
            " (a student is a .yaml or .py mission, or a folder holding one)"
        )


_FEW_SHOWN = 10
"""Most names a one-line note lists before saying how many more there are."""


def _first_few(names: Sequence[str]) -> str:
    """``names`` joined for one line of a note: the first few, then ``and N more``."""
    more = len(names) - _FEW_SHOWN
    return ", ".join(names[:_FEW_SHOWN]) + (f" and {more} more" if more > 0 else "")


def _write_platform_results(args: argparse.Namespace, results: dict[str, Any]) -> None:
    """Write ready Gradescope-shaped results to --gradescope and --prairielearn."""
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.gradescope import write_gradescope
    from roboscript.grading.prairielearn import write_prairielearn

    for target, write in (
        (args.gradescope, write_gradescope),
        (args.prairielearn, write_prairielearn),
    ):
        if not target:
            continue
        try:
            write(results, target)
        except OSError as write_error:
            _err(f"error: cannot write {target}: {write_error.strerror or write_error}")


def _unwritable_report(args: argparse.Namespace) -> str:
    """Why a report asked for cannot be written where asked (one sentence), or ``""``.

    Checked before grading: a mistyped path must not cost the teacher a class's grading. A
    report's missing folders are made when it is written.
    """
    return _unwritable(_report_targets(args))


def _unwritable_run_output(args: argparse.Namespace) -> str:
    """Why a file ``run`` was asked to write cannot be written (one sentence), or ``""``.

    Checked before the robot moves: a run on a real robot cannot be run again as it was, so a
    mistyped ``--record`` path must not lose it. Missing folders are made when it is written.
    """
    outputs = [
        ("--record", args.record, False),
        ("--plot", args.plot, False),
        ("--wire-log", args.wire_log, False),
    ]
    return _overwritten_input(outputs, _read(("the mission", args.mission))) or _unwritable(outputs)


def _unwritable(targets: Sequence[tuple[str, str | None, bool]]) -> str:
    """Why one of ``(option, path or None, is a folder)`` cannot be written, or ``""``."""
    named: dict[Path, str] = {}
    for option, target, _ in targets:
        if target:
            other = named.setdefault(Path(target).resolve(), option)
            if other != option:
                return f"{other} and {option} both name {target}: one would overwrite the other"
    for _, target, is_folder in targets:
        if not target:
            continue
        path = Path(target)
        if path.exists() and path.is_dir() != is_folder:
            return f"cannot write {target}: it is {'a folder' if path.is_dir() else 'a file'}"
        existing = path.parent
        while not existing.exists() and existing != existing.parent:
            existing = existing.parent
        if not existing.is_dir():
            return f"cannot write {target}: {existing} is a file, not a folder"
        if not os.access(path if path.exists() else existing, os.W_OK):
            return f"cannot write {target}: {path if path.exists() else existing} is read-only"
    return ""


def _make_parent_folders(path: str | Path) -> None:
    """Make the missing folders above ``path`` (an output file), as the grade reports do."""
    with contextlib.suppress(OSError):  # the write that follows says what is wrong
        Path(path).parent.mkdir(parents=True, exist_ok=True)


def _report_targets(args: argparse.Namespace) -> list[tuple[str, str, bool]]:
    """``(option, path, is a folder)`` of every report file or folder asked for."""
    targets = [
        ("--junit", args.junit, False),
        ("--csv", args.csv, False),
        ("--html", args.html, True),
        ("--gradescope", args.gradescope, False),
        ("--prairielearn", getattr(args, "prairielearn", None), False),
        ("--results", getattr(args, "results", None), False),
    ]
    return [(option, path, folder) for option, path, folder in targets if path]


def _grading_inputs(
    specs: Sequence[Any], submissions: Sequence[Any]
) -> dict[Path, tuple[str, bool]]:
    """What grading reads, by resolved path: a name for a sentence, and whether it is a
    student's (the specs and the worlds they name are not; every student's files and folder
    are)."""
    inputs: dict[Path, tuple[str, bool]] = {}
    for spec in specs:
        inputs[Path(spec.path).resolve()] = (f"the test spec {spec.path}", False)
        for world in spec.worlds:
            if Path(world).is_file():
                inputs[Path(world).resolve()] = (f"the world {world} of {spec.name}", False)
    for submission in submissions:
        for file in submission.missions:
            inputs[Path(file).resolve()] = (f"{submission.student}'s mission", True)
        for file in submission.own:
            inputs[Path(file).resolve()] = (f"{submission.student}'s file", True)
        if submission.folder is not None:
            inputs[Path(submission.folder).resolve()] = (f"{submission.student}'s folder", True)
    return inputs


def _overwritten_input(
    outputs: Sequence[tuple[str, str | None, bool]], inputs: dict[Path, tuple[str, bool]]
) -> str:
    """Why one of the ``(option, path or None, is a folder)`` a command writes would overwrite
    or sit among what it reads (one sentence), or ``""``.

    ``inputs`` maps each resolved path read to a name for the sentence and whether it is a
    student's work. An output written over an input destroys it (a mistyped ``-o`` must never
    cost a student's mission or a recorded run); a report written in a student's folder is read
    by that student's next graded run; a report folder holding students' work would write its
    pages among them.
    """
    for option, target, is_folder in outputs:
        if not target:
            continue
        path = Path(target).resolve()
        for known, (what, students) in inputs.items():
            if path == known:
                return f"{option} {target} is {what}: writing it would destroy it"
            if students and known in path.parents:
                return f"{option} {target} is inside {what}: write reports outside it"
            if is_folder and students and path in known.parents:
                return f"{option} {target} holds {what}: write the report to a folder of its own"
    return ""


def _write_grade_reports(args: argparse.Namespace, report: Any) -> bool:
    """Write --junit, --csv, --html and --gradescope; False (after saying why) if one cannot be
    written. One that cannot be written does not keep the others from being written."""
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading.gradebook import write_gradebook
    from roboscript.grading.gradescope import write_gradescope
    from roboscript.grading.html_report import write_html
    from roboscript.grading.junit import write_junit
    from roboscript.grading.prairielearn import write_prairielearn

    writers = [
        (args.junit, write_junit),
        (args.csv, write_gradebook),
        (args.html, write_html),
        (args.gradescope, write_gradescope),
        (getattr(args, "prairielearn", None), write_prairielearn),
    ]
    written = True
    for target, write in writers:
        if not target:
            continue
        try:
            write(report, target)
        except OSError as exc:
            _err(f"error: cannot write {target}: {exc.strerror or exc}")
            written = False
    if not written:
        return False
    if args.html and not (args.json or args.quiet):
        _err(f"report: {Path(args.html) / 'index.html'} (for the teacher only)")
        _err(f"feedback pages to hand out: {Path(args.html) / 'students'}/ (one per student)")
    return True


# ------------------------------------------------------------------------------ autograder

_GITHUB_REPOSITORY = re.compile(r"[A-Za-z0-9](?:[A-Za-z0-9-]{0,38})/[A-Za-z0-9._-]{1,100}")
"""``OWNER/NAME`` as GitHub allows them (what the workflow's ``repository:`` takes)."""

_QUESTION_PART = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")
"""One folder of a PrairieLearn question's name (its QID may hold ``/``)."""


def _autograder_argument_problem(args: argparse.Namespace) -> str:
    """What is wrong with ``autograder``'s options (one sentence), or ``""``.

    Checked before anything is built: ``-o`` never replaces a file that is not an autograder
    zip (a teacher's test spec, say), ``--tests-repo`` is written into the students' workflow
    and ``--question`` into a path, so neither may carry anything but a name.
    """
    output = Path(args.output)
    if args.platform == "gradescope":
        if output.is_dir():
            return f"cannot write {args.output}: it is a folder (give the zip's name)"
        if output.suffix.lower() != ".zip":
            return f"the Gradescope autograder is a zip: name it so ({output.stem}.zip)"
        if output.exists() and not zipfile.is_zipfile(output):
            return f"{args.output} exists and is not a zip: give a new name"
        if output.resolve() in {Path(spec).resolve() for spec in args.specs}:
            return f"{args.output} is one of the tests: give a new name"
    if args.wheels and not Path(args.wheels).is_dir():
        return f"--wheels {args.wheels}: there is no such folder"
    if args.platform == "classroom" and not _GITHUB_REPOSITORY.fullmatch(args.tests_repo):
        return (
            f"--tests-repo must be a GitHub repository's OWNER/NAME, like"
            f" my-school/robotics-tests (got {args.tests_repo!r})"
        )
    if args.platform == "prairielearn" and args.question is not None:
        parts = args.question.split("/")
        if not all(_QUESTION_PART.fullmatch(part) for part in parts):
            return (
                "--question is a folder name under questions/ (letters, digits, '_', '-' and"
                f" '.', folders joined by '/'; got {args.question!r})"
            )
    return ""


def _cmd_autograder(args: argparse.Namespace) -> int:
    # grading (sandbox, reports, worlds) loads only for the grading commands
    from roboscript.grading import autograder
    from roboscript.grading.batch import find_specs
    from roboscript.grading.wheels import dependency_wheels

    problem = _autograder_argument_problem(args)
    if problem:
        _err(f"error: {problem}")
        return EXIT_INPUT
    specs = find_specs(args.specs)  # a broken spec is found here, not on the platform
    wheels = dependency_wheels(ready=Path(args.wheels) if args.wheels else None)
    try:
        if args.platform == "gradescope":
            Path(args.output).write_bytes(autograder.gradescope_zip(specs, wheels))
        elif args.platform == "classroom":
            files = autograder.classroom_files(specs, wheels, args.tests_repo)
            autograder.write_folder(files, args.output)
        else:
            question = args.question or autograder.default_question(specs)
            autograder.write_folder(
                autograder.prairielearn_files(specs, wheels, question), args.output
            )
    except OSError as exc:
        _err(f"error: cannot write {args.output}: {exc.strerror or exc}")
        return EXIT_FAILED
    for wheel in wheels:
        _err(f"  {wheel.filename}" + (f" ({wheel.note})" if wheel.note else ""))
    if args.platform == "classroom":
        for spec in specs:
            if any(variant.hidden for variant in spec.variants):
                _err(
                    f"warning: {spec.name} has hidden runs: on GitHub Classroom a student can"
                    " edit the workflow and print the private tests; use visible runs only"
                    " there, or Gradescope for hidden ones"
                )
    tests = ", ".join(spec.name for spec in specs)
    _err(f"{args.platform}: {args.output} ({tests}; {len(wheels)} wheels, no package index)")
    return EXIT_OK


# ----------------------------------------------------------------------------------- graph


_GRAPH_SUFFIXES = {".svg": "svg", ".png": "png", ".dot": "dot", ".gv": "dot"}


def _read(*named: tuple[str, str | None]) -> dict[Path, tuple[str, bool]]:
    """The ``(what, path or None)`` a command reads, as :func:`_overwritten_input` takes them:
    by resolved path, each named with its path, none of them a class folder's."""
    return {Path(path).resolve(): (f"{what} {path}", False) for what, path in named if path}


def _cmd_graph(args: argparse.Namespace) -> int:
    # missions load only for the commands that read one
    from roboscript.mission import load_mission
    from roboscript.mission.graph import to_dot, to_mermaid
    from roboscript.mission.graph_picture import RunMarks, require_matplotlib, to_svg, write_png

    suffix = Path(args.output).suffix.lower() if args.output else ""
    fmt = args.format or _GRAPH_SUFFIXES.get(suffix, "mermaid")
    if fmt == "png" and not args.output:
        _err("error: a PNG is written to a file: add -o FILE.png")
        return EXIT_INPUT
    if args.run and fmt not in ("svg", "png"):
        _err("error: --run highlights a run in a picture: add --format svg or --format png")
        return EXIT_INPUT
    outputs = [("-o", args.output, False)]
    problem = _overwritten_input(
        outputs, _read(("the mission", args.mission), ("the run", args.run))
    ) or _unwritable(outputs)
    if problem:  # said before the mission is read, as view and run say it
        _err(f"error: {problem}")
        return EXIT_INPUT
    if fmt == "png":
        require_matplotlib()  # say so before loading anything
    _refuse_a_folder(args.mission)
    if args.run:
        _refuse_a_non_recording(args.run)
    spec, _ = load_mission(args.mission)
    marks = None
    if args.run:
        # recording and the replay page load only when a run is recorded or viewed
        from roboscript.replay.recording import load_recording

        recording = load_recording(args.run)
        recorded = (recording.header.get("mission") or {}).get("name")
        if recorded != spec.name:
            _err(f"warning: {args.run} is a run of '{recorded}', not of '{spec.name}'")
        marks = RunMarks.from_frames(recording.frames, recording.result)
    if fmt == "png":
        try:
            write_png(spec, args.output, marks)
        except OSError as exc:
            _err(f"error: cannot write {args.output}: {exc.strerror or exc}")
            return EXIT_FAILED
        return EXIT_OK
    writers = {"svg": lambda: to_svg(spec, marks), "dot": lambda: to_dot(spec)}
    text = writers.get(fmt, lambda: to_mermaid(spec))()
    if not args.output:
        print(text, end="")
        return EXIT_OK
    try:
        Path(args.output).write_text(text, encoding="utf-8")
    except OSError as exc:
        _err(f"error: cannot write {args.output}: {exc.strerror or exc}")
        return EXIT_FAILED
    return EXIT_OK


# ------------------------------------------------------------------------------------ view


def _cmd_view(args: argparse.Namespace) -> int:
    # recording and the replay page load only when a run is recorded or viewed
    from roboscript.replay.viewer import view_recording

    outputs = [("-o", args.output, False), ("--csv", args.csv, False)]
    overwrite = _overwritten_input(outputs, _read(("the recording", args.recording)))
    overwrite = overwrite or _unwritable(outputs)
    if overwrite:
        _err(f"error: {overwrite}")
        return EXIT_INPUT
    _refuse_a_non_recording(args.recording)
    page, problem = view_recording(
        args.recording, args.output, open_page=args.open, csv_path=args.csv
    )
    if problem:
        _err(problem)
        return EXIT_FAILED
    _err(f"replay: {page}")
    return EXIT_OK


def _as_typed(path: str) -> str:
    """``path`` as it is typed in a command to copy: in quotes when it holds a space."""
    return f'"{path}"' if " " in path else path


def _refuse_a_non_recording(path: str) -> None:
    """A folder, or the summary ``run --json`` prints, named where a recording belongs: say
    what it is and how a run is recorded."""
    record = "a recorded run is the file `roboscript run MISSION --record RUN.jsonl` writes"
    if Path(path).is_dir():
        raise InputError("this is a folder, not a recorded run", path=path, hint=record)
    if Path(path).suffix.lower() in _MISSION_SUFFIXES and Path(path).is_file():
        # `view square.yaml`: the mission named where its run belongs
        # files are told apart only for the commands that read one
        from roboscript.inputs.kinds import file_kind, not_the_kind_expected

        kind = file_kind(path)
        raise InputError(
            not_the_kind_expected(kind, "a recorded run"),
            path=path,
            hint=record.replace("MISSION", _as_typed(path)) if kind == "mission" else record,
        )
    # A recording is one JSON object a line; `run --json > run.json` writes one over many
    # lines, beginning with a line of its own `{`.
    with contextlib.suppress(OSError, UnicodeDecodeError), open(path, encoding="utf-8") as file:
        if file.readline(16).strip() == "{":
            raise InputError(
                "this is a run's summary, as `roboscript run --json` prints it, not a recorded run",
                path=path,
                hint=record,
            )


_MISSION_SUFFIXES = (".yaml", ".yml", ".py")
"""How the files roboscript reads other than recordings end (missions, worlds, profiles,
specs): never a recorded run."""


# ------------------------------------------------------------------------------------- sim


def _cmd_sim(args: argparse.Namespace) -> int:
    # the simulator loads only for a simulated robot or a world
    from roboscript.sim.server import SimServer, parse_host_port
    from roboscript.sim.simulation import make_simulation

    address: tuple[str, int] | None = None
    if not args.pty:
        try:
            address = parse_host_port(args.tcp)
        except ValueError as exc:
            _err(f"error: --tcp {exc}")
            return EXIT_INPUT
    options = {"reset_on_connect": True} if args.reset_on_connect else None
    simulation = make_simulation(args.robot, args.world, args.seed, options=options)

    def announce(line: str) -> None:
        print(line, flush=True)

    try:
        server = SimServer(simulation, announce, handshake_wait_s=args.handshake_wait)
    except ValueError as exc:
        _err(f"error: --handshake-wait: {exc}")
        return EXIT_INPUT
    try:
        if address is None:
            server.serve_pty(max_runtime_s=args.max_runtime)
        else:
            server.serve_tcp(*address, max_runtime_s=args.max_runtime)
    except KeyboardInterrupt:  # the way a server is meant to be stopped: not an error
        _err("stopped")
    except OSError as exc:
        _err(f"error: cannot serve the simulator: {exc.strerror or exc}")
        return EXIT_FAILED
    return EXIT_OK


# ----------------------------------------------------------------------------------- ports


def _cmd_ports(args: argparse.Namespace) -> int:
    # pyserial's port listing and the robots' USB boards load only for `ports`
    from roboscript.drivers import usb_hints
    from roboscript.transport.discovery import list_robot_ports

    ports = list_robot_ports(usb_hints())
    if not ports:
        _err("no serial ports found (is the robot plugged in and switched on?)")
        return EXIT_OK
    for info in ports:
        usb = f"[{info.usb_id}]" if info.usb_id else ""
        line = f"{info.device:<16} {usb:<11} {info.description}"
        print(line.rstrip())
        if info.hint:
            print(f"{'':<16} probably: {info.hint}")
    return EXIT_OK


# ---------------------------------------------------------------------------------- robots


def _cmd_web(args: argparse.Namespace) -> int:
    # loaded here: building the app reads packages no other command needs
    from roboscript.web.build import WebBuildError, build_web_app

    try:  # a spec's SpecError prints file:line:col and exits 2
        built = build_web_app(
            args.dir, pyodide=args.pyodide, codemirror=args.codemirror, specs=args.spec or ()
        )
    except WebBuildError as exc:
        _err(f"error: {exc}")
        return EXIT_FAILED
    if not built.compiled:
        _err(
            "note: node is not installed, so the page compiles roboscript's Python each time"
            " it opens (some seconds slower to start); install node.js and build again"
        )
    for test in built.hidden_tests:
        _err(
            f"warning: {test} has hidden runs: the page carries the spec, so a student who"
            " reads the page's files can see them; ship a practice spec without hidden runs"
        )
    _err(
        f"web app: {built.page} ({built.size_bytes / 1e6:.1f} MB; open it in a web browser, "
        "or copy the folder anywhere: it needs no network)"
    )
    return EXIT_OK


def _cmd_robots(args: argparse.Namespace) -> int:
    # the robots load only for the commands that name one
    from roboscript.profiles import BUILTIN_PROFILES

    width = max(len(name) for name in BUILTIN_PROFILES) + 2
    for profile in BUILTIN_PROFILES.values():
        caps = ", ".join(sorted(profile.capabilities))
        print(
            f"{profile.name:<{width}}{profile.protocol:<10}{profile.control:<14}{profile.description}"
        )
        print(f"{'':<{width}}capabilities: {caps}")
    return EXIT_OK


# -------------------------------------------------------------------------------- examples


def _examples_source() -> Path | None:
    """The example missions this installation carries, or ``None``.

    A wheel carries them as ``roboscript/examples/`` (setup.py copies ``missions/`` there); an
    editable install reads ``missions/`` beside the package, in the source folder.
    """
    package = Path(__file__).resolve().parent
    for folder in (package / "examples", package.parent / EXAMPLES_FOLDER):
        if (folder / "square.yaml").is_file():
            return folder
    return None


def _cmd_examples(args: argparse.Namespace) -> int:
    source = _examples_source()
    if source is None:
        _err("error: this installation of roboscript has no example missions: install it again")
        return EXIT_FAILED
    target = Path(args.dir)
    unwritable = _unwritable([("DIR", args.dir, True)])
    if unwritable:
        _err(f"error: {unwritable}")
        return EXIT_INPUT
    if target.resolve() == source.resolve():
        _err(f"{args.dir} holds the examples already (it is where they come from)")
        return EXIT_OK
    written: list[Path] = []
    kept: list[Path] = []
    for file in sorted(source.rglob("*")):
        if not file.is_file() or "__pycache__" in file.parts or file.suffix in {".pyc", ".pyo"}:
            continue
        destination = target / file.relative_to(source)
        data = file.read_bytes()
        if destination.exists():
            if not (destination.is_file() and destination.read_bytes() == data):
                kept.append(destination)  # a student's own edit is never written over
            continue
        try:
            destination.parent.mkdir(parents=True, exist_ok=True)
            # the bytes, not a copy of the file: an installed file may be read-only, and a
            # student edits these
            destination.write_bytes(data)
        except OSError as exc:
            _err(f"error: cannot write {destination}: {exc.strerror or exc}")
            return EXIT_FAILED
        written.append(destination)
    if kept:
        _err(
            f"kept your own {_first_few([str(path) for path in kept])}"
            " (not the example's text: rename yours to get the example too)"
        )
    if written:
        square = _as_typed(str(target / "square.yaml"))
        _err(
            f"wrote {len(written)} example file{'s' if len(written) != 1 else ''} into"
            f" {args.dir}: try roboscript run {square}"
        )
    elif not kept:
        _err(f"{args.dir} holds the examples already: nothing to write")
    return EXIT_OK


# ------------------------------------------------------------------------------------ main


def _seconds(option: str, example: str, most_s: float = math.inf) -> Callable[[str], float]:
    """An argparse type for ``option``: a time in seconds (``60``, or ``60s`` as a mission
    writes it), greater than 0 and at most ``most_s``; a mistake is answered with ``option
    example`` to copy."""

    def parse(text: str) -> float:
        number = text.strip()
        for unit in ("sec", "s"):  # 60s, 60 s, 60 sec
            if number.endswith(unit):
                number = number.removesuffix(unit).rstrip()
                break
        try:
            value = float(number)
            if math.isinf(value):  # a limit that never comes: a run or a wait without end
                raise ValueError(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"'{text}' is not a number of seconds"
                f" (write it in seconds, e.g. {option} {example})"
            ) from None
        if not value > 0:  # also refuses nan
            raise argparse.ArgumentTypeError(f"a time limit must be more than 0 s (got {text})")
        if value > most_s:
            raise argparse.ArgumentTypeError(
                f"{option} is at most {most_s:g} s (got {text})"
                f" (write it in seconds, e.g. {option} {example})"
            )
        return value

    parse.__name__ = "seconds"
    return parse


HANG_AFTER_MOST_S = 3600.0
"""The longest ``--hang-after``: one tick's code running an hour is hung by any measure (and
a timer of an infinite time cannot be set: every run would crash)."""


def _whole_number(
    option: str, example: str, low: int | None = None, high: int | None = None
) -> Callable[[str], int]:
    """An argparse type for ``option``: a whole number from ``low`` to ``high`` (where given);
    a mistake is answered with ``option example`` to copy, not with Python's type name."""

    def parse(text: str) -> int:
        try:
            value = int(text.strip())
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"'{text}' is not a whole number (write it in digits, e.g. {option} {example})"
            ) from None
        if (low is not None and value < low) or (high is not None and value > high):
            raise argparse.ArgumentTypeError(
                f"{value} is out of range: give {low} to {high} (e.g. {option} {example})"
            )
        return value

    parse.__name__ = "whole number"
    return parse


def _add_class_reports(command: argparse.ArgumentParser) -> None:
    """The class reports ``grade`` and ``gradebook`` both write (see _report_class)."""
    command.add_argument("--json", action="store_true", help="print one JSON report on stdout")
    command.add_argument("--junit", metavar="FILE", help="write JUnit XML (one case per run)")
    command.add_argument(
        "--csv", metavar="FILE", help="write a gradebook CSV (one row per student)"
    )
    command.add_argument(
        "--html",
        metavar="DIR",
        help="write HTML: the teacher's DIR/index.html and a page per student in DIR/students/",
    )


class _Parser(argparse.ArgumentParser):
    """argparse's parser, answering a mistyped command or choice with the one meant.

    A subcommand's parser is made by its parent as the same class (argparse's default).
    """

    _given: Sequence[str] = ()

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        self._given = list(sys.argv[1:] if args is None else args)  # for error() to read
        return super().parse_known_args(args, namespace)

    def error(self, message: str) -> NoReturn:
        missing = message.removeprefix("the following arguments are required: ")
        for action in self._actions:
            # `grade --mission class/ test.yaml`: the option took the spec for a mission
            taken = set(action.option_strings) & set(self._given)
            if taken and action.nargs == "+" and missing != message and "-" not in missing[:1]:
                option = min(taken)
                message += (
                    f" (after {option}, every word is read as a {action.metavar}: write"
                    f" {missing.split(',')[0]} before {option})"
                )
                break
        super().error(message)

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        choices = action.choices
        if choices is None or value in choices:
            return
        names = ", ".join(str(choice) for choice in choices)
        hint = did_you_mean(str(value), [str(choice) for choice in choices], cutoff=0.6)
        if isinstance(action, argparse._SubParsersAction):
            what = f"'{value}' is not a {self.prog} command"
            if hint is None and Path(str(value)).suffix.lower() in {".yaml", ".yml", ".py"}:
                hint = f"to run a mission: {self.prog} run {value}"  # the command left out
            hint = hint or f"the commands: {names}"
        else:
            what = f"'{value}' is not one of {names}"
        raise argparse.ArgumentError(None, f"{what} ({hint})" if hint else what)


def _extra_arguments(
    parser: argparse.ArgumentParser, args: argparse.Namespace, extras: Sequence[str]
) -> str:
    """What to say of the arguments ``parser`` (the command's) did not take: one sentence."""
    options = [extra for extra in extras if extra.startswith("-") and len(extra) > 1]
    if options:
        written = options[0].split("=", 1)[0]
        known = [
            name
            for action in parser._actions
            if action.help != argparse.SUPPRESS
            for name in action.option_strings
            if name.startswith("--")
        ]
        hint = did_you_mean(written, known, cutoff=0.6)
        return f"unknown option {written}" + (
            f" ({hint})" if hint else f" (see {parser.prog} --help)"
        )
    joined = _spaced_path(args, extras)
    if joined:
        return (
            f"one argument too many: '{extras[0]}' (did you mean \"{joined}\"? A path with"
            " spaces goes in quotes)"
        )
    return (
        f"'{extras[0]}' is one argument too many for {parser.prog} (a path with spaces goes in"
        ' quotes: "my mission.yaml")'
    )


def _empty_argument(parser: argparse.ArgumentParser, args: argparse.Namespace) -> str:
    """What to say of an argument given as an empty text (``roboscript check "$FILE"`` with
    ``FILE`` unset), or ``""``: an empty path would otherwise name the current folder, and an
    empty option would be taken as not given."""
    for action in parser._actions:
        value = getattr(args, action.dest, None)
        values = value if isinstance(value, list) else [value]
        if any(isinstance(given, str) and not given.strip() for given in values):
            name = "/".join(action.option_strings) or action.metavar or action.dest
            return (
                f'argument {name} is empty (a variable that is not set, as in "$FILE", gives'
                " an empty argument)"
            )
    return ""


def _spaced_path(args: argparse.Namespace, extras: Sequence[str]) -> str:
    """The existing path that an argument and the extra words after it make when joined with
    spaces (a path with spaces typed without quotes), or ``""``."""
    for value in vars(args).values():
        for word in value if isinstance(value, list) else [value]:
            joined = _spaced_path_from(word, extras)[0] if isinstance(word, str) else ""
            if joined:
                return joined
    return ""


def _spaced_path_from(first: str, following: Sequence[str]) -> tuple[str, int]:
    """The longest existing path ``first`` and the words after it make, joined with spaces
    (``my`` and ``mission.yaml``: ``my mission.yaml``), and how many words after it that
    takes; ``("", 0)`` if none."""
    for end in range(len(following), 0, -1):
        joined = " ".join([first, *following[:end]])
        if os.path.exists(joined):
            return joined, end
    return "", 0


def _parser() -> argparse.ArgumentParser:
    """The command line: every command with its options, each command also taking the global
    ``--debug`` after its name."""
    parser = _Parser(
        prog="roboscript",
        description="Run state-machine missions on educational robots and their simulator.",
    )
    parser.add_argument("--version", action="version", version=f"roboscript {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logs")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    _add_run(sub)
    _add_view(sub)
    _add_check(sub)
    _add_grade(sub)
    _add_gradebook(sub)
    _add_autograder(sub)
    _add_graph(sub)
    _add_sim(sub)
    _add_listings(sub)
    web_sub = _add_web(sub)
    _add_examples(sub)
    for command in [*sub.choices.values(), *web_sub.choices.values()]:
        # which parser says what was not understood: the innermost command's
        command.set_defaults(command_parser=command)
        # Global options are accepted after the command too (`roboscript run m.yaml --debug`);
        # SUPPRESS keeps a command not given --debug from resetting the global one.
        command.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS
        )
    return parser


def _add_run(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``run MISSION``: its robot, port, world and seed, its limits and what it writes."""
    run = sub.add_parser("run", help="run a mission (on the built-in simulator by default)")
    run.add_argument("mission", metavar="MISSION", help="mission file (.yaml or .py)")
    run.add_argument(
        "--robot", help="robot profile name or file (default: the mission's robot, or mirto)"
    )
    run.add_argument(
        "--port", metavar="URL", help="serial port or URL (default: the in-process simulator)"
    )
    run.add_argument(
        "--world", help="simulator world name or file (default: the mission's world, or empty)"
    )
    run.add_argument(
        "--seed",
        type=_whole_number("--seed", "7"),
        default=1,
        metavar="N",
        help="simulator seed (default: 1)",
    )
    run.add_argument("--realtime", action="store_true", help="pace the simulator to the wall clock")
    run.add_argument(
        "--max-time",
        type=_seconds("--max-time", "60"),
        default=300.0,
        metavar="SECONDS",
        help="mission time limit",
    )
    run.add_argument("--json", action="store_true", help="print one JSON summary on stdout")
    run.add_argument("--wire-log", metavar="FILE", help="record every byte on the wire")
    run.add_argument(
        "--plot", metavar="FILE", help="draw the simulated run as a PNG (needs matplotlib)"
    )
    run.add_argument(
        "--record", metavar="RUN.jsonl", help="record the run tick by tick (JSON Lines; see `view`)"
    )
    run.add_argument(
        "--view", action="store_true", help="watch the run live in a web browser (this computer)"
    )
    run.add_argument(
        "--view-port",
        type=_whole_number("--view-port", "8765", 0, 65535),
        default=0,
        metavar="N",
        help="the live view's port (default: any)",
    )
    run.add_argument("--quiet", action="store_true", help="print only the result")
    run.set_defaults(func=_cmd_run)


def _add_view(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``view RUN.jsonl``: the replay page of a recorded run."""
    view = sub.add_parser("view", help="write a recorded run's replay as one HTML page")
    view.add_argument("recording", metavar="RUN.jsonl", help="a file written by `run --record`")
    view.add_argument(
        "-o", "--output", metavar="PAGE.html", help="the page (default: beside the recording)"
    )
    view.add_argument("--open", action="store_true", help="open the page in a web browser")
    view.add_argument(
        "--csv", metavar="FILE", help="also write the run tick by tick as columns (CSV)"
    )
    view.set_defaults(func=_cmd_view)


def _add_check(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``check PATH...``: missions, worlds, profiles and specs checked without a robot."""
    check = sub.add_parser("check", help="check mission files without a robot")
    check.add_argument("paths", nargs="+", metavar="PATH", help="files or folders")
    check.add_argument("--robot", help="also check against this robot's capabilities")
    check.add_argument(
        "--strict", action="store_true", help="treat each warning (a bare number...) as an error"
    )
    check.set_defaults(func=_cmd_check)


def _add_grade(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``grade TEST_SPEC... --mission MISSION...``: a class graded, and its reports."""
    grade = sub.add_parser(
        "grade", help="grade students' missions against teacher test specs on the simulator"
    )
    grade.add_argument(
        "specs", nargs="+", metavar="TEST_SPEC", help="test spec files or folders of them"
    )
    grade.add_argument(
        "--mission",
        dest="missions",
        action="extend",
        nargs="+",
        required=True,
        metavar="MISSION",
        help="mission files, globs or folders of submissions (one student per file or folder)",
    )
    _add_class_reports(grade)
    grade.add_argument(
        "--gradescope",
        metavar="FILE",
        help="write Gradescope's results.json (everything under --mission is one submission)",
    )
    grade.add_argument(
        "--prairielearn",
        metavar="FILE",
        help="write PrairieLearn's results.json (everything under --mission is one submission)",
    )
    grade.add_argument(
        "--jobs",
        type=_whole_number("--jobs", "2"),
        metavar="N",
        help="runs at once (default and most: one per CPU core)",
    )
    grade.add_argument(
        "--results",
        metavar="FILE",
        help="write each run's result as one JSON line the moment it finishes",
    )
    grade.add_argument(
        "--hang-after",
        type=_seconds("--hang-after", "2", HANG_AFTER_MOST_S),
        metavar="SECONDS",
        help=(
            "end a run as hung when its code does not return for this many seconds of its"
            " own time (default: 2)"
        ),
    )
    grade.add_argument(
        "--shard",
        metavar="I/N",
        help="grade only part I of N of the class (by a hash of each student's name)",
    )
    grade.add_argument("--quiet", action="store_true", help="print only the table")
    grade.set_defaults(func=_cmd_grade)


def _add_gradebook(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``gradebook RESULTS.jsonl...``: the shards' results merged into one class's reports."""
    gradebook = sub.add_parser(
        "gradebook",
        help="merge results files (grade --shard I/N --results FILE) into one class's reports",
    )
    gradebook.add_argument(
        "parts", nargs="+", metavar="RESULTS.jsonl", help="the results files of every part"
    )
    _add_class_reports(gradebook)
    gradebook.add_argument(
        "--gradescope", metavar="FILE", help="write Gradescope's results.json (one student only)"
    )
    gradebook.add_argument("--quiet", action="store_true", help="print only the table")
    gradebook.set_defaults(func=_cmd_gradebook)


def _add_autograder(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``autograder PLATFORM TEST_SPEC... -o OUT``: a ready LMS package."""
    autograder = sub.add_parser(
        "autograder",
        help="build a ready-to-upload autograder for Gradescope, GitHub Classroom or PrairieLearn",
    )
    autograder.add_argument("platform", choices=("gradescope", "classroom", "prairielearn"))
    autograder.add_argument(
        "specs", nargs="+", metavar="TEST_SPEC", help="test spec files or folders of them"
    )
    autograder.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="OUT",
        help="the zip (gradescope) or a new folder (classroom, prairielearn)",
    )
    autograder.add_argument(
        "--wheels", metavar="DIR", help="take a dependency's wheel from DIR when it has one"
    )
    autograder.add_argument(
        "--tests-repo",
        default="my-school/robotics-tests",
        metavar="OWNER/NAME",
        help="classroom: your private repository for the tests (default: my-school/robotics-tests)",
    )
    autograder.add_argument(
        "--question", metavar="NAME", help="prairielearn: the question's folder name"
    )
    autograder.set_defaults(func=_cmd_autograder)


def _add_graph(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``graph MISSION``: a mission's state diagram."""
    graph = sub.add_parser(
        "graph", help="draw a mission's state diagram (mermaid, dot, or an SVG or PNG picture)"
    )
    graph.add_argument("mission", metavar="MISSION", help="mission file")
    graph.add_argument(
        "--format",
        choices=("mermaid", "dot", "svg", "png"),
        help="default: from -o's suffix (.svg, .png, .dot), else mermaid",
    )
    graph.add_argument("-o", "--output", metavar="FILE", help="write to FILE, not stdout")
    graph.add_argument(
        "--run", metavar="RUN.jsonl", help="highlight the states a recorded run visited"
    )
    graph.set_defaults(func=_cmd_graph)


def _add_sim(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``sim``: a simulated robot's bytes served on TCP or a pty."""
    sim = sub.add_parser(
        "sim", help="serve a simulated robot's protocol bytes on a TCP port or a pty"
    )
    sim.add_argument("--robot", default="mirto", help="robot profile name or file (default: mirto)")
    sim.add_argument("--world", default="empty", help="simulator world name or file")
    sim.add_argument(
        "--seed",
        type=_whole_number("--seed", "7"),
        default=1,
        metavar="N",
        help="simulator seed (default: 1)",
    )
    where = sim.add_mutually_exclusive_group(required=True)
    where.add_argument(
        "--tcp", metavar="HOST:PORT", help="listen on this TCP address (port 0: any)"
    )
    where.add_argument("--pty", action="store_true", help="open a pseudo-terminal; print its path")
    sim.add_argument(
        "--reset-on-connect",
        action="store_true",
        help="the board resets when a client opens it (an Arduino Uno's DTR line) and answers"
        " once its sketch has started again (ASIP: about 3.2 s)",
    )
    sim.add_argument(
        "--handshake-wait",
        type=_seconds("--handshake-wait", "5"),
        default=5.0,
        metavar="SECONDS",
        help="when another TCP client connects, give it the robot if the one that has it sent"
        " nothing this long after connecting, or stopped this long in the middle of a message"
        " (default: 5; a quiet client is never dropped while nobody else wants the robot)",
    )
    # how long a test's server serves before it ends by itself: a time as --max-time is
    sim.add_argument(
        "--max-runtime",
        type=_seconds("--max-runtime", "5"),
        metavar="SECONDS",
        help=argparse.SUPPRESS,
    )
    sim.set_defaults(func=_cmd_sim)


def _add_listings(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``ports`` and ``robots``: what this computer and roboscript have."""
    ports = sub.add_parser("ports", help="list serial ports with a hint of which robot each is")
    ports.set_defaults(func=_cmd_ports)

    robots = sub.add_parser("robots", help="list the built-in robot profiles")
    robots.set_defaults(func=_cmd_robots)


def _add_web(
    sub: argparse._SubParsersAction[_Parser],
) -> argparse._SubParsersAction[_Parser]:
    """``web build DIR``: the browser app. Returns ``web``'s own commands, which take the
    global options too."""
    web = sub.add_parser("web", help="the browser app (zero install)")
    web_sub = web.add_subparsers(dest="web_command", required=True, metavar="COMMAND")
    web_build = web_sub.add_parser(
        "build", help="write the offline browser app into a folder (open its index.html)"
    )
    web_build.add_argument("dir", metavar="DIR", help="the folder to write")
    web_build.add_argument(
        "--pyodide", metavar="DIR", help="an unpacked npm 'pyodide' package (default: npm)"
    )
    web_build.add_argument(
        "--codemirror", metavar="DIR", help="an unpacked npm 'codemirror' 5 package"
    )
    web_build.add_argument(
        "--spec",
        metavar="SPEC",
        nargs="+",
        action="extend",
        help="test specs (or folders of them) to practise against in the page",
    )
    web_build.set_defaults(func=_cmd_web)
    return web_sub


def _add_examples(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``examples [DIR]``: the guides' missions written into a folder."""
    examples = sub.add_parser(
        "examples", help="write the example missions the guides run into a folder"
    )
    examples.add_argument(
        "dir",
        nargs="?",
        default=EXAMPLES_FOLDER,
        metavar="DIR",
        help=f"the folder (default: {EXAMPLES_FOLDER}); files already there are kept",
    )
    examples.set_defaults(func=_cmd_examples)


def main(argv: Sequence[str] | None = None) -> NoReturn:
    """Run the command line and exit with its status."""
    # Ctrl-C, SIGTERM and SIGHUP all stop the robot on the way out; a second one while
    # stopping must still end the program. Installed before anything else is done, so a
    # signal while the arguments are read ends the same way (roboscript.__main__ installs
    # them earlier still, before this module loads).
    install_interrupts()
    try:
        parser = _parser()
        given = sys.argv[1:] if argv is None else list(argv)
        if not given:  # `roboscript` alone: what it can do, rather than what is missing
            parser.print_help(sys.stderr)
            sys.exit(EXIT_INPUT)
        args, extras = parser.parse_known_args(given)
        command = getattr(args, "command_parser", parser)
        if extras:
            command.error(_extra_arguments(command, args, extras))
        empty = _empty_argument(command, args)
        if empty:
            command.error(empty)
    except KeyboardInterrupt as exc:
        _err(f"error: {reason_for(exc)}")
        sys.exit(exit_status_for(exc))
    try:
        logging.basicConfig(
            level=logging.DEBUG if args.debug else logging.WARNING,
            format="roboscript: %(message)s",
        )
        code = args.func(args)
        # A signal that landed in a finalizer, where Python can only drop it, ends the program
        # as any other (a run raises it at once; this is for the rest of the program's time).
        raise_dropped()
    except InputError as exc:
        if args.debug:
            raise
        _print_problems(exc)
        code = EXIT_INPUT
    except CapabilityError as exc:
        if args.debug:
            raise
        _err(f"error: {exc}")
        code = EXIT_INPUT
    except (RoboscriptError, NotImplementedError) as exc:
        if args.debug:
            raise
        _err(f"error: {exc}")
        code = EXIT_FAILED
    except KeyboardInterrupt as exc:
        _err(f"error: {reason_for(exc)}")  # as a run in progress says it
        code = exit_status_for(exc)
    except RunawayCode as exc:  # a mission file stuck while loading (a run handles its own)
        if args.debug:
            raise
        _err(f"error: {exc.reason}")
        code = EXIT_FAILED
    except BrokenPipeError:
        code = _closed_pipe()
    except OSError as exc:
        if args.debug or exc.errno not in _DISK_FULL:
            raise
        code = _output_failed(exc)
    try:
        sys.stdout.flush()  # a closed pipe shows here when the output was still buffered
    except BrokenPipeError:
        code = _closed_pipe()
    except OSError as exc:
        if exc.errno not in _DISK_FULL:
            raise
        code = _output_failed(exc)
    sys.exit(code)


_DISK_FULL = frozenset({errno.ENOSPC, errno.EFBIG, errno.EDQUOT})
"""Write errors of a full disk or a file-size limit: the output could not be written."""


def _output_failed(exc: OSError) -> int:
    """Our output (``--json`` to a file, a table) could not be written: say so in one line.

    Output is printed once the robot has stopped, so it is stopped by now.
    """
    what = exc.filename or "the output"
    _err(f"error: cannot write {what}: {exc.strerror or exc}")
    _stdout_to_nowhere()
    return EXIT_FAILED


def _closed_pipe() -> int:
    """The reader of our output went away (``| head``): end quietly, as a C tool would."""
    _stdout_to_nowhere()
    return EXIT_CLOSED_PIPE


def _stdout_to_nowhere() -> None:
    """Point standard output at the null device once it can no longer be written: Python
    flushes it again at exit and would report the same failure a second time."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)
