"""What only a served connection does: a child process after ``fork``,
and a server that asks for its access token (given by the environment,
as ``addipos call`` takes it)."""

import os
import threading
import time

import pytest

import addipos
from conftest import serve

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
    config = tmp_path / "serve.toml"
    config.write_text("token_on_loopback = true\n")
    for target in serve(binary, tmp_path, "--config", str(config)):
        yield target, tmp_path / "serve-data" / "access-token"


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


def test_the_with_block_ends_a_served_wait_at_once_without_the_gil(realtime_server):
    # Leaving the block closes the connection while another thread waits
    # on the server: the wait ends with Connection (not Timeout after the
    # 20 s), and closing does not hold the GIL meanwhile.
    outcome = []
    with addipos.open(realtime_server, timeout=20) as m:
        m.lin(X=1000, F=600)  # 100 s of path on the server's clock
        started = threading.Event()

        def wait():
            started.set()
            try:
                m.exec()
                outcome.append("ran")
            except addipos.Error as e:
                outcome.append(type(e))

        t = threading.Thread(target=wait)
        t.start()
        started.wait()
        time.sleep(0.3)
    t.join(30)
    assert outcome == [addipos.Connection]


def test_ctrl_c_during_a_served_wait_raises_keyboard_interrupt(realtime_server):
    with addipos.open(realtime_server, timeout=20) as m:
        m.lin(X=1000, F=600)
        timer = threading.Timer(0.3, _interrupt_main)
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                m.exec()
        finally:
            timer.cancel()
        # The next call connects again; the line still runs. Given up at
        # the signal, not at the 20 s timeout (200 mm of the line): the
        # bound leaves 10 s for a slow machine.
        assert m.queue() == 1
        assert 0 < m.pos().X < 100


def _interrupt_main():
    import _thread

    _thread.interrupt_main()
