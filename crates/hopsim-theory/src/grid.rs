//! Parallel evaluation of grids (rayon) that reports progress through a callback, so that
//! callers draw whatever progress display they like (a bar, a log line, nothing).

use rayon::prelude::*;

/// Called once for every finished grid cell, from any worker thread.
pub type CellDone<'a> = &'a (dyn Fn() + Sync);

/// A [`CellDone`] that ignores every report.
pub const NO_PROGRESS: CellDone<'static> = &|| {};

/// Maps `f` over `items` on all cores, calling `progress` once per finished item; the
/// result keeps the order of `items`.
pub fn par_map<T, R, F>(items: &[T], progress: CellDone<'_>, f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    items
        .par_iter()
        .map(|item| {
            let r = f(item);
            progress();
            r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn keeps_order_and_reports_every_item() {
        let done = AtomicUsize::new(0);
        let items: Vec<u64> = (0..1000).collect();
        let squares = par_map(
            &items,
            &|| {
                done.fetch_add(1, Ordering::Relaxed);
            },
            |x| x * x,
        );
        assert_eq!(squares, items.iter().map(|x| x * x).collect::<Vec<_>>());
        assert_eq!(done.load(Ordering::Relaxed), 1000);
    }
}
