//! The C side of the host library: the example of examples/c (the
//! manual's "Using TC" sequence) and the failure-path program built with
//! the system C compiler against libaddipos and run on an embedded
//! emulator, stepped and in real time, and against a running `addipos
//! serve` (stepped and in real time): the same spooled path and final
//! position; recorded runs of the example replayed with `addipos replay`.

// Setups may stop loudly.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The folder of the libaddipos this test was built with. Cargo builds
/// it as this package's dev-dependency into `target/<profile>/deps/`,
/// beside the test itself; `cargo build -p libaddipos` puts it one
/// folder up. Built with cargo if it is in neither.
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap().to_path_buf();
    let profile = deps.parent().unwrap().to_path_buf();
    if let Some(dir) = [&deps, &profile]
        .into_iter()
        .find(|d| d.join(shared_library()).exists())
    {
        return dir.clone();
    }
    let status = Command::new(env!("CARGO"))
        .args(["build", "-p", "libaddipos", "--lib"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .status()
        .unwrap();
    assert!(status.success(), "cargo build -p libaddipos");
    profile
}

fn shared_library() -> &'static str {
    if cfg!(target_os = "macos") {
        "libaddipos.dylib"
    } else {
        "libaddipos.so"
    }
}

/// `examples/c/NAME.c` built with `cc` against the library, into `out`.
fn build(name: &str, out: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib = library_dir();
    let exe = out.join(name);
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let result = Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"])
        .arg("-I")
        .arg(root.join("libaddipos/include"))
        .arg(root.join("examples/c").join(format!("{name}.c")))
        .arg("-o")
        .arg(&exe)
        .arg("-L")
        .arg(&lib)
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-laddipos")
        .output()
        .unwrap_or_else(|e| panic!("{cc}: {e}"));
    assert!(
        result.status.success(),
        "{cc} {name}.c: {}",
        text(&result.stderr)
    );
    exe
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs a built program with `args` and `env`.
fn run(exe: &Path, args: &[&str], env: &[(&str, &Path)]) -> Output {
    let mut cmd = Command::new(exe);
    cmd.args(args)
        .env_remove("ADDIPOS_TARGET")
        .env_remove("ADDIPOS_RECORD");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().unwrap()
}

/// The corrected path of the example, worked out by hand (docs/trc.md):
/// tool radius 2 on the left of the square (0,0)-(20,0)-(20,20)-(0,20)
/// driven counter-clockwise, so the tool centre runs 2 inside it. The
/// first side is held; the second spools the approach from (0,0) to the
/// inside corner (18,2); the third and fourth the corners (18,18) and
/// (2,18); STATUS = 0 the held last side to (2,0); the rapid the
/// departure to (-5,-5).
const PATH: [&str; 5] = [
    "< LIN X18 Y2",
    "< LIN X18 Y18",
    "< LIN X2 Y18",
    "< LIN X2 Y0",
    "< LIN X-5 Y-5",
];

/// The example's output: where the machine stands, no error bit.
const OUTPUT: &str = "position X-5 Y-5 Z0\nERROR 0\n";

fn spooled(trace_text: &str) -> Vec<&str> {
    trace_text.lines().filter(|l| l.starts_with('<')).collect()
}

fn replay_passes(file: &Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("replay")
        .arg(file)
        .output()
        .unwrap();
    let said = text(&out.stdout);
    assert!(
        out.status.success(),
        "addipos replay {}: {said}",
        file.display()
    );
    assert!(said.contains("1 passed, 0 failed"), "{said}");
}

#[test]
fn the_example_runs_on_an_embedded_emulator_and_its_recording_replays() {
    let dir = tempfile::tempdir().unwrap();
    let exe = build("using_tc", dir.path());
    let record = dir.path().join("using_tc.trace");
    let out = run(&exe, &[], &[("ADDIPOS_RECORD", &record)]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), OUTPUT);
    let trace = std::fs::read_to_string(&record).unwrap();
    assert_eq!(spooled(&trace), PATH, "{trace}");
    replay_passes(&record);
}

#[test]
fn in_real_time_the_example_gives_the_same_path_and_position() {
    let dir = tempfile::tempdir().unwrap();
    let exe = build("using_tc", dir.path());
    let record = dir.path().join("realtime.trace");
    let out = run(
        &exe,
        &["embedded:realtime=100"],
        &[("ADDIPOS_RECORD", &record)],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), OUTPUT);
    let trace = std::fs::read_to_string(&record).unwrap();
    assert_eq!(spooled(&trace), PATH, "{trace}");
    replay_passes(&record);
}

