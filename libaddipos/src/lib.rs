//! # libaddipos — the C ABI of the host library
//!
//! `libaddipos.so` / `libaddipos.a`, declared in `include/addipos.h`
//! (generated from this file by cbindgen, its codes from the host
//! library's [`ErrorCode`] table; docs/host-api.md). A thin layer over
//! [`Machine`] of `addipos_host`: it reads and writes through the
//! pointers a C program hands over, turns results into codes, and
//! catches every panic at the boundary (`ADDIPOS_E_INTERNAL`).
//!
//! An `addipos *` is a token of the connection registry
//! (the library's registry), never followed as a pointer: NULL is
//! `ADDIPOS_E_ARGUMENT`, a closed or made-up one `ADDIPOS_E_CONNECTION`.

// The one crate allowed `unsafe`: a C caller's pointers (target and
// path strings, descriptors, axis arrays, out parameters) can only be
// read and written through raw pointers, and exported symbols need
// `#[no_mangle]`. Each unsafe block is one pointer access, with the
// caller's promise it rests on beside it.
#![allow(unsafe_code)]

use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::Duration;

use addipos_host::{
    ArcDir, AxisWords, Descriptor, Error, ErrorCode, Handle, Machine, Result, AXES,
};

mod registry;

/// One connection (opaque): what `addipos_open` returns.
pub struct Addipos {
    _opaque: [u8; 0],
}

/// A handle to one object of one connection; 0 is the null handle.
pub type UoiHandle = u32;

/// Success (`ADDIPOS_OK`). The error codes `ADDIPOS_E_*` of the header
/// are the host library's table ([`ErrorCode`]), written into the header
/// from it (tests/header.rs).
const OK: u32 = 0;

/// `tc_exec`: run until the spooler is empty.
pub const ADDIPOS_EXEC_ALL: u64 = u64::MAX;
/// Machine axes: X Y Z A B C U V, the length of every position array.
pub const ADDIPOS_AXES: u32 = 8;

/// The library's version, e.g. `"0.1.0"`.
const VERSION: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(v) => v,
        Err(_) => c"unknown",
    };

