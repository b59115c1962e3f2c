"""Bytecode compiled at build time: the page imports it instead of compiling source."""

from __future__ import annotations

import io
import subprocess
import sys
import zipfile
from pathlib import Path

from roboscript.web.bytecode import compile_zip


def _zip(files: dict[str, str]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, text in files.items():
            archive.writestr(name, text)
    return buffer.getvalue()


def _python(code: str, cwd: Path) -> str:
    done = subprocess.run(
        [sys.executable, "-I", "-c", code], cwd=cwd, capture_output=True, text=True, check=True
    )
    return done.stdout.strip()


FILES = {"pkg/__init__.py": "", "pkg/mod.py": "ANSWER = 'compiled'\n", "pkg/data.yaml": "a: 1\n"}


def test_a_zip_imported_as_it_is_holds_bytecode_in_place_of_source(tmp_path: Path) -> None:
    compiled = compile_zip(_zip(FILES), beside_source=False)
    names = sorted(zipfile.ZipFile(io.BytesIO(compiled)).namelist())
    assert names == ["pkg/__init__.pyc", "pkg/data.yaml", "pkg/mod.pyc"]
    (tmp_path / "lib.zip").write_bytes(compiled)
    answer = _python(
        "import sys; sys.path.insert(0, 'lib.zip'); import pkg.mod; print(pkg.mod.ANSWER)", tmp_path
    )
    assert answer == "compiled"


def test_unpacked_packages_keep_their_source_and_import_the_bytecode(tmp_path: Path) -> None:
    compiled = compile_zip(_zip(FILES), beside_source=True)
    zipfile.ZipFile(io.BytesIO(compiled)).extractall(tmp_path)
    assert (tmp_path / "pkg" / "data.yaml").is_file()
    # the bytecode is never checked against the source: changing the source changes nothing
    (tmp_path / "pkg" / "mod.py").write_text("ANSWER = 'source'\n")
    code = "import sys; sys.path.insert(0, ''); import pkg.mod; print(pkg.mod.ANSWER)"
    assert _python(code, tmp_path) == "compiled"


def test_a_file_that_does_not_compile_keeps_its_source() -> None:
    compiled = compile_zip(_zip({"bad.py": "def (:\n"}), beside_source=False)
    assert zipfile.ZipFile(io.BytesIO(compiled)).read("bad.py") == b"def (:\n"


def test_the_same_zip_compiles_to_the_same_bytes() -> None:
    assert compile_zip(_zip(FILES), beside_source=True) == compile_zip(
        _zip(FILES), beside_source=True
    )
