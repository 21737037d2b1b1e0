//! How a study reports progress: every grid it evaluates is a task of some number of
//! cells, ticked once per finished cell from any worker thread. Front ends draw a bar per
//! task (the command line) or nothing ([`Silent`]).

/// The tick of one task: call it once per finished cell; the task ends when it is dropped.
pub type Tick<'a> = Box<dyn Fn() + Sync + 'a>;

/// Receives a study's progress.
pub trait Progress: Sync {
    /// A task of `cells` cells called `label` begins.
    fn task(&self, cells: usize, label: &str) -> Tick<'_>;
}

/// Progress nobody watches.
pub struct Silent;

impl Progress for Silent {
    fn task(&self, _cells: usize, _label: &str) -> Tick<'_> {
        Box::new(|| {})
    }
}
