//! Once its buffers have grown, a `LemkeSolver` solve allocates nothing: not on the hot
//! path, not in the fallbacks, not when the problem size changes.

mod common;

use hopsim_lcp::{LcpStatus, LemkeSolver};
use nalgebra::{dmatrix, dvector};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    /// Allocations of this thread: the test harness's own threads may allocate while a
    /// test runs, and only the solver's thread is under test.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the slot may be gone while a thread shuts down.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

fn allocated() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

// SAFETY: forwards to the system allocator, only counting calls.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn repeated_solves_of_varying_size_do_not_allocate() {
    let mut rng = common::Rng(11);
    let mut problems = vec![common::robbit_two_contacts()];
    for discs in [1, 2, 4, 8, 1, 2] {
        problems.push(common::disc_row(&mut rng, discs, false, None));
    }
    problems.push((dmatrix![-1.0], dvector![-1.0])); // ray + all fallbacks
    problems.push((dmatrix![0.0, 1.0; 2.0, 0.0], dvector![0.0, -3.0])); // enumeration
    problems.push((dmatrix![1.0, 2.0; 0.0, 1.0], dvector![1.0, 1.0])); // trivial

    let mut solver = LemkeSolver::default();
    for (m, q) in &problems {
        solver.solve(m.as_view(), q.as_view()).unwrap();
    }
    let before = allocated();
    let mut solved = 0;
    for _ in 0..20 {
        for (m, q) in &problems {
            let sol = solver.solve(m.as_view(), q.as_view()).unwrap();
            solved += usize::from(sol.status == LcpStatus::Solved);
        }
    }
    let after = allocated();
    assert_eq!(
        after - before,
        0,
        "allocations during {} solves",
        20 * problems.len()
    );
    assert_eq!(
        solved,
        20 * (problems.len() - 1),
        "all but the infeasible one solve"
    );
}