thread_local! {
    /// Why the last `addipos_open` of this thread returned NULL.
    static OPEN_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Runs `f`, a panic turned into `ADDIPOS_E_INTERNAL`.
fn guard(f: impl FnOnce() -> u32) -> u32 {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(ErrorCode::Internal.code())
}

/// The code of a result.
fn code(r: Result<()>) -> u32 {
    match r {
        Ok(()) => OK,
        Err(e) => e.code().code(),
    }
}

/// Runs `f` on the connection `a`; NULL is `ADDIPOS_E_ARGUMENT`, a token
/// that names no open connection `ADDIPOS_E_CONNECTION`.
fn on(a: *const Addipos, f: impl FnOnce(&Machine) -> Result<()>) -> u32 {
    guard(|| {
        if a.is_null() {
            return ErrorCode::Argument.code();
        }
        match registry::get(a.addr()) {
            Some(m) => code(f(&m)),
            None => ErrorCode::Connection.code(),
        }
    })
}

/// A bad argument, kept as the connection's last failure.
fn refuse(m: &Machine, message: String) -> Result<()> {
    m.refuse(Error::argument(message))
}

/// The text of a C string, if it is UTF-8.
fn text_of(s: *const c_char) -> Option<String> {
    if s.is_null() {
        return None;
    }
    // SAFETY: not NULL; the caller promises a NUL-terminated string that
    // stays valid for the call.
    let c = unsafe { CStr::from_ptr(s) };
    c.to_str().ok().map(str::to_string)
}

/// The 8 doubles at `p`, if `p` is not NULL.
fn axes_at(p: *const f64) -> Option<[f64; AXES]> {
    // SAFETY: the caller promises `p` is NULL or points to 8 readable,
    // aligned doubles; `as_ref` answers None for NULL.
    unsafe { p.cast::<[f64; AXES]>().as_ref() }.copied()
}

/// The 3 doubles at `p`, if `p` is not NULL.
fn ijk_at(p: *const f64) -> Option<[f64; 3]> {
    // SAFETY: the caller promises `p` is NULL or points to 3 readable,
    // aligned doubles.
    unsafe { p.cast::<[f64; 3]>().as_ref() }.copied()
}

/// Writes `value` to `out`; false when `out` is NULL.
fn put<T>(out: *mut T, value: T) -> bool {
    // SAFETY: the caller promises `out` is NULL or points to a writable,
    // aligned `T` (a `T[n]` for an array) that no one else uses during
    // the call.
    match unsafe { out.as_mut() } {
        Some(slot) => {
            *slot = value;
            true
        }
        None => false,
    }
}

/// Axis words from a mask and a position array (bit i: `pos[i]` given);
/// a mask beyond the axes, or a NULL array for a mask that names some, is
/// a bad argument.
fn words(call: &str, mask: u32, pos: *const f64) -> Result<AxisWords> {
    if mask >> AXES != 0 {
        return Err(Error::argument(format!(
            "{call}: mask 0x{mask:x} names axes beyond 7 (bits 0..7 are X Y Z A B C U V)"
        )));
    }
    let mut w: AxisWords = [None; AXES];
    if mask == 0 {
        return Ok(w);
    }
    let p = axes_at(pos)
        .ok_or_else(|| Error::argument(format!("{call}: pos is NULL but mask names axes")))?;
    for (i, slot) in w.iter_mut().enumerate() {
        if mask & (1 << i) != 0 {
            *slot = Some(p[i]);
        }
    }
    Ok(w)
}

/// A feed: 0 is the modal one; a negative feed (and NaN) is handed on,
/// and refused with Range, as in Python (docs/host-api.md, decision 384).
fn feed_of(feed: f64) -> Option<f64> {
    (feed != 0.0).then_some(feed)
}

/// The handle `h`, or the null-handle failure.
fn handle(m: &Machine, h: UoiHandle, call: &str) -> Result<Handle> {
    match Handle::from_raw(h) {
        Some(h) => Ok(h),
        None => Err(m.refuse_with(Error::new(
            ErrorCode::NullHandle,
            format!("{call}: the null handle 0 (initialise the object with uoi_init first)"),
        ))),
    }
}

/// The library's version, `"MAJOR.MINOR.PATCH"` (static).
#[no_mangle]
pub extern "C" fn addipos_version() -> *const c_char {
    VERSION.as_ptr()
}

/// Opens a connection. `target` NULL or `""`: `$ADDIPOS_TARGET` if set,
/// else an embedded emulator with the built-in settings, stepped.
/// `"embedded"`, `"embedded:realtime"`, `"embedded:realtime=10"`,
/// `"embedded:config=FILE"` (options joined by commas): an emulator
/// inside this process. `"HOST:PORT"`, `"localhost:PORT"` or a bare
/// port: a running `addipos serve` (options `,token=TOKEN` or
/// `,token_file=FILE` give its access token; else `$ADDIPOS_TOKEN_FILE`
/// or `$ADDIPOS_TOKEN`). With `$ADDIPOS_RECORD` set,
/// the connection records its session as a trace into that file. NULL on
/// failure: `addipos_open_error()` says why.
///
/// # Safety
///
/// `target` is NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn addipos_open(target: *const c_char) -> *mut Addipos {
    let opened = catch_unwind(AssertUnwindSafe(|| {
        let text = if target.is_null() {
            String::new()
        } else {
            text_of(target).ok_or_else(|| Error::argument("addipos_open: target is not UTF-8"))?
        };
        let machine = Machine::open(&text)?;
        registry::insert(machine)
            .ok_or_else(|| Error::new(ErrorCode::Connection, "addipos_open: too many connections"))
    }));
    let result = opened.unwrap_or_else(|_| Err(Error::new(ErrorCode::Internal, "panic")));
    let message = match &result {
        Ok(_) => String::new(),
        Err(e) => e.message().replace('\0', " "),
    };
    OPEN_ERROR.with(|o| *o.borrow_mut() = CString::new(message).unwrap_or_default());
    match result {
        Ok(token) => std::ptr::without_provenance_mut(token),
        Err(_) => std::ptr::null_mut(),
    }
}

/// Why the last `addipos_open` of this thread returned NULL (`""` after
/// one that succeeded). Valid until this thread's next `addipos_open`.
#[no_mangle]
pub extern "C" fn addipos_open_error() -> *const c_char {
    OPEN_ERROR.with(|o| o.borrow().as_ptr())
}

/// Closes a connection: a wait in progress on it ends, the recording is
/// written out, and the connection goes once no call uses it any more.
/// NULL and a closed connection are allowed (nothing happens).
#[no_mangle]
pub extern "C" fn addipos_close(a: *mut Addipos) {
    guard(|| {
        if let Some(m) = registry::remove(a.addr()) {
            m.close();
        }
        OK
    });
}

