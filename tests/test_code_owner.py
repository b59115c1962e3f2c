"""Whose code is this: the one rule, on the cases each of its former copies handled.

The watchdog watches only a student's code, errors are told at the student's line, a student's
action has its ``update`` checked and a built-in action's own checks are told as a mission's
check tells them: each asks :mod:`roboscript.code_owner`, so each case is pinned here once.
"""

from __future__ import annotations

import importlib
import io
import os
import runpy
import shutil
import subprocess
import sys
import sysconfig
import textwrap
import zipfile
from pathlib import Path

import pytest
import simple_pid
import transitions
import yaml
from helpers import HANG_BOUND_S

import roboscript.actions.base
from roboscript import code_owner
from roboscript.actions.base import Action, Result, UpdateReturnError
from roboscript.code_owner import (
    LIBRARY,
    PACKAGE_DIR,
    ROBOSCRIPT,
    STUDENT,
    is_roboscript_module,
    is_student_class,
    is_student_file,
    owner_of_file,
    raised_by_roboscript,
)
from roboscript.inputs.quantities import parse_quantity
from roboscript.mission.student_code import import_student_file
from roboscript.web.bytecode import compile_zip

SPIN = """\
from roboscript import Action, Result


class Spin(Action):
    name = "spin"

    def update(self, ctx):
        return True
"""
"""A student's action whose ``update`` forgets to return a :class:`Result`."""


def _update_is_checked(cls: type[Action]) -> bool:
    """True if ``cls``'s ``update`` returning ``True`` is answered with what to return."""
    action = cls.__new__(cls)
    try:
        action.update(None)  # type: ignore[arg-type]
    except UpdateReturnError:
        return True
    return False


# ------------------------------------------------------------------ roboscript's own code


def test_roboscripts_own_files_and_classes_are_roboscripts() -> None:
    for module in (code_owner, roboscript.actions.base, roboscript):
        assert owner_of_file(str(module.__file__)) == ROBOSCRIPT
        assert not is_student_file(str(module.__file__))
    assert not is_student_class(Action)
    assert not is_student_class(type("Shim", (), {"__module__": "roboscript"}))


def test_a_file_put_in_roboscripts_folder_is_roboscripts_whoever_put_it_there() -> None:
    assert owner_of_file(os.path.join(PACKAGE_DIR, "my_mission.py")) == ROBOSCRIPT
    assert owner_of_file(os.path.join(PACKAGE_DIR, "missions", "square.py")) == ROBOSCRIPT


def test_a_symlinked_install_is_roboscripts_where_its_files_really_are(tmp_path: Path) -> None:
    site = tmp_path / "site"
    site.mkdir()
    (site / "roboscript").symlink_to(PACKAGE_DIR.rstrip(os.sep), target_is_directory=True)
    assert owner_of_file(str(site / "roboscript" / "actions" / "base.py")) == ROBOSCRIPT
    # imported through the link: its checks are still told as a mission's check tells them
    probe = textwrap.dedent(
        """
        import sys
        sys.path.insert(0, sys.argv[1])
        import roboscript
        assert roboscript.__file__.startswith(sys.argv[1]), roboscript.__file__
        from roboscript.actions import Wait
        from roboscript.code_owner import is_student_file
        print(is_student_file(roboscript.__file__))
        try:
            Wait(duration_s=[2])
        except ValueError as exc:
            print(exc)
        """
    )
    out = _python(["-S", "-c", probe, str(site)], tmp_path, _dependency_folders())
    assert out.splitlines() == [
        "False",
        "wait duration: expected a time such as '200 ms', got [2]",
    ]


def _python(args: list[str], cwd: Path, path: list[str] | None = None) -> str:
    """The standard output of this interpreter run with ``args`` in a fresh process (with
    ``path`` as its ``PYTHONPATH`` when given), which must succeed."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(path)} if path is not None else None
    done = subprocess.run(
        [sys.executable, *args],
        capture_output=True,
        text=True,
        check=False,
        cwd=cwd,
        env=env,
        timeout=HANG_BOUND_S,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def _dependency_folders() -> list[str]:
    """Where roboscript's runtime packages are, for an interpreter started without site."""
    return sorted({str(Path(str(m.__file__)).parent.parent) for m in (yaml, transitions)})


# ------------------------------------------------------------------ a student's code


def test_a_folder_named_like_roboscripts_plus_a_suffix_is_the_students() -> None:
    beside = os.path.join(PACKAGE_DIR.rstrip(os.sep) + "_missions", "square.py")
    assert owner_of_file(beside) == STUDENT


def test_a_students_own_folder_named_roboscript_is_the_students(tmp_path: Path) -> None:
    assert owner_of_file(str(tmp_path / "roboscript" / "actions" / "base.py")) == STUDENT


def test_a_student_file_named_like_a_roboscript_module_is_the_students(here: Path) -> None:
    (here / "motion.py").write_text(SPIN, encoding="utf-8")  # roboscript has actions/motion.py
    module = import_student_file(here / "motion.py")
    assert is_student_file(str(module.__file__))
    assert is_student_class(module.Spin)
    assert _update_is_checked(module.Spin)


