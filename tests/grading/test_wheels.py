"""Wheels of roboscript and its dependencies, made offline from the installed files."""

from __future__ import annotations

import base64
import hashlib
import io
import zipfile
from pathlib import Path

import pytest

from roboscript.errors import RoboscriptError
from roboscript.grading.wheels import dependency_wheels


def test_pyyaml_is_packed_pure_python() -> None:
    """Gradescope's image may run another Python: no compiled module crosses."""
    wheel = next(w for w in dependency_wheels() if w.filename.lower().startswith("pyyaml"))
    assert wheel.filename.endswith("-py3-none-any.whl")
    with zipfile.ZipFile(io.BytesIO(wheel.content)) as archive:
        names = archive.namelist()
    assert "yaml/__init__.py" in names
    assert not [n for n in names if n.endswith((".so", ".pyd"))]
    assert any(n.endswith(".dist-info/RECORD") for n in names)


def _fake_distribution(site: Path, name: str, module: str) -> None:
    info = site / f"{name}-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
    (site / module).mkdir()
    (site / module / "__init__.py").write_text("")
    (site / module / "_speed.cpython-311-x86_64-linux-gnu.so").write_bytes(b"\x7fELF")
    (info / "RECORD").write_text(
        f"{module}/__init__.py,,\n{module}/_speed.cpython-311-x86_64-linux-gnu.so,,\n"
        f"{name}-1.0.dist-info/METADATA,,\n{name}-1.0.dist-info/RECORD,,\n"
    )


def test_compiled_code_is_refused_unless_a_wheel_is_given(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    site = tmp_path / "site"
    _fake_distribution(site, "fastthing", "fastthing")
    monkeypatch.syspath_prepend(str(site))
    with pytest.raises(RoboscriptError, match=r"fastthing has compiled code .* --wheels DIR"):
        dependency_wheels("fastthing")
    ready = tmp_path / "ready"
    ready.mkdir()
    (ready / "fastthing-1.0-cp311-cp311-manylinux_2_17_x86_64.whl").write_bytes(b"PK ready")
    [wheel] = dependency_wheels("fastthing", ready)
    assert wheel.content == b"PK ready" and wheel.filename.startswith("fastthing-1.0-cp311")


def test_every_wheel_installs_as_pip_reads_it() -> None:
    """A RECORD that lists every file with its hash, and the metadata pip checks."""
    for wheel in dependency_wheels():
        with zipfile.ZipFile(io.BytesIO(wheel.content)) as archive:
            names = archive.namelist()
            info = next(n.split("/")[0] for n in names if n.endswith(".dist-info/RECORD"))
            record = archive.read(f"{info}/RECORD").decode().splitlines()
            listed = {line.rsplit(",", 2)[0]: line.rsplit(",", 2)[1] for line in record}
            assert set(listed) == set(names), wheel.filename
            for name, digest in listed.items():
                if name.endswith("RECORD"):
                    continue
                content = archive.read(name)
                expected = base64.urlsafe_b64encode(hashlib.sha256(content).digest())
                assert digest == "sha256=" + expected.rstrip(b"=").decode(), name
            metadata = archive.read(f"{info}/METADATA").decode()
            version = wheel.filename.split("-")[1]
            assert f"\nVersion: {version}\n" in metadata
            assert b"Tag: py3-none-any" in archive.read(f"{info}/WHEEL")