/// The last failure on this connection, in words (`""` if none). The
/// text stays valid until the next failed call on the connection or its
/// close; a program that shares the connection between threads should
/// use `addipos_error_copy`. A NULL or closed connection gives a static
/// text.
#[no_mangle]
pub extern "C" fn addipos_error_text(a: *const Addipos) -> *const c_char {
    if a.is_null() {
        return c"".as_ptr();
    }
    let text = catch_unwind(|| registry::get(a.addr()).map(|m| m.with_failure(|t| t.as_ptr())));
    match text {
        Ok(Some(p)) => p,
        Ok(None) => c"not an open connection (closed, or not returned by addipos_open)".as_ptr(),
        Err(_) => c"internal fault".as_ptr(),
    }
}

/// Copies the last failure's text into `buf` (at most `size` bytes,
/// NUL included, cut if longer); returns the text's full length, without
/// the NUL. Ask for the size first: with `size` 0 (or `buf` NULL) nothing
/// is copied and the length is returned, so a buffer of length + 1 bytes
/// holds the whole text. For a NULL or closed connection, copies nothing
/// and returns 0.
///
/// # Safety
///
/// `buf` is NULL or points to `size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn addipos_error_copy(
    a: *const Addipos,
    buf: *mut c_char,
    size: usize,
) -> usize {
    let copied = catch_unwind(AssertUnwindSafe(|| {
        let m = registry::get(a.addr())?;
        let text = m.last_failure();
        let Some(room) = size.checked_sub(1).filter(|_| !buf.is_null()) else {
            return Some(text.len());
        };
        let n = text.len().min(room);
        // SAFETY: `buf` is not NULL and holds `size` bytes (the caller's
        // promise); `n + 1 <= size`, and `text` is our own string.
        unsafe {
            std::ptr::copy_nonoverlapping(text.as_ptr().cast::<c_char>(), buf, n);
            *buf.add(n) = 0;
        }
        Some(text.len())
    }));
    copied.ok().flatten().unwrap_or(0)
}

/// Records this connection's session as a trace into the file `path`
/// (created or emptied), before its first request; `path` NULL stops the
/// recording and writes it out. A write error later stops the recording
/// (the call goes on; `addipos_error_text` says why, `addipos_recording`
/// answers 0).
///
/// # Safety
///
/// `path` is NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn addipos_record(a: *mut Addipos, path: *const c_char) -> u32 {
    on(a, |m| {
        if path.is_null() {
            m.stop_recording();
            return Ok(());
        }
        match text_of(path) {
            Some(p) => m.record(Path::new(&p)),
            None => refuse(m, "addipos_record: path is not UTF-8".into()),
        }
    })
}

/// 1 while the connection records its session, else 0.
#[no_mangle]
pub extern "C" fn addipos_recording(a: *const Addipos) -> c_int {
    let on = catch_unwind(|| registry::get(a.addr()).is_some_and(|m| m.recording()));
    c_int::from(on.unwrap_or(false))
}

/// How long `tc_exec` may wait, in milliseconds (default 30000).
#[no_mangle]
pub extern "C" fn addipos_set_timeout(a: *mut Addipos, ms: u32) -> u32 {
    on(a, |m| {
        m.set_timeout(Duration::from_millis(ms.into()));
        Ok(())
    })
}

/// Initialises a handle to the object `d` names. Refuses an object that
/// does not exist (`ADDIPOS_E_NO_OBJECT`, `ADDIPOS_E_NO_SUBINDEX`); `*h`
/// is then 0. The handle belongs to this connection and is void after a
/// Clean.
///
/// # Safety
///
/// `d` is NULL or points to a readable `uoi_descriptor`; `h` is NULL or
/// points to a writable `uoi_handle`.
#[no_mangle]
pub unsafe extern "C" fn uoi_init(a: *mut Addipos, d: *const Descriptor, h: *mut UoiHandle) -> u32 {
    on(a, |m| {
        // SAFETY: the caller promises `d` is NULL or a readable descriptor.
        let Some(d) = (unsafe { d.as_ref() }).copied() else {
            return refuse(m, "uoi_init: the descriptor is NULL".into());
        };
        if !put(h, 0) {
            return refuse(m, "uoi_init: the handle pointer is NULL".into());
        }
        let handle = m.handle(&d)?;
        put(h, handle.raw());
        Ok(())
    })
}

