"""The type stubs (addipos/__init__.pyi) match the installed package:
mypy's stubtest compares every name, signature and class with the module
as it runs."""

import os
import subprocess
import sys

import pytest


def test_the_stubs_match_the_package(tmp_path):
    pytest.importorskip("mypy.stubtest", reason="mypy is not installed (pip install mypy)")
    # Run away from the source tree, so the installed package is checked.
    run = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "addipos"],
        cwd=tmp_path,
        env=dict(os.environ, MYPY_CACHE_DIR=str(tmp_path / "cache")),
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stdout + run.stderr


def test_a_type_checker_catches_a_wrong_direction(tmp_path):
    pytest.importorskip("mypy.api", reason="mypy is not installed (pip install mypy)")
    from mypy import api

    program = tmp_path / "use.py"
    program.write_text(
        "import addipos\n"
        "with addipos.open() as m:\n"
        "    m.cir('CW', X=1, I=1)\n"
        "    m.cir('sideways', X=1, I=1)\n"
        "    kind: str = m.take_spooled()[0].kind\n"
    )
    out, err, status = api.run(
        ["--strict", "--cache-dir", str(tmp_path / "cache"), str(program)]
    )
    assert status == 1, out + err
    assert "use.py:4" in out and "sideways" in out, out
    assert "use.py:3" not in out, out
