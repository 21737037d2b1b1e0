//! A batch step allocates nothing (counted by a global allocator on the stepping thread):
//! 32 Robbits at rest, their motors under changing controls, in stance without events.

mod common;

use hopsim_sim::Batch;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    /// Allocations of this thread.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

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
fn a_batch_step_allocates_nothing() {
    let path = common::repo("scenes/robbit.toml");
    // The controller's torque off: the robot stands (no events); a weak motor rocks the
    // flywheel against the disc.
    let text = std::fs::read_to_string(&path).unwrap()
        + "\n[[actuators]]\nname = \"motor\"\njoint = \"flywheel\"\nkind = \"motor\"\n";
    let scene =
        hopsim_scene::parse(&text, &path, &["controller.torque=0".parse().unwrap()]).unwrap();
    let start = ALLOCATIONS.with(|c| c.get());
    let mut batch = Batch::new(&scene, 32, 1).unwrap();
    assert!(ALLOCATIONS.with(|c| c.get()) > start, "the counter counts");
    let mut block = |b: usize| {
        for (i, c) in batch.controls_mut().iter_mut().enumerate() {
            *c = 1e-3 * (((i + b) % 5) as f64 - 2.0);
        }
        batch.step(10);
    };
    for b in 0..10 {
        block(b);
    }
    let before = ALLOCATIONS.with(|c| c.get());
    for b in 10..200 {
        block(b);
    }
    let allocations = ALLOCATIONS.with(|c| c.get()) - before;
    assert_eq!(allocations, 0);
    assert!(batch.in_contact().iter().all(|&c| c), "the robots stand");
    assert!(batch.t()[0] > 0.39, "{}", batch.t()[0]);
}
