"""Type stubs of the package addipos (docs/python.md)."""

import os
from typing import Dict, List, Literal, NamedTuple, Optional, Tuple, Type, Union, final

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

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Axis = Union[str, int]
#: The direction of an arc (any case; G2 is CW, G3 CCW).
_Direction = Literal["CW", "CCW", "cw", "ccw", "G2", "G3", "G02", "G03"]
#: The kind of a spooled element.
_Kind = Literal["LIN", "RAP", "CIR"]
#: Who spooled an element.
_Origin = Literal["Uncorrected", "Approach", "Corrected", "Transition", "Departure"]

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
    """One element the emulator spooled (``m.take_spooled()``)."""

    kind: _Kind
    start: Position
    end: Position
    feed: float
    origin: _Origin
    ccw: Optional[bool]
    centre: Optional[Tuple[float, float]]

def open(
    target: Optional[str] = None,
    *,
    record: Optional[_Path] = None,
    timeout: Optional[float] = None,
) -> Machine:
    """Opens a connection to ``target`` (``None``: ``$ADDIPOS_TARGET``,
    else ``"embedded"``); ``record``: a trace file the session is recorded
    into; ``timeout``: the longest ``exec`` wait in seconds (30)."""

@final
class Machine:
    """One connection to a TC module (from :func:`open`); a context
    manager that closes it."""

    def __enter__(self) -> Machine: ...
    def __exit__(self, *exc: object) -> bool: ...
    def close(self) -> None:
        """Closes the connection (a wait of another thread ends)."""
    @property
    def closed(self) -> bool:
        """Whether the connection is closed."""
    @property
    def target(self) -> str:
        """The target, as a target string names it."""
    @property
    def realtime(self) -> Optional[float]:
        """The real-time factor, or ``None`` when stepped."""
    def set_timeout(self, seconds: float) -> None:
        """The longest ``exec`` wait, in seconds."""
    # Handles, reads and writes.
    def init(self, bus: int, device: int, index: int, subindex: int) -> Handle:
        """A handle to an object; raises NoObject or NoSubindex."""
    def release(self, h: Handle) -> None:
        """Releases a handle: it raises StaleHandle from now on."""
    def read_int(self, h: Handle) -> int:
        """Reads an i32 object through ``h``."""
    def read_double(self, h: Handle) -> float:
        """Reads a double object through ``h``."""
    def write_int(self, h: Handle, value: int) -> None:
        """Writes an i32 object through ``h``."""
    def write_double(self, h: Handle, value: float) -> None:
        """Writes a double object through ``h``."""
    # Motion and the executor.
    def lin(
        self,
        *,
        X: Optional[float] = ...,
        Y: Optional[float] = ...,
        Z: Optional[float] = ...,
        A: Optional[float] = ...,
        B: Optional[float] = ...,
        C: Optional[float] = ...,
        U: Optional[float] = ...,
        V: Optional[float] = ...,
        F: Optional[float] = ...,
    ) -> None:
        """LIN: a feed line to the axes named; F sets the modal feed."""
    def rap(
        self,
        *,
        X: Optional[float] = ...,
        Y: Optional[float] = ...,
        Z: Optional[float] = ...,
        A: Optional[float] = ...,
        B: Optional[float] = ...,
        C: Optional[float] = ...,
        U: Optional[float] = ...,
        V: Optional[float] = ...,
        F: Optional[float] = ...,
    ) -> None:
        """RAP: a rapid line to the axes named."""
    def cir(
        self,
        direction: _Direction,
        *,
        X: Optional[float] = ...,
        Y: Optional[float] = ...,
        Z: Optional[float] = ...,
        A: Optional[float] = ...,
        B: Optional[float] = ...,
        C: Optional[float] = ...,
        U: Optional[float] = ...,
        V: Optional[float] = ...,
        I: Optional[float] = ...,
        J: Optional[float] = ...,
        K: Optional[float] = ...,
        F: Optional[float] = ...,
    ) -> None:
        """CIR: an arc "CW" or "CCW" to the axes named, centre I J K from
        the start."""
    def ja(
        self,
        *,
        X: Optional[float] = ...,
        Y: Optional[float] = ...,
        Z: Optional[float] = ...,
        A: Optional[float] = ...,
        B: Optional[float] = ...,
        C: Optional[float] = ...,
        U: Optional[float] = ...,
        V: Optional[float] = ...,
    ) -> None:
        """JA: direct positioning of the axes named."""
    def js(self, *axes: _Axis) -> None:
        """JS: direct stop of the axes named."""
    def ssf(self, axis: _Axis, function: int) -> None:
        """SSF: special function to an axis; 2001 spools the held profile."""
    def rs(self) -> None:
        """rs(): the coordinate rotation back to 0."""
    def exec(self, cycles: Optional[int] = None) -> None:
        """EXEC: runs ``cycles`` cycles, ``None`` until the spooler is
        empty; raises Timeout after the timeout."""
    def pos(self) -> Position:
        """The executed position of the 8 axes."""
    def queue(self) -> int:
        """Motion waiting in the spooler."""
    # The spool log.
    def spool_log(self, on: bool) -> None:
        """Keeps the elements spooled from now on, or stops keeping them."""
    def take_spooled(self) -> List[Element]:
        """The elements spooled since the last call."""
    # Recording.
    def record(self, path: _Path) -> None:
        """Records the session into ``path``; before the first request."""
    def stop_recording(self) -> None:
        """Ends the recording."""
    @property
    def recording(self) -> bool:
        """Whether a recording goes on."""
    @property
    def record_failure(self) -> Optional[str]:
        """Why the recording stopped or did not start, if it did."""

@final
class Handle:
    """A handle to one object of a connection (from ``Machine.init``)."""

    def read_int(self) -> int:
        """Reads an i32 object."""
    def read_double(self) -> float:
        """Reads a double object."""
    def write_int(self, value: int) -> None:
        """Writes an i32 object."""
    def write_double(self, value: float) -> None:
        """Writes a double object."""
    def read(self) -> Union[int, float]:
        """Reads the object as its type says."""
    def write(self, value: Union[int, float]) -> None:
        """Writes the object as its type says."""
    def release(self) -> None:
        """Releases the handle."""
    @property
    def descriptor(self) -> Tuple[int, int, int, int]:
        """(bus, device, index, subindex)."""
    @property
    def value_type(self) -> Literal["int", "double"]:
        """"int" or "double"."""
    @property
    def number(self) -> int:
        """The library's handle number."""

class Error(Exception):
    """A failed call: ``code``, ``name``, ``message``."""

    CODE: int
    code: int
    message: str
    def __init__(self, message: str, code: int = 0) -> None: ...
    @property
    def name(self) -> str: ...

class AccessError(Error):
    """An access error of the object interface (CANopen code)."""

class NoObject(AccessError): ...
class NoSubindex(AccessError): ...
class WriteOnly(AccessError): ...
class ReadOnly(AccessError): ...
class TypeMismatch(AccessError): ...
class Range(AccessError): ...
class State(AccessError): ...
class Full(AccessError): ...
class Storage(AccessError): ...
class StaleHandle(Error): ...
class NullHandle(Error): ...
class Argument(Error, ValueError): ...
class Connection(Error, ConnectionError): ...
class NotSupported(Error): ...
class Timeout(Error, TimeoutError): ...
class BadHandle(Error): ...
class TooManyHandles(Error): ...
class Record(Error): ...
class Protocol(Error): ...
class Stopped(Error): ...
class Internal(Error): ...

_CLASSES: Dict[int, Type[Error]]
_NAMES: Dict[int, str]

def _error(code: int, message: str) -> Error: ...
