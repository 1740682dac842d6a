"""Motion, the executor and the position: the worked example of
docs/python.md (the square with left correction) and each motion call
(embedded, and served when the library can open a server)."""

import pytest

import addipos


def square_with_left_correction(m):
    """The worked example of docs/python.md: a 20 mm square around the
    origin's corner, a 2 mm tool corrected on the left, then the departure
    to (-5, -5)."""
    reset, xaxis, yaxis, zaxis = (m.init(1300, 1, 1, s) for s in (2, 4, 5, 11))
    wkzindex, radius, left, status = (m.init(1300, 1, 1, s) for s in (8, 6, 9, 3))
    m.rs()
    reset.write_int(0)
    xaxis.write_int(0)
    yaxis.write_int(1)
    zaxis.write_int(2)
    wkzindex.write_int(3)
    radius.write_double(2.0)
    wkzindex.write_int(3)
    left.write_int(0)
    status.write_int(1)
    m.lin(X=20, Y=0, F=600)
    m.lin(X=20, Y=20)
    m.lin(X=0, Y=20)
    m.lin(X=0, Y=0)
    status.write_int(0)
    m.rap(X=-5, Y=-5)
    while m.queue() > 0:
        m.exec(100)


def test_the_square_runs_on_the_corrected_path(m):
    m.spool_log(True)
    square_with_left_correction(m)
    p = m.pos()
    assert isinstance(p, addipos.Position)
    assert (p.X, p.Y, p.Z) == (-5.0, -5.0, 0.0)
    assert m.read_int(m.init(1300, 1, 1, 1)) == 0, "ERROR: no bit set"
    path = m.take_spooled()
    ends = [(e.end.X, e.end.Y) for e in path]
    assert ends == [(18, 2), (18, 18), (2, 18), (2, 0), (-5, -5)], "the tool centre 2 inside the square"
    assert [e.origin for e in path] == ["Approach", "Corrected", "Corrected", "Corrected", "Departure"]
    assert path[-1].kind == "RAP" and path[0].kind == "LIN"
    assert path[0].feed == 600.0
    assert m.take_spooled() == [], "taken once"


def test_exec_runs_cycles_and_pos_follows(m):
    m.lin(X=100, F=6000)  # 100 mm/s: 1000 cycles of 1 ms
    assert m.queue() == 1
    m.exec(500)
    half = m.pos().X
    assert 0 < half < 100
    assert m.queue() == 1
    m.exec()
    assert m.pos().X == 100.0
    assert m.queue() == 0


def test_exec_refuses_a_negative_count(m):
    with pytest.raises(addipos.Argument):
        m.exec(-1)
    with pytest.raises(addipos.Argument):
        m.exec("all")


def test_an_arc_ends_where_it_was_programmed(m):
    m.spool_log(True)
    m.lin(X=10, Y=0, F=6000)
    m.cir("CCW", X=0, Y=10, I=-10, J=0)
    m.exec()
    p = m.pos()
    assert abs(p.X) < 1e-9 and p.Y == pytest.approx(10.0)
    arc = m.take_spooled()[-1]
    assert arc.kind == "CIR" and arc.ccw is True
    assert arc.centre == pytest.approx((0.0, 0.0))


def test_cir_takes_cw_and_ccw_only(m):
    with pytest.raises(addipos.Argument):
        m.cir("left", X=1, I=1)
    m.cir("cw", X=0, Y=0, I=1, J=0, F=600)  # a full circle in either case


def test_motion_words_are_the_axes_and_f(m):
    with pytest.raises(addipos.Argument) as e:
        m.lin(X=1, W=2)
    assert "X Y Z A B C U V F" in str(e.value)
    with pytest.raises(addipos.Argument):
        m.ja(X=1, F=600)  # JA has no feed
    with pytest.raises(addipos.Argument):
        m.lin(I=1)  # a line has no centre
    with pytest.raises(addipos.Argument):
        m.lin(X="ten")


def test_a_coordinate_beyond_the_limit_raises_range(m):
    with pytest.raises(addipos.Range):
        m.lin(X=2e9, F=600)
    assert m.queue() == 0


def test_ja_drops_the_spooler_and_positions_directly(m):
    m.lin(X=50, F=600)
    m.lin(Y=50)
    assert m.queue() == 2
    m.ja(X=-3, Z=7)
    assert m.queue() == 0
    m.exec()
    p = m.pos()
    assert (p.X, p.Y, p.Z) == (-3.0, 0.0, 7.0)


def test_js_stops_the_axes_named(m):
    m.lin(X=100, F=6000)
    m.exec(200)
    m.js("X")
    m.exec()
    stopped = m.pos().X
    assert 0 < stopped < 100
    m.js()  # no axis: nothing to stop
    with pytest.raises(addipos.Argument):
        m.js("W")


def test_ssf_takes_an_axis_name_or_number(m):
    m.ssf("X", 2001)
    m.ssf(1, 2001)
    for bad in ("Q", 8, -1, "XY"):
        with pytest.raises(addipos.Argument):
            m.ssf(bad, 2001)


def test_a_faulted_group_refuses_motion_with_state(m):
    # An arc whose offset radius vanishes: the correction faults (ERROR
    # bit CalcError), motion is refused until ERROR is written.
    for s, v in ((2, 0), (8, 1)):
        m.init(1300, 1, 1, s).write_int(v)
    m.init(1300, 1, 1, 6).write_double(2.0)
    m.init(1300, 1, 1, 9).write_int(0)
    m.init(1300, 1, 1, 3).write_int(1)
    m.lin(X=10, Y=0)
    m.cir("CCW", X=10, Y=2, I=0, J=1)
    error = m.init(1300, 1, 1, 1)
    assert error.read_int() == 4
    with pytest.raises(addipos.State) as e:
        m.lin(X=0, Y=0)
    assert e.value.code == 0x08000022
    error.write_int(0)
    m.lin(X=0, Y=0)


def test_rs_is_accepted(m):
    m.rs()
    assert m.queue() == 0
