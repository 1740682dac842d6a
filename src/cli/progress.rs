//! Progress bars on standard error, only when it is a terminal: replays
//! and plots of long work say how far they are, at what rate, and how long
//! is left; output redirected to a file or a CI log stays free of them.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How often a bar is redrawn at most (a tenth of a second is smooth
/// enough to read, and costs nothing next to the work).
const REDRAW_HZ: u8 = 10;

/// A bar counting `total` bytes, or a hidden one when standard error is not
/// a terminal.
pub fn bytes_bar(total: u64) -> ProgressBar {
    bar(
        total,
        "{spinner} [{elapsed_precise}] {wide_bar} {bytes}/{total_bytes} \
         {binary_bytes_per_sec}, {eta} left  {msg}",
    )
}

/// A bar counting `total` items of `unit`, or a hidden one when standard
/// error is not a terminal.
pub fn count_bar(total: u64, unit: &str) -> ProgressBar {
    let template = format!(
        "{{spinner}} [{{elapsed_precise}}] {{wide_bar}} {{human_pos}}/{{human_len}} {unit} \
         {{per_sec}}, {{eta}} left  {{msg}}"
    );
    bar(total, &template)
}

fn bar(total: u64, template: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let pb =
        ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr_with_hz(REDRAW_HZ));
    if let Ok(style) = ProgressStyle::with_template(template) {
        pb.set_style(style);
    }
    pb.enable_steady_tick(Duration::from_millis(1000 / u64::from(REDRAW_HZ)));
    pb
}
