"""What only an embedded connection does here: real time, waits released
from the GIL, timeouts, the spooler's size, recording."""

import os
import subprocess
import sys
import threading
import time

import pytest

import addipos
from test_motion import square_with_left_correction


def test_open_takes_the_target_strings():
    with addipos.open() as m:
        assert m.target == "embedded" and m.realtime is None
    with addipos.open("embedded:realtime=10") as m:
        assert m.realtime == 10.0
    with pytest.raises(addipos.Argument):
        addipos.open("nowhere")


def test_an_empty_target_reads_addipos_target(monkeypatch):
    monkeypatch.setenv("ADDIPOS_TARGET", "embedded:realtime=2")
    with addipos.open() as m:
        assert m.realtime == 2.0


def test_a_wait_beyond_the_timeout_raises_timeout():
    with addipos.open("embedded:realtime", timeout=0.05) as m:
        m.lin(X=1000, F=600)  # 100 s of path
        with pytest.raises(addipos.Timeout) as e:
            m.exec()
        assert isinstance(e.value, TimeoutError) and e.value.code == 0xADD00006
        assert m.queue() == 1, "what ran stays run, the rest waits"
    with pytest.raises(addipos.Argument):
        addipos.open(timeout=-1)


def test_close_from_another_thread_ends_a_wait():
    # The wait releases the GIL: the main thread runs and closes, and the
    # waiting call ends with Connection (held, it would wait out its
    # timeout and raise Timeout).
    m = addipos.open("embedded:realtime", timeout=60)
    m.lin(X=1000, F=600)
    outcome = []
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
    # Give the thread time to enter the wait (were it not in yet, close
    # first would also give Connection: the check would be weaker, not
    # wrong).
    time.sleep(0.2)
    while t.is_alive() and not outcome:
        m.close()
        t.join(0.01)
    t.join()
    assert outcome == [addipos.Connection]


def test_a_full_spooler_raises_full(tmp_path):
    config = tmp_path / "small.toml"
    config.write_text("spool_capacity = 8\n")
    with addipos.open(f"embedded:config={config}") as m:
        with pytest.raises(addipos.Full):
            for x in range(1, 20):
                m.lin(X=x, F=600)
        assert m.queue() == 8
        m.exec()
        m.lin(X=20)


def test_a_recorded_session_replays(tmp_path, binary):
    trace = tmp_path / "square.trace"
    with addipos.open(record=trace) as m:
        assert m.recording
        square_with_left_correction(m)
        with pytest.raises(addipos.Range):
            m.init(1300, 1, 1, 8).write_int(5000)
    text = trace.read_text()
    assert "W 1300/1/1/6 d 2 => ok" in text
    assert "< LIN X18 Y2" in text
    assert "=> err Range" in text
    replay = subprocess.run([str(binary), "replay", str(trace)], capture_output=True, text=True)
    assert replay.returncode == 0, replay.stdout + replay.stderr


def test_recording_starts_before_the_first_request_only(tmp_path):
    with addipos.open() as m:
        m.pos()
        with pytest.raises(addipos.Record):
            m.record(tmp_path / "late.trace")
        assert not m.recording
    with addipos.open() as m:
        m.record(tmp_path / "explicit.trace")
        m.lin(X=1, F=600)
        m.stop_recording()
        assert not m.recording
    assert "LIN X1 F600 => ok" in (tmp_path / "explicit.trace").read_text()
    with pytest.raises(addipos.Record):
        addipos.open(record=tmp_path / "no-such-dir" / "x.trace")


def test_addipos_record_records_a_script(tmp_path, binary):
    trace = tmp_path / "env.trace"
    script = "import addipos\nm = addipos.open()\nm.lin(X=5, F=600)\nm.exec()\nprint(m.pos().X)\nm.close()\n"
    env = dict(os.environ, ADDIPOS_RECORD=str(trace))
    env.pop("ADDIPOS_TARGET", None)
    run = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "5.0"
    assert "LIN X5 F600 => ok" in trace.read_text()
    replay = subprocess.run([str(binary), "replay", str(trace)], capture_output=True, text=True)
    assert replay.returncode == 0, replay.stdout + replay.stderr


def test_an_explicit_record_wins_over_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("ADDIPOS_RECORD", str(tmp_path / "env.trace"))
    with addipos.open(record=tmp_path / "mine.trace") as m:
        m.rs()
    assert (tmp_path / "mine.trace").exists()
    assert not (tmp_path / "env.trace").exists()



def test_ctrl_c_during_a_wait_raises_keyboard_interrupt_at_once():
    # A signal during the wait: the wait is given up, KeyboardInterrupt is
    # raised (not Timeout at the end of the 60 s), and what ran stays run.
    with addipos.open("embedded:realtime", timeout=60) as m:
        m.lin(X=1000, F=600)  # 100 s of path
        timer = threading.Timer(0.2, _thread_interrupt_main)
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                m.exec()
        finally:
            timer.cancel()
        assert m.queue() == 1, "the line still runs"
        # Given up at the signal, not at the timeout: 60 s of the line
        # would be 600 mm; the bound leaves 10 s for a slow machine.
        assert 0 < m.pos().X < 100


def _thread_interrupt_main():
    import _thread

    _thread.interrupt_main()


def test_exec_quotes_what_it_was_given():
    with addipos.open() as m:
        with pytest.raises(addipos.Argument) as e:
            m.exec("10")
        assert "cycles='10'" in str(e.value)


def test_one_feed_rule_with_c_zero_is_modal_and_negative_is_range():
    with addipos.open() as m:
        m.lin(X=10, F=600)
        m.lin(X=20, F=0)  # the modal feed, as feed 0 in C
        m.spool_log(True)
        m.lin(X=30, F=0)
        assert m.take_spooled()[0].feed == 600
        with pytest.raises(addipos.Range) as e:
            m.lin(X=40, F=-5)
        assert "negative" in str(e.value)
        with pytest.raises(addipos.Range) as e:
            m.lin(X=40, F=0.1)
        assert "smallest feed" in str(e.value)
