//! Parallel grid evaluation with a progress bar (rayon + indicatif).
//!
//! The bar is drawn on standard error only when standard error is a terminal, so piped
//! output, tests and CI stay clean. Grid analyses (the Cargo template grid, the obstacle
//! region maps, and later ones such as Robbit fixed points) share [`par_map_progress`].

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::io::IsTerminal;

/// A progress bar over `len` items labelled `message`; hidden unless stderr is a terminal.
pub fn progress_bar(len: usize, message: &str) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(len as u64), target);
    if let Ok(style) = ProgressStyle::with_template(
        "{msg} [{bar:40}] {pos}/{len} cells, {elapsed_precise} elapsed, eta {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(message.to_string());
    bar
}

/// A bar that never draws (for library callers and tests).
pub fn hidden_bar() -> ProgressBar {
    ProgressBar::hidden()
}

/// Maps `f` over `items` on all cores (rayon), advancing `bar` once per item; the result
/// keeps the order of `items`. The bar is finished (and cleared) at the end.
pub fn par_map_progress<T, R, F>(items: &[T], bar: &ProgressBar, f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    let out = items
        .par_iter()
        .map(|item| {
            let r = f(item);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    out
}
