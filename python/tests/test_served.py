"""What only a served connection does: a child process after ``fork``,
and a server that asks for its access token (given by the environment,
as ``addipos call`` takes it)."""

import os
import socket
import subprocess
import time

import pytest

import addipos
from conftest import SERVE_START_LIMIT_S, free_port

PLANE = (1300, 0, 3, 0)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork on this system")
def test_a_child_after_fork_gets_a_clear_error_and_the_parent_goes_on(server):
    with addipos.open(server) as m:
        plane = m.init(*PLANE)
        assert plane.read_int() == 17
        read, write = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: one call, its outcome to the parent
            os.close(read)
            try:
                m.pos()
                said = "no error"
            except addipos.Connection as e:
                said = "Connection: " + str(e)
            except BaseException as e:  # noqa: BLE001 - reported to the parent
                said = f"{type(e).__name__}: {e}"
            os.write(write, said.encode())
            os._exit(0)
        os.close(write)
        with os.fdopen(read) as r:
            said = r.read()
        os.waitpid(pid, 0)
        assert said.startswith("Connection: ") and "fork" in said, said
        assert plane.read_int() == 17, "the parent's connection goes on"


@pytest.fixture
def guarded_server(binary, tmp_path):
    """An ``addipos serve`` that asks every client, loopback ones too, for
    its access token; yields its target string and its token file."""
    port = free_port()
    data = tmp_path / "serve-data"
    config = tmp_path / "serve.toml"
    config.write_text("token_on_loopback = true\n")
    proc = subprocess.Popen(
        [str(binary), "serve", "--listen", f"127.0.0.1:{port}", "--no-persist",
         "--data-dir", str(data), "--config", str(config)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + SERVE_START_LIMIT_S
        while not (data / "access-token").exists() or not _listens(port):
            if proc.poll() is not None:
                raise RuntimeError(f"addipos serve ended: {proc.stderr.read().decode()}")
            if time.monotonic() > deadline:
                raise TimeoutError("addipos serve did not start")
            time.sleep(0.05)
        yield f"127.0.0.1:{port}", data / "access-token"
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def _listens(port):
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1).close()
        return True
    except OSError:
        return False


def test_the_token_comes_from_the_environment_or_the_target(guarded_server, monkeypatch):
    target, token_file = guarded_server
    monkeypatch.delenv("ADDIPOS_TOKEN", raising=False)
    monkeypatch.delenv("ADDIPOS_TOKEN_FILE", raising=False)
    with pytest.raises(addipos.Protocol) as e:
        addipos.open(target)
    assert "ADDIPOS_TOKEN" in str(e.value)
    monkeypatch.setenv("ADDIPOS_TOKEN", token_file.read_text().strip())
    with addipos.open(target) as m:
        assert m.init(*PLANE).read_int() == 17
    monkeypatch.delenv("ADDIPOS_TOKEN")
    monkeypatch.setenv("ADDIPOS_TOKEN_FILE", str(token_file))
    with addipos.open(target) as m:
        assert m.init(*PLANE).read_int() == 17
    monkeypatch.delenv("ADDIPOS_TOKEN_FILE")
    with addipos.open(f"{target},token_file={token_file}") as m:
        assert m.init(*PLANE).read_int() == 17
