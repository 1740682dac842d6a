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