#[test]
fn the_target_can_come_from_the_environment() {
    let dir = tempfile::tempdir().unwrap();
    let exe = build("using_tc", dir.path());
    let out = Command::new(&exe)
        .env("ADDIPOS_TARGET", "embedded:realtime=200")
        .env_remove("ADDIPOS_RECORD")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), OUTPUT);
    let out = Command::new(&exe)
        .env("ADDIPOS_TARGET", "nowhere:")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("ADDIPOS_TARGET"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn no_misuse_crashes_or_hangs() {
    let dir = tempfile::tempdir().unwrap();
    let exe = build("failure_paths", dir.path());
    let out = run(&exe, &[], &[]);
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(said.ends_with(" passed, 0 failed\n"), "{said}");
    // The same checks with the connection under test on a server.
    let server = common::ServeProcess::start(&["--listen", "127.0.0.1:0"], &[]);
    let out = run(&exe, &[&server.addr], &[]);
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(said.ends_with(" passed, 0 failed\n"), "{said}");
    server.stop();
}

#[test]
fn against_a_server_the_example_gives_the_same_path_and_position() {
    let dir = tempfile::tempdir().unwrap();
    let exe = build("using_tc", dir.path());
    for realtime in [None, Some("20")] {
        let served = dir.path().join("served.trace");
        let lib = dir.path().join("lib.trace");
        let mut args = vec!["--listen", "127.0.0.1:0", "--record"];
        args.push(served.to_str().unwrap());
        if let Some(f) = realtime {
            args.extend(["--realtime", f]);
        }
        let server = common::ServeProcess::start(&args, &[]);
        let port = server.addr.rsplit_once(':').unwrap().1.to_string();
        let out = run(&exe, &[&port], &[("ADDIPOS_RECORD", &lib)]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert_eq!(text(&out.stdout), OUTPUT, "{realtime:?}");
        let (status, log) = server.terminate(std::time::Duration::from_secs(20));
        assert!(status.success(), "{log}");
        // The server's own recording: what its emulator spooled.
        let trace = std::fs::read_to_string(&served).unwrap();
        assert_eq!(spooled(&trace), PATH, "{trace}");
        replay_passes(&served);
        // The library's recording of the same run.
        let trace = std::fs::read_to_string(&lib).unwrap();
        assert_eq!(spooled(&trace), PATH, "{trace}");
        assert!(!trace.contains("# WARNING"), "{trace}");
        replay_passes(&lib);
    }
}

/// A C (or C++) file that includes the header and uses what it declares:
/// every code is an unsigned constant, the library's internals stay out.
const HEADER_USE: &str = r#"#include "addipos.h"
#ifdef QUEUE_CHUNKS
#error "an internal macro of the library leaks into the program"
#endif
static unsigned check(addipos *a)
{
    unsigned long code = ADDIPOS_E_INTERNAL;
    uoi_handle h = 0;
    uoi_descriptor d = {1300, 0, 3, 0};
    if (uoi_init(a, &d, &h) != ADDIPOS_OK) {
        return (unsigned)(code == 0xADD000FFul);
    }
    return ADDIPOS_E_STOPPED + 0u * ADDIPOS_E_NO_OBJECT;
}
int main(void)
{
    return (int)(check(addipos_open(0)) & 1u);
}
"#;

/// The header compiles as C89, C99 and C++98 (and C++17) with every
/// warning an error: no `//` comments in C89, no decimal codes above
/// INT32_MAX, no unprefixed internal macro. A language whose compiler is
/// missing is skipped with a line saying so.
#[test]
fn the_header_compiles_clean_as_c89_c99_and_cpp() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let include = root.join("libaddipos/include");
    let c = dir.path().join("use.c");
    let cpp = dir.path().join("use.cpp");
    std::fs::write(&c, HEADER_USE).unwrap();
    std::fs::write(&cpp, HEADER_USE).unwrap();
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let cxx = std::env::var("CXX").unwrap_or_else(|_| "c++".into());
    let cases = [
        (&cc, "-std=c89", &c),
        (&cc, "-std=c99", &c),
        (&cxx, "-std=c++98", &cpp),
        (&cxx, "-std=c++17", &cpp),
    ];
    for (compiler, std, file) in cases {
        let out = Command::new(compiler)
            .args([std, "-Wall", "-Wextra", "-pedantic", "-Werror", "-c"])
            .arg("-I")
            .arg(&include)
            .arg(file)
            .arg("-o")
            .arg(dir.path().join("use.o"))
            .output();
        let out = match out {
            Ok(o) => o,
            Err(e) => {
                eprintln!("skipped {std}: {compiler} cannot be run ({e})");
                continue;
            }
        };
        assert!(
            out.status.success(),
            "{compiler} {std}: {}",
            text(&out.stderr)
        );
    }
}
