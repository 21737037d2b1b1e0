//! The stepper allocates nothing per step (counted by a global allocator).

mod common;

use hopsim_step::{Actuation, TorqueCommand};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn stepping_robbit_with_contacts_torque_and_a_brake_does_not_allocate() {
    let model = common::robbit();
    let mut stepper = common::stepper(&model, 2e-4);
    let mut state = common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]);
    stepper.start(&model, &state);
    let mut act = Actuation::default();
    act.torques.reserve(4);
    act.locks.reserve(4);
    let mut run = |steps: usize, state: &mut hopsim_step::State| {
        for k in 0..steps {
            act.clear();
            if k % 500 == 499 {
                act.locks.push((0, 1));
            } else {
                act.torques.push(TorqueCommand {
                    body: 1,
                    reaction: Some(0),
                    torque: 0.16,
                });
            }
            let rec = stepper.step(&model, state, &act).unwrap();
            assert!(rec.step > 0);
        }
    };
    // Warm up: buffers reach their final size.
    run(1000, &mut state);
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    run(2000, &mut state);
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert_eq!(
        after - before,
        0,
        "{} allocations in 2000 steps",
        after - before
    );
}
