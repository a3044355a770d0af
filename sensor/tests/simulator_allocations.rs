//! The simulator allocates up front: after a warm-up trial, a trial allocates only its output
//! (events, labels, info), however long the slide — the stepping itself never allocates.

use neurotac_sensor::sim::{Camera, SimParams, Simulator, Texture};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn a_trial_allocates_only_its_output() {
    let mut p = SimParams::default();
    p.kinematics.distance_mm = 30.0;
    let camera = Camera::new(&p, 2);
    let mut sim = Simulator::new(p, &camera).unwrap();
    let grid = sim.prepare(Texture::grid(5.0).unwrap());
    // Warm-up: buffers grow to their working size (a longer slide than the measured ones).
    drop(sim.simulate(&grid, 1));
    let mut counts = Vec::new();
    for seed in [2, 3] {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        let trial = sim.simulate(&grid, seed);
        counts.push(ALLOCATIONS.load(Ordering::Relaxed) - before);
        assert!(trial.events.len() > 10_000);
    }
    // Output: 4 event columns, labels, the pins-in-contact flags, the texture name (formatted,
    // so it may grow once), and the onset facts' three per-pin vectors.
    assert!(counts.iter().all(|&c| c <= 11), "{counts:?}");
}