/// Releases a handle and sets `*h` to 0 (0 itself is allowed: nothing
/// happens). The handle answers `ADDIPOS_E_STALE_HANDLE` from then on.
///
/// # Safety
///
/// `h` is NULL or points to a readable and writable `uoi_handle`.
#[no_mangle]
pub unsafe extern "C" fn uoi_clean_handle(a: *mut Addipos, h: *mut UoiHandle) -> u32 {
    on(a, |m| {
        // SAFETY: the caller promises `h` is NULL or a readable handle.
        let Some(raw) = (unsafe { h.as_ref() }).copied() else {
            return refuse(m, "uoi_clean_handle: the handle pointer is NULL".into());
        };
        if let Some(handle) = Handle::from_raw(raw) {
            m.release(handle)?;
        }
        put(h, 0);
        Ok(())
    })
}

/// Reads an i32 object through its handle.
///
/// # Safety
///
/// `value` is NULL or points to a writable `int32_t`.
#[no_mangle]
pub unsafe extern "C" fn uoi_read_int(a: *mut Addipos, h: UoiHandle, value: *mut i32) -> u32 {
    on(a, |m| {
        if value.is_null() {
            return refuse(m, "uoi_read_int: value is NULL".into());
        }
        let v = m.read_int(handle(m, h, "uoi_read_int")?)?;
        put(value, v);
        Ok(())
    })
}

/// Writes an i32 object through its handle.
#[no_mangle]
pub extern "C" fn uoi_write_int(a: *mut Addipos, h: UoiHandle, value: i32) -> u32 {
    on(a, |m| m.write_int(handle(m, h, "uoi_write_int")?, value))
}

/// Reads a double object through its handle (an i32 object:
/// `ADDIPOS_E_TYPE_MISMATCH`).
///
/// # Safety
///
/// `value` is NULL or points to a writable `double`.
#[no_mangle]
pub unsafe extern "C" fn uoi_read_double(a: *mut Addipos, h: UoiHandle, value: *mut f64) -> u32 {
    on(a, |m| {
        if value.is_null() {
            return refuse(m, "uoi_read_double: value is NULL".into());
        }
        let v = m.read_double(handle(m, h, "uoi_read_double")?)?;
        put(value, v);
        Ok(())
    })
}

/// Writes a double object through its handle.
#[no_mangle]
pub extern "C" fn uoi_write_double(a: *mut Addipos, h: UoiHandle, value: f64) -> u32 {
    on(a, |m| {
        m.write_double(handle(m, h, "uoi_write_double")?, value)
    })
}

/// Runs `f` with the axis words of `mask` and `pos`, or refuses them.
fn with_words(
    m: &Machine,
    call: &str,
    mask: u32,
    pos: *const f64,
    f: impl FnOnce(AxisWords) -> Result<()>,
) -> Result<()> {
    match words(call, mask, pos) {
        Ok(w) => f(w),
        Err(e) => m.refuse(e),
    }
}

/// Spools a feed line to the axes of `mask` (bit i: `pos[i]` given, 0 X
/// .. 7 V; others keep their value); `feed` 0: the modal feed (a
/// negative feed is `ADDIPOS_E_RANGE`).
///
/// # Safety
///
/// `pos` is NULL (only with `mask` 0) or points to 8 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn tc_lin(a: *mut Addipos, mask: u32, pos: *const f64, feed: f64) -> u32 {
    on(a, |m| {
        with_words(m, "tc_lin", mask, pos, |w| m.lin(w, feed_of(feed)))
    })
}

/// Spools a rapid line to the axes of `mask`.
///
/// # Safety
///
/// `pos` is NULL (only with `mask` 0) or points to 8 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn tc_rap(a: *mut Addipos, mask: u32, pos: *const f64) -> u32 {
    on(a, |m| {
        with_words(m, "tc_rap", mask, pos, |w| m.rap(w, None))
    })
}

