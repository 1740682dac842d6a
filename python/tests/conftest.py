"""Fixtures of the addipos tests: a connection to an embedded emulator
and, for the tests that run against both, to a served one
(``addipos serve`` started on a free port)."""

import os
import socket
import subprocess
import time
from pathlib import Path

import pytest

import addipos

#: The repository (python/tests/../..).
REPO = Path(__file__).resolve().parents[2]

#: How long a started server may take to listen (a bound on the wait, not
#: a measured time).
SERVE_START_LIMIT_S = 30.0


def addipos_binary() -> Path:
    """The command-line program: $ADDIPOS_BIN, else the debug build."""
    return Path(os.environ.get("ADDIPOS_BIN", REPO / "target" / "debug" / "addipos"))


@pytest.fixture(scope="session")
def binary() -> Path:
    """The command-line program, or a skip when it is not built."""
    path = addipos_binary()
    if not path.exists():
        pytest.skip(f"{path} is not built (cargo build)")
    return path


def free_port() -> int:
    """A port on 127.0.0.1 nobody listens on right now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve(binary, tmp_path, *extra):
    """Starts ``addipos serve`` with ``extra`` arguments on a free loopback
    port, no tool files kept; yields its target string, stops it after."""
    port = free_port()
    data = tmp_path / "serve-data"
    proc = subprocess.Popen(
        [str(binary), "serve", "--listen", f"127.0.0.1:{port}", "--no-persist", "--data-dir", str(data), *extra],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + SERVE_START_LIMIT_S
        while True:
            if proc.poll() is not None:
                raise RuntimeError(f"addipos serve ended: {proc.stderr.read().decode()}")
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
        yield f"127.0.0.1:{port}"
    finally:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.fixture
def server(binary, tmp_path):
    """A running ``addipos serve`` of its own (a fresh emulator, as an
    embedded connection has) on a free loopback port, no tool files kept;
    yields its target string ``127.0.0.1:PORT``."""
    yield from serve(binary, tmp_path)


@pytest.fixture
def realtime_server(binary, tmp_path):
    """As ``server``, in real time (``--realtime 1``)."""
    yield from serve(binary, tmp_path, "--realtime", "1")


@pytest.fixture(params=["embedded", "served"])
def target(request) -> str:
    """The target string of a test that runs against both: an embedded
    emulator, then a served one."""
    if request.param == "served":
        return request.getfixturevalue("server")
    return "embedded"


@pytest.fixture
def m(target):
    """A fresh connection to the target, closed after the test."""
    with addipos.open(target) as machine:
        yield machine
