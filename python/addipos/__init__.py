"""addipos: the ADDIPOS TC emulator's host library for Python.

Open a connection with :func:`open` (a context manager), get handles to
objects with ``m.init(bus, device, index, subindex)``, read and write
through them, spool motion (``m.lin(X=50, Y=0, F=6000)``), run the
executor (``m.exec()``) and read the executed position (``m.pos()``).
Every failure raises a subclass of :class:`Error`: the access errors of
the object interface as :class:`AccessError` subclasses named as in
traces (:class:`Range`, :class:`State`, ...) with their CANopen
``code``, the library's own failures (:class:`StaleHandle`,
:class:`Timeout`, ...) with codes ``0xADD000xx``. See docs/python.md.
"""

from typing import Dict, Literal, NamedTuple, Optional, Tuple, Type

from ._addipos import Handle, Machine, __version__, open

__all__ = [
    "open",
    "Machine",
    "Handle",
    "Position",
    "Element",
    "Error",
    "AccessError",
    "NoObject",
    "NoSubindex",
    "WriteOnly",
    "ReadOnly",
    "TypeMismatch",
    "Range",
    "State",
    "Full",
    "Storage",
    "StaleHandle",
    "NullHandle",
    "Argument",
    "Connection",
    "NotSupported",
    "Timeout",
    "BadHandle",
    "TooManyHandles",
    "Record",
    "Protocol",
    "Stopped",
    "Internal",
    "__version__",
]


class Position(NamedTuple):
    """The executed position of the 8 machine axes (``m.pos()``)."""

    X: float
    Y: float
    Z: float
    A: float
    B: float
    C: float
    U: float
    V: float


class Element(NamedTuple):
    """One element the emulator spooled (``m.take_spooled()``): what the
    correction made of the programmed path."""

    #: ``"LIN"``, ``"RAP"`` or ``"CIR"``.
    kind: Literal["LIN", "RAP", "CIR"]
    #: Where it starts.
    start: Position
    #: Where it ends.
    end: Position
    #: Feed, units/min.
    feed: float
    #: Who spooled it: ``"Uncorrected"``, ``"Approach"``, ``"Corrected"``,
    #: ``"Transition"`` (an outside corner) or ``"Departure"``.
    origin: Literal["Uncorrected", "Approach", "Corrected", "Transition", "Departure"]
    #: An arc: ``True`` counter-clockwise, ``False`` clockwise; a line:
    #: ``None``.
    ccw: Optional[bool]
    #: An arc: its centre in its plane (horizontal, vertical axis of the
    #: plane); a line: ``None``.
    centre: Optional[Tuple[float, float]]


class Error(Exception):
    """A failed call of the library.

    ``code`` is the number the C library returns (``ADDIPOS_E_*``),
    ``name`` the code's name as traces and docs write it, ``message``
    what happened, in words (with the call and the object).
    """

    #: The code of this class (0 on :class:`Error` itself).
    CODE = 0

    def __init__(self, message: str, code: int = 0) -> None:
        super().__init__(message)
        self.message = message
        self.code = code or type(self).CODE

    @property
    def name(self) -> str:
        """The code's name (``"Range"``, ``"StaleHandle"``, ...)."""
        return _NAMES.get(self.code, type(self).__name__)


class AccessError(Error):
    """An access error of the object interface: ``code`` is its CANopen
    abort code (docs/objects.md), the same in a trace's ``err`` answer."""


class NoObject(AccessError):
    """Bus, device or index does not exist (0x06020000)."""

    CODE = 0x06020000


class NoSubindex(AccessError):
    """The index exists, the subindex does not (0x06090011)."""

    CODE = 0x06090011


class WriteOnly(AccessError):
    """Reading a command object (Clean, RESET, Left, ...) (0x06010001)."""

    CODE = 0x06010001


class ReadOnly(AccessError):
    """Writing a read-only object (WearRadius, ...) (0x06010002)."""

    CODE = 0x06010002


class TypeMismatch(AccessError):
    """An i32 object read or written as a double, or the reverse
    (0x06070010)."""

    CODE = 0x06070010


class Range(AccessError):
    """A value outside the object's range, a non-finite double, a
    coordinate beyond ±1e9, a feed too slow (0x06090030)."""

    CODE = 0x06090030


class State(AccessError):
    """Refused in the current state: a faulted group refuses motion until
    ERROR is written (0x08000022)."""

    CODE = 0x08000022


class Full(AccessError):
    """The spooler is full: run ``m.exec`` and send the command again
    (0x05040005)."""

    CODE = 0x05040005


class Storage(AccessError):
    """A server could not store tool data; nothing changed (0x08000020)."""

    CODE = 0x08000020


class StaleHandle(Error):
    """The handle was issued before a Clean, or released: get a new one
    with ``m.init`` (0xADD00001)."""

    CODE = 0xADD00001


class NullHandle(Error):
    """The null handle 0 (0xADD00002); not raised by this package, whose
    handles are never 0."""

    CODE = 0xADD00002


class Argument(Error, ValueError):
    """A bad argument: an axis or word that does not exist, a value that
    is not a number or does not fit, a bad target string (0xADD00003).
    Also a :class:`ValueError`."""

    CODE = 0xADD00003


class Connection(Error, ConnectionError):
    """The connection is closed, lost or refused (0xADD00004). Also a
    :class:`ConnectionError`."""

    CODE = 0xADD00004


class NotSupported(Error):
    """A target this version of the library cannot open (0xADD00005)."""

    CODE = 0xADD00005


class Timeout(Error, TimeoutError):
    """``m.exec`` waited longer than the connection's timeout; what ran
    stays run (0xADD00006). Also a :class:`TimeoutError`."""

    CODE = 0xADD00006


class BadHandle(Error):
    """A handle of another connection (0xADD00007)."""

    CODE = 0xADD00007


class TooManyHandles(Error):
    """65535 handles in use on the connection (0xADD00008)."""

    CODE = 0xADD00008


class Record(Error):
    """A recording cannot start: the file cannot be created, or requests
    ran already (0xADD00009)."""

    CODE = 0xADD00009


class Protocol(Error):
    """A server refused a request as malformed (0xADD0000A)."""

    CODE = 0xADD0000A


class Stopped(Error):
    """The server stopped the request before its end (it is shutting
    down): ``m.exec`` did not run to its end; what ran stays run
    (0xADD0000B)."""

    CODE = 0xADD0000B


class Internal(Error):
    """A fault inside the library; close the connection (0xADD000FF)."""

    CODE = 0xADD000FF


_CLASSES: Dict[int, Type[Error]] = {
    cls.CODE: cls
    for cls in (
        NoObject,
        NoSubindex,
        WriteOnly,
        ReadOnly,
        TypeMismatch,
        Range,
        State,
        Full,
        Storage,
        StaleHandle,
        NullHandle,
        Argument,
        Connection,
        NotSupported,
        Timeout,
        BadHandle,
        TooManyHandles,
        Record,
        Protocol,
        Stopped,
        Internal,
    )
}

_NAMES: Dict[int, str] = {code: cls.__name__ for code, cls in _CLASSES.items()}


def _error(code: int, message: str) -> Error:
    """The exception of a failed call with ``code`` (used by the
    extension module)."""
    return _CLASSES.get(code, Error)(message, code)