def test_a_students_module_named_like_roboscripts_is_still_the_students(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "mine.py"
    path.write_text(SPIN, encoding="utf-8")
    spec = importlib.util.spec_from_file_location("roboscript.mine", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "roboscript.mine", module)
    spec.loader.exec_module(module)
    assert module.Spin.__module__ == "roboscript.mine"
    assert is_student_class(module.Spin)
    assert _update_is_checked(module.Spin)


def test_a_module_named_roboscript_plus_a_suffix_is_not_roboscripts() -> None:
    assert is_roboscript_module("roboscript")
    assert is_roboscript_module("roboscript.actions.base")
    assert not is_roboscript_module("roboscript_helpers")
    assert not is_roboscript_module("my.roboscript")
    assert is_student_class(type("Helper", (), {"__module__": "roboscript_helpers"}))


def test_a_class_made_by_exec_is_the_students_and_its_update_is_checked() -> None:
    made: dict[str, object] = {"Action": Action, "Result": Result}
    exec(SPIN.split("\n", 2)[2], made)  # noqa: S102 - as a notebook or a teacher's tool would
    spin = made["Spin"]
    assert isinstance(spin, type) and issubclass(spin, Action)
    assert is_student_class(spin)
    assert _update_is_checked(spin)


def test_the_working_folder_holding_a_virtual_environment_stays_the_students() -> None:
    site = Path(sysconfig.get_paths()["purelib"])
    around = site.parents[2] if len(site.parents) > 3 else site.parent
    assert owner_of_file(str(around / "my_mission.py")) == STUDENT


@pytest.mark.skipif(
    not (Path(PACKAGE_DIR).parent / "pyproject.toml").is_file(), reason="not an editable install"
)
def test_the_checkout_around_an_editable_install_is_the_students() -> None:
    checkout = Path(PACKAGE_DIR).parent
    assert owner_of_file(str(checkout / "missions" / "square.py")) == STUDENT
    assert owner_of_file(__file__) == STUDENT  # the tests run as a student's code would


def test_a_relative_name_of_a_file_in_the_working_folder_is_the_students(here: Path) -> None:
    (here / "m.py").write_text(
        "import sys\nwhere = sys._getframe().f_code.co_filename\n", encoding="utf-8"
    )
    ran = runpy.run_path("m.py")
    assert ran["where"] == "m.py"
    assert is_student_file(ran["where"])


# ------------------------------------------------------------------ a library's code


def test_pythons_and_installed_packages_files_are_library_code() -> None:
    for module in (os, yaml, transitions, simple_pid, pytest):
        assert owner_of_file(str(module.__file__)) == LIBRARY
    # the console command pip made (`roboscript`) is in every traceback of a command
    assert owner_of_file(os.path.join(sysconfig.get_paths()["scripts"], "roboscript")) == LIBRARY


def test_a_folder_inside_site_packages_is_library_code() -> None:
    site = sysconfig.get_paths()["purelib"]
    assert owner_of_file(os.path.join(site, "homework", "square.py")) == LIBRARY


def test_code_from_no_file_is_no_students() -> None:
    for name in ("<string>", "<frozen importlib._bootstrap>", "<stdin>"):
        assert owner_of_file(name) == LIBRARY
        assert not is_student_file(name)


def test_bytecode_compiled_under_its_name_in_a_zip_is_library_code_as_on_the_page(
    here: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The browser page imports the standard library from a zip of bytecode compiled under
    each file's name in the zip (``json/decoder.py``): no file a student could open, so no
    student's (else the watchdog would watch it line by line and blame it)."""
    source = io.BytesIO()
    with zipfile.ZipFile(source, "w") as archive:
        archive.writestr(
            "pagelib/__init__.py",
            "import sys\n\ndef where():\n    return sys._getframe().f_code.co_filename\n",
        )
    stdlib = here / "python_stdlib.zip"
    stdlib.write_bytes(compile_zip(source.getvalue(), beside_source=False))
    monkeypatch.syspath_prepend(str(stdlib))
    where = importlib.import_module("pagelib").where()
    assert where == "pagelib/__init__.py"
    assert owner_of_file(where) == LIBRARY


def test_a_zip_of_source_in_the_students_folder_is_the_students(
    here: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    archive_path = here / "helpers.zip"
    with zipfile.ZipFile(archive_path, "w") as archive:
        archive.writestr(
            "zipped_helper.py",
            "import sys\n\ndef where():\n    return sys._getframe().f_code.co_filename\n",
        )
    monkeypatch.syspath_prepend(str(archive_path))
    where = importlib.import_module("zipped_helper").where()
    assert where.startswith(str(archive_path))
    assert owner_of_file(where) == STUDENT


def test_packages_unpacked_outside_pythons_paths_are_library_code_as_on_the_page(
    tmp_path: Path,
) -> None:
    """The browser page unpacks yaml, transitions and simple_pid in a folder of its own, first
    on the path: their code is still no student's (else the watchdog would watch it line by
    line and blame it for a slow check)."""
    site = tmp_path / "home" / "site-packages"
    for package in (yaml, transitions, simple_pid):
        folder = Path(str(package.__file__)).parent
        shutil.copytree(folder, site / folder.name, ignore=shutil.ignore_patterns("__pycache__"))
    probe = (
        "import sys; sys.path.insert(0, sys.argv[1])\n"
        "import yaml, transitions, simple_pid\n"
        "from roboscript.code_owner import is_student_file\n"
        "for module in (yaml, transitions, simple_pid):\n"
        "    assert module.__file__.startswith(sys.argv[1]), module.__file__\n"
        "    print(module.__name__, is_student_file(module.__file__))\n"
        "print('mission', is_student_file(sys.argv[2]))\n"
    )
    mission = tmp_path / "home" / "square.py"
    mission.write_text("x = 1\n", encoding="utf-8")
    out = _python(["-c", probe, str(site), str(mission)], tmp_path)
    assert out.split("\n")[:4] == [
        "yaml False",
        "transitions False",
        "simple_pid False",
        "mission True",
    ]


# ------------------------------------------------------------------ where an error was raised


def test_an_error_raised_by_roboscripts_own_checks_is_told_as_roboscripts() -> None:
    with pytest.raises(ValueError) as raised:
        parse_quantity("fast", "speed")
    assert raised_by_roboscript(raised.value)


def test_an_error_raised_in_a_students_or_a_librarys_code_is_not_roboscripts() -> None:
    with pytest.raises(ZeroDivisionError) as mine:
        _ = 1 / 0
    assert not raised_by_roboscript(mine.value)
    with pytest.raises(yaml.YAMLError) as theirs:
        yaml.safe_load("a: [")
    assert not raised_by_roboscript(theirs.value)
    with pytest.raises(NameError) as executed:
        exec("undefined_name")  # noqa: S102 - code from no file
    assert not raised_by_roboscript(executed.value)
    assert not raised_by_roboscript(ValueError("never raised"))


# ------------------------------------------------------------------ in a graded run's jail


def test_the_rule_holds_inside_a_graded_runs_jail(tmp_path: Path) -> None:
    from roboscript.grading.sandbox import Jail, Limits

    tmp_path.chmod(0o755)
    box = tmp_path / "student"
    box.mkdir(mode=0o755)
    (box / "square.py").write_text("x = 1\n", encoding="utf-8")
    probe = textwrap.dedent(
        """
        import os, sys, yaml
        import roboscript.actions.base as base
        from roboscript.code_owner import is_student_class, owner_of_file
        class Mine(base.Action):
            name = "mine"
        for name in (base.__file__, yaml.__file__, os.path.abspath("square.py"), "<string>"):
            print(owner_of_file(name))
        print(is_student_class(Mine), is_student_class(base.Action))
        """
    )
    argv = [sys.executable, "-I", "-c", probe]
    with Jail(argv, visible=[box], workdir=box, limits=Limits()) as jail:
        status = jail.wait(HANG_BOUND_S)
        out, err = jail.stdout, jail.stderr
    assert status == 0, err
    assert out.splitlines() == [ROBOSCRIPT, LIBRARY, STUDENT, LIBRARY, "True False"]


def test_a_crashed_graded_run_names_the_students_line_not_roboscripts_nor_pythons() -> None:
    from roboscript.grading.world_host import crash_message

    student = Path(PACKAGE_DIR.rstrip(os.sep) + "_missions") / "square.py"
    frames = [
        ("<frozen runpy>", 198, "_run_module_as_main"),
        (str(roboscript.actions.base.__file__), 40, "wrapped"),
        (str(student), 12, "update"),
        (str(yaml.__file__), 81, "safe_load"),
        (os.path.join(PACKAGE_DIR, "mission", "student_code.py"), 7, "student_fault"),
    ]
    stderr = "Traceback (most recent call last):\n"
    stderr += "".join(f'  File "{file}", line {line}, in {func}\n' for file, line, func in frames)
    stderr += "ZeroDivisionError: division by zero\n"
    assert crash_message(stderr, 1, loaded=True) == (
        "the run crashed: ZeroDivisionError: division by zero (square.py:12)"
    )


def test_a_student_file_named_like_a_runtime_package_keeps_the_students_folder_theirs(
    tmp_path: Path,
) -> None:
    """A student's ``serial.py`` beside their mission, first on the path before pyserial is
    imported, is no installed package: their folder stays theirs (the watchdog watches it)."""
    (tmp_path / "serial.py").write_text("BAUD = 9600\n", encoding="utf-8")
    mission = tmp_path / "mission.py"
    mission.write_text("import serial\n", encoding="utf-8")
    probe = textwrap.dedent(
        """
        import sys
        sys.path.insert(0, sys.argv[1])
        from roboscript.code_owner import is_student_file
        print(is_student_file(sys.argv[2]))
        import serial  # the student's
        print(is_student_file(sys.argv[2]), is_student_file(serial.__file__))
        """
    )
    out = _python(["-c", probe, str(tmp_path), str(mission)], tmp_path)
    assert out.splitlines() == ["True", "True True"]
