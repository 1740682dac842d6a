"""Handles, reads and writes, and the errors they raise (embedded, and
served when the library can open a server)."""

import re

import pytest

import addipos
from conftest import REPO

# Objects of docs/objects.md used here: (bus, device, index, subindex).
CLEAN = (1300, 0, 1, 0)
PLANE = (1300, 0, 3, 0)
ERROR = (1300, 1, 1, 1)
RESET = (1300, 1, 1, 2)
STATUS = (1300, 1, 1, 3)
RADIUS = (1300, 1, 1, 6)
WKZINDEX = (1300, 1, 1, 8)
WEAR_RADIUS = (1300, 3, 1, 10)


def test_a_handle_reads_through_the_connection_and_itself(m):
    h = m.init(*WKZINDEX)
    m.write_int(h, 3)
    assert m.read_int(h) == 3
    h.write_int(5)
    assert h.read_int() == 5
    assert h.read() == 5 and isinstance(h.read(), int)
    assert h.descriptor == WKZINDEX
    assert h.value_type == "int"
    assert h.number != 0


def test_a_double_object_reads_and_writes_as_float(m):
    index, radius = m.init(*WKZINDEX), m.init(*RADIUS)
    index.write(2)
    radius.write(1.25)
    assert m.read_double(radius) == 1.25
    assert radius.read() == 1.25 and radius.value_type == "double"
    with pytest.raises(addipos.Argument):
        radius.write("wide")
    index.write(3)
    assert radius.read_double() == 0.0, "another tool entry has its own radius"


def test_objects_that_do_not_exist_raise_their_access_error(m):
    with pytest.raises(addipos.NoObject) as e:
        m.init(1300, 9, 1, 1)
    assert e.value.code == 0x06020000 and e.value.name == "NoObject"
    assert isinstance(e.value, addipos.AccessError)
    with pytest.raises(addipos.NoSubindex) as e:
        m.init(1300, 1, 1, 99)
    assert e.value.code == 0x06090011
    for bad in [(1301, 1, 1, 1), (1300, -1, 1, 1), (1300, 1, 2**40, 1), (1300, 70000, 1, 1)]:
        with pytest.raises(addipos.NoObject):
            m.init(*bad)


def test_access_and_type_are_checked_by_each_read_and_write(m):
    with pytest.raises(addipos.WriteOnly):
        m.init(*RESET).read_int()
    with pytest.raises(addipos.ReadOnly):
        m.init(*WEAR_RADIUS).write_double(1.0)
    with pytest.raises(addipos.TypeMismatch):
        m.init(*RADIUS).read_int()
    with pytest.raises(addipos.TypeMismatch):
        m.init(*WKZINDEX).write_double(1.0)


def test_a_value_outside_the_range_raises_range_and_changes_nothing(m):
    index = m.init(*WKZINDEX)
    index.write_int(7)
    with pytest.raises(addipos.Range) as e:
        index.write_int(1024)
    assert e.value.code == 0x06090030
    assert "1300/1/1/8" in str(e.value)
    assert index.read_int() == 7
    with pytest.raises(addipos.Range):
        m.init(*RADIUS).write_double(float("nan"))


def test_an_int_beyond_32_bits_is_an_argument_error(m):
    index = m.init(*WKZINDEX)
    with pytest.raises(addipos.Argument):
        index.write_int(2**31)
    with pytest.raises(ValueError):
        index.write("three")


def test_ints_of_any_size_give_the_librarys_errors_not_overflow(m):
    # Beyond 64 bits too: the library's error, never OverflowError.
    index = m.init(*WKZINDEX)
    for big in (2**64, -(2**70)):
        with pytest.raises(addipos.Argument):
            index.write_int(big)
        with pytest.raises(addipos.Argument):
            m.write_int(index, big)
        with pytest.raises(addipos.Argument):
            index.write(big)
    with pytest.raises(addipos.NoObject):
        m.init(2**70, 1, 1, 1)
    with pytest.raises(addipos.NoObject):
        m.init(1300, -(2**80), 1, 1)
    with pytest.raises(addipos.Argument):
        m.ssf("X", 2**40)
    with pytest.raises(addipos.Argument):
        m.exec(2**70)


def test_clean_voids_every_handle_issued_before_it(m):
    index, clean = m.init(*WKZINDEX), m.init(*CLEAN)
    index.write_int(4)
    clean.write_int(1)
    for h in (index, clean):
        with pytest.raises(addipos.StaleHandle) as e:
            h.read_int() if h is index else h.write_int(1)
        assert e.value.code == 0xADD00001
        assert not isinstance(e.value, addipos.AccessError)
    fresh = m.init(*WKZINDEX)
    assert fresh.read_int() == 0, "Clean put the objects back to their defaults"


def test_a_refused_clean_voids_nothing(m):
    index, clean = m.init(*WKZINDEX), m.init(*CLEAN)
    with pytest.raises(addipos.Range):
        clean.write_int(2)
    assert index.read_int() == 0


def test_a_released_handle_is_stale(m):
    h = m.init(*PLANE)
    plane = h.read_int()
    h.release()
    with pytest.raises(addipos.StaleHandle):
        h.read_int()
    with pytest.raises(addipos.StaleHandle):
        m.release(h)
    assert m.init(*PLANE).read_int() == plane


def test_a_handle_of_another_connection_is_refused(m):
    with addipos.open() as other:
        foreign = other.init(*PLANE)
        with pytest.raises(addipos.BadHandle):
            m.read_int(foreign)
        assert foreign.read_int() == m.init(*PLANE).read_int()


def test_a_closed_connection_raises_connection(target):
    m = addipos.open(target)
    h = m.init(*PLANE)
    m.close()
    assert m.closed
    m.close()  # twice is allowed
    for call in (lambda: m.pos(), lambda: h.read_int(), lambda: m.init(*PLANE)):
        with pytest.raises(addipos.Connection) as e:
            call()
        assert isinstance(e.value, ConnectionError)


def test_the_context_manager_closes(target):
    with addipos.open(target) as m:
        assert not m.closed
        assert m.pos() == (0.0,) * 8
    assert m.closed


def access_errors_of_the_docs():
    """(name, code) of each row of the access error table in
    docs/objects.md, the table the emulator's code generates."""
    text = (REPO / "docs" / "objects.md").read_text()
    table = text.split("## Access errors", 1)[1].split("\n## ", 1)[0]
    return [(n, int(c, 16)) for n, c in re.findall(r"^\| `(\w+)` \| (0x[0-9a-fA-F]+) \|", table, re.M)]


def test_every_access_error_of_the_object_table_is_a_class_with_its_code():
    rows = access_errors_of_the_docs()
    assert len(rows) >= 9
    for name, code in rows:
        cls = getattr(addipos, name)
        assert issubclass(cls, addipos.AccessError), name
        assert cls.CODE == code, name
        err = addipos._error(code, "x")
        assert type(err) is cls and err.code == code and err.name == name


def test_the_library_codes_are_classes_outside_the_access_errors():
    own = [addipos.StaleHandle, addipos.NullHandle, addipos.Argument, addipos.Connection,
           addipos.NotSupported, addipos.Timeout, addipos.BadHandle, addipos.TooManyHandles,
           addipos.Record, addipos.Protocol, addipos.Stopped, addipos.Internal]
    for cls in own:
        assert issubclass(cls, addipos.Error) and not issubclass(cls, addipos.AccessError)
        assert cls.CODE >> 16 == 0xADD0, cls
    assert type(addipos._error(0x12345678, "unknown")) is addipos.Error
    assert addipos.Stopped.CODE == 0xADD0000B
