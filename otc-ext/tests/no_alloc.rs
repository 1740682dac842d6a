//! The per-cycle step with OTC on allocates nothing: a counting
//! global allocator watches `EXEC` cycles of every processing type in AUTO
//! (continuous wear on a running correction, a PLC unit ramping), moving
//! along lines, arcs and transitions, crossing element ends, and idle on an
//! empty spooler. Set-up (writes, spooling) happens outside the counted
//! regions.
//!
//! Run without the test harness (`harness = false`, a `main` of its own):
//! the allocator counts every thread, so no other thread may run while the
//! regions are counted.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::alloc::System;

use common::{command_all, otc_auto_on, otc_module, run, set_units, Contour, CORRECTION_ON, TYPES};
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// Allocations and reallocations counted in `region` so far.
fn allocs(region: &Region<'_, System>) -> usize {
    let s = region.change();
    s.allocations + s.reallocations
}

fn main() {
    otc_cycles_allocate_nothing();
    println!("test otc_cycles_allocate_nothing ... ok");
}

/// Every processing type, moving and idle, counted; panics (a failing
/// exit) on any allocation.
fn otc_cycles_allocate_nothing() {
    // The counter counts: an allocation inside a region is seen.
    let probe = Region::new(GLOBAL);
    let v: Vec<u64> = Vec::with_capacity(std::hint::black_box(4));
    assert_eq!(allocs(&probe), 1);
    drop(v);

    for (code, name) in TYPES {
        let mut tc = otc_module();
        run(&mut tc, CORRECTION_ON);
        otc_auto_on(&mut tc, code, 100_000);
        // About 50,000 cycles of path: the spooler never empties below.
        let mut contour = Contour::default();
        command_all(&mut tc, &contour.next_profiles(400));
        tc.exec(Some(10));
        assert!(
            tc.executor().offset().is_some(),
            "{name}: the wear model does not act per cycle"
        );

        let region = Region::new(GLOBAL);
        for _ in 0..2_000 {
            tc.exec(Some(1));
        }
        tc.exec(Some(20_000));
        let moving = allocs(&region);
        assert!(tc.queue_len() > 0, "{name}: the spooler emptied");
        assert_eq!(moving, 0, "{name}: allocations while moving");

        // Idle cycles on an empty spooler, a unit still ramping (the
        // command turned around so the ramp does not settle).
        tc.exec(None);
        set_units(&mut tc, code, -100_000);
        let region = Region::new(GLOBAL);
        tc.exec(Some(5_000));
        for _ in 0..500 {
            tc.exec(Some(1));
        }
        assert_eq!(allocs(&region), 0, "{name}: allocations while idle");
        assert!(tc.executor().offset().is_some(), "{name}: model stopped");
    }
}
