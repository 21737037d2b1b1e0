//! Progress bars on standard error: drawn only on a terminal, and only once a run has
//! taken longer than a second.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A bar over `seconds` of simulated time (position in milliseconds), hidden until the
/// run loop reveals it after a second of wall time.
pub fn bar(seconds: f64, what: &str) -> ProgressBar {
    let bar =
        ProgressBar::with_draw_target(Some((seconds * 1e3) as u64), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:40}] {pos}/{len} ms simulated, {elapsed_precise} elapsed, eta {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// A bar over `len` items (e.g. the runs of a sweep), on stderr unless `quiet`; indicatif
/// draws nothing when stderr is not a terminal.
pub fn count_bar(len: u64, unit: &str, quiet: bool) -> ProgressBar {
    let target = if quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let bar = ProgressBar::with_draw_target(Some(len), target);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{msg}} [{{bar:40}}] {{pos}}/{{len}} {unit}, {{elapsed_precise}} elapsed, eta {{eta}}"
        ))
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}
