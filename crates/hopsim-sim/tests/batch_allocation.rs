//! A batch step allocates nothing on one thread, and on two only rayon's queue of jobs
//! sent into its pool (a block per 63 jobs): counted by a global allocator on the calling
//! thread, 32 Robbits at rest, their motors under changing controls and their brakes
//! engaged in turns, in stance without events. (The copies' steps, the same on the pool's threads, are those counted at one
//! thread; `rayon::join` keeps its jobs on the stack.)

mod common;

use hopsim_sim::Batch;

#[path = "../../../tests/support/counting_allocator.rs"]
mod counting_allocator;
use counting_allocator::allocated;

/// Allocations in 190 batch steps (of 10 steps each) of 32 Robbits on `threads` threads,
/// after 10.
fn allocations(threads: usize) -> usize {
    let path = common::repo("scenes/robbit.toml");
    // The controller's torque off: the robot stands (no events); a weak motor rocks the
    // flywheel against the disc.
    let text = std::fs::read_to_string(&path).unwrap()
        + "\n[[actuators]]\nname = \"motor\"\njoint = \"flywheel\"\nkind = \"motor\"\n";
    let scene =
        hopsim_scene::parse(&text, &path, &["controller.torque=0".parse().unwrap()]).unwrap();
    let start = allocated();
    let mut batch = Batch::new(&scene, 32, threads).unwrap();
    batch.set_commands(&[(0, 1)], &[]).unwrap();
    assert!(allocated() > start, "the counter counts");
    let mut block = |b: usize| {
        for (i, c) in batch.controls_mut().iter_mut().enumerate() {
            *c = 1e-3 * (((i + b) % 5) as f64 - 2.0);
        }
        for (i, e) in batch.engaged_mut().iter_mut().enumerate() {
            *e = (i + b).is_multiple_of(3);
        }
        batch.step(10);
    };
    for b in 0..10 {
        block(b);
    }
    let before = allocated();
    for b in 10..200 {
        block(b);
    }
    let allocations = allocated() - before;
    assert!(batch.in_contact().iter().all(|&c| c), "the robots stand");
    assert!(batch.t()[0] > 0.39, "{}", batch.t()[0]);
    allocations
}

#[test]
fn a_batch_step_allocates_nothing_but_the_pools_queue() {
    assert_eq!(allocations(1), 0);
    let two = allocations(2);
    assert!(two <= 190 / 63 + 1, "{two} allocations in 190 batch steps");
}