/// Spools an arc in the main plane, counter-clockwise when `ccw` is not
/// 0: end point from `mask`/`pos`, centre offsets `I J K` from the start
/// from `ijk_mask` (bits 0..2) and `ijk`; `feed` 0: the modal feed (a
/// negative feed is `ADDIPOS_E_RANGE`).
///
/// # Safety
///
/// `pos` is NULL (only with `mask` 0) or points to 8 readable doubles;
/// `ijk` is NULL (only with `ijk_mask` 0) or points to 3 readable
/// doubles.
#[no_mangle]
pub unsafe extern "C" fn tc_cir(
    a: *mut Addipos,
    ccw: c_int,
    mask: u32,
    pos: *const f64,
    ijk_mask: u32,
    ijk: *const f64,
    feed: f64,
) -> u32 {
    on(a, |m| {
        if ijk_mask >> 3 != 0 {
            return refuse(
                m,
                format!("tc_cir: ijk_mask 0x{ijk_mask:x} beyond bits 0..2 (I J K)"),
            );
        }
        let centre = match (ijk_mask, ijk_at(ijk)) {
            (0, _) => [None; 3],
            (_, None) => return refuse(m, "tc_cir: ijk is NULL but ijk_mask names words".into()),
            (bits, Some(v)) => std::array::from_fn(|k| (bits & (1 << k) != 0).then_some(v[k])),
        };
        let dir = if ccw != 0 { ArcDir::Ccw } else { ArcDir::Cw };
        with_words(m, "tc_cir", mask, pos, |w| {
            m.cir(dir, w, centre, feed_of(feed))
        })
    })
}

/// Direct positioning (JA) of the axes of `mask`: what waits in the
/// spooler and the correction buffer is dropped.
///
/// # Safety
///
/// `pos` is NULL (only with `mask` 0) or points to 8 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn tc_ja(a: *mut Addipos, mask: u32, pos: *const f64) -> u32 {
    on(a, |m| with_words(m, "tc_ja", mask, pos, |w| m.ja(w)))
}

/// Direct stop (JS) of the axes of `mask`.
#[no_mangle]
pub extern "C" fn tc_js(a: *mut Addipos, mask: u32) -> u32 {
    on(a, |m| {
        if mask >> AXES != 0 {
            return refuse(m, format!("tc_js: mask 0x{mask:x} names axes beyond 7"));
        }
        m.js(std::array::from_fn(|i| mask & (1 << i) != 0))
    })
}

/// Special function `function` to machine axis `axis` (0..7); 2001
/// spools the held profile (SSF 2001).
#[no_mangle]
pub extern "C" fn tc_ssf(a: *mut Addipos, axis: u32, function: i32) -> u32 {
    on(a, |m| m.ssf(axis as usize, function))
}

/// The legacy `rs()`: coordinate rotation back to angle 0, centre 0.
#[no_mangle]
pub extern "C" fn tc_rs(a: *mut Addipos) -> u32 {
    on(a, |m| m.rs())
}

/// Runs the executor `cycles` interpolation cycles, `ADDIPOS_EXEC_ALL`
/// until the spooler is empty. Stepped: runs them now. In real time:
/// waits until the clock has run them (or the spooler is empty), never
/// ahead of the clock. Returns at the latest after the connection's
/// timeout with `ADDIPOS_E_TIMEOUT`; what ran stays run. A server that
/// shuts down during the wait answers `ADDIPOS_E_STOPPED` (the motion did
/// not run to its end); `addipos_close` from another thread ends the wait
/// at once with `ADDIPOS_E_CONNECTION`.
#[no_mangle]
pub extern "C" fn tc_exec(a: *mut Addipos, cycles: u64) -> u32 {
    let cycles = (cycles != ADDIPOS_EXEC_ALL).then_some(cycles);
    on(a, |m| m.exec(cycles))
}

/// The executed position of the 8 axes into `pos`.
///
/// # Safety
///
/// `pos` is NULL or points to 8 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn tc_pos(a: *mut Addipos, pos: *mut f64) -> u32 {
    on(a, |m| {
        if pos.is_null() {
            return refuse(m, "tc_pos: pos is NULL".into());
        }
        let p = m.position()?;
        put(pos.cast::<[f64; AXES]>(), p);
        Ok(())
    })
}

/// Motion waiting into `*len`: elements in the spooler, plus plane-null
/// profiles waiting with the held profile.
///
/// # Safety
///
/// `len` is NULL or points to a writable `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn tc_queue(a: *mut Addipos, len: *mut u32) -> u32 {
    on(a, |m| {
        if len.is_null() {
            return refuse(m, "tc_queue: len is NULL".into());
        }
        let n = m.queue()?;
        put(len, u32::try_from(n).unwrap_or(u32::MAX));
        Ok(())
    })
}
